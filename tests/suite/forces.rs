//! The forces stage (`src/fracture/forces.rs`): the mean force on the
//! obstacles and the pack's Love–Weber stress per output interval
//! (`obstacles.csv`, `stress.csv`), held to closed forms; and reading the
//! loads for it changes no result.

use crate::common::{case_path, cases_dir, load, run, scenario, tempdir};
use floebench::contact::Load;
use floebench::formulation::{build, FormulationOptions, REGISTRY};
use floebench::fracture::forces::ForceStage;
use floebench::geometry::Vec2;
use floebench::model::Scenario;
use floebench::physics::ForceModel;
use floebench::run::{output, RunOptions, RunResult, Runner};
use floebench::state::System;

/// The wind force on floe `i` of `scn` at rest at its initial pose, N.
fn wind(scn: &Scenario, i: usize) -> Vec2 {
    let sys = System::initial(scn);
    ForceModel::new(&scn.floes)
        .forces(&scn.environment, i, 0.0, &sys.bodies[i])
        .force()
}

/// The rows of `result` at output times after `t` (s).
fn after(
    result: &RunResult,
    t: f64,
) -> impl Iterator<Item = &floebench::fracture::forces::ObstacleForce> {
    result.obstacle_forces.iter().filter(move |r| r.t > t)
}

#[test]
fn coast_force_equals_the_wind_force_once_at_rest() {
    // bouncing_floe: the floe is at rest against the wall from 273.3 s.
    let scn = load("bouncing_floe");
    let w = wind(&scn, 0);
    assert!(w.x > 0.0 && w.y == 0.0, "wind {w:?}");
    for name in ["moreau", "event-driven", "moreau-cone", "rapier"] {
        let r = run(&scn, name);
        let rows: Vec<_> = after(&r, 300.0).collect();
        assert_eq!(rows.len(), 100, "{name}: a row per output time");
        for row in rows {
            let tol = match name {
                // rapier's soft contacts settle to its own accuracy.
                "rapier" => 1e-3,
                _ => 1e-6,
            };
            assert!(
                (row.fx - w.x).abs() <= tol * w.x && row.fy.abs() <= tol * w.x,
                "{name}: force on the coast at t = {} s: ({}, {}) N, the wind's {} N",
                row.t,
                row.fx,
                row.fy,
                w.x
            );
            // The load's line passes through the wall's centroid height
            // (y = 5, the floe's centre; the wall's centroid y = 5): no torque
            // beyond rounding.
            assert!(
                row.torque.abs() <= tol * w.x * 10.0,
                "{name}: torque {}",
                row.torque
            );
        }
    }
}

#[test]
fn coast_impulse_equals_the_momentum_change_at_each_bounce() {
    // The wind force W is constant (absolute wind): over each output
    // interval the coast's impulse is W Δt − m Δv.
    let scn = load("bouncing_floe");
    let w = wind(&scn, 0).x;
    let m = scn.floes[0].mass;
    for name in ["moreau", "event-driven"] {
        let r = run(&scn, name);
        let vx: Vec<(f64, f64)> = r.trajectory.iter().map(|row| (row.t, row.vx)).collect();
        let scale = m * vx.iter().map(|v| v.1.abs()).fold(0.0, f64::max);
        let mut bounces = 0;
        for (k, row) in r.obstacle_forces.iter().enumerate() {
            let ((t0, v0), (t1, v1)) = (vx[k], vx[k + 1]);
            assert_eq!(t1, row.t);
            let dt = t1 - t0;
            let expected = w * dt - m * (v1 - v0);
            let measured = row.fx * dt;
            assert!(
                (measured - expected).abs() <= 1e-9 * scale,
                "{name}: impulse on the coast over ({t0}, {t1}] s: {measured} N·s, momentum balance {expected} N·s"
            );
            if v1 < 0.0 && v0 > 0.0 {
                bounces += 1;
            }
        }
        assert!(bounces >= 3, "{name}: {bounces} bounces seen");
    }
}

/// Two 10 m square floes, `floe B` behind `floe A`, pushed by the wind
/// against a coast, with no restitution (they come to rest).
const STACK: &str = r#"
[case]
version = 1
name = "stack"
duration = 400.0
output_interval = 1.0

[environment]
air = { density = 1.3, drag = 1.7e-3, velocity = [10.0, 0.0] }

[contact]
restitution = 0.0
friction = 0.0

[[floe]]
polygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
thickness = 1.0

[[floe]]
polygon = [[-10.5, 0.0], [-0.5, 0.0], [-0.5, 10.0], [-10.5, 10.0]]
thickness = 1.0

[[obstacle]]
polygon = [[11.0, -50.0], [20.0, -50.0], [20.0, 60.0], [11.0, 60.0]]
"#;

