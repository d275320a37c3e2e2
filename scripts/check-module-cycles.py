#!/usr/bin/env python3
"""No import circle between the modules of any crate.

For every crate of the repository (a folder with Cargo.toml and src/), read each module's
`crate::x`, `super::x` and `use crate::{x, ...}` references outside its tests and build two
graphs: one between the crate's top-level modules, one between the sibling modules of each
folder module. A strongly connected component of more than one module is a circle; each is
printed and the script exits 1. A parent that declares its children and a child that reads its
parent's items are not a circle (that is how Rust nests modules); test code (`#[cfg(test)]` to
the end of a file, and files named tests*.rs) is left out.

Written out (about a hundred lines) because no packaged tool checks module-level cycles.
Usage: scripts/check-module-cycles.py [REPO]
"""
import os
import re
import sys

IDENT = r"[a-z_][a-z0-9_]*"


def modules(src):
    """Map each source file to its module path (list of names; [] for the crate root)."""
    found = {}
    for root, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs") or f.startswith("tests"):
                continue
            path = os.path.join(root, f)
            parts = os.path.relpath(path, src)[:-3].split(os.sep)
            if parts[-1] == "mod":
                parts = parts[:-1]
            if parts in (["lib"], ["main"]) or parts[0] == "bin":
                parts = [] if parts[0] != "bin" else None
            if parts is not None:
                found[path] = parts
    return found


def code_of(text):
    """The text without comments, string contents and the test module at the end."""
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r'"(\\.|[^"\\])*"', '""', text)
    cut = text.find("#[cfg(test)]")
    return text if cut < 0 else text[:cut]


def references(text):
    """(kind, name) pairs: ('crate', x) for crate::x, ('super', x) for super::x."""
    refs = set()
    for m in re.finditer(r"\b(crate|super)::(" + IDENT + r")", text):
        refs.add((m.group(1), m.group(2)))
    for m in re.finditer(r"use\s+(crate|super)::\{([^;]*)\};", text, flags=re.S):
        for part in m.group(2).split(","):
            name = re.match(r"\s*(" + IDENT + ")", part)
            if name:
                refs.add((m.group(1), name.group(1)))
    return refs


def circles(graph):
    """Strongly connected components of more than one node (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(n):
        index[n] = low[n] = len(index)
        stack.append(n)
        on.add(n)
        for w in sorted(graph.get(n, ())):
            if w not in index:
                visit(w)
                low[n] = min(low[n], low[w])
            elif w in on:
                low[n] = min(low[n], index[w])
        if low[n] == index[n]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == n:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for n in sorted(graph):
        if n not in index:
            visit(n)
    return out


def crate_graph(src):
    files = modules(src)
    known = {tuple(m) for m in files.values()}
    graph = {}
    for path, mod in files.items():
        if not mod:
            continue
        with open(path, encoding="utf-8") as f:
            text = code_of(f.read())
        for kind, name in references(text):
            if kind == "super" and len(mod) == 1:
                kind = "crate"
            if kind == "crate":
                target = [name]
                source = mod[:1]
            else:
                target = mod[:-1] + [name]
                source = mod
            if tuple(target) in known and target != source[: len(target)] and target[: len(source)] != source:
                graph.setdefault("::".join(source), set()).add("::".join(target))
    return graph


def main():
    repo = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    found = 0
    for root, dirs, files in os.walk(repo):
        dirs[:] = [d for d in dirs if d not in ("target", ".git", "node_modules")]
        if "Cargo.toml" in files and os.path.isdir(os.path.join(root, "src")):
            for comp in circles(crate_graph(os.path.join(root, "src"))):
                found += 1
                print(f"{os.path.relpath(root, repo)}: import circle: {' <-> '.join(comp)}")
    print(f"module import circles: {found}")
    sys.exit(1 if found else 0)


if __name__ == "__main__":
    main()
