#!/usr/bin/env bash
# Long recordings (issue #48, item 4): a simulated hour at 1 kHz (twelve presses to 60 N with
# 280 s of rest each, one viscoelastic relaxation concealed) diagnosed by one `tactile diagnose
# REC --json OUT`, timed and its peak resident memory read (`/usr/bin/time -v`), against the goals
# of 15 s and 500 MB; and the same test four times as long (48 presses) against 1 GB. Checks that
# the hour's relaxation is named with tau and fraction within 5 % of what was concealed. The FE
# tables are warmed first (one untimed diagnosis of a short recording). Prints the load average:
# the figures mean little on a busy machine. Exits non-zero when a goal is missed.
#
#   scripts/bench-long.sh [hours...]     # default: 1 4
set -euo pipefail
cd "$(dirname "$0")/.."
hours=("$@")
[ "${#hours[@]}" -gt 0 ] || hours=(1 4)
# As a user runs it: release.
cargo build --release --locked -p tactile --bin tactile
tactile="$PWD/target/release/tactile"
work="$(mktemp -d "${TMPDIR:-/tmp}/tactile-bench-long.XXXXXX")"
trap 'rm -rf "$work"' EXIT
tau_s=4 fraction=0.3

# A test of 12 presses per hour: each press, hold and return ~20 s, then 280 s at rest.
simulate() {
    local presses="$1" out="$2" more=()
    for ((i = 1; i < presses; i++)); do more+=(--then-peak-load 60); done
    "$tactile" simulate --contact-angle 20 --azimuth 60 --rate 1000 --recovery-s 280 \
        --peak-load 60 "${more[@]}" --noise-v 0.002 --noise-load-n 0.02 --seed 7 \
        --effect "viscoelastic_relaxation:tau_s=$tau_s,fraction=$fraction" --out "$out"
}
simulate 1 "$work/warm.csv"
"$tactile" diagnose "$work/warm.csv" --quiet --json "$work/warm.json"

# Wall seconds and peak resident KiB of one diagnosis of $1.
measure() {
    /usr/bin/time -f '%e %M' -o "$1.time" "$tactile" diagnose "$1" --quiet --json "$1.json"
    cat "$1.time"
}
status=0
for h in "${hours[@]}"; do
    rec="$work/h$h.csv"
    simulate $((12 * h)) "$rec"
    rows="$(($(wc -l <"$rec") - 1))"
    mb="$(du -m "$rec" | cut -f1)"
    read -r wall_s peak_kb <<<"$(measure "$rec")"
    rm -f "$rec"
    named="$(python3 - "$rec.json" "$tau_s" "$fraction" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
tau, frac = float(sys.argv[2]), float(sys.argv[3])
e = [e for e in d["effects"] if e["name"] == "viscoelastic_relaxation"]
ok = bool(e) and abs(e[0]["params"]["tau_s"] / tau - 1) < 0.05 \
    and abs(e[0]["params"]["fraction"] / frac - 1) < 0.05
names = ",".join(x["name"] for x in d["effects"]) or "none"
print(("named" if ok else "MISSED") + " (" + names + ")")
EOF
)"
    # The hour has both goals; longer tests the memory's alone, scaled to 1 GB at 4 h.
    awk -v h="$h" -v rows="$rows" -v mb="$mb" -v wall="$wall_s" -v kb="$peak_kb" \
        -v named="$named" -v cores="$(nproc)" -v load="$(cut -d' ' -f1-3 /proc/loadavg)" 'BEGIN {
        peak = kb / 1024
        printf "%g h @ 1 kHz: %d rows, %d MB of CSV; %d cores, load average %s; relaxation %s\n",
            h, rows, mb, cores, load, named
        if (h == 1) {
            printf "  time %.1f s (ratio %.1f/15 = %.2f, goal <= 1); peak %.0f MB (ratio %.0f/500 = %.2f, goal <= 1)\n",
                wall, wall, wall / 15, peak, peak, peak / 500
            exit !(wall <= 15 && peak <= 500 && named ~ /^named/)
        }
        printf "  time %.1f s; peak %.0f MB (ratio %.0f/1024 = %.2f, goal <= 1 at 4 h)\n",
            wall, peak, peak, peak / 1024
        exit !(peak <= 1024)
    }' || status=1
done
exit "$status"
