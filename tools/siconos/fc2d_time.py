#!/usr/bin/env python3
"""Time Siconos' 2D frictional contact solvers on the files `floebench fc2d` solves.

Usage (Debian's python3-siconos, installed only to measure; floebench never needs it):

    /usr/bin/python3 tools/siconos/fc2d_time.py tests/data/fc2d --csv siconos.csv
    /usr/bin/python3 tools/siconos/fc2d_time.py FILE.dat --solver lemke --tolerance 1e-6

For each file (a folder: its *.dat files, sorted) it solves the problem with
`fc2d_nsgs` (SICONOS_FRICTION_2D_NSGS, the default) or `fc2d_lexicolemke`
(SICONOS_FRICTION_2D_LEMKE) through `fc2d_driver`, from zero reactions, at the
tolerance given (Siconos' own stop test: its error, below), one thread. The CPU
is the thread CPU of the driver call (time.thread_time), µs, the median of
--runs cold solves (default 5). It prints and, with --csv, writes the columns of
`floebench fc2d --csv`:

    file,contacts,solver,iterations,residual,siconos_error,cpu_us

- iterations: Siconos' iparam[SICONOS_IPARAM_ITER_DONE] (sweeps; Lemke: pivots);
- siconos_error: ||r - P_K(r - u_hat)||_2 / max(||r||, ||u||, ||q||) (undivided
  when that max is below machine epsilon), u_hat = (u_N + mu |u_T|, u_T),
  recomputed here from u = W r + q (W read entry by entry from the problem);
- residual: floebench's natural-map residual of the same answer: per contact
  rho = 1 / W_NN, F = (r - P_K(r - rho u_hat)) / rho, ||F||_2 over
  max(||q||_2, 1e-9 max|q_i| + 1e-12) (src/iterative/fc2d.rs).

Both measures are defined in tests/data/fc2d/README.md. Siconos' `info` of
fc2d_lexicolemke is 0 whatever the error, so the error is what to check.
"""

import argparse
import math
import os
import statistics
import sys
import tempfile
import time

import numpy as np

try:
    import siconos.numerics as sn
except ImportError as e:  # pragma: no cover - measured, not tested
    sys.exit(f"error: siconos.numerics cannot be imported ({e}); install python3-siconos "
             "(Debian) and run this script with /usr/bin/python3")

SOLVERS = {
    "nsgs": sn.SICONOS_FRICTION_2D_NSGS,
    "lemke": sn.SICONOS_FRICTION_2D_LEMKE,
}

HEADER = "file,contacts,solver,iterations,residual,siconos_error,cpu_us"


def project_cone(n, t, mu):
    """The projection of (n, t) onto {|t| <= mu n}."""
    if n >= 0.0 and abs(t) <= mu * n:
        return n, t
    if mu * abs(t) <= -n:
        return 0.0, 0.0
    lam = (n + mu * abs(t)) / (1.0 + mu * mu)
    return lam, mu * lam * math.copysign(1.0, t)


def dense_w(problem):
    """W as a dense array, entry by entry (outside the timing)."""
    m = 2 * problem.numberOfContacts
    w = np.zeros((m, m))
    for i in range(m):
        for j in range(m):
            w[i, j] = sn.NM_get_value(problem.M, i, j)
    return w


def measures(w, q, mu, r):
    """(floebench's residual, Siconos' error) of the reactions r."""
    u = w @ r + q
    nc = len(mu)
    f_ours = 0.0
    f_sic = 0.0
    for j in range(nc):
        rn, rt = r[2 * j], r[2 * j + 1]
        un, ut = u[2 * j], u[2 * j + 1]
        uh = (un + mu[j] * abs(ut), ut)
        pn, pt = project_cone(rn - uh[0], rt - uh[1], mu[j])
        f_sic += (rn - pn) ** 2 + (rt - pt) ** 2
        wnn = w[2 * j, 2 * j]
        rho = 1.0 / wnn if wnn > 0.0 and math.isfinite(wnn) else 1.0
        pn, pt = project_cone(rn - rho * uh[0], rt - rho * uh[1], mu[j])
        f_ours += ((rn - pn) / rho) ** 2 + ((rt - pt) / rho) ** 2
    qn = float(np.linalg.norm(q))
    scale = max(qn, 1e-9 * float(np.max(np.abs(q))) + 1e-12)
    norm = max(float(np.linalg.norm(r)), float(np.linalg.norm(u)), qn)
    err = math.sqrt(f_sic)
    if norm >= sys.float_info.epsilon:
        err /= norm
    return math.sqrt(f_ours) / scale, err


