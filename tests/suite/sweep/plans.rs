//! Plans that load: a start from an earlier run's state, the dense plan's
//! tolerances beside their solver, the bundled plan's points named once.

use super::{load, plan_file};
use crate::common::{case_text, scenario, tempdir};
use floebench::sweep::plan::{load_plan, parse_plan};
use floebench::sweep::points::points;
use std::path::Path;

#[test]
fn a_plan_with_a_start_runs_every_point_from_that_state_for_its_duration() {
    // docs/sweep-format.md, `start`: the state of an earlier run at one of
    // its output times, as `run --from … --at` takes it.
    let tmp = tempdir();
    let dir = tmp.path();
    let scn = scenario(&case_text("head_on"));
    let r = crate::common::run(&scn, "event-driven");
    let earlier = dir.join("earlier");
    floebench::run::output::write_run(&earlier, &r).unwrap();
    let body = "start = { trajectory = \"earlier/trajectory.csv\", at = 10.0, duration = 2.5 }\nreference = \"event-driven\"\n[[formulation]]\nname = \"moreau\"\ngrid = { step = [0.5, 0.25] }\n";
    let plan = load(&plan_file(dir, &["head_on"], body));
    let at10: Vec<_> = r.trajectory.iter().filter(|row| row.t == 10.0).collect();
    assert_eq!(at10.len(), 2);
    for p in points(&plan) {
        let s = plan.scenario(p.case, p.table, &p.settings).unwrap();
        assert_eq!((s.duration, s.output_interval), (2.5, 0.5), "{}", p.id);
        for (b, row) in s.floes.iter().zip(&at10) {
            assert_eq!((b.position.x, b.position.y), (row.x, row.y), "{}", p.id);
            assert_eq!((b.velocity.x, b.velocity.y), (row.vx, row.vy), "{}", p.id);
        }
    }
    // The start is part of each point's fingerprint.
    let other = body.replace("at = 10.0", "at = 9.5");
    let plan2 = load(&plan_file(dir, &["head_on"], &other));
    assert_ne!(points(&plan)[0].fingerprint, points(&plan2)[0].fingerprint);
    // A missing state, a duration off the output grid: one-line errors at
    // the start's line.
    for (change, says) in [
        ("earlier/trajectory.csv", "missing/trajectory.csv"),
        ("duration = 2.5", "duration = 2.2"),
    ] {
        let bad = body.replace(change, says);
        let e = load_plan(&plan_file(dir, &["head_on"], &bad))
            .err()
            .unwrap_or_else(|| panic!("{says}: accepted"))
            .to_string();
        assert!(e.contains("plan.toml:5: [sweep] start"), "{e}");
    }
}

#[test]
fn the_dense_plan_loads_with_each_tolerance_beside_its_solver() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/sweeps/dense_work_precision.toml");
    let plan = load(&path);
    let pts = points(&plan);
    assert_eq!(pts.len(), 18);
    let p = pts
        .iter()
        .find(|p| p.id == "bay_jam_200__moreau__tolerance=0.0001__solver=nsgs")
        .unwrap_or_else(|| panic!("{:?}", pts.iter().map(|p| &p.id).collect::<Vec<_>>()));
    let scn = plan.scenario(p.case, p.table, &p.settings).unwrap();
    let s = floebench::formulation::moreau::MoreauSettings::of(&scn).unwrap();
    assert_eq!(s.iterative.map(|o| o.tolerance), Some(1e-4));
}

#[test]
fn the_bundled_plan_loads_and_its_points_are_named_once() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/sweeps/convergence.toml");
    let plan = load(&path);
    let pts = points(&plan);
    let mut ids: Vec<&str> = pts.iter().map(|p| p.id.as_str()).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), pts.len());
    assert_eq!(pts.len(), 96);
    // A grid value is applied where its formulation reads it.
    let p = pts
        .iter()
        .find(|p| p.id == "bouncing_floe__moreau__step=0.25")
        .unwrap();
    let scn = plan.scenario(p.case, p.table, &p.settings).unwrap();
    let s = floebench::formulation::moreau::MoreauSettings::of(&scn).unwrap();
    assert_eq!(s.step, 0.25);
    let p = pts
        .iter()
        .find(|p| {
            p.id == "head_on__event-driven__contact.distance=0.005__integrator.tolerance=1e-8"
        })
        .unwrap();
    let scn = plan.scenario(p.case, p.table, &p.settings).unwrap();
    assert_eq!(
        (scn.contact.distance, scn.integrator.tolerance),
        (0.005, 1e-8)
    );
    // Inline plans take cases relative to the plan's folder.
    let inline = parse_plan(
        "[sweep]\nversion = 1\ncases = [\"../bouncing_floe.toml\"]\nreference = \"exact\"\n[[formulation]]\nname = \"rapier\"\n",
        &path,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        inline.cases[0].path,
        Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/bouncing_floe.toml")
    );
    assert_eq!(inline.name, "convergence");
}
