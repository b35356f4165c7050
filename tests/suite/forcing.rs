//! Winds and currents that vary in space (docs/physics.md §2.4) and CF
//! NetCDF in and out: the grid against the analytic fields it samples, the
//! shear-current and vortex closed forms, the trajectory file read back,
//! and bad forcing files refused with errors naming the file, the variable
//! and the point.

use crate::common::{case_path, load, run, scenario, tempdir};
use floebench::formulation::load_case;
use floebench::geometry::{area_properties, Vec2};
use floebench::model::forcing::GridData;
use floebench::model::netcdf::{read_grid, write_grid, GridFile, GridRequest};
use floebench::model::Scenario;
use floebench::physics::ForceModel;
use floebench::run::netcdf_out::{read_trajectory, write_trajectory};
use floebench::run::{EndReason, RunResult};
use floebench::state::BodyState;
use std::path::Path;

/// A regular `n`-gon of circumradius `r` centred at `(cx, cy)`, as TOML.
fn regular(cx: f64, cy: f64, r: f64, n: usize) -> String {
    let pts: Vec<String> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            format!("[{}, {}]", cx + r * a.cos(), cy + r * a.sin())
        })
        .collect();
    format!("polygon = [{}]\nthickness = 1.0", pts.join(", "))
}

/// A case with `env` as its `[environment]` and `floes` (TOML tables).
fn case(env: &str, duration: f64, floes: &str) -> String {
    let floes = if floes.starts_with("[[") {
        floes.to_string()
    } else {
        format!("[[floe]]\n{floes}")
    };
    format!(
        "# test\n[case]\nversion = 1\nname = \"t\"\nduration = {duration}\noutput_interval = {}\n\n[environment]\n{env}\n\n[contact]\nrestitution = 0.5\nfriction = 0.3\n\n{floes}\n",
        duration / 20.0
    )
}

/// A projected grid (x, y in km) of the `f(x m, y m, t s)` components
/// `(u, v)` at `times` (s), as `u`/`v`, with the given units.
fn grid_file(
    xs_km: &[f64],
    ys_km: &[f64],
    times: &[f64],
    units: &str,
    f: impl Fn(f64, f64, f64) -> (f64, f64),
) -> GridFile {
    let (mut u, mut v) = (Vec::new(), Vec::new());
    for &t in times {
        for &y in ys_km {
            for &x in xs_km {
                let (a, b) = f(1e3 * x, 1e3 * y, t);
                u.push(a);
                v.push(b);
            }
        }
    }
    GridFile {
        title: "test".into(),
        x: ("x".into(), "km".into(), xs_km.to_vec()),
        y: ("y".into(), "km".into(), ys_km.to_vec()),
        time: Some((
            "time".into(),
            "seconds since 2020-01-01 00:00:00".into(),
            times.to_vec(),
        )),
        variables: vec![
            ("u".into(), units.into(), "u".into(), u),
            ("v".into(), units.into(), "v".into(), v),
        ],
    }
}

/// Writes `grid` as `dir/g.nc` and `text` as `dir/c.toml`; loads the case.
fn load_with_grid(dir: &Path, grid: &GridFile, text: &str) -> Result<Scenario, String> {
    write_grid(&dir.join("g.nc"), grid).unwrap_or_else(|e| panic!("{e}"));
    let path = dir.join("c.toml");
    std::fs::write(&path, text).unwrap();
    load_case(&path).map_err(|e| e.to_string())
}

const GRIDDED_WATER: &str = "water = { density = 1024.0, drag = 5.0e-3, field = \"netcdf\", file = \"g.nc\", variables = [\"u\", \"v\"] }";

