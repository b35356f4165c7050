//! The crush stage: the ice that crushes at a contact is cut from the
//! floes at the formulation's safe points, and goes to ridges or to the
//! coast (`[contact] crushing`, docs/physics.md §10).
//!
//! With crushing, a contact's normal force is bounded by `p(A)·A`
//! ([`crate::model::Crushing::max_force`]); a contact at its bound keeps
//! approaching, so the floes **overlap**: the overlap is the crushed ice.
//! A formulation reports the pairs whose normal impulse reached its bound
//! ([`Topology::crushed`]); at its next safe point the stage cuts each
//! pair's overlap ([`overlap::Overlap`]) on a plane normal to the pair's
//! normal `n` (from the first body to the second), with `s(x) = n·x` over
//! the overlap's vertices:
//!
//! - floe against a coast: the floe keeps `n·x ≤ min s` (the coast's face:
//!   a corner rammed into a straight coast loses exactly the overlap), and
//!   the crushed ice is **deposited** on the coast and booked there
//!   ([`Deposit`]: mass, volume, momentum, angular momentum, kinetic
//!   energy);
//! - two floes: the plane at `(min s + max s)/2`, the first keeps `n·x ≤`
//!   it and the second `≥`; the ice crushed from each goes to the **other**
//!   as thickness, with its momentum ([`transfer`], Subzero.jl's rule).
//!
//! The cut keeps a convex floe convex; a floe of several convex parts is
//! not cut (counted as refused, it still receives ice). Mass is conserved
//! (floes plus deposits), and linear and angular momentum (the deposits'
//! included); the kinetic energy the transfers take (a perfectly inelastic
//! merge, or the crushed ice's energy against a coast) is booked in the
//! ledger's `crushing` column. Floe ids do not change; a floe's outline,
//! thickness and mass do (`floes.json` gives them at the end of the run).

pub mod overlap;
pub mod transfer;

use crate::formulation::context::{Reads, Topology};
use crate::geometry::Vec2;
use crate::model::{Body, Floe, Scenario};
use crate::record::{Counter, Counters, Stage, StageClock, Unit};
use crate::state::{BodyState, System};
use overlap::Overlap;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use transfer::{cut_on_plane, kept_state, reshaped, ridged, Ice};

/// An overlap thinner than this fraction of the floe's radius along the
/// pair's normal is not cut: 1e-9, the split's own tolerance for a vertex
/// on the chord ([`mod@crate::fracture::split`]), below which a cut has no
/// area on one side; such an overlap is rounding, not crushed ice.
pub const DEPTH_TOLERANCE: f64 = 1e-9;

/// A cut that would leave a floe smaller than this fraction of its area
/// when the stage first saw it (the run's start for the case's floes, its
/// first crushing for a piece of a fracture) is refused, the floe kept
/// whole and the refusal counted: 0.1. A floe crushed that far is no
/// longer a floe with a crushed edge (its overlap is no thin strip at its
/// face), and a floe that vanished by crushing would be a change of the
/// floe set, which is fracture's.
pub const MIN_KEPT_FRACTION: f64 = 0.1;

/// Total volume of ice crushed (at the cut floe's thickness), m³.
pub const CRUSHED_VOLUME: Counter = Counter::value(
    "crushed_volume_m3",
    Unit::CubicMetre,
    "volume of ice crushed, at the thickness of the floe it was cut from",
);
/// Volume of crushed ice added to floes (at the receiving floe's density), m³.
pub const RIDGED_VOLUME: Counter = Counter::value(
    "ridged_volume_m3",
    Unit::CubicMetre,
    "volume of crushed ice added to floes as thickness (at their density)",
);
/// Volume of crushed ice deposited on obstacles, m³.
pub const DEPOSITED_VOLUME: Counter = Counter::value(
    "deposited_volume_m3",
    Unit::CubicMetre,
    "volume of crushed ice deposited on obstacles (coasts)",
);
/// Cuts made (one per floe cut).
pub const CRUSH_CUTS: Counter = Counter::sum("crush_cuts", "floes cut by the crush stage");
/// Cuts refused (a floe of several convex parts, or one that would be
/// left below [`MIN_KEPT_FRACTION`] of its area).
pub const CRUSH_CUTS_REFUSED: Counter = Counter::sum(
    "crush_cuts_refused",
    "cuts refused: a non-convex floe, or one that would be left too small",
);
/// Reported pairs whose overlap was below [`DEPTH_TOLERANCE`] (or gone).
pub const CRUSH_BELOW_TOLERANCE: Counter = Counter::sum(
    "crush_pairs_below_tolerance",
    "reported pairs with no overlap above the depth tolerance",
);

/// The crushed ice deposited on one obstacle over a run
/// (`summary.json`'s `crushing.deposits`).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Deposit {
    /// The obstacle (index in the case's `[[obstacle]]` tables).
    pub obstacle: usize,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Volume (at the thickness of the floes it was cut from), m³.
    pub volume_m3: f64,
    /// Linear momentum the ice brought, kg·m/s.
    pub momentum: [f64; 2],
    /// Angular momentum the ice brought, about the world origin, kg·m²/s.
    pub angular_momentum: f64,
    /// Kinetic energy the ice brought, J (booked in the ledger's `crushing`).
    pub kinetic_energy_j: f64,
}

