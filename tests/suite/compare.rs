//! The comparison harness: `floebench compare` writes every file
//! docs/output-format.md promises, and the divergence metric is zero for identical runs and not
//! for runs that must differ.

use crate::common::{bad_case, case_path, case_text, floebench, load, run, scenario, tempdir};
use floebench::analysis::comparison::CaseComparison;
use floebench::analysis::divergence;
use floebench::compare::{self, CompareOptions};
use floebench::record::spread::Spread;
use floebench::report::verdict::verdict;
use floebench::run::batch::{top_up_count, MAX_REPEATS, TOP_UP_CPU};
use floebench::run::repeat::{merge, physics_difference};
use std::path::Path;

/// `compare` on the bundled cases `names` with `opts`.
fn compare_cases(names: &[&str], opts: &CompareOptions) -> Vec<CaseComparison> {
    let cases = names.iter().map(|n| (case_path(n), load(n))).collect();
    compare::compare(cases, opts).unwrap_or_else(|e| panic!("{e}"))
}

/// The verdict line that starts with `start`.
fn line<'a>(lines: &'a [String], start: &str) -> &'a str {
    lines
        .iter()
        .find(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("no verdict line `{start}…` in {lines:#?}"))
}

/// The formulations a `Fastest: a (…), b (…) (tied…); the others…` line names fastest.
fn fastest_named(line: &str, names: &[String]) -> Vec<String> {
    let head = line
        .strip_prefix("Fastest: ")
        .and_then(|l| l.split("; the others").next())
        .or_else(|| line.strip_prefix("CPU time: all tied"))
        .unwrap_or_else(|| panic!("not a speed line: {line}"));
    names
        .iter()
        .filter(|n| head.contains(&format!("{n} (")))
        .cloned()
        .collect()
}

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
            "median_diameter_m",
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
    // Provenance and the case's parameters on the page; code spans as <code>.
    for text in [
        "commit `",
        "UTC",
        "wind (air):",
        "initial velocities:",
        "settings (defaults resolved)",
    ] {
        assert!(md.contains(text), "index.md lacks {text:?}");
    }
    assert!(
        html.contains("<code>metrics.csv</code>"),
        "code spans in HTML"
    );
    assert!(!html.contains("`metrics.csv`"));
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "not self-contained"
    );
    // No temporary folder left behind; the list of the report's case
    // folders is the one hidden file.
    for e in std::fs::read_dir(&out).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            !n.starts_with('.') || n == floebench::report::folder::MANIFEST,
            "left {n}"
        );
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
    let dbar = scn.median_floe_diameter();
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

#[test]
fn the_top_up_asks_for_an_odd_count_that_reaches_its_cpu_time() {
    assert_eq!(top_up_count(1.0, 3), 3, "runs of a second keep their count");
    assert_eq!(top_up_count(TOP_UP_CPU / 3.0, 3), 3);
    assert_eq!(top_up_count(0.01, 3), 25);
    assert_eq!(top_up_count(0.0125, 3), 21, "20 asked, made odd");
    assert_eq!(top_up_count(1e-9, 3), MAX_REPEATS);
    assert_eq!(top_up_count(1e-9, 500), 500, "never fewer than asked");
    assert_eq!(top_up_count(0.0, 3), 3, "no timing: no top-up");
    for m in [3e-5, 7e-4, 0.03] {
        let n = top_up_count(m, 3);
        assert!(n % 2 == 1 && (n as f64 * m >= TOP_UP_CPU || n == MAX_REPEATS));
    }
}

#[test]
fn repeats_are_bit_identical_and_give_a_spread() {
    let opts = CompareOptions {
        formulations: vec!["event-driven".into(), "moreau".into()],
        repeat: 3,
        chaos_probe: false,
        ..CompareOptions::default()
    };
    let comps = compare_cases(&["head_on"], &opts);
    let c = &comps[0];
    assert!(c.findings.is_empty(), "{:?}", c.findings);
    assert!(c.chaos.is_none());
    for (r, (cpu, t)) in c.runs.iter().zip(c.cpu.iter().zip(&c.timings)) {
        // head_on's runs take well under 0.25 s / 3: topped up from the
        // median of the first three, to an odd count.
        let first: Vec<f64> = t[..3].iter().map(|x| x.cpu_total).collect();
        let want = top_up_count(Spread::of(&first).median, 3);
        assert!(want > 3 && want % 2 == 1 && want <= MAX_REPEATS, "{want}");
        assert_eq!((cpu.count(), t.len()), (want, want));
        assert!(cpu.min <= cpu.median && cpu.median <= cpu.max);
        // The run kept is the repeat of median CPU time.
        assert_eq!(r.summary.timing.cpu_total, cpu.median);
        let metric = |m: &str| {
            c.metrics
                .iter()
                .find(|x| x.metric == m && x.formulation == r.summary.formulation)
                .unwrap_or_else(|| panic!("no {m}"))
                .value
        };
        assert_eq!(metric("cpu_repeats"), want as f64);
        assert_eq!(metric("cpu_median"), cpu.median);
        assert_eq!((metric("cpu_min"), metric("cpu_max")), (cpu.min, cpu.max));
    }
}

