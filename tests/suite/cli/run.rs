//! `run`: the promised files (and the dumps `lcp` re-solves), nothing for
//! a bad case, both Moreau formulations, and the files its help names.

use super::cli;
use crate::common::{bad_case, case_path, floebench, tempdir};

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
        .starts_with("t,kinetic,work_air,work_water,work_coriolis,dissipated,fracture,vibration,dashpot,crushing,residual\n"));
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
