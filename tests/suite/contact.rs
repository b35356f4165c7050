//! Tests of the contact module: narrow phase against hand-computed values and
//! brute force, broad phase against all pairs, and `detect`.

use floebench::contact::{
    contacts, contacts_with, detect, separation, signed_distance, Aabb, BroadPhase, Contact,
    ContactGeom, Feature, NarrowOptions,
};
use floebench::geometry::{area_properties, check_convex_ccw, perp, rotate, sat_separation, Vec2};
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

#[test]
fn facing_edges_give_two_points_at_the_ends_of_the_overlap() {
    let a = square(0.0, 0.0, 1.0);
    let b = translate(&a, v(1.25, 0.4)); // gap 0.25, overlap y ∈ [0.4, 1]
    let c = by_point(all_contacts(&a, &b, 0.5));
    assert_eq!(c.len(), 2, "{c:?}");
    for (k, y) in [0.4, 1.0].into_iter().enumerate() {
        assert_vec_close(&c[k].point, &v(1.125, y), HAND, "point");
        assert_close(c[k].gap, 0.25, HAND, "gap");
        assert_vec_close(&c[k].normal, &v(1.0, 0.0), HAND, "normal");
        assert_vec_close(&c[k].tangent, &v(0.0, 1.0), HAND, "tangent");
    }
    // B below-left of A's bottom edge: interval x ∈ [0, 0.3], normal −y.
    let d = translate(&a, v(-0.7, -1.1));
    let c = by_point(all_contacts(&a, &d, 0.2));
    assert_eq!(c.len(), 2, "{c:?}");
    let xs: Vec<f64> = c.iter().map(|g| g.point.x).collect();
    let mut xs_sorted = xs.clone();
    xs_sorted.sort_by(f64::total_cmp);
    assert_close(xs_sorted[0], 0.0, HAND, "x lo");
    assert_close(xs_sorted[1], 0.3, HAND, "x hi");
    for g in &c {
        assert_close(g.point.y, -0.05, HAND, "midway");
        assert_close(g.gap, 0.1, HAND, "gap");
        assert_vec_close(&g.normal, &v(0.0, -1.0), HAND, "normal");
    }
}

#[test]
fn tilted_corner_on_an_edge_gives_one_point() {
    let floor = vec![v(-2.0, -1.0), v(2.0, -1.0), v(2.0, 0.0), v(-2.0, 0.0)];
    // Unit square tilted by 30°, its lowest corner at (0.3, 0.05).
    let sq = rotate_about(
        &square(0.0, 0.0, 1.0),
        v(0.0, 0.0),
        std::f64::consts::FRAC_PI_6,
    );
    let sq = translate(&sq, v(0.3, 0.05));
    let c = all_contacts(&floor, &sq, 0.1);
    assert_eq!(c.len(), 1, "{c:?}");
    assert_vec_close(&c[0].point, &v(0.3, 0.025), HAND, "point");
    assert_close(c[0].gap, 0.05, HAND, "gap");
    assert_vec_close(&c[0].normal, &v(0.0, 1.0), HAND, "normal");
    assert_eq!(c[0].feature.a, Feature::Edge(2));
    assert_eq!(c[0].feature.b, Feature::Vertex(0));
    // The same corner 0.02 deep: one point, negative gap.
    let deep = translate(&sq, v(0.0, -0.07));
    let c = all_contacts(&floor, &deep, 0.1);
    assert_eq!(c.len(), 1, "{c:?}");
    assert_close(c[0].gap, -0.02, HAND, "depth");
    assert_vec_close(&c[0].point, &v(0.3, -0.01), HAND, "point midway");
}

#[test]
fn pairs_beyond_the_contact_distance_give_nothing() {
    let a = square(0.0, 0.0, 1.0);
    let b = translate(&a, v(1.5, 0.3));
    assert!(all_contacts(&a, &b, 0.4).is_empty());
    assert!(all_contacts(&a, &b, 0.0).is_empty());
    assert_eq!(all_contacts(&a, &b, 0.5).len(), 2, "gap = distance is kept");
    let corner = translate(&a, v(1.3, 1.4)); // 0.5 apart, vertex–vertex
    assert!(all_contacts(&a, &corner, 0.49).is_empty());
    let c = all_contacts(&a, &corner, 0.51);
    assert_eq!(c.len(), 1);
    assert_vec_close(&c[0].point, &v(1.15, 1.2), HAND, "vertex-vertex midpoint");
    assert_vec_close(&c[0].normal, &v(0.6, 0.8), HAND, "vertex-vertex normal");
}

