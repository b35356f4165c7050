//! Crushing ice (docs/physics.md §10): the bound of a contact's force in
//! every solver against the closed forms of a floe rammed into a coast,
//! and the refusals of bad crushing input.

use crate::common::{case_path, floebench, run};
use floebench::analysis::check::check_run;
use floebench::formulation::{load_case, parse_case};
use std::path::Path;

fn row<'a>(
    rows: &'a [floebench::analysis::check::CheckOutcome],
    check: &str,
) -> &'a floebench::analysis::check::CheckOutcome {
    rows.iter()
        .find(|o| o.check == check)
        .unwrap_or_else(|| panic!("no `{check}` row in {rows:#?}"))
}

/// A face crushing against a coast: the force is `σ_c h w` and the floe
/// stops after `M V / F`, in Moreau–Jean by Lemke and by the cone program;
/// a rigid contact (no crushing) would stop it in one step, at a force of
/// `M V / h` = 9.2e9 N, far outside 5 %.
#[test]
fn a_face_crushes_at_the_closed_form_force_for_the_closed_form_time() {
    let scn = load_case(&case_path("crushing/flat_coast")).unwrap();
    for f in ["moreau", "moreau-cone"] {
        let r = run(&scn, f);
        let rows = check_run(&scn, &r);
        for check in ["crush_force", "crush_duration", "energy_ledger"] {
            let o = row(&rows, check);
            assert!(o.pass, "{f}: {o:#?}");
        }
    }
}

/// The same face without crushing carries the rigid force: the check of the
/// crushing force does not apply, and the floe stops within a step.
#[test]
fn without_crushing_the_face_stops_at_once() {
    let text = std::fs::read_to_string(case_path("crushing/flat_coast")).unwrap();
    let rigid = text.replace("crushing = { strength = 1e6 }   # Pa\n", "");
    assert_ne!(rigid, text);
    let scn = parse_case(&rigid, Path::new("rigid.toml")).unwrap();
    let r = run(&scn, "moreau");
    assert!(check_run(&scn, &r)
        .iter()
        .all(|o| !o.check.starts_with("crush_")));
    let stopped = r
        .trajectory
        .iter()
        .find(|row| row.vx <= 0.0)
        .expect("the floe stops");
    // First contact at 1 ms, stopped at the next output.
    assert!(stopped.t <= 0.002 + 1e-12, "{stopped:?}");
}

fn refused(crushing: &str, expect: &str) {
    let text = std::fs::read_to_string(case_path("crushing/flat_coast")).unwrap();
    let bad = text.replace("crushing = { strength = 1e6 }", crushing);
    let err = parse_case(&bad, Path::new("bad.toml"))
        .expect_err(crushing)
        .to_string();
    assert!(err.contains("bad.toml:16"), "{crushing}: {err}");
    assert!(err.contains(expect), "{crushing}: {err}");
}

#[test]
fn bad_crushing_laws_are_refused_at_their_line() {
    refused(
        "crushing = { strength = 0 }",
        "crushing.strength = 0 Pa must be",
    );
    refused("crushing = { strength = -1e6 }", "crushing.strength");
    refused("crushing = { strength = nan }", "crushing.strength");
    refused("crushing = { strength = inf }", "crushing.strength");
    refused(
        "crushing = { p0 = 3e6, exponent = -1.5 }",
        "crushing.exponent",
    );
    refused(
        "crushing = { p0 = 3e6, exponent = 0.1 }",
        "crushing.exponent",
    );
    refused("crushing = { p0 = 3e6 }", "`p0` needs `exponent`");
    refused("crushing = { exponent = -0.5 }", "`exponent` needs `p0`");
    refused("crushing = { strength = 1e6, p0 = 3e6 }", "not both");
    refused("crushing = { }", "give `strength`");
}

#[test]
fn unknown_crushing_keys_are_refused() {
    let text = std::fs::read_to_string(case_path("crushing/flat_coast")).unwrap();
    let bad = text.replace(
        "crushing = { strength = 1e6 }",
        "crushing = { strenght = 1e6 }",
    );
    let err = parse_case(&bad, Path::new("bad.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("strenght"), "{err}");
}

/// rapier cannot bound a contact force: a run of it on a crushing case is
/// refused with the line of `crushing`, and nothing is written.
#[test]
fn rapier_refuses_a_crushing_case_and_writes_nothing() {
    let dir = crate::common::tempdir();
    let out = dir.path().join("out");
    let o = floebench()
        .args(["run", "-q", "-f", "rapier", "-o"])
        .arg(&out)
        .arg(case_path("crushing/flat_coast"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("flat_coast.toml:16"), "{err}");
    assert!(err.contains("rapier cannot bound a contact force"), "{err}");
    assert!(!out.exists());
}

/// A crushing run cannot restart from an earlier run's positions: the
/// trajectory holds no cut outlines.
#[test]
fn a_crushing_case_refuses_to_start_from_an_earlier_state() {
    let dir = crate::common::tempdir();
    let first = dir.path().join("first");
    let ok = floebench()
        .args(["run", "-q", "-f", "moreau", "-o"])
        .arg(&first)
        .arg(case_path("crushing/flat_coast"))
        .status()
        .unwrap();
    assert!(ok.success());
    let o = floebench()
        .args(["run", "-q", "-f", "moreau", "--from"])
        .arg(first.join("trajectory.csv"))
        .arg("-o")
        .arg(dir.path().join("second"))
        .arg(case_path("crushing/flat_coast"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("cannot start from an earlier run's state"),
        "{err}"
    );
    assert!(!dir.path().join("second").exists());
}

/// The lattices resolve an impact with no bound: crushing with
/// `impact = "lattice"` is refused at the line of `crushing`.
#[test]
fn crushing_with_lattice_impacts_is_refused() {
    let text = std::fs::read_to_string(case_path("crushing/flat_coast")).unwrap();
    let bad = format!("{text}\n[fracture]\nmodel = \"lattice\"\nimpact = \"lattice\"\n");
    let err = parse_case(&bad, Path::new("bad.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("bad.toml:16"), "{err}");
    assert!(err.contains("impact = \"lattice\""), "{err}");
}

/// With crushing, event-driven has no impact: the fracture criteria read
/// its step impulses as percussions. `fracture_ram` (energy criterion,
/// critical speed 0.0156 m/s for a rigid impact with `e` = 0.5) with
/// crushing: at 0.05 m/s the floe breaks in event-driven (without the
/// percussions it would never break) as in Moreau–Jean; at 0.02 m/s
/// Moreau–Jean's Newton rebound breaks it and event-driven's stop, with
/// the impulse `M V` instead of `(1 + e) M V`, does not (docs/physics.md
/// §10.2).
#[test]
fn event_driven_breaks_a_crushing_floe_from_its_step_impulses() {
    let text = crate::common::case_text("fracture_ram").replace(
        "friction = 0.0\n",
        "friction = 0.0\ncrushing = { strength = 1e6 }\n",
    );
    assert!(text.contains("crushing"));
    let at = |v: &str| {
        let t = text.replace("velocity = [0.02, 0.0]", &format!("velocity = [{v}, 0.0]"));
        parse_case(&t, Path::new("ram.toml")).unwrap()
    };
    for f in ["event-driven", "moreau"] {
        assert_eq!(run(&at("0.05"), f).fractures.len(), 1, "{f} at 0.05 m/s");
    }
    assert_eq!(run(&at("0.02"), "moreau").fractures.len(), 1);
    assert_eq!(run(&at("0.02"), "event-driven").fractures.len(), 0);
}