#[test]
fn two_floes_pressed_on_a_coast_have_the_closed_form_stress() {
    // At rest, with side a and wind W on each floe: the coast pushes A with
    // 2W, A and B push each other with W. Love–Weber's sum over the floes
    // is −W (G_A − G_B) − 2W (x_c − G_A), whatever the point of the
    // floe–floe contact, with x_c the coast contact's point: the middle of
    // the wall's face (x = 11 m) and A's front face (G_A + a/2), which a
    // scheme leaves a hair apart (event-driven) or overlapping (Moreau's
    // drift at rest); over the area 2 a². Touching exactly, σ_xx = −W / a.
    let scn = scenario(STACK);
    let (w, a) = (wind(&scn, 0).x, 10.0);
    for name in ["moreau", "event-driven"] {
        let r = run(&scn, name);
        for s in r.stress.iter().filter(|s| s.t > 350.0) {
            let at = |floe: usize| {
                let row = r
                    .trajectory
                    .iter()
                    .find(|row| row.t == s.t && row.floe == floe);
                row.unwrap().x
            };
            let (ga, gb) = (at(0), at(1));
            let xc = (11.0 + ga + a / 2.0) / 2.0;
            let closed = -w * ((ga - gb) + 2.0 * (xc - ga)) / (2.0 * a * a);
            assert_eq!(s.area, 2.0 * a * a);
            assert!(
                (s.sxx - closed).abs() <= 1e-6 * w / a,
                "{name}: σ_xx at t = {} s: {} N/m, closed form {closed} N/m",
                s.t,
                s.sxx,
            );
            assert!((s.sxx + w / a).abs() <= 1e-2 * w / a, "{name}: {s:?}");
            for v in [s.sxy, s.syx, s.syy] {
                assert!(v.abs() <= 1e-6 * w / a, "{name}: {s:?}");
            }
            assert_eq!(s.pressure(), -(s.sxx + s.syy) / 2.0);
        }
        for f in after(&r, 350.0) {
            assert!((f.fx - 2.0 * w).abs() <= 1e-6 * w, "{name}: {f:?}");
        }
    }
}

#[test]
fn equal_and_opposite_forces_give_minus_force_times_branch_over_area() {
    // Two floes 10.5 m apart along x, pressed together by F over [0.5, 1.5]
    // s, with output times 1 and 2 s: half the impulse in each interval,
    // σ_xx = −F L / A in both; an impulse at an instant at t = 1 s goes
    // to the interval (0, 1].
    let mut scn = scenario(STACK);
    scn.obstacles.clear();
    let sys = System::initial(&scn);
    let (ga, gb) = (sys.bodies[0].position, sys.bodies[1].position);
    let l = (ga - gb).norm();
    let point = (ga + gb) / 2.0;
    let f = 1000.0;
    let area: f64 = scn.floes.iter().map(|f| f.area).sum();
    let pressed = |impulse: f64| {
        [
            Load {
                floe: 0,
                other: 1,
                point,
                impulse: Vec2::new(impulse, 0.0),
            },
            Load {
                floe: 1,
                other: 0,
                point,
                impulse: Vec2::new(-impulse, 0.0),
            },
        ]
    };
    let mut stage = ForceStage::new(&scn, 0.0, &[1.0, 2.0], true);
    assert!(stage.reads());
    stage.load(&scn, &sys, &pressed(f * 1.0), 0.5, 1.5);
    stage.load(&scn, &sys, &pressed(f * 0.25), 1.0, 1.0);
    let mut at = sys.clone();
    for t in [1.0, 2.0] {
        at.t = t;
        stage.close(&scn, &at);
    }
    let (obstacles, stress) = stage.take_rows();
    assert!(obstacles.is_empty());
    // (0, 1]: half of F·1 s plus the instant's F/4 s, over 1 s.
    let first = -(0.5 + 0.25) * f * l / area;
    let second = -0.5 * f * l / area;
    for (s, want) in stress.iter().zip([first, second]) {
        assert!(
            (s.sxx - want).abs() <= 1e-12 * want.abs(),
            "{s:?}, expected σ_xx = {want}"
        );
        assert_eq!((s.sxy, s.syx, s.syy), (0.0, 0.0, 0.0));
    }
    // Without an obstacle or a second floe, nothing is read.
    let mut one = scn.clone();
    one.floes.truncate(1);
    assert!(!ForceStage::new(&one, 0.0, &[1.0], true).reads());
    assert!(!ForceStage::new(&scn, 0.0, &[1.0], false).reads());
}

