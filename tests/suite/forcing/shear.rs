//! The shear-current closed form: a floe spinning at half the shear
//! vorticity feels no force and no torque, and a disc-like floe spins up to
//! it.

use super::{case, regular};
use crate::common::{load, run, scenario};
use floebench::geometry::Vec2;
use floebench::physics::ForceModel;
use floebench::run::EndReason;
use floebench::state::BodyState;

/// `[[floe]]` of an axis-aligned square of side `s` centred at `(cx, cy)`.
fn square(cx: f64, cy: f64, s: f64) -> String {
    let h = s / 2.0;
    format!(
        "polygon = [[{}, {}], [{}, {}], [{}, {}], [{}, {}]]\nthickness = 1.0",
        cx - h,
        cy - h,
        cx + h,
        cy - h,
        cx + h,
        cy + h,
        cx - h,
        cy + h
    )
}

#[test]
fn a_floe_spinning_at_half_the_shear_vorticity_feels_no_force_and_no_torque() {
    let alpha = 1e-3;
    let env = format!(
        "water = {{ density = 1024.0, drag = 5.0e-3, field = \"linear\", velocity = [0.0, 0.0], gradient = [[0.0, {alpha}], [0.0, 0.0]], extent = [[-5000.0, -5000.0], [5000.0, 5000.0]] }}"
    );
    for (what, floe) in [
        ("square", format!("[[floe]]\n{}", square(0.0, 200.0, 300.0))),
        (
            "16-gon",
            format!("[[floe]]\n{}", regular(0.0, 200.0, 150.0, 16)),
        ),
    ] {
        let scn = scenario(&case(&env, 100.0, &floe));
        let model = ForceModel::new(&scn.floes);
        let f = &scn.floes[0];
        let state = |omega: f64| BodyState {
            position: f.position,
            angle: 0.0,
            velocity: Vec2::new(alpha * f.position.y, 0.0),
            angular_velocity: omega,
        };
        // The scale: the force and torque of the same floe not spinning.
        let still = model.forces(&scn.environment, 0, 0.0, &state(0.0));
        let (f0, m0) = (still.water.norm(), still.water_torque.abs());
        assert!(m0 > 0.0, "{what}: a floe at rest in shear feels a torque");
        let at = model.forces(&scn.environment, 0, 0.0, &state(-alpha / 2.0));
        let scale_f = 1024.0 * 5.0e-3 * (alpha * f.radius).powi(2) * f.area;
        assert!(
            at.water.norm() <= 1e-12 * scale_f,
            "{what}: force {:e} N (scale {scale_f:e}, at rest {f0:e})",
            at.water.norm()
        );
        assert!(
            at.water_torque.abs() <= 1e-12 * m0,
            "{what}: torque {:e} N m against {m0:e} at rest",
            at.water_torque
        );
    }
}

#[test]
fn a_disc_like_floe_spins_up_to_half_the_shear_vorticity() {
    // cases/shear_current.toml: a 16-gon of radius 100 m at rest on the line
    // of zero current of u = (α y, 0), α = 1e-3 1/s. Measured: ω(21600 s) =
    // −4.9963e-4 rad/s; the tolerance 0.1 % of α/2 holds the last slip of
    // the quadratic drag (which decays as 1/t, not exponentially).
    let scn = load("shear_current");
    let alpha = 1e-3;
    let r = run(&scn, "free-drift");
    assert_eq!(r.summary.end, EndReason::Completed);
    let last = r.trajectory.last().unwrap();
    let target = -alpha / 2.0;
    assert!(
        (last.omega - target).abs() <= 1e-3 * alpha / 2.0,
        "ω = {} rad/s, expected {target} to 0.1 %",
        last.omega
    );
    // The spin-up is monotone and the centre does not move.
    let omegas: Vec<f64> = r.trajectory.iter().map(|row| row.omega).collect();
    assert!(omegas.windows(2).all(|w| w[1] <= w[0]), "{omegas:?}");
    assert!(
        last.x.abs().max(last.y.abs()) < 1e-9 * 100.0,
        "{} {}",
        last.x,
        last.y
    );
}
