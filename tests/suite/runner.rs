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
