//! The exact curves the checks know, beside the same quantity measured on
//! each run, for the report's plots ([`crate::report::figures`]): the gap of
//! the bouncing floe (impact times and rest marked), the distance slid
//! (stop marked), the speed of a drifting floe against its steady drift
//! speed, the inertial circles of the calm, and the crushing force of a
//! floe rammed into a coast. Each comes from the set-up
//! its checks recognise ([`super::Bouncing`], [`super::Sliding`],
//! [`super::Drift`], [`super::Inertial`]), so a curve is drawn exactly when
//! its checks apply.

use super::ram::{Ram, RamShape};
use super::setup::{Bouncing, Drift, Inertial, Sliding};
use crate::geometry::Vec2;
use crate::model::Scenario;
use crate::run::RunResult;

/// Points of an exact curve sampled over a run.
const SAMPLES: usize = 2000;

/// Impact times marked on the bouncing plot, at most.
const MARKED_IMPACTS: usize = 6;

/// Quadrature steps per output interval of the exact inertial path.
const PATH_SUBSTEPS: usize = 16;

/// An exact curve and the same quantity on each run.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactCurve {
    /// File stem of the plot.
    pub stem: &'static str,
    /// What the plot shows (its title and alternative text).
    pub what: String,
    /// x axis label with unit.
    pub x_label: String,
    /// y axis label with unit.
    pub y_label: String,
    /// A plan view (x, y in metres, equal aspect) rather than a curve
    /// against time.
    pub plan: bool,
    /// The exact curve's legend label.
    pub exact_label: String,
    /// The exact curve.
    pub exact: Vec<(f64, f64)>,
    /// Marked instants (vertical lines on a time axis): time, label.
    pub marks: Vec<(f64, String)>,
    /// The measured quantity of each run (same order as the runs).
    pub measured: Vec<Vec<(f64, f64)>>,
}

/// `n + 1` equally spaced times over `[0, t_end]`.
fn times(t_end: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |k| t_end * k as f64 / n as f64)
}

/// The rows of floe `i` of `run` as `(t, f(row))`.
fn of_floe(
    run: &RunResult,
    i: usize,
    f: impl Fn(&crate::run::TrajectoryRow) -> f64,
) -> Vec<(f64, f64)> {
    run.trajectory
        .iter()
        .filter(|r| r.floe == i)
        .map(|r| (r.t, f(r)))
        .collect()
}

