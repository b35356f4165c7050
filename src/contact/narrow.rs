//! Narrow phase: signed distance, closest features and contact points of two
//! convex counter-clockwise polygons.
//!
//! # Minkowski difference, walked without storing it
//!
//! The configuration space obstacle `M = A ⊖ B = {a − b}` is a convex polygon
//! whose `n + m` edges are the edges of `A` and the reversed edges of `B`,
//! sorted by angle. Each edge of `M` pairs an edge of one polygon with the
//! vertex of the other polygon that supports it (the vertex deepest along the
//! edge's inward normal). [`separation`] merges the two edge sequences, both
//! started at their lowest vertex (the classic `O(n + m)` Minkowski-sum
//! merge), and visits each pair once, without allocating:
//!
//! * its SAT value `s = n̂ · (q − p₀)` (outward unit normal `n̂` of the edge
//!   `p₀p₁`, opposite vertex `q`): the largest `s` over all edges of `M` is
//!   the separating-axis value of both polygons' edge normals;
//! * the Euclidean distance from `q` to the segment `p₀p₁`.
//!
//! If the largest `s` is positive the polygons are disjoint and the origin is
//! outside `M`: the distance is the smallest vertex–segment distance met
//! (the boundary of `M` is exactly the union of those segments). The closest
//! features are then a vertex and an edge, with the edge's normal, when the
//! vertex projects inside the edge, or when the distance equals the largest
//! `s` to `1e-12` relative plus coordinate rounding (a vertex facing the end
//! of an edge, as for aligned facing edges); otherwise they are two vertices
//! and the normal joins them.
//!
//! If the largest `s` is `≤ 0` the polygons touch or overlap, and it is minus
//! the penetration depth (the minimum translation distance, along that
//! edge's normal). Both branches meet at zero, so the signed distance is
//! continuous.
//!
//! # Contact points
//!
//! [`contacts`] takes the feature pair of [`separation`]:
//!
//! * vertex–vertex (separated only): one point, the midpoint of the two
//!   vertices, normal along the segment joining them;
//! * vertex `q` against a reference edge `R`: if an edge of the other polygon
//!   adjacent to `q` (the incident edge) faces `R` within the angular
//!   parallel tolerance, the incident edge is clipped to the slab orthogonal
//!   to `R` through its ends (Box2D's reference/incident face clipping,
//!   applied to separated polygons too) and the one or two clipped ends are
//!   the contact points; otherwise one point at `q`.
//!
//! Every point is reported midway between the incident point and its
//! projection on the reference edge's line, with the gap measured along the
//! pair normal; points with a gap above the contact distance are dropped.
//!
//! # Degenerate input
//!
//! Polygons are expected convex, counter-clockwise, with finite coordinates
//! (see [`crate::geometry::check_convex_ccw`]). Zero-length edges (repeated
//! vertices) carry no normal and are skipped. Coincident polygons are simply
//! a deep overlap (depth = their smallest width). A polygon with no non-zero
//! edge is a point: two such points give a vertex–vertex separation, with
//! normal `+x` if they coincide. An empty polygon is infinitely far
//! ([`signed_distance`] returns `+∞`, [`separation`] `None`, no contact). No
//! function of this module panics or divides by a zero length.

use crate::geometry::{cross, perp, Vec2};

/// Default largest angle between two facing edges for an edge–edge
/// (two-point) contact, rad.
pub const DEFAULT_PARALLEL_TOLERANCE: f64 = 1e-6;

/// Default length, as a fraction of the reference edge length, below which
/// the two clipped points of an edge–edge contact are merged into one
/// (dimensionless).
pub const DEFAULT_MERGE_FRACTION: f64 = 1e-9;

/// Relative excess of the Euclidean distance over the best SAT value below
/// which separated closest vertices are reported as vertex–edge along the
/// edge normal (the normals then differ by at most `√(2·1e-12) ≈ 1.4e-6` rad).
const VERTEX_VERTEX_RELATIVE_SLACK: f64 = 1e-12;

/// A vertex or an edge of one polygon.
///
/// Edge `i` joins vertex `i` to vertex `i + 1` (modulo the vertex count).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Feature {
    /// Vertex index.
    Vertex(usize),
    /// Edge index (from vertex `i` to vertex `i + 1`).
    Edge(usize),
}

/// The features of polygon A and of polygon B that make one contact, for
/// debugging and for warm-starting by feature identity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FeaturePair {
    /// Feature of the first polygon, A.
    pub a: Feature,
    /// Feature of the second polygon, B.
    pub b: Feature,
}

