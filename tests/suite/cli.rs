//! The command line: `validate`, `run` (outputs, dumps), `lcp`.

use crate::common::{bad_case, case_path, floebench, interrupt_after, tempdir};

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
fn run_writes_the_promised_files_and_lcp_re_solves_a_dump() {
    let dir = tempdir();
    let out = dir.path().join("out");
    let dumps = dir.path().join("lcp");
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        case_path("head_on").as_os_str(),
        "--quiet".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
        "--dump-lcp".as_ref(),
        dumps.as_os_str(),
    ]);
    assert!(ok, "{stderr}");
    let traj = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    assert!(traj.starts_with("t,floe,x,y,theta,vx,vy,omega\n"));
    assert_eq!(
        traj.lines().count(),
        1 + 2 * 41,
        "2 floes every 0.5 s over 20 s"
    );
    let energy = std::fs::read_to_string(out.join("energy.csv")).unwrap();
    assert!(energy
        .starts_with("t,kinetic,work_air,work_water,work_coriolis,dissipated,fracture,vibration,dashpot,residual\n"));
    let floes: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("floes.json")).unwrap()).unwrap();
    let floes = floes.as_array().unwrap();
    assert_eq!(floes.len(), 2, "the two floes of the case, none broken");
    for (i, f) in floes.iter().enumerate() {
        assert_eq!(f["id"], i);
        assert!(f["parent"].is_null() && f["t_end"].is_null());
        assert_eq!(f["t_birth"], 0.0);
        assert!(f["mass"].as_f64().unwrap() > 0.0 && f["polygon"].as_array().unwrap().len() >= 3);
    }
    let fractures = std::fs::read_to_string(out.join("fractures.csv")).unwrap();
    assert_eq!(
        fractures,
        "t,parent,children,model,measure,threshold,energy,kinetic_gain\n"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["end"]["reason"], "completed");
    assert_eq!(summary["formulation"], "event-driven");
    assert_eq!(summary["counters"]["impacts"]["value"].as_u64(), Some(1));
    assert_eq!(summary["counters"]["impacts"]["unit"], "count");
    // Settings are reported apart from the counters, with their unit.
    assert_eq!(summary["settings"]["contact_distance_m"]["unit"], "m");
    assert!(summary["counters"].get("contact_distance_m").is_none());
    for key in ["cpu_total", "stages", "wall"] {
        assert!(summary["timing"].get(key).is_some(), "{key}");
    }
    let first = dumps.join("000000.json");
    let re = floebench().arg("lcp").arg(&first).output().unwrap();
    assert!(re.status.success());
    let text = String::from_utf8_lossy(&re.stdout);
    assert!(
        text.contains("re-solved:") && text.contains("residual"),
        "{text}"
    );
}

#[test]
fn a_bad_case_writes_nothing() {
    let dir = tempdir();
    let out = dir.path().join("out");
    let bad = bad_case("floes_overlap");
    let st = floebench()
        .arg("run")
        .arg(&bad)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(!st.status.success());
    assert!(
        String::from_utf8_lossy(&st.stderr).contains("floes_overlap.toml:13"),
        "the error names the file and line"
    );
    assert!(!out.exists(), "no partial output for a bad case");
}

