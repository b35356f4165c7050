//! Contact detection between rigid convex polygonal floes and obstacles.
//!
//! Lengths are in metres; normals and tangents are unit vectors. Polygons
//! are slices of world-frame vertices, convex and counter-clockwise (see
//! [`crate::geometry::check_convex_ccw`]).
//!
//! Two phases:
//!
//! 1. **Broad phase** ([`BroadPhase`], `broad.rs`): sweep and prune. The
//!    axis-aligned bounding boxes, inflated by a margin, are sorted along `x`
//!    (insertion sort on the order kept from the previous call, nearly linear
//!    when bodies move little), swept once to find the pairs overlapping in
//!    `x`, and filtered by overlap in `y`. Pairs of two fixed bodies are
//!    skipped. Output sorted, hence deterministic.
//! 2. **Narrow phase** (`narrow.rs`): for each candidate pair, the signed
//!    distance is found by walking the edges of the Minkowski difference
//!    `A ⊖ B` in angular order, `O(n + m)` and allocation-free: the largest
//!    separating-axis value over both polygons' edge normals tells whether
//!    they are disjoint; if so the distance is the smallest vertex–segment
//!    distance among the Minkowski edges (exact Euclidean distance,
//!    vertex–edge or vertex–vertex closest features), else it is minus the
//!    penetration depth along the best edge normal. Contact points follow
//!    from the closest features: one point for a vertex against an edge or a
//!    vertex, two for facing edges parallel within an angular tolerance
//!    (reference/incident edge clipping as in Box2D, also for separated
//!    polygons up to the contact distance). Each point lies midway between
//!    the two surfaces, with the gap along the pair normal (from A to B).
//!
//! [`detect`] chains both for a set of bodies. The contact problem of a
//! group is assembled in [`problem`] (the LCP) and, for the convex cone
//! relaxation, solved in [`cone`].

mod broad;
pub mod cone;
mod narrow;
pub mod problem;

pub use broad::{Aabb, BroadPhase};
pub use narrow::{
    contacts, contacts_with, separation, signed_distance, ContactGeom, Feature, FeaturePair,
    NarrowOptions, Separation, DEFAULT_MERGE_FRACTION, DEFAULT_PARALLEL_TOLERANCE,
};

use crate::geometry::Vec2;

/// One contact point between bodies `a` and `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Index of the first body; the non-fixed one when exactly one is fixed.
    pub a: usize,
    /// Index of the second body.
    pub b: usize,
    /// Point, normal (from `a` to `b`), tangent, gap (m) and features; the
    /// features' `a` and `b` refer to bodies `a` and `b`.
    pub geom: ContactGeom,
}

/// The identity of a contact point from one step to the next: its two
/// bodies and the vertex/edge features that produced it (for warm starts).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ContactKey {
    /// Index of the first body.
    pub a: usize,
    /// Index of the second body.
    pub b: usize,
    /// The features of bodies `a` and `b`.
    pub feature: FeaturePair,
}

impl Contact {
    /// This contact's identity ([`ContactKey`]).
    pub fn key(&self) -> ContactKey {
        ContactKey {
            a: self.a,
            b: self.b,
            feature: self.geom.feature,
        }
    }
}

/// Replaces the content of `out` by the contact points of all pairs of
/// `bodies` (world vertices, m) whose signed distance is at most `distance`
/// (m, `≥ 0`), with the default [`NarrowOptions`].
///
/// `fixed[i]` marks obstacles (a missing entry counts as not fixed); pairs
/// of two fixed bodies are skipped. Within a pair, `a` is the non-fixed body
/// when exactly one is fixed, else the smaller index. The broad phase uses
/// margin `max(distance, 0)`. Output ordered by pair `(min, max)` index,
/// then by point, so it is deterministic.
pub fn detect(
    bodies: &[&[Vec2]],
    fixed: &[bool],
    distance: f64,
    bp: &mut BroadPhase,
    out: &mut Vec<Contact>,
) {
    detect_with(bodies, fixed, distance, &NarrowOptions::default(), bp, out);
}

/// [`detect`] with explicit narrow-phase tolerances.
pub fn detect_with(
    bodies: &[&[Vec2]],
    fixed: &[bool],
    distance: f64,
    options: &NarrowOptions,
    bp: &mut BroadPhase,
    out: &mut Vec<Contact>,
) {
    out.clear();
    let is_fixed = |i: usize| fixed.get(i).copied().unwrap_or(false);
    let mut boxes = std::mem::take(&mut bp.boxes);
    let mut candidates = std::mem::take(&mut bp.candidates);
    boxes.clear();
    boxes.extend(
        bodies
            .iter()
            .enumerate()
            .map(|(i, p)| Aabb::of_polygon(p, is_fixed(i))),
    );
    bp.pairs(&boxes, distance.max(0.0), &mut candidates);
    for &(i, j) in &candidates {
        let (a, b) = if is_fixed(i) && !is_fixed(j) {
            (j, i)
        } else {
            (i, j)
        };
        narrow::for_each_contact(bodies[a], bodies[b], distance, options, |geom| {
            out.push(Contact { a, b, geom })
        });
    }
    bp.boxes = boxes;
    bp.candidates = candidates;
}