#[test]
fn a_case_without_obstacles_writes_no_obstacles_csv() {
    let tmp = tempdir();
    let dir = tmp.path();
    for (case, obstacles) in [("head_on", false), ("bouncing_floe", true)] {
        let out = dir.join(case);
        std::fs::create_dir_all(&out).unwrap();
        // An earlier run's obstacles.csv is not this run's.
        std::fs::write(out.join(output::OBSTACLES_FILE), "stale").unwrap();
        let r = run(&load(case), "event-driven");
        output::write_run(&out, &r).unwrap();
        assert_eq!(
            out.join(output::OBSTACLES_FILE).exists(),
            obstacles,
            "{case}"
        );
        let stress = std::fs::read_to_string(out.join("stress.csv")).unwrap();
        assert_eq!(stress.lines().next(), Some(output::STRESS_HEADER));
        assert_eq!(
            stress.lines().count(),
            r.trajectory.len() / r.summary.floes,
            "{case}"
        );
        if obstacles {
            let text = std::fs::read_to_string(out.join(output::OBSTACLES_FILE)).unwrap();
            assert_eq!(text.lines().next(), Some(output::OBSTACLES_HEADER));
            assert_eq!(text.lines().count(), 1 + r.obstacle_forces.len());
        }
    }
    // head_on's two floes collide: its stress is not all zero.
    let r = run(&load("head_on"), "event-driven");
    assert!(r.stress.iter().any(|s| s.sxx < 0.0));
}

/// Runs `name` on `scn` with the forces stage on or off.
fn run_forces(scn: &Scenario, name: &str, skip: bool) -> Option<RunResult> {
    let mut f = build(name, scn, &FormulationOptions::default()).ok()?;
    let runner = Runner::new(RunOptions {
        skip_forces: skip,
        ..RunOptions::default()
    });
    Some(runner.run(scn, f.name(), f.formulation.as_mut()))
}

/// Reading the loads changes nothing: every bundled case with contacts (an
/// obstacle or two floes) and the crushing cases, every formulation that
/// accepts it, its first 60 output intervals: the trajectory, the ledger
/// and the counters bit for bit.
#[test]
fn reading_loads_changes_no_result() {
    let mut cases: Vec<(String, f64)> = std::fs::read_dir(cases_dir())
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| (p.file_stem().unwrap().to_string_lossy().to_string(), 60.0))
        .collect();
    cases.sort_by(|a, b| a.0.cmp(&b.0));
    for name in ["crushing/flat_coast", "crushing/corner_coast"] {
        cases.push((name.to_string(), 60.0));
    }
    assert!(on_and_off_agree(cases) >= 20);
}

/// The same on four dense fields (the iterative solvers, a field that
/// breaks), their first 20 output intervals: about two minutes, so run on
/// demand: `cargo test --release --test suite forces::dense -- --ignored`.
#[test]
#[ignore = "two minutes: cargo test --release --test suite forces::dense -- --ignored"]
fn dense_fields_reading_loads_changes_no_result() {
    let cases = [
        "bay_jam_200",
        "bay_jam_200_nsgs",
        "channel_100",
        "field_200_coast_fracture",
    ]
    .map(|name| (format!("fields/{name}"), 20.0));
    assert!(on_and_off_agree(cases.to_vec()) >= 8);
}

/// Runs each case (name, output intervals kept) with and without the loads
/// read, in every formulation that accepts it, and asserts bit-identical
/// results; returns the number of runs compared.
fn on_and_off_agree(cases: Vec<(String, f64)>) -> usize {
    let mut compared = 0;
    for (name, outputs) in cases {
        let mut scn = load(&name);
        assert!(case_path(&name).exists());
        if scn.obstacles.is_empty() && scn.floes.len() < 2 {
            continue;
        }
        scn.duration = scn.duration.min(outputs * scn.output_interval);
        for entry in REGISTRY {
            let (Some(on), Some(off)) = (
                run_forces(&scn, entry.name, false),
                run_forces(&scn, entry.name, true),
            ) else {
                continue;
            };
            let what = format!("{name} / {}", entry.name);
            assert_eq!(on.trajectory.len(), off.trajectory.len(), "{what}");
            for (a, b) in on.trajectory.iter().zip(&off.trajectory) {
                let bits = |r: &floebench::run::TrajectoryRow| {
                    [r.t, r.x, r.y, r.theta, r.vx, r.vy, r.omega].map(f64::to_bits)
                };
                assert_eq!(bits(a), bits(b), "{what}: trajectory at t = {}", a.t);
            }
            for (a, b) in on.energy.iter().zip(&off.energy) {
                let bits = |e: &floebench::run::EnergySample| {
                    e.values().map(|(_, v)| v.to_bits()).collect::<Vec<_>>()
                };
                assert_eq!(bits(a), bits(b), "{what}: ledger at t = {}", a.t);
            }
            assert_eq!(
                format!("{:?}", on.summary.counters),
                format!("{:?}", off.summary.counters),
                "{what}: counters"
            );
            assert_eq!(on.summary.end, off.summary.end, "{what}");
            compared += 1;
        }
    }
    compared
}
