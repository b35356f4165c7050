//! The Minkowski difference `A ⊖ B` walked without storing it (the
//! module doc of [`super`]): its edges in angular order, and from them
//! the signed distance, normal and closest features of two convex
//! polygons ([`separation`], [`signed_distance`]; [`separation_in`] for
//! parts of compound bodies).

use super::{Feature, FeaturePair, Parts, Separation, Side, VERTEX_VERTEX_RELATIVE_SLACK};
use crate::geometry::{cross, Vec2};

/// One edge of `A ⊖ B`: edge `edge` of polygon `side`, and the vertex
/// `vertex` of the other polygon that supports it.
#[derive(Debug, Clone, Copy)]
struct MinkEdge {
    side: Side,
    edge: usize,
    vertex: usize,
}

#[inline]
pub(super) fn next(i: usize, n: usize) -> usize {
    if i + 1 >= n {
        0
    } else {
        i + 1
    }
}

/// Outward unit normal of the edge `p → q` of a counter-clockwise polygon,
/// `None` for a zero-length (or non-finite) edge.
#[inline]
pub(super) fn outward_normal(p: &Vec2, q: &Vec2) -> Option<Vec2> {
    let e = q - p;
    let len = e.norm();
    if len > 0.0 && len.is_finite() {
        Some(Vec2::new(e.y / len, -e.x / len))
    } else {
        None
    }
}

/// Index of the lowest (then leftmost) vertex of `poly`, or of `−poly` when
/// `negated`.
fn lowest(poly: &[Vec2], negated: bool) -> usize {
    let s = if negated { -1.0 } else { 1.0 };
    let mut best = 0;
    for (i, p) in poly.iter().enumerate().skip(1) {
        let q = &poly[best];
        let (py, px, qy, qx) = (s * p.y, s * p.x, s * q.y, s * q.x);
        if py < qy || (py == qy && px < qx) {
            best = i;
        }
    }
    best
}

/// Visits the edges of `A ⊖ B` in angular order (the Minkowski-sum merge of
/// `A` and `−B`), zero-length edges skipped. At most `n + m` calls; the loop
/// always advances, so it ends even on invalid input.
fn for_each_minkowski_edge(a: &[Vec2], b: &[Vec2], mut f: impl FnMut(MinkEdge)) {
    let (n, m) = (a.len(), b.len());
    if n == 0 || m == 0 {
        return;
    }
    let (mut ia, mut jb) = (lowest(a, false), lowest(b, true));
    let (mut i, mut j) = (0, 0);
    while i < n || j < m {
        let (ia1, jb1) = (next(ia, n), next(jb, m));
        let ea = a[ia1] - a[ia];
        let eb = b[jb] - b[jb1]; // edge of −B
        if i < n && ea.x == 0.0 && ea.y == 0.0 {
            ia = ia1;
            i += 1;
            continue;
        }
        if j < m && eb.x == 0.0 && eb.y == 0.0 {
            jb = jb1;
            j += 1;
            continue;
        }
        let take_a = if i >= n {
            false
        } else if j >= m {
            true
        } else {
            cross(&ea, &eb) >= 0.0
        };
        if take_a {
            f(MinkEdge {
                side: Side::A,
                edge: ia,
                vertex: jb,
            });
            ia = ia1;
            i += 1;
        } else {
            f(MinkEdge {
                side: Side::B,
                edge: jb,
                vertex: ia,
            });
            jb = jb1;
            j += 1;
        }
    }
}

/// Builds the feature pair for a feature of the `side` polygon and one of
/// the other polygon.
#[inline]
pub(super) fn pair(side: Side, own: Feature, other: Feature) -> FeaturePair {
    match side {
        Side::A => FeaturePair { a: own, b: other },
        Side::B => FeaturePair { a: other, b: own },
    }
}

/// Signed distance between two convex counter-clockwise polygons, m.
///
/// The exact Euclidean distance when they are disjoint (closest features
/// vertex–edge or vertex–vertex), minus the penetration depth (minimum
/// translation distance over both polygons' edge normals) when they overlap,
/// zero when they touch. `+∞` if either polygon is empty. `O(n + m)`.
pub fn signed_distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    separation(a, b).map_or(f64::INFINITY, |s| s.distance)
}

/// Signed distance, normal (from A to B) and closest features of two convex
/// counter-clockwise polygons; `None` if either polygon is empty.
///
/// See the module documentation for the algorithm and degenerate cases.
pub fn separation(a: &[Vec2], b: &[Vec2]) -> Option<Separation> {
    separation_in(a, b, &Parts::default())
}

