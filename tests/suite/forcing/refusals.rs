//! Bad forcing files refused naming the file and the variable, and a floe
//! leaving the grid ending the run naming the file, the variables and the
//! point.

use super::{case, grid_file, load_with_grid, regular, GRIDDED_WATER};
use crate::common::{run, tempdir};
use floebench::formulation::load_case;
use floebench::model::netcdf::GridFile;
use floebench::run::EndReason;

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
