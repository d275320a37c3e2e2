#!/usr/bin/env bash
# HIL 2 end to end, as a user would run it: the firmware's QEMU board binary in
# qemu-system-arm -machine mps2-an386 with UART0 on a pty, `tactile log` recording it live (it
# sets the rate and starts the stream: commands over the same link), then `tactile plot`.
# Leaves out/hil-qemu.csv (recording-v1), out/hil-qemu-time.png/.svg and out/hil-qemu-qemu.log.
# Usage: scripts/demo-hil.sh [seconds]      (called by ./demo.sh; needs scripts/setup.sh first)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-6}"
mkdir -p out
say() { printf '\033[1m[demo-hil]\033[0m %s\n' "$*"; }

say "build the QEMU firmware and the tactile CLI"
(cd firmware && cargo build -q --release --bin qemu-mps2-an386)
cargo build -q -p tactile --bin tactile
elf=firmware/target/thumbv7em-none-eabihf/release/qemu-mps2-an386
tactile=target/debug/tactile

# shellcheck source=scripts/demo-qemu.sh
. scripts/demo-qemu.sh
qemu_start "$elf" out/hil-qemu-qemu.log
say "QEMU running, UART0 on $qemu_pty"
say "recording ${seconds} s with tactile log (rate 1000 Hz set by command)"
"$tactile" log --port "$qemu_pty" --duration "$seconds" --rate 1000 --no-mcap -q -o out/hil-qemu.csv
qemu_stop
"$tactile" plot out/hil-qemu.csv -o out/hil-qemu
rows=$(grep -cv '^#' out/hil-qemu.csv || true)
say "out/hil-qemu.csv: $((rows - 1)) samples; plots: out/hil-qemu-time.png, out/hil-qemu-time.svg"
