//! `check` and `compare`: the table of `check` and its exit status, and
//! the case folders `compare` replaces, keeps and clears.

use super::cli;
use crate::common::{bad_case, case_path, floebench, tempdir};

#[test]
fn check_prints_the_table_and_exits_non_zero_only_on_claimed_failures() {
    // rapier fails head-on only as known findings: exit 0, `fail (known)` shown.
    let out = floebench()
        .arg("check")
        .arg(case_path("head_on"))
        .args(["--formulations", "event-driven,rapier"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table.contains("head_on_v1") && table.contains("fail (known)"),
        "{table}"
    );
    assert!(table.contains("0 FAIL (claimed)"), "{table}");
    // An unknown formulation or a bad case file is an error naming it.
    let out = floebench()
        .arg("check")
        .arg(case_path("head_on"))
        .args(["--formulations", "nope"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("nope"));
    let bad = bad_case("clockwise");
    let out = floebench().arg("check").arg(&bad).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("clockwise.toml:14"));
}

#[test]
fn compare_replaces_only_its_own_case_folders_and_clears_its_stale_ones() {
    let dir = tempdir();
    // A folder named like a case that is not one of this report's (here,
    // another report, as reports/sample is in reports/): refused before any
    // run, untouched.
    let out = dir.path().join("reports");
    let other = out.join("head_on");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("index.md"), "another report").unwrap();
    let compare = |out: &std::path::Path, cases: &[&str]| {
        let mut args: Vec<std::ffi::OsString> = vec!["compare".into()];
        args.extend(cases.iter().map(|c| case_path(c).into_os_string()));
        args.extend(["-f", "event-driven", "--quiet", "-o"].map(Into::into));
        args.push(out.as_os_str().to_owned());
        let args: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
        cli(&args)
    };
    let (ok, _, stderr) = compare(&out, &["head_on"]);
    assert!(
        !ok && stderr.contains("is not a case folder of a report"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("runs at a time"),
        "refused before running: {stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(other.join("index.md")).unwrap(),
        "another report"
    );
    // A report of fewer cases into the same folder removes the case folders
    // of the earlier report that it no longer has, and nothing else.
    let out = dir.path().join("mine");
    let (ok, _, stderr) = compare(&out, &["head_on", "sliding_floe"]);
    assert!(ok, "{stderr}");
    std::fs::create_dir_all(out.join("notes")).unwrap();
    let (ok, _, stderr) = compare(&out, &["head_on"]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("sliding_floe (a case of an earlier report"),
        "{stderr}"
    );
    assert!(!out.join("sliding_floe").exists());
    assert!(out.join("head_on").join("metrics.csv").is_file());
    assert!(
        out.join("notes").is_dir(),
        "a folder it did not write is kept"
    );
}
