//! Planar geometry of polygons: the one vocabulary of the project.
//!
//! Points and vectors are [`Vec2`] (`nalgebra::Vector2<f64>`), in metres.
//! Polygons are slices of vertices, counter-clockwise, without repetition of
//! the first vertex at the end.
//!
//! Mass properties use the exact polygon formulas (Green's theorem on each
//! edge, the "shoelace" formulas), which hold for any simple polygon, convex
//! or not. To keep rounding small far from the origin they are computed
//! about the vertex average and shifted afterwards.
//!
//! An outline is valid ([`check_simple_ccw`]) when it is simple (no two
//! edges meet except consecutive ones at their shared vertex, tested on all
//! pairs of edges with exact-sign orientation predicates, `O(n²)`),
//! counter-clockwise, without repeated or aligned consecutive vertices.
//! A non-convex outline is split once into convex parts
//! ([`decompose::convex_parts`]: ear clipping, then Hertel–Mehlhorn) for the
//! contact detection. The sweep-and-prune broad phase on bounding boxes
//! is [`broad`].
//!
//! # References
//!
//! - J. O'Rourke (1998), *Computational Geometry in C*, 2nd ed., Cambridge
//!   University Press: §1.3 (area), §1.5 (segment intersection), §1.6
//!   (ear clipping).
//! - S. Hertel, K. Mehlhorn (1983), *Fast triangulation of simple polygons*,
//!   LNCS 158 (the convex decomposition within four times the optimum).

pub mod broad;
pub mod decompose;

use nalgebra::Vector2;

/// A point or a vector of the sea plane, metres (or m/s, N, … by context).
pub type Vec2 = Vector2<f64>;

/// The 2-D cross product `a × b = a.x b.y − a.y b.x` (the `k` component of `a ∧ b`).
#[inline]
pub fn cross(a: &Vec2, b: &Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// `k ∧ v`: the vector `v` turned by +90°.
#[inline]
pub fn perp(v: &Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

/// Rotation of `v` by the angle `theta` (rad, counter-clockwise).
#[inline]
pub fn rotate(v: &Vec2, theta: f64) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// The outline `shape` (about a body's centre, at angle 0) placed at centre
/// `g` and angle `theta` (rad), into `out` (m): `g + R(θ) p` for each `p`.
pub fn place(shape: &[Vec2], g: &Vec2, theta: f64, out: &mut Vec<Vec2>) {
    out.clear();
    out.extend(shape.iter().map(|p| g + rotate(p, theta)));
}

/// Area, centroid and second moment of a polygon, per unit surface density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaProperties {
    /// Area, m² (positive for a counter-clockwise polygon).
    pub area: f64,
    /// Centroid, m.
    pub centroid: Vec2,
    /// Polar second moment of area about the centroid, `∫ |x − G|² dx`, m⁴.
    pub polar_moment: f64,
}

/// Exact area, centroid and polar second moment about the centroid.
///
/// The signed area is negative for a clockwise polygon; callers validate the
/// orientation first (see [`check_convex_ccw`]).
pub fn area_properties(poly: &[Vec2]) -> AreaProperties {
    let n = poly.len();
    if n == 0 {
        return AreaProperties {
            area: 0.0,
            centroid: Vec2::zeros(),
            polar_moment: 0.0,
        };
    }
    let o = poly.iter().fold(Vec2::zeros(), |s, p| s + p) / n as f64;
    let mut a2 = 0.0; // twice the area
    let mut cx = 0.0; // 6 A x_c
    let mut cy = 0.0;
    let mut jo = 0.0; // 12 ∫ |x - o|²
    for i in 0..n {
        let p = poly[i] - o;
        let q = poly[(i + 1) % n] - o;
        let c = cross(&p, &q);
        a2 += c;
        cx += (p.x + q.x) * c;
        cy += (p.y + q.y) * c;
        jo += c * (p.x * p.x + p.x * q.x + q.x * q.x + p.y * p.y + p.y * q.y + q.y * q.y);
    }
    let area = 0.5 * a2;
    if area == 0.0 {
        return AreaProperties {
            area: 0.0,
            centroid: o,
            polar_moment: 0.0,
        };
    }
    let c = Vec2::new(cx / (3.0 * a2), cy / (3.0 * a2));
    let polar_o = jo / 12.0;
    AreaProperties {
        area,
        centroid: o + c,
        polar_moment: polar_o - area * c.norm_squared(),
    }
}

/// Why a polygon is not a valid floe or obstacle outline.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolygonError {
    /// Fewer than three vertices.
    #[error("a polygon needs at least 3 vertices, got {0}")]
    TooFewVertices(usize),
    /// A coordinate is NaN or infinite.
    #[error("vertex {0} has a non-finite coordinate")]
    NonFinite(usize),
    /// Two vertices coincide.
    #[error("vertices {0} and {1} are repeated (same point)")]
    RepeatedVertex(usize, usize),
    /// Signed area negative: the vertices turn clockwise.
    #[error("vertices are clockwise; list them counter-clockwise")]
    Clockwise,
    /// A turn in the wrong direction, or three aligned vertices.
    #[error("polygon is not strictly convex at vertex {0}")]
    NotConvex(usize),
    /// Three consecutive vertices aligned (the middle one is not a corner),
    /// or an edge turning back on the previous one.
    #[error("vertices {0}, {1} and {2} are aligned; remove vertex {1}")]
    Aligned(usize, usize, usize),
    /// Two edges that are not consecutive meet: the outline is not simple.
    /// Edge `i` joins vertex `i` to vertex `i + 1`.
    #[error("edges {0} (vertices {0}-{1}) and {2} (vertices {2}-{3}) cross; the outline must not intersect itself")]
    SelfIntersecting(usize, usize, usize, usize),
}

