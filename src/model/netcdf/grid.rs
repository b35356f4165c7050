//! Gridded velocities from a CF NetCDF file, classic or NetCDF-4
//! ([`read_grid`], through `reader.rs`), and
//! the writer of such files ([`write_grid`]) that makes the bundled gridded
//! case's forcing and the tests' files.
//!
//! A velocity variable has the dimensions `(time, …, y, x)` in CF's order
//! (the last two the horizontal axes, every other dimension but time of
//! size 1, e.g. a single depth level). The horizontal coordinates are
//! projected (`units` m or km) or longitude/latitude (`degrees_east`,
//! `degrees_north`), mapped to the case's metres by the local
//! equirectangular projection about `origin = [λ₀, φ₀]`:
//! `x = R cos φ₀ (λ − λ₀) π/180`, `y = R (φ − φ₀) π/180`,
//! `R` = [`EARTH_RADIUS`]; eastward and northward components are the
//! projection's x and y components. An axis written decreasing (ERA5's
//! latitudes) is reversed. The time axis is CF's `"<unit> since <date>"`
//! (Gregorian calendars); the run's t = 0 is the case's `start` date, or
//! the first record.

use super::cf::{self, Axis};
use super::reader::NcInput;
use crate::model::forcing::GridData;
use crate::model::limits;
use netcdf3::{DataSet, FileWriter, Version};
use std::path::Path;

/// The mean Earth radius of the local projection of lon/lat grids, m
/// (IUGG mean radius `R₁`).
pub const EARTH_RADIUS: f64 = 6_371_008.8;

/// The local equirectangular projection about `origin = [λ₀, φ₀]`
/// (degrees) of longitude `lon` or latitude `lat` (degrees), m:
/// `x = R cos φ₀ (λ − λ₀) π/180` ([`project_lon`]), `y = R (φ − φ₀) π/180`.
pub fn project_lon(lon: f64, origin: [f64; 2]) -> f64 {
    EARTH_RADIUS * origin[1].to_radians().cos() * (lon - origin[0]) * (std::f64::consts::PI / 180.0)
}

/// The latitude half of the projection of [`project_lon`], m.
pub fn project_lat(lat: f64, origin: [f64; 2]) -> f64 {
    EARTH_RADIUS * (lat - origin[1]) * (std::f64::consts::PI / 180.0)
}

/// What the case asks of a gridded file.
#[derive(Debug, Clone, PartialEq)]
pub struct GridRequest {
    /// The two velocity components' variable names.
    pub variables: [String; 2],
    /// `[λ₀, φ₀]`, degrees: the reference point of a lon/lat grid.
    pub origin: Option<[f64; 2]>,
    /// The date of the run's t = 0 (default: the first record).
    pub start: Option<String>,
}

/// A coordinate variable's values (unpacked), every one present.
fn coordinate(nc: &NcInput, name: &str) -> Result<Vec<f64>, String> {
    let file = nc.file();
    if !nc.has_var(name) {
        return Err(format!(
            "{file}: no coordinate variable `{name}` for the dimension `{name}`"
        ));
    }
    nc.values(name)?
        .into_iter()
        .enumerate()
        .map(|(k, v)| {
            v.ok_or_else(|| format!("{file}: coordinate `{name}` has a missing value at index {k}"))
        })
        .collect()
}

/// Whether `a` is strictly increasing (`Some(true)`), strictly decreasing
/// (`Some(false)`) or neither.
fn monotonic(a: &[f64]) -> Option<bool> {
    if a.windows(2).all(|w| w[0] < w[1]) {
        Some(true)
    } else if a.windows(2).all(|w| w[0] > w[1]) {
        Some(false)
    } else {
        None
    }
}

