#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds everything (host workspace, both
# firmware binaries), runs every test (host, firmware host tests, QEMU, HIL, ngspice, the main
# demo's chain, the Python package).
# Style is checked first: rustfmt, clippy (functions over 80 lines included, clippy.toml) and
# rustdoc, with warnings as errors, for both workspaces.
# Usage: ./test.sh            (CI runs exactly this through .ci/run)
set -euo pipefail
cd "$(dirname "$0")"
start=$(date +%s)
# A one-off build gains nothing from incremental state; it only costs disk (gigabytes here).
export CARGO_INCREMENTAL=0

bash scripts/setup.sh

# The firmware first: it builds the QEMU binary that the host workspace's HIL test runs.
echo "== firmware: host tests, release binaries, QEMU on-target tests"
bash scripts/test-firmware.sh

echo "== structure: no import circle between the modules of any crate"
# The checker's own fixtures first (a circle behind a test module's declaration among them).
python3 scripts/check-module-cycles.py --self-test
python3 scripts/check-module-cycles.py
echo "== structure: no function over 80 raw lines outside tests, in any crate"
# clippy's too_many_lines (below) counts code lines only: comments and blank lines are free.
python3 scripts/check-fn-lines.py --self-test
python3 scripts/check-fn-lines.py
# The driver library stays free of the command line's crates: the HIL tests and the fuzz
# targets link host alone.
for tree in "cargo tree -p hil -e normal,build --locked" "cargo tree --manifest-path fuzz/Cargo.toml -e normal,build --locked"; do
    if $tree | grep -qE ' (clap|ratatui|crossterm) v'; then
        echo "$tree: links clap, ratatui or crossterm"; exit 1
    fi
done

# Every crate root asks clippy for the length limit, so a new crate cannot skip it.
for root in */src/lib.rs */src/main.rs */src/bin/*.rs; do
    grep -q 'warn(clippy::too_many_lines)' "$root" ||
        { echo "$root: lacks #![cfg_attr(not(test), warn(clippy::too_many_lines))]"; exit 1; }
done

echo "== host workspace: style (rustfmt, clippy, rustdoc), warnings are errors"
cargo fmt --all -- --check
# Functions outside tests stay under 80 lines (clippy.toml): each crate root switches
# `clippy::too_many_lines` on outside `cfg(test)`, so one pass checks it.
cargo clippy --workspace --all-targets --locked -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --locked

echo "== host workspace: build and test (protocol, hardware, chip, fingertip, sim, host, HIL)"
# `cargo test` builds every target it runs; the benches are type-checked by clippy above and
# built by their own commands (a separate `cargo build --all-targets` only linked them twice).
cargo test --workspace --locked

echo "== the main demo's chain (./demo.sh), checked against what it conceals"
# The README's first command: emulated sensor -> firmware under QEMU -> serial -> tactile log ->
# tactile diagnose, on the builds made above. Its rows were once timed by the host clock while
# QEMU's virtual clock ran the test 25 times faster, and nothing here ran it to see.
TACTILE_DEMO_CHECK=1 TACTILE_DEMO_PROFILE=debug TACTILE_DEMO_OUT=target/demo-check \
    bash scripts/demo-chain.sh

echo "== Python package: wheel (pip install ./python), pytest against the binary, the example"
bash scripts/test-python.sh

echo "== all tests passed in $(( $(date +%s) - start )) s"
