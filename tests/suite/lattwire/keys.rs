//! The `[fracture]` keys of the lattice model: read, and refused by key
//! and line.

use super::diamond;
use crate::common::case_path;
use floebench::formulation::parse_case;
use floebench::fracture::lattice::Mesh;
use floebench::fracture::strike::lattice_spec;
use std::path::Path;

#[test]
fn lattice_keys_are_read() {
    // The refusals are in `fracture::table::bad_fracture_tables_are_refused_with_file_line_and_key`.
    let base = std::fs::read_to_string(case_path("fracture_ram")).unwrap();
    let base = &base[..base.find("[fracture]").unwrap()];
    let ok = format!(
        "{base}[fracture]\nmodel = \"lattice\"\nrule = \"strain\"\ncritical_strain = 1e-4\ntrigger = \"always\"\nseed = 7\nspacing = 2.0\nyoung = 1e9\ndamping = 0.3\npoisson = 0.3\n"
    );
    let s = parse_case(&ok, Path::new("ok.toml")).unwrap().fracture;
    assert_eq!(
        (s.critical_strain, s.seed, s.spacing, s.young, s.damping),
        (1e-4, 7, Some(2.0), 1e9, 0.3)
    );
    assert_eq!(s.poisson, 0.3);
    assert_eq!(lattice_spec(&s, &diamond()).poisson, 0.3);
    // A Poisson ratio past the reach of central and torsion springs is refused by key.
    let bad = ok.replace("poisson = 0.3", "poisson = 0.4");
    let err = parse_case(&bad, Path::new("bad.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("poisson"), "{err}");
    // The mesh: random by default, triangular on request (its offset the
    // seed's variant), anything else refused at its line.
    assert_eq!(lattice_spec(&s, &diamond()).mesh, Mesh::Random);
    let tri = parse_case(
        &format!("{ok}mesh = \"triangular\"\n"),
        Path::new("ok.toml"),
    )
    .unwrap()
    .fracture;
    assert_eq!(
        lattice_spec(&tri, &diamond()).mesh,
        Mesh::triangular_variant(0.0, 7)
    );
    let bad = format!("{ok}mesh = \"hexagonal\"\n");
    let err = parse_case(&bad, Path::new("bad.toml"))
        .unwrap_err()
        .to_string();
    let line = bad.lines().count();
    assert!(
        err.contains("mesh") && err.contains(&format!("bad.toml:{line}")),
        "{err}"
    );
}