impl Deposit {
    fn add(&mut self, ice: &Ice) {
        self.mass_kg += ice.mass;
        self.volume_m3 += ice.volume;
        let p = ice.momentum();
        self.momentum[0] += p.x;
        self.momentum[1] += p.y;
        self.angular_momentum += ice.angular_momentum_about(&Vec2::zeros());
        self.kinetic_energy_j += ice.kinetic;
    }
}

/// The other body of a reported pair: a floe by id, or an obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Other {
    Floe(usize),
    Obstacle(usize),
}

/// The crush stage of one run (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct CrushStage {
    enabled: bool,
    /// The reported pairs waiting for the next safe point: (floe id, other).
    pending: BTreeSet<(usize, Other)>,
    /// Each floe's area when the stage first saw it, m², by id.
    reference: BTreeMap<usize, f64>,
    deposits: Vec<Deposit>,
    crushed: f64,
    ridged: f64,
    deposited: f64,
    cuts: u64,
    refused: u64,
    below: u64,
    /// The ids of the floes cut by the last [`Topology::apply`].
    reshaped: Vec<usize>,
}

impl CrushStage {
    /// The stage of a run of `scn`: it does nothing without `[contact]
    /// crushing`.
    pub fn new(scn: &Scenario) -> CrushStage {
        let enabled = scn.contact.crushing.is_some();
        CrushStage {
            enabled,
            reference: scn.floes.iter().map(|f| (f.id, f.area)).collect(),
            deposits: match enabled {
                true => (0..scn.obstacles.len())
                    .map(|obstacle| Deposit {
                        obstacle,
                        ..Deposit::default()
                    })
                    .collect(),
                false => Vec::new(),
            },
            ..CrushStage::default()
        }
    }

    /// Whether the case's ice crushes.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// The ice deposited on each obstacle so far (empty without crushing).
    pub fn deposits(&self) -> &[Deposit] {
        &self.deposits
    }

    /// The ids of the floes the last [`Topology::apply`] cut (their
    /// outlines changed), emptied.
    pub fn take_reshaped(&mut self) -> Vec<usize> {
        std::mem::take(&mut self.reshaped)
    }

    /// The cut of floe `k` on the plane `n·x = c`, keeping the side below
    /// it when `below`: the floe reduced to its kept piece, its state and
    /// the crushed ice; `None` when refused (counted) or when the plane
    /// leaves a side without area.
    fn cut(
        &mut self,
        scn: &Scenario,
        sys: &System,
        k: usize,
        plane: (&Vec2, f64),
        below: bool,
    ) -> Option<(Floe, BodyState, Ice)> {
        let f = &scn.floes[k];
        let b = &sys.bodies[k];
        if !f.is_convex() {
            self.refused += 1;
            return None;
        }
        let (kept, crushed) = cut_on_plane(f, b, plane.0, plane.1, below)?;
        let reference = *self.reference.entry(f.id).or_insert(f.area);
        if kept.floe.area < MIN_KEPT_FRACTION * reference {
            self.refused += 1;
            return None;
        }
        self.cuts += 1;
        self.crushed += crushed.floe.area * f.thickness;
        Some((
            reshaped(f, &kept, b.angle),
            kept_state(&kept, b),
            Ice::of(&crushed),
        ))
    }