/// [`separation`] of two convex parts of compound bodies: `None` also when
/// the pair's closest features are hidden behind another part of a body
/// (an internal edge, or a vertex approached from inside its body; that
/// other part's pair carries the contact). An overlap is measured along
/// the best outline edge (internal edges are not contact faces), falling
/// back to every edge if no outline edge is left. Without compound bodies,
/// exactly [`separation`].
pub(crate) fn separation_in(a: &[Vec2], b: &[Vec2], parts: &Parts) -> Option<Separation> {
    if a.is_empty() || b.is_empty() {
        return None;
    }
    // Best SAT edge: (value, edge, pair normal).
    let mut sat: Option<(f64, MinkEdge, Vec2)> = None;
    // Best SAT edge among outline edges (internal edges excluded).
    let mut sat_face: Option<(f64, MinkEdge, Vec2)> = None;
    // Closest vertex–segment pair: (squared distance, edge, parameter, pair
    // normal, largest coordinate magnitude involved, for the rounding
    // tolerance).
    let mut near: Option<(f64, MinkEdge, f64, Vec2, f64)> = None;
    for_each_minkowski_edge(a, b, |e| {
        let (poly, other) = match e.side {
            Side::A => (a, b),
            Side::B => (b, a),
        };
        let p0 = poly[e.edge];
        let p1 = poly[next(e.edge, poly.len())];
        let q = other[e.vertex];
        let Some(nr) = outward_normal(&p0, &p1) else {
            return;
        };
        let pair_normal = match e.side {
            Side::A => nr,
            Side::B => -nr,
        };
        let s = nr.dot(&(q - p0));
        if sat.is_none_or(|(best, _, _)| s > best) {
            sat = Some((s, e, pair_normal));
        }
        if !parts.internal(e.side, e.edge) && sat_face.is_none_or(|(best, _, _)| s > best) {
            sat_face = Some((s, e, pair_normal));
        }
        let d = p1 - p0;
        let t = d.dot(&(q - p0)) / d.norm_squared();
        let foot = if t <= 0.0 {
            p0
        } else if t >= 1.0 {
            p1
        } else {
            p0 + t * d
        };
        let dist2 = (q - foot).norm_squared();
        if near.is_none_or(|(best, _, _, _, _)| dist2 < best) {
            near = Some((dist2, e, t, pair_normal, q.amax().max(foot.amax())));
        }
    });

    let Some((s_best, e_sat, n_sat)) = sat else {
        // No edge of non-zero length: both polygons are points.
        let d = b[0] - a[0];
        let dist = d.norm();
        let normal = if dist > 0.0 && dist.is_finite() {
            d / dist
        } else {
            Vec2::x()
        };
        return Some(Separation {
            distance: dist,
            normal,
            feature: FeaturePair {
                a: Feature::Vertex(0),
                b: Feature::Vertex(0),
            },
        });
    };

    if s_best > 0.0 {
        if let Some((dist2, e, t, normal, magnitude)) = near {
            let dist = dist2.sqrt();
            if t > 0.0 && t < 1.0 {
                if parts.internal(e.side, e.edge) {
                    return None; // closest to a diagonal: hidden
                }
                return Some(Separation {
                    distance: dist,
                    normal,
                    feature: pair(e.side, Feature::Edge(e.edge), Feature::Vertex(e.vertex)),
                });
            }
            // The closest points are at a vertex of both polygons. If the
            // distance is nevertheless the best SAT value (a vertex facing
            // the end of an edge, e.g. aligned facing edges), the edge normal
            // is the axis: report the SAT edge so that facing edges can give
            // a two-point contact.
            let slack = VERTEX_VERTEX_RELATIVE_SLACK * dist + 8.0 * f64::EPSILON * magnitude;
            if dist - s_best <= slack && !parts.internal(e_sat.side, e_sat.edge) {
                return Some(Separation {
                    distance: dist,
                    normal: n_sat,
                    feature: pair(
                        e_sat.side,
                        Feature::Edge(e_sat.edge),
                        Feature::Vertex(e_sat.vertex),
                    ),
                });
            }
            // Vertex–vertex: the normal joins the two vertices.
            let (ia, jb) = match e.side {
                Side::A => (
                    if t <= 0.0 {
                        e.edge
                    } else {
                        next(e.edge, a.len())
                    },
                    e.vertex,
                ),
                Side::B => (
                    e.vertex,
                    if t <= 0.0 {
                        e.edge
                    } else {
                        next(e.edge, b.len())
                    },
                ),
            };
            let feature = FeaturePair {
                a: Feature::Vertex(ia),
                b: Feature::Vertex(jb),
            };
            let d = b[jb] - a[ia];
            let len = d.norm();
            let normal = if len > 0.0 && len.is_finite() {
                d / len
            } else {
                n_sat
            };
            if parts.hidden_vertex(Side::A, ia, &normal)
                || parts.hidden_vertex(Side::B, jb, &-normal)
            {
                return None;
            }
            return Some(Separation {
                distance: dist,
                normal,
                feature,
            });
        }
    }
    // Touching or overlapping: the best outline face (the same as the best
    // edge for whole convex bodies).
    let (s_face, e_face, n_face) = sat_face.unwrap_or((s_best, e_sat, n_sat));
    Some(Separation {
        distance: s_face,
        normal: n_face,
        feature: pair(
            e_face.side,
            Feature::Edge(e_face.edge),
            Feature::Vertex(e_face.vertex),
        ),
    })
}
