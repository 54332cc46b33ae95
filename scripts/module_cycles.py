#!/usr/bin/env python3
"""Fails if any crate of the workspace has a cycle among its modules (issue 24).

A module `a` depends on `b` when its code (not its comments or docs, and not its
`#[cfg(test)]` part) names `crate::b` (also in a `crate::{...}` group, on many lines), a name
the crate root re-exports from `b`, or `super::b` from its own top-level file. A cycle is a strongly connected component of more
than one module. Prints each cycle and exits 1; prints the crates checked and exits 0 if none.

    scripts/module_cycles.py            (from the repository root; .ci/run calls it)
    scripts/module_cycles.py --self-test  (each way of naming a module, a cycle found)
"""
import glob
import os
import re
import sys


IDENT = r"[A-Za-z_][A-Za-z_0-9]*"


def code_of(path):
    """The code of a file: no comments, no string contents, nothing from `#[cfg(test)]` on."""
    lines = []
    for line in open(path, encoding="utf-8"):
        code = line.strip()
        if code.startswith("#[cfg(test)]"):
            break  # the test module comes last in this tree
        code = re.sub(r'"(?:\\.|[^"\\])*"', '""', code)
        code = re.sub(r"//.*", "", code)
        lines.append(code)
    return "\n".join(lines)


def top_items(group):
    """The first name of each comma-separated item of a `{...}` group (at depth 0)."""
    items, depth, cur = [], 0, ""
    for ch in group:
        depth += ch == "{"
        depth -= ch == "}"
        if ch == "," and depth == 0:
            items.append(cur)
            cur = ""
        else:
            cur += ch
    items.append(cur)
    return [m.group(0) for m in (re.match(IDENT, it.strip()) for it in items) if m]


def named_after(text, prefix):
    """Every name right after `prefix::` in `text`, through `{...}` groups (also on many
    lines): `crate::a::X` and `crate::{a::X, b}` name `a` and `b`."""
    names = []
    for m in re.finditer(prefix + r"::", text):
        rest = text[m.end():]
        if rest.startswith("{"):
            depth = 0
            for i, ch in enumerate(rest):
                depth += ch == "{"
                depth -= ch == "}"
                if depth == 0:
                    break
            names += top_items(rest[1:i])
        else:
            first = re.match(IDENT, rest)
            if first:
                names.append(first.group(0))
    return names


def reexports(root, files):
    """The names the crate root re-exports from its modules: `pub use a::{X, Y as Z}` maps X
    and Z to `a` (so that `crate::X` in another module names `a`)."""
    found = {}
    if root is None:
        return found
    for stmt in code_of(root).split(";"):
        m = re.search(r"\buse\s+(?:crate::|self::)?(" + IDENT + r")::(.*)", stmt, re.S)
        if m and m.group(1) in files:
            for leaf in re.findall(r"(" + IDENT + r")\s*(?=[,}]|$)", m.group(2).strip()):
                found[leaf] = m.group(1)
    return found


def modules(crate, src=None):
    """Each top-level module of `crate` and the modules of the same crate it names: by
    `crate::` paths (grouped or not), by names the crate root re-exports, and by `super::`
    from a top-level module's own file (which is the crate root)."""
    src = src or os.path.join(crate, "src")
    files = {}
    root = None
    for f in glob.glob(os.path.join(src, "**", "*.rs"), recursive=True):
        rel = os.path.relpath(f, src)[:-3].split(os.sep)
        if rel[0] in ("lib", "main"):
            root = root or f
        else:
            files.setdefault(rel[0], []).append((f, rel))
    exported = reexports(root, files)
    graph = {}
    for m, fs in files.items():
        deps = set()
        for f, rel in fs:
            code = code_of(f)
            names = named_after(code, r"(?<![$\w])crate")
            if len(rel) == 1 or rel[1:] == ["mod"]:
                names += named_after(code, r"(?<![:\w])super")
            for n in names:
                d = n if n in files else exported.get(n)
                if d and d != m:
                    deps.add(d)
        graph[m] = deps
    return graph


def self_test():
    """Each way of naming a module closes a cycle that must be found; a layered crate has none."""
    import tempfile

    cases = {
        "plain": ({"a": "use crate::b::X;", "b": "use crate::a::Y;"}, True),
        "grouped": ({"a": "use crate::{\n    c::Z,\n    b::X,\n};", "b": "use crate::a::Y;", "c": ""}, True),
        "re-export": ({"a": "use crate::X;", "b": "use crate::a::Y;", "lib": "pub use b::{X, W as V};"}, True),
        "super": ({"a": "use super::b::X;", "b": "fn f() { crate::a::g() }"}, True),
        "layered": ({"a": "use crate::b::X; // crate::a\nlet s = \"crate::a\";", "b": "", "lib": "pub use a::Q;"}, False),
    }
    for name, (mods, cyclic) in cases.items():
        with tempfile.TemporaryDirectory() as d:
            for m, text in mods.items():
                open(os.path.join(d, m + ".rs"), "w").write(text + "\n")
            found = cycles(modules(None, src=d))
            assert bool(found) == cyclic, f"self-test {name}: found {found}"
    print(f"self-test: {len(cases)} cases")


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
    if sys.argv[1:] == ["--self-test"]:
        self_test()
        return 0
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