/// Orientation of the triangle `a, b, c`: `+1` counter-clockwise, `-1`
/// clockwise, `0` aligned (the sign of `(b − a) × (c − a)`).
fn orientation(a: &Vec2, b: &Vec2, c: &Vec2) -> i8 {
    let v = cross(&(b - a), &(c - a));
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

/// Whether `q`, aligned with `a` and `b`, lies within their bounding box.
fn on_segment(a: &Vec2, b: &Vec2, q: &Vec2) -> bool {
    q.x >= a.x.min(b.x) && q.x <= a.x.max(b.x) && q.y >= a.y.min(b.y) && q.y <= a.y.max(b.y)
}

/// Whether the closed segments `p1 p2` and `q1 q2` share a point (crossing,
/// touching or overlapping), by orientation tests (O'Rourke §1.5).
pub fn segments_meet(p1: &Vec2, p2: &Vec2, q1: &Vec2, q2: &Vec2) -> bool {
    let o1 = orientation(p1, p2, q1);
    let o2 = orientation(p1, p2, q2);
    let o3 = orientation(q1, q2, p1);
    let o4 = orientation(q1, q2, p2);
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true; // a proper crossing
    }
    (o1 == 0 && on_segment(p1, p2, q1))
        || (o2 == 0 && on_segment(p1, p2, q2))
        || (o3 == 0 && on_segment(q1, q2, p1))
        || (o4 == 0 && on_segment(q1, q2, p2))
}

/// The first pair of non-consecutive edges `(i, j)`, `i < j`, of the closed
/// outline `poly` that meet, if any (`O(n²)`). Edge `i` joins vertex `i` to
/// vertex `i + 1`.
pub fn first_self_intersection(poly: &[Vec2]) -> Option<(usize, usize)> {
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (&poly[i], &poly[(i + 1) % n]);
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue; // consecutive through vertex 0
            }
            if segments_meet(a, b, &poly[j], &poly[(j + 1) % n]) {
                return Some((i, j));
            }
        }
    }
    None
}

