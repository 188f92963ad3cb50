#!/usr/bin/env python3
"""Module dependency graph of src/ and a check that it has no cycle.

A module is a folder of src/. Module A depends on module B when a file in A
includes a header of B (#include "B/...") or, given --objects, when an object
file compiled from A references a global symbol defined by an object file of
B (read with nm). The graph must be acyclic and no module may depend on a top
module (analysis), so that each layer of docs/DESIGN.md can be built, tested
and understood with only the layers below it.

    scripts/depgraph.py [--src DIR] [--objects BUILD_DIR] [--dot]

Prints one line per module with what it depends on (or the graph in DOT with
--dot) and exits 1, listing the offending edges, when there is a cycle or a
dependency on a top module.
"""

import argparse
import os
import re
import subprocess
import sys

TOP = {"analysis"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"/]+)/[^"]+"', re.M)
NM_LINE = re.compile(r"^(.*\.c\.o(?:bj)?):(?:[0-9a-fA-F]+)?\s+([A-Za-z])\s+(\S+)$")


def modules(src):
    return sorted(d for d in os.listdir(src) if os.path.isdir(os.path.join(src, d)))


def include_edges(src, mods):
    """(from, to) -> list of 'file: why' from #include lines."""
    edges = {}
    for mod in mods:
        folder = os.path.join(src, mod)
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".c", ".h")):
                continue
            with open(os.path.join(folder, name), encoding="utf-8") as f:
                text = f.read()
            for target in INCLUDE.findall(text):
                if target in mods and target != mod:
                    why = "%s/%s includes %s/" % (mod, name, target)
                    reasons = edges.setdefault((mod, target), [])
                    if why not in reasons:
                        reasons.append(why)
    return edges


def object_files(build, src, mods):
    """module -> object files under build compiled from a source in src/<module>/
    (objects of sources since moved or deleted are left out; where a build
    folder holds several objects of one source, from targets since renamed,
    only the newest counts)."""
    newest = {}
    for root, _, files in os.walk(build):
        # From the build folder down, and the last "src": the folders above
        # it (a checkout in ~/src/persp) are no part of the object's path.
        parts = os.path.relpath(root, build).replace(os.sep, "/").split("/")
        if "src" not in parts:
            continue
        rest = parts[len(parts) - parts[::-1].index("src"):]
        if len(rest) != 1 or rest[0] not in mods:
            continue
        for name in files:
            source = name[:name.rfind(".c.") + 2]
            if name.endswith((".c.o", ".c.obj")) and os.path.isfile(os.path.join(src, rest[0], source)):
                path = os.path.join(root, name)
                key = (rest[0], source)
                mtime = os.path.getmtime(path)
                if key not in newest or mtime > newest[key][0]:
                    newest[key] = (mtime, path)
    found = {}
    for (mod, _), (_, path) in sorted(newest.items()):
        found.setdefault(mod, []).append(path)
    return found


def nm_symbols(paths):
    """path -> (global symbols defined, symbols referenced), one nm run for all."""
    out = subprocess.run(["nm", "-A"] + paths, check=True, capture_output=True, text=True).stdout
    syms = {p: (set(), set()) for p in paths}
    for line in out.splitlines():
        m = NM_LINE.match(line)
        if not m or m.group(1) not in syms:
            continue
        path, kind, sym = m.groups()
        defined, undefined = syms[path]
        if kind == "U":
            undefined.add(sym)
        elif kind.isupper() or kind == "i":  # global, or a GNU indirect function
            defined.add(sym)
    return syms


def symbol_edges(build, src, mods):
    """(from, to) -> list of 'file: why' from references between object files."""
    objs = object_files(build, src, mods)
    if not objs:
        sys.exit("depgraph: no object files of src/ under %s" % build)
    syms = nm_symbols(sorted(p for paths in objs.values() for p in paths))
    owner, refs = {}, []
    for mod, paths in objs.items():
        for path in sorted(paths):
            defined, undefined = syms[path]
            for sym in defined:
                owner[sym] = mod
            base = os.path.basename(path).rsplit(".", 2)[0]
            refs.extend((mod, "%s/%s.c" % (mod, base), sym) for sym in sorted(undefined))
    edges = {}
    for mod, name, sym in refs:
        target = owner.get(sym)
        if target is not None and target != mod:
            edges.setdefault((mod, target), []).append("%s uses %s (%s/)" % (name, sym, target))
    return edges


def cycles(mods, graph):
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, comps = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(sorted(comp))

    for v in mods:
        if v not in index:
            visit(v)
    return comps


def one_cycle(comp, graph):
    """A closed path through the first module of a strongly connected component."""
    start, members = comp[0], set(comp)
    path, seen = [start], {start}

    def walk(v):
        for w in sorted(graph[v] & members):
            if w == start:
                return True
            if w not in seen:
                seen.add(w)
                path.append(w)
                if walk(w):
                    return True
                path.pop()
        return False

    walk(start)
    return path + [start]


def layers(mods, graph):
    """Longest-path depth of each module above the modules it depends on."""
    depth = {}

    def d(v, trail):
        if v not in depth:
            if v in trail:
                return 0
            depth[v] = 1 + max((d(w, trail | {v}) for w in graph[v]), default=-1)
        return depth[v]

    for v in mods:
        d(v, frozenset())
    return depth


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--src", default=os.path.join(here, "..", "src"))
    ap.add_argument("--objects", metavar="BUILD_DIR",
                    help="also count symbol references between the object files under BUILD_DIR")
    ap.add_argument("--dot", action="store_true", help="print the graph in DOT")
    args = ap.parse_args()

    mods = modules(args.src)
    edges = include_edges(args.src, mods)
    if args.objects:
        for key, why in symbol_edges(args.objects, args.src, mods).items():
            edges.setdefault(key, []).extend(why)
    graph = {m: set() for m in mods}
    for a, b in edges:
        graph[a].add(b)

    comps = cycles(mods, graph)
    depth = layers(mods, graph)
    if args.dot:
        print("digraph persp {\n  rankdir=BT;")
        for m in mods:
            print('  "%s";' % m)
        for a, b in sorted(edges):
            bad = any(a in c and b in c for c in comps) or b in TOP
            print('  "%s" -> "%s"%s;' % (a, b, " [color=red]" if bad else ""))
        print("}")
    else:
        for m in sorted(mods, key=lambda m: (depth[m], m)):
            print("%-9s (layer %d) -> %s" % (m, depth[m], " ".join(sorted(graph[m])) or "-"))

    problems = []
    for comp in comps:
        path = one_cycle(comp, graph)
        problems.append("cycle: " + " -> ".join(path))
        for a, b in zip(path, path[1:]):
            for why in edges[(a, b)][:3]:
                problems.append("  %s -> %s: %s" % (a, b, why))
        if len(comp) > len(path) - 1:
            problems.append("  modules on this or other cycles with it: " + " ".join(comp))
    for (a, b), why in sorted(edges.items()):
        if b in TOP and a not in TOP:
            problems.append("%s depends on top module %s: %s" % (a, b, why[0]))
    if problems:
        sys.stdout.flush()
        print("\n".join(problems), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
