#!/bin/sh
# Installs every build and test dependency of qex from Debian packages.
# Non-interactive: safe for CI (no terminal, no stdin). Needs root (or sudo).
set -eu
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
PKGS="build-essential cmake ninja-build python3 \
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev \
  libopenmesh-dev \
  libgtest-dev libgmock-dev librapidcheck-dev libbenchmark-dev \
  libcli11-dev nlohmann-json3-dev libfast-float-dev \
  clang libclang-rt-dev clang-19 libclang-rt-19-dev \
  libeigen3-dev python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest \
  python3-dask python3-distributed \
  python3-venv python3-pip python3-setuptools python3-wheel python3-build python3-mypy \
  librsvg2-bin"
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  $SUDO apt-get update
  $SUDO apt-get install -y --no-install-recommends $missing
fi
