//! The floe model, the environment forces and the smooth integrator against
//! closed forms (docs/physics.md §1, §2 and §4).

use crate::common::{case_text, counter, load, run, run_with, scenario, within_bound};
use floebench::formulation::FormulationOptions;
use floebench::geometry::{area_properties, cross, perp, Vec2};
use floebench::model::{
    Environment, Floe, FloeOrigin, Fluid, IntegratorKind, Scenario, VelocityField, VelocitySeries,
};
use floebench::physics::{
    air_drag_quadrature, air_velocity, ForceModel, Forces, Quadrature, SmoothIntegrator,
};
use floebench::run::{EndReason, RunResult};
use floebench::state::{BodyState, Ledger, System};
use std::f64::consts::PI;

/// The energy ledger `E(t) − E(0) − W_ext + D` stays below 1e-6 of the work
/// of the wind at every sample.
fn ledger_balances(r: &RunResult) {
    let e = &r.summary.energy;
    assert!(
        e.max_abs_residual < 1e-6 * e.ledger.work_air,
        "residual {} of {}",
        e.max_abs_residual,
        e.ledger.work_air
    );
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

const HEADER: &str = r#"
[contact]
restitution = 0.5
friction = 0.3
"#;

// ---------------------------------------------------------------------------
// Mass properties. Polygons are placed far from the origin so that the
// formulas' rounding is exercised; 1e-12 relative is the required bound.

fn offset(p: &[(f64, f64)], o: (f64, f64)) -> Vec<Vec2> {
    p.iter()
        .map(|&(x, y)| Vec2::new(x + o.0, y + o.1))
        .collect()
}

#[test]
fn mass_properties_of_a_square() {
    let a = 7.5;
    let poly = offset(&[(0.0, 0.0), (a, 0.0), (a, a), (0.0, a)], (1234.5, -987.25));
    let p = area_properties(&poly);
    assert!(rel(p.area, a * a) < 1e-12);
    assert!(rel(p.polar_moment, a.powi(4) / 6.0) < 1e-12);
    assert!((p.centroid - Vec2::new(1234.5 + a / 2.0, -987.25 + a / 2.0)).norm() < 1e-12 * 1234.5);
}

#[test]
fn mass_properties_of_a_right_triangle() {
    let (a, b) = (30.0, 12.0);
    let poly = offset(&[(0.0, 0.0), (a, 0.0), (0.0, b)], (5e3, 2e3));
    let p = area_properties(&poly);
    assert!(rel(p.area, a * b / 2.0) < 1e-12);
    // Ix + Iy about the centroid: a b (a² + b²) / 36.
    assert!(rel(p.polar_moment, a * b * (a * a + b * b) / 36.0) < 1e-12);
    assert!((p.centroid - Vec2::new(5e3 + a / 3.0, 2e3 + b / 3.0)).norm() < 1e-12 * 5e3);
}

#[test]
fn mass_properties_of_a_regular_heptagon_and_the_floe_built_on_it() {
    let (n, r) = (7usize, 250.0);
    let pts: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let t = 2.0 * PI * k as f64 / n as f64 + 0.3;
            (r * t.cos(), r * t.sin())
        })
        .collect();
    let poly = offset(&pts, (-4e4, 7e4));
    let p = area_properties(&poly);
    let phi = 2.0 * PI / n as f64;
    let area = 0.5 * n as f64 * r * r * phi.sin();
    // Fan of n isosceles triangles: n R⁴ sin φ (2 + cos φ) / 12.
    let polar = n as f64 * r.powi(4) * phi.sin() * (2.0 + phi.cos()) / 12.0;
    assert!(rel(p.area, area) < 1e-12, "area {}", rel(p.area, area));
    assert!(
        rel(p.polar_moment, polar) < 1e-12,
        "polar {}",
        rel(p.polar_moment, polar)
    );

    let text = format!(
        "[case]\nversion = 1\nname = \"t\"\nduration = 1.0\noutput_interval = 1.0\n{HEADER}[[floe]]\npolygon = {:?}\nthickness = 1.5\ndensity = 900.0\n",
        poly.iter().map(|v| [v.x, v.y]).collect::<Vec<_>>()
    );
    let scn = scenario(&text);
    let f = &scn.floes[0];
    assert!(rel(f.mass, 900.0 * 1.5 * area) < 1e-12);
    assert!(rel(f.inertia, 900.0 * 1.5 * polar) < 1e-12);
    assert!(rel(f.radius, r) < 1e-12);
}

