//! The Moreau–Jean formulation (`moreau`, `moreau-cone`) against the closed
//! forms of docs/physics.md §6. Every run also goes through the shared
//! physical checks: completed, Coulomb on every contact impulse, no
//! unresolved contact problem, and a penetration within the scheme's
//! `O(h × approach speed)` (Moreau–Jean does not project positions).
//!
//! Measured figures are printed (`cargo test --release --test suite
//! moreau:: -- --nocapture`) and pinned where they are findings rather
//! than tolerances.

use crate::common::{
    assert_head_on, bouncing_expected, case_text, counter, drift_velocity, final_velocity, head_on,
    head_on_expected, rest_time_below, run, scenario, setting, sliding_expected, tempdir,
    with_formulation_table, Bouncing, Sliding,
};
use floebench::contact::cone::{solve_cone, ConeOptions, ConeStatus};
use floebench::contact::problem::{groups, spare_matrix_capacity, ContactLcp, Friction, Gen};
use floebench::contact::{BroadPhase, NarrowOptions};
use floebench::formulation::contact_solver::SolverKind;
use floebench::formulation::moreau::Moreau;
use floebench::formulation::moreau::MoreauSettings;
use floebench::formulation::{build, FormulationOptions};
use floebench::lcp::{residual, solve, LcpDump, SolveOptions};
use floebench::model::Scenario;
use floebench::record::SettingValue;
use floebench::run::{EndReason, RunOptions, RunResult, Runner};
use floebench::state::{detect_contacts_with, normal_velocity, System};

const SOLVERS: [SolverKind; 2] = [SolverKind::Lcp, SolverKind::Cone];

/// The case text with a `[formulation.moreau]` table (step `h`, s).
fn with_step(text: &str, h: f64) -> String {
    with_formulation_table(text, "moreau", &format!("step = {h:?}"))
}

/// Runs `scn` with the given solver; `v_approach` bounds the normal approach
/// speed of any contact in the case (m/s), for the penetration check.
fn run_checked(scn: &Scenario, solver: SolverKind, v_approach: f64) -> (RunResult, Moreau) {
    run_with(scn, solver, v_approach, FormulationOptions::default())
}

fn run_with(
    scn: &Scenario,
    solver: SolverKind,
    v_approach: f64,
    opts: FormulationOptions,
) -> (RunResult, Moreau) {
    let mut mj = Moreau::new(scn, &opts, Some(solver)).unwrap();
    let label = match solver {
        SolverKind::Lcp => "moreau",
        SolverKind::Cone => "moreau-cone",
    };
    let r = Runner::new(RunOptions::default()).run(scn, label, &mut mj);
    physical_checks(&r, solver, v_approach);
    (r, mj)
}

/// Checks that apply to every run.
fn physical_checks(r: &RunResult, solver: SolverKind, v_approach: f64) {
    let s = &r.summary;
    let name = format!("{} / {}", s.case, s.formulation);
    assert_eq!(s.end, EndReason::Completed, "{name}");
    let mut bad = vec!["coulomb_violations", "lcp_unresolved"];
    if solver == SolverKind::Cone {
        bad.push("cone_failed");
    }
    for bad in bad {
        assert_eq!(counter(r, bad), 0.0, "{name}: {bad}");
    }
    // |β| ≤ μ λ for every contact impulse: Lemke's accepted solutions to 1e-9
    // relative; the cone's are projected onto the cone.
    let ratio = counter(r, "max_coulomb_ratio");
    assert!(ratio <= 1.0 + 1e-9, "{name}: Coulomb ratio {ratio}");
    assert_eq!(
        s.settings
            .0
            .iter()
            .find(|x| x.name == "solver")
            .map(|x| &x.value),
        Some(&SettingValue::Text(solver.name().to_string())),
        "{name}"
    );
    // Moreau–Jean does not project positions: a contact activated at a
    // predicted gap g + hγu_N ≤ 0 ends its step at most h |u_N| deep.
    let h = setting(r, "step_s");
    let pen = counter(r, "max_penetration_m");
    assert!(
        pen <= h * v_approach,
        "{name}: penetration {pen} m beyond h v = {}",
        h * v_approach
    );
}

#[test]
fn head_on_impact_matches_the_closed_form_in_one_step_of_contact() {
    for solver in SOLVERS {
        for e in [0.0, 0.4, 1.0] {
            let scn = head_on(e);
            let (v1p, v2p) = head_on_expected(&scn, e);
            let (r, mj) = run_checked(&scn, solver, 0.6);
            assert_eq!(
                mj.contact_steps().len(),
                1,
                "{solver:?} e = {e}: one step of contact"
            );
            let (a, b) = (final_velocity(&r, 0), final_velocity(&r, 1));
            eprintln!(
                "head-on {solver:?} e = {e}: v1' error {:.1e}, v2' error {:.1e} m/s",
                a.x - v1p,
                b.x - v2p
            );
            assert_head_on(&r, &scn, e, &format!("{solver:?} e = {e}"));
            // The contact step: the output interval 0.5 s cuts h = 1 s into
            // steps of 0.5 s; the gap 5 − 0.3k is first closed (predicted
            // gap ≤ 0) at the step from t = 8.5 s.
            assert_eq!(mj.contact_steps()[0].t, 8.5);
            assert_eq!(mj.contact_steps()[0].h, 0.5);
        }
    }
}

