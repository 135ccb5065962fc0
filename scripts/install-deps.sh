#!/usr/bin/env bash
# Installs the Debian bookworm packages flexslosh needs, if any is missing (needs root or sudo).
# python3-pil: the movie as GIF (python3 -m flexslosh.plot movie) where ffmpeg is not installed.
# python3-venv: the checkout's own Python environment, build/venv (scripts/install-python.sh).
# python3-pytest-xdist: make test runs the Python tests in JOBS (2) processes at once (pytest -n).
set -euo pipefail
pkgs=(petsc-dev slepc-dev python3-petsc4py python3-slepc4py python3-mpi4py libhdf5-openmpi-dev
      python3-h5py-mpi python3-pytest python3-numpy python3-matplotlib python3-pil cmake make gcc pkg-config
      openmpi-bin libpng-dev libjson-c-dev python3-cffi python3-dev clang-format python3-venv
      python3-pytest-xdist)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "flexslosh: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