// ---------------------------------------------------------------------------
// Forces.

fn one_floe(env: &str, extra: &str, floe: &str) -> Scenario {
    scenario(&format!(
        r#"# test
[case]
version = 1
name = "t"
{extra}
[environment]
{env}
[contact]
restitution = 0.5
friction = 0.3
[[floe]]
{floe}
"#
    ))
}

const PENTAGON: &str = "polygon = [[0.0, 0.0], [400.0, -50.0], [600.0, 200.0], [350.0, 500.0], [-50.0, 300.0]]\nthickness = 1.0";

#[test]
fn drag_integral_of_a_translating_floe_is_area_times_traction() {
    let scn = one_floe(
        "air = { density = 1.3, drag = 1.7e-3, velocity = [8.0, -3.0] }\nwater = { density = 1025.0, drag = 5.5e-3, velocity = [0.2, 0.1] }",
        "duration = 1.0\noutput_interval = 1.0",
        PENTAGON,
    );
    let f = &scn.floes[0];
    let model = ForceModel::new(&scn.floes);
    for angle in [0.0, 0.7, 2.9] {
        let b = BodyState {
            position: f.position,
            angle,
            velocity: Vec2::new(-0.3, 0.45),
            angular_velocity: 0.0,
        };
        let forces = model.forces(&scn.environment, 0, 0.0, &b);
        let u = Vec2::new(0.2, 0.1) - b.velocity;
        let expected = u * (1025.0 * 5.5e-3 * u.norm() * f.area);
        assert!((forces.water - expected).norm() < 1e-12 * expected.norm());
        let ua = Vec2::new(8.0, -3.0);
        let expected_air = ua * (1.3 * 1.7e-3 * ua.norm() * f.area);
        assert!((forces.air - expected_air).norm() < 1e-12 * expected_air.norm());
        // Uniform traction about the centroid: no torque, to rounding of ∫ GP.
        assert!(forces.water_torque.abs() < 1e-12 * expected.norm() * f.radius);
    }
}

#[test]
fn a_spinning_floe_in_still_water_loses_angular_momentum() {
    let scn = one_floe(
        "water = { density = 1025.0, drag = 5.5e-3, velocity = [0.0, 0.0] }",
        "duration = 2000.0\noutput_interval = 100.0",
        &format!("{PENTAGON}\nangular_velocity = 0.01"),
    );
    let f = &scn.floes[0];
    let model = ForceModel::new(&scn.floes);
    let b = BodyState {
        position: f.position,
        angle: 0.0,
        velocity: Vec2::zeros(),
        angular_velocity: 0.01,
    };
    let forces = model.forces(&scn.environment, 0, 0.0, &b);
    assert!(forces.water_torque < 0.0, "drag torque opposes the spin");
    let r = run(&scn, "free-drift");
    let omegas: Vec<f64> = r.trajectory.iter().map(|row| row.omega).collect();
    for w in omegas.windows(2) {
        assert!(
            w[1] < w[0] && w[1] > 0.0,
            "|ω| must decrease monotonically: {w:?}"
        );
    }
    assert!(omegas.last().unwrap() < &(0.5 * 0.01));
}

// The force model: air drag by quadrature, the split of the forces, the map
// to accelerations.

/// ρ_a C_a of the tests' air, kg/m³.
const KA: f64 = 1.3 * 1.7e-3;

fn windy(ua: Vec2) -> Environment {
    Environment {
        coriolis: 0.0,
        air: Fluid {
            density: 1.3,
            drag: 1.7e-3,
            velocity: VelocityField::Uniform(VelocitySeries::Constant(ua)),
        },
        water: Fluid::none(),
        outside: Default::default(),
    }
}

