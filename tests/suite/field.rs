//! The `[[field]]` generator: deterministic, non-overlapping, at the target
//! concentration, within the radius and sides ranges.

use crate::common::scenario;
use floebench::geometry::{check_convex_ccw, convex_overlap, Vec2};
use floebench::model::case::FieldSpec;
use floebench::model::field::generate_field;
use floebench::model::Scenario;

fn field(seed: u64, count: usize, concentration: f64) -> Scenario {
    let text = format!(
        r#"[case]
version = 1
name = "f"
duration = 1.0
output_interval = 1.0
[contact]
restitution = 0.5
friction = 0.3
[[field]]
region = [[0.0, 0.0], [10000.0, 10000.0]]
count = {count}
concentration = {concentration}
radius = [50.0, 600.0]
sides = [5, 9]
thickness = [0.8, 1.2]
seed = {seed}
"#
    );
    scenario(&text)
}

fn world(scn: &Scenario) -> Vec<Vec<Vec2>> {
    scn.floes
        .iter()
        .map(|f| f.shape.iter().map(|p| p + f.position).collect())
        .collect()
}

#[test]
fn same_seed_same_field_other_seed_other_field() {
    let a = world(&field(42, 200, 0.6));
    let b = world(&field(42, 200, 0.6));
    let c = world(&field(43, 200, 0.6));
    assert_eq!(a, b, "same seed must give the same field, bit for bit");
    assert_ne!(a, c);
}

#[test]
fn field_floes_are_valid_disjoint_and_at_the_target_concentration() {
    for &(count, conc) in &[(200usize, 0.6), (200, 0.9), (50, 0.3)] {
        let scn = field(7, count, conc);
        assert_eq!(scn.floes.len(), count);
        let polys = world(&scn);
        for (i, p) in polys.iter().enumerate() {
            check_convex_ccw(p).unwrap_or_else(|e| panic!("floe {i}: {e}"));
            assert!((5..=9).contains(&p.len()), "floe {i} has {} sides", p.len());
            let r = scn.floes[i].radius;
            assert!(
                (50.0 * (1.0 - 1e-12)..=600.0 * (1.0 + 1e-12)).contains(&r),
                "floe {i} radius {r}"
            );
            for (x, y) in p.iter().map(|v| (v.x, v.y)) {
                assert!((0.0..=10000.0).contains(&x) && (0.0..=10000.0).contains(&y));
            }
        }
        for i in 0..polys.len() {
            for j in i + 1..polys.len() {
                assert!(
                    !convex_overlap(&polys[i], &polys[j], 0.0),
                    "floes {i} and {j} overlap"
                );
            }
        }
        let area: f64 = scn.floes.iter().map(|f| f.area).sum();
        let c = area / 1e8;
        assert!(
            (c - conc).abs() < 0.05 * conc,
            "concentration {c} vs {conc}"
        );
    }
}

#[test]
fn the_generator_never_panics_or_hangs_on_regions_the_limits_refuse() {
    // The case limits refuse these regions before the generator runs; the
    // generator itself must still end, with a field or an error (a
    // 1e300 region used to index an empty polygon, field.rs "index out of
    // bounds", and to hang on 100000 floes).
    let regions = [
        [[1000.0, 1000.0], [1e300, 1e300]],
        [[-1e308, -1e308], [1000.0, 1000.0]],
        [[-1e308, -1e308], [1e308, 1e308]],
        [[0.0, 0.0], [1e-300, 1e-300]],
        [[1e7, 1e7], [1e7 + 4e-9, 1e7 + 4e-9]],
        [[0.0, 0.0], [1e7, 1e-6]],
    ];
    for region in regions {
        for count in [1, 7, 100, 100_000, usize::MAX] {
            let spec = FieldSpec {
                region,
                count,
                concentration: 0.5,
                radius: [0.01, 1e7],
                sides: [3, 64],
                thickness: [1.0, 1.0],
                density: 917.0,
                velocity: [0.0, 0.0],
                seed: 3,
                roughness: 0.0,
            };
            if let Ok(floes) = generate_field(&spec, 0) {
                assert_eq!(floes.len(), count, "{region:?}");
                for f in &floes {
                    assert!(f.mass.is_finite() && f.mass > 0.0, "{region:?} {count}");
                }
            }
        }
    }
}