#[test]
fn bouncing_floe_passes_the_accumulation_point_and_rests_at_the_wall() {
    let scn = scenario(&case_text("bouncing_floe"));
    let Bouncing { a, t1, v1, t_inf } = bouncing_expected(&scn);
    let h = MoreauSettings::of(&scn).unwrap().step;
    for solver in SOLVERS {
        let (r, mj) = run_checked(&scn, solver, v1);
        // Rest: speed below 1e-3 of a h, the speed the wind gives in one
        // step (the scheme's velocity resolution). Measured: 276 s for
        // t∞ = 273.3 s. After the last bounce, Newton's law on the active,
        // penetrated contact alternates u⁺ = −e u⁻ with a factor e per
        // step: the speed reaches 1e-12 m/s only at 294 s (lcp), a
        // sub-micrometre motion.
        let rest = rest_time_below(&r, 1e-3 * a * h);
        eprintln!(
            "bouncing {solver:?}: rest (|v| <= 1e-3 a h) at {rest} s, (|v| <= 1e-12 m/s) at {} s, t_inf {t_inf:.2} s, {} contact steps",
            rest_time_below(&r, 1e-12),
            mj.contact_steps().len()
        );
        assert!(
            (rest - t_inf).abs() <= 3.0 * h,
            "{solver:?}: rest at {rest} vs t_inf {t_inf}"
        );
        // The first impact is in the step that contains t1 (= 91.09 s).
        let first = mj.contact_steps()[0].t;
        assert!(
            first <= t1 && t1 < first + 2.0 * h,
            "{solver:?}: first impact step {first} vs t1 {t1}"
        );
        // At rest against the wall (x = 6 touches it): penetrated by less
        // than h times the last approach speeds, and no drift afterwards
        // beyond O(h): measured drift below 1e-6 m after t∞ + 2h.
        let x_end = r.final_state.bodies[0].position.x;
        let gap = 6.0 - x_end;
        assert!(gap <= 0.0 && -gap <= h * 1e-3, "{solver:?}: gap {gap}");
        let drift = r
            .trajectory
            .iter()
            .filter(|row| row.t >= t_inf + 2.0 * h)
            .map(|row| (row.x - x_end).abs())
            .fold(0.0, f64::max);
        eprintln!("bouncing {solver:?}: end gap {gap:.4e} m, drift after t_inf + 2h {drift:.2e} m");
        assert!(drift <= 1e-6, "{solver:?}: drift {drift}");
        assert!(r.final_state.bodies[0].velocity.norm() == 0.0 || rest < scn.duration);
    }
}

/// Stop time (s, on the step grid) and sliding distance (m) of the sliding
/// floe run with step `h` (output every step).
fn sliding(h: f64, solver: SolverKind) -> (f64, f64, RunResult) {
    let text = with_step(&case_text("sliding_floe"), h)
        .replace("output_interval = 1.0", &format!("output_interval = {h:?}"));
    let scn = scenario(&text);
    let (r, _) = run_checked(&scn, solver, 0.05);
    let stop = rest_time_below(&r, 1e-12);
    let y = r.final_state.bodies[0].position.y - 5.0;
    (stop, y, r)
}

#[test]
fn sliding_floe_stops_within_o_h_and_converges_at_second_order() {
    let scn = scenario(&case_text("sliding_floe"));
    let Sliding {
        a,
        mu,
        t_stop,
        dist,
        ..
    } = sliding_expected(&scn);
    let mut errors = Vec::new();
    for h in [1.0, 0.5, 0.25, 0.125] {
        let (stop, y, r) = sliding(h, SolverKind::Lcp);
        // The stop lands on the step grid: the first step end after t_stop.
        assert!(
            stop >= t_stop && stop - t_stop <= h * (1.0 + 1e-9),
            "h = {h}: stop {stop} vs {t_stop}"
        );
        // Trapezoidal positions are exact while the floe decelerates at μa;
        // only the last step, where it sticks, errs: with f the fractional
        // part of t_stop / h, the distance error is ½ μ a h² f (1 − f)
        // ≤ μ a h² / 8 (second order).
        let f = (t_stop / h).fract();
        let predicted = 0.5 * mu * a * h * h * f * (1.0 - f);
        let err = y - dist;
        assert!(
            (err - predicted).abs() <= 1e-3 * predicted + 1e-12,
            "h = {h}: distance error {err:e} vs predicted {predicted:e}"
        );
        assert!(err.abs() <= mu * a * h * h / 8.0 + 1e-12);
        // Pressed on the wall: no drift into or away from it.
        for row in &r.trajectory {
            assert!((row.x - 5.0).abs() < 1e-9, "h = {h}: x drift at {}", row.t);
        }
        errors.push((h, stop - t_stop, err));
    }
    for w in errors.windows(2) {
        eprintln!(
            "sliding lcp h = {} -> {}: stop error {:.4} -> {:.4} s, distance error {:.3e} -> {:.3e} m, order {:.2}",
            w[0].0,
            w[1].0,
            w[0].1,
            w[1].1,
            w[0].2,
            w[1].2,
            (w[0].2 / w[1].2).log2()
        );
    }
    // Over three halvings the distance error falls by 2^6: order 2.00
    // (single halvings measure 3.37, 1.18, 1.46: f changes with h).
    let order = (errors[0].2 / errors[3].2).log2() / 3.0;
    eprintln!("sliding lcp: distance order over three halvings {order:.3}");
    assert!((order - 2.0).abs() < 0.05, "order {order}");
}

