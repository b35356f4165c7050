//! The overlap of a crushing pair and the plane it is cut on
//! (docs/physics.md §10.4).
//!
//! The overlap of two bodies is the union of the intersections of their
//! convex parts ([`crate::model::Floe::parts`]); each intersection is one
//! convex polygon clipped by the edge lines of the other with the split's
//! chord cut ([`crate::fracture::split::cut`], the one polygon cut of the
//! project). The pair's normal `n` (from the first body to the second) is
//! the minimum-penetration axis of the narrow phase
//! ([`crate::contact::separation`]) of each pair of parts that overlaps,
//! weighted by the area of their intersection.

use crate::contact::separation;
use crate::fracture::split::cut;
use crate::geometry::{area_properties, cross, Vec2};

/// The overlap of two bodies: its convex pieces (world, m,
/// counter-clockwise) and the pair's unit normal from the first body to
/// the second.
#[derive(Debug, Clone, PartialEq)]
pub struct Overlap {
    /// The convex pieces of the overlap, one per pair of parts that
    /// overlaps with an area, m.
    pub pieces: Vec<Vec<Vec2>>,
    /// The unit normal from the first body to the second.
    pub normal: Vec2,
}

impl Overlap {
    /// The overlap of the bodies of world outlines `a` and `b` (m,
    /// counter-clockwise) made of the convex parts `parts_a` and `parts_b`
    /// (indices into the outlines); `None` when no pair of parts overlaps
    /// with an area or the normals cancel.
    pub fn of(
        a: &[Vec2],
        parts_a: &[Vec<usize>],
        b: &[Vec2],
        parts_b: &[Vec<usize>],
    ) -> Option<Overlap> {
        let mut pieces = Vec::new();
        let mut normal = Vec2::zeros();
        for ia in parts_a {
            let pa: Vec<Vec2> = ia.iter().map(|&k| a[k]).collect();
            for ib in parts_b {
                let pb: Vec<Vec2> = ib.iter().map(|&k| b[k]).collect();
                let piece = convex_intersection(&pa, &pb);
                if piece.len() < 3 {
                    continue;
                }
                let area = area_properties(&piece).area;
                let Some(sep) = separation(&pa, &pb) else {
                    continue;
                };
                if area > 0.0 && sep.distance < 0.0 {
                    normal += sep.normal * area;
                    pieces.push(piece);
                }
            }
        }
        let norm = normal.norm();
        (!pieces.is_empty() && norm > 0.0 && norm.is_finite()).then(|| Overlap {
            pieces,
            normal: normal / norm,
        })
    }

    /// The least and the largest of `n·x` over the overlap's vertices `x`,
    /// m: the overlap lies between the planes `n·x = lo` and `n·x = hi`.
    pub fn extent(&self) -> (f64, f64) {
        self.pieces
            .iter()
            .flatten()
            .map(|x| self.normal.dot(x))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s), hi.max(s))
            })
    }

    /// Its area, m².
    pub fn area(&self) -> f64 {
        self.pieces.iter().map(|p| area_properties(p).area).sum()
    }
}

/// The part of the convex polygon `a` inside the convex polygon `b` (both
/// counter-clockwise, m): `a` cut by the line of each edge of `b`
/// ([`cut`]), keeping the piece on the edge's left (inside `b`). Empty
/// when they do not overlap with an area.
pub fn convex_intersection(a: &[Vec2], b: &[Vec2]) -> Vec<Vec2> {
    let mut poly = a.to_vec();
    let n = b.len();
    for i in 0..n {
        if poly.len() < 3 {
            return Vec::new();
        }
        let (p, d) = (b[i], b[(i + 1) % n] - b[i]);
        match cut(&poly, &p, &d) {
            Some(c) => poly = c.left,
            None => {
                // The line leaves one side without area: the polygon is on
                // one side of it (within the cut's tolerance), the side of
                // its mean vertex (inside a convex polygon).
                let mean = poly.iter().fold(Vec2::zeros(), |s, x| s + x) / poly.len() as f64;
                if cross(&d, &(mean - p)) <= 0.0 {
                    return Vec::new();
                }
            }
        }
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, y0: f64, s: f64) -> Vec<Vec2> {
        vec![
            Vec2::new(x0, y0),
            Vec2::new(x0 + s, y0),
            Vec2::new(x0 + s, y0 + s),
            Vec2::new(x0, y0 + s),
        ]
    }

    /// Two unit squares shifted by (0.5, 0.25) overlap on a 0.5 × 0.75
    /// rectangle, with the normal of the shallower axis.
    #[test]
    fn two_shifted_squares_overlap_on_a_rectangle() {
        let (a, b) = (square(0.0, 0.0, 1.0), square(0.5, 0.25, 1.0));
        let part = vec![vec![0, 1, 2, 3]];
        let o = Overlap::of(&a, &part, &b, &part).unwrap();
        assert!((o.area() - 0.375).abs() < 1e-15, "{}", o.area());
        assert!(
            (o.normal - Vec2::new(1.0, 0.0)).norm() < 1e-15,
            "{:?}",
            o.normal
        );
        let (lo, hi) = o.extent();
        assert!((lo - 0.5).abs() < 1e-15 && (hi - 1.0).abs() < 1e-15);
    }

    /// Disjoint or touching polygons have no overlap.
    #[test]
    fn touching_squares_do_not_overlap() {
        let part = vec![vec![0, 1, 2, 3]];
        let (a, b) = (square(0.0, 0.0, 1.0), square(1.0, 0.0, 1.0));
        assert!(Overlap::of(&a, &part, &b, &part).is_none());
        let c = square(3.0, 0.0, 1.0);
        assert!(convex_intersection(&a, &c).is_empty());
    }

    /// A polygon inside the other is its own intersection.
    #[test]
    fn a_polygon_inside_the_other_is_the_intersection() {
        let (a, b) = (square(0.25, 0.25, 0.5), square(0.0, 0.0, 1.0));
        let i = convex_intersection(&a, &b);
        assert!((area_properties(&i).area - 0.25).abs() < 1e-15);
    }
}
