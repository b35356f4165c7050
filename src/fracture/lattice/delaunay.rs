//! The Delaunay triangulation of a point set by Bowyer–Watson (Bowyer 1981,
//! Watson 1981): start from a triangle enclosing every point, insert the
//! points one by one, each time removing the triangles whose circumcircle
//! contains the new point (the cavity) and joining the point to the
//! cavity's boundary; at the end, drop the triangles that use a vertex of
//! the enclosing triangle. The cavity is found by scanning every triangle
//! (O(n²) in all, fine for the few thousand nodes of a floe's lattice).
//!
//! The enclosing triangle is 1000 times the size of the points' bounding
//! box, so that its circumcircles near the hull are almost half-planes and
//! the triangulation covers the convex hull (checked by the lattice's
//! area, docs/physics.md §7.2).

use crate::geometry::{cross, Vec2};
use std::collections::HashMap;

/// A triangle and its circumcircle.
#[derive(Debug, Clone, Copy)]
struct Tri {
    v: [usize; 3],
    centre: Vec2,
    r2: f64,
    alive: bool,
}

fn circumcircle(a: &Vec2, b: &Vec2, c: &Vec2) -> (Vec2, f64) {
    let (ab, ac) = (b - a, c - a);
    let d = 2.0 * cross(&ab, &ac);
    let (b2, c2) = (ab.norm_squared(), ac.norm_squared());
    let u = Vec2::new(ac.y * b2 - ab.y * c2, ab.x * c2 - ac.x * b2) / d;
    (a + u, u.norm_squared())
}

/// The Delaunay triangles of `points` (indices, counter-clockwise), in the
/// order they were made. Points closer than rounding to one already
/// inserted are skipped (they join no triangle).
pub fn triangulate(points: &[Vec2]) -> Vec<[usize; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let c = (lo + hi) * 0.5;
    let s = (hi - lo).max().max(f64::MIN_POSITIVE) * 1000.0;
    let mut pts: Vec<Vec2> = points.to_vec();
    pts.push(c + Vec2::new(-2.0 * s, -s));
    pts.push(c + Vec2::new(2.0 * s, -s));
    pts.push(c + Vec2::new(0.0, 2.0 * s));
    let make = |pts: &[Vec2], v: [usize; 3]| {
        let (centre, r2) = circumcircle(&pts[v[0]], &pts[v[1]], &pts[v[2]]);
        Tri {
            v,
            centre,
            r2,
            alive: true,
        }
    };
    let mut tris = vec![make(&pts, [n, n + 1, n + 2])];
    // The alive triangles on each edge (at most two).
    let mut on_edge: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    let key = |a: usize, b: usize| (a.min(b), a.max(b));
    for k in 0..3 {
        on_edge.insert(key(n + k, n + (k + 1) % 3), vec![0]);
    }
    let mut cavity: Vec<usize> = Vec::new();
    let mut stack: Vec<usize> = Vec::new();
    for (i, p) in points.iter().enumerate() {
        // The cavity: the triangles whose circumcircle holds p, grown from
        // the one that contains p across edges (so it is connected).
        let inside = |t: &Tri| {
            (0..3).all(|k| cross(&(pts[t.v[(k + 1) % 3]] - pts[t.v[k]]), &(p - pts[t.v[k]])) >= 0.0)
        };
        let Some(first) = tris.iter().position(|t| t.alive && inside(t)) else {
            continue;
        };
        cavity.clear();
        stack.clear();
        stack.push(first);
        tris[first].alive = false;
        while let Some(t) = stack.pop() {
            cavity.push(t);
            let v = tris[t].v;
            for k in 0..3 {
                for &o in &on_edge[&key(v[k], v[(k + 1) % 3])] {
                    if tris[o].alive && (p - tris[o].centre).norm_squared() < tris[o].r2 {
                        tris[o].alive = false;
                        stack.push(o);
                    }
                }
            }
        }
        // Its boundary: edges of one cavity triangle only.
        let mut boundary: Vec<(usize, usize)> = Vec::new();
        for &t in &cavity {
            let v = tris[t].v;
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                if on_edge[&key(a, b)].iter().all(|&o| o == t || tris[o].alive) {
                    boundary.push((a, b));
                }
            }
        }
        for &t in &cavity {
            let v = tris[t].v;
            for k in 0..3 {
                if let Some(list) = on_edge.get_mut(&key(v[k], v[(k + 1) % 3])) {
                    list.retain(|&o| o != t);
                }
            }
        }
        for (a, b) in boundary {
            if cross(&(pts[b] - pts[a]), &(p - pts[a])) > 0.0 {
                let id = tris.len();
                tris.push(make(&pts, [a, b, i]));
                for e in [key(a, b), key(b, i), key(i, a)] {
                    on_edge.entry(e).or_default().push(id);
                }
            }
        }
    }
    tris.iter()
        .filter(|t| t.alive && t.v.iter().all(|&k| k < n))
        .map(|t| t.v)
        .collect()
}
