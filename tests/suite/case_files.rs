//! Case files: every rule of docs/case-format.md has a bad file in
//! `tests/cases/bad/`, whose first line says which message it must produce
//! (`# expect: …`) and, where the rule points at a line, which (`# line: N`).
//! Good files (all of `cases/`) must load.

use crate::common::{bad_cases_dir, case_text, cases_dir, tempdir};
use floebench::formulation::{load_case, parse_case, tables};
use floebench::model::limits::{doc_row, Limit, CASE_LIMITS};
use std::path::Path;

#[test]
fn every_bad_case_is_rejected_with_a_message_naming_the_fault() {
    let dir = bad_cases_dir();
    let mut seen = 0;
    let mut faults = Vec::new();
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let expect = text
            .lines()
            .find_map(|l| l.strip_prefix("# expect: "))
            .unwrap_or_else(|| panic!("{} has no `# expect:` line", path.display()));
        let line = text
            .lines()
            .find_map(|l| l.strip_prefix("# line: "))
            .map(|l| l.trim().parse::<usize>().unwrap());
        seen += 1;
        let err = match load_case(&path) {
            Ok(_) => {
                faults.push(format!(
                    "{} loaded but must be rejected ({expect})",
                    path.display()
                ));
                continue;
            }
            Err(e) => e,
        };
        let msg = err.to_string();
        let fname = path.file_name().unwrap().to_string_lossy().into_owned();
        if !msg.contains(expect) {
            faults.push(format!(
                "{fname}: message `{msg}` does not contain `{expect}`"
            ));
        }
        if !msg.contains(&fname) {
            faults.push(format!("{fname}: message `{msg}` does not name the file"));
        }
        if msg.lines().count() != 1 {
            faults.push(format!("{fname}: message `{msg}` is not one line"));
        }
        if line.is_some() && err.line != line {
            faults.push(format!(
                "{fname}: message `{msg}` points at line {:?}, not {line:?}",
                err.line
            ));
        }
    }
    assert!(faults.is_empty(), "{}", faults.join("\n"));
    assert!(
        seen >= 75,
        "expected the whole set of bad files, saw {seen}"
    );
}

/// `text` with the first `from` replaced by `to` (which must be there).
fn mutated(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "`{from}` is not in the case");
    text.replacen(from, to, 1)
}

/// The error of loading `text`, which must be refused with a one-line
/// message holding `expect` and a line.
fn refused(text: &str, expect: &str) {
    let err = parse_case(text, Path::new("mutant.toml"))
        .err()
        .unwrap_or_else(|| panic!("accepted; must be refused with `{expect}`"));
    let msg = err.to_string();
    assert!(msg.starts_with("mutant.toml:"), "{msg}");
    assert!(err.line.is_some(), "{msg}");
    assert!(msg.contains(expect), "`{msg}` does not contain `{expect}`");
    assert_eq!(msg.lines().count(), 1, "{msg}");
}

#[test]
fn every_input_of_issue_17_is_refused_at_once() {
    // Field counts that overflowed, aborted or hung before the limit: each
    // refused before anything is allocated (a test that panicked, aborted or
    // hung here would fail the suite).
    let field = case_text("fields/field_10000");
    for count in [
        "9223372036854775807",
        "4294967296",
        "1000000000",
        "10000000",
    ] {
        let text = mutated(&field, "count = 10000", &format!("count = {count}"));
        refused(
            &text,
            &format!("count = {count} is above the limit of 100000 floes"),
        );
    }
    // Regions that panicked (index out of bounds) or hung.
    for (region, expect) in [
        (
            "[[1000.0, 1000.0], [1e300, 1e300]]",
            "x = 1e300 m is above the limit of 1e7 m",
        ),
        (
            "[[-1e308, -1e308], [1000.0, 1000.0]]",
            "x = -1e308 m is below the limit of -1e7 m",
        ),
    ] {
        let text = mutated(&field, "[[0.0, 0.0], [100000.0, 100000.0]]", region);
        refused(&text, expect);
        refused(&mutated(&text, "count = 10000", "count = 100000"), expect);
    }
    // Output intervals that panicked or aborted in every formulation, and
    // a duration of 2e15 outputs.
    let head_on = case_text("head_on");
    for interval in ["5e-324", "1e-12"] {
        let text = mutated(
            &head_on,
            "output_interval = 0.5",
            &format!("output_interval = {interval}"),
        );
        refused(
            &text,
            &format!("[case] output_interval = {interval} s gives"),
        );
    }
    refused(
        &mutated(&head_on, "duration = 20.0", "duration = 1e15"),
        "[case] duration = 1e15 s is above the limit of 1e8 s",
    );
    // A floe 1e308 m thick gave NaN energy in a completed run.
    let cradle = case_text("cradle_gaps");
    refused(
        &mutated(&cradle, "thickness = 1.0", "thickness = 1e308"),
        "[[floe]] #0: thickness = 1e308 m is above the limit of 1000 m",
    );
}

#[test]
fn a_case_file_above_the_size_limit_is_refused_before_it_is_parsed() {
    let limit = floebench::model::limits::FILE_BYTES.max as usize;
    let mut text = case_text("head_on");
    text.push_str(&"#".repeat(limit));
    let err = parse_case(&text, Path::new("big.toml")).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("big.toml: the case file's size = "),
        "{err}"
    );
    let dir = tempdir();
    let path = dir.path().join("big.toml");
    std::fs::write(&path, &text).unwrap();
    let err = load_case(&path).unwrap_err();
    assert!(err.to_string().contains("is above the limit of"), "{err}");
}

#[test]
fn every_bundled_case_loads() {
    let root = cases_dir();
    let mut n = 0;
    let paths = std::fs::read_dir(&root)
        .unwrap()
        .chain(std::fs::read_dir(root.join("fields")).unwrap());
    for entry in paths {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scn = load_case(&path).unwrap_or_else(|e| panic!("{e}"));
            assert!(!scn.floes.is_empty(), "{} has no floe", path.display());
            let first = std::fs::read_to_string(&path).unwrap();
            assert!(
                first.starts_with('#'),
                "{} must open with a comment saying what it shows",
                path.display()
            );
            n += 1;
        }
    }
    assert!(n >= 4);
}

#[test]
fn every_limit_is_documented_with_its_bound_and_reason() {
    let doc = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/case-format.md"),
    )
    .unwrap();
    let mut limits: Vec<Limit> = CASE_LIMITS.to_vec();
    for t in tables() {
        limits.extend(
            t.limits
                .iter()
                .filter(|l| !limits.contains(l))
                .copied()
                .collect::<Vec<_>>(),
        );
    }
    let missing: Vec<String> = limits
        .iter()
        .map(doc_row)
        .filter(|row| !doc.contains(row.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "docs/case-format.md lacks these rows of its Limits table:\n{}",
        missing.join("\n")
    );
}
