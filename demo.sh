#!/usr/bin/env bash
# The main demo: installs what is missing, then runs the sensor chain end to end and leaves its
# results in ./out/:
#   1. hardware in the loop: the firmware under QEMU (mps2-an386) reads the emulated ADS131M04,
#      streams frames over a pty; `tactile log` records them, `tactile plot` plots them;
#   2. the diagnosis: a compression test simulated with the two effects the original paper saw
#      (gel relaxation and AC-coupled offset cut), diagnosed blind, with an HTML report.
# Usage: ./demo.sh
set -euo pipefail
cd "$(dirname "$0")"

bash scripts/setup.sh
mkdir -p out
say() { printf '\033[1m[demo]\033[0m %s\n' "$*"; }

say "1/2 emulated sensor -> firmware (QEMU) -> serial (pty) -> tactile log -> recording + plot"
bash scripts/demo-hil.sh 6

say "2/2 compression test with concealed effects -> tactile diagnose -> report"
cargo build -q --release -p host --bin tactile
tactile=target/release/tactile
"$tactile" simulate --contact-angle 20 --azimuth 60 --peak-load 60 --then-peak-load 60 \
    --noise-v 0.002 --noise-load-n 0.02 --seed 7 \
    --effect viscoelastic_relaxation:tau_s=4,fraction=0.3 \
    --effect highpass_coupling:tau_s=25 \
    --out out/compression.csv
"$tactile" diagnose out/compression.csv --json out/diagnosis.json --report out/report
python3 - <<'PY'
import json
d = json.load(open("out/diagnosis.json"))
print(f"verdict: {d['verdict']}")
for e in d["effects"]:
    params = ", ".join(f"{k} = {v:.3g}" for k, v in e["params"].items())
    print(f"  effect {e['name']}: {params}")
    print(f"    {e['evidence']}")
h = d["fit"]["heldout"]
print(f"held-out RMSE {h['rmse_before']:.4f} -> {h['rmse_after']:.4f} "
      f"({h['t_start_s']:.0f}-{h['t_end_s']:.0f} s, not fitted)")
PY
say "results: out/hil-qemu.csv, out/hil-qemu-time.png, out/compression.csv, out/diagnosis.json, out/report/index.html"
