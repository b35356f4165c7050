//! A floe pressed by the wind on a coast along a nearly flush edge
//! (docs/physics.md §5.1 step 2): Moreau–Jean takes the second corner of
//! the facing edge pair as a contact point when it is within the contact
//! distance `δ`, so the floe turns flush and rests. With one point per
//! pair (the narrow phase's default for edges more than 1e-6 rad apart)
//! it turned about its first corner at every step, rocked, and crept into
//! the coast: measured, 0.029 m of penetration and 0.013 J of kinetic
//! energy after 400 s, still growing; the jammed bay's packs crept
//! downwind the same way at a step of 1 s
//! (docs/results/2026-12-07-moreau-projection.md, "The step").

use crate::common::{counter, run, scenario, turned_square};

/// A 20 m square turned by 3e-4 rad, its right side 1 mm from a coast,
/// a 10 m/s wind into the coast, `e` = 0.4, `μ` = 0.7, `h` = 1 s.
fn flush_floe() -> String {
    let (polygon, lead) = turned_square(10.0, 3e-4);
    let coast = lead + 0.001;
    let far = coast + 50.0;
    format!(
        r#"
[case]
version = 1
name = "flush_floe"
description = "A floe pressed by the wind on a coast along a nearly flush edge."
duration = 400.0
output_interval = 10.0

[environment]
air   = {{ density = 1.3,    drag = 1.7e-3, velocity = [10.0, 0.0] }}
water = {{ density = 1024.0, drag = 5.0e-3, velocity = [0.0, 0.0] }}

[contact]
restitution = 0.4
friction = 0.7

[[floe]]
polygon = {polygon}
thickness = 1.0

[[obstacle]]
polygon = [[{coast:.17}, -100.0], [{far:.17}, -100.0], [{far:.17}, 100.0], [{coast:.17}, 100.0]]

[formulation.moreau]
step = 1.0
"#
    )
}

#[test]
fn a_floe_pressed_on_a_coast_along_a_nearly_flush_edge_turns_flush_and_rests() {
    let scn = scenario(&flush_floe());
    let r = run(&scn, "moreau");
    let end = &r.final_state.bodies[0];
    // At rest: no kinetic energy left (measured 1e-29 J; 0.013 J with one
    // point per pair), no spin.
    let ke = r.summary.energy.final_kinetic;
    assert!(ke < 1e-12, "kinetic energy {ke} J");
    assert!(
        end.angular_velocity.abs() < 1e-12,
        "spin {} rad/s",
        end.angular_velocity
    );
    // Turned flush with the coast (its 3e-4 rad undone, to 3 %) and into
    // it no deeper than the scheme's first step puts it (measured 1.1 mm;
    // 29 mm and growing with one point per pair).
    assert!((end.angle + 3e-4).abs() < 1e-5, "angle {} rad", end.angle);
    let pen = counter(&r, "max_penetration_m");
    assert!(pen < 0.002, "penetration {pen} m");
}
