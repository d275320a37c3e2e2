#!/usr/bin/env python3
"""No import circle between the modules of any crate.

For every crate of the repository (a folder with Cargo.toml and src/), read each module's paths
into its own crate outside its tests: `use` trees (`use crate::{a, b::{c, d}}`, `use super::*`)
and inline paths (`crate::a::b::f()`, `super::super::x`) alike. Each path is resolved to the
deepest module it names, and a reference from module S to module T is an edge between the two
siblings under their common parent that contain S and T (`a::b::c` reading `a::d::e` is the edge
`a::b` -> `a::d`). A strongly connected component of more than one module is a circle; each is
printed and the script exits 1. A parent that declares its children and a child that reads its
parent's items are not a circle (that is how Rust nests modules).

Test code is left out, and only test code: the item after a `#[cfg(test)]` (a `mod tests { ... }`
block, a function, a `use`), the files of modules declared `#[cfg(test)] mod name;`, and files
named tests*.rs. Everything else of a file is read, before and after any `#[cfg(test)]`.

Written out because no packaged tool checks module-level cycles.
Usage: scripts/check-module-cycles.py [REPO]
       scripts/check-module-cycles.py --self-test   (the checker finds the circles it should)
"""
import os
import re
import sys
import tempfile

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from rustsrc import IDENT, blank, split_tests

PATH = re.compile(r"(?<![A-Za-z0-9_:])((?:crate|super|self)(?:\s*::\s*" + IDENT + r")+)")


def use_paths(tree, prefix=()):
    """The full paths of a `use` tree (`crate::{a, b::{c, d}}` -> crate::a, crate::b::c, ...)."""
    tree = tree.strip()
    if not tree:
        return []
    depth, parts, last = 0, [], 0
    for i, c in enumerate(tree):
        depth += {"{": 1, "}": -1}.get(c, 0)
        if c == "," and depth == 0:
            parts.append(tree[last:i])
            last = i + 1
    parts.append(tree[last:])
    if len(parts) > 1:
        return [p for part in parts for p in use_paths(part, prefix)]
    brace = tree.find("{")
    if brace >= 0:
        head = [s.strip() for s in tree[:brace].split("::") if s.strip()]
        inner = tree[brace + 1: tree.rfind("}")]
        return use_paths(inner, prefix + tuple(head))
    tree = re.sub(r"\s+as\s+" + IDENT + r"\s*$", "", tree)
    segs = [s.strip() for s in tree.split("::") if s.strip() and s.strip() != "*"]
    if segs == ["self"] and prefix:
        segs = []
    return [prefix + tuple(segs)]


def references(code):
    """Every path into the crate that `code` names, as tuples of segments."""
    paths = set()
    for m in re.finditer(r"\buse\s+([^;]*);", code):
        for p in use_paths(m.group(1)):
            if p and p[0] in ("crate", "super", "self"):
                paths.add(p)
    for m in PATH.finditer(code):
        paths.add(tuple(s.strip() for s in m.group(1).split("::")))
    return paths


def resolve(path, mod, known):
    """The deepest module of `known` that `path`, read in module `mod`, names (or None)."""
    at, rest = list(mod), list(path)
    if rest[0] == "crate":
        at, rest = [], rest[1:]
    else:
        while rest and rest[0] in ("super", "self"):
            if rest[0] == "super":
                if not at:
                    return None
                at = at[:-1]
            rest = rest[1:]
    for seg in rest:
        if tuple(at + [seg]) in known:
            at.append(seg)
        else:
            break
    return at


def module_path(src, path):
    parts = os.path.relpath(path, src)[:-3].split(os.sep)
    if parts[0] == "bin":
        return None
    if parts[-1] == "mod":
        parts = parts[:-1]
    if parts in (["lib"], ["main"]):
        parts = []
    return parts


def modules(src):
    """Map each non-test source file to (module path, its code without tests)."""
    found, test_mods = {}, set()
    for root, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs") or f.startswith("tests"):
                continue
            path = os.path.join(root, f)
            mod = module_path(src, path)
            if mod is None:
                continue
            with open(path, encoding="utf-8") as fh:
                code, tests = split_tests(blank(fh.read()))
            found[path] = (mod, code)
            test_mods |= {tuple(mod + [t]) for t in tests}
    return {
        p: v for p, v in found.items() if not any(tuple(v[0][: len(t)]) == t for t in test_mods)
    }