/// A triangle, a square and an irregular convex hexagon, world outlines at
/// t = 0 away from the origin, m.
fn test_shapes() -> Vec<(&'static str, Vec<Vec2>)> {
    vec![
        (
            "triangle",
            offset(&[(0.0, 0.0), (300.0, 40.0), (90.0, 210.0)], (2e3, -1e3)),
        ),
        (
            "square",
            offset(
                &[(0.0, 0.0), (120.0, 0.0), (120.0, 120.0), (0.0, 120.0)],
                (-500.0, 700.0),
            ),
        ),
        (
            "hexagon",
            offset(
                &[
                    (0.0, 0.0),
                    (150.0, -30.0),
                    (270.0, 60.0),
                    (300.0, 180.0),
                    (180.0, 270.0),
                    (30.0, 150.0),
                ],
                (4e3, 3e3),
            ),
        ),
    ]
}

#[test]
fn air_drag_quadrature_of_a_uniform_wind_is_the_closed_form_without_torque() {
    let ua = Vec2::new(8.0, -3.0);
    let env = windy(ua);
    let expected_traction = ua * (KA * ua.norm());
    for (name, poly) in test_shapes() {
        let floe =
            Floe::from_world_polygon(&poly, 1.0, 917.0, Vec2::zeros(), 0.0, FloeOrigin::Listed(0));
        let model = ForceModel::new(std::slice::from_ref(&floe));
        for (angle, shift) in [
            (0.0, Vec2::zeros()),
            (0.7, Vec2::new(350.0, -1200.0)),
            (2.9, Vec2::new(-4e3, 2.5e3)),
            (-1.3, Vec2::new(1e4, 1e4)),
        ] {
            let b = BodyState {
                position: floe.position + shift,
                angle,
                velocity: Vec2::new(-0.3, 0.45),
                angular_velocity: 2e-3,
            };
            // The model takes the closed form: area × traction, no torque.
            let forces = model.forces(&env, 0, 0.0, &b);
            let expected = expected_traction * floe.area;
            assert_eq!(forces.air, expected, "{name}, θ = {angle}");
            assert_eq!(forces.air_torque, 0.0, "{name}, θ = {angle}");
            // The quadrature path agrees with it, its torque is rounding.
            let (f, m) =
                air_drag_quadrature(KA, model.quadrature(0), &b, |p| air_velocity(&env, p, 0.0));
            assert!(
                (f - forces.air).norm() <= 1e-13 * forces.air.norm(),
                "{name}, θ = {angle}: force {f:?} vs {:?}",
                forces.air
            );
            assert!(
                m.abs() <= 1e-12 * forces.air.norm() * floe.radius,
                "{name}, θ = {angle}: torque {m} N·m"
            );
        }
    }
}

#[test]
fn air_drag_quadrature_of_a_shear_wind_matches_the_analytic_integrals() {
    // U_a = (a + b y, 0), positive over the floe: the traction k (a + b y)² x̂
    // is of degree 2 and its moment of degree 3, both integrated exactly by
    // the degree-5 rule. Rectangle of half sides (hx, hy) about G; with
    // s = y − G_y and u_G = a + b G_y:
    //   F_x = k 2hx ∫ (u_G + b s)² ds = k 2hx (2 hy u_G² + 2 b² hy³ / 3),
    //   M_G = −k 2hx ∫ s (u_G + b s)² ds = −k 2hx 4 u_G b hy³ / 3.
    let (a, b) = (2.0, 0.01);
    let (hx, hy) = (150.0, 75.0);
    let g = Vec2::new(1150.0, 275.0); // y in [200, 350] m: U_a in [4, 5.5] m/s
    let ug = a + b * g.y;
    let fx = KA * 2.0 * hx * (2.0 * hy * ug * ug + 2.0 * b * b * hy.powi(3) / 3.0);
    let torque = -KA * 2.0 * hx * 4.0 * ug * b * hy.powi(3) / 3.0;
    let wind = |p: &Vec2| Vec2::new(a + b * p.y, 0.0);
    // The same world rectangle at each quarter turn of the body frame.
    for k in 0..4 {
        let (sx, sy) = if k % 2 == 0 { (hx, hy) } else { (hy, hx) };
        let shape = [
            Vec2::new(-sx, -sy),
            Vec2::new(sx, -sy),
            Vec2::new(sx, sy),
            Vec2::new(-sx, sy),
        ];
        let quad = Quadrature::for_shape(&shape);
        let body = BodyState {
            position: g,
            angle: k as f64 * PI / 2.0,
            velocity: Vec2::new(0.3, -0.2),
            angular_velocity: 1e-3,
        };
        let (f, m) = air_drag_quadrature(KA, &quad, &body, wind);
        assert!(rel(f.x, fx) < 1e-12, "turn {k}: F_x {} vs {fx}", f.x);
        assert!(f.y.abs() < 1e-12 * fx, "turn {k}: F_y {}", f.y);
        assert!(rel(m, torque) < 1e-12, "turn {k}: M {m} vs {torque}");
    }
}

