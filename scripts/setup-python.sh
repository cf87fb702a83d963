#!/usr/bin/env bash
# Creates the virtual environment .venv at the repository root and installs the pinned
# packages that scripts/report_tables.py and scripts/sampler_convergence.py need.
# Idempotent: reruns reuse .venv and only install what is missing or at another version.
#
#   bash scripts/setup-python.sh
#   .venv/bin/python scripts/report_tables.py --help
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$repo/.venv"
python="${PYTHON:-python3}"

# numpy: the error measurements; pillow: reading PNGs and drawing the contact sheet;
# matplotlib: the convergence chart; OpenEXR: reading foton's linear .exr output
# (Pillow cannot read EXR).
packages=(
    "numpy==2.4.6"
    "pillow==13.0.0"
    "matplotlib==3.11.2"
    "OpenEXR==3.5.3"
)

if ! "$python" -c 'import sys; sys.exit(sys.version_info < (3, 11))'; then
    echo "error: $python is older than Python 3.11; set PYTHON=/path/to/python3.11" >&2
    exit 1
fi

if [ ! -x "$venv/bin/python" ]; then
    "$python" -m venv "$venv"
fi

if "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "${packages[@]}"; then
    echo "Python environment ready: $venv (${packages[*]})"
else
    echo "error: installing ${packages[*]} into $venv failed" >&2
    exit 1
fi
