//! The comparison harness: `floebench compare` writes every file the README
//! promises, and the divergence metric is zero for identical runs and not
//! for runs that must differ.

use crate::common::{bad_case, case_path, floebench, load, run, tempdir};
use floebench::analysis::divergence;
use floebench::compare::{self, CompareOptions};
use std::path::Path;

/// The header of a CSV file and its rows, each checked to have as many fields.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>())
        .collect();
    for r in &rows {
        assert_eq!(
            r.len(),
            header.len(),
            "{}: ragged row {r:?}",
            path.display()
        );
    }
    assert!(!rows.is_empty(), "{} has no row", path.display());
    (header, rows)
}

fn json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn compare_writes_every_promised_file_and_each_parses() {
    let dir = tempdir();
    let out = dir.path().join("reports");
    let forms = ["event-driven", "moreau", "rapier"];
    let status = floebench()
        .arg("compare")
        .arg(case_path("head_on"))
        .arg(case_path("cradle_touching"))
        .args(["--formulations", &forms.join(","), "--quiet", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    for name in ["head_on", "cradle_touching"] {
        let c = out.join(name);
        let (h, rows) = read_csv(&c.join("metrics.csv"));
        assert_eq!(
            h,
            ["case", "formulation", "other", "metric", "value", "unit"]
        );
        for r in &rows {
            assert_eq!(r[0], name);
            assert!(forms.contains(&r[1].as_str()), "{r:?}");
            r[4].parse::<f64>().unwrap_or_else(|e| panic!("{r:?}: {e}"));
            assert!(!r[5].is_empty(), "{r:?} has no unit");
        }
        for metric in [
            "cpu_total",
            "dissipated",
            "kinetic_final",
            "cpu_solve",
            "steps",
        ] {
            for f in forms {
                assert!(
                    rows.iter()
                        .any(|r| r[1] == f && r[2].is_empty() && r[3] == metric),
                    "{name}: no {metric} for {f}"
                );
            }
        }
        // Three pairs, each with its summary figures.
        let pairs = rows
            .iter()
            .filter(|r| r[3] == "max_rms_position_rel" && !r[2].is_empty())
            .count();
        assert_eq!(pairs, 3);
        let (h, rows) = read_csv(&c.join("divergence.csv"));
        assert_eq!(
            h,
            [
                "t",
                "a",
                "b",
                "rms_position_rel",
                "max_position_m",
                "rms_angle_rad",
                "max_angle_rad"
            ]
        );
        assert!(rows.iter().all(|r| r[3].parse::<f64>().is_ok()));
        let checks = std::fs::read_to_string(c.join("checks.csv")).unwrap();
        assert!(checks.starts_with(
            "case,formulation,check,measured,expected,tolerance,unit,pass,claimed,note\n"
        ));
        assert!(checks.lines().count() > forms.len(), "{name}: no check row");
        let s = json(&c.join("summary.json"));
        for key in [
            "case",
            "file",
            "floes",
            "duration_s",
            "mean_diameter_m",
            "verdict",
            "runs",
            "pairs",
        ] {
            assert!(s.get(key).is_some(), "{name}/summary.json lacks {key}");
        }
        assert_eq!(s["runs"].as_array().unwrap().len(), forms.len());
        for plot in [
            "kinetic",
            "dissipated",
            "divergence",
            "paths",
            "snapshots",
            "cpu",
        ] {
            let png = std::fs::read(c.join(format!("{plot}.png"))).unwrap();
            assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "{name}/{plot}.png");
            assert!(png.len() > 5000, "{name}/{plot}.png is nearly empty");
            let svg = std::fs::read_to_string(c.join(format!("{plot}.svg"))).unwrap();
            assert!(
                svg.contains("<svg") && svg.trim_end().ends_with("</svg>"),
                "{name}/{plot}.svg"
            );
            assert!(
                md.contains(&format!("{name}/{plot}.png")),
                "index.md does not show {plot}"
            );
        }
        for f in forms {
            let (h, _) = read_csv(&c.join(f).join("trajectory.csv"));
            assert_eq!(h, ["t", "floe", "x", "y", "theta", "vx", "vy", "omega"]);
            let (h, _) = read_csv(&c.join(f).join("energy.csv"));
            assert_eq!(h[0], "t");
            let s = json(&c.join(f).join("summary.json"));
            assert_eq!(s["formulation"], f);
            assert!(s["timing"]["cpu_total"].as_f64().unwrap() > 0.0);
        }
    }
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(md.contains("## head_on") && md.contains("**Verdict.**"));
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "not self-contained"
    );
    // No temporary folder left behind.
    for e in std::fs::read_dir(&out).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!n.starts_with('.'), "left {n}");
    }
}

#[test]
fn a_bad_case_or_formulation_writes_nothing() {
    let dir = tempdir();
    let out = dir.path().join("reports");
    let bad = bad_case("clockwise");
    let r = floebench()
        .arg("compare")
        .arg(case_path("head_on"))
        .arg(&bad)
        .args(["--quiet", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("clockwise.toml:14"));
    let r = floebench()
        .arg("compare")
        .arg(case_path("head_on"))
        .args(["-f", "event-driven,nonsense", "--quiet", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("unknown formulation `nonsense`"));
    assert!(!out.exists());
}

#[test]
fn identical_runs_do_not_diverge_and_the_touching_cradle_separates_formulations() {
    let scn = load("cradle_touching");
    let a = run(&scn, "event-driven");
    let b = run(&scn, "event-driven");
    let same = divergence::divergence(&scn, &a, &b, 0.1).unwrap();
    assert_eq!(same.samples.len(), a.energy.len());
    assert_eq!(same.max_rms_position_rel, 0.0);
    assert_eq!(same.max_angle_rad, 0.0);
    assert_eq!(same.diverged_at, None);

    // The touching cradle: the simultaneous LCP sends the first floe back at
    // (2 − n)/n v0 while rapier's sequential soft contacts do not: the
    // trajectories must differ, and the metric must say so.
    let r = run(&scn, "rapier");
    let d = divergence::divergence(&scn, &a, &r, 0.1).unwrap();
    assert!(d.max_rms_position_rel > 0.1, "{d:?}");
    assert!(d.diverged_at.is_some());
    // The metric is symmetric and its largest floe distance bounds the RMS.
    let back = divergence::divergence(&scn, &r, &a, 0.1).unwrap();
    assert_eq!(back.max_rms_position_rel, d.max_rms_position_rel);
    let dbar = divergence::mean_diameter(&scn);
    for s in &d.samples {
        assert!(s.rms_position_rel * dbar <= s.max_position_m * (1.0 + 1e-12));
    }
    // The same through the harness, with its metric rows.
    let opts = CompareOptions {
        formulations: vec!["event-driven".into(), "rapier".into()],
        ..CompareOptions::default()
    };
    let comps = compare::compare(vec![(case_path("cradle_touching"), scn.clone())], &opts).unwrap();
    let diverged = comps[0]
        .metrics
        .iter()
        .find(|m| m.metric == "diverged" && m.other == "rapier")
        .unwrap();
    assert_eq!(diverged.value, 1.0);
}
