#!/usr/bin/env bash
# Installs what the scripts in scripts/peers need, idempotently:
#   - a virtual environment at <repo>/.venv-peers with pinned mitsuba, numpy and embreex (Embree 4's
#     bindings, for embree_compare.py);
#   - Debian's libllvm19, which Mitsuba's llvm_ad_rgb variant needs (Debian 12's default LLVM 15
#     fails with "LLVM ERROR: Cannot select ... fminimum"). Dr.Jit is pointed at it with
#     DRJIT_LIBLLVM_PATH (compare_mitsuba.py sets it itself).
# Usage: bash scripts/peers/setup.sh        (as root, or with sudo available, for apt-get)
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
VENV="$REPO/.venv-peers"
MITSUBA_VERSION="3.9.1"
NUMPY_VERSION="2.2.6"
EMBREEX_VERSION="4.4.0.post1"
LIBLLVM="/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"

if [ ! -x "$VENV/bin/python" ]; then
    python3 -m venv "$VENV"
fi
if ! "$VENV/bin/python" - <<PY 2>/dev/null
import importlib.metadata as m
assert m.version("mitsuba") == "$MITSUBA_VERSION"
assert m.version("numpy") == "$NUMPY_VERSION"
assert m.version("embreex") == "$EMBREEX_VERSION"
PY
then
    "$VENV/bin/pip" install --quiet "mitsuba==$MITSUBA_VERSION" "numpy==$NUMPY_VERSION" \
        "embreex==$EMBREEX_VERSION"
fi

if [ ! -e "$LIBLLVM" ]; then
    SUDO=""
    if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
    $SUDO apt-get update
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y libllvm19
fi

echo "python: $VENV/bin/python ($("$VENV/bin/python" -c 'import importlib.metadata as m; print(*(f"{p} {m.version(p)}" for p in ("mitsuba", "numpy", "embreex")))'))"
if [ -e "$LIBLLVM" ]; then
    echo "llvm:   export DRJIT_LIBLLVM_PATH=$LIBLLVM"
else
    echo "llvm:   $LIBLLVM missing: only scalar_rgb will work" >&2
fi
