#!/usr/bin/env python3
"""No function longer than 80 lines outside tests, in any crate.

clippy's `too_many_lines` counts code lines only (comments and blank lines are free), so a
function of 88 raw lines passed it. This counts raw lines, from the line of `fn` to the line of
its closing brace, for every function with a body in every crate of the repository (the host
workspace, firmware/, fuzz/: every folder with a Cargo.toml), in src/, benches/, examples/ and
build.rs. Test code is left out: the item after a `#[cfg(test)]`, the files of modules
declared `#[cfg(test)] mod name;`, files named tests*.rs, and tests/ folders. Each function over
the limit is printed with its file, line and length, and the script exits 1.

Usage: scripts/check-fn-lines.py [REPO] [--limit N]
       scripts/check-fn-lines.py --self-test   (the checker counts what it should)
"""
import os
import re
import sys
import tempfile

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from rustsrc import IDENT, item_end, blank, split_tests  # noqa: E402

LIMIT = 80
FN = re.compile(r"\bfn\s+(" + IDENT + r")")
SKIP_DIRS = ("target", ".git", "node_modules", "tests")


def functions(code):
    """(name, first line, length in lines) of every function with a body in `code`."""
    found = []
    for m in FN.finditer(code):
        end = item_end(code, m.start())
        if code[m.start():end].rstrip().endswith(";"):
            continue  # a declaration without a body (a trait's, an extern one)
        first = code.count("\n", 0, m.start()) + 1
        last = code.count("\n", 0, end - 1) + 1
        found.append((m.group(1), first, last - first + 1))
    return found


def test_module_files(path, names):
    """The files (and folders) the modules `names` declared in `path` live in."""
    folder, stem = os.path.split(path)
    stem = stem[:-3]
    base = folder if stem in ("mod", "lib", "main") else os.path.join(folder, stem)
    out = set()
    for n in names:
        out |= {os.path.join(base, n + ".rs"), os.path.join(base, n)}
    return out


def crate_files(crate):
    """The crate's non-test source files, each with its code without tests."""
    files, excluded = {}, set()
    roots = [os.path.join(crate, d) for d in ("src", "benches", "examples")]
    for root in roots:
        for folder, dirs, names in os.walk(root):
            dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS)
            for f in sorted(names):
                if f.endswith(".rs") and not f.startswith("tests"):
                    files[os.path.join(folder, f)] = None
    build = os.path.join(crate, "build.rs")
    if os.path.isfile(build):
        files[build] = None
    for path in list(files):
        with open(path, encoding="utf-8") as fh:
            code, test_mods = split_tests(blank(fh.read()))
        files[path] = code
        excluded |= test_module_files(path, test_mods)
    return {
        p: c
        for p, c in files.items()
        if not any(p == e or p.startswith(e + os.sep) for e in excluded)
    }


def check(repo, limit):
    over = []
    for root, dirs, names in os.walk(repo):
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS)
        if "Cargo.toml" not in names:
            continue
        for path, code in sorted(crate_files(root).items()):
            for name, line, length in functions(code):
                if length > limit:
                    over.append((os.path.relpath(path, repo), line, name, length))
    return over


FIXTURE = {
    "src/lib.rs": "mod a;\n#[cfg(test)]\nmod a_tests;\n"
    + "pub fn long() {\n" + "    let _x = 1;\n" * 79 + "}\n"
    + "pub fn short() {\n" + "    // a comment line counts too\n" * 78 + "}\n"
    + "#[cfg(test)]\nmod tests {\n    fn long_test() {\n" + "        let _x = 1;\n" * 90 + "    }\n}\n",
    "src/a.rs": "pub trait T {\n    fn declared(&self);\n}\n"
    + "pub fn with_string() -> &'static str {\n    \"fn not_a_function() {\"\n}\n"
    + "#[cfg(test)]\nfn helper() {\n" + "    let _y = 2;\n" * 90 + "}\n"
    + "pub fn after_tests() {\n" + "\n" * 81 + "}\n",
    "src/a_tests.rs": "fn in_test_file() {\n" + "\n" * 90 + "}\n",
    "tests/it.rs": "fn integration() {\n" + "\n" * 90 + "}\n",
}


def self_test():
    with tempfile.TemporaryDirectory() as tmp:
        crate = os.path.join(tmp, "fixture")
        for name, text in FIXTURE.items():
            path = os.path.join(crate, name)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as fh:
                fh.write(text)
        open(os.path.join(crate, "Cargo.toml"), "w").close()
        got = sorted((name, length) for _, _, name, length in check(tmp, LIMIT))
    expected = [("after_tests", 83), ("long", 81)]
    ok = got == expected
    print(f"self-test {'ok' if ok else 'FAILED'}: found {got}, expected {expected}")
    sys.exit(0 if ok else 1)


def main():
    args = sys.argv[1:]
    if args == ["--self-test"]:
        self_test()
    limit = LIMIT
    if "--limit" in args:
        i = args.index("--limit")
        limit = int(args[i + 1])
        del args[i: i + 2]
    repo = args[0] if args else os.path.join(os.path.dirname(__file__), "..")
    over = check(repo, limit)
    for path, line, name, length in over:
        print(f"{path}:{line}: fn {name} is {length} lines (limit {limit})")
    print(f"functions over {limit} lines outside tests: {len(over)}")
    sys.exit(1 if over else 0)


if __name__ == "__main__":
    main()
