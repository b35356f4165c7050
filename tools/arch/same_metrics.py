#!/usr/bin/env python3
"""Whether two comparison reports hold the same metrics, timing excluded.

A restructuring that must not change behaviour is checked with it:
    floebench compare cases/ --out /tmp/new --quiet
    python3 tools/arch/same_metrics.py reports/sample /tmp/new
It reads each case's metrics.csv in both folders and prints, per case, how
many metrics differ beyond 1e-12 relative (CPU, wall and clock metrics left
out), with the first few differences; the last line is the total. A case
that only one folder holds is named, not compared.
Usage: same_metrics.py A B [case ...]
"""
import sys, os, csv
a, b = sys.argv[1], sys.argv[2]
cases = sys.argv[3:] or sorted(d for d in os.listdir(b) if os.path.isfile(os.path.join(b, d, 'metrics.csv')))
def load(p):
    out = {}
    with open(p) as f:
        for r in csv.DictReader(f):
            m = r['metric']
            if m.startswith('cpu_') or m == 'wall' or 'wall' in m or m.startswith('timer_') or 'clock' in m:
                continue
            out[(r['formulation'], r['other'], m)] = r['value']
    return out
bad = 0; total = 0
for c in cases:
    if not os.path.isfile(os.path.join(a, c, 'metrics.csv')):
        print(f"{c}: only in {b}")
        continue
    A = load(os.path.join(a, c, 'metrics.csv')); B = load(os.path.join(b, c, 'metrics.csv'))
    keys = set(A) | set(B)
    diffs = []
    for k in sorted(keys):
        total += 1
        va, vb = A.get(k), B.get(k)
        if va == vb: continue
        try:
            fa, fb = float(va), float(vb)
            if fa == fb or abs(fa - fb) <= 1e-12 * max(abs(fa), abs(fb)): continue
        except Exception: pass
        diffs.append((k, va, vb))
    bad += len(diffs)
    print(f"{c}: {len(keys)} metrics, {len(diffs)} differ")
    for d in diffs[:8]: print("   ", d)
print(f"total {total} metrics compared, {bad} differ")
