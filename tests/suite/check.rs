//! `floebench check`: the check over `cases/` with every formulation has no
//! claimed failure, and every check fails on a deliberately wrong input and
//! passes on the unmodified one.

use crate::common::{case_text, cases_dir, load, run, scenario};
use floebench::analysis::check::{self, check_run, claimed_failures, CheckOutcome};
use floebench::compare::{self, CompareOptions};
use floebench::formulation;
use floebench::model::Scenario;
use floebench::record::{ContactEvent, ImpulseRecord};
use floebench::report::checks::{format_table, markdown_table};
use floebench::run::batch;
use floebench::run::{EndReason, RunResult};
use std::time::Instant;

fn find<'a>(rows: &'a [CheckOutcome], id: &str) -> &'a CheckOutcome {
    rows.iter()
        .find(|o| o.check == id)
        .unwrap_or_else(|| panic!("no check `{id}` in {rows:#?}"))
}

/// Asserts that `id` passes on `run` and fails once `spoil` has changed it.
fn fails_when_spoiled(
    scn: &Scenario,
    run: &RunResult,
    id: &str,
    spoil: impl FnOnce(&mut RunResult),
) {
    let good = check_run(scn, run);
    let o = find(&good, id);
    assert!(o.pass, "{}: unmodified `{id}` must pass: {o:#?}", scn.name);
    let mut bad = run.clone();
    spoil(&mut bad);
    let rows = check_run(scn, &bad);
    let o = find(&rows, id);
    assert!(!o.pass, "{}: spoiled `{id}` must fail: {o:#?}", scn.name);
    if o.claimed {
        assert!(claimed_failures(&rows) >= 1);
    }
}

/// Row index of floe `floe` at output `k` (rows are written time by time).
fn row(scn: &Scenario, k: usize, floe: usize) -> usize {
    k * scn.floes.len() + floe
}