#[test]
fn water_drag_quadrature_is_unchanged() {
    // The water drag of the force law before the force model, verbatim: the
    // model must give the same bits.
    let scn = one_floe(
        "water = { density = 1025.0, drag = 5.5e-3, velocity = [0.2, 0.1] }\nair = { density = 1.3, drag = 1.7e-3, velocity = [8.0, -3.0] }",
        "duration = 1.0\noutput_interval = 1.0",
        PENTAGON,
    );
    let f = &scn.floes[0];
    let model = ForceModel::new(&scn.floes);
    assert_eq!(model.quadrature(0).nodes().len(), 7 * f.shape.len());
    let kw = 1025.0 * 5.5e-3;
    let uw = Vec2::new(0.2, 0.1);
    for (angle, velocity, omega) in [
        (0.0, Vec2::new(0.2, 0.1), 0.0),
        (0.7, Vec2::new(-0.3, 0.45), 0.0),
        (2.9, Vec2::new(0.1, 0.05), 3e-3),
        (-1.1, Vec2::new(0.5, -0.2), -2e-2),
    ] {
        let b = BodyState {
            position: f.position + Vec2::new(-300.0, 800.0),
            angle,
            velocity,
            angular_velocity: omega,
        };
        let forces = model.forces(&scn.environment, 0, 0.0, &b);
        let (mut water, mut water_torque) = (Vec2::zeros(), 0.0);
        let (s, c) = b.angle.sin_cos();
        for (r0, w) in model.quadrature(0).nodes() {
            let r = Vec2::new(c * r0.x - s * r0.y, s * r0.x + c * r0.y);
            let u = uw - b.velocity - perp(&r) * b.angular_velocity;
            let tau = u * (kw * u.norm()) * *w;
            water += tau;
            water_torque += cross(&r, &tau);
        }
        assert_eq!(forces.water, water, "θ = {angle}");
        assert_eq!(forces.water_torque, water_torque, "θ = {angle}");
    }
}

#[test]
fn the_air_torque_enters_the_torque_the_power_and_the_work() {
    let f = Forces {
        air: Vec2::new(3.0, 4.0),
        air_torque: 5.0,
        water: Vec2::new(1.0, -2.0),
        water_torque: -7.0,
        coriolis: Vec2::new(0.5, 0.25),
    };
    assert_eq!(f.force(), Vec2::new(4.5, 2.25));
    assert_eq!(f.torque(), -2.0);
    let b = BodyState {
        position: Vec2::new(10.0, 20.0),
        angle: 0.3,
        velocity: Vec2::new(2.0, -1.0),
        angular_velocity: 0.5,
    };
    // air 3·2 − 4 + 5·0.5, water 2 + 2 − 7·0.5, Coriolis 1 − 0.25.
    assert_eq!(f.powers(&b), (4.5, 0.5, 0.75));
    assert_eq!(f.works(&Vec2::new(-1.0, 0.5), 2.0), (9.0, -16.0, -0.375));
}

