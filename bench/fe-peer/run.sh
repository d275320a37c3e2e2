#!/usr/bin/env bash
# Peer cross-check of the fingertip FE model against scikit-fem + gmsh.
# Creates bench/fe-peer/.venv with scikit-fem, gmsh, scipy (PyPI) if missing, checks that the
# gmsh wheel can load (it needs libGLU / libXcursor / libXinerama / libXft on Debian: installed
# with apt-get when missing and running as root), then runs the Rust bench's peer section,
# which prints both curves, their difference and the wall-time ratio.
#   bench/fe-peer/run.sh            # peer comparison only
#   bench/fe-peer/run.sh all        # also the curve / haptic benchmarks
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$here/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import skfem, gmsh, scipy" 2>/dev/null; then
    "$venv/bin/pip" install --quiet scikit-fem gmsh scipy numpy || true
fi
if ! "$venv/bin/python" -c "import gmsh" 2>/dev/null; then
    if [ "$(id -u)" = 0 ]; then
        apt-get install -y --no-install-recommends libglu1-mesa libxcursor1 libxinerama1 libxft2 libxrender1 >/dev/null
    fi
    "$venv/bin/python" -c "import gmsh" || { echo "gmsh cannot load (missing shared libraries?)" >&2; exit 69; }
fi
cd "$root"
if [ "${1:-}" = all ]; then
    exec cargo bench -p fingertip --bench fe_bench
fi
exec cargo bench -p fingertip --bench fe_bench -- peer
