//! Floes that break (docs/physics.md §9): the loads a contact solve puts on
//! each floe, the two criteria (`energy`, `stress`) and the lattice model,
//! the cut rule, and the one function that changes a run's floe set
//! ([`apply_split`]).
//!
//! Fracture is a stage of the run's topology ([`stage::FractureStage`],
//! with the crush stage [`crush::CrushStage`] in [`topology::RunTopology`],
//! owned by the [`crate::run::Runner`]): formulations report each contact solve's
//! impulses to it as [`Load`]s ([`loads_of`]); its [`Fracturer`] decides
//! which floes break and where, and at the formulation's next safe point
//! [`apply_split`] replaces each by its pieces in the scenario, the state
//! and the history together. Without a `[fracture]` table (or
//! `model = "none"`) nothing here runs. The lattice model (`strike`) keeps
//! the crack of its largest percussion in the history ([`crack`]). With
//! `impact = "lattice"` the stage also resolves impacts of one pair in
//! the floes' lattices ([`impact`], docs/physics.md §9.10). Ice that
//! crushes at contacts (`[contact] crushing`) is cut from the floes by
//! [`crush`] (docs/physics.md §10), which changes outlines, not the floe
//! set.
//!
//! To add a fracture rule: its name in [`FractureModel`] and the case
//! keys it reads with their limits (`src/model/fracture.rs`,
//! `src/model/limits/fracture.rs`, docs/case-format.md); its decision in
//! one file of this folder, called from one arm of
//! [`Fracturer::decide_over`] (a [`Decision`] with its cut line, or its
//! pieces); whether it reads sustained forces ([`stage::FractureStage::new`]);
//! its section in docs/physics.md §9 and its tests. No formulation changes:
//! every formulation that reports its solves runs it.

pub mod chain;
pub mod crack;
pub mod crush;
pub mod forces;
pub mod impact;
pub mod lattice;
pub mod split;
pub mod stage;
pub mod stress;
pub mod strike;
pub mod topology;

pub use crate::contact::{loads_of, Load};
use crate::geometry::{rotate, Vec2};
use crate::model::fracture::{FloeRecord, FractureModel, FractureRecord};
use crate::model::Scenario;
use crate::state::{BodyState, System};
use split::{conservation_error, cut_floe, split, Cut, Piece};
use std::collections::BTreeMap;

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
    /// for `stress`, the lattice's loss for `lattice`).
    pub crack_energy: f64,
    /// The pieces of the lattice model (`None`: the chord cut on `line`).
    pub lattice: Option<strike::LatticeSplit>,
}

/// A formulation's fracture state: the criterion of the case and, for the
/// stress criterion, the recent stresses of each floe (by id).
#[derive(Debug, Clone, Default)]
pub struct Fracturer {
    history: BTreeMap<usize, stress::Window>,
    fractures: u64,
    /// The lattice model's lattices, by floe id (built once per shape: a
    /// floe the crush stage cuts is forgotten, [`Fracturer::forget_shape`]).
    lattices: BTreeMap<usize, lattice::Lattice>,
    /// Why the lattice of a floe (by id) cannot be built: the build is
    /// deterministic, so it is tried once per floe, not at each impact.
    unbuildable: BTreeMap<usize, String>,
    percussions: u64,
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

    /// Forgets what it kept of the shape of floe `id` (its lattice, or
    /// why it could not be built): the crush stage changed its outline
    /// (docs/physics.md §10), so its lattice is built again when needed.
    pub fn forget_shape(&mut self, id: usize) {
        self.lattices.remove(&id);
        self.unbuildable.remove(&id);
    }

    /// The percussions the lattice model ran so far.
    pub fn percussions(&self) -> u64 {
        self.percussions
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
                            lattice: None,
                        });
                    }
                }
                FractureModel::Lattice => {
                    if f.area < s.min_area {
                        continue;
                    }
                    if let Some(d) = self.percussion(scn, sys, floe, &pairs) {
                        out.push(d);
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
                                lattice: None,
                            });
                        }
                    }
                }
            }
        }
        out
    }

    /// The lattice model's decision for floe `floe` under `pairs`: one
    /// percussion with every pair's equivalent impact as a striker at once
    /// ([`strike::equivalent_impacts`], docs/physics.md §9.8), when the
    /// trigger lets it run and it leaves at least two pieces.
    fn percussion(
        &mut self,
        scn: &Scenario,
        sys: &System,
        floe: usize,
        pairs: &[PairLoad],
    ) -> Option<Decision> {
        let s = &scn.fracture;
        let f = &scn.floes[floe];
        let impacts = strike::equivalent_impacts(scn, sys, floe, pairs)?;
        // The decision's line is the cut of the other models; the lattice's
        // pieces do not use it, so it only records the first striker.
        let first = *impacts.first()?;
        let lattice = self.lattice_of(scn, f).ok()?;
        let always = s.trigger == crate::model::fracture::Trigger::Always;
        let out = strike::strike_all(
            lattice,
            &impacts,
            strike::chain_options(s),
            always,
            s.min_area,
            f.density * f.thickness,
        )
        .ok()?;
        if out.ran {
            self.percussions += 1;
        }
        let split = out.split?;
        Some(Decision {
            floe,
            line: BodyLine {
                point: first.point,
                dir: first.normal,
            },
            length: 0.0,
            measure: out.bound,
            threshold: out.weakest,
            crack_energy: split.loss,
            lattice: Some(split),
        })
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
            // The window is kept by floe id, not by index.
            let id = scn.floes[d.floe].id;
            let applied = match &d.lattice {
                None => {
                    let spent = d.crack_energy.min(budget);
                    apply_split(scn, sys, d, spent).map(|_| spent)
                }
                Some(l) => {
                    let pose = sys.bodies[d.floe];
                    let taken = apply_lattice(scn, sys, d, l, budget);
                    // The crack of the run's largest percussion (crack.rs).
                    if let (Some(_), Some(lat), Some(row)) = (
                        taken,
                        self.lattices.get(&id),
                        scn.history.fractures.last().cloned(),
                    ) {
                        crack::keep(&mut scn.history, lat, l, &pose, &row);
                    }
                    taken
                }
            };
            if let Some(taken) = applied {
                budget = (budget - taken).max(0.0);
                self.history.remove(&id);
                self.lattices.remove(&id);
                done += 1;
                self.fractures += 1;
            }
        }
        done
    }
}

