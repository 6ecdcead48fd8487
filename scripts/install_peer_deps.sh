#!/usr/bin/env bash
# Install what the peer programs in bench/peers need, from Debian 12's packages:
#   libcgal-dev + libtbb-dev  peer_cgal_bilateral, peer_cgal_jet, peer_cgal_wlop (parallel via TBB)
#   libpcl-dev                peer_pcl_mls
#   meshlab + xvfb + xauth    peer_meshlab_rimls.sh (meshlabserver needs an X display
#   + libgl1-mesa-dri         with OpenGL even headless: it runs under xvfb-run on Mesa)
#   libcli11-dev              command lines of every peer
#   libassimp-dev             bench/peers/prepare_mesh (reads the models of bench/quality_real)
#   assimp-testmodels         the real base meshes of bench/quality_real (/usr/share/assimp/models)
#   pcl-tools                 pcl_pcd2ply / pcl_ply2pcd, for tests/test_pcd_pcl.cpp (our PCD
#                             files against PCL's; the test is skipped without them)
#   python3-numpy python3-scipy  bench/normals_from_positions.py (k-d tree, eigenvectors)
# Run as root (or with sudo available). Non-interactive and idempotent: running it
# again installs nothing new.
set -euo pipefail

export DEBIAN_FRONTEND=noninteractive

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    SUDO="sudo -E"
  else
    echo "install_peer_deps.sh: must run as root (or with sudo installed)." >&2
    exit 1
  fi
fi

PACKAGES=(
  cmake
  g++
  libeigen3-dev
  libcli11-dev
  libnanoflann-dev
  libcgal-dev
  libtbb-dev
  libpcl-dev
  meshlab
  xvfb
  xauth
  libgl1-mesa-dri
  libassimp-dev
  assimp-testmodels
  pcl-tools
  python3-numpy
  python3-scipy
)

$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends \
  -o Dpkg::Options::=--force-confdef -o Dpkg::Options::=--force-confold \
  "${PACKAGES[@]}"

echo "install_peer_deps.sh: installed ${PACKAGES[*]}"
