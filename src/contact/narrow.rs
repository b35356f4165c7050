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

mod manifold;
mod minkowski;

pub use manifold::{contacts, contacts_with};
pub(crate) use manifold::{for_each_contact, for_each_part_contact};
pub use minkowski::{separation, signed_distance};

use crate::geometry::Vec2;

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
