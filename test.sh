#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds everything (host workspace, both
# firmware binaries), runs every test (host, firmware host tests, QEMU, HIL, ngspice).
# Usage: ./test.sh            (CI runs exactly this through .ci/run)
set -euo pipefail
cd "$(dirname "$0")"
start=$(date +%s)

bash scripts/setup.sh

# The firmware first: it builds the QEMU binary that the host workspace's HIL test runs.
echo "== firmware: host tests, release binaries, QEMU on-target tests"
bash scripts/test-firmware.sh

echo "== host workspace: build and test (protocol, hardware, chip, fingertip, sim, host, HIL)"
cargo build --workspace --all-targets --locked
cargo test --workspace --locked

echo "== all tests passed in $(( $(date +%s) - start )) s"
