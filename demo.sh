#!/usr/bin/env bash
# The main demo: installs what is missing, then runs the sensor chain once, end to end, and leaves
# its results in ./out/ (scripts/demo-chain.sh):
#   emulated sensor (a 2 x 60 N compression test with gel relaxation and an AC-coupled offset cut,
#   concealed) -> firmware under QEMU (mps2-an386, its real ADC driver, auto-null and framing,
#   the sensor's volts fed to the emulated ADS131M04 through semihosting) -> serial (pty) ->
#   `tactile log` (+ the test machine's rod/load) -> `tactile diagnose` -> report.
# Ends non-zero, naming the stage, if any stage fails; leaves no QEMU behind.
# Usage: ./demo.sh
set -euo pipefail
cd "$(dirname "$0")"

bash scripts/setup.sh
started=$SECONDS
bash scripts/demo-chain.sh
printf '\033[1m[demo]\033[0m chain done in %d s; results: out/compression.csv (recording), out/diagnosis.json, out/report.html\n' \
    $((SECONDS - started))
