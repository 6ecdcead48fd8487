#!/usr/bin/env bash
# Installs the dependencies, builds detexture (Release) into build/ — the
# library, the command line, the Python module — and installs them under
# /usr/local (cmake --install): headers, libdetexture.a and the CMake package
# (find_package(detexture)), /usr/local/bin/detexture, and the module in
# Debian's site path (/usr/local/lib/python3.11/dist-packages), so that
# `/usr/bin/python3 -c "import detexture"` works from any folder.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
cmake --install build >/dev/null
echo "build.sh: installed under $(cmake -L -N build 2>/dev/null | sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p')"
