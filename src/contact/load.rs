//! The impulses a contact solve applied to the floes, as the topology
//! stage reads them ([`crate::formulation::context::Topology`]; the
//! fracture criteria, docs/physics.md §9.3).

use super::Contact;
use crate::geometry::Vec2;
use crate::model::{Body, Scenario};

/// One impulse that a contact solve applied to a floe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Load {
    /// The floe (index in the scenario).
    pub floe: usize,
    /// The other body (body id: floes, then obstacles).
    pub other: usize,
    /// The contact point, m (world).
    pub point: Vec2,
    /// The impulse on the floe, N·s (world).
    pub impulse: Vec2,
}

/// The loads of a contact solve: contact `k` of `contacts` got the normal
/// impulse `normal[k]` (N·s, along its normal `N`, pushing `b` away from
/// `a`) and the tangential impulse `tangential[k]` (N·s, along `T`); `+P`
/// acts on `b`, `−P` on `a`, each only if it is a floe.
pub fn loads_of(
    scn: &Scenario,
    contacts: &[&Contact],
    normal: &[f64],
    tangential: &[f64],
) -> Vec<Load> {
    let mut out = Vec::with_capacity(2 * contacts.len());
    for (k, c) in contacts.iter().enumerate() {
        let p =
            c.geom.normal * normal[k] + c.geom.tangent * tangential.get(k).copied().unwrap_or(0.0);
        for (body, other, sign) in [(c.b, c.a, 1.0), (c.a, c.b, -1.0)] {
            if let Body::Floe(i) = scn.body(body) {
                out.push(Load {
                    floe: i,
                    other,
                    point: c.geom.point,
                    impulse: p * sign,
                });
            }
        }
    }
    out
}
