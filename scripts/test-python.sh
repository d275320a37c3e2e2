#!/usr/bin/env bash
# The Python package (python/): a virtual environment in target/py-venv (made once, reused),
# the tools it needs from pip where missing, the wheel built and installed with
# `pip install ./python` (maturin; the dev profile here), then its pytest suite against the
# `tactile` binary and the example. Usage: bash scripts/test-python.sh
set -euo pipefail
cd "$(dirname "$0")/.."

say() { printf '\033[1m[python]\033[0m %s\n' "$*"; }

venv=target/py-venv
if [ ! -x "$venv/bin/python" ]; then
    say "python3 -m venv $venv"
    python3 -m venv "$venv"
fi
py="$venv/bin/python"
# The interpreter a user's plain `pip install ./python` goes to (before the venv shadows it).
user_python="$(command -v python3)"
# maturin's build backend runs the `maturin` found on PATH: the venv's.
export PATH="$PWD/$venv/bin:$PATH"

# Each tool only when it cannot be imported yet: a warm run needs no network.
missing=()
for pkg in maturin pandas pytest matplotlib numpy; do
    "$py" -c "import $pkg" 2>/dev/null || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
    say "pip install ${missing[*]}"
    "$py" -m pip install --quiet "${missing[@]}"
fi

say "pip install ./python (dev profile)"
# --no-build-isolation: build with the venv's maturin rather than fetch one per build. The dev
# profile reuses what `cargo build --workspace` just built (a release build of every dependency
# would add minutes to CI); users' `pip install ./python` stays release.
MATURIN_PEP517_ARGS="--profile dev" \
    "$py" -m pip install --quiet --no-build-isolation --force-reinstall --no-deps ./python

say "pytest python/tests"
"$py" -m pytest -q python/tests

say "example: python/examples/diagnose.py"
"$py" python/examples/diagnose.py --png target/py-example-diagnosis.png

# Outside the test venv, a user's `pip install ./python && python python/examples/diagnose.py`
# uses the default interpreter: pip brings the package's own dependencies (numpy, pandas), and
# the example's plotting library is installed here, once. An interpreter that refuses pip
# installs (PEP 668) only gets a note: the user's venv is then theirs to set up.
if ! "$user_python" -c "import matplotlib" 2>/dev/null; then
    say "$user_python -m pip install matplotlib (for the example outside the venv)"
    "$user_python" -m pip install --quiet matplotlib ||
        say "could not install matplotlib for python3: install it to run the example outside target/py-venv"
fi
