//! Decomposition of a simple polygon into convex parts, for the contact
//! detection of non-convex floes and obstacles.
//!
//! # Scheme
//!
//! A strictly convex polygon is its own single part (the vertex list
//! `0, 1, …, n − 1`), so convex bodies are detected exactly as before.
//! Otherwise:
//!
//! 1. **Ear clipping** (O'Rourke §1.6): a vertex is an ear when it turns
//!    strictly left and the triangle it makes with its two neighbours holds
//!    no other remaining vertex (closed test). Among the ears, the one whose
//!    triangle has the largest smallest angle is cut first (a quality rule
//!    that keeps thin triangles out where it can), until three vertices
//!    remain. `O(n³)` for `n ≤ 64` vertices.
//! 2. **Hertel–Mehlhorn**: the diagonals of the triangulation are visited
//!    from the longest to the shortest, and a diagonal is removed (its two
//!    parts merged) when the merged part still turns strictly left at both
//!    ends of the diagonal. The result has at most four times the minimum
//!    number of convex parts (Hertel & Mehlhorn 1983) and no part is thinner
//!    than a triangle of the triangulation it came from.
//!
//! Parts never add vertices: each is a list of indices into the outline,
//! counter-clockwise and strictly convex, starting at its smallest index
//! (the parts sorted), and the parts tile the polygon
//! exactly (their areas sum to its area, they overlap only along the
//! diagonals that were kept). An edge of a part joining two outline
//! vertices that are not consecutive is an internal edge (a kept diagonal):
//! contacts are never generated on it (see [`crate::contact`]).
//!
//! # References
//!
//! - J. O'Rourke (1998), *Computational Geometry in C*, 2nd ed., §1.6.
//! - S. Hertel, K. Mehlhorn (1983), *Fast triangulation of simple polygons*,
//!   Foundations of Computation Theory, LNCS 158, 207–218.

use super::{cross, is_strictly_convex, Vec2};

/// Whether `p` lies in the closed counter-clockwise triangle `a b c`.
fn in_triangle(p: &Vec2, a: &Vec2, b: &Vec2, c: &Vec2) -> bool {
    cross(&(b - a), &(p - a)) >= 0.0
        && cross(&(c - b), &(p - b)) >= 0.0
        && cross(&(a - c), &(p - c)) >= 0.0
}

/// The smallest angle of the triangle `a b c`, rad.
fn smallest_angle(a: &Vec2, b: &Vec2, c: &Vec2) -> f64 {
    let angle = |p: &Vec2, q: &Vec2, r: &Vec2| {
        let (u, v) = (q - p, r - p);
        cross(&u, &v).abs().atan2(u.dot(&v))
    };
    angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b))
}

/// Ear-clipping triangulation of the simple counter-clockwise polygon
/// `poly`: triangles as counter-clockwise vertex indices. `None` if no ear
/// is found (only for outlines that are not simple, or degenerate within
/// rounding).
pub fn triangulate(poly: &[Vec2]) -> Option<Vec<[usize; 3]>> {
    let n = poly.len();
    if n < 3 {
        return None;
    }
    let mut rem: Vec<usize> = (0..n).collect();
    let mut tris = Vec::with_capacity(n - 2);
    while rem.len() > 3 {
        let m = rem.len();
        let mut best: Option<(usize, f64)> = None;
        for k in 0..m {
            let (ia, ib, ic) = (rem[(k + m - 1) % m], rem[k], rem[(k + 1) % m]);
            let (a, b, c) = (&poly[ia], &poly[ib], &poly[ic]);
            if cross(&(b - a), &(c - b)) <= 0.0 {
                continue;
            }
            let blocked = rem
                .iter()
                .any(|&v| v != ia && v != ib && v != ic && in_triangle(&poly[v], a, b, c));
            if blocked {
                continue;
            }
            let q = smallest_angle(a, b, c);
            if best.is_none_or(|(_, bq)| q > bq) {
                best = Some((k, q));
            }
        }
        let (k, _) = best?;
        tris.push([rem[(k + m - 1) % m], rem[k], rem[(k + 1) % m]]);
        rem.remove(k);
    }
    tris.push([rem[0], rem[1], rem[2]]);
    Some(tris)
}

