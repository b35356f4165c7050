//! CF NetCDF in and out: gridded winds and currents read for
//! `field = "netcdf"` ([`read_grid`]), and a run's trajectory written for
//! `run --netcdf` and `compare --netcdf` ([`write_trajectory`]).
//!
//! Files are NetCDF classic (CDF-1) and 64-bit offset (CDF-2), read and
//! written by the pure-Rust `netcdf3` crate, so that the project builds
//! with cargo alone (docs/case-format.md, "Forcing fields", says why
//! NetCDF-4/HDF5 files are not read and how to convert them). The
//! conventions are CF 1.8 (Eaton et al., *NetCDF Climate and Forecast
//! Metadata Conventions*): coordinate variables named as their
//! dimensions, `units` on every variable, a time axis in
//! `"<unit> since <date>"`, `scale_factor`/`add_offset` packing and
//! `_FillValue`/`missing_value`. The calendar arithmetic of [`cf`] is the
//! proleptic Gregorian one (Hinnant's days-from-civil).

pub mod cf;
mod grid;
mod reader;
mod trajectory;

pub use grid::{
    project_lat, project_lon, read_grid, write_grid, GridFile, GridRequest, EARTH_RADIUS,
};
pub use trajectory::{read_trajectory, write_trajectory, NetcdfTrajectory, TRAJECTORY_FILE};
