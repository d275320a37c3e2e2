#!/usr/bin/env bash
# A whole hand at once. First a simulated hour on a virtual clock (16 crystals within ±100 ppm,
# a jittered link, a reconnect): prints `worst misalignment` between any two fingers (goal < 1 ms).
# Then [sensors] (default 16) emulated fingertips at 1 kHz on their own ptys into
# one `tactile log --live` for [seconds] (default 60); prints the logger's share of one core
# against the 5 % goal, the samples lost (goal 0) and its resident memory, with the load average
# (hil/benches/hand.rs, docs/hil.md). Exits non-zero when a goal is missed.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
sensors="${2:-16}"
# The logger as a user runs it: release, the same profile as the bench.
cargo build --release -p tactile --bin tactile
TACTILE_HAND_SECONDS="$seconds" TACTILE_HAND_SENSORS="$sensors" \
    cargo bench -p hil --bench hand
