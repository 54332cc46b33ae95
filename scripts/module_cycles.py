#!/usr/bin/env python3
"""Fails if any crate of the workspace has a cycle among its modules (issue 24).

A module `a` depends on `b` when its code (not its comments or docs, and not its
`#[cfg(test)]` part) names `crate::b`. A cycle is a strongly connected component of more
than one module. Prints each cycle and exits 1; prints the crates checked and exits 0 if none.

    scripts/module_cycles.py            (from the repository root; .ci/run calls it)
"""
import glob
import os
import re
import sys


def modules(crate):
    """Each top-level module of `crate` and the modules of the same crate it names."""
    src = os.path.join(crate, "src")
    files = {}
    for f in glob.glob(os.path.join(src, "**", "*.rs"), recursive=True):
        top = os.path.relpath(f, src)[:-3].split(os.sep)[0]
        if top not in ("lib", "main"):
            files.setdefault(top, []).append(f)
    graph = {}
    for m, fs in files.items():
        deps = set()
        for f in fs:
            for line in open(f, encoding="utf-8"):
                code = line.strip()
                if code.startswith("#[cfg(test)]"):
                    break  # the test module comes last in this tree
                if code.startswith("//"):
                    continue
                code = re.sub(r'"[^"]*"', "", code)
                deps.update(d for d in re.findall(r"crate::([a-z_0-9]+)", code) if d != m and d in files)
        graph[m] = deps
    return graph


def cycles(graph):
    """Tarjan's strongly connected components of more than one node."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
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
                found.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def main():
    crates = sorted(glob.glob("crates/*")) + ["xtask", "python"]
    bad = False
    for crate in crates:
        for comp in cycles(modules(crate)):
            print(f"{crate}: module cycle {' ↔ '.join(comp)}")
            bad = True
    if bad:
        return 1
    print(f"no module cycle in {len(crates)} crates")
    return 0


if __name__ == "__main__":
    sys.exit(main())
