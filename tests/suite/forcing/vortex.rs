//! The Rankine-vortex closed forms: free drift at the velocity of the floe's
//! centre, the centre floe moving with the drifting core, and a floe in
//! the core keeping the free drift of its centre.

use super::{case, regular};
use crate::common::{load, run, scenario};
use floebench::geometry::{area_properties, Vec2};
use floebench::physics::ForceModel;
use floebench::run::EndReason;
use floebench::state::BodyState;

/// The Rankine vortex of the tests, evaluated independently of the code's:
/// core radius `R`, peak speed `S`, centre at the origin, no drift.
fn rankine(p: Vec2, r_core: f64, s: f64) -> Vec2 {
    let r = p.norm();
    let e = Vec2::new(-p.y, p.x);
    if r <= r_core {
        e * (s / r_core)
    } else {
        e * (s * r_core / (r * r))
    }
}

#[test]
fn free_drift_in_a_rankine_vortex_matches_the_drift_at_the_floe_centre() {
    // A 16-gon of radius a = 100 m at r0 = 3000 m from the centre of a
    // vortex current (R = 500 m, S = 0.2 m/s), in a uniform wind, moving at
    // the analytic free-drift velocity of the current at its centre:
    // u = U_w(G) + sqrt(ρ_a C_a / ρ_w C_w) U_a (no Coriolis).
    //
    // Tolerance. Outside the core U_w − iV_w = −i S R / z is analytic, so
    // the mean of U_w over a regular 16-gon about G is U_w(G) up to
    // O((a/r0)^16) (∫(z − z_G)^m dA = 0 for 0 < m < 16). What is left is the
    // nonlinearity of the traction τ(w) = k|w|w: with δ(P) = U_w(P) − U_w(G),
    // |τ(w + δ) − τ(w) − Dτ δ| ≤ 2k|δ|² and |δ| ≤ |U_w'|max |GP| with
    // |U_w'| = S R / r² ≤ S R / (r0 − a)², so the floe's acceleration is at
    // most 2k (S R / (r0 − a)²)² J_G / (ρ_i h |ω|).
    let (r_core, s, r0, a) = (500.0, 0.2, 3000.0, 100.0);
    let (ka, kw): (f64, f64) = (1.3 * 1.7e-3, 1024.0 * 5.0e-3);
    let ua = Vec2::new(10.0, 0.0);
    let env = format!(
        "air = {{ density = 1.3, drag = 1.7e-3, velocity = [10.0, 0.0] }}\nwater = {{ density = 1024.0, drag = 5.0e-3, field = \"vortex\", center = [0.0, 0.0], radius = {r_core}, speed = {s} }}"
    );
    let floe = format!("[[floe]]\n{}", regular(0.0, r0, a, 16));
    let scn = scenario(&case(&env, 100.0, &floe));
    let f = &scn.floes[0];
    let g = f.position;
    let drift = rankine(g, r_core, s) + ua * (ka / kw).sqrt();
    let model = ForceModel::new(&scn.floes);
    let state = |v: Vec2| BodyState {
        position: g,
        angle: 0.0,
        velocity: v,
        angular_velocity: 0.0,
    };
    let acc = |v: Vec2| {
        let forces = model.forces(&scn.environment, 0, 0.0, &state(v));
        let [ax, ay, _] = model.acceleration(0, &forces);
        Vec2::new(ax, ay)
    };
    let jg = area_properties(&f.shape).polar_moment;
    let grad = s * r_core / (r0 - a).powi(2);
    let tol = 2.0 * kw * grad * grad * jg / (f.surface_density() * f.area);
    let at_drift = acc(drift).norm();
    assert!(
        at_drift <= tol,
        "acceleration {at_drift:e} m/s² above {tol:e}"
    );
    // The tolerance is sharp enough to see a velocity off by 1 mm/s.
    let off = acc(drift + Vec2::new(0.0, 1e-3)).norm();
    assert!(off > 100.0 * tol, "{off:e} vs {tol:e}");
}

#[test]
fn the_centre_floe_of_the_vortex_case_moves_exactly_with_the_drifting_core() {
    // cases/vortex_field.toml: inside the core the flow is a rigid rotation
    // (S/R = 1e-4 rad/s) plus the drift (0.05, 0) m/s, which the centre
    // floe starts on: it must stay on it (the integrator's tolerance).
    let scn = load("vortex_field");
    let r = run(&scn, "event-driven");
    assert_eq!(r.summary.end, EndReason::Completed);
    let t = scn.duration;
    let row = r
        .trajectory
        .iter()
        .find(|row| row.floe == 0 && row.t == t)
        .unwrap();
    let expected = [0.05 * t, 0.0, 1e-4 * t, 0.05, 0.0, 1e-4];
    let got = [row.x, row.y, row.theta, row.vx, row.vy, row.omega];
    for (k, (g, e)) in got.iter().zip(expected).enumerate() {
        let scale = [0.05 * t, 0.05 * t, 1e-4 * t, 0.05, 0.05, 1e-4][k];
        assert!((g - e).abs() <= 1e-9 * scale, "component {k}: {g} vs {e}");
    }
}

