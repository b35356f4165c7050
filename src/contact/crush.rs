//! The crushing bound of each contact's normal impulse (docs/physics.md
//! §10): with `[contact] crushing`, the normal force of a body pair is at
//! most `F_max = p(A)·A` ([`crate::model::Crushing::max_force`]), `A = h w`
//! the crushed face's area, so the normal impulse of each of its points
//! over a step (or an interval) of `dt` is at most `F_max dt / k`.
//!
//! - `h` (m): the thinner floe's thickness (a floe against an obstacle: the
//!   floe's; coasts do not crush, the ice crushes against them);
//! - `w` (m): the width of the pair's contact, the extent of its `k` points
//!   along the pair's tangent: a flush edge pair's common length, 0 for a
//!   corner (a lone point). A corner therefore carries no force until it
//!   has crushed into a face (the crush stage cuts the overlap, and the cut
//!   is flush with the other body), and the face's force then grows with
//!   its width: the closed forms of a corner rammed into a coast.
//! - the pair's bound is shared equally among its `k` points: one box per
//!   point, which is what every solver takes (a box in NSGS and APGD, a
//!   bound row in Lemke's LCP, a linear constraint in the cone program).
//!
//! A contact whose gap is positive (beyond [`TOUCHING`]) has the bound 0:
//! the formulations close contacts within a distance (the event-driven
//! contact distance `δ`, Moreau–Jean's predicted gap), and a crushing force
//! acting across that gap would stop a floe before it touched, with no
//! overlap to cut. The pair meets within the step and crushes from the
//! next.
//!
//! Without `crushing` there are no bounds (an empty list): every contact
//! is rigid, as before.

use super::problem::Gen;
use super::Contact;
use crate::geometry::Vec2;
use crate::model::Scenario;
use std::collections::BTreeMap;

/// The normal impulse bound (N·s) of every contact of `contacts` over a
/// duration `dt` (s), in the same order; empty when the case has no
/// crushing law (see the module doc).
pub fn normal_bounds(scn: &Scenario, contacts: &[Contact], dt: f64) -> Vec<f64> {
    let Some(law) = scn.contact.crushing else {
        return Vec::new();
    };
    let n = scn.floes.len();
    // Per body pair: the extent of its points along the tangent, and their
    // number.
    let mut pairs: BTreeMap<(usize, usize), (f64, f64, usize)> = BTreeMap::new();
    for c in contacts {
        let s = c.geom.point.dot(&c.geom.tangent);
        let e = pairs
            .entry((c.a, c.b))
            .or_insert((f64::INFINITY, f64::NEG_INFINITY, 0));
        e.0 = e.0.min(s);
        e.1 = e.1.max(s);
        e.2 += 1;
    }
    contacts
        .iter()
        .map(|c| {
            let (lo, hi, k) = pairs[&(c.a, c.b)];
            let thickness = |i: usize| {
                if i < n {
                    scn.floes[i].thickness
                } else {
                    f64::INFINITY
                }
            };
            // A pair not yet touching carries no crushing force: it meets
            // the other body within the step and crushes from then on.
            if c.geom.gap > TOUCHING * scn.floes[c.a.min(n - 1)].radius {
                return 0.0;
            }
            let h = thickness(c.a).min(thickness(c.b));
            let width = if k > 1 { hi - lo } else { 0.0 };
            law.max_force(h, width) * dt / k as f64
        })
        .collect()
}

/// The gap (in radii of the pair's floe) above which a contact is not
/// touching and carries no crushing force: the rounding of a cut, whose
/// face lies on the other body's to about 1e-15 of the coordinates
/// (1e-9 of a 10 m floe's radius is 10⁴ times that at 1,000 km from the
/// origin).
pub const TOUCHING: f64 = 1e-9;

/// Whether a contact of bound `bound` (N·s) crushes: it is bounded and
/// still approaches (`u_after` < 0, m/s) after the solve's impulses. A
/// contact below its bound is stopped (Signorini, `u_N ≥ 0`); one that
/// approaches is at its bound, so that this reads the law, not the
/// solver's rounding of the bound: an iterative solver at its tolerance
/// may leave a small impulse below a small bound (a face just cut, whose
/// force over a step is 1e-7 of the floe's momentum), and the pair, which
/// approaches, crushes all the same.
pub fn crushing(bound: f64, u_after: f64) -> bool {
    bound.is_finite() && u_after < 0.0
}

