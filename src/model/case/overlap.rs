//! No two bodies may overlap at t = 0: listed floes with each other and
//! with obstacles, field floes with listed floes and obstacles (touching is
//! allowed, to [`OVERLAP_TOLERANCE`]).

use super::{CaseError, Ctx};
use crate::geometry::broad::{Aabb, BroadPhase};
use crate::geometry::{sat_separation, Vec2};
use crate::model::{Floe, FloeOrigin, Obstacle};
use std::ops::Range;

/// Relative overlap tolerance at t = 0: touching polygons (a cradle) are
/// allowed, overlaps deeper than this fraction of the smaller size are not.
const OVERLAP_TOLERANCE: f64 = 1e-9;

pub(super) fn check_overlaps(
    ctx: &Ctx,
    floes: &[Floe],
    floe_spans: &[Range<usize>],
    obstacles: &[Obstacle],
    obstacle_spans: &[Range<usize>],
) -> Result<(), CaseError> {
    let world: Vec<Vec<Vec2>> = floes
        .iter()
        .map(|f| f.shape.iter().map(|p| p + f.position).collect())
        .collect();
    let fixed: Vec<&[Vec2]> = obstacles.iter().map(|o| o.polygon.as_slice()).collect();
    let mut bodies: Vec<&[Vec2]> = world.iter().map(|w| w.as_slice()).collect();
    bodies.extend(fixed.iter().copied());
    let parts = parts_of(floes, obstacles);
    if let Some(&(i, j)) = overlapping_pairs(&bodies, &parts, floes.len()).first() {
        let span = floe_spans.get(i).cloned();
        let msg = if j < floes.len() {
            format!(
                "[[floe]] #{i} and [[floe]] #{j} overlap at t = 0 (line {} and line {})",
                ctx.line_of(floe_spans[i].start),
                ctx.line_of(floe_spans[j].start)
            )
        } else {
            let k = j - floes.len();
            format!(
                "[[floe]] #{i} overlaps [[obstacle]] #{k} at t = 0 (obstacle at line {})",
                ctx.line_of(obstacle_spans[k].start)
            )
        };
        return Err(ctx.err(span, msg));
    }
    Ok(())
}

/// The convex parts of the floes, then of the obstacles.
fn parts_of<'a>(floes: &'a [Floe], obstacles: &'a [Obstacle]) -> Vec<&'a [Vec<usize>]> {
    floes
        .iter()
        .map(|f| f.parts.as_slice())
        .chain(obstacles.iter().map(|o| o.parts.as_slice()))
        .collect()
}

/// The separating-axis value of two bodies made of convex parts (`parts`:
/// indices into each outline): the smallest over the pairs of parts, so
/// negative when two parts overlap ([`sat_separation`] for two convex
/// bodies).
fn compound_sat(a: &[Vec2], pa: &[Vec<usize>], b: &[Vec2], pb: &[Vec<usize>]) -> f64 {
    if pa.len() <= 1 && pb.len() <= 1 {
        return sat_separation(a, b);
    }
    let pick =
        |poly: &[Vec2], ids: &[usize]| -> Vec<Vec2> { ids.iter().map(|&k| poly[k]).collect() };
    pa.iter()
        .flat_map(|ia| pb.iter().map(move |ib| (ia, ib)))
        .map(|(ia, ib)| sat_separation(&pick(a, ia), &pick(b, ib)))
        .fold(f64::INFINITY, f64::min)
}

/// Pairs `(i, j)`, `i < j`, of polygons that overlap by more than the
/// tolerance, skipping pairs where both indices are `>= n_movable` (two
/// obstacles may overlap). Sweep and prune on x, so not all pairs.
fn overlapping_pairs(
    bodies: &[&[Vec2]],
    parts: &[&[Vec<usize>]],
    n_movable: usize,
) -> Vec<(usize, usize)> {
    let boxes: Vec<Aabb> = bodies
        .iter()
        .enumerate()
        .map(|(i, b)| Aabb::of_polygon(b, i >= n_movable))
        .collect();
    let mut candidates = Vec::new();
    BroadPhase::new().pairs(&boxes, 0.0, &mut candidates);
    candidates
        .into_iter()
        .filter(|&(i, j)| {
            let size = (boxes[i].max - boxes[i].min)
                .norm()
                .min((boxes[j].max - boxes[j].min).norm());
            compound_sat(bodies[i], parts[i], bodies[j], parts[j]) < -OVERLAP_TOLERANCE * size
        })
        .collect()
}

pub(super) fn check_field_against_fixed(
    ctx: &Ctx,
    span: &Range<usize>,
    k: usize,
    floes: &[Floe],
    first: usize,
    obstacles: &[Obstacle],
) -> Result<(), CaseError> {
    let world: Vec<Vec<Vec2>> = floes
        .iter()
        .map(|f| f.shape.iter().map(|p| p + f.position).collect())
        .collect();
    let mut bodies: Vec<&[Vec2]> = world.iter().map(|w| w.as_slice()).collect();
    bodies.extend(obstacles.iter().map(|o| o.polygon.as_slice()));
    let parts = parts_of(floes, obstacles);
    for (i, j) in overlapping_pairs(&bodies, &parts, floes.len()) {
        // Field floes do not overlap each other by construction; report the
        // first clash with something else.
        if j < first && i < first {
            continue;
        }
        let name = |idx: usize| -> String {
            if idx >= floes.len() {
                format!("[[obstacle]] #{}", idx - floes.len())
            } else {
                match floes[idx].origin {
                    FloeOrigin::Listed(n) => format!("[[floe]] #{n}"),
                    FloeOrigin::Field { field, index } => {
                        format!("floe {index} of [[field]] #{field} (floe index {idx})")
                    }
                }
            }
        };
        return Err(ctx.err(
            Some(span.clone()),
            format!(
                "[[field]] #{k}: {} overlaps {} at t = 0; move the region away from listed floes and obstacles",
                name(i),
                name(j)
            ),
        ));
    }
    Ok(())
}