#[test]
fn elastic_frictionless_pool_keeps_its_kinetic_energy_at_every_step() {
    // Newton's law with e = 1 on every active contact: each pushing contact
    // has u_N⁺ = −u_N⁻, so the impulses do no work; a finite step loses
    // nothing (measured: |ΔE|/E ≤ 1e-15 with Lemke, 3e-11 with clarabel).
    let scn = scenario(&case_text("elastic_pool"));
    let e0 = floebench::state::System::initial(&scn).kinetic_energy(&scn);
    for (solver, tol) in [(SolverKind::Lcp, 1e-13), (SolverKind::Cone, 1e-9)] {
        // Floes up to 1.1 m/s and 0.05 rad/s at radii below 7 m: relative
        // approach speeds below 3 m/s.
        let (r, mj) = run_checked(&scn, solver, 3.0);
        assert!(mj.contact_steps().len() >= 100, "{solver:?}: few contacts");
        let worst = r
            .energy
            .iter()
            .map(|s| (s.kinetic - e0) / e0)
            .fold(0.0f64, |m, d| if d.abs() > m.abs() { d } else { m });
        eprintln!(
            "pool {solver:?}: {} contact steps, worst relative energy change {worst:.2e}, max penetration {:.3} m (h = 1 s)",
            mj.contact_steps().len(),
            mj.max_penetration()
        );
        assert!(worst.abs() <= tol, "{solver:?}: energy change {worst}");
        for row in &r.trajectory {
            assert!((-1.5..101.5).contains(&row.x) && (-1.5..101.5).contains(&row.y));
        }
    }
}

/// The largest difference between two lists of generalised velocities.
fn largest_difference(a: &[Gen], b: &[Gen]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f64, f64::max)
}

/// The contact problems of a scenario's floes at t = 0 within `distance` m
/// (gaps ignored), with the case velocities as free velocities, friction
/// assembled per point.
pub(crate) fn problems_at_start(scn: &Scenario, distance: f64) -> (Vec<ContactLcp>, Vec<Gen>) {
    problems_with(scn, distance, Friction::PerPoint, &NarrowOptions::default())
}

/// [`problems_at_start`] with the friction `layout` and the contact point
/// tolerances `options`.
pub(crate) fn problems_with(
    scn: &Scenario,
    distance: f64,
    layout: Friction,
    options: &NarrowOptions,
) -> (Vec<ContactLcp>, Vec<Gen>) {
    let n = scn.floes.len();
    let sys = System::initial(scn);
    let mut cs = Vec::new();
    detect_contacts_with(
        scn,
        &sys.bodies,
        distance,
        options,
        &mut BroadPhase::new(),
        &mut cs,
    );
    let centres = sys.centres();
    let w: Vec<Gen> = sys.velocities();
    // A Newton offset e u_N on every contact, as in the formulation.
    let offsets: Vec<f64> = cs
        .iter()
        .map(|c| 0.5 * normal_velocity(scn, &sys.bodies, c))
        .collect();
    let lcps = groups(&cs, n)
        .iter()
        .map(|g| ContactLcp::assemble(scn, &centres, &cs, g, &w, &offsets, layout))
        .collect();
    (lcps, w)
}

