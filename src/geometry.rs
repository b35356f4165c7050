//! Planar geometry of convex polygons: the one vocabulary of the project.
//!
//! Points and vectors are [`Vec2`] (`nalgebra::Vector2<f64>`), in metres.
//! Polygons are slices of vertices, counter-clockwise, without repetition of
//! the first vertex at the end.
//!
//! Mass properties use the exact polygon formulas (Green's theorem on each
//! edge). To keep rounding small far from the origin they are computed about
//! the vertex average and shifted afterwards.

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
}

/// Checks that `poly` is a strictly convex, counter-clockwise polygon with
/// at least three distinct, finite vertices. Nothing is reordered.
pub fn check_convex_ccw(poly: &[Vec2]) -> Result<(), PolygonError> {
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
}