/// Reads the two velocity components of `req` from the CF NetCDF file
/// `path` (classic or NetCDF-4). Every error names the file, and the
/// variable or the node.
pub fn read_grid(path: &Path, req: &GridRequest) -> Result<GridData, String> {
    let nc = NcInput::open(path)?;
    let file = nc.file().to_string();
    let [un, vn] = &req.variables;
    for name in [un, vn] {
        if !nc.has_var(name) {
            return Err(format!(
                "{file}: no variable `{name}` (the file has: {}; name yours with `variables = [\"u\", \"v\"]`)",
                nc.var_names().join(", ")
            ));
        }
        let units = nc.attr_string(name, "units").unwrap_or_default();
        if !cf::is_metres_per_second(&units) {
            return Err(format!(
                "{file}: variable `{name}` has units `{units}`; expected m s-1"
            ));
        }
    }
    let sized = nc.dims(un);
    let dim_size = |d: &str| sized.iter().find(|(n, _)| n == d).map(|(_, s)| *s);
    let dims: Vec<String> = sized.iter().map(|(n, _)| n.clone()).collect();
    let vdims: Vec<String> = nc.dims(vn).into_iter().map(|(n, _)| n).collect();
    if dims != vdims {
        return Err(format!(
            "{file}: `{un}` has dimensions ({}) but `{vn}` has ({})",
            dims.join(", "),
            vdims.join(", ")
        ));
    }
    if dims.len() < 2 {
        return Err(format!(
            "{file}: variable `{un}` has dimensions ({}); expected (time, …, y, x)",
            dims.join(", ")
        ));
    }
    let xd = &dims[dims.len() - 1];
    let yd = &dims[dims.len() - 2];
    // The time dimension: the one whose coordinate has CF time units.
    let is_time = |d: &String| {
        nc.attr_string(d, "units")
            .is_some_and(|u| u.contains(" since "))
    };
    let td = dims[..dims.len() - 2].iter().find(|d| is_time(d)).cloned();
    for d in &dims[..dims.len() - 2] {
        if Some(d) != td.as_ref() && dim_size(d) != Some(1) {
            return Err(format!(
                "{file}: variable `{un}` has a dimension `{d}` of size {} that is neither time nor a single level",
                dim_size(d).unwrap_or(0)
            ));
        }
    }
    if let Some(t) = &td {
        if dims.iter().position(|d| d == t) > dims.iter().position(|d| d == yd) {
            return Err(format!(
                "{file}: variable `{un}`: time must come before the horizontal dimensions"
            ));
        }
    }
    let (nx, ny) = (dim_size(xd).unwrap_or(0), dim_size(yd).unwrap_or(0));
    let nt = td.as_ref().and_then(|t| dim_size(t)).unwrap_or(1);
    if nx < 2 || ny < 2 || nt < 1 {
        return Err(format!(
            "{file}: variable `{un}` needs at least 2 nodes along `{xd}` and `{yd}` and one record (it has {nx} × {ny}, {nt} records)"
        ));
    }
    let count = (nx as i128) * (ny as i128) * (nt as i128);
    limits::GRID_VALUES
        .check_integer(&format!("{file}: variable `{un}`: values"), count)
        .map_err(|m| m.to_string())?;

    // Horizontal coordinates, to metres.
    let mut x = coordinate(&nc, xd)?;
    let mut y = coordinate(&nc, yd)?;
    let axis = |d: &str| {
        let units = nc.attr_string(d, "units").unwrap_or_default();
        cf::coordinate_axis(&units).ok_or_else(|| {
            format!(
                "{file}: coordinate `{d}` has units `{units}`; expected m or km (projected) or degrees_east / degrees_north"
            )
        })
    };
    match (axis(xd)?, axis(yd)?) {
        (Axis::Metres(sx), Axis::Metres(sy)) => {
            x.iter_mut().for_each(|v| *v *= sx);
            y.iter_mut().for_each(|v| *v *= sy);
        }
        (Axis::Longitude, Axis::Latitude) => {
            let Some([lon0, lat0]) = req.origin else {
                return Err(format!(
                    "{file}: the grid is on longitude/latitude: give `origin = [longitude, latitude]` (degrees), the point of the local projection"
                ));
            };
            x.iter_mut().for_each(|v| *v = project_lon(*v, [lon0, lat0]));
            y.iter_mut().for_each(|v| *v = project_lat(*v, [lon0, lat0]));
        }
        (a, b) => {
            return Err(format!(
                "{file}: coordinates `{xd}` ({a:?}) and `{yd}` ({b:?}) are not both projected nor longitude then latitude"
            ))
        }
    }
    for (name, c) in [(xd, &x), (yd, &y)] {
        for (k, v) in c.iter().enumerate() {
            limits::COORDINATE
                .check(&format!("{file}: coordinate `{name}` [{k}] in m"), *v)
                .map_err(|m| m.to_string())?;
        }
    }
    let (Some(x_up), Some(y_up)) = (monotonic(&x), monotonic(&y)) else {
        return Err(format!(
            "{file}: the coordinates `{xd}` and `{yd}` must be strictly monotonic"
        ));
    };

    // Time.
    let mut epoch = match &req.start {
        Some(s) => Some(cf::parse_date(s).map_err(|e| format!("start: {e}"))?),
        None => None,
    };
    let t = match &td {
        None => vec![0.0],
        Some(tn) => {
            let raw = coordinate(&nc, tn)?;
            let units = nc.attr_string(tn, "units").unwrap_or_default();
            let (scale, reference) =
                cf::parse_time_units(&units).map_err(|e| format!("{file}: `{tn}`: {e}"))?;
            if let Some(cal) = nc.attr_string(tn, "calendar") {
                if !cf::gregorian(&cal) {
                    return Err(format!(
                        "{file}: `{tn}` has calendar `{cal}`; this reader knows standard, gregorian and proleptic_gregorian"
                    ));
                }
            }
            let abs: Vec<f64> = raw.iter().map(|v| reference + v * scale).collect();
            if monotonic(&abs) != Some(true) && abs.len() > 1 {
                return Err(format!(
                    "{file}: the times of `{tn}` must increase strictly"
                ));
            }
            let start = *epoch.get_or_insert(abs[0]);
            abs.iter().map(|a| a - start).collect()
        }
    };

    // The two components, in (t, y, x) order with increasing axes.
    let mut comps = Vec::new();
    for name in [un, vn] {
        let vals = nc.values(name)?;
        if vals.len() != nt * ny * nx {
            return Err(format!(
                "{file}: variable `{name}` holds {} values, not {nt} × {ny} × {nx}",
                vals.len()
            ));
        }
        let mut out = Vec::with_capacity(vals.len());
        for k in 0..nt {
            for j in 0..ny {
                let jj = if y_up { j } else { ny - 1 - j };
                for i in 0..nx {
                    let ii = if x_up { i } else { nx - 1 - i };
                    let v = vals[(k * ny + jj) * nx + ii].ok_or_else(|| {
                        format!(
                            "{file}: variable `{name}` has a missing value at node ({}, {}) m, t = {} s (record {k}): fill land or gaps before use",
                            x[ii], y[jj], t[k]
                        )
                    })?;
                    out.push(v);
                }
            }
        }
        comps.push(out);
    }
    if !x_up {
        x.reverse();
    }
    if !y_up {
        y.reverse();
    }
    let v = comps.pop().unwrap_or_default();
    let u = comps.pop().unwrap_or_default();
    Ok(GridData {
        x,
        y,
        t,
        u,
        v,
        epoch,
    })
}

