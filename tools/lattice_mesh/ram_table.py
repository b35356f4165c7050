#!/usr/bin/env python3
"""The outcome of cases/lattice_ram.toml against the lattice spacing (issue 39 item 5).

Runs `floebench run` on copies of a lattice case whose `[fracture]` table gets
`spacing = S` and `seed = N` (every other line unchanged), for each spacing,
seed and formulation, and prints one Markdown row per (formulation, spacing,
seed, lane). A lane is one of the case's listed floes and all its
descendants (floes.json's `parent` chain). Per lane:

- `fractures`: the rows of fractures.csv whose parent is in the lane;
- `pieces`: the lane's floes alive at the end (t_end null in floes.json);
- `areas`: their areas (floes.json), m², largest first;
- `v_main`: the speed |v| (m/s) of the lane's largest piece at the last
  output (trajectory.csv), `v_rest`: the area-weighted mean speed of the
  others (blank when the floe stayed whole), `v_max`: the fastest piece's.

Then, per formulation, spacing and lane, the mean over the seeds of
fractures, pieces, largest area, v_main and v_max.

Usage (from the worktree root, after `cargo build --release`):

    python3 tools/lattice_mesh/ram_table.py --spacings 0.5 0.35 0.25 --seeds 1 2 3 \
        --formulations event-driven moreau --out /tmp/lattice_mesh

Extra `[fracture]` lines can be added with --set KEY=VALUE (e.g.
`--set toughness=1.9635`); the runs' folders stay in --out.
"""

import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
from collections import defaultdict


def variant(text, settings):
    """The case text with `settings` (key -> value string) in its [fracture] table."""
    lines = text.splitlines()
    start = next(i for i, l in enumerate(lines) if l.strip() == "[fracture]")
    end = next(
        (i for i in range(start + 1, len(lines)) if lines[i].lstrip().startswith("[")),
        len(lines),
    )
    body = [
        l
        for l in lines[start + 1 : end]
        if re.match(r"\s*([A-Za-z_]+)\s*=", l) is None
        or re.match(r"\s*([A-Za-z_]+)\s*=", l).group(1) not in settings
    ]
    body += [f"{k} = {v}" for k, v in settings.items()]
    return "\n".join(lines[: start + 1] + body + lines[end:]) + "\n"


def lanes(out):
    """Per lane (root floe id): fractures, the alive pieces' areas and speeds."""
    floes = json.load(open(os.path.join(out, "floes.json")))
    parent = {f["id"]: f["parent"] for f in floes}

    def root(i):
        while parent[i] is not None:
            i = parent[i]
        return i

    last = {}
    with open(os.path.join(out, "trajectory.csv")) as fh:
        for row in csv.DictReader(fh):
            last[int(row["floe"])] = row  # rows are in time order
    fractures = defaultdict(int)
    with open(os.path.join(out, "fractures.csv")) as fh:
        for row in csv.DictReader(fh):
            fractures[root(int(row["parent"]))] += 1
    result = {}
    for f in floes:
        if f["parent"] is not None:
            continue
        lane = f["id"]
        alive = [g for g in floes if g["t_end"] is None and root(g["id"]) == lane]
        alive.sort(key=lambda g: -g["area"])
        speeds = [math.hypot(float(last[g["id"]]["vx"]), float(last[g["id"]]["vy"])) for g in alive]
        rest = alive[1:]
        result[lane] = {
            "fractures": fractures[lane],
            "pieces": len(alive),
            "areas": [g["area"] for g in alive],
            "v_main": speeds[0],
            "v_rest": (
                sum(g["area"] * v for g, v in zip(rest, speeds[1:])) / sum(g["area"] for g in rest)
                if rest
                else None
            ),
            "v_max": max(speeds),
        }
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--case", default="cases/lattice_ram.toml")
    ap.add_argument("--bin", default="target/release/floebench")
    ap.add_argument("--spacings", nargs="+", type=float, default=[0.5, 0.35, 0.25])
    ap.add_argument("--seeds", nargs="+", type=int, default=[1])
    ap.add_argument("--formulations", nargs="+", default=["event-driven", "moreau"])
    ap.add_argument("--set", nargs="*", default=[], help="extra [fracture] KEY=VALUE lines")
    ap.add_argument("--out", default="/tmp/lattice_mesh")
    ap.add_argument("--reuse", action="store_true", help="read existing runs, do not run")
    a = ap.parse_args()
    text = open(a.case).read()
    extra = dict(kv.split("=", 1) for kv in a.set)
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for s in a.spacings:
        for seed in a.seeds:
            settings = {"spacing": repr(s), "seed": str(seed), **extra}
            case = os.path.join(a.out, f"ram_s{s}_seed{seed}.toml")
            with open(case, "w") as fh:
                fh.write(variant(text, settings))
            for f in a.formulations:
                out = os.path.join(a.out, f"s{s}_seed{seed}", f)
                if not a.reuse:
                    subprocess.run([a.bin, "run", case, "-f", f, "-o", out, "--quiet"], check=True,
                                   stdout=subprocess.DEVNULL)
                for lane, r in sorted(lanes(out).items()):
                    rows.append((f, s, seed, lane, r))
    print("| formulation | spacing (m) | seed | lane | fractures | pieces | areas (m², largest first) | v_main | v_rest | v_max |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for f, s, seed, lane, r in rows:
        areas = ", ".join(f"{x:.2f}" for x in r["areas"])
        vr = "" if r["v_rest"] is None else f"{r['v_rest']:.3f}"
        print(f"| {f} | {s} | {seed} | {lane} | {r['fractures']} | {r['pieces']} | {areas} | "
              f"{r['v_main']:.3f} | {vr} | {r['v_max']:.3f} |")
    print()
    print("Means over the seeds:")
    print()
    print("| formulation | lane | spacing (m) | fractures | pieces | largest area (m²) | v_main | v_max |")
    print("|---|---|---|---|---|---|---|---|")
    groups = defaultdict(list)
    for f, s, seed, lane, r in rows:
        groups[(f, lane, s)].append(r)
    for (f, lane, s), rs in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][1], -kv[0][2])):
        n = len(rs)
        mean = lambda key: sum(key(r) for r in rs) / n
        print(f"| {f} | {lane} | {s} | {mean(lambda r: r['fractures']):.2f} | {mean(lambda r: r['pieces']):.2f} | "
              f"{mean(lambda r: r['areas'][0]):.2f} | {mean(lambda r: r['v_main']):.3f} | {mean(lambda r: r['v_max']):.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
