//! The broad phase against all pairs (random boxes, fixed pairs, the
//! margin), and `detect`, which joins the broad and narrow phases.

use super::{assert_close, assert_vec_close, square, v, HAND};
use floebench::contact::{detect, Aabb, BroadPhase, Contact};
use floebench::geometry::Vec2;
use floebench::rng::SplitMix64;

fn random_boxes(rng: &mut SplitMix64, n: usize) -> Vec<Aabb> {
    (0..n)
        .map(|_| {
            let c = v(rng.range(0.0, 100.0), rng.range(0.0, 100.0));
            let h = v(rng.range(0.05, 2.0), rng.range(0.05, 2.0));
            Aabb {
                min: c - h,
                max: c + h,
                fixed: rng.uniform() < 0.2,
            }
        })
        .collect()
}

fn brute_pairs(boxes: &[Aabb], margin: f64) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            let (p, q) = (&boxes[i], &boxes[j]);
            let overlap = p.min.x - margin <= q.max.x + margin
                && q.min.x - margin <= p.max.x + margin
                && p.min.y - margin <= q.max.y + margin
                && q.min.y - margin <= p.max.y + margin;
            if overlap && !(p.fixed && q.fixed) {
                out.push((i, j));
            }
        }
    }
    out
}

#[test]
fn broad_phase_equals_all_pairs_on_random_boxes() {
    let mut rng = SplitMix64::new(7);
    let mut bp = BroadPhase::new();
    let mut out = Vec::new();
    let mut boxes = random_boxes(&mut rng, 3000);
    for step in 0..6 {
        let margin = [0.0, 0.1, 0.5][step % 3];
        bp.pairs(&boxes, margin, &mut out);
        let want = brute_pairs(&boxes, margin);
        assert!(want.len() > 1000, "enough pairs: {}", want.len());
        assert_eq!(out, want, "step {step}");
        assert!(out
            .iter()
            .all(|&(i, j)| i < j && !(boxes[i].fixed && boxes[j].fixed)));
        // Small motion: exercises the insertion sort on the kept order.
        for b in &mut boxes {
            let d = v(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5));
            b.min += d;
            b.max += d;
        }
    }
    // A different box count resets the order.
    let fewer = &boxes[..1234];
    bp.pairs(fewer, 0.2, &mut out);
    assert_eq!(out, brute_pairs(fewer, 0.2));
}

#[test]
fn broad_phase_skips_fixed_pairs_and_inflates_by_margin() {
    let bx = |x0: f64, x1: f64, fixed: bool| Aabb {
        min: v(x0, 0.0),
        max: v(x1, 1.0),
        fixed,
    };
    let mut bp = BroadPhase::new();
    let mut out = Vec::new();
    // 0 and 1 overlap but are both fixed; 2 is 0.1 right of 1.
    let boxes = [bx(0.0, 1.0, true), bx(0.5, 1.5, true), bx(1.6, 2.6, false)];
    bp.pairs(&boxes, 0.0, &mut out);
    assert!(out.is_empty(), "{out:?}");
    bp.pairs(&boxes, 0.04, &mut out);
    assert!(out.is_empty(), "gap 0.1 > 2 × 0.04");
    bp.pairs(&boxes, 0.06, &mut out);
    assert_eq!(out, vec![(1, 2)], "gap 0.1 < 2 × 0.06");
    let boxes = [bx(0.0, 1.0, false), bx(0.5, 1.5, true), bx(1.5, 2.6, false)];
    bp.pairs(&boxes, 0.0, &mut out);
    assert_eq!(out, vec![(0, 1), (1, 2)], "touching boxes pair");
    // An empty polygon's box pairs with nothing.
    let boxes = [Aabb::of_polygon(&[], false), bx(0.0, 1.0, false)];
    bp.pairs(&boxes, 1.0, &mut out);
    assert!(out.is_empty());
}

#[test]
fn detect_orders_floe_before_fixed_obstacle() {
    let obstacle = vec![v(-5.0, -1.0), v(5.0, -1.0), v(5.0, 0.0), v(-5.0, 0.0)];
    let floe = square(0.0, 0.02, 1.0); // 0.02 above the obstacle
    let far = square(10.0, 10.0, 1.0);
    let wall = vec![v(5.0, -1.0), v(6.0, -1.0), v(6.0, 3.0), v(5.0, 3.0)]; // touches obstacle
    let bodies: Vec<&[Vec2]> = vec![&obstacle, &floe, &far, &wall];
    let fixed = [true, false, false, true];
    let mut bp = BroadPhase::new();
    let mut out: Vec<Contact> = Vec::new();
    detect(&bodies, &fixed, 0.05, &mut bp, &mut out);
    assert_eq!(out.len(), 2, "{out:#?}");
    for c in &out {
        assert_eq!((c.a, c.b), (1, 0), "floe first");
        assert_vec_close(&c.geom.normal, &v(0.0, -1.0), HAND, "floe to obstacle");
        assert_close(c.geom.gap, 0.02, HAND, "gap");
        assert_close(c.geom.point.y, 0.01, HAND, "midway");
    }
    // Floe moved beyond the distance: nothing; fixed pair 0–3 never reported.
    let floe = square(0.0, 0.2, 1.0);
    let bodies: Vec<&[Vec2]> = vec![&obstacle, &floe, &far, &wall];
    detect(&bodies, &fixed, 0.05, &mut bp, &mut out);
    assert!(out.is_empty(), "{out:?}");
    // Two free floes: smaller index first.
    let left = square(0.0, 0.0, 1.0);
    let right = square(1.01, 0.0, 1.0);
    let bodies: Vec<&[Vec2]> = vec![&left, &right];
    detect(&bodies, &[false, false], 0.05, &mut bp, &mut out);
    assert_eq!(out.len(), 2);
    assert!(out
        .iter()
        .all(|c| (c.a, c.b) == (0, 1) && c.geom.normal.x > 0.99));
}