#[test]
fn the_acceleration_is_force_over_mass_and_torque_over_inertia() {
    // Two floes of different mass and inertia: each gets its own.
    let scn = scenario(&format!(
        "[case]\nversion = 1\nname = \"t\"\nduration = 1.0\noutput_interval = 1.0\n{HEADER}\
         [[floe]]\n{PENTAGON}\n\
         [[floe]]\npolygon = [[1000.0, 0.0], [1010.0, 0.0], [1010.0, 20.0], [1000.0, 20.0]]\nthickness = 2.0\n"
    ));
    let model = ForceModel::new(&scn.floes);
    let f = Forces {
        air: Vec2::new(3.0e4, 4.0e4),
        air_torque: 5.0e6,
        water: Vec2::new(1.0e4, -2.0e4),
        water_torque: -7.0e6,
        coriolis: Vec2::new(0.5e4, 0.25e4),
    };
    // Rectangle 10 m × 20 m, 2 m thick: M = 917 · 2 · 200 kg,
    // I = ρ h (a b (a² + b²) / 12) kg·m².
    let m1 = 917.0 * 2.0 * 200.0;
    let i1 = 917.0 * 2.0 * (10.0 * 20.0 * (100.0 + 400.0) / 12.0);
    let a1 = model.acceleration(1, &f);
    assert!(rel(a1[0], 4.5e4 / m1) < 1e-12, "{a1:?}");
    assert!(rel(a1[1], 2.25e4 / m1) < 1e-12, "{a1:?}");
    assert!(rel(a1[2], -2.0e6 / i1) < 1e-12, "{a1:?}");
    let p = &scn.floes[0];
    let a0 = model.acceleration(0, &f);
    assert!(rel(a0[0], 4.5e4 / p.mass) < 1e-15, "{a0:?}");
    assert!(rel(a0[2], -2.0e6 / p.inertia) < 1e-15, "{a0:?}");
    assert_eq!(
        model.wrench_acceleration(1, &f.force(), f.torque()),
        a1,
        "the same map"
    );
}

// ---------------------------------------------------------------------------
// Free drift.

#[test]
fn free_drift_reaches_the_analytic_velocity_without_coriolis() {
    let scn = load("free_drift");
    let r = run(&scn, "free-drift");
    let env = &scn.environment;
    let expected = Vec2::new(0.1, 0.0)
        + Vec2::new(10.0, 0.0) * (env.air.drag_factor() / env.water.drag_factor()).sqrt();
    let last = r.final_state.bodies[0];
    assert!(
        (last.velocity - expected).norm() < 1e-6 * expected.norm(),
        "{:?} vs {expected:?}",
        last.velocity
    );
    ledger_balances(&r);
}

#[test]
fn free_drift_reaches_the_analytic_velocity_with_coriolis() {
    let scn = load("free_drift_coriolis");
    let r = run(&scn, "free-drift");
    let mut angles = Vec::new();
    for i in 0..scn.floes.len() {
        // The one steady-drift solver, the one `floebench check` uses.
        let expected = floebench::analysis::check::steady_drift_velocity(&scn, i)
            .expect("steady drift converges");
        let v = r.final_state.bodies[i].velocity;
        assert!(
            (v - expected).norm() < 1e-6 * expected.norm(),
            "floe {i}: {v:?} vs {expected:?}"
        );
        angles.push(expected.y.atan2(expected.x));
    }
    // Turned to the right of the wind, more for the thicker floe.
    assert!(angles[0] < 0.0 && angles[1] < angles[0], "{angles:?}");
    ledger_balances(&r);
}

#[test]
fn after_the_wind_stops_the_floe_makes_inertial_circles_of_period_two_pi_over_f() {
    let scn = load("inertial_oscillation");
    let r = run(&scn, "free-drift");
    // Direction of the velocity after the wind has stopped, unwrapped.
    let rows: Vec<_> = r.trajectory.iter().filter(|row| row.t >= 20200.0).collect();
    let mut phase = Vec::new();
    let mut prev = f64::NAN;
    let mut turn = 0.0;
    for row in &rows {
        let a = row.vy.atan2(row.vx);
        if prev.is_finite() {
            let mut d = a - prev;
            while d > PI {
                d -= 2.0 * PI;
            }
            while d < -PI {
                d += 2.0 * PI;
            }
            turn += d;
        }
        prev = a;
        phase.push((row.t, turn));
    }
    let (t0, p0) = phase[0];
    let (t1, p1) = *phase.last().unwrap();
    let rate = (p1 - p0) / (t1 - t0);
    let period = 2.0 * PI / rate.abs();
    let expected = 2.0 * PI / scn.environment.coriolis;
    assert!(rate < 0.0, "northern hemisphere: clockwise");
    assert!(
        rel(period, expected) < 1e-3,
        "period {period} vs {expected}"
    );
}

// ---------------------------------------------------------------------------
// Integrators under a constant force.

fn constant_wind(integrator: &str) -> Scenario {
    one_floe(
        "air = { density = 1.3, drag = 1.7e-3, velocity = [10.0, 4.0] }",
        &format!("duration = 1000.0\noutput_interval = 1000.0\n[integrator]\n{integrator}"),
        "polygon = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]\nthickness = 1.0\nvelocity = [-0.3, 0.2]",
    )
}