/// The largest relative difference between two runs' trajectories, each
/// quantity against the largest magnitude it takes.
fn trajectory_difference(a: &RunResult, b: &RunResult) -> f64 {
    assert_eq!(a.trajectory.len(), b.trajectory.len());
    let cols = |r: &floebench::run::TrajectoryRow| [r.x, r.y, r.theta, r.vx, r.vy, r.omega];
    let mut scale = [0.0f64; 6];
    for r in &a.trajectory {
        for (s, v) in scale.iter_mut().zip(cols(r)) {
            *s = s.max(v.abs());
        }
    }
    let mut worst = 0.0f64;
    for (ra, rb) in a.trajectory.iter().zip(&b.trajectory) {
        assert_eq!((ra.t, ra.floe), (rb.t, rb.floe));
        for ((x, y), s) in cols(ra).iter().zip(cols(rb)).zip(scale) {
            if s > 0.0 {
                worst = worst.max((x - y).abs() / s);
            }
        }
    }
    worst
}

#[test]
fn a_linear_field_is_interpolated_exactly_by_the_grid() {
    let dir = tempdir();
    let lin = |x: f64, y: f64, t: f64| {
        (
            0.3 - 2e-5 * x + 7e-6 * y + 1e-6 * t,
            -0.1 + 4e-6 * x + 1.5e-5 * y,
        )
    };
    let xs = [-5.0, -2.0, 0.0, 1.5, 6.0];
    let ys = [-3.0, 0.5, 4.0];
    let grid = grid_file(&xs, &ys, &[0.0, 1800.0, 3600.0], "m s-1", lin);
    let text = case(GRIDDED_WATER, 3600.0, &regular(0.0, 0.0, 50.0, 6));
    let scn = load_with_grid(dir.path(), &grid, &text).unwrap_or_else(|e| panic!("{e}"));
    let field = &scn.environment.water.velocity;
    let mut worst = 0.0f64;
    for k in 0..200 {
        let s = k as f64 / 200.0;
        let p = Vec2::new(-5000.0 + 11000.0 * s, -3000.0 + 7000.0 * (s * 7.3).fract());
        let t = 3600.0 * (s * 3.1).fract();
        let u = field.at(&p, t, &scn.environment.outside);
        let (ex, ey) = lin(p.x, p.y, t);
        worst = worst.max((u.x - ex).abs().max((u.y - ey).abs()) / ex.abs().max(ey.abs()));
    }
    assert!(worst <= 1e-12, "largest relative error {worst:e}");
    assert!(scn.environment.outside.first().is_none());
}

#[test]
fn a_gridded_uniform_field_gives_the_trajectory_of_the_uniform_case() {
    let dir = tempdir();
    let floe = regular(100.0, -50.0, 300.0, 7);
    let uniform = scenario(&case(
        "coriolis = 1.4e-4\nair = { density = 1.3, drag = 1.7e-3, velocity = [9.0, -4.0] }\nwater = { density = 1024.0, drag = 5.0e-3, velocity = [0.1, 0.05] }",
        20000.0,
        &floe,
    ));
    let mut grid = grid_file(
        &[-20.0, 0.0, 20.0],
        &[-20.0, 20.0],
        &[0.0, 30000.0],
        "m s-1",
        |_, _, _| (9.0, -4.0),
    );
    let water = grid_file(
        &[-20.0, 0.0, 20.0],
        &[-20.0, 20.0],
        &[0.0, 30000.0],
        "m s-1",
        |_, _, _| (0.1, 0.05),
    );
    grid.variables[0].0 = "u10".into();
    grid.variables[1].0 = "v10".into();
    grid.variables.push((
        "uo".into(),
        "m s-1".into(),
        "uo".into(),
        water.variables[0].3.clone(),
    ));
    grid.variables.push((
        "vo".into(),
        "m s-1".into(),
        "vo".into(),
        water.variables[1].3.clone(),
    ));
    let text = case(
        "coriolis = 1.4e-4\nair = { density = 1.3, drag = 1.7e-3, field = \"netcdf\", file = \"g.nc\" }\nwater = { density = 1024.0, drag = 5.0e-3, field = \"netcdf\", file = \"g.nc\" }",
        20000.0,
        &floe,
    );
    let gridded = load_with_grid(dir.path(), &grid, &text).unwrap_or_else(|e| panic!("{e}"));
    let (a, b) = (run(&uniform, "free-drift"), run(&gridded, "free-drift"));
    assert_eq!(b.summary.end, EndReason::Completed);
    let d = trajectory_difference(&a, &b);
    assert!(d <= 1e-12, "relative difference {d:e}");
    // Not trivially equal: the floe drifted several kilometres.
    let last = a.trajectory.last().unwrap();
    assert!(last.x > 3000.0, "{}", last.x);
}

