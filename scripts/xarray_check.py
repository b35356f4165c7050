"""Opens the trajectory.nc of floebench runs with xarray and checks it
against the same runs' trajectory.csv. An optional tool for users and
maintainers (CI does not run it: it needs Python with xarray).

    python3 -m venv /tmp/venv_nc && /tmp/venv_nc/bin/pip install netCDF4 numpy xarray
    cargo run --release -- run cases/gridded_drift.toml -f rapier --netcdf -o /tmp/nc_x
    /tmp/venv_nc/bin/python scripts/xarray_check.py /tmp/nc_x [MORE_RUN_FOLDERS...]

A run folder is one holding trajectory.nc and trajectory.csv (`run -o DIR`
writes them in DIR; `compare --netcdf -o DIR` in DIR/<case>/<formulation>/;
every folder below the given ones that holds both is checked). For each it
prints the dataset as xarray shows it and checks:

- the dimensions `time` and `floe`, and the variables x, y, theta, vx, vy,
  omega on (time, floe), each with `units` and `long_name`;
- that `time` decodes to datetimes (CF "seconds since <date>"), equal to
  the start date plus the CSV's t;
- that every value equals trajectory.csv's to float precision (the CSV
  prints shortest round-trip decimals, so the test is equality), and that a
  (time, floe) absent from the CSV (before a floe's birth, after its end by
  fracture) reads as NaN through `_FillValue`.

It exits non-zero at the first failed check.
"""

import csv
import os
import sys

import numpy as np
import xarray as xr

VARIABLES = ["x", "y", "theta", "vx", "vy", "omega"]


def fail(msg):
    print("FAILED:", msg)
    sys.exit(1)


def check(folder):
    nc = os.path.join(folder, "trajectory.nc")
    ds = xr.open_dataset(nc)
    print(f"== {nc}")
    print(ds)
    if dict(ds.sizes) != {"time": ds.sizes["time"], "floe": ds.sizes["floe"]}:
        fail(f"dimensions {dict(ds.sizes)}")
    if not np.issubdtype(ds["time"].dtype, np.datetime64):
        fail(f"time decodes to {ds['time'].dtype}, not datetimes")
    for v in VARIABLES:
        if ds[v].dims != ("time", "floe"):
            fail(f"{v} has dimensions {ds[v].dims}")
        for a in ("units", "long_name"):
            if a not in ds[v].attrs:
                fail(f"{v} has no {a}")
    # The raw seconds, from the undecoded file.
    raw = xr.open_dataset(nc, decode_times=False)
    t_s = raw["time"].values
    start = np.datetime64(raw["time"].attrs["units"].split(" since ")[1].replace(" ", "T"))
    decoded = start + (t_s * 1e9).round().astype("timedelta64[ns]")
    if not (decoded == ds["time"].values).all():
        fail("decoded times differ from start + t")
    rows = {}
    with open(os.path.join(folder, "trajectory.csv")) as f:
        for r in csv.DictReader(f):
            rows[(float(r["t"]), int(r["floe"]))] = [float(r[v]) for v in VARIABLES]
    floes = [int(f) for f in ds["floe"].values]
    times = list(t_s)
    if sorted({k[1] for k in rows}) != floes:
        fail("the floe ids differ from the CSV's")
    if sorted({k[0] for k in rows}) != times:
        fail("the times differ from the CSV's")
    values = {v: ds[v].values for v in VARIABLES}
    filled = 0
    for i, t in enumerate(times):
        for j, fl in enumerate(floes):
            got = [values[v][i, j] for v in VARIABLES]
            want = rows.get((t, fl))
            if want is None:
                if not all(np.isnan(g) for g in got):
                    fail(f"t = {t}, floe {fl} is not in the CSV but reads {got}")
                filled += 1
            elif got != want:
                fail(f"t = {t}, floe {fl}: {got} != CSV {want}")
    print(
        f"OK: {len(times)} times x {len(floes)} floes, {len(rows)} rows equal to the CSV, "
        f"{filled} (time, floe) outside a floe's life read as NaN"
    )


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(2)
    found = 0
    for top in sys.argv[1:]:
        for folder, _, files in sorted(os.walk(top)):
            if "trajectory.nc" in files and "trajectory.csv" in files:
                check(folder)
                found += 1
    if found == 0:
        fail("no folder holds both trajectory.nc and trajectory.csv")


if __name__ == "__main__":
    main()
