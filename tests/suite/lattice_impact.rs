//! `[fracture] impact = "lattice"` (docs/physics.md §9.10): the impact of
//! one pair resolved in the floes' lattices by the fracture stage, in
//! event-driven and Moreau–Jean; the ledger's vibration and dashpot
//! columns; `impact = "rigid"` unchanged; the validation errors.

use crate::common::{case_text, counter, floebench, run, scenario, tempdir};
use floebench::formulation::{build, parse_case, FormulationOptions};
use floebench::model::Scenario;
use floebench::run::RunResult;
use std::path::Path;

/// The bars of `cases/lattice_bars.toml` (100 m at 1 m/s into 200 m at
/// rest): Saint-Venant's `e = L1/L2 = 0.5`.
const SAINT_VENANT: f64 = 0.5;

/// `−u_N(after)/u_N(before)` of the bars of `scn` (the first at 1 m/s
/// along x into the second at rest) at the trajectory's last output, and
/// the relative error of the pair's linear momentum there.
fn bars_outcome(scn: &Scenario, r: &RunResult) -> (f64, f64) {
    let end = r.trajectory.last().map_or(f64::NAN, |row| row.t);
    let v = |i: usize| {
        r.trajectory
            .iter()
            .find(|row| row.t == end && row.floe == i)
            .map_or(nalgebra::Vector2::new(f64::NAN, f64::NAN), |row| {
                nalgebra::Vector2::new(row.vx, row.vy)
            })
    };
    let e_eff = (v(1).x - v(0).x) / 1.0;
    let p0 = scn.floes[0].mass * 1.0;
    let p1 = v(0) * scn.floes[0].mass + v(1) * scn.floes[1].mass;
    let err = (p1 - nalgebra::Vector2::new(p0, 0.0)).norm() / p0;
    (e_eff, err)
}

/// `cases/lattice_bars.toml` with the struck bar `l2` long (m).
fn bars_case(l2: f64) -> Scenario {
    let end = 101.0 + l2;
    let text = case_text("lattice_bars").replace(
        "[[101.0, 0.0], [301.0, 0.0], [301.0, 10.0], [101.0, 10.0]]",
        &format!("[[101.0, 0.0], [{end:?}, 0.0], [{end:?}, 10.0], [101.0, 10.0]]"),
    );
    assert!(
        text.contains(&format!("{end:?}")),
        "the case's bars changed"
    );
    scenario(&text)
}

/// The ledger closes: the largest residual over the run, against the
/// energy exchanged.
fn assert_ledger_closed(r: &RunResult, label: &str) {
    let e = &r.summary.energy;
    assert!(
        e.max_abs_residual <= 1e-9 * e.exchanged,
        "{label}: residual {} J of {} J exchanged",
        e.max_abs_residual,
        e.exchanged
    );
}

#[test]
fn the_bars_separate_at_saint_venants_restitution_with_momentum_conserved() {
    let scn = crate::common::load("lattice_bars");
    for name in ["event-driven", "moreau", "moreau-cone"] {
        let r = run(&scn, name);
        let (e_eff, momentum) = bars_outcome(&scn, &r);
        assert!(
            (e_eff - SAINT_VENANT).abs() <= 0.1 * SAINT_VENANT,
            "{name}: e_eff = {e_eff}, expected {SAINT_VENANT} within 10 % (the case's restitution is 0.9)"
        );
        assert!(momentum <= 1e-9, "{name}: momentum error {momentum:e}");
        assert_eq!(counter(&r, "lattice_impacts"), 1.0, "{name}");
        assert_eq!(
            counter(&r, "lattice_impacts_multi_pair_rigid"),
            0.0,
            "{name}"
        );
        let l = &r.final_state.ledger;
        // About half of the initial 4.585e5 J stays in the long bar's
        // vibration (no dashpots in the case).
        assert!(
            l.vibration > 0.4 * r.summary.energy.initial_kinetic && l.dashpot == 0.0,
            "{name}: vibration {} J, dashpot {} J",
            l.vibration,
            l.dashpot
        );
        assert_ledger_closed(&r, name);
    }
}