#[test]
fn cone_solver_agrees_with_lemke_on_frictionless_problems() {
    // Frictionless, the cone program is the LCP: the post-contact velocities
    // must agree to 1e-8 of the velocity scale. Problems: the elastic pool
    // with a 12 m detection distance (one group of 46 contacts, many with
    // λ = 0) and a 5 m one (several small groups), Newton's cradle touching.
    let mut checked = 0;
    let mut worst = 0.0f64;
    for (name, distance) in [
        ("elastic_pool", 12.0),
        ("elastic_pool", 5.0),
        ("cradle_touching", 0.01),
    ] {
        let scn = scenario(&case_text(name).replace("friction = 0.3", "friction = 0.0"));
        assert_eq!(scn.contact.friction, 0.0);
        let (lcps, w) = problems_at_start(&scn, distance);
        let v_scale = w.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for lcp in &lcps {
            assert!(!lcp.friction);
            let lemke = solve(lcp.lcp(), &SolveOptions::default());
            assert!(lemke.status.is_solved());
            let cone = solve_cone(&lcp.normal_tangent(), &ConeOptions::default());
            assert_eq!(
                cone.status,
                ConeStatus::Solved,
                "{name}: {}",
                cone.solver_status
            );
            let z = lcp.z_from_impulses(&cone.lambda, &cone.beta);
            let err =
                largest_difference(&lcp.velocity_changes(&lemke.z), &lcp.velocity_changes(&z));
            worst = worst.max(err / v_scale);
            assert!(
                err <= 1e-8 * v_scale,
                "{name} ({} contacts): velocities differ by {err:e}",
                lcp.m
            );
            checked += 1;
        }
    }
    eprintln!("cone vs lemke, frictionless: {checked} problems, worst velocity difference {worst:.2e} of the velocity scale");
    assert!(checked >= 5);
    // And along a run: the head-on impact without friction.
    let scn = scenario(&case_text("head_on").replace("friction = 0.3", "friction = 0.0"));
    let (a, _) = run_checked(&scn, SolverKind::Lcp, 0.6);
    let (b, _) = run_checked(&scn, SolverKind::Cone, 0.6);
    for i in 0..2 {
        let d = (final_velocity(&a, i) - final_velocity(&b, i)).norm();
        assert!(d <= 1e-8 * 0.5, "head-on floe {i}: {d}");
    }
}

#[test]
fn cone_relaxation_lets_a_sliding_contact_separate_at_mu_u_t() {
    // The documented artefact of the Anitescu–Tasora relaxation: in the
    // first step of the sliding floe the cone solution pushes the floe off
    // the wall at u_N = μ |u_T| (0.3 × 0.0458 = 0.0137 m/s), where the LCP
    // keeps it on the wall (u_N = 0).
    let scn = scenario(&case_text("sliding_floe").replace("duration = 1000.0", "duration = 1.0"));
    let mu = scn.contact.friction;
    let (lcp, _) = run_checked(&scn, SolverKind::Lcp, 0.05);
    let (cone, mj) = run_checked(&scn, SolverKind::Cone, 0.05);
    let (vl, vc) = (final_velocity(&lcp, 0), final_velocity(&cone, 0));
    // The wall is at +x: the floe's normal separation speed is −vx.
    assert!(vl.x.abs() < 1e-12, "lcp leaves the wall: {}", vl.x);
    let sep = -vc.x;
    eprintln!(
        "cone artefact, first step: separation {sep:.6e} m/s, mu |u_T| = {:.6e} m/s (lcp: {:.1e}); tangential speed lcp {:.6e}, cone {:.6e} m/s",
        mu * vc.y.abs(),
        -vl.x,
        vl.y,
        vc.y
    );
    assert!(
        (sep - mu * vc.y.abs()).abs() <= 1e-8 * sep,
        "separation {sep} vs mu |u_T| {}",
        mu * vc.y.abs()
    );
    // The counter reports it, with the Newton offset (e = 0 here).
    let reported = counter(&cone, "cone_max_pushing_normal_speed_m_per_s");
    let _ = &mj;
    assert!((reported - sep).abs() <= 1e-8 * sep, "counter {reported}");
    // Friction saturates the cone in both, so the tangential speed loses
    // μ × (normal impulse)/M: the cone's normal impulse also carries the
    // separation, M μ |u_T|, so it slides slower after one step.
    assert!(vc.y < vl.y);
}

#[test]
fn sliding_floe_with_the_cone_flies_off_the_wall_and_still_stops() {
    // Measured consequence of the artefact over the whole run (h = 1 s): the
    // floe leaves the wall, flies up to 0.40 m away, lands, slides and
    // leaves again; it stops at the same step as the LCP (692 s) within
    // 1.1e-5 m of the exact distance.
    let scn = scenario(&case_text("sliding_floe"));
    let Sliding { dist, .. } = sliding_expected(&scn);
    let (r, mj) = run_checked(&scn, SolverKind::Cone, 0.05);
    let x_min = r
        .trajectory
        .iter()
        .map(|row| row.x)
        .fold(f64::INFINITY, f64::min);
    let y = r.final_state.bodies[0].position.y - 5.0;
    let stop = rest_time_below(&r, 1e-12);
    eprintln!(
        "sliding cone: lifts off by {:.3} m, {} contact steps of 1000, stops at {stop} s after {y:.6} m (exact {dist:.6} m)",
        5.0 - x_min,
        mj.contact_steps().len()
    );
    assert!(5.0 - x_min > 0.3, "the floe must lift off: {}", 5.0 - x_min);
    assert!(mj.contact_steps().len() < 500);
    assert!((y - dist).abs() < 1e-4, "distance {y} vs {dist}");
}

