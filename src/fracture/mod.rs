//! Floes that break (docs/physics.md §9): the loads a contact solve puts on
//! each floe, the two criteria (`energy`, `stress`), the cut rule, and the
//! one function that changes a run's floe set ([`apply_split`]), used by
//! every formulation.
//!
//! A formulation that resolves contacts hands each contact solve's
//! impulses to its [`Fracturer`] as [`Load`]s ([`loads_of`]); the
//! fracturer decides which floes break and where, and [`apply_split`]
//! replaces each by its two pieces in the scenario, the state and the
//! history together. Without a `[fracture]` table (or `model = "none"`)
//! nothing here runs.

pub mod chain;
pub mod lattice;
pub mod split;
pub mod stress;

use crate::contact::Contact;
use crate::geometry::{rotate, Vec2};
use crate::model::fracture::{FloeRecord, FractureModel, FractureRecord};
use crate::model::{Body, Scenario};
use crate::state::{BodyState, System};
use split::{conservation_error, cut_floe, split, Cut};
use std::collections::BTreeMap;

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

/// The loads of one floe by the body pressing it: the summed impulse of
/// the pair (N·s) and its centre of pressure (m), the contact points
/// weighted by the size of their impulses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairLoad {
    /// The other body.
    pub other: usize,
    /// Summed impulse on the floe, N·s.
    pub impulse: Vec2,
    /// Centre of pressure, m.
    pub point: Vec2,
}

/// The loads of each floe, summed per pair (ordered by floe, then other
/// body, so the result does not depend on the order of the contacts).
pub fn pair_loads(loads: &[Load]) -> BTreeMap<usize, Vec<PairLoad>> {
    let mut acc: BTreeMap<(usize, usize), (Vec2, Vec2, f64)> = BTreeMap::new();
    for l in loads {
        let e = acc
            .entry((l.floe, l.other))
            .or_insert((Vec2::zeros(), Vec2::zeros(), 0.0));
        let w = l.impulse.norm();
        e.0 += l.impulse;
        e.1 += l.point * w;
        e.2 += w;
    }
    let mut out: BTreeMap<usize, Vec<PairLoad>> = BTreeMap::new();
    for ((floe, other), (impulse, weighted, w)) in acc {
        if w > 0.0 {
            out.entry(floe).or_default().push(PairLoad {
                other,
                impulse,
                point: weighted / w,
            });
        }
    }
    out
}

/// The impulse energy a solve delivered to a floe of mass `mass` (kg), J:
/// `Σ ½ |P|² / m` over its pair impulses `P` (docs/physics.md §9.2).
pub fn impulse_energy(pairs: &[PairLoad], mass: f64) -> f64 {
    pairs
        .iter()
        .map(|p| 0.5 * p.impulse.norm_squared() / mass)
        .sum()
}

/// The line of a cut in a floe's body frame: a point (m, about its centre
/// of mass, at angle 0) and a direction, so that it follows the floe if the
/// split comes later than the decision (the fixed-step schemes split
/// between steps).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyLine {
    /// A point of the line, m.
    pub point: Vec2,
    /// Its direction (not normalised).
    pub dir: Vec2,
}

impl BodyLine {
    /// The line of world point `p` and direction `d` for a floe in state `b`.
    pub fn of_world(b: &BodyState, p: &Vec2, d: &Vec2) -> BodyLine {
        BodyLine {
            point: rotate(&(p - b.position), -b.angle),
            dir: rotate(d, -b.angle),
        }
    }

    /// The cut of floe `floe` in state `b` on this line ([`cut_floe`]).
    pub fn cut(&self, floe: &crate::model::Floe, b: &BodyState) -> Option<Cut> {
        let p = b.position + rotate(&self.point, b.angle);
        cut_floe(floe, b, &p, &rotate(&self.dir, b.angle))
    }
}

