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
cargo build -q -p host --bin tactile
elf=firmware/target/thumbv7em-none-eabihf/release/qemu-mps2-an386
tactile=target/debug/tactile

work="$(mktemp -d)"
qemu_pid=""
cleanup() {
    # Quit through the monitor, then make sure: no QEMU outlives the demo.
    if [ -n "$qemu_pid" ] && kill -0 "$qemu_pid" 2>/dev/null; then
        echo quit >&4 2>/dev/null || true
        sleep 0.3
        kill "$qemu_pid" 2>/dev/null || true
        wait "$qemu_pid" 2>/dev/null || true
    fi
    exec 3>&- 4>&- 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT INT TERM

# The monitor reads a fifo we hold open; QEMU starts halted (-S) because QEMU 7.2 drops pty
# output until someone has the slave open.
mkfifo "$work/monitor"
qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic -S \
    -serial pty -monitor stdio -kernel "$elf" \
    <"$work/monitor" >out/hil-qemu-qemu.log 2>&1 &
qemu_pid=$!
exec 4>"$work/monitor"
pty=""
for _ in $(seq 100); do
    pty="$(grep -o '/dev/pts/[0-9]*' out/hil-qemu-qemu.log | head -n1 || true)"
    [ -n "$pty" ] && break
    sleep 0.1
done
[ -n "$pty" ] || { say "QEMU did not name its pty (see out/hil-qemu-qemu.log)"; exit 1; }
say "QEMU halted, UART0 on $pty"

exec 3<>"$pty"          # hold the slave open (never read) so no output is lost
echo cont >&4
say "recording ${seconds} s with tactile log (rate 1000 Hz set by command)"
"$tactile" log --port "$pty" --duration "$seconds" --rate 1000 --no-mcap -q -o out/hil-qemu.csv
exec 3>&-
"$tactile" plot out/hil-qemu.csv -o out/hil-qemu
rows=$(grep -cv '^#' out/hil-qemu.csv || true)
say "out/hil-qemu.csv: $((rows - 1)) samples; plots: out/hil-qemu-time.png, out/hil-qemu-time.svg"