#[test]
fn every_lcp_of_a_moreau_run_can_be_dumped_and_re_solved() {
    let dir = tempdir();
    let scn = scenario(&case_text("sliding_floe").replace("duration = 1000.0", "duration = 5.0"));
    let (r, _) = run_with(
        &scn,
        SolverKind::Lcp,
        0.05,
        FormulationOptions {
            dump_lcp: Some(dir.path().to_path_buf()),
            ..Default::default()
        },
    );
    let files: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(files.len() as f64, counter(&r, "lcp_solves"));
    assert_eq!(files.len(), 5, "one LCP per step");
    for f in &files {
        let d = LcpDump::read(f).unwrap();
        let lcp = d.to_lcp().unwrap();
        // Stewart–Trinkle: 4 unknowns per contact, 3 fewer per extra member
        // of a friction group (flush edge pairs, docs/physics.md §3.1).
        let groups = d.friction_groups.unwrap_or(d.contacts);
        assert!(groups <= d.contacts);
        assert_eq!(lcp.n, d.contacts + 3 * groups);
        assert!(residual(&lcp.m, &lcp.q, &d.z) < 1e-10);
    }
}

#[test]
fn names_and_the_case_solver_key_choose_the_solver() {
    let text = case_text("head_on");
    let scn = scenario(&text);
    let opts = FormulationOptions::default();
    assert_eq!(build("moreau", &scn, &opts).unwrap().name(), "moreau");
    assert_eq!(
        build("moreau-cone", &scn, &opts).unwrap().name(),
        "moreau-cone"
    );
    // The case has a [formulation.moreau] table (step = 0.5): its step and
    // solver replaced.
    let cone_case = scenario(&text.replacen("step = 0.5", "step = 0.25\nsolver = \"cone\"", 1));
    let s = MoreauSettings::of(&cone_case).unwrap();
    assert_eq!(s.solver, SolverKind::Cone);
    assert_eq!(s.step, 0.25);
    // The label comes from the registry entry, not from the solver in use:
    // `-f moreau` on a cone case is labelled `moreau` (its `solver` setting
    // says cone), so `-f moreau,moreau-cone` gives two labels.
    assert_eq!(build("moreau", &cone_case, &opts).unwrap().name(), "moreau");
    let r = run(&cone_case, "moreau");
    assert_eq!(r.summary.formulation, "moreau");
    assert!(counter(&r, "cone_solves") > 0.0);
}

#[test]
fn field_against_the_coast_runs_with_both_solvers_and_balances_its_ledger() {
    // 75 minutes of the 200-floe field (h = 1 s): the floes reach the coast
    // and pile up. Water drag and Coriolis make the ledger residual nonzero;
    // it measures the θ-method's energy error against the trapezoidal power
    // of each force.
    let scn = scenario(
        &case_text("fields/field_200_coast").replace("duration = 21600.0", "duration = 4500.0"),
    );
    for solver in SOLVERS {
        // Drift below 0.5 m/s: approach speeds below 1 m/s.
        let (r, mj) = run_checked(&scn, solver, 1.0);
        let e = &r.summary.energy;
        let groups = counter(&r, "contact_groups");
        let failed = counter(&r, "lcp_failed");
        // Kept by the cone solver only; none without it.
        let cone_fallbacks = if solver == SolverKind::Cone {
            counter(&r, "cone_fallback_lcp")
        } else {
            0.0
        };
        eprintln!(
            "field 75 min {solver:?}: {} contact steps, {groups} contact problems, {failed} Lemke failures (frictionless last resort), {} cone fallbacks, residual {:.3e} J of {:.3e} J exchanged, penetration {:.3} m",
            mj.contact_steps().len(),
            cone_fallbacks,
            e.max_abs_residual,
            e.exchanged,
            mj.max_penetration()
        );
        assert!(groups > 1000.0);
        assert!(e.max_abs_residual <= 1e-6 * e.exchanged);
        if solver == SolverKind::Lcp {
            // With the Coulomb rows in velocity units, Lemke's solutions pass
            // the residual check: measured 2 failures of 5,933 problems with
            // that row scaling alone (1,623 unscaled, all rejected on
            // rounding), 7 of 5,933 once the whole LCP is also scaled by the
            // mean Delassus diagonal (shared with the event-driven scheme,
            // where it took failures from 26 % to 0.05 %). Pinned at 0.2 %;
            // each failure goes to the counted frictionless last resort.
            assert!(failed * 500.0 <= groups, "{failed} of {groups} failed");
        }
    }
}