#[test]
fn the_gridded_case_equals_its_analytic_fields() {
    // cases/gridded_drift.nc holds linear fields (examples/gridded_forcing.rs):
    // the same case with field = "linear" must give the same trajectories.
    let text = std::fs::read_to_string(case_path("gridded_drift")).unwrap();
    // The linear fields on the grid's own extent (the largest speeds, hence
    // the step bounds, are then the same).
    let (o, lon, lat) = ([0.0, 79.0], 0.6, 0.2);
    let (x0, x1) = (
        floebench::model::netcdf::project_lon(-lon, o),
        floebench::model::netcdf::project_lon(lon, o),
    );
    let (y0, y1) = (
        floebench::model::netcdf::project_lat(79.0 - lat, o),
        floebench::model::netcdf::project_lat(79.0 + lat, o),
    );
    let extent = format!("[[{x0:?}, {y0:?}], [{x1:?}, {y1:?}]]");
    let air = format!("air   = {{ density = 1.3,    drag = 1.7e-3, field = \"linear\", velocity = [8.0, 2.0], gradient = [[-5.0e-5, 2.0e-5], [1.0e-5, 0.0]], extent = {extent}, scale = [[0.0, 0.6], [10800.0, 1.0], [21600.0, 1.2], [32400.0, 0.9], [43200.0, 0.5]] }}");
    let water = format!("water = {{ density = 1024.0, drag = 5.0e-3, field = \"linear\", velocity = [0.1, 0.0], gradient = [[0.0, 2.0e-6], [0.0, 0.0]], extent = {extent} }}");
    let analytic: String = text
        .lines()
        .map(|l| {
            if l.starts_with("air ") {
                air.as_str()
            } else if l.starts_with("water ") {
                water.as_str()
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    // Euler with a fixed step (below both stability bounds): the two runs
    // take the same steps, and differ by the rounding of the interpolation.
    let euler = "\n[integrator]\nmethod = \"euler\"\nmax_step = 20.0\n";
    let analytic = scenario(&format!("{analytic}{euler}"));
    let gridded = {
        let path = case_path("gridded_drift");
        let text = format!("{text}{euler}");
        floebench::formulation::parse_case(&text, &path).unwrap_or_else(|e| panic!("{e}"))
    };
    let (a, b) = (run(&analytic, "free-drift"), run(&gridded, "free-drift"));
    assert_eq!(b.summary.end, EndReason::Completed, "{:?}", b.summary.end);
    let d = trajectory_difference(&a, &b);
    assert!(d <= 1e-12, "relative difference {d:e}");
}

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

#[test]
fn the_trajectory_netcdf_file_reads_back_with_fill_values_outside_a_floes_life() {
    let dir = tempdir();
    let row = |t: f64, floe: usize, k: f64| floebench::run::TrajectoryRow {
        t,
        floe,
        x: k,
        y: -k,
        theta: 0.1 * k,
        vx: 1e-3 * k,
        vy: -2e-3 * k,
        omega: 1e-5 * k,
    };
    // Floe 0 ends after t = 1 (fracture into 1 and 2, born at t = 2).
    let rows = vec![
        row(0.0, 0, 1.0),
        row(1.0, 0, 2.0),
        row(2.0, 1, 3.0),
        row(2.0, 2, 4.0),
        row(3.0, 1, 5.0),
        row(3.0, 2, 6.0),
    ];
    let path = dir.path().join("trajectory.nc");
    write_trajectory(&path, &rows, "test", Some("2024-03-01 00:00:00")).unwrap();
    let back = read_trajectory(&path).unwrap();
    assert_eq!(back.time, vec![0.0, 1.0, 2.0, 3.0]);
    assert_eq!(back.floe, vec![0, 1, 2]);
    assert_eq!(back.time_units, "seconds since 2024-03-01 00:00:00");
    let names: Vec<&str> = back.variables.iter().map(|v| v.0.as_str()).collect();
    assert_eq!(names, ["x", "y", "theta", "vx", "vy", "omega"]);
    let x = &back.variables[0].2;
    assert_eq!(
        x,
        &vec![
            Some(1.0),
            None,
            None,
            Some(2.0),
            None,
            None,
            None,
            Some(3.0),
            Some(4.0),
            None,
            Some(5.0),
            Some(6.0),
        ]
    );
    assert_eq!(back.variables[5].1, "rad s-1");
    assert_eq!(back.variables[5].2[11], Some(1e-5 * 6.0));
    // A run written by the CLI's writer reads back to its trajectory.csv rows.
    let scn = load("gridded_drift");
    let r = run(&scn, "free-drift");
    let out = floebench::run::output::write_netcdf(dir.path(), &r, &scn).unwrap();
    let back = read_trajectory(&out).unwrap();
    assert_eq!(back.time_units, "seconds since 2024-03-01 00:00:00");
    let nf = back.floe.len();
    for row in &r.trajectory {
        let k = back.time.iter().position(|&t| t == row.t).unwrap();
        let j = back.floe.iter().position(|&f| f == row.floe).unwrap();
        let got: Vec<f64> = back
            .variables
            .iter()
            .map(|v| v.2[k * nf + j].unwrap())
            .collect();
        assert_eq!(
            got,
            vec![row.x, row.y, row.theta, row.vx, row.vy, row.omega]
        );
    }
}

/// The error of loading a case over `grid` (which must be refused).
fn refused(grid: &GridFile, env: &str, duration: f64) -> String {
    let dir = tempdir();
    let text = case(env, duration, &regular(0.0, 0.0, 50.0, 6));
    match load_with_grid(dir.path(), grid, &text) {
        Ok(_) => panic!("loaded, but must be refused"),
        Err(e) => e,
    }
}

#[test]
fn bad_forcing_files_are_refused_naming_the_file_and_the_variable() {
    let xs = [-5.0, 0.0, 5.0];
    let calm = |_: f64, _: f64, _: f64| (0.1, 0.0);
    let good = grid_file(&xs, &xs, &[0.0, 3600.0], "m s-1", calm);
    // A missing variable.
    let e = refused(
        &good,
        "water = { density = 1024.0, drag = 5.0e-3, field = \"netcdf\", file = \"g.nc\", variables = [\"uo\", \"vo\"] }",
        3600.0,
    );
    assert!(
        e.contains("g.nc") && e.contains("no variable `uo`") && e.contains(":9:"),
        "{e}"
    );
    // Wrong units.
    let knots = grid_file(&xs, &xs, &[0.0, 3600.0], "knots", calm);
    let e = refused(&knots, GRIDDED_WATER, 3600.0);
    assert!(
        e.contains("variable `u` has units `knots`; expected m s-1"),
        "{e}"
    );
    // Wrong coordinate units.
    let mut kelvin = good.clone();
    kelvin.x.1 = "K".into();
    let e = refused(&kelvin, GRIDDED_WATER, 3600.0);
    assert!(e.contains("coordinate `x` has units `K`"), "{e}");
    // A time axis that does not cover the run.
    let e = refused(&good, GRIDDED_WATER, 7200.0);
    assert!(
        e.contains("time axis covers [0, 3600] s of the run, not [0, 7200] s"),
        "{e}"
    );
    // Lon/lat without an origin.
    let mut lonlat = good.clone();
    lonlat.x.1 = "degrees_east".into();
    lonlat.y.1 = "degrees_north".into();
    let e = refused(&lonlat, GRIDDED_WATER, 3600.0);
    assert!(e.contains("give `origin = [longitude, latitude]`"), "{e}");
    // A NetCDF-4 (HDF5) file.
    let dir = tempdir();
    std::fs::write(dir.path().join("g.nc"), b"\x89HDF\r\n\x1a\n rest").unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(
        &path,
        case(GRIDDED_WATER, 3600.0, &regular(0.0, 0.0, 50.0, 6)),
    )
    .unwrap();
    let e = load_case(&path).unwrap_err().to_string();
    assert!(e.contains("is NetCDF-4 (HDF5)"), "{e}");
}

#[test]
fn a_floe_leaving_the_grid_ends_the_run_with_the_file_the_variables_and_the_point() {
    let dir = tempdir();
    let xs = [-1.0, 0.0, 1.0];
    let grid = grid_file(&xs, &xs, &[0.0, 20000.0], "m s-1", |_, _, _| (0.5, 0.0));
    let text = case(
        GRIDDED_WATER,
        20000.0,
        &format!("[[floe]]\n{}", regular(0.0, 0.0, 50.0, 6)),
    );
    let scn = load_with_grid(dir.path(), &grid, &text).unwrap_or_else(|e| panic!("{e}"));
    let r = run(&scn, "free-drift");
    let EndReason::Failed { message } = &r.summary.end else {
        panic!("the run must fail: {:?}", r.summary.end);
    };
    assert!(
        message.contains("g.nc (variables u, v)")
            && message.contains("is outside the grid")
            && message.contains("x in [-1000, 1000] m"),
        "{message}"
    );
    // The trajectory stops at the last output inside (the floe was not out).
    let last = r.trajectory.last().unwrap();
    assert!(
        last.x + 50.0 <= 1000.0 + 1e-9 && last.t < scn.duration,
        "{} at {}",
        last.x,
        last.t
    );
    // With outside = "clamp" the same run completes, held at the edge value.
    let clamped = text.replace(
        "variables = [\"u\", \"v\"] }",
        "variables = [\"u\", \"v\"], outside = \"clamp\" }",
    );
    let scn = load_with_grid(dir.path(), &grid, &clamped).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(run(&scn, "free-drift").summary.end, EndReason::Completed);
}

/// `tests/data/netcdf4/<name>`: the NetCDF-4 fixtures written by
/// `tests/data/netcdf4/make_fixtures.py` from `cases/gridded_drift.nc`.
fn netcdf4_fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/netcdf4")
        .join(name)
}

/// The gridded case's request for `variables` (its air or its water).
fn gridded_request(variables: [&str; 2]) -> GridRequest {
    GridRequest {
        variables: variables.map(String::from),
        origin: Some([0.0, 79.0]),
        start: Some("2024-03-01 00:00:00".into()),
    }
}

/// The gridded case's air and water fields (`u10`/`v10`, `uo`/`vo`) read
/// from `cases/gridded_drift.nc` and from the fixture `name`.
fn classic_and_fixture(name: &str) -> Vec<([&str; 2], GridData, GridData)> {
    let classic = case_path("gridded_drift").with_file_name("gridded_drift.nc");
    [["u10", "v10"], ["uo", "vo"]]
        .into_iter()
        .map(|vars| {
            let req = gridded_request(vars);
            let read = |p: &Path| read_grid(p, &req).unwrap_or_else(|e| panic!("{e}"));
            (vars, read(&classic), read(&netcdf4_fixture(name)))
        })
        .collect()
}

#[test]
fn a_netcdf4_file_gives_the_classic_files_field_bit_for_bit() {
    // The NetCDF-4 twin of cases/gridded_drift.nc: chunked, deflate +
    // shuffle, int32 hours since 1900, latitudes decreasing, a depth level
    // on uo/vo, values stored as doubles. The field read must be the
    // classic file's exactly (nodes, times, values, epoch): the field at
    // every point is a function of these alone.
    for (vars, a, b) in classic_and_fixture("gridded_drift_nc4.nc") {
        assert_eq!((a.x.len(), a.y.len(), a.t.len()), (13, 9, 5));
        assert_eq!(a, b, "{vars:?}");
    }
}

#[test]
fn a_netcdf4_file_gives_the_classic_files_trajectory_bit_for_bit() {
    let text = std::fs::read_to_string(case_path("gridded_drift")).unwrap();
    let classic = load("gridded_drift");
    // The same case beside the NetCDF-4 twin.
    let twin = text.replace(
        "file = \"gridded_drift.nc\"",
        "file = \"gridded_drift_nc4.nc\"",
    );
    assert_ne!(twin, text);
    let twin = floebench::formulation::parse_case(&twin, &netcdf4_fixture("twin.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    let (a, b) = (run(&classic, "free-drift"), run(&twin, "free-drift"));
    assert_eq!(a.summary.end, EndReason::Completed, "{:?}", a.summary.end);
    assert!(a.trajectory.len() > 3 * 70, "{}", a.trajectory.len());
    assert_eq!(a.trajectory, b.trajectory);
}

#[test]
fn a_packed_netcdf4_file_is_unpacked_to_within_half_its_scale_factor() {
    // ERA5's packing: int16 with scale_factor and add_offset, fill -32767.
    // The script packs each variable over its range, so the scale factor
    // is (max − min)/65532 and the unpacked values are within half of it.
    for (vars, a, b) in classic_and_fixture("gridded_drift_nc4_packed.nc") {
        assert_eq!((&a.x, &a.y, &a.t, a.epoch), (&b.x, &b.y, &b.t, b.epoch));
        for (name, exact, unpacked) in [(vars[0], &a.u, &b.u), (vars[1], &a.v, &b.v)] {
            let max = exact.iter().copied().fold(f64::MIN, f64::max);
            let min = exact.iter().copied().fold(f64::MAX, f64::min);
            let half = 0.5 * (max - min) / 65532.0;
            let worst = exact
                .iter()
                .zip(unpacked)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            // (rounding to int16 leaves up to half a step; 1e-9 of it for
            // the f64 arithmetic of packing and unpacking)
            assert!(worst <= half * (1.0 + 1e-9), "{name}: {worst:e} > {half:e}");
            if half > 0.0 {
                assert!(worst > 0.0, "{name}: not packed?");
            }
        }
    }
}

#[test]
fn a_netcdf4_file_without_a_variable_is_refused_naming_the_file_and_the_variable() {
    let text = std::fs::read_to_string(case_path("gridded_drift"))
        .unwrap()
        .replace(
            "file = \"gridded_drift.nc\"",
            "file = \"missing_variable_nc4.nc\"",
        );
    let e = floebench::formulation::parse_case(&text, &netcdf4_fixture("bad.toml"))
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("missing_variable_nc4.nc") && e.contains("no variable `v10`"),
        "{e}"
    );
    // A truncated NetCDF-4 file: refused as NetCDF-4 that cannot be read.
    let dir = tempdir();
    let bytes = std::fs::read(netcdf4_fixture("gridded_drift_nc4.nc")).unwrap();
    std::fs::write(dir.path().join("g.nc"), &bytes[..bytes.len() / 3]).unwrap();
    let path = dir.path().join("c.toml");
    std::fs::write(
        &path,
        case(
            "water = { density = 1024.0, drag = 5.0e-3, field = \"netcdf\", file = \"g.nc\", origin = [0.0, 79.0] }",
            3600.0,
            &regular(0.0, 0.0, 50.0, 6),
        ),
    )
    .unwrap();
    let e = load_case(&path).unwrap_err().to_string();
    assert!(
        e.contains("g.nc")
            && (e.contains("is NetCDF-4 (HDF5) but cannot be read")
                || e.contains("cannot read variable `uo`")),
        "{e}"
    );
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