/// Geometry of one contact point between polygons A and B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactGeom {
    /// Contact point in world coordinates, m: midway between the two
    /// bodies' surfaces along the normal.
    pub point: Vec2,
    /// Unit normal pointing from A to B (dimensionless). The same for every
    /// point of a pair.
    pub normal: Vec2,
    /// Unit tangent, `perp(normal)`: the normal turned by +90°.
    pub tangent: Vec2,
    /// Signed distance between the surfaces along the normal at this point,
    /// m: positive apart, negative penetrating.
    pub gap: f64,
    /// Which vertex or edge of each polygon produced the point.
    pub feature: FeaturePair,
}

/// Signed distance of two polygons with the axis and features realising it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Separation {
    /// Signed distance, m: the Euclidean distance when disjoint, minus the
    /// penetration depth (minimum translation distance) when overlapping.
    pub distance: f64,
    /// Unit normal from A to B (dimensionless): direction of the closest
    /// features when disjoint, of the minimum translation of B when
    /// overlapping.
    pub normal: Vec2,
    /// Closest features: vertex–edge, edge–vertex or (disjoint only)
    /// vertex–vertex.
    pub feature: FeaturePair,
}

/// Every facing edge pair clipped (Box2D's reference/incident clipping at
/// any angle, not only within [`DEFAULT_PARALLEL_TOLERANCE`]), each clipped
/// end within the contact distance a contact point: the event-driven
/// scheme's contact points, and Moreau–Jean's second corners of nearly
/// flush pairs. With one point per nearly flush pair (edges a few 1e-4 rad
/// apart), the second corner is not held and the floe turns about the
/// first: in the event-driven scheme that corner turned into the other floe
/// (docs/physics.md §4.3, step 1); under Moreau–Jean at a step of 1 s a
/// jammed pack's floes turned and the pack crept downwind (§5.1, step 2).
pub const CLIPPED_EDGE_PAIRS: NarrowOptions = NarrowOptions {
    parallel_tolerance: std::f64::consts::FRAC_PI_2,
    merge_fraction: DEFAULT_MERGE_FRACTION,
};

/// Tolerances of the contact point generation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NarrowOptions {
    /// Largest angle between the outward normal of the reference edge and the
    /// reversed outward normal of an incident edge for the two to count as
    /// parallel facing edges and give a two-point contact, rad. Meaningful in
    /// `[0, π/2)`; `0` keeps only exactly parallel edges. Default
    /// [`DEFAULT_PARALLEL_TOLERANCE`].
    pub parallel_tolerance: f64,
    /// When the clipped overlap of two parallel edges is shorter than this
    /// fraction of the reference edge length, only its deeper end is kept
    /// (dimensionless). Default [`DEFAULT_MERGE_FRACTION`].
    pub merge_fraction: f64,
}

impl Default for NarrowOptions {
    fn default() -> Self {
        Self {
            parallel_tolerance: DEFAULT_PARALLEL_TOLERANCE,
            merge_fraction: DEFAULT_MERGE_FRACTION,
        }
    }
}

/// Which polygon an edge of the Minkowski difference comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    A,
    B,
}

/// A convex part of a compound (non-convex) body: the body's whole outline
/// and the part's vertex indices into it, so that the narrow phase knows
/// which part edges are internal (kept diagonals, never contact features)
/// and the outline's neighbours of each part vertex.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PartOf<'a> {
    /// The body's outline, world frame, m.
    pub outline: &'a [Vec2],
    /// The part's vertices, indices into `outline`, counter-clockwise.
    pub ids: &'a [usize],
}

impl PartOf<'_> {
    /// Whether the part edge `k` (part vertex `k` to `k + 1`) is internal.
    fn internal(&self, k: usize) -> bool {
        crate::geometry::decompose::is_internal_edge(self.ids, k, self.outline.len())
    }

    /// Whether `out` (a unit direction pointing out of the body) lies in the
    /// outline's normal cone at part vertex `k`: the closest point of the
    /// whole body to a point along `out` can be that vertex (never at a
    /// reflex vertex).
    fn in_normal_cone(&self, k: usize, out: &Vec2) -> bool {
        let n = self.outline.len();
        let v = self.ids[k];
        let p = self.outline[v];
        out.dot(&(self.outline[(v + 1) % n] - p)) <= 0.0
            && out.dot(&(self.outline[(v + n - 1) % n] - p)) <= 0.0
    }
}

/// The compound-body information of the two polygons of a pair (`None`: a
/// whole convex body, nothing internal).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Parts<'a> {
    /// Polygon A's.
    pub a: Option<PartOf<'a>>,
    /// Polygon B's.
    pub b: Option<PartOf<'a>>,
}