#[test]
fn free_drift_reaches_the_analytic_velocity_and_the_ledger_error_falls_with_h() {
    // No contact: the θ-method alone. Its fixed point is the exact steady
    // drift u = U_w + sqrt(ρ_a C_a / (ρ_w C_w)) U_a (the forces vanish
    // there). With θ = ½ (Heun) the ledger residual (the energy error of the
    // smooth step against the trapezoidal power) falls at least at second
    // order: measured 1.35e-10, 1.69e-11, 2.13e-12 of the exchanged energy
    // for h = 4, 2, 1 s (order 3.0).
    let text = case_text("free_drift");
    let scn = scenario(&text);
    let u = drift_velocity(&scn);
    let mut residuals = Vec::new();
    for h in [4.0, 2.0, 1.0] {
        let scn = scenario(&with_step(&text, h));
        let (r, mj) = run_checked(&scn, SolverKind::Lcp, 0.0);
        assert!(mj.contact_steps().is_empty());
        let v = final_velocity(&r, 0);
        assert!((v - u).norm() <= 1e-9 * u.norm(), "h = {h}: {v:?} vs {u:?}");
        let e = &r.summary.energy;
        residuals.push(e.max_abs_residual / e.exchanged);
    }
    let shown: Vec<String> = residuals.iter().map(|r| format!("{r:.3e}")).collect();
    eprintln!(
        "free drift: ledger residual / exchanged for h = 4, 2, 1 s: {}",
        shown.join(", ")
    );
    for w in residuals.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 1.8, "ledger error order {order}");
    }
}

#[test]
fn block_sparse_assembly_equals_the_dense_product() {
    // The Delassus block of every group of real packs (several floes, walls,
    // shores and coast as obstacles, with and without friction) against the
    // dense faer product over every row of H that the assembly used before,
    // and the assembly's own block (the block-sparse sum) against both.
    // Each entry is now one fused sum over its non-zero terms in row order;
    // the dense product splits the rows of H into cache blocks (of a size
    // chosen by the CPU's caches) and adds the blocks' sums, so on groups
    // larger than one block an entry may differ by one rounding. Small
    // groups (at most 64 rows of H, within any block) must agree bit for
    // bit, large ones to 1e-15 of sqrt(G_rr G_cc) (the scale of the terms);
    // the assembled LCP holds the block-sparse sum, bit for bit.
    let mut groups_checked = 0;
    let mut multi_floe = 0;
    let mut with_obstacle = 0;
    let mut coupled_entries = 0usize;
    let mut large_differing = 0usize;
    let mut impulse_entries = 0usize;
    let mut with_columns = 0usize;
    for (name, distance, frictionless) in [
        ("elastic_pool", 12.0, true),
        ("narrow_channel", 6.0, false),
        ("narrow_channel", 6.0, true),
        ("l_shaped_corner", 3.0, false),
        ("fields/bay_jam_200", 30.0, false),
        ("fields/bay_jam_200", 30.0, true),
    ] {
        let mut text = case_text(name);
        if frictionless {
            text = without_friction(&text);
        }
        let scn = scenario(&text);
        assert_eq!(scn.contact.friction == 0.0, frictionless, "{name}");
        let (lcps, _) = problems_at_start(&scn, distance);
        for lcp in &lcps {
            let reference = lcp.dense_delassus_reference();
            let sparse = lcp.block_sparse_delassus();
            let cols = if lcp.friction { 3 * lcp.m } else { lcp.m };
            let n = lcp.lcp().n;
            let small = 3 * lcp.floes.len() <= 64;
            for r in 0..cols {
                for c in 0..cols {
                    let want = reference[r * cols + c];
                    let got = sparse[r * cols + c];
                    assert_eq!(lcp.lcp().m[r * n + c].to_bits(), got.to_bits());
                    let bound = 1e-15 * (reference[r * cols + r] * reference[c * cols + c]).sqrt();
                    let same = got.to_bits() == want.to_bits();
                    assert!(
                        same || (!small && (got - want).abs() <= bound),
                        "{name}: entry ({r}, {c}) of a group of {} floes: {got:e} vs {want:e}",
                        lcp.floes.len()
                    );
                    large_differing += usize::from(!same);
                    coupled_entries += usize::from(r != c && want != 0.0);
                }
            }
            // The compressed columns built at assembly from the pattern
            // against a scan of every entry of the matrix.
            if let Some(same) = lcp.columns_match_a_full_scan() {
                assert!(
                    same,
                    "{name}: columns of a group of {} unknowns",
                    lcp.lcp().n
                );
                with_columns += 1;
            }
            // The impulses summed over each floe's own columns against the
            // row sums over every column, for a z with zeros and spread
            // magnitudes, and for the frictionless sub-problem.
            for sub in [lcp.clone(), lcp.frictionless()] {
                let z: Vec<f64> = (0..sub.lcp().n)
                    .map(|k| {
                        if k % 3 == 1 {
                            0.0
                        } else {
                            10f64.powi((k % 7) as i32 - 3) * (1.0 + k as f64)
                        }
                    })
                    .collect();
                let got = sub.impulses(&z);
                let want = sub.dense_impulses_reference(&z);
                assert_eq!(got.len(), want.len());
                for (g, w) in got.iter().zip(&want) {
                    for d in 0..3 {
                        // The same number (a zero may differ in sign).
                        assert!(g[d] == w[d], "{name}: {g:?} vs {w:?}");
                        assert!(g[d] == 0.0 || g[d].to_bits() == w[d].to_bits());
                    }
                    impulse_entries += g.iter().filter(|x| **x != 0.0).count();
                }
            }
            groups_checked += 1;
            multi_floe += usize::from(lcp.floes.len() >= 3);
            with_obstacle += usize::from(
                lcp.keys
                    .iter()
                    .any(|k| k.a >= scn.floes.len() || k.b >= scn.floes.len()),
            );
        }
    }
    assert_eq!(groups_checked, 6);
    assert!(
        multi_floe >= 5,
        "{multi_floe} groups of three floes or more"
    );
    assert!(
        with_obstacle >= 1,
        "{with_obstacle} groups touching an obstacle"
    );
    assert!(
        coupled_entries >= 100_000,
        "{coupled_entries} coupled entries"
    );
    assert!(with_columns >= 4, "{with_columns} groups with columns");
    assert!(
        impulse_entries >= 2_000,
        "{impulse_entries} non-zero impulse entries"
    );
    eprintln!("{large_differing} entries of the large groups differ by one rounding");
}