/// The position of the directed edge `i → j` in the cycle `part`, if it is
/// one of its edges.
fn edge_at(part: &[usize], i: usize, j: usize) -> Option<usize> {
    let m = part.len();
    (0..m).find(|&k| part[k] == i && part[(k + 1) % m] == j)
}

/// `part` rotated to start at position `k`.
fn rotated(part: &[usize], k: usize) -> Vec<usize> {
    part[k..].iter().chain(&part[..k]).copied().collect()
}

/// The convex parts of the simple counter-clockwise polygon `poly` (see the
/// module documentation), as counter-clockwise lists of vertex indices;
/// `vec![0..n]` for a strictly convex polygon. `None` if the triangulation
/// fails (see [`triangulate`]).
pub fn convex_parts(poly: &[Vec2]) -> Option<Vec<Vec<usize>>> {
    let n = poly.len();
    if is_strictly_convex(poly) {
        return Some(vec![(0..n).collect()]);
    }
    let tris = triangulate(poly)?;
    let mut parts: Vec<Vec<usize>> = tris.iter().map(|t| t.to_vec()).collect();
    let outline_edge = |i: usize, j: usize| (i + 1) % n == j || (j + 1) % n == i;
    let mut diagonals: Vec<(usize, usize)> = tris
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .filter(|&(i, j)| i < j && !outline_edge(i, j))
        .collect();
    diagonals.sort_by(|&(a, b), &(c, d)| {
        let la = (poly[a] - poly[b]).norm_squared();
        let lc = (poly[c] - poly[d]).norm_squared();
        lc.total_cmp(&la).then((a, b).cmp(&(c, d)))
    });
    for (i, j) in diagonals {
        let Some((p, kp)) = parts
            .iter()
            .enumerate()
            .find_map(|(k, part)| edge_at(part, i, j).map(|e| (k, e)))
        else {
            continue;
        };
        let Some((q, kq)) = parts
            .iter()
            .enumerate()
            .find_map(|(k, part)| edge_at(part, j, i).map(|e| (k, e)))
        else {
            continue;
        };
        // P from j round to i, then Q from i round to j without its ends.
        let pp = rotated(&parts[p], (kp + 1) % parts[p].len());
        let qq = rotated(&parts[q], (kq + 1) % parts[q].len());
        let mut merged = pp;
        merged.extend(&qq[1..qq.len() - 1]);
        let pts: Vec<Vec2> = merged.iter().map(|&v| poly[v]).collect();
        if !is_strictly_convex(&pts) {
            continue;
        }
        let (lo, hi) = (p.min(q), p.max(q));
        parts[lo] = merged;
        parts.remove(hi);
    }
    // Each part from its smallest vertex index, the parts in that order.
    for part in &mut parts {
        let k = (0..part.len()).min_by_key(|&k| part[k]).unwrap_or(0);
        *part = rotated(part, k);
    }
    parts.sort();
    Some(parts)
}

/// Whether the edge from part vertex `k` to `k + 1` of `part` (indices into
/// an outline of `n` vertices) is an internal edge (a diagonal), not an edge
/// of the outline.
pub fn is_internal_edge(part: &[usize], k: usize, n: usize) -> bool {
    let (i, j) = (part[k], part[(k + 1) % part.len()]);
    (i + 1) % n != j
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::area_properties;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    #[test]
    fn an_l_shape_splits_into_two_convex_parts() {
        let l = [
            v(0., 0.),
            v(2., 0.),
            v(2., 1.),
            v(1., 1.),
            v(1., 2.),
            v(0., 2.),
        ];
        let parts = convex_parts(&l).unwrap();
        assert_eq!(parts.len(), 2, "{parts:?}");
        let area: f64 = parts
            .iter()
            .map(|p| area_properties(&p.iter().map(|&k| l[k]).collect::<Vec<_>>()).area)
            .sum();
        assert!((area - 3.0).abs() < 1e-12);
    }

    #[test]
    fn a_convex_polygon_is_its_own_part() {
        let sq = [v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)];
        assert_eq!(convex_parts(&sq).unwrap(), vec![vec![0, 1, 2, 3]]);
    }
}
