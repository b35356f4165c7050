//! A run's trajectory as a CF NetCDF file (`trajectory.nc`, `run --netcdf`
//! and `compare --netcdf`): dimensions `time × floe`, the variables `x`,
//! `y`, `theta`, `vx`, `vy`, `omega` with `units` and `long_name`, the
//! floe ids as the `floe` coordinate, and the fill value `_FillValue` =
//! 9.969e36 (NetCDF's default for doubles, which xarray reads as NaN)
//! before a floe's birth and after its end by fracture. The time axis is
//! `seconds since <start>`: the forcing's start date for a gridded case,
//! otherwise 1970-01-01 as a nominal date (`comment` says so). Written
//! atomically like the other outputs.

use super::TrajectoryRow;
use crate::model::netcdf::reader::NcInput;
use netcdf3::{DataSet, FileWriter, Version, NC_FILL_F64};
use std::path::Path;

/// The file name of the trajectory in a run's output folder.
pub const TRAJECTORY_FILE: &str = "trajectory.nc";

/// The state variables: name, units, long name.
const VARIABLES: [(&str, &str, &str); 6] = [
    ("x", "m", "x of the centre of mass"),
    ("y", "m", "y of the centre of mass"),
    (
        "theta",
        "rad",
        "angle from the floe's orientation at its birth",
    ),
    ("vx", "m s-1", "x velocity of the centre of mass"),
    ("vy", "m s-1", "y velocity of the centre of mass"),
    ("omega", "rad s-1", "angular velocity"),
];

/// A trajectory file read back: times (s from the start), floe ids, and
/// each variable `[time][floe]` (`None` where the floe did not exist).
#[derive(Debug, Clone, PartialEq)]
pub struct NetcdfTrajectory {
    /// Output times, s.
    pub time: Vec<f64>,
    /// The `units` of `time`.
    pub time_units: String,
    /// Floe ids.
    pub floe: Vec<usize>,
    /// `(name, units, values [time * floe])` in the order x, y, theta, vx, vy, omega.
    pub variables: Vec<(String, String, Vec<Option<f64>>)>,
}

/// Writes the rows of a trajectory (as `trajectory.csv` holds them) to
/// `path`; `start` is the date of t = 0 as CF writes it
/// (`YYYY-MM-DD hh:mm:ss`), `None` for a nominal 1970-01-01.
pub fn write_trajectory(
    path: &Path,
    rows: &[TrajectoryRow],
    title: &str,
    start: Option<&str>,
) -> Result<(), String> {
    let file = path.display().to_string();
    let err = |e: &dyn std::fmt::Debug| format!("{file}: cannot write: {e:?}");
    let mut times: Vec<f64> = rows.iter().map(|r| r.t).collect();
    times.dedup();
    let mut floes: Vec<usize> = rows.iter().map(|r| r.floe).collect();
    floes.sort_unstable();
    floes.dedup();
    let (nt, nf) = (times.len(), floes.len());
    let mut data = vec![vec![NC_FILL_F64; nt * nf]; VARIABLES.len()];
    let mut k = 0;
    for r in rows {
        // Rows come in time order: advance to the row's time.
        while k < nt && times[k] != r.t {
            k += 1;
        }
        let Ok(j) = floes.binary_search(&r.floe) else {
            continue;
        };
        if k == nt {
            return Err(format!(
                "{file}: the trajectory's rows are not in time order"
            ));
        }
        for (d, v) in data
            .iter_mut()
            .zip([r.x, r.y, r.theta, r.vx, r.vy, r.omega])
        {
            d[k * nf + j] = v;
        }
    }
    let mut ds = DataSet::new();
    ds.add_fixed_dim("time", nt).map_err(|e| err(&e))?;
    ds.add_fixed_dim("floe", nf).map_err(|e| err(&e))?;
    ds.add_global_attr_string("Conventions", "CF-1.8")
        .map_err(|e| err(&e))?;
    ds.add_global_attr_string("title", title)
        .map_err(|e| err(&e))?;
    ds.add_global_attr_string("source", "floebench")
        .map_err(|e| err(&e))?;
    ds.add_var_f64("time", &["time"]).map_err(|e| err(&e))?;
    let date = start.unwrap_or("1970-01-01 00:00:00");
    for (a, v) in [
        ("units", format!("seconds since {date}")),
        ("standard_name", "time".to_string()),
        ("calendar", "standard".to_string()),
        ("long_name", "time since the start of the run".to_string()),
    ] {
        ds.add_var_attr_string("time", a, v).map_err(|e| err(&e))?;
    }
    if start.is_none() {
        ds.add_var_attr_string(
            "time",
            "comment",
            "t = 0 is the start of the run; the date is nominal",
        )
        .map_err(|e| err(&e))?;
    }
    ds.add_var_i32("floe", &["floe"]).map_err(|e| err(&e))?;
    ds.add_var_attr_string("floe", "long_name", "floe id (floes.json)")
        .map_err(|e| err(&e))?;
    ds.add_var_attr_string("floe", "cf_role", "trajectory_id")
        .map_err(|e| err(&e))?;
    for (n, units, long) in VARIABLES {
        ds.add_var_f64(n, &["time", "floe"]).map_err(|e| err(&e))?;
        ds.add_var_attr_string(n, "units", units)
            .map_err(|e| err(&e))?;
        ds.add_var_attr_string(n, "long_name", long)
            .map_err(|e| err(&e))?;
        ds.add_var_attr_f64(n, "_FillValue", vec![NC_FILL_F64])
            .map_err(|e| err(&e))?;
    }
    let ids: Vec<i32> = floes
        .iter()
        .map(|&f| i32::try_from(f).map_err(|_| format!("{file}: floe id {f} does not fit")))
        .collect::<Result<_, _>>()?;
    crate::fsio::write_atomic_with(path, |tmp| {
        let io = |e: netcdf3::WriteError| std::io::Error::other(format!("{e:?}"));
        let mut w = FileWriter::open(tmp).map_err(io)?;
        w.set_def(&ds, Version::Offset64Bit, 0).map_err(io)?;
        w.write_var_f64("time", &times).map_err(io)?;
        w.write_var_i32("floe", &ids).map_err(io)?;
        for ((n, _, _), d) in VARIABLES.iter().zip(&data) {
            w.write_var_f64(n, d).map_err(io)?;
        }
        w.close().map_err(io)
    })
    .map_err(|e| format!("{file}: cannot write: {e}"))
}

/// Reads a file written by [`write_trajectory`] (or the same variables
/// saved again by another tool, classic or NetCDF-4).
pub fn read_trajectory(path: &Path) -> Result<NetcdfTrajectory, String> {
    let nc = NcInput::open(path)?;
    let file = nc.file();
    let time = nc.raw("time")?;
    let floe = nc
        .raw("floe")?
        .into_iter()
        .map(|f| {
            (f >= 0.0 && f.fract() == 0.0 && f <= u32::MAX as f64)
                .then_some(f as usize)
                .ok_or_else(|| format!("{file}: floe id {f} is not a non-negative integer"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut variables = Vec::new();
    for (n, _, _) in VARIABLES {
        let v = nc.values(n)?;
        let units = nc.attr_string(n, "units").unwrap_or_default();
        variables.push((n.to_string(), units, v));
    }
    Ok(NetcdfTrajectory {
        time,
        time_units: nc.attr_string("time", "units").unwrap_or_default(),
        floe,
        variables,
    })
}
