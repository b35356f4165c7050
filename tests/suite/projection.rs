//! Moreau–Jean's projection of the positions (`[formulation.moreau]
//! projection = true`, docs/physics.md §5.1 step 5): a floe thrown at a
//! coast with a step of 1 s ends its impact step penetrated by the
//! scheme's `h (1 − γ) |u_N|`-order depth without it, and at most
//! `projection_depth` deep with it, its velocities and ledger untouched.

use crate::common::{counter, run, scenario, setting, turned_square, with_formulation_table};
use floebench::formulation::parse_case;
use floebench::iterative::DEFAULT_TOLERANCE;
use std::path::Path;

/// A 10 m square at 1 m/s towards a coast 1.3 m away, plastic and
/// frictionless, no forcing: with `h` = 1 s and `γ` = ½ the contact is
/// activated at a gap of 0.3 m (`g + h γ u_N` = −0.2 m), the impulse stops
/// the floe (`e` = 0), and the θ-method moves it by `h (u⁻ + u⁺)/2` = 0.5 m:
/// 0.2 m into the coast.
const THROWN: &str = r#"
[case]
version = 1
name = "thrown_floe"
description = "A floe thrown at a coast."
duration = 20.0
output_interval = 1.0

[contact]
restitution = 0.0
friction = 0.0

[[floe]]
polygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]
thickness = 1.0
velocity = [1.0, 0.0]

[[obstacle]]
polygon = [[11.3, -50.0], [20.0, -50.0], [20.0, 60.0], [11.3, 60.0]]
"#;

#[test]
fn the_projection_keeps_a_thrown_floe_within_its_depth_of_the_coast() {
    let plain = run(
        &scenario(&with_formulation_table(THROWN, "moreau", "step = 1.0")),
        "moreau",
    );
    let projected = run(
        &scenario(&with_formulation_table(
            THROWN,
            "moreau",
            "step = 1.0\nprojection = true",
        )),
        "moreau",
    );
    // Without it: the scheme's 0.2 m, kept for ever (nothing pushes out).
    let deep = counter(&plain, "max_penetration_m");
    assert!((deep - 0.2).abs() < 1e-9, "penetration {deep} m");
    // With it: one projection, the floe half the depth into the coast (the
    // projection's target), to the Gauss–Seidel tolerance relative to the
    // 0.2 m it removed.
    let depth = setting(&projected, "projection_depth_m");
    let slack = DEFAULT_TOLERANCE * 0.2;
    let pen = counter(&projected, "max_penetration_m");
    assert!(
        depth > 0.0 && pen <= 0.5 * depth + slack,
        "{pen} m, depth {depth} m"
    );
    assert_eq!(counter(&projected, "projections"), 1.0);
    assert_eq!(counter(&projected, "projections_unconverged"), 0.0);
    assert_eq!(counter(&projected, "projections_incomplete"), 0.0);
    let x = |r: &floebench::run::RunResult| r.final_state.bodies[0].position.x;
    let gap = 11.3 - (x(&projected) + 5.0);
    assert!((gap + 0.5 * depth).abs() <= slack, "gap {gap} m");
    // The velocities are the scheme's: the floe stopped, in both runs, and
    // the ledger is untouched (the plastic impact dissipates the same).
    for r in [&plain, &projected] {
        let v = r.final_state.bodies[0].velocity.norm();
        assert!(v < 1e-12, "speed {v} m/s");
        let e = &r.summary.energy;
        assert!(e.residual.abs() < 1e-9 * e.ledger.dissipated, "{e:?}");
    }
    assert_eq!(
        plain.summary.energy.ledger.dissipated,
        projected.summary.energy.ledger.dissipated
    );
}

/// The deepest point of `r`'s floe 0 beyond the line `x = coast`, m (0
/// when none is).
fn depth_beyond(
    r: &floebench::run::RunResult,
    scn: &floebench::model::Scenario,
    coast: f64,
) -> f64 {
    let polys = floebench::state::world_polygons(scn, &r.final_state.bodies);
    polys[0].iter().map(|p| p.x - coast).fold(0.0, f64::max)
}

#[test]
fn the_projection_translates_a_floe_out_of_an_oblique_coast_and_turns_nothing() {
    // A 10 m square turned by 0.05 rad, its lowest corner leading, thrown
    // at 1 m/s at a coast: one step of 1 s (γ = ½, plastic) leaves that
    // corner 0.2 m deep, its neighbour corner 0.5 m short of the coast.
    // A projection that also turned the floe would lift the corner by
    // turning it and press the next one in (the jammed bay's failure,
    // docs/results/2026-12-07-moreau-projection.md, "Translations only").
    let (polygon, lead) = turned_square(5.0, 0.05);
    let coast = lead + 0.3;
    let text = THROWN
        .replace("duration = 20.0", "duration = 1.0")
        .replace(
            "polygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]",
            &format!("polygon = {polygon}"),
        )
        .replace("11.3", &format!("{coast:.17}"));
    let plain_scn = scenario(&with_formulation_table(&text, "moreau", "step = 1.0"));
    let scn = scenario(&with_formulation_table(
        &text,
        "moreau",
        "step = 1.0\nprojection = true",
    ));
    let (plain, projected) = (run(&plain_scn, "moreau"), run(&scn, "moreau"));
    let before = depth_beyond(&plain, &plain_scn, coast);
    assert!(before > 0.1, "the step left only {before} m to project");
    // One projection, no pass left over, the corner at half the depth.
    let depth = setting(&projected, "projection_depth_m");
    let after = depth_beyond(&projected, &scn, coast);
    assert!(
        (after - 0.5 * depth).abs() <= DEFAULT_TOLERANCE * before,
        "{after} m"
    );
    assert_eq!(counter(&projected, "projections"), 1.0);
    assert_eq!(counter(&projected, "projections_incomplete"), 0.0);
    // The floe is turned as the step turned it, and moved along x only
    // (the coast's normal).
    let (a, b) = (
        &plain.final_state.bodies[0],
        &projected.final_state.bodies[0],
    );
    assert_eq!(a.angle, b.angle);
    assert_eq!(a.position.y, b.position.y);
    assert!(
        b.position.x < a.position.x - 0.1,
        "{} {}",
        a.position.x,
        b.position.x
    );
}

#[test]
fn a_projection_depth_without_the_projection_is_refused_at_its_line() {
    let text = with_formulation_table(THROWN, "moreau", "step = 1.0\nprojection_depth = 0.01");
    let e = match parse_case(&text, Path::new("inline.toml")) {
        Ok(_) => panic!("a projection_depth without projection was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("projection_depth needs projection = true"),
        "{e}"
    );
    assert!(e.contains("inline.toml:"), "{e}");
    for bad in ["0.0", "-1.0", "nan"] {
        let text = with_formulation_table(
            THROWN,
            "moreau",
            &format!("projection = true\nprojection_depth = {bad}"),
        );
        assert!(
            parse_case(&text, Path::new("inline.toml")).is_err(),
            "{bad}"
        );
    }
}
