//! Broad phase: sweep and prune on axis-aligned bounding boxes.
//!
//! The boxes are kept sorted by their lower `x` bound in a buffer that
//! survives between calls. The first call (or a call with a different box
//! count) sorts from scratch, `O(N log N)`; later calls re-sort the previous
//! order by insertion sort, `O(N + inversions)`, which is nearly linear when
//! the bodies moved little. The sweep then walks the sorted list and, for
//! each box, the following boxes until one starts beyond its upper `x` bound;
//! those overlap in `x`, and the pair is kept if they also overlap in `y`
//! and are not both fixed. Cost `O(N + K_x)` with `K_x` the pairs
//! overlapping in `x`. Ties in `x` are broken by index and the output is
//! sorted, so the result is deterministic.
//!
//! Boxes touching at a boundary overlap (comparisons are `≤`), so touching
//! bodies are reported. A box with a NaN or an empty box (`min > max`, as
//! [`crate::geometry::aabb`] gives for an empty polygon) pairs with nothing.
//!
//! It is pure geometry, below both the contact detection
//! ([`crate::contact`], which re-exports it) and the case validation's
//! overlap check.

use super::{aabb, Vec2};
use std::cmp::Ordering;

/// An axis-aligned bounding box in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner, m.
    pub min: Vec2,
    /// Upper corner, m.
    pub max: Vec2,
    /// Whether the body is fixed (an obstacle): pairs of two fixed boxes are
    /// never reported.
    pub fixed: bool,
}

impl Aabb {
    /// The bounding box of a polygon (vertices in m).
    pub fn of_polygon(poly: &[Vec2], fixed: bool) -> Self {
        let (min, max) = aabb(poly);
        Self { min, max, fixed }
    }

    /// Whether the two boxes, each inflated by `margin` (m) on every side,
    /// overlap or touch. The same arithmetic as [`BroadPhase::pairs`].
    pub fn overlaps(&self, other: &Aabb, margin: f64) -> bool {
        self.min.x - margin <= other.max.x + margin
            && other.min.x - margin <= self.max.x + margin
            && self.min.y - margin <= other.max.y + margin
            && other.min.y - margin <= self.max.y + margin
    }
}

/// Sweep-and-prune broad phase, reusable across time steps (keeps its sort
/// order and scratch buffers).
#[derive(Debug, Clone, Default)]
pub struct BroadPhase {
    /// Box indices sorted by `min.x`, from the previous call.
    order: Vec<usize>,
    /// Scratch boxes for [`crate::contact::detect`].
    pub(crate) boxes: Vec<Aabb>,
    /// Scratch candidate pairs for [`crate::contact::detect`].
    pub(crate) candidates: Vec<(usize, usize)>,
}

/// Sort key: lower `x` bound (total order, NaN last), then index.
#[inline]
fn key_cmp(boxes: &[Aabb], i: usize, j: usize) -> Ordering {
    boxes[i].min.x.total_cmp(&boxes[j].min.x).then(i.cmp(&j))
}

impl BroadPhase {
    /// An empty broad phase.
    pub fn new() -> Self {
        Self::default()
    }

    /// Replaces the content of `out` by the candidate pairs `(i, j)`, `i < j`,
    /// of boxes that overlap once each is inflated by `margin` (m) on every
    /// side, skipping pairs of two fixed boxes. Each pair appears once; the
    /// list is sorted.
    pub fn pairs(&mut self, boxes: &[Aabb], margin: f64, out: &mut Vec<(usize, usize)>) {
        out.clear();
        let n = boxes.len();
        if self.order.len() != n {
            self.order.clear();
            self.order.extend(0..n);
            self.order.sort_unstable_by(|&i, &j| key_cmp(boxes, i, j));
        } else {
            // Insertion sort: near-linear on the nearly sorted previous order.
            for p in 1..n {
                let mut q = p;
                while q > 0 && key_cmp(boxes, self.order[q - 1], self.order[q]) == Ordering::Greater
                {
                    self.order.swap(q - 1, q);
                    q -= 1;
                }
            }
        }
        for (p, &i) in self.order.iter().enumerate() {
            let bi = &boxes[i];
            let reach = bi.max.x + margin;
            for &j in &self.order[p + 1..] {
                let bj = &boxes[j];
                let starts_within = bj.min.x - margin <= reach; // false for NaN
                if !starts_within {
                    break;
                }
                if (bi.fixed && bj.fixed) || !bi.overlaps(bj, margin) {
                    continue;
                }
                out.push((i.min(j), i.max(j)));
            }
        }
        out.sort_unstable();
    }
}