#[test]
fn a_physics_difference_between_repeats_is_a_finding_and_timing_is_not() {
    let scn = load("head_on");
    let a = run(&scn, "event-driven");
    let mut b = a.clone();
    b.summary.timing.cpu_total *= 2.0;
    b.summary.timing.wall *= 3.0;
    assert_eq!(physics_difference(&a, &b), None);
    let mut c = a.clone();
    c.trajectory[7].vy = f64::from_bits(c.trajectory[7].vy.to_bits() ^ 1);
    let d = physics_difference(&a, &c).expect("one bit of a velocity differs");
    assert!(d.contains("trajectory") && d.contains("vy"), "{d}");
    let mut e = a.clone();
    e.energy[3].ledger.dissipated = f64::from_bits(e.energy[3].ledger.dissipated.to_bits() ^ 1);
    assert!(physics_difference(&a, &e).unwrap().contains("dissipated"));
    let merged = merge("head_on: event-driven", vec![a.clone(), b, c]).unwrap();
    assert_eq!(merged.findings.len(), 1, "{:?}", merged.findings);
    assert!(merged.findings[0].contains("repeat 3 of 3"));
    assert_eq!(merged.timings.len(), 3);
}

#[test]
fn verdicts_judge_against_the_exact_answers_with_ties_and_label_chaos() {
    let opts = CompareOptions {
        progress: false,
        ..CompareOptions::default()
    };
    let comps = compare_cases(&["head_on", "elastic_pool"], &opts);
    let (head_on, pool) = (&comps[0], &comps[1]);
    let v = verdict(head_on);
    let truth = line(&v, "Against the exact answers");
    // rapier misses the closed form: last, after the tie of the exact ones.
    let v1 = truth
        .split("; ")
        .find(|s| s.starts_with("head_on_v1"))
        .unwrap_or_else(|| panic!("{truth}"));
    assert!(v1.contains("< rapier ("), "{v1}");
    assert!(
        v1.matches(" = ").count() == 2,
        "three exact runs tied: {v1}"
    );
    // The dissipations of the exact runs differ by rounding only: a tie.
    let diss = line(&v, "Dissipation in contacts");
    assert!(diss.matches(" = ").count() == 2, "{diss}");
    for l in &v {
        assert!(!l.contains("agree"), "no agreement wording: {l}");
    }
    assert!(v.iter().any(|l| l.starts_with("Not chaotic")));
    assert!(!head_on.chaos.as_ref().unwrap().chaotic);
    // The elastic pool is chaotic; its divergence is said not to be a disagreement.
    let probe = pool.chaos.as_ref().unwrap();
    assert!(probe.chaotic, "{probe:?}");
    assert!(probe.rate.unwrap() > 0.0 && probe.growth > 1e6);
    let v = verdict(pool);
    assert!(line(&v, "Chaotic case").contains("not a disagreement"));
    assert!(line(&v, "Divergence between runs").contains("d_med"));
}

#[test]
fn speed_is_a_tie_when_the_repeats_overlap_or_the_medians_are_within_the_margin() {
    let opts = CompareOptions {
        formulations: vec!["event-driven".into(), "moreau".into(), "rapier".into()],
        chaos_probe: false,
        ..CompareOptions::default()
    };
    let mut c = compare_cases(&["head_on"], &opts).remove(0);
    c.cpu = vec![
        Spread::of(&[1.0, 1.2, 1.1]),
        Spread::of(&[1.15, 1.3, 1.25]),
        Spread::of(&[5.0, 5.1, 5.2]),
    ];
    let v = verdict(&c);
    let speed = line(&v, "Fastest");
    assert!(speed.contains("tied"), "{speed}");
    let names: Vec<String> = c
        .runs
        .iter()
        .map(|r| r.summary.formulation.clone())
        .collect();
    assert_eq!(fastest_named(speed, &names), ["event-driven", "moreau"]);
    // Disjoint ranges, but medians 1.1 and 1.3 (1.18×, within the 1.25
    // margin): still tied.
    c.cpu[1] = Spread::of(&[1.25, 1.3, 1.35]);
    let v = verdict(&c);
    let speed = line(&v, "Fastest");
    assert!(speed.contains("tied"), "{speed}");
    assert_eq!(fastest_named(speed, &names), ["event-driven", "moreau"]);
    // Disjoint ranges and medians 1.1 and 1.45 (1.32×): apart.
    c.cpu[1] = Spread::of(&[1.4, 1.45, 1.5]);
    let v = verdict(&c);
    let speed = line(&v, "Fastest");
    assert!(!speed.contains("tied"), "{speed}");
    assert_eq!(fastest_named(speed, &names), ["event-driven"]);
    // 5.1 / 1.1 = 4.6, from 5.0 / 1.2 = 4.2 to 5.2 / 1.0 = 5.2: one digit.
    assert!(speed.contains("rapier 5×"), "{speed}");
}

