//! SIGINT and SIGTERM: a run ends with its outputs written up to the last
//! output time, at the formulation's next step, and `compare` keeps the
//! cases that finished.

use crate::common::{case_path, interrupt_after, interrupt_after_timed, tempdir};

#[test]
fn sigint_ends_a_run_with_its_outputs_written_up_to_the_last_output_time() {
    let dir = tempdir();
    let out = dir.path().join("o");
    let (code, stderr) = interrupt_after(
        &[
            "run".as_ref(),
            case_path("fields/field_200_coast").as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "--quiet".as_ref(),
        ],
        "field_200_coast:",
        std::time::Duration::from_millis(1500),
        libc::SIGINT,
    );
    assert_eq!(code, Some(130), "{stderr}");
    assert!(stderr.contains("run interrupted at t = "), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["end"]["reason"], "interrupted", "{summary}");
    let reached = summary["t_reached"].as_f64().unwrap();
    assert!(reached < 21600.0);
    let trajectory = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let last = trajectory.lines().last().unwrap();
    let t: f64 = last.split(',').next().unwrap().parse().unwrap();
    assert_eq!(t, reached, "the last row is the last output time reached");
    for file in ["trajectory.csv", "energy.csv"] {
        let text = std::fs::read_to_string(out.join(file)).unwrap();
        for line in text.lines().skip(1) {
            for x in line.split(',') {
                assert!(x.parse::<f64>().unwrap().is_finite(), "{file}: {line}");
            }
        }
    }
}

#[test]
fn sigint_between_two_outputs_stops_the_formulation_at_its_next_step() {
    // One output, at the end of 6 h: the formulations poll the signal once
    // per step of their own grid, so the run ends interrupted at its last
    // output (t = 0), not after the whole run.
    let dir = tempdir();
    let text = std::fs::read_to_string(case_path("fields/field_200_coast"))
        .unwrap()
        .replace("output_interval = 300.0", "output_interval = 21600.0");
    assert!(text.contains("output_interval = 21600.0"));
    let case = dir.path().join("field_200_coast.toml");
    std::fs::write(&case, text).unwrap();
    for f in ["event-driven", "moreau-cone", "rapier"] {
        let out = dir.path().join(f);
        let (code, stderr) = interrupt_after(
            &[
                "run".as_ref(),
                case.as_os_str(),
                "-f".as_ref(),
                f.as_ref(),
                "-o".as_ref(),
                out.as_os_str(),
                "--quiet".as_ref(),
            ],
            "field_200_coast:",
            std::time::Duration::from_millis(1500),
            libc::SIGINT,
        );
        assert_eq!(code, Some(130), "{f}: {stderr}");
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(summary["end"]["reason"], "interrupted", "{f}: {summary}");
        assert_eq!(summary["t_reached"].as_f64(), Some(0.0), "{f}");
    }
}

#[test]
fn sigterm_during_compare_keeps_the_cases_that_finished() {
    let dir = tempdir();
    let out = dir.path().join("report");
    let (code, stderr) = interrupt_after(
        &[
            "compare".as_ref(),
            case_path("head_on").as_os_str(),
            case_path("fields/field_200_coast").as_os_str(),
            "-f".as_ref(),
            "event-driven".as_ref(),
            "-j".as_ref(),
            "1".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
            "--quiet".as_ref(),
        ],
        "runs at a time",
        std::time::Duration::from_millis(2000),
        libc::SIGTERM,
    );
    assert_eq!(code, Some(130), "{stderr}");
    assert!(
        stderr.contains("not reported (runs not finished): field_200_coast"),
        "{stderr}"
    );
    assert!(out.join("head_on").join("metrics.csv").is_file());
    assert!(!out.join("field_200_coast").exists());
    let page = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert!(page.contains("head_on") && !page.contains("## field_200_coast"));
}

#[test]
fn sigterm_ends_a_run_inside_its_lattice_impacts_promptly_with_its_files() {
    // A run whose steps hold lattice percussions (and Lemke solves): the
    // loops inside a step poll the stop request, so SIGTERM ends the run
    // within about a second (2 s allowed for a loaded machine), exit 130,
    // its files written up to its last output time.
    let dir = tempdir();
    let out = dir.path().join("o");
    let (code, stderr, took) = interrupt_after_timed(
        &[
            "run".as_ref(),
            case_path("fields/lattice_field_200_impact").as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "--quiet".as_ref(),
        ],
        "lattice_field_200_impact:",
        std::time::Duration::from_millis(2500),
        libc::SIGTERM,
    );
    assert_eq!(code, Some(130), "{stderr}");
    assert!(
        took < std::time::Duration::from_secs(2),
        "ended {took:?} after SIGTERM"
    );
    assert!(stderr.contains("run interrupted at t = "), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["end"]["reason"], "interrupted", "{summary}");
    let trajectory = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let last = trajectory.lines().last().unwrap();
    let t: f64 = last.split(',').next().unwrap().parse().unwrap();
    assert_eq!(Some(t), summary["t_reached"].as_f64());
    assert!(t < 1200.0, "stopped before the end");
}