#[test]
fn every_small_case_passes_every_check_its_formulations_claim() {
    let start = Instant::now();
    let paths = batch::case_files(&[cases_dir()]).unwrap();
    assert!(paths.len() >= 12, "{} cases", paths.len());
    for p in &paths {
        let text = std::fs::read_to_string(p).unwrap();
        assert!(
            text.starts_with('#'),
            "{}: a case opens with a comment",
            p.display()
        );
    }
    let cases = batch::load_cases(&[cases_dir()]).unwrap_or_else(|e| panic!("{e}"));
    let comps =
        compare::compare(cases, &CompareOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let rows: Vec<CheckOutcome> = comps.into_iter().flat_map(|c| c.checks).collect();
    println!("{}", format_table(&rows));
    println!("check over cases/: {:.1} s", start.elapsed().as_secs_f64());
    assert_eq!(claimed_failures(&rows), 0, "claimed checks failed");
    // Every kind of check applied somewhere, and every formulation ran.
    for id in [
        "run_completed",
        "momentum",
        "impact_energy",
        "energy_conserved",
        "coulomb",
        "penetration",
        "symmetry",
        "head_on_v1",
        "head_on_v2",
        "bouncing_first_impact",
        "bouncing_rest",
        "sliding_distance",
        "sliding_stop",
        "cradle_outcome",
        "cradle_physical",
        "cannon_velocities",
        "free_drift_velocity",
        "energy_ledger",
        "fracture_conservation",
        "ram_critical_speed",
    ] {
        assert!(
            rows.iter().any(|o| o.check == id),
            "check `{id}` never applied"
        );
    }
    for formulation::Entry { name, .. } in formulation::REGISTRY {
        assert!(
            rows.iter().any(|o| o.formulation == *name),
            "{name} never ran"
        );
    }
    // free-drift only on contact-free cases; the mirror case is symmetric.
    assert!(!rows
        .iter()
        .any(|o| o.formulation == "free-drift" && o.case == "head_on"));
    assert!(rows
        .iter()
        .any(|o| o.case == "mirror_collision" && o.check == "symmetry"));
    // The Markdown table has a row per outcome.
    assert_eq!(markdown_table(&rows).lines().count(), rows.len() + 2);
}

#[test]
fn structure_decides_applicability() {
    // Symmetry: found on the mirror case (pairing 1 <-> 2), not on the pool.
    let (axis, pairing) = check::find_symmetry(&load("mirror_collision")).unwrap();
    assert_eq!(pairing, vec![0, 2, 1]);
    assert!(axis.d.y.abs() < 1e-12 && axis.c.y.abs() < 1e-12);
    assert!(check::find_symmetry(&load("elastic_pool")).is_none());
    // A Coriolis force breaks the mirror symmetry.
    let mut scn = load("mirror_collision");
    scn.environment.coriolis = 1e-4;
    assert!(check::find_symmetry(&scn).is_none());
    // Contact-free cases only for free-drift.
    assert!(load("free_drift_coriolis").contact_free());
    assert!(!load("head_on").contact_free());
    assert!(!batch::default_formulations(&load("head_on")).contains(&"free-drift"));
    // The bouncing floe's gap along the wind is 1 m, face on.
    let scn = load("bouncing_floe");
    let (gap, rays) =
        check::translation_gap(&scn, 0, &floebench::geometry::Vec2::new(1.0, 0.0)).unwrap();
    assert!((gap - 1.0).abs() < 1e-12 && rays >= 2);
}

#[test]
fn momentum_head_on_and_penetration_fail_on_wrong_input() {
    let scn = load("head_on");
    let r = run(&scn, "event-driven");
    // A momentum change: floe 0 a little faster at one output.
    fails_when_spoiled(&scn, &r, "momentum", |b| {
        let i = row(&scn, 30, 0);
        b.trajectory[i].vx += 1e-6;
    });
    // Wrong head-on velocities.
    fails_when_spoiled(&scn, &r, "head_on_v1", |b| {
        b.final_state.bodies[0].velocity.x += 1e-6;
    });
    fails_when_spoiled(&scn, &r, "head_on_v2", |b| {
        b.final_state.bodies[1].velocity.x -= 1e-6;
    });
    // A penetration: floe 1 moved 1 cm into floe 0 at the last output.
    fails_when_spoiled(&scn, &r, "penetration", |b| {
        let k = b.trajectory.len() / scn.floes.len() - 1;
        let (a, c) = (row(&scn, k, 0), row(&scn, k, 1));
        let gap = (b.trajectory[c].x - 10.0) - (b.trajectory[a].x + 5.0);
        b.trajectory[c].x -= gap + 0.01;
    });
    // A broken symmetry: floe 0 off the axis by 1 mm.
    fails_when_spoiled(&scn, &r, "symmetry", |b| {
        let i = row(&scn, 10, 0);
        b.trajectory[i].y += 1e-3;
    });
    // A run that did not complete.
    fails_when_spoiled(&scn, &r, "run_completed", |b| {
        b.summary.end = EndReason::Failed {
            message: "test".into(),
        };
    });
}

#[test]
fn energy_checks_fail_on_an_energy_gain() {
    let scn = load("elastic_pool");
    let r = run(&scn, "event-driven");
    fails_when_spoiled(&scn, &r, "energy_conserved", |b| {
        let k = b.energy.len() / 2;
        b.energy[k].kinetic *= 1.0 + 1e-6;
    });
    fails_when_spoiled(&scn, &r, "impact_energy", |b| {
        let e = b.contacts.events[3];
        b.contacts.push_event(ContactEvent {
            energy_after: e.energy_before * (1.0 + 1e-3),
            ..e
        });
    });
    fails_when_spoiled(&scn, &r, "energy_ledger", |b| {
        let k = b.energy.len() / 2;
        b.energy[k].residual = 1e-5 * b.summary.energy.exchanged;
        b.summary.energy.max_abs_residual = b.energy[k].residual;
    });
}

#[test]
fn coulomb_and_sliding_fail_on_wrong_input() {
    let scn = load("sliding_floe");
    let r = run(&scn, "event-driven");
    // A friction impulse just outside the cone.
    fails_when_spoiled(&scn, &r, "coulomb", |b| {
        b.contacts.push_impulse(ImpulseRecord {
            t: 1.0,
            normal: 100.0,
            tangent: 0.3 * 100.0 * (1.0 + 1e-6),
            mu: 0.3,
            slack: 0.0,
        });
    });
    fails_when_spoiled(&scn, &r, "sliding_distance", |b| {
        b.final_state.bodies[0].position.y += 0.01;
    });
    fails_when_spoiled(&scn, &r, "sliding_stop", |b| {
        // Still moving 10 s after the exact stop.
        for row in b
            .trajectory
            .iter_mut()
            .filter(|r| r.t > 690.0 && r.t < 702.0)
        {
            row.vy = 1e-3;
        }
    });
}

/// The Coulomb check holds each impulse to the accuracy its solver
/// guarantees: an impulse past the bound by less than its allowance (the
/// impulse of the accepted LCP residual) passes, one past it fails, and an
/// impulse beyond the log's kept records is judged as a kept one.
#[test]
fn coulomb_follows_each_impulses_allowance_kept_or_not() {
    let scn = load("sliding_floe");
    let r = run(&scn, "event-driven");
    let at = |ratio: f64, slack: f64| ImpulseRecord {
        t: 1.0,
        normal: 100.0,
        tangent: 0.3 * 100.0 * ratio,
        mu: 0.3,
        slack,
    };
    // 1 + 1.3e-8 of the bound (as the newcomer's channel measured), inside an
    // allowance of 1e-6 N·s: in the cone to the solver's accuracy.
    let mut inside = r.clone();
    inside.contacts.push_impulse(at(1.0 + 1.3e-8, 1e-6));
    let o = check_run(&scn, &inside);
    let c = find(&o, "coulomb");
    assert!(c.pass && c.measured < 1.0, "{c:#?}");
    // The same ratio with no residual allowance is outside.
    fails_when_spoiled(&scn, &r, "coulomb", |b| {
        b.contacts.push_impulse(at(1.0 + 1.3e-8, 0.0))
    });
    // Past the log's cap: the kept records are all inside, the late one is not.
    fails_when_spoiled(&scn, &r, "coulomb", |b| {
        for _ in 0..floebench::record::ContactLog::CAP {
            b.contacts.push_impulse(at(0.5, 0.0));
        }
        b.contacts.push_impulse(at(1.0 + 1e-6, 1e-6));
    });
}

/// The newcomer's 100-floe channel (issue 55): event-driven slides on the
/// cone's boundary to `1 + 1.7e-9` of the bound, inside its accepted LCP
/// residual, and `check` reports no claimed failure.
#[test]
fn the_newcomers_channel_has_no_claimed_failure() {
    let scn = load("fields/channel_100");
    let r = run(&scn, "event-driven");
    assert!(
        r.contacts.max_coulomb_ratio() > 1.0 + 1e-9,
        "the case exercises impulses on the cone's boundary beyond the bound's rounding"
    );
    let rows = check_run(&scn, &r);
    assert_eq!(claimed_failures(&rows), 0, "{rows:#?}");
}

#[test]
fn fracture_checks_fail_on_wrong_input() {
    let scn = load("fracture_ram");
    let r = run(&scn, "event-driven");
    // A split that changed a conserved quantity by 1e-9 relative.
    fails_when_spoiled(&scn, &r, "fracture_conservation", |b| {
        b.fractures[0].conservation = 1e-9;
    });
    // A first fracture whose measure is 1 % off the closed form's (the
    // critical speed 0.5 % off).
    fails_when_spoiled(&scn, &r, "ram_critical_speed", |b| {
        b.fractures[0].measure *= 1.01;
    });
    // No fracture at all above the critical speed.
    fails_when_spoiled(&scn, &r, "ram_critical_speed", |b| {
        b.fractures.clear();
    });
}

#[test]
fn the_head_on_law_follows_the_material_of_floes_broken_at_the_impact() {
    // head_on with a toughness so low that the impact breaks both floes:
    // the head-on law holds for each floe's material (the mass-weighted
    // velocity of its pieces), momentum being conserved by the split.
    let text = format!(
        "{}\n[fracture]\nmodel = \"energy\"\ntoughness = 0.01\n",
        case_text("head_on")
    );
    let scn = scenario(&text);
    for name in ["event-driven", "moreau"] {
        let r = run(&scn, name);
        assert!(!r.fractures.is_empty(), "{name}: no fracture");
        let rows = check_run(&scn, &r);
        for id in ["head_on_v1", "head_on_v2"] {
            let o = find(&rows, id);
            assert!(o.pass, "{name}: {o:#?}");
        }
        // One piece of floe 1 a little faster at the end: its material is
        // too.
        fails_when_spoiled(&scn, &r, "head_on_v2", |b| {
            let last = b.summary.t_reached;
            let floes = &b.floes;
            let row = b
                .trajectory
                .iter_mut()
                .find(|row| row.t == last && floes[row.floe].parent == Some(1))
                .unwrap_or_else(|| panic!("no piece of floe 1 at the end"));
            row.vx += 1e-3;
        });
    }
}

#[test]
fn bouncing_cradle_cannon_and_drift_fail_on_wrong_input() {
    let scn = load("bouncing_floe");
    let r = run(&scn, "event-driven");
    fails_when_spoiled(&scn, &r, "bouncing_first_impact", |b| {
        b.contacts.events[0].t += 2.0;
    });
    // bouncing_rest is not claimed by event-driven (default contact
    // distance); moreau-cone is checked on first impact too.
    let scn = load("cradle_gaps");
    let r = run(&scn, "event-driven");
    fails_when_spoiled(&scn, &r, "cradle_outcome", |b| {
        b.final_state.bodies[4].velocity.x *= 1.0 - 1e-6;
    });
    let scn = load("cradle_touching");
    let r = run(&scn, "moreau");
    fails_when_spoiled(&scn, &r, "cradle_outcome", |b| {
        b.final_state.bodies[0].velocity.x += 1e-6;
    });
    let scn = load("newtons_cannon");
    let r = run(&scn, "event-driven");
    fails_when_spoiled(&scn, &r, "cannon_velocities", |b| {
        b.final_state.bodies[1].velocity.x += 1e-6;
    });
    let scn = load("free_drift");
    let r = run(&scn, "free-drift");
    fails_when_spoiled(&scn, &r, "free_drift_velocity", |b| {
        b.final_state.bodies[0].velocity *= 1.0 + 1e-5;
    });
}

#[test]
fn bouncing_rest_passes_at_the_accumulation_time_and_fails_when_late() {
    // The rest check on a trajectory that reaches t_inf exactly: the
    // event-driven run with a tiny contact distance (impacts located at the
    // root of the gap), then spoiled by a late motion.
    let scn = scenario(
        &case_text("bouncing_floe").replace("friction = 0.0", "friction = 0.0\ndistance = 1e-9"),
    );
    let r = run(&scn, "event-driven");
    fails_when_spoiled(&scn, &r, "bouncing_rest", |b| {
        for row in b
            .trajectory
            .iter_mut()
            .filter(|r| r.t > 280.0 && r.t < 290.0)
        {
            row.vx = 1e-3;
        }
    });
}

#[test]
fn mirror_symmetry_fails_when_one_image_moves() {
    let scn = load("mirror_collision");
    let r = run(&scn, "event-driven");
    let good = check_run(&scn, &r);
    assert!(find(&good, "symmetry").pass);
    fails_when_spoiled(&scn, &r, "symmetry", |b| {
        let i = row(&scn, 150, 2);
        b.trajectory[i].theta += 1e-5;
    });
}

#[test]
fn a_first_impact_at_91_s_fails_for_91_097_s() {
    // The floe starts closer, so that its free flight reaches the wall at
    // 91 s: judged against the case's t1 = 91.097 s it must fail, although
    // it is within one output interval.
    let scn = load("bouncing_floe");
    let b = check::Bouncing::of(&scn).unwrap();
    let good = check_run(&scn, &run(&scn, "event-driven"));
    let o = find(&good, "bouncing_first_impact");
    assert!(o.pass && (o.measured - b.t1).abs() < 1e-9, "{o:#?}");
    let mut early = scn.clone();
    early.floes[0].position += b.dir * (b.gap - 0.5 * b.a * 91.0 * 91.0);
    for f in ["event-driven", "moreau"] {
        let rows = check_run(&scn, &run(&early, f));
        let o = find(&rows, "bouncing_first_impact");
        assert!((o.measured - 91.0).abs() < 1e-6, "{f}: {o:#?}");
        assert!(!o.pass && o.tolerance < b.t1 - 91.0, "{f}: {o:#?}");
    }
}

#[test]
fn inertial_period_is_the_coriolis_period_whatever_the_drag() {
    let scn = load("inertial_oscillation");
    let period = std::f64::consts::TAU / scn.environment.coriolis;
    let o = find(
        &check_run(&scn, &run(&scn, "event-driven")),
        "inertial_period",
    )
    .clone();
    assert!(
        o.pass && (o.measured - period).abs() < 1e-9 * period,
        "{o:#?}"
    );
    // Twice the water drag: smaller circles, the same period.
    let mut drag = scn.clone();
    drag.environment.water.drag *= 2.0;
    let o = find(
        &check_run(&drag, &run(&drag, "event-driven")),
        "inertial_period",
    )
    .clone();
    assert!(
        o.pass && (o.measured - period).abs() < 1e-9 * period,
        "{o:#?}"
    );
    // A Coriolis force 1 % too strong, or turning the wrong way, fails.
    for factor in [1.01, -1.0] {
        let mut wrong = scn.clone();
        wrong.environment.coriolis *= factor;
        let rows = check_run(&scn, &run(&wrong, "event-driven"));
        let o = find(&rows, "inertial_period");
        assert!(!o.pass, "f × {factor}: {o:#?}");
    }
}

#[test]
fn reasons_explain_failing_rows_only() {
    let scn = load("bouncing_floe");
    let rows = check_run(&scn, &run(&scn, "rapier"));
    let entry = formulation::entry("rapier").unwrap();
    for o in rows.iter().filter(|o| !o.claimed) {
        let reason = entry.not_claimed(&o.check, &o.case).unwrap();
        assert_eq!(o.note.contains(reason), !o.pass, "{o:#?}");
    }
    // rapier's penetration stays within the tolerance here: a pass without
    // its reason; its symmetry fails, with it.
    assert!(find(&rows, "penetration").pass);
    assert!(!find(&rows, "symmetry").pass);
}

/// A printed verdict agrees with the numbers printed beside it: a value
/// that fails against a tolerance it rounds to is printed with the digits
/// that tell them apart (issue 55: `1.000` against `1.000`, FAIL).
#[test]
fn a_failing_value_is_printed_apart_from_its_tolerance() {
    use floebench::report::format::fmt_apart;
    let (m, t) = fmt_apart(1.000_000_012_9, 1.000_000_001);
    assert_ne!(m, t);
    assert!(
        m.starts_with("1.00000001") && t.starts_with("1.00000000"),
        "{m} {t}"
    );
    // Values that print apart, or are equal, keep the four digits.
    assert_eq!(fmt_apart(0.5, 1.0), ("0.5000".into(), "1.000".into()));
    assert_eq!(fmt_apart(1.0, 1.0), ("1.000".into(), "1.000".into()));
}