def as_sparse_block(problem, w, folder):
    """The problem with W in sparse-block storage (1), through a file in
    `folder`: fc2d_driver refuses storage 2 (CSparse), "unknown storagetype".
    The 2x2 blocks of W with a nonzero entry (and every diagonal block)."""
    nc = problem.numberOfContacts
    rows = []
    for i in range(nc):
        cols = [j for j in range(nc)
                if i == j or np.any(w[2 * i:2 * i + 2, 2 * j:2 * j + 2] != 0.0)]
        rows.append(cols)
    nnz = sum(len(c) for c in rows)
    cum = "\t".join(str(2 * (k + 1)) for k in range(nc))
    out = ["2", str(nc), "1", str(2 * nc), str(2 * nc), str(nnz), str(nc), str(nc), cum, cum,
           str(nc + 1), str(nnz)]
    ptr = [0]
    for c in rows:
        ptr.append(ptr[-1] + len(c))
    out.append("\t".join(map(str, ptr)))
    out.append("\t".join(str(j) for c in rows for j in c))
    k = 0
    for i, c in enumerate(rows):
        for j in c:
            b = w[2 * i:2 * i + 2, 2 * j:2 * j + 2]
            out.append(str(k))
            # column-major: W_NN W_TN W_NT W_TT
            out.extend(repr(float(x)) for x in (b[0, 0], b[1, 0], b[0, 1], b[1, 1]))
            k += 1
    out.extend(repr(float(x)) for x in np.asarray(problem.q))
    out.extend(repr(float(x)) for x in np.asarray(problem.mu))
    path = os.path.join(folder, "sbm.dat")
    with open(path, "w") as fh:
        fh.write("\n".join(out) + "\n")
    return sn.frictionContact_new_from_filename(path)


def solve(problem, solver, tolerance, max_iterations):
    """One cold solve: (reactions, iterations, thread CPU in µs, info)."""
    n = problem.numberOfContacts
    options = sn.SolverOptions(SOLVERS[solver])
    options.dparam[sn.SICONOS_DPARAM_TOL] = tolerance
    options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = max_iterations
    r = np.zeros(2 * n)
    u = np.zeros(2 * n)
    t0 = time.thread_time()
    info = sn.fc2d_driver(problem, r, u, options)
    cpu = (time.thread_time() - t0) * 1e6
    return r, int(options.iparam[sn.SICONOS_IPARAM_ITER_DONE]), cpu, info


def version():
    """The installed siconos package's version (its Python metadata)."""
    try:
        from importlib.metadata import version as v
        return v("siconos")
    except Exception:  # pragma: no cover - a report line only
        return "(version unknown)"


def files_of(path):
    if os.path.isdir(path):
        names = sorted(f for f in os.listdir(path) if f.endswith(".dat"))
        return [os.path.join(path, f) for f in names]
    return [path]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("path", help="a problem file (.dat) or a folder of them")
    ap.add_argument("--solver", choices=sorted(SOLVERS), default="nsgs")
    ap.add_argument("--tolerance", type=float, default=1e-6)
    ap.add_argument("--max-iterations", type=int, default=10000)
    ap.add_argument("--runs", type=int, default=5, help="cold solves; the median CPU is reported")
    ap.add_argument("--csv", help="also write the rows to this file")
    a = ap.parse_args()
    if not (a.tolerance > 0.0 and math.isfinite(a.tolerance)):
        sys.exit(f"error: --tolerance must be a finite number > 0, got {a.tolerance}")
    if a.runs < 1:
        sys.exit("error: --runs must be at least 1")
    rows = []
    for f in files_of(a.path):
        problem = sn.frictionContact_new_from_filename(f)
        if problem is None:
            print(f"error: {f}: Siconos cannot read it", file=sys.stderr)
            continue
        w = dense_w(problem)
        note = ""
        if problem.M.storageType == sn.NM_SPARSE:
            with tempfile.TemporaryDirectory() as folder:
                problem = as_sparse_block(problem, w, folder)
            note = " (W given to Siconos as sparse blocks)"
        cpus = []
        for _ in range(a.runs):
            r, iterations, cpu, info = solve(problem, a.solver, a.tolerance, a.max_iterations)
            cpus.append(cpu)
        residual, err = measures(w, np.asarray(problem.q), np.asarray(problem.mu), r)
        rows.append((os.path.basename(f), problem.numberOfContacts, a.solver, iterations,
                     residual, err, statistics.median(cpus), info, note))
    print(f"Siconos {version()} {a.solver}, tolerance {a.tolerance}, "
          f"thread CPU median of {a.runs} cold solves")
    print(HEADER + ",info")
    for row in rows:
        print("{},{},{},{},{:.4g},{:.4g},{:.1f},{}{}".format(*row))
    if a.csv:
        tmp = a.csv + ".tmp"
        with open(tmp, "w") as out:
            out.write(HEADER + "\n")
            for row in rows:
                out.write("{},{},{},{},{!r},{!r},{!r}\n".format(*row[:7]))
        os.replace(tmp, a.csv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
