#!/usr/bin/env bash
# The firmware's checks and tests: style first (rustfmt; clippy on the host build of the library,
# its tests and the binaries' host stubs, and on the thumb release binaries as they are built
# below; rustdoc; warnings are errors), then host unit tests of the library (drivers, DSP, offset
# cut, framing, commands, against mocks and the sim's emulated ADC), both release board binaries
# built, the on-target self-test under QEMU mps2-an386 (FPU DSP, queue under interrupt pressure,
# semihosting exit code), and the QEMU board binary's byte stream decoded by the host.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/setup-firmware.sh"
cd "$here/../firmware"

host="$(rustc -vV | sed -n "s/^host: //p")"
echo "== firmware style: rustfmt, clippy (host and thumb), rustdoc; warnings are errors"
cargo fmt --all -- --check
cargo clippy --all-targets --target "$host" -- -D warnings
cargo clippy --release --bins -- -D warnings
# --release: the dependencies were just checked for the release profile by clippy above.
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --release

echo "== firmware host tests"
cargo test --target "$host"

echo "== release binaries (qemu-mps2-an386, nucleo-f411re, qemu-selftest, qemu-bench)"
cargo build --release --bins

echo "== on-target self-test under QEMU mps2-an386"
timeout 300 qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -display none -monitor none \
    -serial null -semihosting-config enable=on,target=native -icount shift=0 \
    -kernel target/thumbv7em-none-eabihf/release/qemu-selftest

echo "== QEMU board binary streaming to the host"
cargo test --target "$host" --test qemu_stream -- --ignored