/// Saint-Venant's bars through the runner at the case's coarse spacing
/// (2.5 m): L1/L2 = 1/2 and 1/3 within 10 % of L1/L2, equal bars within
/// 5 % of 1 (the lattices' dispersion keeps them 3.3 % below it: energy
/// left in vibration), momentum conserved, and the check library's
/// `saint_venant` claim passed. The finer spacings:
/// `cargo run --release --example lattice_bars_runner`
/// (docs/results/2026-12-06-lattice-bars.md, "Through the runner").
#[test]
fn bars_of_three_ratios_through_the_runner_separate_at_saint_venants_e() {
    for (l2, tolerance) in [(200.0, 0.1), (300.0, 0.1), (100.0, 0.05)] {
        let scn = bars_case(l2);
        let expected = 100.0f64.min(l2) / 100.0f64.max(l2);
        for name in ["event-driven", "moreau"] {
            let label = format!("L2 = {l2} m, {name}");
            let r = run(&scn, name);
            let (e_eff, momentum) = bars_outcome(&scn, &r);
            assert!(
                (e_eff - expected).abs() <= tolerance * expected,
                "{label}: e_eff = {e_eff}, Saint-Venant {expected}"
            );
            assert!(momentum <= 1e-9, "{label}: momentum error {momentum:e}");
            assert_eq!(counter(&r, "lattice_impacts"), 1.0, "{label}");
            let rows = floebench::analysis::check::check_run(&scn, &r);
            let row = rows.iter().find(|o| o.check == "saint_venant");
            assert!(
                row.is_some_and(|o| o.pass && o.claimed && o.expected == Some(expected)),
                "{label}: {row:?}"
            );
            assert!(rows.iter().all(|o| !o.check.starts_with("head_on")));
            assert_ledger_closed(&r, &label);
        }
    }
}

#[test]
fn impact_rigid_is_the_rigid_law_bit_for_bit() {
    let text = case_text("lattice_bars");
    let rigid = text.replace("impact = \"lattice\"", "impact = \"rigid\"");
    let absent = text.replace("impact = \"lattice\"\n", "");
    assert!(rigid != text && absent != text);
    for name in ["event-driven", "moreau"] {
        let a = run(&scenario(&rigid), name);
        let b = run(&scenario(&absent), name);
        assert_eq!(a.trajectory, b.trajectory, "{name}");
        assert_eq!(a.final_state.ledger, b.final_state.ledger, "{name}");
        let (e, momentum) = bars_outcome(&scenario(&rigid), &a);
        assert!((e - 0.9).abs() < 1e-9, "{name}: e = {e}");
        assert!(momentum <= 1e-9, "{name}: {momentum:e}");
        assert_eq!(a.final_state.ledger.vibration, 0.0);
        assert!(
            a.summary.counters.by_name("lattice_impacts").is_err(),
            "{name}: the coupling's counters only with impact = \"lattice\""
        );
    }
}

/// A 20 m × 10 m floe at 0.5 m/s into a coast, its lattice with dashpots.
const COAST: &str = r#"
[case]
version = 1
name = "lattice_coast"
duration = 20.0
output_interval = 1.0

[contact]
restitution = 0.5
friction = 0.0