/// The steady free-drift velocity `u` of a floe of mass per area `m`
/// (kg/m²) in a water velocity `uw` and air traction `tau_a` (N/m²),
/// with quadratic water drag `kw |uw − u| (uw − u)` and Coriolis
/// `−m f k ∧ u` (docs/physics.md §2.2), by Newton's method on the 2×2
/// balance, written here independently of `src/analysis`.
fn free_drift_newton(tau_a: Vec2, uw: Vec2, kw: f64, m: f64, f: f64) -> Vec2 {
    // Start from the Coriolis-free root.
    let mut u = uw + tau_a / (kw * tau_a.norm()).sqrt();
    for _ in 0..50 {
        let w = uw - u;
        let r = tau_a + w * (kw * w.norm()) - Vec2::new(-u.y, u.x) * (m * f);
        // d/du of kw|w|w = −kw (|w| I + w wᵀ/|w|); of −m f k∧u = −m f [[0, −1], [1, 0]].
        let n = w.norm().max(1e-300);
        let j = [
            [-kw * (n + w.x * w.x / n), -kw * w.x * w.y / n + m * f],
            [-kw * w.x * w.y / n - m * f, -kw * (n + w.y * w.y / n)],
        ];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let du = Vec2::new(
            (j[1][1] * r.x - j[0][1] * r.y) / det,
            (-j[1][0] * r.x + j[0][0] * r.y) / det,
        );
        u -= du;
        if du.norm() <= 1e-16 * u.norm() {
            break;
        }
    }
    u
}

#[test]
fn a_floe_in_a_drifting_vortex_core_keeps_the_free_drift_of_its_centre() {
    // docs/physics.md §2.4, "Free drift in a vortex". In the core of a
    // Rankine vortex drifting at c', the water moves as c' + Ω k ∧ (P − c(t)).
    // A floe at G = c(t) + d moving at u and spinning at Ω sees the relative
    // velocity W = Ω k ∧ d + c' − u at every point: uniform, so the drag is
    // area × traction with no torque, exactly as in a uniform current
    // U_w(G) = c' + Ω k ∧ d. Choosing d so that u = c' is the free drift
    // (with Coriolis) of a floe in U_w(G) and U_a, the floe drifts with the
    // core at c', spinning at Ω, forever. The state is an exact equilibrium
    // of the force law in the frame of the core, so the only departures are
    // rounding and the integrator's: 1e-9 of the scales below.
    let (r_core, s, f, h, rho_i) = (2000.0, 0.2, 1.4e-4, 1.0, 917.0);
    let omega = s / r_core;
    let (ka, kw): (f64, f64) = (1.3 * 1.7e-3, 1024.0 * 5.0e-3);
    let (ua, drift) = (Vec2::new(5.0, 0.0), Vec2::new(0.1, 0.0));
    let m = rho_i * h;
    let tau_a = ua * (ka * ua.norm());
    // The relative water velocity W of the balance τ_a + kw|W|W − m f k∧c' = 0,
    // and the offset d from the core's centre with Ω k ∧ d = W.
    let t_ = Vec2::new(-drift.y, drift.x) * (m * f) - tau_a;
    let w = t_ / (kw * t_.norm()).sqrt();
    let d = Vec2::new(w.y, -w.x) / omega;
    let a = 200.0;
    assert!(d.norm() + a < 0.7 * r_core, "{}", d.norm());
    // The floe, a 16-gon about the origin; the core's centre at −d.
    let env = format!(
        "coriolis = {f:?}\nair = {{ density = 1.3, drag = 1.7e-3, velocity = [{:?}, {:?}] }}\nwater = {{ density = 1024.0, drag = 5.0e-3, field = \"vortex\", center = [{:?}, {:?}], radius = {r_core:?}, speed = {s:?}, center_velocity = [{:?}, {:?}] }}",
        ua.x, ua.y, -d.x, -d.y, drift.x, drift.y
    );
    let floe = format!(
        "[[floe]]\n{}\nvelocity = [{:?}, {:?}]\nangular_velocity = {omega:?}",
        regular(0.0, 0.0, a, 16),
        drift.x,
        drift.y
    );
    let duration = 21600.0;
    let scn = scenario(&case(&env, duration, &floe));
    let g0 = scn.floes[0].position;
    // The analytic free drift at the floe's centre, by Newton's method on
    // the water velocity there (the independent Rankine formula above).
    let uw = rankine(g0 + d, r_core, s) + drift;
    let u = free_drift_newton(tau_a, uw, kw, m, f);
    assert!((u - drift).norm() <= 1e-12 * drift.norm(), "{u:?}");
    // The closed form of docs/physics.md §2.2 gives the same root.
    let b = Vec2::new(-uw.y, uw.x) * (m * f) - tau_a;
    let w2 = ((m.powi(4) * f.powi(4) + 4.0 * kw * kw * b.norm_squared()).sqrt() - (m * f).powi(2))
        / (2.0 * kw * kw);
    let wc = (b * (kw * w2.sqrt()) - Vec2::new(-b.y, b.x) * (m * f)) * (w2 / b.norm_squared());
    assert!(
        (uw - wc - u).norm() <= 1e-12 * u.norm(),
        "{:?} vs {u:?}",
        uw - wc
    );
    let r = run(&scn, "free-drift");
    assert_eq!(r.summary.end, EndReason::Completed, "{:?}", r.summary.end);
    assert_eq!(r.trajectory.len(), 21);
    let mut worst = [0.0f64; 3];
    for row in &r.trajectory {
        let dv = (Vec2::new(row.vx, row.vy) - u).norm() / u.norm();
        let dw = (row.omega - omega).abs() / omega;
        let dx = (Vec2::new(row.x, row.y) - (g0 + u * row.t)).norm() / (u.norm() * duration);
        for (k, e) in [dv, dw, dx].into_iter().enumerate() {
            worst[k] = worst[k].max(e);
        }
    }
    assert!(
        worst.iter().all(|&e| e <= 1e-9),
        "relative departures (velocity, spin, position): {worst:?}"
    );
}
