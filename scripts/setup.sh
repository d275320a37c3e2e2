#!/usr/bin/env bash
# Install what the demo and the tests need, only where missing. Safe to run again and again.
# Used by ./demo.sh and ./test.sh; works on a bare Debian machine with rustup and root or sudo.
set -euo pipefail
cd "$(dirname "$0")/.."

say() { printf '\033[1m[setup]\033[0m %s\n' "$*"; }

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
        say "need root for: $*"; return 1; fi
}

apt_ready=0
apt_install() {
    local missing=()
    for pkg in "$@"; do
        dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    if [ $apt_ready -eq 0 ]; then
        say "apt-get update"
        as_root apt-get update -qq
        apt_ready=1
    fi
    say "apt-get install ${missing[*]}"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

if ! command -v cargo >/dev/null; then
    say "cargo not found: install Rust with rustup first (https://rustup.rs)"
    exit 1
fi

# rustfmt and clippy check style in the test run; a minimal rustup profile lacks them.
for component in rustfmt clippy; do
    if ! rustup component list --installed | grep -q "^$component"; then
        say "rustup component add $component"
        rustup component add "$component"
    fi
done

# The firmware's target: the Cortex-M4F of the QEMU mps2-an386 and the NUCLEO-F411RE.
if ! rustup target list --installed | grep -qx thumbv7em-none-eabihf; then
    say "rustup target add thumbv7em-none-eabihf"
    rustup target add thumbv7em-none-eabihf
fi

# qemu-system-arm runs the firmware; ngspice simulates the analog front end; pkg-config and
# libudev let serialport enumerate USB devices.
apt_install qemu-system-arm ngspice pkg-config libudev-dev
# Headless Chromium renders the diagnosis report in its browser test
# (diagnosis/tests/report_browser.rs); DejaVu is the font figures measure their labels with.
apt_install chromium fonts-dejavu-core

# The Python package's tests make a virtual environment (scripts/test-python.sh): Debian's
# python3 leaves venv's pip bootstrap (ensurepip) to python3-venv.
if command -v python3 >/dev/null && ! python3 -c "import ensurepip, venv" 2>/dev/null; then
    apt_install python3-venv
fi

# Pieces that need more (each script is idempotent too).
for extra in scripts/setup-*.sh; do
    [ -e "$extra" ] && bash "$extra"
done
say "ready"
