#!/usr/bin/env bash
# Installs what the firmware's build and tests need, only where missing (safe to re-run):
#   - the Rust target thumbv7em-none-eabihf (Cortex-M4F), through rustup;
#   - qemu-system-arm (Debian package), for the on-target tests and the QEMU board.
# The real board's runner (probe-rs) is not installed here: CI never flashes hardware.
set -euo pipefail

if ! rustup target list --installed | grep -qx thumbv7em-none-eabihf; then
    rustup target add thumbv7em-none-eabihf
fi

if ! command -v qemu-system-arm >/dev/null 2>&1; then
    if [ "$(id -u)" -eq 0 ]; then
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq qemu-system-arm >/dev/null
    else
        sudo apt-get update -qq
        sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq qemu-system-arm >/dev/null
    fi
fi

# readelf (binutils) measures flash and RAM in bench-firmware.sh; it comes with gcc.
command -v readelf >/dev/null 2>&1 || echo "setup-firmware: readelf not found (install binutils) - bench sizes will fail" >&2
echo "setup-firmware: thumbv7em-none-eabihf and $(qemu-system-arm --version | head -n1) ready"
