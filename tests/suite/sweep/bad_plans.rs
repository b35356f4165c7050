//! The bad plans of `tests/cases/bad_plans/`: one-line errors naming file,
//! line and key, from the library and the command line.

use crate::common::{floebench, tempdir};
use floebench::sweep::plan::load_plan;
use std::path::{Path, PathBuf};

/// The bad plans of `tests/cases/bad_plans/` and the line and words of their error.
const BAD_PLANS: &[(&str, Option<usize>, &str)] = &[
    ("version_2", Some(3), "version = 2 is not supported"),
    ("missing_sweep", None, "missing [sweep] table"),
    ("unknown_key", Some(4), "unknown field `case`"),
    ("no_cases", Some(4), "[sweep] cases is empty"),
    (
        "missing_case_file",
        Some(6),
        "cases/no_such_case.toml: cannot read the case file",
    ),
    (
        "unknown_reference",
        Some(5),
        "[sweep] reference: unknown formulation `rapeir`",
    ),
    (
        "reference_ignores_contacts",
        Some(5),
        "free-drift does not apply to",
    ),
    ("unknown_measure", Some(6), "unknown measure `velocity`"),
    (
        "exact_position",
        Some(6),
        "`position` needs a reference run",
    ),
    ("no_formulation", Some(2), "no [[formulation]] table"),
    (
        "unknown_formulation",
        Some(12),
        "[[formulation]] #1: name: unknown formulation `moreua`",
    ),
    (
        "unknown_grid_key",
        Some(9),
        "[formulation.moreau] unknown key `stepp`",
    ),
    (
        "negative_step",
        Some(11),
        "[formulation.moreau] step = -0.25 s must be finite and >= 1e-6 s",
    ),
    (
        "negative_distance",
        Some(9),
        "[contact] distance = -0.01 m must be finite and >= 0",
    ),
    (
        "unquoted_dotted_key",
        Some(9),
        "a dotted grid key is written in quotes",
    ),
    (
        "free_drift_table_key",
        Some(9),
        "free-drift reads no [formulation.*] table",
    ),
    (
        "repeated_value",
        Some(9),
        "grid iterations: 2 is listed twice",
    ),
    ("case_not_in_plan", Some(9), "not one of [sweep] cases"),
    (
        "free_drift_on_contacts",
        Some(9),
        "free-drift ignores contacts",
    ),
    ("bad_name", Some(4), "must be [a-z0-9_-]+"),
    (
        "bad_reference_setting",
        Some(5),
        "[formulation.event-driven] unknown key `step`",
    ),
    (
        "tolerance_without_solver",
        Some(9),
        "tolerance is a setting of the iterative solvers",
    ),
    (
        "negative_tolerance",
        Some(11),
        "tolerance = -1e-4 must be finite",
    ),
];

fn bad_plans_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cases/bad_plans")
}

#[test]
fn bad_plans_are_refused_with_one_line_errors_naming_file_line_and_key() {
    let mut listed: Vec<String> = std::fs::read_dir(bad_plans_dir())
        .unwrap()
        .map(|e| {
            e.unwrap()
                .path()
                .file_stem()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    listed.sort();
    let mut named: Vec<String> = BAD_PLANS.iter().map(|b| b.0.to_string()).collect();
    named.sort();
    assert_eq!(listed, named, "every bad plan is tested");
    for (name, line, words) in BAD_PLANS {
        let path = bad_plans_dir().join(format!("{name}.toml"));
        let e = load_plan(&path)
            .err()
            .unwrap_or_else(|| panic!("{name} loads"));
        let msg = e.to_string();
        assert!(!msg.contains('\n'), "{name}: {msg}");
        assert_eq!(e.line, *line, "{name}: {msg}");
        assert!(
            msg.starts_with(&path.display().to_string()),
            "{name}: {msg}"
        );
        assert!(msg.contains(words), "{name}: {msg}");
        // A resolved path is written without `..` (the plan's own text, in
        // quotes, is quoted as written).
        assert!(!msg.contains("bad_plans/../"), "{name}: {msg}");
    }
    // The command line says the same, and writes nothing.
    let out = tempdir();
    let o = floebench()
        .args([
            "sweep".as_ref(),
            bad_plans_dir().join("negative_step.toml").as_os_str(),
            "-o".as_ref(),
            out.path().join("o").as_os_str(),
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: ") && stderr.contains("negative_step.toml:11:"),
        "{stderr}"
    );
    assert!(!out.path().join("o").exists());
}