def crate_graph(src):
    """Edges between sibling modules, keyed by their `::`-joined paths."""
    files = modules(src)
    known = {tuple(m) for m, _ in files.values()}
    graph = {}
    for mod, code in files.values():
        for path in references(code):
            target = resolve(path, mod, known)
            if target is None:
                continue
            common = 0
            while common < min(len(mod), len(target)) and mod[common] == target[common]:
                common += 1
            if common in (len(mod), len(target)):
                continue  # the module itself, an ancestor or a descendant
            a, b = mod[: common + 1], target[: common + 1]
            graph.setdefault("::".join(a), set()).add("::".join(b))
    return graph


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


def check(repo):
    found = []
    for root, dirs, files in os.walk(repo):
        dirs[:] = sorted(d for d in dirs if d not in ("target", ".git", "node_modules"))
        if "Cargo.toml" in files and os.path.isdir(os.path.join(root, "src")):
            for comp in circles(crate_graph(os.path.join(root, "src"))):
                found.append(f"{os.path.relpath(root, repo)}: import circle: {' <-> '.join(comp)}")
    return found


# Each fixture: files of a crate's src/, and the circles the checker must report.
FIXTURES = [
    (
        "a test module declared before code that reads a sibling (terms/mod.rs once)",
        {
            "lib.rs": "mod a;\nmod b;\n",
            "a/mod.rs": "#[cfg(test)]\nmod tests;\n\npub struct X(pub Vec<crate::b::Y>);\n",
            "a/tests.rs": "",
            "b.rs": "use crate::a::X;\npub struct Y;\npub fn f(_: X) {}\n",
        },
        ["a <-> b"],
    ),
    (
        "a reference only from tests is not a circle",
        {
            "lib.rs": "mod a;\nmod b;\n",
            "a.rs": "pub struct X;\n#[cfg(test)]\nmod tests {\n    use crate::b::Y;\n}\npub fn g() {}\n",
            "b.rs": "use crate::a::X;\npub struct Y;\n#[cfg(test)]\nuse crate::a::g;\n",
            "c.rs": "#[cfg(test)]\nmod c_tests;\n",
            "c/c_tests.rs": "use crate::b::Y;\n",
        },
        [],
    ),
    (
        "siblings in a folder through inline paths and nested use trees",
        {
            "lib.rs": "mod f;\n",
            "f/mod.rs": "mod x;\nmod y;\nmod z;\n",
            "f/x.rs": "pub fn w() -> crate::f::y::Z { todo!() }\n",
            "f/y.rs": "use super::{z, x::{w as _}};\npub struct Z;\n",
            "f/z.rs": "pub fn s() -> &'static str { \"crate::f::x\" } // crate::f::y\nconst Q: char = '\"';\n",
        },
        ["f::x <-> f::y"],
    ),
]


def self_test():
    failed = 0
    for what, files, expected in FIXTURES:
        with tempfile.TemporaryDirectory() as tmp:
            for name, text in files.items():
                path = os.path.join(tmp, "fixture", "src", name)
                os.makedirs(os.path.dirname(path), exist_ok=True)
                with open(path, "w", encoding="utf-8") as fh:
                    fh.write(text)
            with open(os.path.join(tmp, "fixture", "Cargo.toml"), "w") as fh:
                fh.write("")
            got = [c.split("import circle: ")[1] for c in check(tmp)]
        ok = got == expected
        failed += not ok
        print(f"{'ok' if ok else 'FAILED'}: {what}: found {got}, expected {expected}")
    print(f"self-test: {len(FIXTURES) - failed} of {len(FIXTURES)} fixtures as expected")
    sys.exit(1 if failed else 0)


def main():
    if sys.argv[1:] == ["--self-test"]:
        self_test()
    repo = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    found = check(repo)
    for line in found:
        print(line)
    print(f"module import circles: {len(found)}")
    sys.exit(1 if found else 0)


if __name__ == "__main__":
    main()