#[test]
fn the_driver_residual_of_large_lcps_equals_the_dense_compensated_sum() {
    // Above 64 unknowns the driver computes w = M z + q over the compressed
    // columns of M; its w must be the dense compensated sum's, bit for bit
    // (up to the sign of a zero), on real contact LCPs: the frictional
    // elastic pool (184 unknowns) and the frictionless bay jam (980).
    let pool = case_text("elastic_pool").replace("friction = 0.0", "friction = 0.3");
    let bay = without_friction(&case_text("fields/bay_jam_200"));
    let mut large = 0;
    for (text, distance) in [(pool, 12.0), (bay, 30.0)] {
        let (lcps, _) = problems_at_start(&scenario(&text), distance);
        for lcp in lcps.iter().filter(|l| l.lcp().n > 64) {
            // Every contact approaching (the packs start at rest or slow).
            let mut l = lcp.lcp().clone();
            for (j, q) in l.q.iter_mut().take(lcp.m).enumerate() {
                *q -= 0.1 * (1.0 + (j % 3) as f64);
            }
            let sol = solve(&l, &SolveOptions::default());
            assert!(sol.z.iter().filter(|z| **z != 0.0).count() >= 10);
            let dense = floebench::lcp::compute_w(&l.m, &l.q, &sol.z).unwrap();
            for (i, (a, b)) in sol.w.iter().zip(&dense).enumerate() {
                assert!(
                    a.to_bits() == b.to_bits() || (*a == 0.0 && *b == 0.0),
                    "n = {}, row {i}: {a:e} vs {b:e}",
                    lcp.lcp().n
                );
            }
            large += 1;
        }
    }
    assert!(large >= 2, "{large} large LCPs");
}

/// A case text with its `friction` line set to 0.
#[test]
fn recycled_matrix_buffers_assemble_the_same_lcps() {
    // A dropped large LCP zeroes the pattern of its matrix and leaves the
    // buffer for the next large assembly on its thread. The bay jam's
    // groups, with friction (merged and per point) and without, each
    // assembled on a fresh thread (no spare buffer) and all of them one
    // after another on one thread (each set on the buffer the previous set
    // left): the same matrices and right-hand sides, bit for bit.
    type Bits = Vec<(usize, Vec<u64>, Vec<u64>)>;
    fn assembled(frictionless: bool, layout: Friction) -> Bits {
        let mut text = case_text("fields/bay_jam_200");
        if frictionless {
            text = without_friction(&text);
        }
        let scn = scenario(&text);
        let (lcps, _) = problems_with(&scn, 30.0, layout, &NarrowOptions::default());
        lcps.iter()
            .map(|l| {
                let p = l.lcp();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect();
                (p.n, bits(&p.m), bits(&p.q))
            })
            .collect()
    }
    let sets = [
        (false, Friction::Merged),
        (true, Friction::Merged),
        (false, Friction::PerPoint),
        (false, Friction::Merged),
    ];
    let fresh: Vec<Bits> = sets
        .iter()
        .map(|&(f, l)| {
            std::thread::spawn(move || {
                assert_eq!(spare_matrix_capacity(), 0, "a new thread has no spare");
                assembled(f, l)
            })
            .join()
            .unwrap()
        })
        .collect();
    let (reused, spares) = std::thread::spawn(move || {
        let mut spares = Vec::new();
        let reused: Vec<Bits> = sets
            .iter()
            .map(|&(f, l)| {
                let out = assembled(f, l);
                spares.push(spare_matrix_capacity());
                out
            })
            .collect();
        (reused, spares)
    })
    .join()
    .unwrap();
    // Large groups were assembled, and each set left a buffer.
    let large = fresh.iter().flatten().filter(|(n, _, _)| *n >= 41).count();
    assert!(large >= 4, "{large} large groups");
    assert!(spares.iter().all(|&c| c > 0), "spare capacities {spares:?}");
    for (k, (a, b)) in fresh.iter().zip(&reused).enumerate() {
        assert_eq!(a.len(), b.len(), "set {k}");
        for (g, (x, y)) in a.iter().zip(b).enumerate() {
            assert!(x == y, "set {k}, group {g} of {} unknowns", x.0);
        }
    }
}

