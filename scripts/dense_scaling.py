#!/usr/bin/env python3
"""Dense scaling and warm-start runs of the jammed bay (issue 12).

Runs `floebench run` on the bay jam family `cases/fields/bay_jam_<N>.toml`,
each started (`--from ... --at START`) from the jammed state of a rapier run
of the same case in `target/dense/bay_jam_<N>/trajectory.csv`, for a short
span, one formulation at a time (one process at a time, under `nice`), and
collects each run's `summary.json`: thread CPU of the run, time reached,
steps and LCP counters. The case is copied (into the output folder) with
`duration = SPAN`, `output_interval = 1` and, with `--warm on`, the
`warm_start = true` key of event-driven and moreau.

A run may be given a CPU budget (`--budget S`): past it the run is sent
SIGINT, ends at its next step and writes its outputs up to then
(`end = interrupted`); its CPU per simulated second is then its CPU over
the time it reached.

Writes `runs.csv` (one row per run) and `exponents.csv` (for each
formulation and each pair of consecutive sizes, the exponent
log(c2/c1)/log(N2/N1) of the CPU per simulated second c).

Example (the dense scaling table of docs/results/2026-12-04-dense-packs-lemke.md):

    python3 scripts/dense_scaling.py --sizes 200 --span 20 --start 5000 \
        --out target/dense/scaling --csv target/dense/scaling/csv200

(docs/results/2026-12-04-dense-packs-lemke.md gives every command).

Needs only Python 3 and a built `target/release/floebench`.
"""

import argparse
import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import time

FORMULATIONS = ["rapier", "moreau-cone", "moreau", "event-driven"]
COUNTERS = [
    "steps",
    "steps_rejected_penetration",
    "lcp_solves",
    "lcp_size_max",
    "lemke_pivots",
    "lcp_warm_hits",
    "lcp_warm_misses",
    "cone_solves",
    "max_penetration_m",
    "warm_check_sustained",
    "warm_check_sustained_different",
    "warm_check_sustained_rounding",
    "warm_check_impact",
    "warm_check_impact_different",
    "warm_check_impact_rounding",
    "warm_check_cold_failed",
    "contact_solves_measured",
    "contact_residual_median",
    "contact_residual_p95",
    "contact_residual_max",
    "contact_iterations_median",
    "contact_iterations_p95",
    "contact_iterations_max",
    "contact_unconverged",
    "contact_warm_hit_rate",
    "warm_check_max_difference",
]


def case_copy(src, dst, span, warm):
    """The case `src` with duration SPAN, output every 1 s (every SPAN if
    shorter) and, with `warm`, the warm start of event-driven and moreau."""
    with open(src, encoding="utf-8") as f:
        text = f.read()
    interval = min(1.0, span)
    text, n1 = re.subn(r"(?m)^duration\s*=.*$", f"duration = {span!r}", text, count=1)
    text, n2 = re.subn(
        r"(?m)^output_interval\s*=.*$", f"output_interval = {interval!r}", text, count=1
    )
    if n1 != 1 or n2 != 1:
        sys.exit(f"{src}: no `duration` or `output_interval` line to replace")
    if warm:
        if "[formulation." in text:
            sys.exit(f"{src}: already has formulation settings; add warm_start by hand")
        text += "\n[formulation.event-driven]\nwarm_start = true\n"
        text += "\n[formulation.moreau]\nwarm_start = true\n"
    with open(dst, "w", encoding="utf-8") as f:
        f.write(text)