/// The Brazilian cut of a floe under `pairs`: the chord through the centre
/// of pressure of its most loaded pair, along that pair's impulse (the
/// direction of the largest compressive load), with its line; `None` when
/// there is no load or the line does not cut the floe.
pub fn brazilian_cut(
    scn: &Scenario,
    sys: &System,
    floe: usize,
    pairs: &[PairLoad],
) -> Option<(BodyLine, Cut)> {
    let most = pairs
        .iter()
        .max_by(|a, b| a.impulse.norm().total_cmp(&b.impulse.norm()))?;
    let b = &sys.bodies[floe];
    let line = BodyLine::of_world(b, &most.point, &most.impulse);
    let cut = line.cut(&scn.floes[floe], b)?;
    Some((line, cut))
}

/// A decision to break floe `floe` on `line`.
#[derive(Debug, Clone, PartialEq)]
pub struct Decision {
    /// The floe (index).
    pub floe: usize,
    /// Where it breaks, in its body frame.
    pub line: BodyLine,
    /// The cut's length at the decision, m.
    pub length: f64,
    /// What the criterion measured.
    pub measure: f64,
    /// What it compared it with.
    pub threshold: f64,
    /// The crack energy the criterion spends, J (`G h L` for `energy`, 0
    /// for `stress`).
    pub crack_energy: f64,
}

/// A formulation's fracture state: the criterion of the case and, for the
/// stress criterion, the recent stresses of each floe (by id).
#[derive(Debug, Clone, Default)]
pub struct Fracturer {
    history: BTreeMap<usize, stress::Window>,
    fractures: u64,
}

impl Fracturer {
    /// Whether the case lets floes break.
    pub fn enabled(scn: &Scenario) -> bool {
        scn.fracture.enabled()
    }

    /// The fractures made so far.
    pub fn count(&self) -> u64 {
        self.fractures
    }

    /// The floes that break under the loads `loads` of a contact solve at
    /// the instant `sys.t` (an energy criterion reads this solve alone; the
    /// stress criterion its window), at most one decision per floe, in floe
    /// order.
    pub fn decide(&mut self, scn: &Scenario, sys: &System, loads: &[Load]) -> Vec<Decision> {
        self.decide_over(scn, sys, loads, sys.t, sys.t)
    }

    /// As [`Fracturer::decide`], for loads delivered over `[from, to]` (s):
    /// the span the formulation attributes to the solve (its step), over
    /// which the stress criterion spreads their impulse in its window
    /// ([`stress::Window`]; docs/physics.md §9.3). `sys` is the state the
    /// loads' points and the cut refer to. The energy criterion reads the
    /// impulses alone, whatever their span.
    pub fn decide_over(
        &mut self,
        scn: &Scenario,
        sys: &System,
        loads: &[Load],
        from: f64,
        to: f64,
    ) -> Vec<Decision> {
        let s = &scn.fracture;
        let mut out = Vec::new();
        for (floe, pairs) in pair_loads(loads) {
            let f = &scn.floes[floe];
            match s.model {
                FractureModel::None => {}
                FractureModel::Energy => {
                    if f.area < s.min_area {
                        continue;
                    }
                    let measure = impulse_energy(&pairs, f.mass);
                    let Some((line, cut)) = brazilian_cut(scn, sys, floe, &pairs) else {
                        continue;
                    };
                    let threshold = s.toughness * f.thickness * cut.length;
                    if measure >= threshold {
                        out.push(Decision {
                            floe,
                            line,
                            length: cut.length,
                            measure,
                            threshold,
                            crack_energy: threshold,
                        });
                    }
                }
                FractureModel::Stress => {
                    let b = &sys.bodies[floe];
                    let tensor =
                        stress::moment(&b.position, loads.iter().filter(|l| l.floe == floe));
                    let w = self.history.entry(f.id).or_default();
                    w.push(from, to, tensor, s.window);
                    if f.area < s.min_area {
                        continue;
                    }
                    let sigma = w.mean_stress(to, f.area, f.thickness, s.window);
                    let measure = stress::yield_measure(s, &sigma);
                    if measure > 1.0 {
                        if let Some((line, cut)) = brazilian_cut(scn, sys, floe, &pairs) {
                            out.push(Decision {
                                floe,
                                line,
                                length: cut.length,
                                measure,
                                threshold: 1.0,
                                crack_energy: 0.0,
                            });
                        }
                    }
                }
            }
        }
        out
    }

