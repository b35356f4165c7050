//! Winds and currents that vary in space (docs/physics.md §2.4) and CF
//! NetCDF in and out: the grid against the analytic fields it samples, the
//! shear-current and vortex closed forms, the trajectory file read back,
//! and bad forcing files refused with errors naming the file, the variable
//! and the point.
//!
//! This file holds what the submodules share: the case and grid builders.
//! The tests are in the submodules, one topic each.

mod grid;
mod netcdf;
mod refusals;
mod shear;
mod vortex;

use floebench::formulation::load_case;
use floebench::model::netcdf::{write_grid, GridFile};
use floebench::model::Scenario;
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
