//! Tests of the contact module: narrow phase against hand-computed values and
//! brute force, broad phase against all pairs, and `detect`.
//!
//! This file holds what the submodules share: the polygon builders (squares,
//! translations, rotations, random convex polygons), the distance to a
//! boundary, the comparisons with a tolerance and the narrow phase's
//! manifolds sorted. The tests are in the submodules, one topic each.

mod broad_phase;
mod manifolds;
mod random_pairs;
mod signed_distance;

use floebench::contact::{contacts, ContactGeom};
use floebench::geometry::{check_convex_ccw, rotate, Vec2};
use floebench::rng::SplitMix64;

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

/// Axis-aligned square `[x, x + side] × [y, y + side]`, counter-clockwise.
fn square(x: f64, y: f64, side: f64) -> Vec<Vec2> {
    vec![
        v(x, y),
        v(x + side, y),
        v(x + side, y + side),
        v(x, y + side),
    ]
}

fn translate(poly: &[Vec2], d: Vec2) -> Vec<Vec2> {
    poly.iter().map(|p| p + d).collect()
}

/// Rotation of `poly` by `theta` about the point `c`.
fn rotate_about(poly: &[Vec2], c: Vec2, theta: f64) -> Vec<Vec2> {
    poly.iter().map(|p| c + rotate(&(p - c), theta)).collect()
}

/// A random strictly convex CCW polygon of 3–9 vertices, size about 1 m,
/// centred in `[-spread, spread]²`: points on an ellipse at sorted random
/// angles, rotated.
fn random_convex(rng: &mut SplitMix64, spread: f64) -> Vec<Vec2> {
    let c = v(rng.range(-spread, spread), rng.range(-spread, spread));
    loop {
        let k = 3 + (rng.next_u64() % 7) as usize;
        let mut angles: Vec<f64> = (0..k)
            .map(|_| rng.range(0.0, std::f64::consts::TAU))
            .collect();
        angles.sort_by(f64::total_cmp);
        let (sx, sy) = (rng.range(0.3, 1.2), rng.range(0.3, 1.2));
        let theta = rng.range(0.0, std::f64::consts::TAU);
        let poly: Vec<Vec2> = angles
            .iter()
            .map(|a| c + rotate(&v(sx * a.cos(), sy * a.sin()), theta))
            .collect();
        if check_convex_ccw(&poly).is_ok() {
            return poly;
        }
    }
}

fn point_segment_distance(p: &Vec2, s0: &Vec2, s1: &Vec2) -> f64 {
    let d = s1 - s0;
    let t = (d.dot(&(p - s0)) / d.norm_squared()).clamp(0.0, 1.0);
    (p - (s0 + t * d)).norm()
}

/// Distance from `p` to the boundary of `poly`.
fn boundary_distance(p: &Vec2, poly: &[Vec2]) -> f64 {
    (0..poly.len())
        .map(|i| point_segment_distance(p, &poly[i], &poly[(i + 1) % poly.len()]))
        .fold(f64::INFINITY, f64::min)
}

fn assert_close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:e}, want {want:e}, diff {:e} > {tol:e}",
        (got - want).abs()
    );
}

fn assert_vec_close(got: &Vec2, want: &Vec2, tol: f64, what: &str) {
    assert!(
        (got - want).norm() <= tol,
        "{what}: got {got:?}, want {want:?}"
    );
}

fn all_contacts(a: &[Vec2], b: &[Vec2], distance: f64) -> Vec<ContactGeom> {
    let mut out = Vec::new();
    contacts(a, b, distance, &mut out);
    out
}

/// Sorts contacts by point (y then x) to compare sets.
fn by_point(mut c: Vec<ContactGeom>) -> Vec<ContactGeom> {
    c.sort_by(|p, q| {
        p.point
            .y
            .total_cmp(&q.point.y)
            .then(p.point.x.total_cmp(&q.point.x))
    });
    c
}

// Tolerance for hand-computed values of unit-size shapes: a few roundings
// of O(1) coordinates.
const HAND: f64 = 1e-14;
