//! Helpers shared by the formulation tests (`mod common;`): bundled case
//! text, inline scenarios, final velocities, rest time, and the head-on
//! closed form with its assertions.

#![allow(dead_code)] // each test crate uses a part

use floebench::formulation::parse_case;
use floebench::geometry::Vec2;
use floebench::model::Scenario;
use floebench::run::RunResult;
use std::path::Path;

/// The text of `cases/<name>.toml`.
pub fn case_text(name: &str) -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases")
            .join(format!("{name}.toml")),
    )
    .unwrap()
}

/// A scenario from case text (panics with the parse error).
pub fn scenario(text: &str) -> Scenario {
    parse_case(text, Path::new("inline.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// The velocity of `floe` at the end of the run, m/s.
pub fn final_velocity(r: &RunResult, floe: usize) -> Vec2 {
    r.final_state.bodies[floe].velocity
}

/// The first sample time after which floe 0 no longer moves (|vx| ≤ 1e-12 m/s).
pub fn rest_time(r: &RunResult) -> f64 {
    let last_move = r
        .trajectory
        .iter()
        .filter(|row| row.vx.abs() > 1e-12)
        .map(|row| row.t)
        .fold(0.0, f64::max);
    r.trajectory
        .iter()
        .map(|row| row.t)
        .find(|&t| t > last_move)
        .unwrap()
}

/// The head-on case (`cases/head_on.toml`) with restitution `e`.
pub fn head_on(e: f64) -> Scenario {
    scenario(&case_text("head_on").replace("restitution = 0.4", &format!("restitution = {e:?}")))
}

/// The head-on closed form (physics.md §6) for the head-on case's speeds
/// (0.5 and −0.1 m/s): `(v1', v2')`, m/s.
pub fn head_on_expected(scn: &Scenario, e: f64) -> (f64, f64) {
    let (m1, m2) = (scn.floes[0].mass, scn.floes[1].mass);
    let (v1, v2) = (0.5, -0.1);
    let v1p = (m1 * v1 + m2 * v2 - m2 * e * (v1 - v2)) / (m1 + m2);
    let v2p = (m1 * v1 + m2 * v2 + m1 * e * (v1 - v2)) / (m1 + m2);
    (v1p, v2p)
}

/// Asserts the head-on closed form to 1e-9 (relative), no transverse
/// velocity, and momentum to 1e-12; `label` names the run in messages.
pub fn assert_head_on(r: &RunResult, scn: &Scenario, e: f64, label: &str) {
    let (m1, m2) = (scn.floes[0].mass, scn.floes[1].mass);
    let (v1, v2) = (0.5, -0.1);
    let (v1p, v2p) = head_on_expected(scn, e);
    let (a, b) = (final_velocity(r, 0), final_velocity(r, 1));
    assert!(
        (a.x - v1p).abs() <= 1e-9 * v1p.abs().max(1e-3),
        "{label}: v1' {} vs {v1p}",
        a.x
    );
    assert!(
        (b.x - v2p).abs() <= 1e-9 * v2p.abs().max(1e-3),
        "{label}: v2' {} vs {v2p}",
        b.x
    );
    assert!(a.y.abs() < 1e-12 && b.y.abs() < 1e-12);
    let p0 = m1 * v1 + m2 * v2;
    let p1 = r.final_state.momentum(scn);
    assert!(
        (p1.x - p0).abs() <= 1e-12 * p0.abs(),
        "{label}: momentum {} vs {p0}",
        p1.x
    );
}

/// The counter `name` of a run as a real number; panics if the run does not
/// keep it (a misspelt name fails the test instead of reading 0).
pub fn counter(r: &RunResult, name: &str) -> f64 {
    match r.summary.counters.by_name(name) {
        Ok(Some(v)) => v,
        Ok(None) => panic!("{}: counter `{name}` kept but never set", r.summary.case),
        Err(e) => panic!("{}: {e}", r.summary.case),
    }
}

/// The numeric setting `name` of a run; panics if the run has none.
pub fn setting(r: &RunResult, name: &str) -> f64 {
    r.summary
        .settings
        .get(name)
        .unwrap_or_else(|| panic!("{}: no numeric setting `{name}`", r.summary.case))
}
