//! The forces stage of the run's topology: it changes nothing, it reads
//! the impulses the formulations report ([`Load`]s of their percussions and
//! sustained contacts) and turns them into data, per output interval
//! `(t_prev, t]` (docs/output-format.md, `obstacles.csv` and `stress.csv`):
//!
//! - the **mean force on each obstacle**, N: minus the sum of the impulses
//!   on the floes whose other body is that obstacle, divided by the
//!   interval; its torque, N·m, about the obstacle's centroid (the area
//!   centroid of its outline);
//! - the **pack's mean stress tensor** by Love–Weber (Love 1927; Weber
//!   1966; Christoffersen, Mehrabadi & Nemat-Nasser 1981):
//!   `σ_ij = (1/A) Σ_loads (x_c − G)_i P_j / Δt`, N/m (integrated over
//!   the thickness), with `x_c` the load's point, `G` its floe's centre of
//!   mass at the load's time, `P` its impulse (N·s) and `A` the total
//!   area of the floes at the interval's end (m²: the mean stress in the
//!   ice itself, not in the ice and the open water around it, which has no
//!   well-defined extent; multiply by the concentration for a stress per
//!   unit area of ocean). Every contact between two floes counts on both;
//!   a contact with an obstacle on its floe only (the obstacle's reaction
//!   is the boundary traction on the pack). Tension positive: a pack under
//!   compression has negative `sxx`, `syy`, and its mean pressure is
//!   `p = −(sxx + syy)/2`.
//!
//! Impulses are what the formulations exchange in every scheme (an impact
//! at an instant, a time step's, an event-driven step's sustained
//! contacts), so fixed-step and event-driven runs are compared on the same
//! footing: an impulse at an instant goes to the interval holding it
//! (an instant at an output time to the interval it ends); an impulse
//! delivered over `[from, to]` is split between the intervals it overlaps,
//! in proportion to the overlap (a uniform rate over the step).
//!
//! The stage reads loads only in a run that may have contacts (at least one
//! obstacle or two floes, [`ForceStage::reads`]); reading them changes no
//! result (tested: `forces::reading_loads_changes_no_result`).

use crate::contact::Load;
use crate::geometry::{area_properties, Vec2};
use crate::model::{Body, Scenario};
use crate::state::System;

/// One row of `obstacles.csv`: the mean force on one obstacle over the
/// output interval ending at `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObstacleForce {
    /// The interval's end, s.
    pub t: f64,
    /// The obstacle (its index among the case's obstacles).
    pub obstacle: usize,
    /// Mean force on the obstacle, x, N.
    pub fx: f64,
    /// Mean force on the obstacle, y, N.
    pub fy: f64,
    /// Mean torque on the obstacle about its centroid, N·m
    /// (counter-clockwise positive).
    pub torque: f64,
}

/// One row of `stress.csv`: the pack's mean stress over the output
/// interval ending at `t` (N/m; tension positive).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PackStress {
    /// The interval's end, s.
    pub t: f64,
    /// σ_xx, N/m.
    pub sxx: f64,
    /// σ_xy (branch along x, force along y), N/m.
    pub sxy: f64,
    /// σ_yx (branch along y, force along x), N/m.
    pub syx: f64,
    /// σ_yy, N/m.
    pub syy: f64,
    /// The total area of the floes at `t`, m².
    pub area: f64,
}

impl PackStress {
    /// The mean pressure `p = −(σ_xx + σ_yy)/2`, N/m (positive in
    /// compression).
    pub fn pressure(&self) -> f64 {
        -(self.sxx + self.syy) / 2.0
    }
}

/// What one output interval collected: per obstacle the impulse (N·s)
/// and its moment about the obstacle's centroid (N·m·s), and the sum of
/// `(x_c − G) ⊗ P` (N·m·s, `[xx, xy, yx, yy]`).
#[derive(Debug, Clone, Default)]
struct Bin {
    obstacles: Vec<(Vec2, f64)>,
    moment: [f64; 4],
}

/// The forces stage (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct ForceStage {
    /// Whether it reads loads.
    reads: bool,
    /// The start of the run, s.
    start: f64,
    /// The output times, s, increasing.
    times: Vec<f64>,
    /// One bin per output interval.
    bins: Vec<Bin>,
    /// The obstacles' centroids, m.
    centroids: Vec<Vec2>,
    /// The output times reached so far, s, and the floes' total area
    /// then, m² ([`ForceStage::close`]).
    closed: Vec<(f64, f64)>,
}

