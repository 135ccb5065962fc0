#!/usr/bin/env bash
# Makes the flexslosh Python package (python/flexslosh) importable by this checkout's own Python, and by no other:
# a virtual environment, $VENV (default build/venv), made from $BASE_PYTHON (default /usr/bin/python3) with
# --system-site-packages, so that Debian's petsc4py, mpi4py, h5py and numpy stay visible, holding a flexslosh.pth
# that points at this checkout's python/ folder (like `pip install -e`, without pip, which the environment does not
# need). Nothing outside the checkout is written: two checkouts each import their own package, and
# /usr/bin/python3 is left as it was. Use $VENV/bin/python3 (the Makefile's PYTHON). The package finds libflexslosh
# and its binding _flexslosh_cffi (built by CMake) in build/ beside it, or in $FLEXSLOSH_BUILD. Run by `make build`
# (so by `make demo` and `make test`).
set -euo pipefail
top="$(cd "$(dirname "$0")/.." && pwd)"
base="${BASE_PYTHON:-/usr/bin/python3}"
venv="${VENV:-$top/build/venv}"
if [ ! -x "$venv/bin/python3" ]; then
  # --without-pip: no network, and no ensurepip (Debian's python3-venv package carries it)
  "$base" -m venv --without-pip --system-site-packages "$venv" ||
    { echo "install-python.sh: $base -m venv failed (Debian: apt-get install python3-venv)" >&2; exit 1; }
fi
site="$("$venv/bin/python3" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
mkdir -p "$site"
echo "$top/python" > "$site/flexslosh.pth"
# the environment's package is this checkout's (its .pth comes before any machine-wide one)
"$venv/bin/python3" - "$top/python" <<'PY' || { echo "install-python.sh: $venv/bin/python3 does not import flexslosh from $top/python" >&2; exit 1; }
import os, sys
import flexslosh
sys.exit(not os.path.realpath(flexslosh.__file__).startswith(os.path.realpath(sys.argv[1]) + os.sep))
PY
# an earlier build's machine-wide flexslosh.pth (this script wrote one into the system's site directory before)
for old in $("$base" -c 'import site; print(" ".join(site.getsitepackages()))'); do
  if [ -f "$old/flexslosh.pth" ]; then
    echo "install-python.sh: note: $old/flexslosh.pth (from an earlier build) makes $base import flexslosh from" \
      "$(cat "$old/flexslosh.pth"); builds no longer write or need it (remove it unless something relies on it)" >&2
  fi
done
echo "Python: $venv/bin/python3 imports flexslosh from $top/python"
