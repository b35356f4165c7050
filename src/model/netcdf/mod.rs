//! CF NetCDF in: gridded winds and currents read for `field = "netcdf"`
//! ([`read_grid`]), with the writer of such grids ([`write_grid`]) that makes
//! the bundled gridded case's forcing and the tests' files, and the CF
//! calendar ([`cf`]). The run's own NetCDF output (`trajectory.nc`) is
//! written with the other output files, by [`crate::run::netcdf_out`].
//!
//! Files are read by one low-level reader (`reader.rs`, the pure-Rust
//! `netcdf-reader` crate): NetCDF classic (CDF-1), 64-bit offset (CDF-2),
//! 64-bit data (CDF-5) and NetCDF-4/HDF5, chunked and compressed (deflate,
//! shuffle), so that the project builds with cargo alone
//! (docs/case-format.md, "Forcing fields", lists what is not read). They are
//! written as 64-bit offset classic files by the pure-Rust `netcdf3` crate
//! (`netcdf-reader` has no writer). The
//! conventions are CF 1.8 (Eaton et al., *NetCDF Climate and Forecast
//! Metadata Conventions*): coordinate variables named as their
//! dimensions, `units` on every variable, a time axis in
//! `"<unit> since <date>"`, `scale_factor`/`add_offset` packing and
//! `_FillValue`/`missing_value`. The calendar arithmetic of [`cf`] is the
//! proleptic Gregorian one (Hinnant's days-from-civil).

pub mod cf;
mod grid;
pub(crate) mod reader;

pub use grid::{
    project_lat, project_lon, read_grid, write_grid, GridFile, GridRequest, EARTH_RADIUS,
};