/// Every exact curve of `scn`, with the runs' measurements (see the module doc).
pub fn exact_curves(scn: &Scenario, runs: &[RunResult]) -> Vec<ExactCurve> {
    let mut out = Vec::new();
    let t_end = scn.duration;
    if let Some(b) = Bouncing::of(scn) {
        let mut ts: Vec<f64> = times(t_end, SAMPLES).collect();
        let impacts = b.impact_times(t_end, usize::MAX);
        ts.extend(&impacts);
        ts.sort_by(f64::total_cmp);
        let mut marks: Vec<(f64, String)> = impacts
            .iter()
            .take(MARKED_IMPACTS)
            .enumerate()
            .map(|(k, &t)| (t, format!("t{}", k + 1)))
            .collect();
        if let Some(tr) = b.rest_time().filter(|&t| t <= t_end) {
            marks.push((tr, "t∞ (rest)".into()));
        }
        out.push(ExactCurve {
            stem: "exact_bouncing",
            what: "gap to the obstacle against the exact bounces".into(),
            x_label: "t (s)".into(),
            y_label: "gap to the obstacle (m)".into(),
            plan: false,
            exact_label: "exact (impacts t_k, rest t∞)".into(),
            exact: ts.iter().map(|&t| (t, b.gap_at(t))).collect(),
            marks,
            measured: runs
                .iter()
                .map(|r| of_floe(r, 0, |row| b.gap_of(Vec2::new(row.x, row.y))))
                .collect(),
        });
    }
    if let Some(ram) = Ram::of(scn).filter(|r| r.force_at(0.0).is_some()) {
        let (_, _, duration) = ram.exact();
        let mut ts: Vec<f64> = times(t_end, SAMPLES).collect();
        ts.extend([ram.t_contact, ram.t_contact + duration]);
        ts.sort_by(f64::total_cmp);
        out.push(ExactCurve {
            stem: "exact_crushing",
            what: "crushing force against its closed form".into(),
            x_label: "t (s)".into(),
            y_label: "crushing force (N)".into(),
            plan: false,
            exact_label: match ram.shape {
                RamShape::Corner(_) => "exact: V sqrt(M k) sin(omega t)".into(),
                RamShape::Face(_) => "exact: p(h w) h w".into(),
            },
            exact: ts
                .iter()
                .filter_map(|&t| ram.force_at(t).map(|f| (t, f)))
                .collect(),
            marks: vec![
                (ram.t_contact, "contact".into()),
                (ram.t_contact + duration, "stop".into()),
            ],
            measured: runs.iter().map(|r| ram.interval_forces(r)).collect(),
        });
    }
    if let Some(sl) = Sliding::of(scn) {
        let mut ts: Vec<f64> = times(t_end, SAMPLES).collect();
        ts.push(sl.t_stop);
        ts.sort_by(f64::total_cmp);
        out.push(ExactCurve {
            stem: "exact_sliding",
            what: "distance slid against the exact deceleration at mu a".into(),
            x_label: "t (s)".into(),
            y_label: "distance slid along v0 (m)".into(),
            plan: false,
            exact_label: "exact (stop at v0 / (mu a))".into(),
            exact: ts.iter().map(|&t| (t, sl.distance_at(t))).collect(),
            marks: vec![(sl.t_stop, "stop".into())],
            measured: runs
                .iter()
                .map(|r| {
                    of_floe(r, 0, |row| {
                        (Vec2::new(row.x, row.y) - sl.start).dot(&sl.dir)
                    })
                })
                .collect(),
        });
    }
    if let Some(d) = Drift::of(scn) {
        let (i, u, _) = d.floes[0];
        out.push(ExactCurve {
            stem: "exact_drift",
            what: format!("speed of floe {i} against the steady drift speed"),
            x_label: "t (s)".into(),
            y_label: format!("speed of floe {i} (m/s)"),
            plan: false,
            exact_label: "steady drift speed |u| (exact, docs/physics.md §2.2)".into(),
            exact: vec![(0.0, u.norm()), (t_end, u.norm())],
            marks: Vec::new(),
            measured: runs
                .iter()
                .map(|r| of_floe(r, i, |row| row.vx.hypot(row.vy)))
                .collect(),
        });
    }
    if let (Some(inr), Some(reference)) = (Inertial::of(scn), runs.first()) {
        let calm = |r: &RunResult| -> Vec<(f64, f64)> {
            r.trajectory
                .iter()
                .filter(|row| row.floe == 0 && row.t >= inr.t_calm)
                .map(|row| (row.x, row.y))
                .collect()
        };
        let start = reference
            .trajectory
            .iter()
            .find(|row| row.floe == 0 && row.t >= inr.t_calm);
        if let Some(s) = start {
            let steps = ((t_end - s.t) / scn.output_interval).ceil().max(1.0) as usize;
            let exact = inertial_path(
                &inr,
                Vec2::new(s.x, s.y),
                Vec2::new(s.vx, s.vy),
                t_end - s.t,
                steps * PATH_SUBSTEPS,
            );
            out.push(ExactCurve {
                stem: "exact_inertial",
                what: "inertial circles after the wind stops".into(),
                x_label: "x (m)".into(),
                y_label: "y (m)".into(),
                plan: true,
                exact_label: format!(
                    "exact from {}'s state at t = {} s",
                    reference.summary.formulation, s.t
                ),
                exact,
                marks: Vec::new(),
                measured: runs.iter().map(calm).collect(),
            });
        }
    }
    out
}

/// The exact path of the calm of `inr` from position `p0` and velocity
/// `v0` over `duration` (s), by Simpson's rule on `n` steps of the exact
/// velocity ([`Inertial::velocity_after`]); points `(x, y)`, m.
pub fn inertial_path(
    inr: &Inertial,
    p0: Vec2,
    v0: Vec2,
    duration: f64,
    n: usize,
) -> Vec<(f64, f64)> {
    let n = n.max(1);
    let h = duration / n as f64;
    let mut p = p0;
    let mut out = Vec::with_capacity(n + 1);
    out.push((p.x, p.y));
    for k in 0..n {
        let s = k as f64 * h;
        let (a, m, b) = (
            inr.velocity_after(v0, s),
            inr.velocity_after(v0, s + 0.5 * h),
            inr.velocity_after(v0, s + h),
        );
        p += (a + m * 4.0 + b) * (h / 6.0);
        out.push((p.x, p.y));
    }
    out
}
