//! Contact detection between rigid polygonal floes and obstacles.
//!
//! Lengths are in metres; normals and tangents are unit vectors. Polygons
//! are slices of world-frame vertices, counter-clockwise. The narrow phase
//! works on convex polygons (see [`crate::geometry::check_convex_ccw`]); a
//! non-convex body is a [`Compound`] of convex parts held rigidly together
//! ([`crate::geometry::decompose`]), detected by [`detect_compound`]: the
//! broad phase boxes each part, pairs of parts of the same body are never
//! tested, and each contact carries the body (not the part), with features
//! numbered on the body's outline. Internal edges (the diagonals between
//! parts) are never contact faces: a pair of parts whose closest features
//! are hidden behind another part of a body gives no contact (that other
//! part's pair does), an overlap is measured along the best outline edge,
//! and two parts of a body giving the same contact (same features, e.g. at
//! a vertex shared by two parts) keep the one with the smaller gap.
//!
//! Two phases:
//!
//! 1. **Broad phase** ([`BroadPhase`], `geometry/broad.rs`): sweep and prune. The
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

pub mod cone;
pub mod crush;
mod load;
mod narrow;
pub mod problem;

pub use crate::geometry::broad::{Aabb, BroadPhase};
pub use load::{loads_of, Load};
pub use narrow::{
    contacts, contacts_with, separation, signed_distance, ContactGeom, Feature, FeaturePair,
    NarrowOptions, Separation, CLIPPED_EDGE_PAIRS, DEFAULT_MERGE_FRACTION,
    DEFAULT_PARALLEL_TOLERANCE,
};

use narrow::{PartOf, Parts};

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

/// A body for [`detect_compound`]: its world outline (m, counter-clockwise)
/// and its convex parts (counter-clockwise lists of indices into the
/// outline; one part `0..n` for a convex body).
#[derive(Debug, Clone, Copy)]
pub struct Compound<'a> {
    /// World outline, m.
    pub outline: &'a [Vec2],
    /// Convex parts, as indices into `outline`.
    pub parts: &'a [Vec<usize>],
}

/// A part-local feature renumbered on the body's outline (`ids`: the part's
/// vertex indices). Part edges that are contact features are outline edges,
/// so edge `k` of the part is edge `ids[k]` of the outline.
fn on_outline(f: Feature, ids: &[usize]) -> Feature {
    match f {
        Feature::Vertex(k) => Feature::Vertex(ids[k]),
        Feature::Edge(k) => Feature::Edge(ids[k]),
    }
}

/// Signed distance between two bodies made of convex parts (m): the smallest
/// signed distance over the pairs of parts ([`signed_distance`]); for two
/// convex bodies exactly [`signed_distance`]. Disjoint bodies: their
/// Euclidean distance; overlapping ones: minus the deepest penetration of a
/// pair of parts.
pub fn compound_signed_distance(a: &Compound, b: &Compound) -> f64 {
    if a.parts.len() <= 1 && b.parts.len() <= 1 {
        return signed_distance(a.outline, b.outline);
    }
    let mut pa = Vec::new();
    let mut pb = Vec::new();
    let mut best = f64::INFINITY;
    for ia in a.parts {
        pa.clear();
        pa.extend(ia.iter().map(|&k| a.outline[k]));
        for ib in b.parts {
            pb.clear();
            pb.extend(ib.iter().map(|&k| b.outline[k]));
            best = best.min(signed_distance(&pa, &pb));
        }
    }
    best
}

/// [`detect_with`] for bodies made of convex parts ([`Compound`]), with the
/// same contract: contacts between different bodies only, `a` the non-fixed
/// body when exactly one is fixed, ordered by body pair then by pair of
/// parts then by point, features on the outlines. When every body is a
/// single part this is exactly [`detect_with`] on the outlines.
pub fn detect_compound(
    bodies: &[Compound],
    fixed: &[bool],
    distance: f64,
    options: &NarrowOptions,
    bp: &mut BroadPhase,
    out: &mut Vec<Contact>,
) {
    if bodies.iter().all(|b| b.parts.len() <= 1) {
        let outlines: Vec<&[Vec2]> = bodies.iter().map(|b| b.outline).collect();
        detect_with(&outlines, fixed, distance, options, bp, out);
        return;
    }
    out.clear();
    let is_fixed = |i: usize| fixed.get(i).copied().unwrap_or(false);
    // Every part, body-major: (body, part index) and its world polygon.
    let mut owner: Vec<(usize, usize)> = Vec::new();
    let mut polys: Vec<Vec<Vec2>> = Vec::new();
    for (i, body) in bodies.iter().enumerate() {
        for (k, ids) in body.parts.iter().enumerate() {
            owner.push((i, k));
            polys.push(ids.iter().map(|&v| body.outline[v]).collect());
        }
    }
    let mut boxes = std::mem::take(&mut bp.boxes);
    let mut candidates = std::mem::take(&mut bp.candidates);
    boxes.clear();
    boxes.extend(
        polys
            .iter()
            .zip(&owner)
            .map(|(p, &(i, _))| Aabb::of_polygon(p, is_fixed(i))),
    );
    bp.pairs(&boxes, distance.max(0.0), &mut candidates);
    // (body, body, part, part) with a the non-fixed body, by body pair.
    let mut pairs: Vec<(usize, usize, usize, usize)> = candidates
        .iter()
        .filter(|&&(p, q)| owner[p].0 != owner[q].0)
        .map(|&(p, q)| {
            let (p, q) = if owner[p].0 < owner[q].0 {
                (p, q)
            } else {
                (q, p)
            };
            (owner[p].0, owner[q].0, p, q)
        })
        .collect();
    pairs.sort_unstable();
    let part_of = |p: usize| -> Option<PartOf> {
        let (i, k) = owner[p];
        let body = &bodies[i];
        (body.parts.len() > 1).then(|| PartOf {
            outline: body.outline,
            ids: &body.parts[k],
        })
    };
    let mut start = 0;
    for (n, &(i, j, p, q)) in pairs.iter().enumerate() {
        let (a, b, pa, pb) = if is_fixed(i) && !is_fixed(j) {
            (j, i, q, p)
        } else {
            (i, j, p, q)
        };
        let parts = Parts {
            a: part_of(pa),
            b: part_of(pb),
        };
        let (ids_a, ids_b) = (&bodies[a].parts[owner[pa].1], &bodies[b].parts[owner[pb].1]);
        narrow::for_each_part_contact(&polys[pa], &polys[pb], &parts, distance, options, |g| {
            let mut geom = g;
            geom.feature = FeaturePair {
                a: on_outline(g.feature.a, ids_a),
                b: on_outline(g.feature.b, ids_b),
            };
            let c = Contact { a, b, geom };
            // The same features from another pair of parts of these bodies.
            match out[start..].iter_mut().find(|d| d.key() == c.key()) {
                Some(d) if c.geom.gap < d.geom.gap => *d = c,
                Some(_) => {}
                None => out.push(c),
            }
        });
        let last_of_pair = pairs.get(n + 1).is_none_or(|nx| (nx.0, nx.1) != (i, j));
        if last_of_pair {
            start = out.len();
        }
    }
    bp.boxes = boxes;
    bp.candidates = candidates;
}
