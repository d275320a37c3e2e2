#!/usr/bin/env bash
# Firmware figures against their goals, as ratios:
#   instructions per sample (QEMU mps2-an386 under -icount shift=0: driver read with SPI CRC
#   check, queue, offset cut, 3 channels x two biquads, framing with CRC-32C and COBS; the
#   emulated ADC's own work measured separately and subtracted), goal 400;
#   flash (vector table, code, read-only data, initialised data) and static RAM (data, bss,
#   uninit; the stack is not static) of both release board binaries, goals 64 KiB and 16 KiB.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/setup-firmware.sh" >/dev/null
cd "$here/../firmware"
cargo build --release --bins 2>&1 | grep -E "^(warning|error)" || true

echo "== instructions per sample (qemu-bench, -icount shift=0)"
timeout 300 qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -display none -monitor none \
    -serial null -semihosting-config enable=on,target=native -icount shift=0 \
    -kernel target/thumbv7em-none-eabihf/release/qemu-bench

echo "== flash and static RAM of the release binaries"
for bin in qemu-mps2-an386 nucleo-f411re; do
    readelf -S -W "target/thumbv7em-none-eabihf/release/$bin" | python3 -c '
import re, sys
bin = sys.argv[1]
sizes = {}
for line in sys.stdin:
    m = re.match(r"\s*\[\s*\d+\]\s+(\S+)\s+\S+\s+[0-9a-f]+\s+[0-9a-f]+\s+([0-9a-f]+)", line)
    if m:
        sizes[m.group(1)] = int(m.group(2), 16)
flash = sum(sizes.get(s, 0) for s in (".vector_table", ".text", ".rodata", ".data", ".gnu.sgstubs"))
ram = sum(sizes.get(s, 0) for s in (".data", ".bss", ".uninit"))
print(f"{bin:16} flash {flash:7d} B = {flash/1024:6.1f} KiB (goal 64 KiB, ratio {flash/65536:.3f})   "
      f"static RAM {ram:6d} B = {ram/1024:5.1f} KiB (goal 16 KiB, ratio {ram/16384:.3f})")
' "$bin"
done
