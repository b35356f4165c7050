//! The signed distance: hand-computed values, continuity across touching,
//! and a brute-force reference on random pairs.

use super::{
    assert_close, assert_vec_close, boundary_distance, random_convex, rotate_about, square,
    translate, v, HAND,
};
use floebench::contact::{separation, signed_distance, Feature};
use floebench::geometry::{sat_separation, Vec2};
use floebench::rng::SplitMix64;

/// Brute-force signed distance: all vertex–segment distances of both
/// polygons when SAT separates them, else the SAT value (minus the depth).
fn brute_signed_distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    let sat = sat_separation(a, b);
    if sat > 0.0 {
        let ab = b.iter().map(|p| boundary_distance(p, a));
        let ba = a.iter().map(|p| boundary_distance(p, b));
        ab.chain(ba).fold(f64::INFINITY, f64::min)
    } else {
        sat
    }
}

#[test]
fn signed_distance_matches_hand_computed_values() {
    let a = square(0.0, 0.0, 1.0);
    // Edge–edge, apart along x by 0.5.
    let b = translate(&a, v(1.5, 0.3));
    assert_close(signed_distance(&a, &b), 0.5, HAND, "squares along x");
    // Corner to corner: (1,1) to (1.3,1.4), distance sqrt(0.3² + 0.4²) = 0.5.
    let c = translate(&a, v(1.3, 1.4));
    assert_close(signed_distance(&a, &c), 0.5, HAND, "corner to corner");
    let s = separation(&a, &c).unwrap();
    assert_vec_close(&s.normal, &v(0.6, 0.8), HAND, "vertex-vertex normal");
    assert_eq!(s.feature.a, Feature::Vertex(2));
    assert_eq!(s.feature.b, Feature::Vertex(0));
    // Triangle vertex (0.5, 1.2) above the top edge y = 1.
    let t = vec![v(0.5, 1.2), v(1.5, 2.0), v(-0.5, 2.0)];
    assert_close(
        signed_distance(&a, &t),
        0.2,
        HAND,
        "triangle vertex over edge",
    );
    // Overlaps: depth 0.25 along x; depth 0.8 (x) < 0.9 (y).
    let d = translate(&a, v(0.75, 0.2));
    assert_close(signed_distance(&a, &d), -0.25, HAND, "overlap 0.25");
    let e = translate(&a, v(0.2, 0.1));
    assert_close(signed_distance(&a, &e), -0.8, HAND, "overlap 0.8");
    // Coincident polygons: depth = width, finite normal.
    let s = separation(&a, &a).unwrap();
    assert_close(s.distance, -1.0, HAND, "coincident");
    assert!(s.normal.iter().all(|x| x.is_finite()));
    // 45° diamond with its bottom corner 0.3 above the top edge.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let diamond = vec![
        v(0.5, 1.3),
        v(0.5 + h, 1.3 + h),
        v(0.5, 1.3 + 2.0 * h),
        v(0.5 - h, 1.3 + h),
    ];
    assert_close(signed_distance(&a, &diamond), 0.3, HAND, "diamond");
    // Symmetry.
    for b in [&b, &c, &t, &d, &e, &diamond] {
        assert_close(
            signed_distance(b, &a),
            signed_distance(&a, b),
            HAND,
            "symmetry",
        );
    }
}

#[test]
fn signed_distance_is_continuous_across_touching() {
    let a = square(0.0, 0.0, 1.0);
    for eps in [1e-3, 1e-9, 0.0, -1e-9, -1e-3] {
        let b = translate(&a, v(1.0 + eps, 0.4));
        // One rounding of 1 + eps.
        assert_close(signed_distance(&a, &b), eps, 1e-15, "edge touching");
        let c = rotate_about(&square(0.0, 0.0, 1.0), v(0.0, 0.0), 0.3);
        let c = translate(&c, v(0.5, 1.0 + eps)); // lowest corner over (0.5, 1)
        assert_close(signed_distance(&a, &c), eps, 1e-15, "vertex touching");
    }
}

#[test]
fn signed_distance_agrees_with_brute_force_on_random_pairs() {
    let mut rng = SplitMix64::new(0x5EED_F10E);
    let (mut disjoint, mut overlapping) = (0, 0);
    for _ in 0..600 {
        let a = random_convex(&mut rng, 1.0);
        let b = random_convex(&mut rng, 1.5);
        let want = brute_signed_distance(&a, &b);
        let got = signed_distance(&a, &b);
        // 1e-12 relative; the floor 1e-3 m (size/1000) covers the absolute
        // rounding of O(1 m) coordinates for near-touching pairs.
        let tol = 1e-12 * want.abs().max(1e-3);
        assert_close(got, want, tol, "random pair");
        assert_close(signed_distance(&b, &a), want, tol, "random pair swapped");
        if want > 0.0 {
            disjoint += 1;
        } else {
            overlapping += 1;
        }
    }
    assert!(
        disjoint > 150 && overlapping > 150,
        "{disjoint} / {overlapping}"
    );
}
