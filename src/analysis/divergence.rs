//! How two runs of the same case differ over time.
//!
//! Trajectory differences are taken between the states recorded at the same
//! output times: for each time, the position difference of each floe's centre
//! of mass (m) and the difference of its cumulative rotation angle (rad, not
//! wrapped: a floe that turned a full turn more has turned 2π more). The
//! position difference is summarised by its RMS over floes, divided by the
//! median floe diameter `d_med` (the median of the equal-area diameters
//! `2·sqrt(A/π)`, [`Scenario::median_floe_diameter`], the one length scale
//! of the report), and by its maximum over floes, in metres. Runs in which
//! floes broke are compared by the material of each initial floe (the
//! mass-weighted centre of its pieces, [`material_rows`]).

use crate::model::Scenario;
use crate::run::{RunResult, TrajectoryRow};
use serde::Serialize;

/// Two runs of a case recorded different output times, so they cannot be
/// compared time by time.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{a} and {b} recorded different output times ({t_a} s and {t_b} s)")]
pub struct TimeMismatch {
    /// The first run's formulation.
    pub a: String,
    /// The second run's formulation.
    pub b: String,
    /// The first run's output time, s.
    pub t_a: f64,
    /// The second run's output time at the same index, s.
    pub t_b: f64,
}

/// The difference of two runs at one output time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DivergenceSample {
    /// Time, s.
    pub t: f64,
    /// RMS over floes of the position difference, divided by the median floe diameter (-).
    pub rms_position_rel: f64,
    /// Largest position difference of a floe, m.
    pub max_position_m: f64,
    /// RMS over floes of the angle difference, rad.
    pub rms_angle_rad: f64,
    /// Largest angle difference of a floe, rad.
    pub max_angle_rad: f64,
}

/// How two runs of the same case differ over time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairDivergence {
    /// First formulation (the reference).
    pub a: String,
    /// Second formulation.
    pub b: String,
    /// The difference at each output time both runs reached.
    pub samples: Vec<DivergenceSample>,
    /// Largest RMS relative position difference over time (-).
    pub max_rms_position_rel: f64,
    /// Largest position difference of any floe at any time, m.
    pub max_position_m: f64,
    /// Largest angle difference of any floe at any time, rad.
    pub max_angle_rad: f64,
    /// RMS relative position difference at the last common time (-).
    pub final_rms_position_rel: f64,
    /// The threshold on the RMS relative position difference (-).
    pub threshold: f64,
    /// The first output time at which the RMS relative position difference
    /// exceeds the threshold, s; `None` if it never does.
    pub diverged_at: Option<f64>,
}

/// The trajectory cut into frames: one slice of rows per output time (the
/// floes alive then, by id; every floe of the case when none breaks).
pub fn frames(run: &RunResult) -> impl Iterator<Item = &[TrajectoryRow]> {
    row_frames(&run.trajectory)
}

/// [`frames`] of trajectory rows.
pub fn row_frames(rows: &[TrajectoryRow]) -> impl Iterator<Item = &[TrajectoryRow]> {
    rows.chunk_by(|a, b| a.t == b.t)
}

/// Whether two frames hold the same floes, in the same order.
fn same_floes(a: &[TrajectoryRow], b: &[TrajectoryRow]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.floe == y.floe)
}

/// The divergence between runs `a` and `b` of `scn`, over the output times
/// both reached. `threshold` is on the RMS position difference relative to
/// the median floe diameter.
///
/// When a floe broke in either run, each initial floe is followed through
/// its descendants instead ([`material_rows`]): the runs are compared by
/// the mass-weighted centre and orientation of each initial floe's
/// material, whatever their fracture histories (docs/physics.md §9.7).
pub fn divergence(
    scn: &Scenario,
    a: &RunResult,
    b: &RunResult,
    threshold: f64,
) -> Result<PairDivergence, TimeMismatch> {
    if a.fractures.is_empty() && b.fractures.is_empty() {
        return divergence_of_rows(
            scn,
            (&a.summary.formulation, &a.trajectory),
            (&b.summary.formulation, &b.trajectory),
            threshold,
        );
    }
    divergence_of_rows(
        scn,
        (&a.summary.formulation, &material_rows(a)),
        (&b.summary.formulation, &material_rows(b)),
        threshold,
    )
}

