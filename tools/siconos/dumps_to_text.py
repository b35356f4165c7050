#!/usr/bin/env python3
"""Convert floebench LCP dumps (JSON, src/lcp/dump.rs) to the plain text read
by lexicolemke_time.c.

Usage: dumps_to_text.py DIR OUT.txt [MAX_N]

With MAX_N, dumps of more than MAX_N unknowns are left out.

Every *.json file of DIR (sorted by name) becomes one record:

    <file name> <n> <contacts>
    <q_1> ... <q_n>
    <M_11> ... <M_1n>        (n lines, M row by row)
    ...

Numbers are written with repr(), the shortest string that reads back to the
same double, and Python's float() parses the JSON numbers correctly rounded,
so the C program sees the dumps' data bit for bit. Non-finite entries
("NaN", "Infinity", null) are written as nan/inf, which strtod reads.
"""
import json
import math
import os
import sys


def num(v):
    if v is None:
        return float("nan")
    if isinstance(v, str):
        return float({"NaN": "nan", "Infinity": "inf", "-Infinity": "-inf"}[v])
    return float(v)


def fmt(x):
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    src, out = sys.argv[1], sys.argv[2]
    max_n = int(sys.argv[3]) if len(sys.argv) == 4 else None
    kept = 0
    names = sorted(f for f in os.listdir(src) if f.endswith(".json"))
    with open(out, "w") as o:
        for name in names:
            with open(os.path.join(src, name)) as f:
                d = json.load(f)
            q = [num(v) for v in d["q"]]
            rows = [[num(v) for v in r] for r in d["M"]]
            n = len(q)
            if max_n is not None and n > max_n:
                continue
            kept += 1
            if len(rows) != n or any(len(r) != n for r in rows):
                sys.exit(f"{name}: M is not {n}x{n}")
            o.write(f"{name} {n} {int(d['contacts'])}\n")
            o.write(" ".join(fmt(x) for x in q) + "\n")
            for r in rows:
                o.write(" ".join(fmt(x) for x in r) + "\n")
    print(f"{kept} of {len(names)} dumps -> {out}")


if __name__ == "__main__":
    main()
