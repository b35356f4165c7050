//! `floebench sweep` resumed (nothing recomputed, a removed point run
//! again) and interrupted (no result file for the interrupted point).

use super::plan_file;
use crate::common::{floebench, interrupt_after, tempdir};

#[test]
fn a_resumed_sweep_recomputes_nothing_and_a_removed_point_is_run_again() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["head_on", "bouncing_floe"],
        "reference = \"event-driven\"\n\n[[formulation]]\nname = \"moreau\"\ngrid = { step = [0.5, 0.25] }",
    );
    let out = dir.path().join("out");
    let args = |extra: &[&str]| {
        let mut a: Vec<String> = vec![
            "sweep".into(),
            path.display().to_string(),
            "-o".into(),
            out.display().to_string(),
            "--quiet".into(),
        ];
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |extra: &[&str]| {
        let o = floebench().args(args(extra)).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let first = run(&[]);
    assert!(
        first.contains("sweep: 4 points run, 0 skipped (already finished), 2 reference runs"),
        "{first}"
    );
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert!(csv
        .starts_with("case,formulation,settings,metric,value,unit\nhead_on,moreau,step=0.5,cpu,"));
    // The page and its plots.
    let page = std::fs::read_to_string(out.join("index.md")).unwrap();
    for case in ["head_on", "bouncing_floe"] {
        for stem in ["work_precision", "setting_step"] {
            for ext in ["png", "svg"] {
                let f = format!("{case}/{stem}.{ext}");
                assert!(out.join(&f).is_file(), "{f}");
            }
            assert!(page.contains(&format!("{case}/{stem}.png")), "{page}");
        }
    }
    assert!(page.contains("4 of 4 points finished"), "{page}");
    let file = out.join("points").join("head_on__moreau__step=0.5.json");
    let written = std::fs::metadata(&file).unwrap().modified().unwrap();
    let again = run(&[]);
    assert!(
        again.contains("sweep: 0 points run, 4 skipped (already finished), 0 reference runs"),
        "{again}"
    );
    assert_eq!(
        std::fs::metadata(&file).unwrap().modified().unwrap(),
        written
    );
    assert_eq!(std::fs::read_to_string(out.join("sweep.csv")).unwrap(), csv);
    std::fs::remove_file(&file).unwrap();
    let third = run(&[]);
    assert!(
        third.contains("sweep: 1 point run, 3 skipped (already finished), 0 reference runs"),
        "{third}"
    );
}

#[test]
fn an_interrupted_point_leaves_no_result_file() {
    let dir = tempdir();
    let path = plan_file(
        dir.path(),
        &["head_on", "fields/field_200_coast"],
        "reference = \"exact\"\n\n[[formulation]]\nname = \"event-driven\"",
    );
    let out = dir.path().join("out");
    // The field's point runs after head_on's (one at a time): interrupted
    // 1.5 s into it.
    let (code, seen) = interrupt_after(
        &[
            "sweep".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "-j".as_ref(),
            "1".as_ref(),
        ],
        "head_on / event-driven",
        std::time::Duration::from_millis(1500),
        libc::SIGINT,
    );
    assert_eq!(code, Some(130), "{seen}");
    assert!(seen.contains("interrupted"), "{seen}");
    let points = out.join("points");
    assert!(points
        .join("head_on__event-driven__defaults.json")
        .is_file());
    let files: Vec<String> = std::fs::read_dir(&points)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        files,
        ["head_on__event-driven__defaults.json"],
        "no partial or temporary file"
    );
    let page = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert!(page.contains("1 of 2 points finished"), "{page}");
}
