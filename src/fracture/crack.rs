//! The crack pattern of a percussion as data (docs/physics.md §9.8): the
//! lattice at rest with each spring intact or broken, and the impact that
//! broke it ([`PercussionRecord`]). A run of the lattice model keeps one,
//! the percussion of largest lattice loss among those that broke a floe
//! ([`keep`]; written as `percussion.json`, drawn by
//! [`crate::report::crack`]); `floebench percussion-2d` makes one of its
//! single percussion ([`of_lattice`]) and draws it the same way.
//!
//! No scheme: this copies the lattice's rest geometry and the broken
//! springs' indices; nothing is computed.

use super::lattice::percussion::Impact;
use super::lattice::Lattice;
use super::strike::LatticeSplit;
use crate::model::fracture::{FloeHistory, FractureRecord, ImpactRecord, PercussionRecord};
use crate::state::BodyState;

/// The impact of a record: `impact` in the same frame, an infinite striker
/// mass written as `None`.
pub fn impact_record(impact: &Impact) -> ImpactRecord {
    ImpactRecord {
        point: [impact.point.x, impact.point.y],
        normal: [impact.normal.x, impact.normal.y],
        speed: impact.speed,
        striker_mass: impact.mass.is_finite().then_some(impact.mass),
    }
}

/// The record of a percussion of `lattice` by `impacts` (one striker each)
/// that broke the springs `broken` (in the order they broke): its geometry
/// and impacts,
/// at `t = 0` for floe 0 at the world origin, its energies 0 (the caller
/// sets what it knows).
pub fn of_lattice(lattice: &Lattice, broken: &[usize], impacts: &[Impact]) -> PercussionRecord {
    let mut intact = vec![true; lattice.springs.len()];
    for &k in broken {
        if let Some(b) = intact.get_mut(k) {
            *b = false;
        }
    }
    PercussionRecord {
        t: 0.0,
        floe: 0,
        children: Vec::new(),
        position: [0.0, 0.0],
        angle: 0.0,
        impacts: impacts.iter().map(impact_record).collect(),
        bound: 0.0,
        weakest: 0.0,
        loss: 0.0,
        energy: 0.0,
        spacing: lattice.spec.spacing,
        nodes: lattice.nodes.iter().map(|p| [p.x, p.y]).collect(),
        springs: lattice.springs.iter().map(|s| s.nodes).collect(),
        intact,
        broken: broken.to_vec(),
    }
}

/// Keeps in `history` the percussion of the fracture `fracture` (the row
/// just made for it) of a floe in state `pose` (before the split), whose
/// lattice `lattice` gave `split`, when its lattice loss is larger than
/// the kept one's (the earlier is kept on a tie); `bound` and
/// `weakest` (J) are the fracture's `measure` and `threshold`.
pub fn keep(
    history: &mut FloeHistory,
    lattice: &Lattice,
    split: &LatticeSplit,
    pose: &BodyState,
    fracture: &FractureRecord,
) {
    if history
        .percussion
        .as_ref()
        .is_some_and(|p| split.loss <= p.loss)
    {
        return;
    }
    history.percussion = Some(PercussionRecord {
        t: fracture.t,
        floe: fracture.parent,
        children: fracture.children.clone(),
        position: [pose.position.x, pose.position.y],
        angle: pose.angle,
        bound: fracture.measure,
        weakest: fracture.threshold,
        loss: split.loss,
        energy: fracture.energy,
        ..of_lattice(lattice, &split.bonds, &split.impacts)
    });
}
