//! `validate`: good cases accepted with their case line, the fault of a
//! bad one named, folders taken with every bad file reported.

use super::cli;
use crate::common::{bad_case, case_path, floebench};

#[test]
fn validate_accepts_good_cases_and_names_the_fault_in_bad_ones() {
    let ok = floebench()
        .arg("validate")
        .arg(case_path("head_on"))
        .output()
        .unwrap();
    assert!(ok.status.success());
    assert!(String::from_utf8_lossy(&ok.stdout).contains("head_on: 2 floes"));
    let bad = bad_case("clockwise");
    let out = floebench().arg("validate").arg(&bad).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("clockwise.toml:14") && err.contains("[[floe]] #0"),
        "{err}"
    );
}

#[test]
fn validate_takes_folders_and_reports_every_bad_file() {
    let (ok, stdout, _) = cli(&[
        "validate".as_ref(),
        case_path("head_on").parent().unwrap().as_os_str(),
    ]);
    assert!(ok);
    assert!(stdout.contains("bouncing_floe: 1 floe ("), "{stdout}");
    assert!(stdout.contains("1 obstacle,"), "{stdout}");
    let bad = bad_case("clockwise");
    let folder = bad.parent().unwrap();
    let (ok, _, stderr) = cli(&["validate".as_ref(), folder.as_os_str()]);
    assert!(!ok);
    let errors = stderr.lines().filter(|l| l.starts_with("error: ")).count();
    let files = std::fs::read_dir(folder).unwrap().count();
    assert_eq!(errors, files, "one error per bad file:\n{stderr}");
    assert!(
        stderr.contains(&format!("{files} case files of {files} bad")),
        "{stderr}"
    );
}

#[test]
fn the_case_line_says_what_the_euler_bound_is_and_why_there_is_none() {
    // bouncing_floe has air drag and no water drag: the bound (the water
    // drag's, docs/physics.md §4.2) is none, and the line says why.
    let (ok, stdout, stderr) = cli(&["validate".as_ref(), case_path("bouncing_floe").as_os_str()]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("explicit-Euler stability bound of the drag none (no water drag)"),
        "{stdout}"
    );
    let (ok, stdout, stderr) = cli(&[
        "validate".as_ref(),
        case_path("free_drift_coriolis").as_os_str(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("explicit-Euler stability bound of the drag ") && stdout.contains(" s\n"),
        "{stdout}"
    );
}
