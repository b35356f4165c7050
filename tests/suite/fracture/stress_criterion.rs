//! The stress criterion in runs: a rammed floe whose window stress leaves
//! the Mohr triangle breaks, and a floe pressed on a coast by the wind
//! breaks when its window fills, in every formulation.

use super::{rel, RAM};
use crate::common::{run, scenario};
use floebench::fracture::stress::yield_measure;

#[test]
fn the_stress_criterion_breaks_a_floe_whose_window_stress_leaves_the_mohr_triangle() {
    // The impact impulse (1 + e) M v0 = 2751 N·s over the 10 s window on a
    // 10 m face, 1 m thick: a uniaxial σ2 = −27.5 Pa, beyond the compressive
    // side σ1 + σ2 = −1.63 Pa of a Mohr triangle scaled down to σ_c = 10 Pa,
    // σ_11 = −1.35 Pa (and inside the default one, σ_c = 250 kPa).
    let base = RAM
        .replace("SPEED", "0.02")
        .replace("duration = 4.0", "duration = 40.0");
    // min_area = 50 m²: the halves may be made, and no cut of a half (into
    // pieces below 50 m²) is.
    let weak = "model = \"stress\"\nmohr_sigma_c = 10.0\nmohr_sigma_11 = -1.35\nmin_area = 50.0";
    for (table, breaks) in [(weak, true), ("model = \"stress\"", false)] {
        let scn = scenario(&format!("{base}\n[fracture]\n{table}\n"));
        let r = run(&scn, "event-driven");
        assert_eq!(r.fractures.len(), usize::from(breaks), "{table}");
        if let Some(f) = r.fractures.first() {
            assert_eq!(f.model, "stress");
            assert!(f.measure > 1.0 && f.threshold == 1.0);
            assert_eq!(f.energy, 0.0, "the stress criterion spends no crack energy");
            for piece in &r.floes[1..] {
                assert!(rel(piece.area, 50.0) <= 1e-12, "the Brazilian halves");
            }
        }
    }
}

/// The ram's 10 m square, 1 m thick, at rest against the coast, pressed by a wind of
/// 10 m/s: the contact carries the air force `F = ρ_a C_a |U|² A` = 22.1 N
/// on the middle of the face, a uniaxial floe-averaged stress
/// `σ_xx = −F (a/2) / (A h)` = −1.105 Pa once the window is full. The Mohr
/// triangle is scaled down so that this is twice the curve's stress.
fn pressed() -> String {
    let ram = RAM
        .replace("SPEED", "0.0")
        .replace("10.02", "10.0")
        .replace("duration = 4.0", "duration = 40.0");
    format!(
        "{ram}
[environment]
air   = {{ density = 1.3,    drag = 1.7e-3, velocity = [10.0, 0.0] }}
water = {{ density = 1024.0, drag = 5.0e-3, velocity = [0.0, 0.0] }}

[fracture]
model = \"stress\"
window = 10.0
mohr_sigma_c = 3.4
mohr_sigma_11 = -0.459
min_area = 50.0
"
    )
}

#[test]
fn a_floe_pressed_on_a_coast_breaks_under_the_stress_criterion_in_every_formulation() {
    // The sustained contact force, not an impact, loads the floe: the
    // window's mean stress grows as F t / W until the window is full, so
    // the floe breaks when it reaches the curve, at t* = W / m (m the
    // measure of the full window's stress), and not before. Each scheme
    // sees it at the end of a step that reaches t* (event-driven: its
    // sustained-contact steps, up to its contact horizon; moreau: h).
    let scn = scenario(&pressed());
    let (a, h) = (10.0, 1.0);
    let force = 1.3 * 1.7e-3 * 10.0f64.powi(2) * a * a;
    let sigma = -force * (a / 2.0) / (a * a * h);
    let full = yield_measure(&scn.fracture, &[sigma, 0.0, 0.0]);
    assert!((1.5..3.0).contains(&full), "the set-up: measure {full}");
    let t_star = scn.fracture.window / full;
    let ed = floebench::formulation::event_driven::EventDrivenSettings::of(&scn)
        .unwrap_or_else(|e| panic!("{e}"));
    let horizon = floebench::formulation::event_driven::contact_horizon(
        &scn,
        ed.penetration_tolerance(&scn),
        floebench::physics::SmoothIntegrator::new(&scn, None).drag_bound(),
    );
    assert!(
        horizon.is_finite(),
        "the event-driven step bound: {horizon} s"
    );
    println!("event-driven contact horizon {horizon} s, t* = {t_star} s");
    for (name, step) in [
        ("event-driven", horizon),
        ("moreau", 0.5),
        ("moreau-cone", 0.5),
        ("rapier", 0.1),
    ] {
        let r = run(&scn, name);
        assert_eq!(r.fractures.len(), 1, "{name}: {:?}", r.fractures);
        let f = &r.fractures[0];
        println!("{name}: broke at {} s, measure {}", f.t, f.measure);
        assert!(
            f.t >= t_star * (1.0 - 1e-9) && f.t <= t_star + step,
            "{name}: broke at {} s, t* = {t_star} s, step {step} s",
            f.t
        );
        assert!(
            f.measure > 1.0 && f.measure <= full * (1.0 + 1e-6),
            "{name}: {f:?}"
        );
        assert!(f.conservation <= 1e-12, "{name}: {}", f.conservation);
        // The Brazilian cut through the middle of the loaded face, along
        // the load: two halves.
        for piece in &r.floes[1..] {
            assert!(rel(piece.area, 50.0) <= 1e-9, "{name}: {}", piece.area);
        }
    }
}
