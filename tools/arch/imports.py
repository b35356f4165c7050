#!/usr/bin/env python3
"""The crate's import graph between top-level modules (folders of src/).

Reads every `crate::a::...` path in src/ (use lines and inline paths, comments
and doc comments skipped), then prints:
  - the edges between top-level modules, with a count of the places;
  - the circles (strongly connected components of more than one module);
  - the back-edges against the layer order given by `LAYERS` in src/lib.rs
    (an import from a module to one of a higher layer);
  - the largest source files.
Usage: python3 tools/arch/imports.py [--files]   (--files: also the file-level circles)
Exit status 0 always: it reports, it does not judge.
"""
import os, re, sys
from collections import defaultdict

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SRC = os.path.join(ROOT, "src")

def strip_comments(text):
    out = []
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("//"):
            continue
        i = line.find("//")
        # crude: ignore // inside strings is rare enough in use paths
        out.append(line if i < 0 else line[:i])
    return "\n".join(out)

def module_of(path):
    rel = os.path.relpath(path, SRC)
    parts = rel.split(os.sep)
    if len(parts) == 1:
        name = parts[0][:-3]
        return name
    return parts[0]

def file_module_path(path):
    rel = os.path.relpath(path, SRC)[:-3]
    parts = rel.split(os.sep)
    if parts[-1] == "mod":
        parts = parts[:-1]
    return "::".join(parts)

USE_BLOCK = re.compile(r"\buse\s+crate::(\{[^;]*\}|[^;]*);", re.S)
SUPER_BLOCK = re.compile(r"\buse\s+((?:super::)+)(\{[^;]*\}|[^;]*);", re.S)
SUPER_INLINE = re.compile(r"\b((?:super::)+)([a-z_][a-z0-9_]*(?:::[a-z_][a-z0-9_]*)*)")
INLINE = re.compile(r"\bcrate::([a-z_][a-z0-9_]*(?:::[a-z_][a-z0-9_]*)*)")

def expand(prefix, body):
    """Expand a use tree body into full paths (modules only, lowercase segments)."""
    body = body.strip()
    if body.startswith("{") and body.endswith("}"):
        inner = body[1:-1]
        depth, cur, items = 0, "", []
        for ch in inner:
            if ch == "{": depth += 1
            if ch == "}": depth -= 1
            if ch == "," and depth == 0:
                items.append(cur); cur = ""
            else:
                cur += ch
        items.append(cur)
        res = []
        for it in items:
            it = it.strip()
            if it:
                res += expand(prefix, it)
        return res
    m = re.match(r"([A-Za-z_][A-Za-z0-9_]*)\s*(::\s*(.*))?$", body, re.S)
    if not m:
        return [prefix]
    head, rest = m.group(1), m.group(3)
    p = prefix + [head]
    if rest is None:
        return [p]
    return expand(p, rest)

def files():
    for d, _, fs in os.walk(SRC):
        for f in fs:
            if f.endswith(".rs"):
                yield os.path.join(d, f)

def targets(text, me=None):
    t = strip_comments(text)
    paths = []
    if me is not None:
        base = me.split("::")
        def up(n):
            return base[:len(base) - n] if n <= len(base) else []
        for m in SUPER_BLOCK.finditer(t):
            n = m.group(1).count("super")
            paths += [up(n) + p for p in expand([], m.group(2))]
        t = SUPER_BLOCK.sub("", t)
        for m in SUPER_INLINE.finditer(t):
            n = m.group(1).count("super")
            paths.append(up(n) + m.group(2).split("::"))
        t = SUPER_INLINE.sub("", t)
    for m in USE_BLOCK.finditer(t):
        paths += expand([], m.group(1))
    t2 = USE_BLOCK.sub("", t)
    for m in INLINE.finditer(t2):
        paths.append(m.group(1).split("::"))
    return [[s for s in p if s != "self"] for p in paths if p]

def layers():
    text = open(os.path.join(SRC, "lib.rs")).read()
    m = re.search(r"LAYERS:\s*\n(.*?)\n\s*//!\s*$", text, re.S | re.M)
    order = {}
    for i, line in enumerate(re.findall(r"//!\s*(\d+)\.\s*([a-z_ ,]+)", text)):
        for name in line[1].split(","):
            order[name.strip()] = int(line[0])
    return order

def sccs(nodes, edges):
    index, low, stack, on, out, idx = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(10000)
    def strong(v):
        index[v] = low[v] = idx[0]; idx[0] += 1; stack.append(v); on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                strong(w); low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop(); on.discard(w); comp.append(w)
                if w == v: break
            if len(comp) > 1: out.append(sorted(comp))
    for v in sorted(nodes):
        if v not in index: strong(v)
    return out

def main():
    mods = set()
    edges = defaultdict(lambda: defaultdict(list))
    fedges = defaultdict(set)
    fmods = {}
    all_files = sorted(files())
    for f in all_files:
        fmods[file_module_path(f)] = f
    for f in all_files:
        src = module_of(f)
        if src in ("lib", "main"): continue
        mods.add(src)
        me = file_module_path(f)
        for p in targets(open(f).read(), me):
            dst = p[0]
            if dst != src and os.path.exists(os.path.join(SRC, dst + ".rs")) or os.path.isdir(os.path.join(SRC, dst)):
                if dst != src:
                    edges[src][dst].append(os.path.relpath(f, ROOT))
            # file-level: longest prefix that is a file module
            for k in range(len(p), 0, -1):
                cand = "::".join(p[:k])
                if cand in fmods:
                    if cand != me and not me.startswith(cand + "::") and not cand.startswith(me + "::"):
                        fedges[me].add(cand)
                    break
    print("## Imports between top-level modules (places)")
    for a in sorted(edges):
        for b in sorted(edges[a]):
            print(f"{a} -> {b} ({len(edges[a][b])})")
    simple = {a: set(edges[a]) for a in edges}
    circ = sccs(mods, simple)
    print(f"\n## Circles between top-level modules: {len(circ)}")
    for c in circ: print("  " + " <-> ".join(c))
    order = layers()
    back = []
    if order:
        for a in sorted(edges):
            for b in sorted(edges[a]):
                if a in order and b in order and order[b] > order[a]:
                    back.append((a, b, edges[a][b]))
        missing = sorted(m for m in mods if m not in order)
        print(f"\n## Back-edges against the layers of lib.rs: {len(back)}")
        for a, b, fs in back:
            print(f"  {a} (layer {order[a]}) -> {b} (layer {order[b]}): {', '.join(sorted(set(fs)))}")
        if missing: print("  modules not in any layer: " + ", ".join(missing))
    else:
        print("\n(no LAYERS list in src/lib.rs: back-edges not computed)")
    fc = sccs(set(fedges) | {x for s in fedges.values() for x in s}, fedges)
    print(f"\n## Circles between files: {len(fc)}")
    if "--files" in sys.argv:
        for c in fc: print("  " + " <-> ".join(c))
    else:
        for c in fc: print(f"  {len(c)} files, e.g. " + ", ".join(c[:4]))
    sizes = sorted(((sum(1 for _ in open(f)), os.path.relpath(f, ROOT)) for f in all_files), reverse=True)
    print("\n## Largest source files")
    for n, f in sizes[:10]: print(f"  {n:5d} {f}")
    print(f"  files over 600 lines: {sum(1 for n, _ in sizes if n > 600)}; over 1,000: {sum(1 for n, _ in sizes if n > 1000)}")

main()
