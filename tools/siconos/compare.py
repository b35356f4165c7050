#!/usr/bin/env python3
"""Side-by-side table of two timing CSVs with the columns of
`floebench lcp DIR --time --csv`: ours (floebench) and Siconos
(lexicolemke_time), joined on the file name.

Usage: compare.py OURS.csv SICONOS.csv [TOL]

Per size bucket (unknowns 1-8, 9-40, 41-200, 201-800, >800): problems, our
median µs, Siconos' median µs, the median over problems of the ratio
ours/Siconos, failures of each (a problem is solved when its residual on the
original data is at most TOL, default 1e-10, the acceptance tolerance of
floebench's driver), Siconos' wrong answers reported as success (info = 0
with a residual above TOL), and the largest residual of each.
"""
import csv
import statistics
import sys

BUCKETS = [(1, 8), (9, 40), (41, 200), (201, 800), (801, 10**9)]


def label(lo, hi):
    return f">{lo - 1}" if hi == 10**9 else f"{lo}-{hi}"


def load(path):
    with open(path) as f:
        return {r["file"]: r for r in csv.DictReader(f)}


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    ours, sic = load(sys.argv[1]), load(sys.argv[2])
    tol = float(sys.argv[3]) if len(sys.argv) == 4 else 1e-10
    common = sorted(set(ours) & set(sic))
    print(f"{len(common)} problems in both; solved = residual <= {tol:g}")
    print("| unknowns | count | ours median µs | Siconos median µs | median ratio ours/Siconos "
          "| ours failed | Siconos failed | Siconos wrong but info=0 | ours max residual "
          "| Siconos max residual |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for lo, hi in BUCKETS:
        sel = [f for f in common if lo <= int(ours[f]["n"]) <= hi]
        if not sel:
            continue
        o = [float(ours[f]["cpu_us"]) for f in sel]
        s = [float(sic[f]["cpu_us"]) for f in sel]
        ratio = statistics.median(a / b for a, b in zip(o, s) if b > 0)
        ro = [float(ours[f]["residual"]) for f in sel]
        rs = [float(sic[f]["residual"]) for f in sel]
        of = sum(1 for r in ro if not r <= tol)
        sf = sum(1 for r in rs if not r <= tol)
        wrong = sum(1 for f, r in zip(sel, rs) if sic[f]["status"] == "Solved" and not r <= tol)
        print(f"| {label(lo, hi)} | {len(sel)} | {statistics.median(o):.3f} | "
              f"{statistics.median(s):.3f} | {ratio:.2f} | {of} | {sf} | {wrong} | "
              f"{max(ro):.1e} | {max(rs):.1e} |")


if __name__ == "__main__":
    main()
