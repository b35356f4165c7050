//! Gridded fields against the analytic fields they sample: a linear field
//! interpolated exactly, a uniform grid giving the uniform case's
//! trajectory, and the bundled gridded case equal to its analytic fields.

use super::{case, grid_file, load_with_grid, regular, GRIDDED_WATER};
use crate::common::{case_path, run, scenario, tempdir};
use floebench::geometry::Vec2;
use floebench::run::{EndReason, RunResult};

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
