//! The `[fracture]` table: refused with file, line and key, and
//! `model = "none"` is no fracture.

use super::RAM;
use crate::common::{run, scenario};
use floebench::formulation::parse_case;
use std::path::Path;

#[test]
fn bad_fracture_tables_are_refused_with_file_line_and_key() {
    let base = RAM.replace("SPEED", "0.01");
    for (table, line, key) in [
        ("model = \"chord\"", 2, "model"),
        ("model = \"energy\"\ntoughness = -1.0", 3, "toughness"),
        ("model = \"stress\"\nyield = \"tresca\"", 3, "yield"),
        ("model = \"energy\"\nmin_area = 1e20", 3, "min_area"),
        ("model = \"stress\"\nwindow = 0.0", 3, "window"),
        ("model = \"energy\"\ntoughnes = 2.0", 3, "toughnes"),
        ("model = 3", 2, "model"),
        ("model = \"lattice\"\nrule = \"strain\"", 3, "rule"),
        ("model = \"lattice\"\nrule = \"griffith\"", 3, "rule"),
        ("model = \"lattice\"\ntrigger = \"never\"", 3, "trigger"),
        ("model = \"lattice\"\nyoung = 0.0", 3, "young"),
        ("model = \"lattice\"\ndamping = -0.5", 3, "damping"),
        ("model = \"lattice\"\nspacing = 0.0", 3, "spacing"),
        (
            "model = \"lattice\"\ncritical_strain = 2.0",
            3,
            "critical_strain",
        ),
        ("model = \"lattice\"\nrule = \"cohesive\"", 3, "rule"),
        ("model = \"lattice\"\nstrength = 3e5", 3, "strength"),
        (
            "model = \"lattice\"\nrule = \"cohesive\"\nstrength = 0.0",
            4,
            "strength",
        ),
        (
            "model = \"lattice\"\nrule = \"cohesive\"\nstrength = 3e5\nspacing = 0.8",
            5,
            "spacing",
        ),
        (
            "model = \"lattice\"\nrule = \"cohesive\"\nstrength = 3e5",
            4,
            "strength",
        ),
        ("model = \"lattice\"\nseed = -1", 3, "seed"),
        ("model = \"lattice\"\nseed = 1.5", 3, "seed"),
    ] {
        let text = format!("{base}\n[fracture]\n{table}\n");
        let at = base.lines().count() + 1 + line;
        let err = match parse_case(&text, Path::new("bad.toml")) {
            Ok(_) => panic!("accepted: {table}"),
            Err(e) => e.to_string(),
        };
        assert!(
            err.starts_with(&format!("bad.toml:{at}: [fracture] ")) && err.contains(key),
            "{table}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

#[test]
fn model_none_gives_the_same_run_as_no_fracture_table() {
    let base = RAM.replace("SPEED", "0.05");
    let none = format!("{base}\n[fracture]\nmodel = \"none\"\ntoughness = 1.0\n");
    for name in ["event-driven", "moreau", "moreau-cone", "rapier"] {
        let a = run(&scenario(&base), name);
        let b = run(&scenario(&none), name);
        assert_eq!(a.trajectory, b.trajectory, "{name}");
        assert_eq!(a.energy, b.energy, "{name}");
        assert!(b.fractures.is_empty() && b.floes.len() == 1, "{name}");
    }
}
