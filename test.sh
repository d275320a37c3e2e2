#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds everything (host workspace, both
# firmware binaries), runs every test (host, firmware host tests, QEMU, HIL, ngspice).
# Usage: ./test.sh            (CI runs exactly this through .ci/run)
set -euo pipefail
cd "$(dirname "$0")"
start=$(date +%s)

bash scripts/setup.sh

echo "== host workspace: build and test"
cargo build --workspace --all-targets --locked
cargo test --workspace --locked

if [ -x scripts/test-firmware.sh ]; then
    echo "== firmware"
    bash scripts/test-firmware.sh
fi

echo "== all tests passed in $(( $(date +%s) - start )) s"