[[floe]]
polygon = [[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [0.0, 10.0]]
thickness = 1.0
velocity = [0.5, 0.0]

[[obstacle]]
polygon = [[21.0, -50.0], [40.0, -50.0], [40.0, 60.0], [21.0, 60.0]]

[fracture]
model = "lattice"
impact = "lattice"
spacing = 2.0
rule = "strain"
critical_strain = 1.0
"#;

#[test]
fn a_floe_striking_a_coast_through_its_lattice_keeps_the_ledger_closed() {
    let scn = scenario(COAST);
    for name in ["event-driven", "moreau"] {
        let r = run(&scn, name);
        assert_eq!(counter(&r, "lattice_impacts"), 1.0, "{name}");
        let l = &r.final_state.ledger;
        assert!(l.vibration > 0.0 && l.dashpot > 0.0, "{name}: {l:?}");
        let v = r.final_state.bodies[0].velocity.x;
        assert!(v < 0.0 && v > -0.5, "{name}: bounced back at {v} m/s");
        assert_ledger_closed(&r, name);
    }
}

/// The coast's floe with bonds that break at a strain of 1e-5 and pieces
/// down to 1 m²: the impact's own lattice cracks (measured: 5 pieces; at
/// 5e-5 bonds break near the contact but every chip is under `min_area`,
/// so the floe stays whole and their energy stays in `vibration`).
#[test]
fn the_impact_lattices_break_the_floe_and_pay_its_cracks_from_their_vibration() {
    let text = COAST.replace(
        "critical_strain = 1.0",
        "critical_strain = 1e-5\nmin_area = 1.0",
    );
    assert_ne!(text, COAST);
    let scn = scenario(&text);
    for name in ["event-driven", "moreau"] {
        let r = run(&scn, name);
        assert!(counter(&r, "lattice_impacts") >= 1.0, "{name}");
        assert!(r.summary.fractures >= 1, "{name}: the impact broke no floe");
        let l = &r.final_state.ledger;
        // The cracks' energy and the pieces' relative motion were taken
        // from what the impact left in the lattice, never more.
        assert!(l.fracture > 0.0, "{name}: {l:?}");
        assert!(l.vibration >= 0.0, "{name}: {l:?}");
        // One lattice decided both: the bounce of the whole body and its
        // pieces (no separate percussion of the impulse ran).
        assert!(r.final_state.bodies.len() >= 2, "{name}");
        assert!(
            r.final_state.bodies.iter().all(|b| b.velocity.x < 0.5),
            "{name}: the pieces left the coast"
        );
        assert_ledger_closed(&r, name);
    }
}

/// The message of the case `text` refused, and the line of `key = ` in it.
fn refusal(text: &str, key: &str) -> (String, usize) {
    let err = match parse_case(text, Path::new("bad.toml")) {
        Ok(_) => panic!("accepted: {text}"),
        Err(e) => e.to_string(),
    };
    let line = text
        .lines()
        .position(|l| l.starts_with(&format!("{key} = ")))
        .unwrap_or_else(|| panic!("no {key} in the text"))
        + 1;
    (err, line)
}

#[test]
fn bad_impact_settings_are_refused_with_file_and_line() {
    let text = case_text("lattice_bars");
    let (err, line) = refusal(
        &text.replace("model = \"lattice\"", "model = \"energy\""),
        "impact",
    );
    assert!(
        err.contains(&format!("bad.toml:{line}:")) && err.contains("needs model = \"lattice\""),
        "{err}"
    );
    let (err, line) = refusal(
        &text.replace("impact = \"lattice\"", "impact = \"latice\""),
        "impact",
    );
    assert!(
        err.contains(&format!("bad.toml:{line}:")) && err.contains("did you mean \"lattice\""),
        "{err}"
    );
    // 10 m across at 6 m: fewer than 3 nodes.
    let (err, line) = refusal(&text.replace("spacing = 2.5", "spacing = 6.0"), "spacing");
    assert!(
        err.contains(&format!("bad.toml:{line}:"))
            && err.contains("floe 0 ([[floe]] #0) is 10 m across")
            && err.contains("spacing 6 m")
            && err.contains("spacing <= 5 m"),
        "{err}"
    );
}

#[test]
fn rapier_is_refused_a_lattice_impact_case_and_writes_nothing() {
    let scn = crate::common::load("lattice_bars");
    let err = match build("rapier", &scn, &FormulationOptions::default()) {
        Ok(_) => panic!("rapier built"),
        Err(e) => e,
    };
    assert!(err.contains("no impact event"), "{err}");
    assert!(floebench::formulation::entry("rapier").is_ok_and(|e| !e.applies(&scn)));
    let dir = tempdir();
    let out = dir.path().join("run");
    let status = floebench()
        .args(["run", "-f", "rapier", "--quiet", "-o"])
        .arg(&out)
        .arg(crate::common::case_path("lattice_bars"))
        .output()
        .expect("floebench runs");
    assert!(!status.status.success());
    assert!(
        String::from_utf8_lossy(&status.stderr).contains("no impact event"),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    assert!(!out.exists(), "nothing written");
}
