//! Writes `cases/gridded_drift.nc`, the forcing of `cases/gridded_drift.toml`:
//! ERA5-like 10 m wind (`u10`, `v10`) and Copernicus-Marine-like surface
//! current (`uo`, `vo`) on a longitude/latitude grid about 0° E, 79° N
//! (Fram Strait), every 3 hours from 2024-03-01 00:00 UTC, in CF NetCDF
//! classic.
//!
//! The values are the analytic fields of [`wind`] and [`current`] at the
//! nodes' projected positions (`floebench::model::netcdf::project_lon`,
//! `project_lat`, the projection the reader applies with `origin = [0, 79]`):
//! both are linear in space, so bilinear interpolation reproduces them
//! exactly and the gridded case must give the trajectory of the same case
//! written with `field = "linear"` (tests/suite/forcing/grid.rs).
//!
//! Run with `cargo run --release --example gridded_forcing [OUT.nc]`.

use floebench::model::netcdf::{project_lat, project_lon, write_grid, GridFile};

/// The reference point of the projection, degrees.
const ORIGIN: [f64; 2] = [0.0, 79.0];

/// The wind's time factor at hour `h` (it rises, then turns weaker).
fn wind_factor(h: f64) -> f64 {
    [0.6, 1.0, 1.2, 0.9, 0.5][(h / 3.0).round() as usize]
}

/// The wind at `(x, y)` m and hour `h`, m/s: 8 m/s from the west and 2 m/s
/// from the south at the origin, converging along x (−5e-5 1/s) and
/// veering with y, times [`wind_factor`].
fn wind(x: f64, y: f64, h: f64) -> (f64, f64) {
    let s = wind_factor(h);
    (s * (8.0 - 5e-5 * x + 2e-5 * y), s * (2.0 + 1e-5 * x))
}

/// The current at `(x, y)` m, m/s: 0.1 m/s eastward with a shear 2e-6 1/s
/// along y, steady.
fn current(_x: f64, y: f64) -> (f64, f64) {
    (0.1 + 2e-6 * y, 0.0)
}

fn main() {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "cases/gridded_drift.nc".to_string());
    let lon: Vec<f64> = (0..13).map(|i| -0.6 + 0.1 * i as f64).collect();
    let lat: Vec<f64> = (0..9).map(|j| 78.8 + 0.05 * j as f64).collect();
    let hours: Vec<f64> = (0..5).map(|k| 3.0 * k as f64).collect();
    let mut fields: [Vec<f64>; 4] = Default::default();
    for &h in &hours {
        for &la in &lat {
            for &lo in &lon {
                let (x, y) = (project_lon(lo, ORIGIN), project_lat(la, ORIGIN));
                let (ua, va) = wind(x, y, h);
                let (uw, vw) = current(x, y);
                for (f, v) in fields.iter_mut().zip([ua, va, uw, vw]) {
                    f.push(v);
                }
            }
        }
    }
    let [u10, v10, uo, vo] = fields;
    let var = |n: &str, long: &str, v: Vec<f64>| {
        (n.to_string(), "m s-1".to_string(), long.to_string(), v)
    };
    let file = GridFile {
        title: "floebench gridded_drift forcing: analytic wind and current (examples/gridded_forcing.rs)"
            .to_string(),
        x: ("longitude".into(), "degrees_east".into(), lon),
        y: ("latitude".into(), "degrees_north".into(), lat),
        time: Some((
            "time".into(),
            "hours since 2024-03-01 00:00:00".into(),
            hours,
        )),
        variables: vec![
            var("u10", "10 metre U wind component", u10),
            var("v10", "10 metre V wind component", v10),
            var("uo", "Eastward sea water velocity", uo),
            var("vo", "Northward sea water velocity", vo),
        ],
    };
    if let Err(e) = write_grid(std::path::Path::new(&out), &file) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
    println!("wrote {out}");
}
