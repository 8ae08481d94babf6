#!/usr/bin/env bash
# One-step set-up on Debian 12 (run as root, or with sudo available for apt).
#  1. Debian packages: DOLFINx 0.5.2, gmsh 4.8 (Python bindings + binary), venv, MPI bindings.
#  2. .venv from the *system* Python with --system-site-packages, so DOLFINx/gmsh are visible.
#  3. pip dependencies pinned to what works with DOLFINx 0.5.2, and this project (editable).
# Re-running when everything is present takes a second or two and changes nothing:
# apt is skipped when dpkg already has every package, pip when the stamp matches pyproject.toml.
set -euo pipefail
cd "$(dirname "$0")/.."

APT_PACKAGES="python3-dolfinx python3-gmsh gmsh python3-venv python3-mpi4py python3-dev"
SYS_PY=/usr/bin/python3
VENV=.venv

missing=""
for p in $APT_PACKAGES; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing="$missing $p"
  fi
done
if [ -n "$missing" ]; then
  echo "[setup] installing Debian packages:$missing"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq $missing
fi

if [ ! -x "$VENV/bin/python" ]; then
  echo "[setup] creating $VENV from $SYS_PY (--system-site-packages)"
  "$SYS_PY" -m venv --system-site-packages "$VENV"
fi

stamp="$VENV/.setup-stamp"
want="$(sha256sum pyproject.toml scripts/setup.sh | sha256sum | cut -d' ' -f1)"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
  echo "[setup] installing pip dependencies and the project (editable)"
  "$VENV/bin/python" -m pip install -q --upgrade "pip>=23" 
  # numpy<2: DOLFINx 0.5.2 is built against numpy 1.x.  numba>=0.59: Debian's 0.56 is too old.
  "$VENV/bin/python" -m pip install -q -e ".[test]"
  echo "$want" > "$stamp"
fi
"$VENV/bin/python" - <<'PY'
import numpy, numba
assert numpy.__version__.split(".")[0] == "1", numpy.__version__
PY