    /// Cuts the overlap of floe `a` (index) and `other` (a floe index or
    /// an obstacle) in `scn` and `sys`; whether a floe changed.
    fn crush_pair(&mut self, scn: &mut Scenario, sys: &mut System, a: usize, other: Body) -> bool {
        let mut wa = Vec::new();
        let fa = &scn.floes[a];
        fa.world_polygon(&sys.bodies[a].position, sys.bodies[a].angle, &mut wa);
        let mut wb = Vec::new();
        let (parts_b, radius_b) = match other {
            Body::Floe(b) => {
                let fb = &scn.floes[b];
                fb.world_polygon(&sys.bodies[b].position, sys.bodies[b].angle, &mut wb);
                (&fb.parts, fb.radius)
            }
            Body::Obstacle(k) => {
                let o = &scn.obstacles[k];
                wb.clone_from(&o.polygon);
                (&o.parts, fa.radius)
            }
        };
        let Some(ov) = Overlap::of(&wa, &fa.parts, &wb, parts_b) else {
            self.below += 1;
            return false;
        };
        let (lo, hi) = ov.extent();
        let depth = hi - lo;
        if depth.is_nan() || depth <= DEPTH_TOLERANCE * fa.radius.max(radius_b) {
            self.below += 1;
            return false;
        }
        let n = ov.normal;
        let kinetic = |scn: &Scenario, sys: &System, k: usize| {
            let s = &sys.bodies[k];
            scn.floes[k].kinetic_energy(&s.velocity, s.angular_velocity)
        };
        match other {
            Body::Obstacle(k) => {
                let before = kinetic(scn, sys, a);
                let Some((floe, state, ice)) = self.cut(scn, sys, a, (&n, lo), true) else {
                    return false;
                };
                scn.floes[a] = floe;
                sys.bodies[a] = state;
                self.deposited += ice.volume;
                if let Some(d) = self.deposits.get_mut(k) {
                    d.add(&ice);
                }
                self.reshaped.push(scn.floes[a].id);
                sys.ledger.crushing += before - kinetic(scn, sys, a);
                true
            }
            Body::Floe(b) => {
                let before = kinetic(scn, sys, a) + kinetic(scn, sys, b);
                let c = 0.5 * (lo + hi);
                let cut_a = self.cut(scn, sys, a, (&n, c), true);
                let cut_b = self.cut(scn, sys, b, (&n, c), false);
                if cut_a.is_none() && cut_b.is_none() {
                    return false;
                }
                let mut ridge =
                    |k: usize, own: Option<&(Floe, BodyState, Ice)>, ice: Option<&Ice>| {
                        let (f, s) = match own {
                            Some((f, s, _)) => {
                                self.reshaped.push(f.id);
                                (f.clone(), *s)
                            }
                            None => (scn.floes[k].clone(), sys.bodies[k]),
                        };
                        let ice: Vec<Ice> = ice.into_iter().copied().collect();
                        self.ridged += ice.iter().map(|i| i.mass / f.density).sum::<f64>();
                        ridged(&f, &s, &ice)
                    };
                let new_a = ridge(a, cut_a.as_ref(), cut_b.as_ref().map(|c| &c.2));
                let new_b = ridge(b, cut_b.as_ref(), cut_a.as_ref().map(|c| &c.2));
                (scn.floes[a], sys.bodies[a]) = new_a;
                (scn.floes[b], sys.bodies[b]) = new_b;
                sys.ledger.crushing += before - (kinetic(scn, sys, a) + kinetic(scn, sys, b));
                true
            }
        }
    }
}

impl Topology for CrushStage {
    fn reads(&self) -> Reads {
        Reads::default()
    }

    fn percussion(
        &mut self,
        _: &Scenario,
        _: &System,
        _: &[crate::contact::Load],
        _: f64,
        _: f64,
        _: f64,
    ) {
    }

    fn sustained(&mut self, _: &Scenario, _: &System, _: &[crate::contact::Load], _: f64, _: f64) {}

    fn crushed(&mut self, scn: &Scenario, _: &System, pairs: &[(usize, usize)]) {
        if !self.enabled {
            return;
        }
        for &(a, b) in pairs {
            let Some(fa) = scn.floes.get(a) else { continue };
            let key = match scn.body(b) {
                Body::Floe(b) if b == a => continue,
                Body::Floe(b) => {
                    let idb = scn.floes[b].id;
                    (fa.id.min(idb), Other::Floe(fa.id.max(idb)))
                }
                Body::Obstacle(k) if k < scn.obstacles.len() => (fa.id, Other::Obstacle(k)),
                Body::Obstacle(_) => continue,
            };
            self.pending.insert(key);
        }
    }

    fn counters(&self) -> Counters {
        if !self.enabled {
            return Counters::default();
        }
        let mut c = Counters::new(&[&CRUSH_CUTS, &CRUSH_CUTS_REFUSED, &CRUSH_BELOW_TOLERANCE]);
        c.add(&CRUSH_CUTS, self.cuts);
        c.add(&CRUSH_CUTS_REFUSED, self.refused);
        c.add(&CRUSH_BELOW_TOLERANCE, self.below);
        c.set(&CRUSHED_VOLUME, self.crushed);
        c.set(&RIDGED_VOLUME, self.ridged);
        c.set(&DEPOSITED_VOLUME, self.deposited);
        c
    }

    fn pending(&self) -> bool {
        !self.pending.is_empty()
    }

    /// Cuts the reported pairs' overlaps, in the order of their floe ids;
    /// the floe ids before when a floe changed (a cut, or ice received),
    /// `None` when none did (every overlap below the tolerance, every cut
    /// refused): the floe set is then as it was, and the formulation has
    /// nothing to rebuild.
    fn apply(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        clock: &mut StageClock,
    ) -> Option<Vec<usize>> {
        if self.pending.is_empty() {
            return None;
        }
        let started = clock.start(Stage::Crushing);
        let old: Vec<usize> = scn.floes.iter().map(|f| f.id).collect();
        let index: BTreeMap<usize, usize> =
            old.iter().enumerate().map(|(k, &id)| (id, k)).collect();
        let mut changed = false;
        for (a, other) in std::mem::take(&mut self.pending) {
            // A floe that broke since the report is no longer there: its
            // pieces' overlaps are reported again by the next solve.
            let Some(&ka) = index.get(&a) else { continue };
            let other = match other {
                Other::Floe(b) => match index.get(&b) {
                    Some(&kb) => Body::Floe(kb),
                    None => continue,
                },
                Other::Obstacle(k) => Body::Obstacle(k),
            };
            changed |= self.crush_pair(scn, sys, ka, other);
        }
        clock.stop(Stage::Crushing, started);
        changed.then_some(old)
    }
}