/// A gridded file to write: coordinates, a time axis and velocity
/// variables laid out `[t][y][x]`, with their CF attributes as given (the
/// tests write wrong ones on purpose).
#[derive(Debug, Clone, PartialEq)]
pub struct GridFile {
    /// Global `title`.
    pub title: String,
    /// The x dimension and coordinate: name, units, values.
    pub x: (String, String, Vec<f64>),
    /// The y dimension and coordinate: name, units, values.
    pub y: (String, String, Vec<f64>),
    /// The time dimension and coordinate: name, CF units, values (`None`:
    /// a steady field without a time dimension).
    pub time: Option<(String, String, Vec<f64>)>,
    /// Velocity variables: name, units, long name, values `[t][y][x]`.
    pub variables: Vec<(String, String, String, Vec<f64>)>,
}

/// Writes `g` as a CF-1.8 NetCDF classic file at `path`, atomically.
pub fn write_grid(path: &Path, g: &GridFile) -> Result<(), String> {
    let file = path.display().to_string();
    let err = |e: &dyn std::fmt::Debug| format!("{file}: cannot write: {e:?}");
    let mut ds = DataSet::new();
    let mut dims: Vec<&str> = Vec::new();
    if let Some((tn, _, tv)) = &g.time {
        ds.add_fixed_dim(tn, tv.len()).map_err(|e| err(&e))?;
        dims.push(tn);
    }
    for (n, _, v) in [&g.y, &g.x] {
        ds.add_fixed_dim(n, v.len()).map_err(|e| err(&e))?;
        dims.push(n);
    }
    ds.add_global_attr_string("Conventions", "CF-1.8")
        .map_err(|e| err(&e))?;
    ds.add_global_attr_string("title", &g.title)
        .map_err(|e| err(&e))?;
    let mut coords = vec![&g.x, &g.y];
    if let Some(t) = &g.time {
        coords.push(t);
    }
    for (n, units, _) in &coords {
        ds.add_var_f64(n, &[n]).map_err(|e| err(&e))?;
        ds.add_var_attr_string(n, "units", units)
            .map_err(|e| err(&e))?;
    }
    if let Some((tn, _, _)) = &g.time {
        ds.add_var_attr_string(tn, "standard_name", "time")
            .map_err(|e| err(&e))?;
        ds.add_var_attr_string(tn, "calendar", "standard")
            .map_err(|e| err(&e))?;
    }
    for (n, units, long, _) in &g.variables {
        ds.add_var_f64(n, &dims).map_err(|e| err(&e))?;
        ds.add_var_attr_string(n, "units", units)
            .map_err(|e| err(&e))?;
        ds.add_var_attr_string(n, "long_name", long)
            .map_err(|e| err(&e))?;
    }
    crate::fsio::write_atomic_with(path, |tmp| {
        let mut w = FileWriter::open(tmp).map_err(|e| std::io::Error::other(format!("{e:?}")))?;
        let io = |e: netcdf3::WriteError| std::io::Error::other(format!("{e:?}"));
        w.set_def(&ds, Version::Offset64Bit, 0).map_err(io)?;
        for (n, _, v) in &coords {
            w.write_var_f64(n, v).map_err(io)?;
        }
        for (n, _, _, v) in &g.variables {
            w.write_var_f64(n, v).map_err(io)?;
        }
        w.close().map_err(io)
    })
    .map_err(|e| format!("{file}: cannot write: {e}"))
}
