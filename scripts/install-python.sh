#!/usr/bin/env bash
# Makes the flexslosh Python package (python/flexslosh) importable by /usr/bin/python3: a .pth file
# in the system's site directory that points at this checkout's python/ folder (like `pip install -e`,
# without pip, which Debian's Python leaves out; pyproject.toml describes the package). The package
# finds libflexslosh and its binding _flexslosh_cffi (built by CMake) in build/ beside it, or in
# $FLEXSLOSH_BUILD. Run by `make build` (so by `make demo` and `make test`).
set -euo pipefail
top="$(cd "$(dirname "$0")/.." && pwd)"
py="${PYTHON:-/usr/bin/python3}"
site="$("$py" -c 'import site, sys; p=[d for d in site.getsitepackages() if d.startswith("/usr/local/")]; print(p[0] if p else site.getsitepackages()[0])')"
SUDO=""
if [ "$(id -u)" != 0 ] && [ ! -w "$site" ]; then SUDO=sudo; fi
$SUDO mkdir -p "$site"
echo "$top/python" | $SUDO tee "$site/flexslosh.pth" > /dev/null
"$py" -c "import flexslosh" || { echo "install-python.sh: $py cannot import flexslosh from $top/python" >&2; exit 1; }
