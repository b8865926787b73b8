#!/usr/bin/env bash
# Installs what noether needs to build and test, from Debian 12 packages only.
# Called by both README command lines and by .ci/run; safe to run repeatedly:
# it installs only what is missing. `--sanitize` adds clang and its sanitizer and libFuzzer
# runtimes, for tools/sanitize.sh and tools/fuzz.sh.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config bc ccache
  libeigen3-dev
  libsundials-dev
  libboost-dev libboost-filesystem-dev
  libspdlog-dev libfmt-dev
  libhdf5-dev hdf5-helpers hdf5-tools
  libyaml-cpp-dev
  libcli11-dev
  libgtest-dev libgmock-dev
  libbenchmark-dev
  libnlopt-dev
  libopenmpi-dev openmpi-bin
  python3 python3-dev python3-numpy python3-matplotlib python3-h5py python3-pytest python3-hypothesis
  python3-nbclient python3-ipykernel python3-meshio
  pybind11-dev
  strace
  libjs-three chromium
)
if [ "${1:-}" = "--sanitize" ]; then
  PACKAGES+=(clang-14 libclang-rt-14-dev)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
