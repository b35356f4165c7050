//! Broken runs compared and written: the divergence by each initial floe's
//! material, the floe size distribution of `compare`, and the floes and
//! fractures files of `run`.

use super::rel;
use crate::common::{case_path, floebench, run, tempdir};
use floebench::geometry::{area_properties, Vec2};

#[test]
fn runs_that_break_differently_are_compared_by_each_initial_floes_material() {
    // The same ram, broken and whole: the two halves leave together at
    // e v0, so the material of floe 0 follows the whole floe's path.
    let broken = crate::common::load("fracture_ram");
    let mut whole = broken.clone();
    whole.fracture.model = floebench::model::fracture::FractureModel::None;
    for name in ["event-driven", "moreau"] {
        let a = run(&broken, name);
        let b = run(&whole, name);
        assert_eq!((a.fractures.len(), b.fractures.len()), (1, 0), "{name}");
        let d = floebench::analysis::divergence::divergence(&broken, &a, &b, 0.1)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            d.samples.len(),
            b.energy.len(),
            "{name}: every output compared"
        );
        assert!(
            d.max_rms_position_rel <= 1e-12,
            "{name}: {}",
            d.max_rms_position_rel
        );
        assert!(d.max_angle_rad <= 1e-12, "{name}: {}", d.max_angle_rad);
        // The material rows of a run that did not break are its rows.
        assert_eq!(
            floebench::analysis::divergence::material_rows(&b),
            b.trajectory
        );
    }
}

#[test]
fn compare_writes_the_floe_size_distribution_of_a_fracture_case_and_none_elsewhere() {
    let dir = tempdir();
    let out = dir.path().join("reports");
    let o = floebench()
        .arg("compare")
        .arg(case_path("fracture_ram"))
        .arg(case_path("head_on"))
        .args(["--formulations", "event-driven,moreau", "--quiet", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("fracture_ram/floe_sizes.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("formulation,when,area_m2,count_at_least")
    );
    let rows: Vec<(String, String, f64, usize)> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 4, "{l}");
            (
                f[0].to_string(),
                f[1].to_string(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect();
    // The start: the one initial floe of 100 m².
    let start: Vec<_> = rows.iter().filter(|r| r.1 == "start").collect();
    assert_eq!(start.len(), 1, "{rows:?}");
    assert!(start[0].0.is_empty() && rel(start[0].2, 100.0) < 1e-12 && start[0].3 == 1);
    // The end of each run: two pieces of 50 m² (one size), the count at
    // the smallest area the number of floes alive.
    for f in ["event-driven", "moreau"] {
        let end: Vec<_> = rows.iter().filter(|r| r.0 == f && r.1 == "end").collect();
        assert_eq!(end.len(), 1, "{f}: {rows:?}");
        assert!(rel(end[0].2, 50.0) < 1e-9 && end[0].3 == 2, "{f}: {end:?}");
    }
    for ext in ["png", "svg"] {
        let p = out.join(format!("fracture_ram/floe_sizes.{ext}"));
        assert!(
            std::fs::metadata(&p).is_ok_and(|m| m.len() > 1000),
            "{}",
            p.display()
        );
    }
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert!(md.contains("fracture_ram/floe_sizes.png") && md.contains("**floe_sizes**"));
    // A case without a [fracture] table has none of it.
    for file in ["floe_sizes.csv", "floe_sizes.png", "floe_sizes.svg"] {
        assert!(!out.join("head_on").join(file).exists(), "head_on/{file}");
    }
    assert!(!md.contains("head_on/floe_sizes"));
}

#[test]
fn run_writes_the_floes_and_fractures_of_a_broken_run() {
    // `floebench run fracture_ram`: floes.json lists the parent (ended at
    // the fracture) and its two pieces (born then, parent 0), each outline
    // about its own centre of mass with the recorded area and mass; one row
    // of fractures.csv names them.
    let dir = tempdir();
    let out = dir.path().join("out");
    let o = floebench()
        .arg("run")
        .arg(case_path("fracture_ram"))
        .args(["--quiet", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("fractures.csv")).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows.len(), 2, "{text}");
    let f: Vec<&str> = rows[1].split(',').collect();
    assert_eq!((f[1], f[2], f[3]), ("0", "1;2", "energy"), "{text}");
    let t: f64 = f[0].parse().unwrap();
    let floes: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("floes.json")).unwrap()).unwrap();
    let floes = floes.as_array().unwrap();
    assert_eq!(floes.len(), 3);
    assert!(floes[0]["parent"].is_null() && floes[0]["t_end"].as_f64() == Some(t));
    for (id, g) in floes.iter().enumerate() {
        assert_eq!(g["id"], id);
        let poly: Vec<Vec2> = g["polygon"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| Vec2::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
            .collect();
        let props = area_properties(&poly);
        let area = g["area"].as_f64().unwrap();
        assert!(
            rel(props.area, area) <= 1e-12,
            "{id}: {} vs {area}",
            props.area
        );
        assert!(
            props.centroid.norm() <= 1e-12 * area.sqrt(),
            "{id}: {:?}",
            props.centroid
        );
        let mass = g["mass"].as_f64().unwrap();
        let h = g["thickness"].as_f64().unwrap();
        assert!(rel(mass, 917.0 * h * area) <= 1e-12, "{id}: {mass}");
        if id > 0 {
            assert_eq!(g["parent"], 0);
            assert_eq!(g["t_birth"].as_f64(), Some(t));
            assert!(g["t_end"].is_null());
            assert!(rel(area, 50.0) <= 1e-12, "{id}: {area}");
        }
    }
}