/// Relative distance to its bound within which a normal impulse is at it:
/// the iterative solvers' answers reach the bound to their tolerance (1e-6
/// by default), the pivoting ones to rounding.
pub const AT_BOUND: f64 = 1e-6;

/// The relative normal velocity (m/s, positive separating) of contact `c`
/// for the generalised velocities `w` of every floe (`centres` their
/// centres of mass, m); obstacles are at rest.
pub fn normal_velocity(scn: &Scenario, centres: &[Vec2], w: &[Gen], c: &Contact) -> f64 {
    let at = |i: usize| {
        if i >= scn.floes.len() {
            return Vec2::zeros();
        }
        let r = c.geom.point - centres[i];
        Vec2::new(w[i][0] - w[i][2] * r.y, w[i][1] + w[i][2] * r.x)
    };
    (at(c.b) - at(c.a)).dot(&c.geom.normal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{ContactGeom, Feature, FeaturePair};
    use crate::model::{parse_case_with, Crushing};
    use std::path::Path;

    fn scenario(crushing: &str) -> Scenario {
        let text = format!(
            "[case]\nversion = 1\nname = \"t\"\nduration = 1.0\noutput_interval = 1.0\n\
             [contact]\nrestitution = 0.0\nfriction = 0.0\n{crushing}\n\
             [[floe]]\npolygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]\nthickness = 2.0\n\
             [[floe]]\npolygon = [[20.0, 0.0], [30.0, 0.0], [30.0, 10.0], [20.0, 10.0]]\nthickness = 0.5\n"
        );
        parse_case_with(&text, Path::new("t.toml"), &[]).unwrap()
    }

    fn contact(a: usize, b: usize, y: f64, gap: f64) -> Contact {
        Contact {
            a,
            b,
            geom: ContactGeom {
                point: Vec2::new(10.0, y),
                normal: Vec2::new(1.0, 0.0),
                tangent: Vec2::new(0.0, 1.0),
                gap,
                feature: FeaturePair {
                    a: Feature::Vertex(0),
                    b: Feature::Vertex(0),
                },
            },
        }
    }

    /// A flush pair of two points 4 m apart: `σ_c h w dt` shared between
    /// them, `h` the thinner floe's; a lone point (a corner) carries none;
    /// a point across a gap carries none.
    #[test]
    fn the_bound_is_the_pair_s_width_times_the_thinner_floe_shared_by_its_points() {
        let scn = scenario("crushing = { strength = 2e6 }");
        let pair = [contact(0, 1, 3.0, 0.0), contact(0, 1, 7.0, -1e-3)];
        let b = normal_bounds(&scn, &pair, 0.1);
        let each = 2e6 * 0.5 * 4.0 * 0.1 / 2.0;
        assert_eq!(b, vec![each, each]);
        assert_eq!(normal_bounds(&scn, &pair[..1], 0.1), vec![0.0]);
        let open = [contact(0, 1, 3.0, 1e-3), contact(0, 1, 7.0, 0.0)];
        assert_eq!(normal_bounds(&scn, &open, 0.1)[0], 0.0);
        // Against an obstacle (body 2): the floe's own thickness.
        let coast = [contact(0, 2, 3.0, 0.0), contact(0, 2, 7.0, 0.0)];
        let b = normal_bounds(&scn, &coast, 0.1);
        assert_eq!(b[0], 2e6 * 2.0 * 4.0 * 0.1 / 2.0);
    }

    #[test]
    fn the_pressure_area_law_bounds_by_p0_a_to_the_one_plus_ex() {
        let scn = scenario("crushing = { p0 = 3e6, exponent = -0.5 }");
        let pair = [contact(0, 1, 3.0, 0.0), contact(0, 1, 7.0, 0.0)];
        let b = normal_bounds(&scn, &pair, 1.0);
        let area: f64 = 0.5 * 4.0;
        assert!(
            (b[0] - 3e6 * area.sqrt() / 2.0).abs() <= 1e-9 * b[0],
            "{b:?}"
        );
        assert_eq!(
            Crushing::PressureArea {
                p0: 3e6,
                exponent: -1.0
            }
            .max_force(1.0, 0.0),
            3e6,
            "ex = -1: a force P0 whatever the area"
        );
    }

    #[test]
    fn without_crushing_there_are_no_bounds() {
        let scn = scenario("");
        let pair = [contact(0, 1, 3.0, 0.0)];
        assert!(normal_bounds(&scn, &pair, 1.0).is_empty());
        assert!(!crushing(f64::INFINITY, -1.0));
        assert!(crushing(0.0, -1e-12) && !crushing(1.0, 0.0));
    }
}