/// The trajectory of each initial floe's material: at every output, one
/// row per initial floe (id `r`) with the mass-weighted centre (m) and
/// velocity (m/s) of its descendants alive then, and their mass-weighted
/// orientation against its own at t = 0 (`theta_birth + θ`, rad) and
/// angular velocity. For a floe that never broke these are its own. Mass
/// is conserved by a split, so the weights of a root always sum to its
/// mass.
pub fn material_rows(run: &RunResult) -> Vec<TrajectoryRow> {
    // Records are by id and a parent's id is below its pieces'.
    let mut root: Vec<usize> = Vec::with_capacity(run.floes.len());
    for (id, f) in run.floes.iter().enumerate() {
        let r = f.parent.and_then(|p| root.get(p).copied()).unwrap_or(id);
        root.push(r);
    }
    let roots = run.floes.iter().filter(|f| f.parent.is_none()).count();
    let mut out = Vec::new();
    for frame in row_frames(&run.trajectory) {
        let mut acc = vec![[0.0f64; 7]; roots];
        // A root with one floe alive (it never broke) is that floe's row.
        let mut only: Vec<(usize, Option<TrajectoryRow>)> = vec![(0, None); roots];
        for row in frame {
            let (Some(&r), Some(f)) = (root.get(row.floe), run.floes.get(row.floe)) else {
                continue;
            };
            let Some(a) = acc.get_mut(r) else { continue };
            let m = f.mass;
            let th = f.theta_birth + row.theta;
            only[r].0 += 1;
            only[r].1 = Some(TrajectoryRow {
                floe: r,
                theta: th,
                ..*row
            });
            for (k, v) in [
                m,
                m * row.x,
                m * row.y,
                m * th,
                m * row.vx,
                m * row.vy,
                m * row.omega,
            ]
            .into_iter()
            .enumerate()
            {
                a[k] += v;
            }
        }
        for (r, a) in acc.iter().enumerate() {
            let m = a[0];
            if let (1, Some(row)) = only[r] {
                out.push(row);
            } else if m > 0.0 {
                out.push(TrajectoryRow {
                    t: frame[0].t,
                    floe: r,
                    x: a[1] / m,
                    y: a[2] / m,
                    theta: a[3] / m,
                    vx: a[4] / m,
                    vy: a[5] / m,
                    omega: a[6] / m,
                });
            }
        }
    }
    out
}

/// [`divergence`] of two trajectories given as (run label, rows), e.g. a
/// reference read back from a file (`floebench sweep`).
pub fn divergence_of_rows(
    scn: &Scenario,
    (a, rows_a): (&str, &[TrajectoryRow]),
    (b, rows_b): (&str, &[TrajectoryRow]),
    threshold: f64,
) -> Result<PairDivergence, TimeMismatch> {
    let d = scn.median_floe_diameter();
    let mut samples = Vec::new();
    for (fa, fb) in row_frames(rows_a).zip(row_frames(rows_b)) {
        // Rows of different floes cannot be compared ([`divergence`]
        // compares runs that broke by their material instead).
        if !same_floes(fa, fb) {
            break;
        }
        let n = fa.len();
        let t = fa[0].t;
        if (t - fb[0].t).abs() > 1e-9 * t.abs().max(1.0) {
            return Err(TimeMismatch {
                a: a.to_string(),
                b: b.to_string(),
                t_a: t,
                t_b: fb[0].t,
            });
        }
        let (mut sp, mut mp, mut sa, mut ma) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for (ra, rb) in fa.iter().zip(fb) {
            let dp = (ra.x - rb.x).hypot(ra.y - rb.y);
            let da = (ra.theta - rb.theta).abs();
            sp += dp * dp;
            mp = mp.max(dp);
            sa += da * da;
            ma = ma.max(da);
        }
        let nf = n.max(1) as f64;
        samples.push(DivergenceSample {
            t,
            rms_position_rel: if d > 0.0 { (sp / nf).sqrt() / d } else { 0.0 },
            max_position_m: mp,
            rms_angle_rad: (sa / nf).sqrt(),
            max_angle_rad: ma,
        });
    }
    let max_of = |f: fn(&DivergenceSample) -> f64| samples.iter().map(f).fold(0.0, f64::max);
    Ok(PairDivergence {
        a: a.to_string(),
        b: b.to_string(),
        max_rms_position_rel: max_of(|s| s.rms_position_rel),
        max_position_m: max_of(|s| s.max_position_m),
        max_angle_rad: max_of(|s| s.max_angle_rad),
        final_rms_position_rel: samples.last().map_or(0.0, |s| s.rms_position_rel),
        threshold,
        diverged_at: samples
            .iter()
            .find(|s| s.rms_position_rel > threshold)
            .map(|s| s.t),
        samples,
    })
}