fn without_friction(text: &str) -> String {
    text.lines()
        .map(|l| {
            if l.trim_start().starts_with("friction =") {
                "friction = 0.0"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// A square floe flush on a straight wall, a second one on top of it
/// rotated by `theta` (rad) about its lower-left corner, both driven into
/// the wall and towards each other (friction 0.3).
fn flush_pair_case(theta: f64) -> Scenario {
    let (c, s) = (theta.cos(), theta.sin());
    let corner = |x: f64, y: f64| format!("[{}, {}]", x * c - y * s, 10.0 + x * s + y * c);
    let text = format!(
        r#"[case]
version = 1
name = "flush_pair"
duration = 1.0
output_interval = 1.0

[contact]
restitution = 0.0
friction = 0.3

[[floe]]
polygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
thickness = 1.0
velocity = [0.3, 0.05]

[[floe]]
polygon = [{}, {}, {}, {}]
thickness = 1.0
velocity = [0.2, -0.1]
angular_velocity = 0.01

[[obstacle]]
polygon = [[10.0, -100.0], [20.0, -100.0], [20.0, 200.0], [10.0, 200.0]]
"#,
        corner(0.0, 0.0),
        corner(10.0, 0.0),
        corner(10.0, 10.0),
        corner(0.0, 10.0)
    );
    scenario(&text)
}

#[test]
fn flush_edge_pairs_share_one_friction_resultant_with_the_same_dynamics() {
    // Exactly flush (θ = 0): each of the three body pairs (floe 1–wall,
    // floe 2–wall, floe 1–floe 2) touches at two corners with equal
    // tangential columns, so the merged LCP has one friction group per pair
    // (n = 6 + 3·3 = 15 instead of 24), and it must give the same velocity
    // changes as the LCP with friction per point, each member within its
    // own Coulomb cone.
    // Every facing edge pair clipped to two points, as the event-driven
    // scheme detects them.
    let every_facing_pair = NarrowOptions {
        parallel_tolerance: std::f64::consts::FRAC_PI_2,
        ..NarrowOptions::default()
    };
    let scn = flush_pair_case(0.0);
    let (per_point, w) = problems_with(&scn, 0.2, Friction::PerPoint, &every_facing_pair);
    let (merged, _) = problems_with(&scn, 0.2, Friction::Merged, &every_facing_pair);
    assert_eq!((per_point.len(), merged.len()), (1, 1));
    let (a, b) = (&per_point[0], &merged[0]);
    assert_eq!((a.m, a.lcp().n, a.friction_groups), (6, 24, 6));
    assert_eq!((b.m, b.lcp().n, b.friction_groups), (6, 15, 3));
    assert_eq!(b.merged_groups(), Some(3));
    let v_scale = w.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let sa = solve(a.lcp(), &SolveOptions::default());
    let sb = solve(b.lcp(), &SolveOptions::default());
    assert!(sa.status.is_solved() && sb.status.is_solved());
    let err = largest_difference(&a.velocity_changes(&sa.z), &b.velocity_changes(&sb.z));
    assert!(err <= 1e-9 * v_scale, "velocity changes differ by {err:e}");
    let (lam, beta) = (b.normal(&sb.z), b.tangential(&sb.z));
    let mut sliding = 0;
    for (l, t) in lam.iter().zip(&beta) {
        assert!(
            t.abs() <= 0.3 * l * (1.0 + 1e-9) + 1e-12,
            "|β| = {t} > μ λ = {}",
            0.3 * l
        );
        sliding += usize::from(t.abs() > 0.29 * l && *l > 0.0);
    }
    // The pairs' total tangential impulses agree (the sums of the members').
    let (ta, tb) = (a.tangential(&sa.z), beta);
    for pair in [0..2, 2..4, 4..6] {
        let (x, y): (f64, f64) = (ta[pair.clone()].iter().sum(), tb[pair].iter().sum());
        assert!(
            (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1e-300),
            "{x} vs {y}"
        );
    }
    assert!(
        sliding > 0,
        "no contact slides: the test would not see the cone"
    );
    // Rotated by 0.01 rad, floe 2's pairs still touch at two points each,
    // but with tangents 0.01 apart, far above the merge tolerance (1e-3):
    // only floe 1–wall is merged.
    let (rotated, _) = problems_with(
        &flush_pair_case(0.01),
        0.2,
        Friction::Merged,
        &every_facing_pair,
    );
    assert_eq!(rotated.len(), 1);
    assert_eq!((rotated[0].m, rotated[0].friction_groups), (6, 5));
    assert_eq!(rotated[0].lcp().n, 6 + 3 * 5);
}