/// Whether the counter-clockwise polygon `poly` turns strictly left at every
/// vertex (a convex polygon without aligned vertices; an outline already
/// checked simple by [`check_simple_ccw`] winds once, so this is strict
/// convexity).
pub fn is_strictly_convex(poly: &[Vec2]) -> bool {
    let n = poly.len();
    n >= 3
        && (0..n).all(|i| {
            let a = poly[(i + n - 1) % n];
            let b = poly[i];
            let c = poly[(i + 1) % n];
            cross(&(b - a), &(c - b)) > 0.0
        })
}

/// The rules every outline keeps: at least three vertices, finite
/// coordinates, no repeated vertex (in this order).
fn check_vertices(poly: &[Vec2]) -> Result<(), PolygonError> {
    let n = poly.len();
    if n < 3 {
        return Err(PolygonError::TooFewVertices(n));
    }
    for (i, p) in poly.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(PolygonError::NonFinite(i));
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            if poly[i] == poly[j] {
                return Err(PolygonError::RepeatedVertex(i, j));
            }
        }
    }
    Ok(())
}

/// Checks that `poly` is a simple (non-self-intersecting), counter-clockwise
/// polygon with at least three distinct, finite vertices and no three
/// consecutive vertices aligned (the same tolerance as
/// [`check_convex_ccw`]: `|cross| ≤ 1e-12 × size²`). Convex or not. Nothing
/// is reordered. The tests run in this order: vertex count, finiteness,
/// repeated vertices, aligned vertices, self-intersection, orientation.
pub fn check_simple_ccw(poly: &[Vec2]) -> Result<(), PolygonError> {
    check_vertices(poly)?;
    let n = poly.len();
    let o = poly.iter().fold(Vec2::zeros(), |s, p| s + p) / n as f64;
    let scale = poly
        .iter()
        .map(|p| (p - o).norm_squared())
        .fold(0.0, f64::max);
    for i in 0..n {
        let a = poly[(i + n - 1) % n];
        let b = poly[i];
        let c = poly[(i + 1) % n];
        if cross(&(b - a), &(c - b)).abs() <= 1e-12 * scale {
            return Err(PolygonError::Aligned((i + n - 1) % n, i, (i + 1) % n));
        }
    }
    if let Some((i, j)) = first_self_intersection(poly) {
        return Err(PolygonError::SelfIntersecting(
            i,
            (i + 1) % n,
            j,
            (j + 1) % n,
        ));
    }
    if area_properties(poly).area <= 0.0 {
        return Err(PolygonError::Clockwise);
    }
    Ok(())
}

/// Checks that `poly` is a strictly convex, counter-clockwise polygon with
/// at least three distinct, finite vertices. Nothing is reordered.
pub fn check_convex_ccw(poly: &[Vec2]) -> Result<(), PolygonError> {
    check_vertices(poly)?;
    let n = poly.len();
    let props = area_properties(poly);
    if props.area <= 0.0 {
        return Err(PolygonError::Clockwise);
    }
    // Scale for the collinearity tolerance: squared size of the polygon.
    let scale = poly
        .iter()
        .map(|p| (p - props.centroid).norm_squared())
        .fold(0.0, f64::max);
    for i in 0..n {
        let a = poly[(i + n - 1) % n];
        let b = poly[i];
        let c = poly[(i + 1) % n];
        if cross(&(b - a), &(c - b)) <= 1e-12 * scale {
            return Err(PolygonError::NotConvex(i));
        }
    }
    // A star polygon turns left at every vertex but winds more than once.
    let mut turn = 0.0;
    for i in 0..n {
        let a = poly[(i + n - 1) % n];
        let b = poly[i];
        let c = poly[(i + 1) % n];
        let (u, v) = (b - a, c - b);
        turn += cross(&u, &v).atan2(u.dot(&v));
    }
    if (turn - std::f64::consts::TAU).abs() > 1e-6 {
        return Err(PolygonError::NotConvex(0));
    }
    Ok(())
}