impl Parts<'_> {
    /// Whether edge `edge` of the polygon on `side` is internal.
    #[inline]
    fn internal(&self, side: Side, edge: usize) -> bool {
        let p = match side {
            Side::A => &self.a,
            Side::B => &self.b,
        };
        p.as_ref().is_some_and(|p| p.internal(edge))
    }

    /// Whether vertex `k` of the polygon on `side` touches an internal edge
    /// and `out` (pointing out of that body) leaves its outline's normal
    /// cone there: the feature is hidden behind the body's other parts.
    fn hidden_vertex(&self, side: Side, k: usize, out: &Vec2) -> bool {
        let p = match side {
            Side::A => &self.a,
            Side::B => &self.b,
        };
        p.as_ref().is_some_and(|p| {
            let m = p.ids.len();
            (p.internal(k) || p.internal((k + m - 1) % m)) && !p.in_normal_cone(k, out)
        })
    }
}

/// One edge of `A ⊖ B`: edge `edge` of polygon `side`, and the vertex
/// `vertex` of the other polygon that supports it.
#[derive(Debug, Clone, Copy)]
struct MinkEdge {
    side: Side,
    edge: usize,
    vertex: usize,
}

#[inline]
fn next(i: usize, n: usize) -> usize {
    if i + 1 >= n {
        0
    } else {
        i + 1
    }
}