#[test]
fn one_run_each_calls_no_speed_tie_and_says_so_once() {
    // Issue 40: with one run each the line called a tie and said that no
    // tie can be called. One run gives no spread: no tie, even within the
    // 1.25 margin, and one sentence says why.
    let opts = CompareOptions {
        formulations: vec!["event-driven".into(), "moreau".into()],
        chaos_probe: false,
        ..CompareOptions::default()
    };
    let mut c = compare_cases(&["head_on"], &opts).remove(0);
    c.cpu = vec![Spread::of(&[1.0]), Spread::of(&[1.1])];
    let v = verdict(&c);
    let speed = line(&v, "Fastest");
    assert!(!speed.contains("tied"), "{speed}");
    assert!(speed.contains("no tie is called"), "{speed}");
    assert_eq!(speed.matches(". ").count(), 0, "one sentence: {speed}");
    let names: Vec<String> = c
        .runs
        .iter()
        .map(|r| r.summary.formulation.clone())
        .collect();
    assert_eq!(fastest_named(speed, &names), ["event-driven"]);
    assert!(!v.iter().any(|l| l.starts_with("CPU time: all tied")));
}

#[test]
fn a_case_without_description_is_named_by_its_file_alone() {
    // Issue 40: without `description` the page printed "`case.toml`: "
    // with nothing after.
    let text = case_text("head_on");
    let bare: String = text
        .lines()
        .filter(|l| !l.starts_with("description"))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_ne!(bare, text, "head_on has a description to remove");
    let scn = scenario(&bare);
    assert!(scn.description.is_empty());
    let opts = CompareOptions {
        formulations: vec!["event-driven".into()],
        chaos_probe: false,
        ..CompareOptions::default()
    };
    let comps = compare::compare(vec![("inline.toml".into(), scn)], &opts).unwrap();
    let dir = tempdir();
    floebench::report::compare::write_report(&comps, dir.path(), "test").unwrap();
    let page = std::fs::read_to_string(dir.path().join("index.md")).unwrap();
    assert!(page.lines().any(|l| l == "`inline.toml`"), "{page}");
    assert!(!page.contains("`inline.toml`:"), "{page}");
}

#[test]
fn two_compare_runs_give_the_same_verdicts() {
    // Every verdict but the speed one is physics, bit-identical between
    // runs; the speed line may differ in its figures but never names a
    // different fastest (a tie absorbs the noise). No wall-clock bound.
    let opts = CompareOptions {
        repeat: 3,
        ..CompareOptions::default()
    };
    let a = compare_cases(&["bouncing_floe"], &opts).remove(0);
    let b = compare_cases(&["bouncing_floe"], &opts).remove(0);
    let (va, vb) = (verdict(&a), verdict(&b));
    assert_eq!(va.len(), vb.len());
    let names: Vec<String> = a
        .runs
        .iter()
        .map(|r| r.summary.formulation.clone())
        .collect();
    for (la, lb) in va.iter().zip(&vb) {
        if la.starts_with("Fastest") || la.starts_with("CPU time") {
            let (fa, fb) = (fastest_named(la, &names), fastest_named(lb, &names));
            assert!(
                fa.iter().any(|f| fb.contains(f)),
                "contradicting speed verdicts:\n{la}\n{lb}"
            );
        } else {
            assert_eq!(la, lb);
        }
    }
}

#[test]
fn check_and_compare_take_a_repeat_count() {
    let out = floebench()
        .args(["check", "--repeat", "2", "-f", "event-driven", "--quiet"])
        .arg(case_path("head_on"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!stdout.contains("finding:"), "{stdout}");
    let bad = floebench()
        .args(["compare", "--repeat", "0", "--quiet"])
        .arg(case_path("head_on"))
        .output()
        .unwrap();
    assert!(!bad.status.success());
}
