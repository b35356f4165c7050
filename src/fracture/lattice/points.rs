//! The nodes of a lattice (docs/physics.md §7.2): the outline's, then a
//! seeded Poisson-disc set inside it ([`poisson_disc`]) or the nodes of a
//! triangular lattice clipped to it ([`triangular_points`]).

#[cfg(doc)]
use super::Mesh;
use crate::geometry::{area_properties, point_polygon_signed_distance, Vec2};
use crate::rng::SplitMix64;
use std::collections::HashMap;

/// A seeded Poisson-disc point set in the convex counter-clockwise polygon
/// `poly` at `spacing` (Bridson 2007): first the outline, its vertices and
/// points at most `spacing` apart along each edge; then, from the
/// centroid, points at least `spacing` from every other and `spacing/2`
/// inside the outline, 30 candidates per active point in the annulus
/// `[spacing, 2 spacing)`. Returns the points and how many of the first
/// are on the outline.
pub fn poisson_disc(poly: &[Vec2], spacing: f64, seed: u64) -> (Vec<Vec2>, usize) {
    let mut pts = outline_points(poly, spacing);
    let nb = pts.len();
    let cell = spacing / std::f64::consts::SQRT_2;
    let key = |p: &Vec2| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in pts.iter().enumerate() {
        grid.entry(key(p)).or_default().push(i);
    }
    let far = |pts: &[Vec2], grid: &HashMap<(i64, i64), Vec<usize>>, p: &Vec2| {
        let (cx, cy) = key(p);
        for dx in -2..=2 {
            for dy in -2..=2 {
                if let Some(list) = grid.get(&(cx + dx, cy + dy)) {
                    if list.iter().any(|&j| (pts[j] - p).norm() < spacing) {
                        return false;
                    }
                }
            }
        }
        true
    };
    let inside = |p: &Vec2| point_polygon_signed_distance(p, poly) <= -0.5 * spacing;
    let mut rng = SplitMix64::new(seed);
    let mut active: Vec<usize> = Vec::new();
    let start = area_properties(poly).centroid;
    if inside(&start) && far(&pts, &grid, &start) {
        grid.entry(key(&start)).or_default().push(pts.len());
        active.push(pts.len());
        pts.push(start);
    }
    while !active.is_empty() {
        let a = rng.int_range(0, active.len() - 1);
        let centre = pts[active[a]];
        let mut found = false;
        for _ in 0..30 {
            let r = spacing * (1.0 + rng.uniform());
            let t = rng.range(0.0, std::f64::consts::TAU);
            let p = centre + Vec2::new(r * t.cos(), r * t.sin());
            if inside(&p) && far(&pts, &grid, &p) {
                grid.entry(key(&p)).or_default().push(pts.len());
                active.push(pts.len());
                pts.push(p);
                found = true;
                break;
            }
        }
        if !found {
            active.swap_remove(a);
        }
    }
    (pts, nb)
}

/// The outline's nodes: the vertices of the polygon `poly` and, along
/// each edge, equally spaced points at most `spacing` apart (both meshes).
fn outline_points(poly: &[Vec2], spacing: f64) -> Vec<Vec2> {
    let mut pts: Vec<Vec2> = Vec::new();
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let m = ((b - a).norm() / spacing).ceil().max(1.0) as usize;
        for j in 0..m {
            pts.push(a + (b - a) * (j as f64 / m as f64));
        }
    }
    pts
}

/// The nodes of a triangular mesh of the convex counter-clockwise polygon
/// `poly` ([`Mesh::Triangular`]): the outline's ([`outline_points`]), then
/// the nodes `o + i a₁ + j a₂` of the equilateral lattice of side
/// `spacing` (`a₁` at `angle`, `a₂` at `angle + π/3`, `o` the centroid
/// plus `offset` in those coordinates) that lie at least `spacing/2`
/// inside the outline, in the order of `j` then `i`. Returns the points and
/// how many of the first are on the outline.
pub fn triangular_points(
    poly: &[Vec2],
    spacing: f64,
    angle: f64,
    offset: [f64; 2],
) -> (Vec<Vec2>, usize) {
    let mut pts = outline_points(poly, spacing);
    let nb = pts.len();
    let a1 = Vec2::new(angle.cos(), angle.sin()) * spacing;
    let third = angle + std::f64::consts::FRAC_PI_3;
    let a2 = Vec2::new(third.cos(), third.sin()) * spacing;
    let origin = area_properties(poly).centroid + a1 * offset[0] + a2 * offset[1];
    // |i a₁ + j a₂|² = s² (i² + i j + j²) ≥ ¾ s² max(|i|, |j|)², so
    // |i|, |j| ≤ 2R/(s√3) cover the disc of radius R about the origin that
    // holds the outline.
    let radius = poly.iter().map(|p| (p - origin).norm()).fold(0.0, f64::max);
    let n = (2.0 * radius / (spacing * 3f64.sqrt())).ceil() as i64 + 1;
    for j in -n..=n {
        for i in -n..=n {
            let p = origin + a1 * i as f64 + a2 * j as f64;
            if point_polygon_signed_distance(&p, poly) <= -0.5 * spacing {
                pts.push(p);
            }
        }
    }
    (pts, nb)
}
