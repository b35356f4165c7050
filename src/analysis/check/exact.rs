//! The exact answers the checks compare with, computed from the case's own
//! parameters (docs/physics.md §2 and §6): the velocities after a central
//! impact, the wind acceleration of "constant wind as gravity" and the
//! steady free-drift velocity.

use crate::geometry::Vec2;
use crate::model::Scenario;

/// `(v1', v2')` of a central impact (docs/physics.md §6.1).
pub fn head_on_velocities(m1: f64, v1: f64, m2: f64, v2: f64, e: f64) -> (f64, f64) {
    let p = m1 * v1 + m2 * v2;
    (
        (p - m2 * e * (v1 - v2)) / (m1 + m2),
        (p + m1 * e * (v1 - v2)) / (m1 + m2),
    )
}

/// The wind acceleration `a = ρ_a C_a |U_a|² / (ρ_i h)` of floe `i` at t = 0
/// (docs/physics.md §2.3: constant wind as gravity), m/s².
pub fn wind_acceleration(scn: &Scenario, i: usize) -> f64 {
    let air = &scn.environment.air;
    let u = air
        .velocity
        .at(&scn.floes[i].position, 0.0, &scn.environment.outside)
        .norm();
    air.drag_factor() * u * u / scn.floes[i].surface_density()
}

/// The steady free-drift velocity of floe `i` under constant wind and
/// current (docs/physics.md §2.2): the root of
/// `τ_a + ρ_w C_w |U_w − u|(U_w − u) − ρ_i h f k ∧ u = 0` by Newton's method,
/// m/s; `None` without water drag, with varying forcing, or if Newton fails.
pub fn steady_drift_velocity(scn: &Scenario, i: usize) -> Option<Vec2> {
    let env = &scn.environment;
    let (Some(ua), Some(uw)) = (
        env.air.velocity.constant_value(),
        env.water.velocity.constant_value(),
    ) else {
        return None;
    };
    let (ka, kw) = (env.air.drag_factor(), env.water.drag_factor());
    if kw <= 0.0 {
        return None;
    }
    let rho_h = scn.floes[i].surface_density();
    let f = env.coriolis;
    let tau_a = ua * (ka * ua.norm());
    let g = |u: Vec2| -> Vec2 {
        let r = uw - u;
        tau_a + r * (kw * r.norm()) - Vec2::new(-u.y, u.x) * (rho_h * f)
    };
    let mut u = uw + ua * (ka / kw).sqrt();
    let scale = tau_a
        .norm()
        .max(kw * uw.norm().powi(2))
        .max(f64::MIN_POSITIVE);
    for _ in 0..100 {
        let g0 = g(u);
        if g0.norm() <= 1e-13 * scale {
            return Some(u);
        }
        let h = 1e-7 * u.norm().max(1e-3);
        let jx = (g(u + Vec2::new(h, 0.0)) - g0) / h;
        let jy = (g(u + Vec2::new(0.0, h)) - g0) / h;
        let det = jx.x * jy.y - jy.x * jx.y;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        u -= Vec2::new(jy.y * g0.x - jy.x * g0.y, -jx.y * g0.x + jx.x * g0.y) / det;
    }
    (g(u).norm() <= 1e-10 * scale).then_some(u)
}

/// The critical speed (m/s) of a floe of mass `m` (kg) and thickness `h`
/// (m) rammed face-on into a fixed coast with restitution `e`, under the
/// energy criterion of toughness `g` (J/m²) with chord `l` (m): the impact
/// impulse `(1 + e) M v` delivers `½ (1 + e)² M v²`, which reaches `G h L`
/// at `v_c = sqrt(2 G h L / ((1 + e)² M))` (docs/physics.md §9.6).
pub fn ram_critical_speed_of(g: f64, h: f64, l: f64, e: f64, m: f64) -> f64 {
    (2.0 * g * h * l / ((1.0 + e).powi(2) * m)).sqrt()
}

/// The closed form of a floe of mass `m` (kg) ramming a straight coast at
/// `v` (m/s) with a corner of interior angle `phi` (rad), the ice crushing
/// at a constant `sigma` (Pa) over its thickness `h` (m), all the normal
/// kinetic energy crushed (docs/physics.md §10.3): the crushed face at
/// depth `δ` is `2 δ tan(φ/2)` wide, so the force is `k δ` with
/// `k = 2 σ h tan(φ/2)` (a linear spring that only compresses): crushed
/// volume `½ m v² / σ`, peak force `v √(m k)`, duration `(π/2) √(m/k)`.
pub fn corner_crush(m: f64, v: f64, sigma: f64, h: f64, phi: f64) -> (f64, f64, f64) {
    let k = 2.0 * sigma * h * (0.5 * phi).tan();
    (
        0.5 * m * v * v / sigma,
        v * (m * k).sqrt(),
        0.5 * std::f64::consts::PI * (m / k).sqrt(),
    )
}

/// The closed form of a floe of mass `m` (kg) meeting a straight coast at
/// `v` (m/s) with a flat face of width `w` (m), the ice crushing at `sigma`
/// (Pa) over its thickness `h` (m) (docs/physics.md §10.3): a constant force
/// `F = σ h w`, crushed volume `½ m v² / σ` (depth `m v² / (2 F)`),
/// duration `m v / F`.
pub fn flat_crush(m: f64, v: f64, sigma: f64, h: f64, w: f64) -> (f64, f64, f64) {
    let f = sigma * h * w;
    (0.5 * m * v * v / sigma, f, m * v / f)
}