#[test]
fn run_accepts_both_moreau_formulations() {
    let list = floebench().arg("formulations").output().unwrap();
    let text = String::from_utf8_lossy(&list.stdout);
    assert!(
        text.contains("moreau ") && text.contains("moreau-cone"),
        "{text}"
    );
    let dir = tempdir();
    for name in ["moreau", "moreau-cone"] {
        let out = dir.path().join(name);
        let run = floebench()
            .arg("run")
            .arg(case_path("head_on"))
            .args(["-f", name, "--quiet", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        assert!(
            summary.contains(&format!("\"formulation\": \"{name}\"")),
            "{summary}"
        );
        assert!(out.join("trajectory.csv").exists() && out.join("energy.csv").exists());
    }
}

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

/// Runs `floebench` with `args`; (success, stdout, stderr).
fn cli(args: &[&std::ffi::OsStr]) -> (bool, String, String) {
    let out = floebench().args(args).output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
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
fn one_grammar_for_formulations_and_jobs() {
    let dir = tempdir();
    let md = dir.path().join("t.md");
    // check takes -f like run and compare, with spaces after the commas.
    let (ok, stdout, stderr) = cli(&[
        "check".as_ref(),
        case_path("head_on").as_os_str(),
        "-f".as_ref(),
        "event-driven, moreau".as_ref(),
        "--quiet".as_ref(),
        "--markdown".as_ref(),
        md.as_os_str(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("moreau") && !stdout.contains("rapier"),
        "{stdout}"
    );
    let (ok, _, stderr) = cli(&[
        "compare".as_ref(),
        case_path("head_on").as_os_str(),
        "-j".as_ref(),
        "0".as_ref(),
    ]);
    assert!(!ok && stderr.contains("-j"), "{stderr}");
}

#[test]
fn run_refuses_what_would_mislead_before_running() {
    let dir = tempdir();
    let out = dir.path().join("o");
    let head_on = case_path("head_on");
    // free-drift through a case with contacts: refused unless asked.
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        case_path("bouncing_floe").as_os_str(),
        "-f".as_ref(),
        "free-drift".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(!ok && stderr.contains("--allow-contacts"), "{stderr}");
    assert!(!out.exists());
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        case_path("bouncing_floe").as_os_str(),
        "-f".as_ref(),
        "free-drift".as_ref(),
        "--allow-contacts".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(ok, "{stderr}");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"ignored\""),
        "the summary says contacts were ignored"
    );
    // --dump-lcp: a formulation that dumps nothing, and a used folder.
    let dumps = dir.path().join("d");
    for f in ["rapier", "moreau-cone", "free-drift"] {
        let (ok, _, stderr) = cli(&[
            "run".as_ref(),
            head_on.as_os_str(),
            "-f".as_ref(),
            f.as_ref(),
            "--dump-lcp".as_ref(),
            dumps.as_os_str(),
            "--quiet".as_ref(),
        ]);
        assert!(
            !ok && stderr.contains("writes no LCP dumps"),
            "{f}: {stderr}"
        );
    }
    std::fs::create_dir_all(&dumps).unwrap();
    std::fs::write(dumps.join("000000.json"), "{}").unwrap();
    let (ok, _, stderr) = cli(&[
        "run".as_ref(),
        head_on.as_os_str(),
        "--dump-lcp".as_ref(),
        dumps.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(!ok && stderr.contains("not an empty folder"), "{stderr}");
    // An output path that is a file: compare says so before any run.
    let file = dir.path().join("notes.txt");
    std::fs::write(&file, "x").unwrap();
    let (ok, _, stderr) = cli(&[
        "compare".as_ref(),
        head_on.as_os_str(),
        "-o".as_ref(),
        file.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(!ok && stderr.contains("is not a folder"), "{stderr}");
    assert!(
        !stderr.contains("runs at a time"),
        "refused before loading: {stderr}"
    );
}

#[test]
fn compare_and_check_refuse_free_drift_through_contacts_as_run_does() {
    // Issue 40: `run -f free-drift` refused a case with contacts, `compare`
    // ran it (the floes passed through the coast). One rule for all three.
    let dir = tempdir();
    let out = dir.path().join("r");
    let bouncing = case_path("bouncing_floe");
    for cmd in ["compare", "check"] {
        let mut args: Vec<&std::ffi::OsStr> = vec![
            cmd.as_ref(),
            bouncing.as_os_str(),
            "-f".as_ref(),
            "event-driven,free-drift".as_ref(),
            "--quiet".as_ref(),
        ];
        if cmd == "compare" {
            args.extend(["-o".as_ref(), out.as_os_str()]);
        }
        let (ok, _, stderr) = cli(&args);
        assert!(
            !ok && stderr.contains("free-drift ignores contacts")
                && stderr.contains("--allow-contacts"),
            "{cmd}: {stderr}"
        );
        assert!(
            !stderr.contains("runs at a time"),
            "refused before any run: {stderr}"
        );
    }
    assert!(!out.exists(), "no report for a refused comparison");
    let (ok, stdout, stderr) = cli(&[
        "compare".as_ref(),
        bouncing.as_os_str(),
        "-f".as_ref(),
        "free-drift".as_ref(),
        "--allow-contacts".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("bouncing_floe"), "{stdout}");
}

#[test]
fn help_names_every_file_run_writes_and_the_reference_of_compare() {
    let run = floebench().args(["run", "--help"]).output().unwrap();
    let text = String::from_utf8_lossy(&run.stdout).replace('\n', " ");
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    for f in [
        "trajectory.csv",
        "energy.csv",
        "summary.json",
        "floes.json",
        "fractures.csv",
        "percussion.json",
    ] {
        assert!(text.contains(f), "run --help omits {f}: {text}");
    }
    let compare = floebench().args(["compare", "--help"]).output().unwrap();
    let text = String::from_utf8_lossy(&compare.stdout);
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        text.contains("the reference of the divergences")
            && !text.contains("reference of the verdicts"),
        "{text}"
    );
    assert!(text.contains("--allow-contacts"), "{text}");
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

#[test]
fn an_unknown_formulation_is_named_without_blaming_a_case() {
    for cmd in ["compare", "check"] {
        let (ok, _, stderr) = cli(&[
            cmd.as_ref(),
            case_path("head_on").as_os_str(),
            "-f".as_ref(),
            "rapeir".as_ref(),
            "--quiet".as_ref(),
        ]);
        assert!(!ok);
        assert!(
            stderr.contains("error: -f: unknown formulation `rapeir`; known: event-driven"),
            "{cmd}: {stderr}"
        );
        assert!(!stderr.contains("head_on.toml"), "{cmd}: {stderr}");
    }
}

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

#[test]
fn lcp_time_switches_the_small_problem_refinement() {
    // `lcp DIR --time` (default `--unpolished-below 1e-13`) keeps the
    // small candidates within 1e-13 unrefined; `--unpolished-below 0`
    // refines every candidate: the same pivots on every dump, and residuals
    // at least as small. The old name of the switch is still read. A
    // negative value is refused by name.
    let dir = tempdir();
    let dumps = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcp");
    let rows = |extra: &[&str], name: &str| {
        let csv = dir.path().join(name);
        let mut args: Vec<&std::ffi::OsStr> = vec!["lcp".as_ref(), dumps.as_os_str()];
        args.extend(["--time", "--repeat", "1", "--csv"].map(std::ffi::OsStr::new));
        args.push(csv.as_os_str());
        args.extend(extra.iter().map(std::ffi::OsStr::new));
        let (ok, _, stderr) = cli(&args);
        assert!(ok, "{stderr}");
        let text = std::fs::read_to_string(&csv).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                let n: usize = f[1].parse().unwrap();
                let pivots: usize = f[3].parse().unwrap();
                let residual: f64 = f[6].parse().unwrap();
                (f[0].to_string(), n, pivots, residual)
            })
            .collect::<Vec<_>>()
    };
    let small = rows(&[], "small.csv");
    assert_eq!(
        small,
        rows(&["--small-unpolished-below", "1e-13"], "old_name.csv")
    );
    let refined = rows(&["--unpolished-below", "0"], "refined.csv");
    assert_eq!(small.len(), refined.len());
    let mut differ = 0;
    for (a, b) in small.iter().zip(&refined) {
        assert_eq!((&a.0, a.1, a.2), (&b.0, b.1, b.2));
        assert!(b.3 <= a.3, "{}: refined {:e} above {:e}", a.0, b.3, a.3);
        if a.1 > 40 {
            assert_eq!(a.3, b.3, "{}: above 40 unknowns nothing changes", a.0);
        } else if a.3 != b.3 {
            differ += 1;
            assert!(a.3 <= 1e-13, "{}: {:e}", a.0, a.3);
        }
    }
    assert!(differ > 0, "the switch changed no residual");
    let (ok, _, stderr) = cli(&[
        "lcp".as_ref(),
        dumps.as_os_str(),
        "--time".as_ref(),
        "--unpolished-below=-1".as_ref(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("--unpolished-below"), "{stderr}");
}
