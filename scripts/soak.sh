#!/usr/bin/env bash
# The soak: HIL 1's board -> pty -> `tactile log` for [minutes] (default 10) at the
# highest lossless rate (TACTILE_SOAK_RATE_HZ overrides it), printing samples, frames, losses,
# CRC errors, the logger's RSS every minute and the throughput; fails on any loss or on memory
# growth beyond the stated limit (hil/tests/soak_native.rs, docs/hil.md).
set -euo pipefail
cd "$(dirname "$0")/.."
minutes="${1:-10}"
target="${CARGO_TARGET_DIR:-$PWD/target}"
# The logger as the tests build it (the test profile: host optimised, see Cargo.toml).
cargo build --profile test -p tactile --bin tactile
TACTILE_SOAK_MINUTES="$minutes" TACTILE_BIN="$target/debug/tactile" \
    cargo test -p hil --test soak_native -- --ignored --nocapture
