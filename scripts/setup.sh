#!/usr/bin/env bash
# Installs every Debian package pnf needs to build, test and benchmark. Idempotent: packages
# already present are left alone, so a second run is quick and changes nothing.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  libeigen3-dev libflann-dev liblz4-dev liblzf-dev libsleef-dev
  googletest libgtest-dev
  libcli11-dev libpng-dev
  clang libclang-rt-14-dev libomp-dev
  python3-matplotlib
  pybind11-dev python3-dev python3-venv
  libopenmpi-dev openmpi-bin
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
