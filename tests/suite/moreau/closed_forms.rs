//! The bundled cases with a closed form: the head-on impact, the bouncing
//! floe past its accumulation point, the sliding floe (stop within O(h),
//! second-order distance), the elastic pool's kinetic energy and the free
//! drift's steady velocity.

use super::{run_checked, with_step, SOLVERS};
use crate::common::{
    assert_head_on, bouncing_expected, case_text, drift_velocity, final_velocity, head_on,
    head_on_expected, rest_time_below, scenario, sliding_expected, Bouncing, Sliding,
};
use floebench::formulation::contact_solver::SolverKind;
use floebench::formulation::moreau::MoreauSettings;
use floebench::run::RunResult;

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