    /// Applies `decisions` (from [`Fracturer::decide`] on the same `scn`
    /// and `sys`) at `sys.t`: each floe is replaced by its pieces. The crack
    /// energies are taken from `dissipated` (J, what the solve removed from
    /// the kinetic energy), at most all of it, and booked in the ledger's
    /// `fracture` column instead of its `dissipated` one. Returns the
    /// number of floes split; the indices of the floes not split are
    /// unchanged, so later decisions stay valid.
    pub fn apply(
        &mut self,
        scn: &mut Scenario,
        sys: &mut System,
        decisions: &[Decision],
        dissipated: f64,
    ) -> usize {
        let mut budget = dissipated.max(0.0);
        let mut done = 0;
        for d in decisions {
            let spent = d.crack_energy.min(budget);
            // The window is kept by floe id, not by index.
            let id = scn.floes[d.floe].id;
            if apply_split(scn, sys, d, spent).is_some() {
                budget -= spent;
                self.history.remove(&id);
                done += 1;
                self.fractures += 1;
            }
        }
        done
    }
}

/// Replaces floe `d.floe` of `scn` and `sys` by its two pieces on
/// `d.line` (at the floe's pose in `sys`) at time `sys.t`: the left piece takes the parent's index, the
/// right one is appended (so every other floe keeps its index); the parent
/// ends in `scn.history`, with the fracture's row, and `spent` (J) moves from
/// the ledger's `dissipated` to its `fracture` column. Returns the pieces'
/// indices, or `None` (nothing changed) when the cut leaves a piece without
/// area or one smaller than the case's `min_area`: a chord through a
/// loaded corner can cut off a sliver (7.6e-5 m long, 5e-7 m² of a floe of
/// hundreds, on the narrow channel), whose crack energy `G h L` is almost
/// nothing and which no scheme resolves at a reasonable cost.
pub fn apply_split(
    scn: &mut Scenario,
    sys: &mut System,
    d: &Decision,
    spent: f64,
) -> Option<(usize, usize)> {
    let k = d.floe;
    let parent = scn.floes[k].clone();
    let cut = d.line.cut(&parent, &sys.bodies[k])?;
    let [mut left, mut right] = split(&parent, &sys.bodies[k], &cut)?;
    if left.floe.area < scn.fracture.min_area || right.floe.area < scn.fracture.min_area {
        return None;
    }
    let conservation = conservation_error(&parent, &sys.bodies[k], &[left.clone(), right.clone()]);
    let t = sys.t;
    let ids = [scn.history.next_id, scn.history.next_id + 1];
    scn.history.next_id += 2;
    for (p, id) in [(&mut left, ids[0]), (&mut right, ids[1])] {
        p.floe.id = id;
        p.floe.t_birth = t;
        p.floe.theta_birth = parent.theta_birth + sys.bodies[k].angle;
    }
    scn.history.ended.push(FloeRecord::of(&parent, Some(t)));
    scn.history.fractures.push(FractureRecord {
        t,
        parent: parent.id,
        children: ids.to_vec(),
        model: scn.fracture.model.name(),
        measure: d.measure,
        threshold: d.threshold,
        energy: spent,
        conservation,
    });
    scn.floes[k] = left.floe;
    sys.bodies[k] = left.state;
    scn.floes.push(right.floe);
    sys.bodies.push(right.state);
    sys.ledger.dissipated -= spent;
    sys.ledger.fracture += spent;
    Some((k, scn.floes.len() - 1))
}
