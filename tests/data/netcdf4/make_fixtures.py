"""Writes the NetCDF-4 (HDF5) test fixtures of tests/suite/forcing/netcdf.rs from
cases/gridded_drift.nc (the classic file of examples/gridded_forcing.rs).

Run from the repository root, with the Python packages netCDF4 and numpy
(e.g. `python3 -m venv /tmp/venv_nc && /tmp/venv_nc/bin/pip install netCDF4 numpy`):

    /tmp/venv_nc/bin/python tests/data/netcdf4/make_fixtures.py

It writes, next to itself:

- `gridded_drift_nc4.nc`: the same wind and current as the classic file, laid
  out as ERA5 and Copernicus Marine distribute them: NetCDF-4, every variable
  chunked and compressed (zlib level 4 with the shuffle filter), `time` as
  int32 "hours since 1900-01-01 00:00:00.0", latitudes decreasing (north
  first), `u10`/`v10` on (time, latitude, longitude) and `uo`/`vo` on
  (time, depth, latitude, longitude) with one depth level. The velocities are
  stored as doubles, so the reader must return the classic file's values
  bit for bit.
- `gridded_drift_nc4_packed.nc`: the same, with the velocities packed as ERA5
  packs them: int16 with `scale_factor`, `add_offset` and
  `_FillValue = -32767`, so the unpacked values differ from the classic
  file's by at most half a `scale_factor`.
- `missing_variable_nc4.nc`: a NetCDF-4 file with `u10` only (no `v10`, `uo`, `vo`).
"""

import datetime
import os

import netCDF4
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CLASSIC = os.path.join(HERE, "..", "..", "..", "cases", "gridded_drift.nc")
ERA5_EPOCH = datetime.datetime(1900, 1, 1)


def read_classic():
    with netCDF4.Dataset(CLASSIC) as src:
        src.set_auto_maskandscale(False)
        out = {k: np.array(src[k][:]) for k in ("longitude", "latitude", "time")}
        for k in ("u10", "v10", "uo", "vo"):
            out[k] = np.array(src[k][:])
            out[k + ":long_name"] = src[k].long_name
        out["time:units"] = src["time"].units
    return out


def hours_since_1900(c):
    """The classic time axis (hours since a date) as ERA5's hours since 1900."""
    ref = c["time:units"].split(" since ")[1]
    ref = datetime.datetime.strptime(ref, "%Y-%m-%d %H:%M:%S")
    offset = (ref - ERA5_EPOCH).total_seconds() / 3600.0
    assert offset == int(offset)
    return (c["time"] + offset).astype(np.int32)


def pack(values):
    """ERA5's packing: int16 over the range, -32767 kept for the fill."""
    lo, hi = float(values.min()), float(values.max())
    scale = (hi - lo) / (2 * 32766) if hi > lo else 1.0
    offset = (hi + lo) / 2
    return np.round((values - offset) / scale).astype(np.int16), scale, offset


def write(path, c, packed=False, drop=()):
    with netCDF4.Dataset(path, "w", format="NETCDF4") as ds:
        ds.Conventions = "CF-1.6"
        ds.history = "tests/data/netcdf4/make_fixtures.py from cases/gridded_drift.nc"
        ds.createDimension("longitude", len(c["longitude"]))
        ds.createDimension("latitude", len(c["latitude"]))
        ds.createDimension("depth", 1)
        ds.createDimension("time", None)  # unlimited, as in ERA5 downloads
        z = dict(zlib=True, complevel=4, shuffle=True)
        # Doubles (ERA5 writes floats) so that the nodes are the classic file's.
        lon = ds.createVariable("longitude", "f8", ("longitude",), **z)
        lon.units = "degrees_east"
        lon.long_name = "longitude"
        lon[:] = c["longitude"]
        lat = ds.createVariable("latitude", "f8", ("latitude",), **z)
        lat.units = "degrees_north"
        lat.long_name = "latitude"
        lat[:] = c["latitude"][::-1]
        depth = ds.createVariable("depth", "f4", ("depth",))
        depth.units = "m"
        depth.positive = "down"
        depth[:] = [0.494]
        time = ds.createVariable("time", "i4", ("time",), **z)
        time.units = "hours since 1900-01-01 00:00:00.0"
        time.long_name = "time"
        time.calendar = "gregorian"
        time[:] = hours_since_1900(c)
        for name in ("u10", "v10", "uo", "vo"):
            if name in drop:
                continue
            dims = ("time", "latitude", "longitude")
            values = c[name][:, ::-1, :]
            if name in ("uo", "vo"):
                dims = ("time", "depth", "latitude", "longitude")
                values = values[:, np.newaxis, :, :]
            chunks = [1] * (len(dims) - 2) + [5, 7]
            if packed:
                data, scale, offset = pack(values)
                v = ds.createVariable(
                    name, "i2", dims, chunksizes=chunks, fill_value=np.int16(-32767), **z
                )
                v.scale_factor = scale
                v.add_offset = offset
                v.set_auto_maskandscale(False)
                v[:] = data
            else:
                v = ds.createVariable(name, "f8", dims, chunksizes=chunks, **z)
                v[:] = values
            v.units = "m s**-1" if name in ("u10", "v10") else "m s-1"
            v.long_name = c[name + ":long_name"]


def main():
    c = read_classic()
    write(os.path.join(HERE, "gridded_drift_nc4.nc"), c)
    write(os.path.join(HERE, "gridded_drift_nc4_packed.nc"), c, packed=True)
    write(os.path.join(HERE, "missing_variable_nc4.nc"), c, drop=("v10", "uo", "vo"))
    for f in sorted(os.listdir(HERE)):
        if f.endswith(".nc"):
            print(f, os.path.getsize(os.path.join(HERE, f)), "bytes")


if __name__ == "__main__":
    main()