/// Replaces floe `d.floe` of `scn` and `sys` by its two pieces on
/// `d.line` (at the floe's pose in `sys`) at time `sys.t` ([`replace`]:
/// the left piece takes the parent's index, the right one is appended), and
/// `spent` (J) moves from the ledger's `dissipated` to its `fracture`
/// column. Returns the pieces' indices, or `None` (nothing changed) when
/// the cut leaves a piece without area or one smaller than the case's
/// `min_area`: a chord through a loaded corner can cut off a sliver
/// (7.6e-5 m long, 5e-7 m² of a floe of hundreds, on the narrow channel),
/// whose crack energy `G h L` is almost nothing and which no scheme
/// resolves at a reasonable cost.
pub fn apply_split(
    scn: &mut Scenario,
    sys: &mut System,
    d: &Decision,
    spent: f64,
) -> Option<(usize, usize)> {
    let k = d.floe;
    let parent = scn.floes[k].clone();
    let cut = d.line.cut(&parent, &sys.bodies[k])?;
    let pieces = split(&parent, &sys.bodies[k], &cut)?;
    if pieces.iter().any(|p| p.floe.area < scn.fracture.min_area) {
        return None;
    }
    let conservation = conservation_error(&parent, &sys.bodies[k], &pieces, true);
    let at = replace(scn, sys, d, pieces.into(), conservation, spent, 0.0);
    Some((at[0], at[1]))
}

/// Replaces floe `d.floe` by the lattice model's pieces `l` at `sys.t`
/// ([`strike::pieces`], docs/physics.md §9.8). The kinetic energy the
/// pieces gain over the parent, `ΔK`, leaves the ledger's `dissipated`
/// column, and the lattice's loss, at most what the solve dissipated less
/// `ΔK` (`budget`, J), moves from it to `fracture`. Returns the energy taken
/// from `budget` (`ΔK` + the loss booked), or `None` (nothing changed) when
/// a piece has no area.
pub fn apply_lattice(
    scn: &mut Scenario,
    sys: &mut System,
    d: &Decision,
    l: &strike::LatticeSplit,
    budget: f64,
) -> Option<f64> {
    let k = d.floe;
    let parent = scn.floes[k].clone();
    let b = sys.bodies[k];
    let pieces = strike::pieces(&parent, &b, l)?;
    let conservation = conservation_error(&parent, &b, &pieces, false);
    let gain = pieces
        .iter()
        .map(|p| {
            p.floe
                .kinetic_energy(&p.state.velocity, p.state.angular_velocity)
        })
        .sum::<f64>()
        - parent.kinetic_energy(&b.velocity, b.angular_velocity);
    let spent = l.loss.min(budget - gain).max(0.0);
    // ΔK ≥ 0 in exact arithmetic (§9.8); a rounding below zero is booked as is.
    replace(scn, sys, d, pieces, conservation, spent, gain);
    Some(spent + gain)
}

/// Replaces floe `d.floe` by `pieces` (at least two) at `sys.t`: the first
/// takes the parent's index, the others are appended in order (so every
/// other floe keeps its index), each with the next id; the parent ends in
/// `scn.history`, with the fracture's row (`energy` = `fracture`,
/// `kinetic_gain` = `gain`, J); `fracture + gain` (J) leaves the ledger's
/// `dissipated` column and `fracture` joins its `fracture` column (the
/// pieces' kinetic energy above the parent's, `gain`, is in the state).
/// Returns the pieces' indices.
fn replace(
    scn: &mut Scenario,
    sys: &mut System,
    d: &Decision,
    pieces: Vec<Piece>,
    conservation: f64,
    fracture: f64,
    gain: f64,
) -> Vec<usize> {
    let k = d.floe;
    let parent = scn.floes[k].clone();
    let t = sys.t;
    let first = scn.history.next_id;
    scn.history.next_id += pieces.len();
    let ids: Vec<usize> = (first..scn.history.next_id).collect();
    scn.history.ended.push(FloeRecord::of(&parent, Some(t)));
    scn.history.fractures.push(FractureRecord {
        t,
        parent: parent.id,
        children: ids.clone(),
        model: scn.fracture.model.name(),
        measure: d.measure,
        threshold: d.threshold,
        energy: fracture,
        kinetic_gain: gain,
        conservation,
    });
    let theta = parent.theta_birth + sys.bodies[k].angle;
    let mut at = Vec::with_capacity(pieces.len());
    for (j, (mut p, id)) in pieces.into_iter().zip(ids).enumerate() {
        p.floe.id = id;
        p.floe.t_birth = t;
        p.floe.theta_birth = theta;
        if j == 0 {
            scn.floes[k] = p.floe;
            sys.bodies[k] = p.state;
            at.push(k);
        } else {
            scn.floes.push(p.floe);
            sys.bodies.push(p.state);
            at.push(scn.floes.len() - 1);
        }
    }
    sys.ledger.dissipated -= fracture + gain;
    sys.ledger.fracture += fracture;
    at
}