impl ForceStage {
    /// The stage of a run of `scn` from `start` (s) with output times
    /// `times` (s, increasing); `observe`: whether it reads loads at all
    /// (it does only when the case has an obstacle or two floes).
    pub fn new(scn: &Scenario, start: f64, times: &[f64], observe: bool) -> ForceStage {
        let centroids: Vec<Vec2> = scn
            .obstacles
            .iter()
            .map(|o| area_properties(&o.polygon).centroid)
            .collect();
        let bin = Bin {
            obstacles: vec![(Vec2::zeros(), 0.0); centroids.len()],
            moment: [0.0; 4],
        };
        ForceStage {
            reads: observe && (!scn.obstacles.is_empty() || scn.floes.len() >= 2),
            start,
            times: times.to_vec(),
            bins: vec![bin; times.len()],
            centroids,
            ..ForceStage::default()
        }
    }

    /// Whether it reads the formulations' loads (percussions and
    /// sustained).
    pub fn reads(&self) -> bool {
        self.reads
    }

    /// Books the impulses `loads` delivered over `[from, to]` (s; an
    /// instant when equal) on the floes of `sys`.
    pub fn load(&mut self, scn: &Scenario, sys: &System, loads: &[Load], from: f64, to: f64) {
        if !self.reads || loads.is_empty() {
            return;
        }
        // An instant: the interval (t_{k−1}, t_k] holding it; a span: the
        // intervals it overlaps, from the first that ends after `from`.
        let instant = to <= from;
        let first = match instant {
            true => self.times.partition_point(|&t| t < from),
            false => self.times.partition_point(|&t| t <= from),
        };
        for k in first..self.times.len() {
            let lo = if k == 0 {
                self.start
            } else {
                self.times[k - 1]
            };
            let hi = self.times[k];
            let share = match instant {
                true => 1.0,
                false => (hi.min(to) - lo.max(from)).max(0.0) / (to - from),
            };
            if share > 0.0 {
                self.book(k, scn, sys, loads, share);
            }
            if instant || to <= hi {
                break;
            }
        }
    }

    /// Books the share `share` of `loads` in interval `k`.
    fn book(&mut self, k: usize, scn: &Scenario, sys: &System, loads: &[Load], share: f64) {
        let bin = &mut self.bins[k];
        for l in loads {
            let p = l.impulse * share;
            if let Some(b) = sys.bodies.get(l.floe) {
                let r = l.point - b.position;
                bin.moment[0] += r.x * p.x;
                bin.moment[1] += r.x * p.y;
                bin.moment[2] += r.y * p.x;
                bin.moment[3] += r.y * p.y;
            }
            if let Body::Obstacle(j) = scn.body(l.other) {
                if let (Some(slot), Some(c)) = (bin.obstacles.get_mut(j), self.centroids.get(j)) {
                    // The reaction on the obstacle, at the load's point.
                    let r = l.point - c;
                    slot.0 -= p;
                    slot.1 -= r.x * p.y - r.y * p.x;
                }
            }
        }
    }

    /// Closes the output interval ending at `sys.t` (the runner calls it
    /// at each output time it records, in order): the floes' area is taken
    /// from `scn` now. Its rows are made by [`ForceStage::take_rows`], at
    /// the end of the run: a step of the formulation's own grid that
    /// straddles the output time may be taken after it (an event-driven
    /// step continued past it), and its share still counts.
    pub fn close(&mut self, scn: &Scenario, sys: &System) {
        if self.closed.len() < self.times.len() {
            self.closed
                .push((sys.t, scn.floes.iter().map(|f| f.area).sum()));
        }
    }

    /// The rows of the intervals closed: (`obstacles.csv`, `stress.csv`).
    pub fn take_rows(&mut self) -> (Vec<ObstacleForce>, Vec<PackStress>) {
        let (mut obstacles, mut stress) = (Vec::new(), Vec::new());
        for (k, &(t, area)) in self.closed.iter().enumerate() {
            let lo = if k == 0 {
                self.start
            } else {
                self.times[k - 1]
            };
            let dt = self.times[k] - lo;
            let bin = std::mem::take(&mut self.bins[k]);
            let rate = |x: f64| if dt > 0.0 { x / dt } else { 0.0 };
            for j in 0..self.centroids.len() {
                let (f, m) = bin
                    .obstacles
                    .get(j)
                    .copied()
                    .unwrap_or((Vec2::zeros(), 0.0));
                obstacles.push(ObstacleForce {
                    t,
                    obstacle: j,
                    fx: rate(f.x),
                    fy: rate(f.y),
                    torque: rate(m),
                });
            }
            let s = |m: f64| if area > 0.0 { rate(m) / area } else { 0.0 };
            stress.push(PackStress {
                t,
                sxx: s(bin.moment[0]),
                sxy: s(bin.moment[1]),
                syx: s(bin.moment[2]),
                syy: s(bin.moment[3]),
                area,
            });
        }
        self.closed.clear();
        (obstacles, stress)
    }
}