def cpu_of(pid):
    """User + system CPU of process `pid` so far, s (Linux /proc)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, IndexError, ValueError):
        return 0.0


def run_one(cmd, budget, log):
    """Runs `cmd`; sends SIGINT once its CPU passes `budget` s (None: no
    budget). Returns the exit status."""
    with open(log, "w", encoding="utf-8") as out:
        p = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT)
        interrupted = False
        while p.poll() is None:
            time.sleep(1.0)
            if budget is not None and not interrupted and cpu_of(p.pid) > budget:
                p.send_signal(signal.SIGINT)
                interrupted = True
        return p.returncode


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", default="200,2000", help="floe counts N (default 200,2000)")
    ap.add_argument("--formulations", default=",".join(FORMULATIONS))
    ap.add_argument("--span", type=float, default=20.0, help="simulated span, s (default 20)")
    ap.add_argument("--start", type=float, default=5000.0,
                    help="output time of the rapier run to start from, s (default 5000)")
    ap.add_argument("--warm", choices=["off", "on"], default="off",
                    help="warm start of event-driven and moreau (default off)")
    ap.add_argument("--warm-check", action="store_true",
                    help="pass --warm-check (diagnostic; its CPU is no timing)")
    ap.add_argument("--budget", type=float, default=None,
                    help="CPU budget per run, s; SIGINT past it (default none)")
    ap.add_argument("--state", default=None,
                    help="trajectory to start from (default target/dense/bay_jam_<N>/trajectory.csv)")
    ap.add_argument("--case", default=None,
                    help="case file, `{n}` standing for N (default cases/fields/bay_jam_{n}.toml;"
                         " e.g. cases/fields/bay_jam_{n}_nsgs.toml for the iterative solvers)")
    ap.add_argument("--out", default="target/dense/scaling", help="run folders")
    ap.add_argument("--csv", default=None, help="folder of runs.csv and exponents.csv (default --out)")
    ap.add_argument("--bin", default="target/release/floebench")
    ap.add_argument("--nice", type=int, default=10,
                    help="niceness of the runs (absolute: this script's own counts; default 10)")
    a = ap.parse_args()

    sizes = [int(s) for s in a.sizes.split(",") if s]
    forms = [f.strip() for f in a.formulations.split(",") if f.strip()]
    warm = a.warm == "on"
    csv_dir = a.csv or a.out
    os.makedirs(a.out, exist_ok=True)
    os.makedirs(csv_dir, exist_ok=True)
    rows = []
    for n in sizes:
        case = (a.case or "cases/fields/bay_jam_{n}.toml").replace("{n}", str(n))
        state = a.state or f"target/dense/bay_jam_{n}/trajectory.csv"
        if not os.path.isfile(state):
            print(f"bay_jam_{n}: no {state}; make it with `cargo run --release -- run "
                  f"{case} -f rapier -o {os.path.dirname(state)} --quiet`", file=sys.stderr)
            continue
        stem = os.path.splitext(os.path.basename(case))[0]
        tag = f"{stem}_{a.span:g}s_warm_{a.warm}"
        copy = os.path.join(a.out, tag + ".toml")
        case_copy(case, copy, a.span, warm)
        for form in forms:
            out = os.path.join(a.out, tag, form)
            cmd = ["nice", "-n", str(max(0, a.nice - os.nice(0))), a.bin, "run", copy, "-f", form,
                   "--from", state, "--at", repr(a.start), "-o", out, "--quiet"]
            if a.warm_check:
                cmd.append("--warm-check")
            print(" ".join(cmd), file=sys.stderr, flush=True)
            os.makedirs(out, exist_ok=True)
            status = run_one(cmd, a.budget, os.path.join(out, "run.log"))
            try:
                with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
                    s = json.load(f)
            except (OSError, ValueError) as e:
                print(f"  no summary ({e}); exit status {status}", file=sys.stderr)
                continue
            cpu = s["timing"]["cpu_total"]
            t = s["t_reached"]
            c = s.get("counters", {})
            row = {
                "n": n,
                "formulation": form,
                "warm_start": a.warm,
                "span_s": a.span,
                "t_reached_s": t,
                "end": s["end"]["reason"],
                "cpu_s": cpu,
                "cpu_per_simulated_s": cpu / t if t > 0 else float("nan"),
            }
            for k in COUNTERS:
                row[k] = c[k]["value"] if k in c else ""
            rows.append(row)
            print(f"  {form}: {cpu:.2f} s CPU for {t:g} s ({row['end']})", file=sys.stderr, flush=True)
    if not rows:
        sys.exit("no run")
    with open(os.path.join(csv_dir, "runs.csv"), "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    ex = []
    for form in forms:
        per = {r["n"]: r["cpu_per_simulated_s"] for r in rows if r["formulation"] == form}
        ns = sorted(per)
        for n1, n2 in zip(ns, ns[1:]):
            c1, c2 = per[n1], per[n2]
            e = math.log(c2 / c1) / math.log(n2 / n1) if c1 > 0 and c2 > 0 else float("nan")
            ex.append({"formulation": form, "n1": n1, "n2": n2,
                       "cpu_per_s_1": c1, "cpu_per_s_2": c2, "exponent": e})
    if ex:
        with open(os.path.join(csv_dir, "exponents.csv"), "w", newline="", encoding="utf-8") as f:
            w = csv.DictWriter(f, fieldnames=list(ex[0]))
            w.writeheader()
            w.writerows(ex)
        for e in ex:
            print(f"{e['formulation']}: N {e['n1']} -> {e['n2']}: exponent {e['exponent']:.3f}")


if __name__ == "__main__":
    main()
