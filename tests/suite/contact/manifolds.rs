//! The narrow phase's contact points against hand-computed values: facing
//! edges, a tilted corner, the contact distance, swapped bodies,
//! penetration, the parallel tolerance, and no NaN from degenerate input.

use super::{
    all_contacts, assert_close, assert_vec_close, by_point, rotate_about, square, translate, v,
    HAND,
};
use floebench::contact::{contacts_with, signed_distance, ContactGeom, Feature, NarrowOptions};
use floebench::geometry::area_properties;

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
