#!/usr/bin/env bash
# Regenerate the diagnosis README's example report: a two-cycle recording with viscoelastic
# relaxation, AC coupling and a warm-up drift, diagnosed blind; writes diagnosis/example/out.json
# and the screenshot diagnosis/report-example.png (headless Chromium, from scripts/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --locked -p tactile
tactile=target/release/tactile
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$tactile" simulate --contact-angle 20 --azimuth 60 --peak-load 60 --then-peak-load 40 \
    --noise-v 0.002 --noise-load-n 0.02 \
    --effect viscoelastic_relaxation:tau_s=4,fraction=0.3 --effect highpass_coupling:tau_s=40 \
    --effect thermal_drift:amplitude_V=0.03,tau_s=60 --out "$work/rec.csv"
"$tactile" diagnose "$work/rec.csv" --json "$work/out.json" --report "$work/report.html" --quiet
# The JSON names the recording by its path; the example names it as the README's command does.
sed "s|$work/rec.csv|rec.csv|" "$work/out.json" > diagnosis/example/out.json
sed -i "s|$work/rec.csv|rec.csv|g" "$work/report.html"
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$work/profile" --hide-scrollbars --window-size=1100,2300 \
    --screenshot="$PWD/diagnosis/report-example.png" "file://$work/report.html" 2>/dev/null
ls -l diagnosis/report-example.png diagnosis/example/out.json