/// Axis-aligned bounding box `(min, max)` of a point set.
pub fn aabb(poly: &[Vec2]) -> (Vec2, Vec2) {
    let mut lo = Vec2::repeat(f64::INFINITY);
    let mut hi = Vec2::repeat(f64::NEG_INFINITY);
    for p in poly {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (lo, hi)
}

/// Largest separation of two convex counter-clockwise polygons along the
/// outward edge normals of `a` and `b` (separating axis theorem).
///
/// Positive: the polygons are apart by at least that much (a lower bound of
/// their distance, exact when the closest features include an edge).
/// Negative or zero: they overlap or touch, and its magnitude is the
/// penetration depth along the best axis.
pub fn sat_separation(a: &[Vec2], b: &[Vec2]) -> f64 {
    fn one_way(a: &[Vec2], b: &[Vec2]) -> f64 {
        let n = a.len();
        let mut best = f64::NEG_INFINITY;
        for i in 0..n {
            let p = a[i];
            let e = a[(i + 1) % n] - p;
            let len = e.norm();
            if len == 0.0 {
                continue;
            }
            let normal = Vec2::new(e.y, -e.x) / len;
            let d = b
                .iter()
                .map(|q| normal.dot(&(q - p)))
                .fold(f64::INFINITY, f64::min);
            best = best.max(d);
        }
        best
    }
    one_way(a, b).max(one_way(b, a))
}

/// Whether two convex polygons overlap with a positive area, i.e. penetrate
/// by more than `tolerance` metres. Touching along an edge is not an overlap.
pub fn convex_overlap(a: &[Vec2], b: &[Vec2], tolerance: f64) -> bool {
    sat_separation(a, b) < -tolerance
}

/// Signed distance from point `p` to the simple counter-clockwise polygon
/// `poly`, convex or not, m: the Euclidean distance to the outline, negative
/// inside (inside by the crossing-number test). For a convex polygon it
/// equals [`point_polygon_signed_distance`] up to rounding; callers keep the
/// convex formula for convex bodies so that their results do not change.
pub fn point_outline_signed_distance(p: &Vec2, poly: &[Vec2]) -> f64 {
    outline_nearest(p, poly).0
}

/// The point of the outline of the simple counter-clockwise polygon `poly`
/// nearest `p`: the signed distance of [`point_outline_signed_distance`]
/// (m), the edge `i` it lies on (from `poly[i]` to `poly[i + 1]`, the first
/// of equals) and its parameter `s ∈ [0, 1]` along that edge.
pub fn outline_nearest(p: &Vec2, poly: &[Vec2]) -> (f64, usize, f64) {
    let n = poly.len();
    let mut best = f64::INFINITY;
    let (mut edge, mut at) = (0, 0.0);
    let mut inside = false;
    for i in 0..n {
        let a = poly[i];
        let b = poly[(i + 1) % n];
        let e = b - a;
        let len2 = e.norm_squared();
        let d = p - a;
        let s = if len2 > 0.0 {
            (d.dot(&e) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dist = (d - e * s).norm();
        if dist < best {
            (best, edge, at) = (dist, i, s);
        }
        // Crossing number: the edge straddles the horizontal through p and
        // crosses it to the right of p.
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    (if inside { -best } else { best }, edge, at)
}

/// The largest distance from `c` to a vertex of `poly` (circumradius about `c`).
pub fn radius_about(poly: &[Vec2], c: &Vec2) -> f64 {
    poly.iter().map(|p| (p - c).norm()).fold(0.0, f64::max)
}

/// Signed distance from point `p` to the convex counter-clockwise polygon
/// `poly`, m: the Euclidean distance when outside, minus the distance to the
/// nearest edge line when inside. Continuous in `p`.
pub fn point_polygon_signed_distance(p: &Vec2, poly: &[Vec2]) -> f64 {
    let n = poly.len();
    let mut inside_depth = f64::INFINITY;
    let mut outside = false;
    let mut best = f64::INFINITY;
    for i in 0..n {
        let a = poly[i];
        let e = poly[(i + 1) % n] - a;
        let len2 = e.norm_squared();
        if len2 == 0.0 {
            continue;
        }
        let d = p - a;
        // Outward normal distance to the edge line.
        let h = cross(&d, &e) / len2.sqrt();
        if h > 0.0 {
            outside = true;
        }
        inside_depth = inside_depth.min(-h);
        let s = (d.dot(&e) / len2).clamp(0.0, 1.0);
        best = best.min((d - e * s).norm());
    }
    if outside {
        best
    } else {
        -inside_depth
    }
}

/// The convex hull of `points`, counter-clockwise, without collinear or
/// repeated vertices (Andrew's monotone chain, 1979); fewer than 3 vertices
/// when the points are fewer or all collinear.
pub fn convex_hull(points: &[Vec2]) -> Vec<Vec2> {
    let mut p: Vec<Vec2> = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let mut hull: Vec<Vec2> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Vec2>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for q in iter {
            while hull.len() >= start + 2
                && cross(
                    &(hull[hull.len() - 1] - hull[hull.len() - 2]),
                    &(q - hull[hull.len() - 2]),
                ) <= 0.0
            {
                hull.pop();
            }
            hull.push(*q);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn convexity_checks_reject_bad_outlines() {
        let sq = [v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)];
        assert!(check_convex_ccw(&sq).is_ok());
        let cw: Vec<_> = sq.iter().rev().cloned().collect();
        assert_eq!(check_convex_ccw(&cw), Err(PolygonError::Clockwise));
        let dent = [v(0., 0.), v(1., 0.), v(0.5, 0.2), v(1., 1.), v(0., 1.)];
        assert!(matches!(
            check_convex_ccw(&dent),
            Err(PolygonError::NotConvex(_))
        ));
        let rep = [v(0., 0.), v(1., 0.), v(1., 0.), v(0., 1.)];
        assert_eq!(
            check_convex_ccw(&rep),
            Err(PolygonError::RepeatedVertex(1, 2))
        );
        let aligned = [v(0., 0.), v(0.5, 0.), v(1., 0.), v(0., 1.)];
        assert_eq!(check_convex_ccw(&aligned), Err(PolygonError::NotConvex(1)));
        assert_eq!(
            check_convex_ccw(&sq[..2]),
            Err(PolygonError::TooFewVertices(2))
        );
    }

    #[test]
    fn sat_separation_measures_gap_and_depth() {
        let a = [v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)];
        let b: Vec<_> = a.iter().map(|p| p + v(1.5, 0.)).collect();
        assert!((sat_separation(&a, &b) - 0.5).abs() < 1e-15);
        let c: Vec<_> = a.iter().map(|p| p + v(0.75, 0.2)).collect();
        assert!((sat_separation(&a, &c) + 0.25).abs() < 1e-15);
        assert!(convex_overlap(&a, &c, 0.0));
        let d: Vec<_> = a.iter().map(|p| p + v(1.0, 0.0)).collect();
        assert!(!convex_overlap(&a, &d, 0.0), "edge contact is not overlap");
    }

    #[test]
    fn point_distances_are_signed() {
        let a = [v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)];
        assert!((point_polygon_signed_distance(&v(2., 0.5), &a) - 1.0).abs() < 1e-15);
        assert!((point_polygon_signed_distance(&v(2., 2.), &a) - 2f64.sqrt()).abs() < 1e-15);
        assert!((point_polygon_signed_distance(&v(0.9, 0.5), &a) + 0.1).abs() < 1e-15);
    }

    #[test]
    fn the_convex_hull_is_the_counter_clockwise_corners() {
        let mut pts = vec![v(0., 0.), v(2., 0.), v(2., 2.), v(0., 2.)];
        // Inside, on an edge (collinear) and repeated points.
        pts.extend([v(1., 1.), v(1., 0.), v(2., 1.), v(0., 0.), v(0.5, 1.5)]);
        let h = convex_hull(&pts);
        assert_eq!(h, vec![v(0., 0.), v(2., 0.), v(2., 2.), v(0., 2.)]);
        assert!(convex_hull(&[v(0., 0.), v(1., 1.), v(2., 2.)]).len() < 3);
    }
}
