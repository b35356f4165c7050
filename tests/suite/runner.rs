//! The runner ends a run at its last finite output: no output file holds a
//! non-finite number, and the end says which quantity of which floe, when.

use crate::common::{case_text, run, scenario, tempdir};
use floebench::geometry::Vec2;
use floebench::model::Floe;
use floebench::run::{output, EndReason};

#[test]
fn a_state_that_is_not_finite_at_the_start_ends_the_run_with_nothing_recorded() {
    // A floe 1e308 m thick has an infinite mass: its kinetic energy is
    // inf × 0 = NaN at t = 0, for every formulation. The case limits refuse
    // such a floe (case_files::every_input_of_issue_17_is_refused), so it is
    // built by hand here, to test the runner's own guard.
    let mut scn = scenario(&case_text("cradle_gaps"));
    let f = &scn.floes[0];
    let world: Vec<Vec2> = f.shape.iter().map(|p| p + f.position).collect();
    scn.floes[0] = Floe::from_world_polygon(
        &world,
        1e308,
        f.density,
        f.velocity,
        f.angular_velocity,
        f.origin,
    );
    for name in ["event-driven", "moreau", "rapier"] {
        let r = run(&scn, name);
        assert_eq!(
            r.summary.end,
            EndReason::NonFinite {
                floe: 0,
                t: 0.0,
                quantity: "kinetic energy".into()
            },
            "{name}"
        );
        assert!(r.trajectory.is_empty() && r.energy.is_empty(), "{name}");
        assert_eq!(
            r.summary.end.to_string(),
            "non-finite kinetic energy of floe 0 at t = 0 s"
        );
        let e = &r.summary.energy;
        assert!(
            e.initial_kinetic.is_finite() && e.exchanged.is_finite(),
            "{name}"
        );
        let dir = tempdir();
        output::write_run(dir.path(), &r).unwrap();
    }
}

#[test]
fn the_writer_refuses_a_non_finite_number_and_names_it() {
    let scn = scenario(&case_text("head_on"));
    let mut r = run(&scn, "event-driven");
    let dir = tempdir();
    output::write_run(dir.path(), &r).unwrap();
    let k = r.trajectory.len() / 2;
    r.trajectory[k].vy = f64::NAN;
    let fresh = tempdir();
    let err = output::write_run(fresh.path(), &r).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("trajectory.csv: non-finite vy of floe"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_dir(fresh.path()).unwrap().count(),
        0,
        "nothing written"
    );
}

/// A run restarted from an earlier run's output (`run --from`) goes on as
/// the earlier run did: head_on restarted at t = 10 s (after the impact, the
/// floes drifting apart) reaches the earlier run's final state, for every
/// contact formulation; the new run's angles go on from the earlier run's.
#[test]
fn a_run_restarted_from_an_earlier_output_goes_on_as_the_earlier_run() {
    use floebench::model::Restart;
    let dir = tempdir();
    let text = case_text("head_on");
    for name in ["event-driven", "moreau", "moreau-cone", "rapier"] {
        let full = run(&scenario(&text), name);
        assert_eq!(full.summary.end, EndReason::Completed);
        let out = dir.path().join(name);
        output::write_run(&out, &full).unwrap();
        let file = out.join("trajectory.csv");
        let (t, bodies) = output::read_state(&file, Some(10.0)).unwrap();
        assert_eq!(t, 10.0);
        let mut rest = scenario(&text.replacen("duration = 20.0", "duration = 10.0", 1));
        floebench::state::restart(&mut rest, &bodies, Restart { file, t }).unwrap();
        let second = run(&rest, name);
        assert_eq!(second.summary.end, EndReason::Completed);
        for (a, b) in full
            .final_state
            .bodies
            .iter()
            .zip(&second.final_state.bodies)
        {
            let d = (a.position - b.position).norm();
            assert!(d < 1e-9 * a.position.norm().max(1.0), "{name}: {d} m");
            assert!((a.velocity - b.velocity).norm() < 1e-9, "{name}");
        }
        assert!(second.summary.restart.is_some());
        // The state read back is the state written, to the last bit.
        let k = full.trajectory.iter().position(|r| r.t == 10.0).unwrap();
        assert_eq!(bodies[0].position.x, full.trajectory[k].x);
    }
}

