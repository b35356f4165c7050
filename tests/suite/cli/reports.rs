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
fn compare_keeps_an_earlier_reports_case_folders_unless_told_to_replace_them() {
    let dir = tempdir();
    // A folder named like a case that is not one of this report's (here,
    // another report, as reports/sample is in reports/): refused before any
    // run, untouched.
    let out = dir.path().join("reports");
    let other = out.join("head_on");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("index.md"), "another report").unwrap();
    let compare_with = |out: &std::path::Path, cases: &[&str], more: &[&str]| {
        let mut args: Vec<std::ffi::OsString> = vec!["compare".into()];
        args.extend(cases.iter().map(|c| case_path(c).into_os_string()));
        args.extend(["-f", "event-driven", "--quiet"].map(Into::into));
        args.extend(more.iter().map(Into::into));
        args.push("-o".into());
        args.push(out.as_os_str().to_owned());
        let args: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
        cli(&args)
    };
    let compare = |out: &std::path::Path, cases: &[&str]| compare_with(out, cases, &[]);
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
    // A report of other cases into the same folder is refused before any
    // run, naming the earlier cases and the option; nothing is written or
    // removed.
    let out = dir.path().join("mine");
    let (ok, _, stderr) = compare(&out, &["head_on", "sliding_floe"]);
    assert!(ok, "{stderr}");
    std::fs::create_dir_all(out.join("notes")).unwrap();
    let listing = |dir: &std::path::Path| {
        let mut all: Vec<(std::path::PathBuf, std::time::SystemTime)> = Vec::new();
        let mut stack = vec![dir.to_path_buf()];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).unwrap() {
                let e = e.unwrap();
                let m = e.metadata().unwrap();
                all.push((e.path(), m.modified().unwrap()));
                if m.is_dir() {
                    stack.push(e.path());
                }
            }
        }
        all.sort();
        all
    };
    let before = listing(&out);
    let (ok, _, stderr) = compare(&out, &["head_on"]);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("sliding_floe") && stderr.contains("--replace"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("runs at a time"),
        "refused before running: {stderr}"
    );
    assert_eq!(listing(&out), before, "nothing written or removed");
    // With --replace, the earlier case folders this report does not have
    // are removed once it is written, and nothing else.
    let (ok, _, stderr) = compare_with(&out, &["head_on"], &["--replace"]);
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
    // The same cases again need no option: their folders are replaced.
    let (ok, _, stderr) = compare(&out, &["head_on"]);
    assert!(ok, "{stderr}");
}

#[test]
fn an_unwritable_output_is_refused_at_once_before_any_run() {
    // A path under a regular file cannot be created, even by root.
    let dir = tempdir();
    let file = dir.path().join("a_file");
    std::fs::write(&file, "not a folder").unwrap();
    let under = file.join("out");
    let case = case_path("fields/field_200_coast");
    let probes: [(&str, Vec<std::ffi::OsString>); 5] = [
        (
            "-o",
            vec![
                "run".into(),
                case.clone().into(),
                "-o".into(),
                under.clone().into(),
            ],
        ),
        (
            "-o",
            vec![
                "compare".into(),
                case.clone().into(),
                "-o".into(),
                under.clone().into(),
            ],
        ),
        (
            "--markdown",
            vec![
                "check".into(),
                case.clone().into(),
                "--markdown".into(),
                under.join("t.md").into(),
            ],
        ),
        (
            "-o",
            vec![
                "sweep".into(),
                std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("cases/sweeps/convergence.toml")
                    .into(),
                "-o".into(),
                under.clone().into(),
            ],
        ),
        (
            "--csv",
            vec![
                "lcp".into(),
                std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("tests/data/lcp")
                    .into(),
                "--time".into(),
                "--csv".into(),
                under.join("t.csv").into(),
            ],
        ),
    ];
    for (flag, args) in probes {
        let started = std::time::Instant::now();
        let args: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
        let (ok, stdout, stderr) = cli(&args);
        assert!(!ok, "{args:?}");
        let first = stderr
            .lines()
            .find(|l| l.starts_with("error:"))
            .unwrap_or("");
        assert!(
            first.contains(flag)
                && first.contains("a_file")
                && first.contains("is a file, not a folder"),
            "{args:?}: {stderr}"
        );
        assert!(
            !stderr.contains("runs at a time")
                && !stderr.contains("points on")
                && stdout.is_empty(),
            "refused before running: {stderr}"
        );
        assert!(
            started.elapsed() < std::time::Duration::from_secs(5),
            "{args:?} took {:?}",
            started.elapsed()
        );
    }
}