#[test]
fn swapping_the_bodies_flips_the_normal() {
    let a = square(0.0, 0.0, 1.0);
    let tri = vec![v(0.5, 1.2), v(1.5, 2.0), v(-0.5, 2.0)];
    let cases = [
        translate(&a, v(1.25, 0.4)),
        translate(&a, v(0.9, 0.3)),
        translate(&a, v(1.3, 1.4)),
        tri,
    ];
    for b in &cases {
        let ab = by_point(all_contacts(&a, b, 0.5));
        let ba = by_point(all_contacts(b, &a, 0.5));
        assert!(!ab.is_empty());
        assert_eq!(ab.len(), ba.len());
        for (p, q) in ab.iter().zip(&ba) {
            assert_vec_close(&p.normal, &-q.normal, HAND, "normal flips");
            assert_vec_close(&p.tangent, &-q.tangent, HAND, "tangent flips");
            assert_vec_close(&p.point, &q.point, HAND, "same point");
            assert_close(p.gap, q.gap, HAND, "same gap");
            assert_eq!(p.feature.a, q.feature.b);
            assert_eq!(p.feature.b, q.feature.a);
        }
        // Normal from A to B: towards B's centroid here.
        let ca = area_properties(&a).centroid;
        let cb = area_properties(b).centroid;
        assert!(ab[0].normal.dot(&(cb - ca)) > 0.0);
    }
}

#[test]
fn penetrating_squares_give_negative_gaps() {
    let a = square(0.0, 0.0, 1.0);
    let b = translate(&a, v(0.9, 0.3)); // depth 0.1 along x, overlap y ∈ [0.3, 1]
    let c = by_point(all_contacts(&a, &b, 0.0));
    assert_eq!(c.len(), 2, "{c:?}");
    for (k, y) in [0.3, 1.0].into_iter().enumerate() {
        assert_close(c[k].gap, -0.1, HAND, "gap");
        assert_vec_close(&c[k].point, &v(0.95, y), HAND, "point");
        assert_vec_close(&c[k].normal, &v(1.0, 0.0), HAND, "normal");
    }
}

#[test]
fn parallel_tolerance_is_an_option() {
    let a = square(0.0, 0.0, 1.0);
    // B turned by −1e-3 rad about its lower-left corner, 0.01 right of A's
    // right edge: its left edge leans away from A going up.
    let b = rotate_about(&square(1.01, 0.2, 1.0), v(1.01, 0.2), -1e-3);
    let c = all_contacts(&a, &b, 0.05);
    assert_eq!(c.len(), 1, "default tolerance 1e-6 rad: vertex-edge, {c:?}");
    assert_close(c[0].gap, 0.01, HAND, "gap");
    assert_eq!(c[0].feature.b, Feature::Vertex(0));
    let loose = NarrowOptions {
        parallel_tolerance: 1e-2,
        ..NarrowOptions::default()
    };
    let run = |distance: f64| {
        let mut out = Vec::new();
        contacts_with(&a, &b, distance, &loose, &mut out);
        by_point(out)
    };
    let out = run(0.05);
    assert_eq!(out.len(), 2, "{out:?}");
    // Lower end: B's corner; upper end: clipped at A's corner y = 1, where
    // B's left edge is 0.8 tan(1e-3) further right.
    let upper_gap = 0.01 + 0.8 * 1e-3_f64.tan();
    assert_close(out[0].gap, 0.01, HAND, "lower gap");
    assert_vec_close(&out[0].point, &v(1.005, 0.2), HAND, "lower point");
    assert_close(out[1].gap, upper_gap, HAND, "upper gap");
    assert_vec_close(
        &out[1].point,
        &v(1.0 + 0.5 * upper_gap, 1.0),
        HAND,
        "upper point",
    );
    assert_eq!(
        out[1].feature.a,
        Feature::Vertex(2),
        "clipped at A's corner"
    );
    assert_eq!(out[1].feature.b, Feature::Edge(3), "on B's left edge");
    // The contact distance filters points one by one.
    assert!(run(0.0095).is_empty(), "signed distance 0.01 > 0.0095");
    assert_eq!(run(0.0101).len(), 1, "upper gap 0.0108 > 0.0101");
    assert_eq!(run(0.011).len(), 2);
}

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

#[test]
fn degenerate_input_gives_no_nan() {
    let a = square(0.0, 0.0, 1.0);
    let finite = |c: &[ContactGeom]| {
        c.iter().all(|g| {
            g.point.iter().chain(g.normal.iter()).all(|x| x.is_finite()) && g.gap.is_finite()
        })
    };
    // Coincident polygons.
    let c = all_contacts(&a, &a, 0.0);
    assert!(!c.is_empty() && finite(&c));
    // A repeated vertex (zero-length edge).
    let rep = vec![
        v(2.0, 0.0),
        v(3.0, 0.0),
        v(3.0, 0.0),
        v(3.0, 1.0),
        v(2.0, 1.0),
    ];
    assert_close(signed_distance(&a, &rep), 1.0, HAND, "repeated vertex");
    let c = all_contacts(&a, &rep, 1.0);
    assert!(!c.is_empty() && finite(&c));
    // Point polygons, coincident and apart.
    let p = vec![v(0.5, 0.5)];
    assert_close(signed_distance(&a, &p), -0.5, HAND, "point inside");
    assert!(finite(&all_contacts(&p, &p, 0.0)));
    assert_eq!(all_contacts(&p, &p, 0.0).len(), 1);
    let q = vec![v(3.5, 4.5)];
    assert_close(signed_distance(&p, &q), 5.0, HAND, "point to point");
    // Empty polygon: infinitely far, no contact.
    assert_eq!(signed_distance(&a, &[]), f64::INFINITY);
    assert!(all_contacts(&a, &[], 1.0).is_empty());
}

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
