#!/usr/bin/env bash
# Installs the Debian packages detexture needs to build and test (the library,
# the CLI, the Python module and its examples), or the
# packages named as arguments (scripts/install_fuzz_deps.sh passes its own).
# Run as root on Debian 12. Skips apt entirely when everything is already
# installed.
set -euo pipefail
packages=(build-essential cmake libeigen3-dev libnanoflann-dev libcli11-dev
          libgtest-dev googletest libpng-dev liblzf-dev libopenmpi-dev openmpi-bin
          python3 python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest
          python3-open3d python3-matplotlib)
[ $# -gt 0 ] && packages=("$@")
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
