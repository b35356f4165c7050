//! The cone solver (`moreau-cone`): equal to Lemke without friction, and the
//! Anitescu–Tasora relaxation's artefact on a sliding contact.

use super::{largest_difference, problems_at_start, run_checked};
use crate::common::{
    case_text, counter, final_velocity, rest_time_below, scenario, sliding_expected, Sliding,
};
use floebench::contact::cone::{solve_cone, ConeOptions, ConeStatus};
use floebench::formulation::contact_solver::SolverKind;
use floebench::lcp::{solve, SolveOptions};

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
