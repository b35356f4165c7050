//! Case files: every rule of docs/case-format.md has a bad file in
//! `tests/cases/bad/`, whose first line says which message it must produce
//! (`# expect: …`) and, where the rule points at a line, which (`# line: N`).
//! Good files (all of `cases/`) must load.

use crate::common::{bad_cases_dir, cases_dir};
use floebench::formulation::load_case;

#[test]
fn every_bad_case_is_rejected_with_a_message_naming_the_fault() {
    let dir = bad_cases_dir();
    let mut seen = 0;
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
        let err = match load_case(&path) {
            Ok(_) => panic!("{} loaded but must be rejected ({expect})", path.display()),
            Err(e) => e,
        };
        let msg = err.to_string();
        assert!(
            msg.contains(expect),
            "{}: message `{msg}` does not contain `{expect}`",
            path.display()
        );
        let fname = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            msg.contains(&fname),
            "{}: message `{msg}` does not name the file",
            path.display()
        );
        if let Some(l) = line {
            assert_eq!(
                err.line,
                Some(l),
                "{}: message `{msg}` points at the wrong line",
                path.display()
            );
        }
        seen += 1;
    }
    assert!(
        seen >= 25,
        "expected the whole set of bad files, saw {seen}"
    );
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
