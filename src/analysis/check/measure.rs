//! Measurements on a recorded run that several checks share: when a floe
//! comes to rest, the deepest overlap at the output times, a floe's final
//! velocity (its material's, through its pieces, when floes broke).

use crate::analysis::divergence::{material_rows, row_frames};
use crate::contact::{compound_signed_distance, Aabb, BroadPhase, Compound};
use crate::geometry::Vec2;
use crate::model::{parts_of, Scenario};
use crate::run::{RunResult, TrajectoryRow};

/// The first output time from which floe `floe` moves slower than `speed`
/// (m/s) at every later output; `None` if it still moves at the end.
pub fn rest_time(rows: &[TrajectoryRow], floe: usize, speed: f64) -> Option<f64> {
    let mine = || rows.iter().filter(|r| r.floe == floe);
    let last_move = mine()
        .filter(|r| r.vx.hypot(r.vy) > speed)
        .map(|r| r.t)
        .reduce(f64::max);
    match last_move {
        None => mine().map(|r| r.t).next(),
        Some(tm) => mine().map(|r| r.t).find(|&t| t > tm),
    }
}

/// The deepest overlap (m, ≥ 0) between two floes or a floe and an obstacle
/// at the output times of `run`: the minimum translation distance
/// ([`compound_signed_distance`]: of the deepest pair of convex parts for
/// a non-convex body) of every overlapping pair, each floe alive at that
/// time drawn from its record ([`RunResult::floes`]: the pieces of broken
/// floes included).
pub fn sampled_penetration(scn: &Scenario, run: &RunResult) -> f64 {
    let mut bp = BroadPhase::new();
    let mut pairs = Vec::new();
    let mut deepest = 0.0f64;
    for sample in row_frames(&run.trajectory) {
        let n = sample.len();
        let mut polys: Vec<Vec<Vec2>> = sample
            .iter()
            .filter_map(|r| {
                let mut p = Vec::new();
                let rec = run.floes.get(r.floe)?;
                rec.world_polygon(&Vec2::new(r.x, r.y), r.theta, &mut p);
                Some(p)
            })
            .collect();
        if polys.len() != n {
            continue;
        }
        polys.extend(scn.obstacles.iter().map(|o| o.polygon.clone()));
        // Convex parts of non-convex outlines (one part for a convex one).
        let parts: Vec<Vec<Vec<usize>>> = polys.iter().map(|p| parts_of(p)).collect();
        let boxes: Vec<Aabb> = polys
            .iter()
            .enumerate()
            .map(|(i, p)| Aabb::of_polygon(p, i >= n))
            .collect();
        bp.pairs(&boxes, 0.0, &mut pairs);
        let body = |i: usize| Compound {
            outline: &polys[i],
            parts: &parts[i],
        };
        for &(i, j) in &pairs {
            deepest = deepest.max(-compound_signed_distance(&body(i), &body(j)));
        }
    }
    deepest
}

/// The final velocity of floe `i`, m/s.
pub(super) fn final_velocity(run: &RunResult, i: usize) -> Vec2 {
    if !run.fractures.is_empty() {
        return material_final_velocity(run, i);
    }
    run.final_state
        .bodies
        .get(i)
        .map_or(Vec2::zeros(), |b| b.velocity)
}

/// The velocity at the end of a run where floes broke of initial floe
/// `i`'s material (m/s): the mass-weighted velocity of its descendants alive
/// at the last output ([`material_rows`]). A split conserves momentum, so
/// it is the velocity the floe's momentum gives, whatever its fracture
/// history. NaN (a failing check) if the last output is not the run's end.
fn material_final_velocity(run: &RunResult, i: usize) -> Vec2 {
    let rows = material_rows(run);
    rows.iter()
        .rev()
        .find(|row| row.floe == i)
        .filter(|row| row.t == run.summary.t_reached)
        .map_or(Vec2::new(f64::NAN, f64::NAN), |row| {
            Vec2::new(row.vx, row.vy)
        })
}
