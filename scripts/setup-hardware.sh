#!/bin/sh
# Installs what the front-end analyses need (ngspice), only when it is missing; safe to re-run.
# Used by the README's test command before `cargo test -p hil --test spice_frontend`.
set -eu
if command -v ngspice >/dev/null 2>&1; then
    echo "ngspice present: $(ngspice --version 2>/dev/null | grep -m1 -o 'ngspice-[0-9]*' || echo unknown)"
    exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
    SUDO="sudo"
fi
$SUDO apt-get update
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y ngspice
ngspice --version | head -n 2