/// Outward unit normal of the edge `p → q` of a counter-clockwise polygon,
/// `None` for a zero-length (or non-finite) edge.
#[inline]
fn outward_normal(p: &Vec2, q: &Vec2) -> Option<Vec2> {
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
fn pair(side: Side, own: Feature, other: Feature) -> FeaturePair {
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

/// Appends to `out` the contact points of polygons `a` and `b` if their
/// signed distance is at most `distance` (m, a contact distance `≥ 0`), with
/// the default [`NarrowOptions`].
///
/// One point for a vertex–edge or vertex–vertex configuration, two for
/// facing parallel edges whose projections overlap (the ends of the
/// overlap). Only points with `gap ≤ distance` are kept. Normals point from
/// A to B.
pub fn contacts(a: &[Vec2], b: &[Vec2], distance: f64, out: &mut Vec<ContactGeom>) {
    contacts_with(a, b, distance, &NarrowOptions::default(), out);
}

/// [`contacts`] with explicit tolerances.
pub fn contacts_with(
    a: &[Vec2],
    b: &[Vec2],
    distance: f64,
    options: &NarrowOptions,
    out: &mut Vec<ContactGeom>,
) {
    for_each_contact(a, b, distance, options, |g| out.push(g));
}

/// Calls `emit` on each contact point of the pair (see [`contacts`]).
pub(crate) fn for_each_contact(
    a: &[Vec2],
    b: &[Vec2],
    distance: f64,
    options: &NarrowOptions,
    emit: impl FnMut(ContactGeom),
) {
    for_each_part_contact(a, b, &Parts::default(), distance, options, emit);
}

/// [`for_each_contact`] for two convex parts of compound bodies (see
/// [`separation_in`]): internal edges are neither reference nor incident
/// edges. Features are indices into the parts.
pub(crate) fn for_each_part_contact(
    a: &[Vec2],
    b: &[Vec2],
    parts: &Parts,
    distance: f64,
    options: &NarrowOptions,
    mut emit: impl FnMut(ContactGeom),
) {
    let Some(sep) = separation_in(a, b, parts) else {
        return;
    };
    let within = sep.distance <= distance; // false for NaN
    if !within {
        return;
    }
    match (sep.feature.a, sep.feature.b) {
        (Feature::Edge(r), Feature::Vertex(q)) => {
            let inc = parts.b.as_ref();
            manifold(a, r, b, q, inc, Side::A, &sep, distance, options, &mut emit)
        }
        (Feature::Vertex(q), Feature::Edge(r)) => {
            let inc = parts.a.as_ref();
            manifold(b, r, a, q, inc, Side::B, &sep, distance, options, &mut emit)
        }
        (Feature::Vertex(i), Feature::Vertex(j)) => emit(ContactGeom {
            point: 0.5 * (a[i] + b[j]),
            normal: sep.normal,
            tangent: perp(&sep.normal),
            gap: sep.distance,
            feature: sep.feature,
        }),
        // Never produced by `separation`.
        (Feature::Edge(_), Feature::Edge(_)) => {}
    }
}

/// Where a clipped end of the incident edge comes from.
#[derive(Clone, Copy)]
enum ClipEnd {
    /// An unclipped vertex of the incident polygon.
    Incident(usize),
    /// The slab plane through this vertex of the reference polygon.
    Reference(usize),
}

/// Contact points for the reference edge `r` of `refp` (on side `ref_side`)
/// against the vertex `q` of `inc` (a part of a compound body when
/// `inc_part` is given: its internal edges are not incident edges), given
/// the pair's separation.
#[allow(clippy::too_many_arguments)]
fn manifold(
    refp: &[Vec2],
    r: usize,
    inc: &[Vec2],
    q: usize,
    inc_part: Option<&PartOf>,
    ref_side: Side,
    sep: &Separation,
    distance: f64,
    options: &NarrowOptions,
    emit: &mut impl FnMut(ContactGeom),
) {
    let normal = sep.normal;
    let tangent = perp(&normal);
    let n_ref = match ref_side {
        Side::A => normal,
        Side::B => -normal,
    };
    let r_next = next(r, refp.len());
    let (r0, r1) = (refp[r], refp[r_next]);
    let make = |p: Vec2, gap: f64, own: Feature, other: Feature| ContactGeom {
        point: p - 0.5 * gap * n_ref,
        normal,
        tangent,
        gap,
        feature: pair(ref_side, own, other),
    };
    let single = make(inc[q], sep.distance, Feature::Edge(r), Feature::Vertex(q));

    // Incident edge: the edge at `q` whose normal is most opposed to n_ref.
    let m = inc.len();
    let prev = if q == 0 { m - 1 } else { q - 1 };
    let mut incident: Option<(usize, f64, Vec2)> = None; // (edge, n·n_ref, normal)
    for k in [prev, q] {
        if inc_part.is_some_and(|p| p.internal(k)) {
            continue;
        }
        if let Some(nk) = outward_normal(&inc[k], &inc[next(k, m)]) {
            let c = nk.dot(&n_ref);
            if incident.is_none_or(|(_, best, _)| c < best) {
                incident = Some((k, c, nk));
            }
        }
    }
    let parallel = incident.filter(|&(_, c, nk)| {
        c < 0.0 && cross(&nk, &n_ref).abs() <= options.parallel_tolerance.sin()
    });
    let Some((k, _, _)) = parallel else {
        emit(single);
        return;
    };

    // Clip the incident edge p(λ) = p0 + λ (p1 − p0) to the slab of the
    // reference edge, 0 ≤ u·(p − r0) ≤ len.
    let k_next = next(k, m);
    let (p0, p1) = (inc[k], inc[k_next]);
    let u_raw = r1 - r0;
    let len = u_raw.norm();
    let u = u_raw / len; // len > 0: the reference edge has a normal
    let s0 = u.dot(&(p0 - r0));
    let ds = u.dot(&(p1 - r0)) - s0;
    let oblique = ds.abs() > 0.0; // false for NaN
    if !oblique {
        emit(single);
        return;
    }
    let at_r0 = -s0 / ds;
    let at_r1 = (len - s0) / ds;
    let ((lmin, fmin), (lmax, fmax)) = if at_r0 <= at_r1 {
        ((at_r0, r), (at_r1, r_next))
    } else {
        ((at_r1, r_next), (at_r0, r))
    };
    let (lo, end_lo) = if lmin > 0.0 {
        (lmin, ClipEnd::Reference(fmin))
    } else {
        (0.0, ClipEnd::Incident(k))
    };
    let (hi, end_hi) = if lmax < 1.0 {
        (lmax, ClipEnd::Reference(fmax))
    } else {
        (1.0, ClipEnd::Incident(k_next))
    };
    let nonempty = lo <= hi; // false for NaN
    if !nonempty {
        emit(single);
        return;
    }
    let point_at = |lambda: f64, end: ClipEnd| {
        let (p, own, other) = match end {
            ClipEnd::Incident(v) => (inc[v], Feature::Edge(r), Feature::Vertex(v)),
            ClipEnd::Reference(v) => (
                p0 + lambda * (p1 - p0),
                Feature::Vertex(v),
                Feature::Edge(k),
            ),
        };
        make(p, n_ref.dot(&(p - r0)), own, other)
    };
    let c_lo = point_at(lo, end_lo);
    let c_hi = point_at(hi, end_hi);
    let overlap = (hi - lo) * (p1 - p0).norm();
    let keep_lo = c_lo.gap <= distance;
    let keep_hi = c_hi.gap <= distance;
    let two_points = overlap > options.merge_fraction * len; // false for NaN
    if !two_points {
        let deeper = if c_hi.gap < c_lo.gap { c_hi } else { c_lo };
        emit(if deeper.gap <= distance {
            deeper
        } else {
            single
        });
    } else if keep_lo || keep_hi {
        if keep_lo {
            emit(c_lo);
        }
        if keep_hi {
            emit(c_hi);
        }
    } else {
        emit(single);
    }
}
