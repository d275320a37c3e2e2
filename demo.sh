#!/usr/bin/env bash
# The main demo: installs what is missing, then runs the sensor chain end to end and leaves its
# results in ./out/. Usage: ./demo.sh
set -euo pipefail
cd "$(dirname "$0")"

bash scripts/setup.sh
mkdir -p out

echo "== protocol: a frame stream with damage, decoded"
cargo run -q --release -p protocol --example stream --features std
