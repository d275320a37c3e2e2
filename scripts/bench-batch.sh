#!/usr/bin/env bash
# A whole session at once (issue #18): [count] (default 20) simulated recordings of ~300 s at
# 1 kHz (three cycles to 60 N, 69 s of recovery each), some with concealed effects, diagnosed by
# one `tactile diagnose DIR --out-dir OUT` against the goal of 60 s for 20; and one of them alone
# against issue #16's goal of 5 s. FE tables are warmed first (one untimed diagnosis), so the
# figures are the diagnosis's, not the FE's. Prints the load average: the figures mean little on
# a busy machine. Exits non-zero when a goal is missed.
set -euo pipefail
cd "$(dirname "$0")/.."
count="${1:-20}"
# As a user runs it: release.
cargo build --release --locked -p tactile --bin tactile
tactile="$PWD/target/release/tactile"
work="$(mktemp -d "${TMPDIR:-/tmp}/tactile-bench-batch.XXXXXX")"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/in"

simulate() {
    local i="$1" effect=()
    case $((i % 4)) in
        0) effect=(--effect "viscoelastic_relaxation:tau_s=$((3 + i % 3)),fraction=0.3") ;;
        1) effect=(--effect highpass_coupling:tau_s=40) ;;
        2) effect=(--effect thermal_drift:amplitude_V=0.02,tau_s=120) ;;
    esac
    "$tactile" simulate --contact-angle 20 --azimuth 60 --rate 1000 --recovery-s 69 \
        --peak-load 60 --then-peak-load 60 --then-peak-load 60 \
        --noise-v 0.002 --noise-load-n 0.02 --seed "$((i + 1))" "${effect[@]}" \
        --out "$(printf '%s/in/rec-%02d.csv' "$work" "$i")"
}
export -f simulate
export tactile work
seq 0 $((count - 1)) | xargs -P "$(nproc)" -I{} bash -c 'simulate {}'
first="$work/in/rec-00.csv"
duration_s="$(tail -n 1 "$first" | cut -d, -f1)"

# Wall and CPU (user + sys) seconds of a command into file $1; its stderr stays on the terminal.
timed() {
    local out="$1"
    shift
    local TIMEFORMAT='%R %U %S'
    { time "$@" 2>&3; } 3>&2 2>"$out"
}
# Warm the FE tables (the disk cache) with one untimed run.
"$tactile" diagnose "$first" --quiet --json "$work/warm.json"
timed "$work/single.t" "$tactile" diagnose "$first" --quiet --json "$work/single.json"
status=0
timed "$work/batch.t" "$tactile" diagnose "$work/in" --quiet --out-dir "$work/out" || status=$?
[ "$status" -eq 0 ] || { echo "bench-batch: the batch failed with exit $status" >&2; exit 1; }

awk -v n="$count" -v d="$duration_s" -v cores="$(nproc)" \
    -v load="$(cut -d' ' -f1-3 /proc/loadavg)" \
    -v single="$(cat "$work/single.t")" -v batch="$(cat "$work/batch.t")" 'BEGIN {
    split(single, s, " "); split(batch, b, " ")
    printf "recordings: %d x %.0f s @ 1 kHz; %d cores, load average %s\n", n, d, cores, load
    printf "single 300 s @ 1 kHz: %.1f s (ratio %.1f/5 = %.2f, goal <= 1); CPU %.1f s\n",
        s[1], s[1], s[1] / 5, s[2] + s[3]
    printf "batch %d x 300 s @ 1 kHz: %.1f s (ratio %.1f/60 = %.2f, goal <= 1); CPU %.1f s, %.1f s on %d idle cores\n",
        n, b[1], b[1], b[1] / 60, b[2] + b[3], (b[2] + b[3]) / cores, cores
    exit !(s[1] <= 5 && b[1] <= 60)
}'
