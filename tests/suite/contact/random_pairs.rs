//! Seeded random pairs: the contacts of random convex polygons agree with
//! the signed distance, and rectangles on a grid (exact ties, turned or
//! not) give the expected manifolds.

use super::{
    all_contacts, assert_close, assert_vec_close, boundary_distance, random_convex, rotate_about, v,
};
use floebench::contact::signed_distance;
use floebench::geometry::{perp, Vec2};
use floebench::rng::SplitMix64;

#[test]
fn random_contacts_are_consistent_with_the_signed_distance() {
    let mut rng = SplitMix64::new(42);
    for _ in 0..400 {
        let a = random_convex(&mut rng, 0.0);
        let b = random_convex(&mut rng, 2.5);
        let sd = signed_distance(&a, &b);
        let c = all_contacts(&a, &b, 10.0);
        assert!(!c.is_empty() && c.len() <= 2);
        let n = c[0].normal;
        // Unit vectors: a few roundings.
        assert_close(n.norm(), 1.0, 1e-15, "unit normal");
        let min_gap = c.iter().map(|g| g.gap).fold(f64::INFINITY, f64::min);
        assert_close(min_gap, sd, 1e-12, "deepest gap is the signed distance");
        for g in &c {
            assert_eq!(g.normal, n, "one normal per pair");
            assert_eq!(g.tangent, perp(&n));
            assert!(g.gap >= sd - 1e-12);
            if sd > 0.0 {
                // Separated: point ∓ gap/2 n lies on A's and B's boundaries.
                let pa = g.point - 0.5 * g.gap * n;
                let pb = g.point + 0.5 * g.gap * n;
                assert_close(boundary_distance(&pa, &a), 0.0, 1e-12, "on A");
                assert_close(boundary_distance(&pb, &b), 0.0, 1e-12, "on B");
            }
        }
        let d = all_contacts(&b, &a, 10.0);
        assert_eq!(c.len(), d.len());
        assert_vec_close(&d[0].normal, &-n, 1e-12, "swap flips the normal");
        // Nothing beyond a distance below the signed distance.
        assert!(all_contacts(&a, &b, sd - 1e-9).is_empty());
    }
}

/// Gap (`> 0` apart) and overlap length of the intervals `[a0, a1]`, `[b0, b1]`.
fn interval_gap_overlap(a0: f64, a1: f64, b0: f64, b1: f64) -> (f64, f64) {
    ((b0 - a1).max(a0 - b1), a1.min(b1) - a0.max(b0))
}

#[test]
fn grid_rectangles_with_exact_ties_give_the_expected_manifolds() {
    // Corners on a 0.25 m grid: aligned corners, touching and coincident
    // edges occur often, and every expected value is exact.
    let mut rng = SplitMix64::new(2024);
    let mut grid = |lo: u64, span: u64| 0.25 * (lo + rng.next_u64() % span) as f64;
    let (mut ones, mut twos) = (0, 0);
    for case in 0..1500 {
        let (ax, ay) = (grid(0, 8), grid(0, 8));
        let (aw, ah) = (grid(1, 6), grid(1, 6));
        let (bx, by) = (grid(0, 8), grid(0, 8));
        let (bw, bh) = (grid(1, 6), grid(1, 6));
        let rect = |x: f64, y: f64, w: f64, h: f64| {
            vec![v(x, y), v(x + w, y), v(x + w, y + h), v(x, y + h)]
        };
        // Any starting vertex: exercises the lowest-vertex tie-breaks.
        let mut a = rect(ax, ay, aw, ah);
        let mut b = rect(bx, by, bw, bh);
        a.rotate_left(case % 4);
        b.rotate_left((case / 4) % 4);
        let (gx, ox) = interval_gap_overlap(ax, ax + aw, bx, bx + bw);
        let (gy, oy) = interval_gap_overlap(ay, ay + ah, by, by + bh);
        let (want_sd, want_n) = if gx > 0.0 && gy > 0.0 {
            (gx.hypot(gy), 1)
        } else {
            // Along the axis of the larger gap; two points if the other
            // axis overlaps with a positive length.
            let other_overlap = if gx >= gy { oy } else { ox };
            (gx.max(gy), if other_overlap > 0.0 { 2 } else { 1 })
        };
        let distance = 0.6;
        let within = want_sd <= distance;
        // The same configuration turned by a common angle about a far point:
        // parallelism and ties then hold only to rounding.
        let theta = 0.1 + 0.37 * case as f64;
        let turned = |p: &[Vec2]| rotate_about(p, v(5.0, -3.0), theta);
        let (ra, rb) = (turned(&a), turned(&b));
        for (pa, pb, tol) in [(&a, &b, 0.0), (&ra, &rb, 1e-13)] {
            // tol: exact on the grid; after rotation, rounding of O(10 m)
            // coordinates.
            assert_close(signed_distance(pa, pb), want_sd, tol, "grid sd");
            let c = all_contacts(pa, pb, distance);
            if !within {
                assert!(c.is_empty(), "case {case}: {c:?}");
                continue;
            }
            assert_eq!(c.len(), want_n, "case {case} tol {tol}: {a:?} {b:?} {c:?}");
            // Exactly parallel facing edges: both ends at the same gap.
            for g in &c {
                assert_close(g.gap, want_sd, tol, "grid gap");
            }
        }
        if within {
            if want_n == 1 {
                ones += 1;
            } else {
                twos += 1;
            }
        }
    }
    assert!(ones > 50 && twos > 200, "{ones} / {twos}");
}
