//! The refusals of the iterative solvers' settings, with their line.

use crate::common::{case_text, with_formulation_table};

#[test]
fn bad_iterative_settings_are_refused_with_their_line() {
    let base = case_text("sliding_floe");
    for (table, settings, says) in [
        ("moreau", "solver = \"nsgs\"\ntolerance = 0.0", "tolerance"),
        ("moreau", "solver = \"nsgs\"\ntolerance = nan", "tolerance"),
        ("moreau", "solver = \"nsgs\"\ntolerance = 1.0", "tolerance"),
        (
            "moreau",
            "solver = \"nsgs\"\nmax_iterations = 0",
            "max_iterations",
        ),
        (
            "moreau",
            "solver = \"nsgs\"\nmax_iterations = 100000000000",
            "max_iterations",
        ),
        (
            "moreau",
            "solver = \"nsgs\"\nrelaxation = 2.5",
            "relaxation",
        ),
        (
            "moreau",
            "solver = \"apgd\"\nrelaxation = 1.2",
            "apgd chooses",
        ),
        (
            "moreau",
            "solver = \"lcp\"\ntolerance = 1e-6",
            "not of solver = \"lcp\"",
        ),
        (
            "moreau",
            "solver = \"apgd\"\npolish = true",
            "apgd's answer solves the cone relaxation",
        ),
        (
            "moreau",
            "solver = \"lcp\"\npolish = true",
            "polish is a setting of the iterative solvers",
        ),
        (
            "moreau",
            "solver = \"nsgs\"\npolish = 1",
            "must be true or false",
        ),
        ("event-driven", "tolerance = 1e-6", "iterative solvers"),
        ("event-driven", "solver = \"gauss\"", "`nsgs` or `apgd`"),
        ("rapier", "solver = \"nsgs\"", "solver"),
    ] {
        let text = with_formulation_table(&base, table, settings);
        let path = std::env::temp_dir().join(format!("iterative_bad_{}.toml", std::process::id()));
        std::fs::write(&path, &text).unwrap();
        let err = floebench::formulation::load_case(&path)
            .err()
            .unwrap_or_else(|| panic!("{table}: `{settings}` was accepted"))
            .to_string();
        let _ = std::fs::remove_file(&path);
        assert!(err.contains(says), "{settings}: {err}");
        assert!(err.contains(".toml:"), "{settings}: no file:line in {err}");
    }
}