#[test]
fn the_default_integrator_is_exact_under_a_constant_force() {
    let scn = constant_wind("method = \"dopri5\"");
    let f = &scn.floes[0];
    let ua = Vec2::new(10.0, 4.0);
    let a = ua * (1.3 * 1.7e-3 * ua.norm() / (917.0 * 1.0));
    let mut integ = SmoothIntegrator::new(&scn, None);
    for &dt in &[1e-3, 1.0, 137.0, 5000.0] {
        let mut sys = System::initial(&scn);
        let mut ledger = Ledger::default();
        integ
            .advance(&scn, 0, &mut sys.bodies[0], &mut ledger, 0.0, dt)
            .unwrap();
        let x = f.position + f.velocity * dt + a * (0.5 * dt * dt);
        let got = sys.bodies[0].position;
        // Relative to x(t) (5 m from the origin here, so rounding of the
        // position itself is 1e-16 relative and the bound is not lenient).
        assert!(
            (got - x).norm() <= 1e-12 * x.norm(),
            "dt {dt}: {got:?} vs {x:?}"
        );
        let v = f.velocity + a * dt;
        assert!((sys.bodies[0].velocity - v).norm() <= 1e-12 * v.norm());
    }
}

#[test]
fn explicit_euler_shows_its_first_order_error() {
    let ua = Vec2::new(10.0, 4.0);
    let a = ua * (1.3 * 1.7e-3 * ua.norm() / 917.0);
    let t = 1000.0;
    let mut errors = Vec::new();
    for h in [10.0, 5.0, 2.5] {
        let scn = constant_wind(&format!("method = \"euler\"\nmax_step = {h}"));
        let r = run(&scn, "free-drift");
        let f = &scn.floes[0];
        let exact = f.position + f.velocity * t + a * (0.5 * t * t);
        let err = (r.final_state.bodies[0].position - exact).norm();
        // Explicit Euler under a constant force errs by exactly a T h / 2.
        assert!(rel(err, 0.5 * a.norm() * t * h) < 1e-6, "h {h}: {err}");
        errors.push(err);
    }
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((order - 1.0).abs() < 1e-6, "observed order {order}");
    }
    // And it is selectable from the command line's option too.
    let scn = constant_wind("max_step = 5.0");
    let r = run_with(
        &scn,
        "free-drift",
        &FormulationOptions {
            integrator: Some(IntegratorKind::Euler),
            ..Default::default()
        },
    );
    assert_eq!(counter(&r, "integrator_steps"), 200.0);
}

// ---------------------------------------------------------------------------
// Negligible water drag (found by the fuzz harness)

/// `cases/free_drift.toml` with a water drag coefficient of `drag`, the
/// Coriolis force on and one output, at the end.
fn free_drift_with_water_drag(drag: &str) -> Scenario {
    let text = case_text("free_drift")
        .replacen("drag = 5.0e-3", &format!("drag = {drag}"), 1)
        .replacen("coriolis = 0.0", "coriolis = 1.4e-4", 1)
        .replacen("output_interval = 100.0", "output_interval = 20000.0", 1);
    scenario(&text)
}

#[test]
fn a_subnormal_water_drag_keeps_the_stability_bound_finite() {
    // rho_w C_w = 1024 x 5e-324 is subnormal: rho_a C_a / (rho_w C_w)
    // overflows, and the bound used to come out as 0 s (the event-driven
    // scheme then stepped by 0 s forever).
    let scn = free_drift_with_water_drag("5e-324");
    let env = &scn.environment;
    let (ka, kw) = (env.air.drag_factor(), env.water.drag_factor());
    assert!(kw > 0.0 && kw < f64::MIN_POSITIVE, "subnormal: {kw}");
    let f = &scn.floes[0];
    let exact = f.surface_density() / (2.0 * 10.0 * ka.sqrt() * kw.sqrt());
    let bound = scn.euler_stability_bound(0);
    assert!(rel(bound, exact) < 1e-12, "{bound} against {exact}");
    let r = within_bound(move || Ok(run(&scn, "event-driven"))).unwrap();
    assert_eq!(r.summary.end, EndReason::Completed);
}