/// A run started from a restarted run's output finds its floes turned as
/// they were: head_on with a spinning floe (0.05 rad/s), restarted at
/// t = 10 s for 5 s, then restarted again from that run's last output,
/// ends where the uninterrupted 20-s run ends, angles included, for every
/// contact formulation. (When a restart turned each outline and started
/// its angles at 0, a restarted run wrote only the angle turned since its
/// start, and a restart from its output left the spinning floe off by the
/// angle it had at the first restart: this test then read 0.350 rad
/// against 1.022.)
#[test]
fn a_restart_of_a_restart_keeps_the_floes_turned_as_they_were() {
    use floebench::model::Restart;
    let dir = tempdir();
    let text = case_text("head_on").replacen(
        "velocity = [-0.1, 0.0]",
        "velocity = [-0.1, 0.0]\nangular_velocity = 0.05",
        1,
    );
    let five = text.replacen("duration = 20.0", "duration = 5.0", 1);
    for name in ["event-driven", "moreau", "moreau-cone", "rapier"] {
        let full = run(&scenario(&text), name);
        let mut state = (dir.path().join(format!("{name}_0")), full, Some(10.0));
        output::write_run(&state.0, &state.1).unwrap();
        for leg in 1..=2 {
            let file = state.0.join("trajectory.csv");
            let (t, bodies) = output::read_state(&file, state.2).unwrap();
            let mut next = scenario(&five);
            floebench::state::restart(&mut next, &bodies, Restart { file, t }).unwrap();
            let result = run(&next, name);
            assert_eq!(result.summary.end, EndReason::Completed, "{name}");
            let out = dir.path().join(format!("{name}_{leg}"));
            output::write_run(&out, &result).unwrap();
            state = (out, result, None);
        }
        let full = run(&scenario(&text), name);
        for (a, b) in full
            .final_state
            .bodies
            .iter()
            .zip(&state.1.final_state.bodies)
        {
            assert!(a.angle.abs() > 0.1, "{name}: the floe must have turned");
            assert!(
                (a.angle - b.angle).abs() < 1e-9,
                "{name}: {} against {} rad",
                b.angle,
                a.angle
            );
            let d = (a.position - b.position).norm();
            assert!(d < 1e-9 * a.position.norm().max(1.0), "{name}: {d} m");
        }
    }
}

#[test]
fn a_restart_names_what_does_not_fit() {
    use floebench::model::Restart;
    let dir = tempdir();
    let one = run(&scenario(&case_text("sliding_floe")), "event-driven");
    output::write_run(dir.path(), &one).unwrap();
    let file = dir.path().join("trajectory.csv");
    let err = output::read_state(&file, Some(0.25)).unwrap_err();
    assert!(err.contains("no output at t = 0.25 s"), "{err}");
    let (t, bodies) = output::read_state(&file, None).unwrap();
    let mut two = scenario(&case_text("head_on"));
    let err = floebench::state::restart(
        &mut two,
        &bodies,
        Restart {
            file: file.clone(),
            t,
        },
    )
    .unwrap_err();
    assert!(err.contains("1 floes") && err.contains("has 2"), "{err}");
    std::fs::write(&file, "t,floe,x,y,theta,vx,vy,omega\n0,0,1,2,3,4,5\n").unwrap();
    let err = output::read_state(&file, None).unwrap_err();
    assert!(
        err.contains("trajectory.csv:2: 7 values, expected 8"),
        "{err}"
    );
    std::fs::write(&file, "x,y\n").unwrap();
    let err = output::read_state(&file, None).unwrap_err();
    assert!(err.contains(":1: not a trajectory file"), "{err}");
}

#[test]
fn a_run_stops_on_its_own_interrupt_handle_and_no_other() {
    // The stop request is a handle in the run's options: a run whose own
    // handle was set ends interrupted at its first output time, with the
    // initial state alone recorded; a run with another handle, and the
    // process-wide request, are untouched.
    use floebench::formulation::{build, FormulationOptions, Interrupt};
    use floebench::run::{RunOptions, Runner};
    let scn = scenario(&case_text("head_on"));
    let stopped = Interrupt::own();
    stopped.request();
    for (handle, interrupted) in [(stopped, true), (Interrupt::own(), false)] {
        let mut f = build("moreau", &scn, &FormulationOptions::default()).unwrap();
        let runner = Runner::new(RunOptions {
            interrupt: handle,
            ..RunOptions::default()
        });
        let r = runner.run(&scn, f.name(), f.formulation.as_mut());
        if interrupted {
            assert_eq!(r.summary.end, EndReason::Interrupted { t: 0.0 });
            assert_eq!(r.energy.len(), 1, "only the initial sample");
        } else {
            assert_eq!(r.summary.end, EndReason::Completed);
            assert!(r.energy.len() > 1);
        }
    }
    assert!(!floebench::run::interrupt::requested());
}
