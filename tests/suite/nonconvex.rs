//! Non-convex floes (issue 16, item 2): exact mass properties of an
//! L-shape, refusal of self-intersecting outlines, the decomposition into
//! convex parts, detection between parts of different bodies only, the
//! L-shaped corner case in every formulation, convex bodies unchanged, and
//! the `[[field]]` roughness.

use crate::common::{load, run, scenario};
use floebench::analysis::check::{check_run, claimed_failures};
use floebench::contact::{
    compound_signed_distance, detect_compound, detect_with, BroadPhase, Compound, Contact, Feature,
    NarrowOptions,
};
use floebench::formulation;
use floebench::geometry::decompose::{convex_parts, is_internal_edge};
use floebench::geometry::{
    area_properties, check_simple_ccw, is_strictly_convex, point_outline_signed_distance,
    point_polygon_signed_distance, sat_separation, PolygonError, Vec2,
};
use floebench::model::{FloeOrigin, Scenario};
use floebench::rng::SplitMix64;
use floebench::state::{detect_contacts, System};

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

/// An L of outer size `a` and arm width `t` (m), corner at `o`.
fn l_shape(a: f64, t: f64, o: Vec2) -> Vec<Vec2> {
    [v(0., 0.), v(a, 0.), v(a, t), v(t, t), v(t, a), v(0., a)]
        .iter()
        .map(|p| p + o)
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

#[test]
fn l_shape_mass_properties_match_the_closed_form() {
    for &(a, t, o) in &[
        (20.0, 10.0, v(0., 0.)),
        (7.0, 2.0, v(-3.0, 5.0)),
        (1000.0, 150.0, v(1e4, -2e4)),
    ] {
        // Two rectangles: [0, a] × [0, t] and [0, t] × [t, a].
        let (a1, c1) = (a * t, v(a / 2.0, t / 2.0));
        let (a2, c2) = (t * (a - t), v(t / 2.0, (a + t) / 2.0));
        let area = a1 + a2;
        let c = (c1 * a1 + c2 * a2) / area;
        let j1 = a1 * (a * a + t * t) / 12.0 + a1 * (c1 - c).norm_squared();
        let j2 = a2 * (t * t + (a - t) * (a - t)) / 12.0 + a2 * (c2 - c).norm_squared();
        let p = area_properties(&l_shape(a, t, o));
        assert!(rel(p.area, area) < 1e-12, "area {} vs {area}", p.area);
        let dc = (p.centroid - (c + o)).norm() / a;
        assert!(dc < 1e-12, "centroid {:?} vs {:?}", p.centroid, c + o);
        assert!(
            rel(p.polar_moment, j1 + j2) < 1e-12,
            "J {} vs {}",
            p.polar_moment,
            j1 + j2
        );
    }
    // Through the case loader: mass and inertia of the floe.
    let scn = load("l_shaped_corner");
    let f = &scn.floes[0];
    let (area, j) = (300.0, {
        let c = v(
            (200.0 * 10.0 + 100.0 * 5.0) / 300.0,
            (200.0 * 5.0 + 100.0 * 15.0) / 300.0,
        );
        200.0 * (400.0 + 100.0) / 12.0
            + 200.0 * (v(10., 5.) - c).norm_squared()
            + 100.0 * (100.0 + 100.0) / 12.0
            + 100.0 * (v(5., 15.) - c).norm_squared()
    });
    assert!(rel(f.area, area) < 1e-12);
    assert!(rel(f.mass, 917.0 * area) < 1e-12);
    assert!(
        rel(f.inertia, 917.0 * j) < 1e-12,
        "{} vs {}",
        f.inertia,
        917.0 * j
    );
    assert_eq!(f.parts.len(), 2, "an L is two convex parts: {:?}", f.parts);
}

#[test]
fn self_intersecting_outlines_are_refused_naming_the_crossing_edges() {
    let bow = [v(0., 0.), v(1., 1.), v(1., 0.), v(0., 1.)];
    assert_eq!(
        check_simple_ccw(&bow),
        Err(PolygonError::SelfIntersecting(0, 1, 2, 3))
    );
    // A pentagram turns left at every vertex and winds twice.
    let star: Vec<Vec2> = (0..5)
        .map(|k| {
            let a = std::f64::consts::TAU * (2 * k) as f64 / 5.0;
            v(a.cos(), a.sin())
        })
        .collect();
    assert!(matches!(
        check_simple_ccw(&star),
        Err(PolygonError::SelfIntersecting(..))
    ));
    // A vertex touching a non-adjacent edge is not simple either.
    let touch = [v(0., 0.), v(4., 0.), v(4., 4.), v(2., 0.0), v(0., 4.)];
    assert!(matches!(
        check_simple_ccw(&touch),
        Err(PolygonError::SelfIntersecting(..))
    ));
    // Valid non-convex outlines, and the other rules kept.
    assert_eq!(check_simple_ccw(&l_shape(2.0, 1.0, v(0., 0.))), Ok(()));
    let cw: Vec<Vec2> = l_shape(2.0, 1.0, v(0., 0.)).into_iter().rev().collect();
    assert_eq!(check_simple_ccw(&cw), Err(PolygonError::Clockwise));
    let aligned = [v(0., 0.), v(1., 0.), v(2., 0.), v(1., 1.)];
    assert_eq!(
        check_simple_ccw(&aligned),
        Err(PolygonError::Aligned(0, 1, 2))
    );
    let rep = [v(0., 0.), v(1., 0.), v(1., 0.), v(0., 1.)];
    assert_eq!(
        check_simple_ccw(&rep),
        Err(PolygonError::RepeatedVertex(1, 2))
    );
}

/// A seeded random simple polygon: `n` vertices at increasing angles about
/// the origin, radii in `[0.3, 1]` (star-shaped, so simple), `scale` m.
fn random_star(rng: &mut SplitMix64, n: usize, scale: f64) -> Vec<Vec2> {
    let mut angles: Vec<f64> = (0..n)
        .map(|_| rng.range(0.0, std::f64::consts::TAU))
        .collect();
    angles.sort_by(f64::total_cmp);
    angles
        .iter()
        .map(|&a| v(a.cos(), a.sin()) * scale * rng.range(0.3, 1.0))
        .collect()
}

/// Asserts that `parts` tile `poly` exactly: areas sum to its area (1e-12
/// relative), every part strictly convex and counter-clockwise, no two
/// parts overlap, every outline edge in exactly one part and every
/// internal edge in exactly two (once each way).
fn assert_tiles(poly: &[Vec2], parts: &[Vec<usize>], what: &str) {
    let n = poly.len();
    let whole = area_properties(poly).area;
    let pts: Vec<Vec<Vec2>> = parts
        .iter()
        .map(|p| p.iter().map(|&k| poly[k]).collect())
        .collect();
    let sum: f64 = pts.iter().map(|p| area_properties(p).area).sum();
    assert!(rel(sum, whole) < 1e-12, "{what}: parts {sum} vs {whole}");
    let size = poly.iter().map(|p| p.norm()).fold(0.0, f64::max);
    for (k, p) in pts.iter().enumerate() {
        assert!(is_strictly_convex(p), "{what}: part {k} not convex");
        assert!(area_properties(p).area > 0.0, "{what}: part {k} not CCW");
        for q in &pts[k + 1..] {
            assert!(
                sat_separation(p, q) >= -1e-12 * size,
                "{what}: parts overlap"
            );
        }
    }
    let mut outline = vec![0usize; n];
    let mut internal: Vec<(usize, usize)> = Vec::new();
    for p in parts {
        for k in 0..p.len() {
            if is_internal_edge(p, k, n) {
                internal.push((p[k], p[(k + 1) % p.len()]));
            } else {
                outline[p[k]] += 1;
            }
        }
    }
    assert!(outline.iter().all(|&c| c == 1), "{what}: {outline:?}");
    for &(i, j) in &internal {
        assert!(
            internal.contains(&(j, i)),
            "{what}: diagonal {i}-{j} one-sided"
        );
    }
}

#[test]
fn the_decomposition_tiles_the_polygon_with_convex_parts() {
    let l = l_shape(20.0, 10.0, v(0., 0.));
    let parts = convex_parts(&l).unwrap();
    assert_tiles(&l, &parts, "L");
    assert_eq!(parts.len(), 2);
    let u = [
        v(0., 0.),
        v(3., 0.),
        v(3., 3.),
        v(2., 3.),
        v(2., 1.),
        v(1., 1.),
        v(1., 3.),
        v(0., 3.),
    ];
    let parts = convex_parts(&u).unwrap();
    assert_tiles(&u, &parts, "U");
    assert_eq!(parts.len(), 3, "a U is three convex parts: {parts:?}");
    let mut rng = SplitMix64::new(16);
    for case in 0..300 {
        let n = 4 + case % 40;
        let poly = random_star(&mut rng, n, 10.0);
        if check_simple_ccw(&poly).is_err() {
            continue;
        }
        let parts = convex_parts(&poly).unwrap_or_else(|| panic!("star {case}"));
        assert_tiles(&poly, &parts, &format!("star {case}"));
        // Each reflex vertex needs a diagonal; there are at most 4× the
        // fewest parts, and the fewest is at least 1 + reflex/2 … so at
        // most n − 2 parts (the triangles) in any case.
        assert!(parts.len() <= n - 2);
    }
    // A convex polygon is its own part.
    let sq = [v(0., 0.), v(1., 0.), v(1., 1.), v(0., 1.)];
    assert_eq!(convex_parts(&sq).unwrap(), vec![vec![0, 1, 2, 3]]);
}

const L_AND_SQUARE: &str = r#"[case]
version = 1
name = "l"
duration = 1.0
output_interval = 1.0
[contact]
restitution = 0.5
friction = 0.3
[[floe]]
polygon = [[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [10.0, 10.0], [10.0, 20.0], [0.0, 20.0]]
thickness = 1.0
[[floe]]
polygon = [[SX0, SY0], [SX1, SY0], [SX1, SY1], [SX0, SY1]]
thickness = 1.0
"#;

/// The L floe and a square `[x0, x1] × [y0, y1]`.
fn l_and_square(x0: f64, y0: f64, x1: f64, y1: f64) -> Scenario {
    let text = L_AND_SQUARE
        .replace("SX0", &format!("{x0:?}"))
        .replace("SY0", &format!("{y0:?}"))
        .replace("SX1", &format!("{x1:?}"))
        .replace("SY1", &format!("{y1:?}"));
    scenario(&text)
}

fn contacts_at_start(scn: &Scenario, distance: f64) -> Vec<Contact> {
    let sys = System::initial(scn);
    let mut out = Vec::new();
    detect_contacts(scn, &sys.bodies, distance, &mut BroadPhase::new(), &mut out);
    out
}

#[test]
fn no_contact_between_the_parts_of_one_floe() {
    // The L alone, with a contact distance larger than the floe: its two
    // parts touch along their diagonal and overlap in their boxes, yet no
    // contact.
    let scn = l_and_square(100.0, 100.0, 101.0, 101.0);
    let c = contacts_at_start(&scn, 50.0);
    assert!(c.iter().all(|c| c.a != c.b), "{c:#?}");
    assert!(
        c.iter()
            .all(|c| (c.a, c.b) == (0, 1) || (c.a, c.b) == (1, 0)),
        "{c:#?}"
    );
    // A square resting in the notch, touching both faces of the concave
    // corner: the contacts are on the two faces (normals ±x, ±y), none on
    // the internal diagonal, features on the outline.
    let scn = l_and_square(10.0, 10.0, 14.0, 14.0);
    let c = contacts_at_start(&scn, 1e-6);
    assert!(!c.is_empty());
    for k in &c {
        let n = k.geom.normal;
        assert!(
            n.x.abs() < 1e-12 || n.y.abs() < 1e-12,
            "normal off the faces: {k:#?}"
        );
        assert!(k.geom.gap.abs() < 1e-9, "{k:#?}");
        let l_feature = if k.a == 0 {
            k.geom.feature.a
        } else {
            k.geom.feature.b
        };
        match l_feature {
            Feature::Edge(e) => assert!(e == 2 || e == 3, "L feature {l_feature:?}"),
            Feature::Vertex(p) => assert_eq!(p, 3, "L feature {l_feature:?}"),
        }
    }
    // Both faces carry contacts, and no two contacts repeat.
    assert!(c.iter().any(|k| k.geom.normal.x.abs() > 0.5));
    assert!(c.iter().any(|k| k.geom.normal.y.abs() > 0.5));
    for (i, a) in c.iter().enumerate() {
        assert!(c[i + 1..].iter().all(|b| b.key() != a.key()), "{c:#?}");
    }
    // A square hovering over the notch near the reflex corner, 1 cm above
    // the horizontal face: one pair of contacts, on that face only.
    let scn = l_and_square(10.5, 10.01, 14.0, 14.0);
    let c = contacts_at_start(&scn, 0.05);
    assert!(!c.is_empty());
    for k in &c {
        assert!((k.geom.normal.y.abs() - 1.0).abs() < 1e-12, "{k:#?}");
        assert!((k.geom.gap - 0.01).abs() < 1e-9, "{k:#?}");
    }
}

#[test]
fn internal_edges_are_never_contact_faces() {
    // The L splits along its diagonal from (0, 0) to the reflex corner
    // (10, 10): parts [0, 1, 2, 3] and [0, 3, 4, 5].
    let scn = l_and_square(100.0, 100.0, 101.0, 101.0);
    assert_eq!(scn.floes[0].parts, vec![vec![0, 1, 2, 3], vec![0, 3, 4, 5]]);
    // A square 1 cm left of the L's left face, its lower corner 2 cm above
    // the diagonal's end (0, 0): the lower part is 2.1 cm away through its
    // diagonal (hidden), and 2.2 cm from its vertex (0, 0) in a direction
    // from inside the L (hidden too); only the left face touches it.
    // Then 5 mm above: the lower part's closest feature is the vertex
    // (0, 0), approached from inside the L's outline.
    for y0 in [0.02, 0.005] {
        let scn = l_and_square(-1.0, y0, -0.01, 1.0);
        let c = contacts_at_start(&scn, 0.05);
        assert_eq!(c.len(), 2, "y0 = {y0}: {c:#?}");
        for k in &c {
            assert_eq!((k.a, k.b), (0, 1));
            assert!((k.geom.normal - v(-1.0, 0.0)).norm() < 1e-12, "{k:#?}");
            assert!((k.geom.gap - 0.01).abs() < 1e-12, "{k:#?}");
            assert_eq!(k.geom.feature.a, Feature::Edge(5), "{k:#?}");
        }
    }
    // A square off the corner (0, 0) along its bisector: both parts have
    // that vertex; one contact, not two.
    let scn = l_and_square(-1.0, -1.0, -0.01, -0.01);
    let c = contacts_at_start(&scn, 0.05);
    assert_eq!(c.len(), 1, "{c:#?}");
    assert_eq!(c[0].geom.feature.a, Feature::Vertex(0));
    assert!((c[0].geom.gap - 0.01 * 2f64.sqrt()).abs() < 1e-12);
}

#[test]
fn convex_bodies_are_detected_exactly_as_before() {
    let mut rng = SplitMix64::new(7);
    let mut bodies: Vec<Vec<Vec2>> = Vec::new();
    for k in 0..40 {
        let c = v(rng.range(0.0, 40.0), rng.range(0.0, 40.0));
        let n = 3 + k % 6;
        let r = rng.range(2.0, 4.0);
        let poly: Vec<Vec2> = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * (i as f64 + rng.range(0.0, 0.5)) / n as f64;
                c + v(a.cos(), a.sin()) * r
            })
            .collect();
        bodies.push(poly);
    }
    let parts: Vec<Vec<Vec<usize>>> = bodies
        .iter()
        .map(|p| convex_parts(p).expect("convex"))
        .collect();
    assert!(parts.iter().all(|p| p.len() == 1));
    let fixed: Vec<bool> = (0..bodies.len()).map(|i| i % 7 == 0).collect();
    let refs: Vec<&[Vec2]> = bodies.iter().map(|p| p.as_slice()).collect();
    let comps: Vec<Compound> = bodies
        .iter()
        .zip(&parts)
        .map(|(b, p)| Compound {
            outline: b,
            parts: p,
        })
        .collect();
    let opts = NarrowOptions::default();
    let (mut old, mut new) = (Vec::new(), Vec::new());
    detect_with(&refs, &fixed, 0.3, &opts, &mut BroadPhase::new(), &mut old);
    detect_compound(&comps, &fixed, 0.3, &opts, &mut BroadPhase::new(), &mut new);
    assert!(!old.is_empty());
    assert_eq!(old, new, "bit for bit");
    for i in 0..bodies.len() {
        for j in 0..bodies.len() {
            let a = floebench::contact::signed_distance(&bodies[i], &bodies[j]);
            let b = compound_signed_distance(&comps[i], &comps[j]);
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }
}

#[test]
fn the_outline_distance_is_signed_and_agrees_with_the_convex_one() {
    let l = l_shape(20.0, 10.0, v(0., 0.));
    // Inside the lower arm, 2 m from the bottom face.
    assert!((point_outline_signed_distance(&v(15.0, 2.0), &l) + 2.0).abs() < 1e-12);
    // In the notch: outside, 1 m from both faces.
    let d = point_outline_signed_distance(&v(11.0, 11.0), &l);
    assert!((d - 1.0).abs() < 1e-12, "{d}");
    // Beyond the reflex corner, inside: the corner is the nearest point.
    let d = point_outline_signed_distance(&v(9.0, 9.0), &l);
    assert!((d + 2f64.sqrt()).abs() < 1e-12, "{d}");
    let mut rng = SplitMix64::new(3);
    let sq = [v(0., 0.), v(3., 0.), v(3., 2.), v(0., 2.)];
    for _ in 0..1000 {
        let p = v(rng.range(-2.0, 5.0), rng.range(-2.0, 4.0));
        let (a, b) = (
            point_outline_signed_distance(&p, &sq),
            point_polygon_signed_distance(&p, &sq),
        );
        assert!((a - b).abs() < 1e-12, "{p:?}: {a} vs {b}");
    }
}

#[test]
fn the_l_shaped_corner_hit_conserves_momentum_in_every_formulation() {
    let scn = load("l_shaped_corner");
    assert!(!scn.floes[0].is_convex() && scn.floes[1].is_convex());
    let m = scn.floes[1].mass;
    let p0 = scn.floes[1].velocity * m;
    for f in formulation::REGISTRY {
        if !f.resolves_contacts {
            continue;
        }
        let name = f.name;
        let r = run(&scn, name);
        let rows = check_run(&scn, &r);
        let momentum = rows
            .iter()
            .find(|o| o.check == "momentum")
            .unwrap_or_else(|| panic!("{name}: no momentum check"));
        assert!(momentum.pass, "{name}: {momentum:#?}");
        assert_eq!(claimed_failures(&rows), 0, "{name}: {rows:#?}");
        // The square was struck: its velocity changed, the L moves.
        let end = &r.final_state.bodies;
        assert!(
            (end[1].velocity * m - p0).norm() > 0.1 * p0.norm(),
            "{name}: no impact? {end:?}"
        );
        let p = end[0].velocity * scn.floes[0].mass + end[1].velocity * m;
        assert!(
            (p - p0).norm() <= 1e-9 * p0.norm(),
            "{name}: momentum {p:?} vs {p0:?}"
        );
    }
}

#[test]
fn rough_fields_are_simple_disjoint_non_convex_and_at_their_concentration() {
    let text = |roughness: &str| {
        format!(
            r#"[case]
version = 1
name = "f"
duration = 1.0
output_interval = 1.0
[contact]
restitution = 0.5
friction = 0.3
[[field]]
region = [[0.0, 0.0], [2000.0, 2000.0]]
count = 60
concentration = 0.6
radius = [20.0, 400.0]
sides = [5, 9]
thickness = [0.8, 1.2]
seed = 5
{roughness}
"#
        )
    };
    let smooth = scenario(&text(""));
    let zero = scenario(&text("roughness = 0.0"));
    let rough = scenario(&text("roughness = 0.3"));
    let shapes = |s: &Scenario| -> Vec<Vec<Vec2>> {
        s.floes
            .iter()
            .map(|f| f.shape.iter().map(|p| p + f.position).collect())
            .collect()
    };
    assert_eq!(shapes(&smooth), shapes(&zero), "roughness 0 is bit for bit");
    assert!(smooth.floes.iter().all(|f| f.is_convex()));
    let polys = shapes(&rough);
    let mut concave = 0;
    for (i, p) in polys.iter().enumerate() {
        check_simple_ccw(p).unwrap_or_else(|e| panic!("floe {i}: {e}"));
        assert!(
            (10..=18).contains(&p.len()),
            "floe {i}: {} vertices",
            p.len()
        );
        assert!(matches!(rough.floes[i].origin, FloeOrigin::Field { .. }));
        assert_tiles(p, &rough.floes[i].parts, &format!("floe {i}"));
        concave += usize::from(!rough.floes[i].is_convex());
    }
    assert_eq!(concave, polys.len(), "every notched floe is non-convex");
    let comps: Vec<Compound> = polys
        .iter()
        .zip(&rough.floes)
        .map(|(p, f)| Compound {
            outline: p,
            parts: &f.parts,
        })
        .collect();
    for i in 0..comps.len() {
        for j in i + 1..comps.len() {
            assert!(
                compound_signed_distance(&comps[i], &comps[j]) >= 0.0,
                "floes {i} and {j} overlap"
            );
        }
    }
    let area: f64 = rough.floes.iter().map(|f| f.area).sum();
    let c = area / 4e6;
    assert!((c - 0.6).abs() < 0.05 * 0.6, "concentration {c}");
}
