#!/usr/bin/env bash
# Installs every Debian package Strandlight needs to build, test, fuzz and view.
# Idempotent: packages already present are skipped by apt; `apt-get update` runs once per call.
set -euo pipefail
PKGS=(
  build-essential pkg-config make
  clang clang-15 libclang-rt-14-dev llvm
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
  libopenexr-dev
  libcjson-dev libstb-dev libembree-dev
  libglfw3-dev libgl-dev libegl-dev libgl1-mesa-dri xvfb xauth libimgui-dev
  slurm-wlm munge parallel
  python3 python3-numpy python3-matplotlib bc
)
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#PKGS[@]} packages already installed"
  exit 0
fi
echo "deps: installing ${missing[*]}"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
