#!/usr/bin/env bash
# Installs the dependencies, builds detexture with its tests and runs the whole
# suite under ctest, then builds it again with AddressSanitizer and
# UndefinedBehaviorSanitizer (build-asan/) and runs the suite there too. Each
# ctest prints its summary line; the fuzz smoke runs are part of the first
# suite when clang is installed (scripts/install_fuzz_deps.sh, called here).
# The Python module is left out of the sanitizer build: an ASan-instrumented
# extension cannot be loaded into Debian's uninstrumented python3 without
# LD_PRELOADing the sanitizer runtime; the C++ package example still runs there.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/install_fuzz_deps.sh
# PCL's own command-line tools, so that tests/test_pcd_pcl.cpp checks our PCD
# files against PCL's reader and writer instead of skipping (issue 13), and
# assimp's test models (20 MB), so that the two tests that read them
# (CliHardening.AssimpTestModelsAreReadOrRefusedCleanly,
# MeshFormats.AssimpWusonIsTheSameMeshInEveryFormat) run instead of skipping:
# a clean clone's CI skipped them until session 30.
bash scripts/install_deps.sh pcl-tools assimp-testmodels
bash scripts/build.sh
# ctest runs two tests at a time and each runs OpenMP on every core, so each
# team's idle threads spun in libgomp's barriers (its default, active wait)
# on the cores the other test was working on: the Release suite took 113-156
# s against 73-82 s with passive waits (session 42, the same build, runs
# interleaved). The output is the same either way. Both suites run so.
export OMP_WAIT_POLICY=passive
start=$(date +%s)
ctest --test-dir build --output-on-failure -j "$(nproc)"
echo "test.sh: Release suite took $(( $(date +%s) - start )) s"

start=$(date +%s)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# -O1 -g1 (line tables only) instead of RelWithDebInfo's -O2 -g: the sanitizer
# build took 610 s of the CI's 20 minutes that way. -Og built as fast, but its
# uninlined Eigen left the suite 1.6 times slower than -O1 (session 11, on a
# machine half as fast as session 9's: build 243 s against 254 s, suite 379 s
# against 236 s, 2 jobs). DETEXTURE_TESTS_UBSAN=OFF compiles the tests' own
# code without UBSan (the library and the CLI keep it; why and the build's
# figures in tests/CMakeLists.txt): the suite ran in 279 s instead of 311 s
# (session 30, side by side, 2 jobs). DETEXTURE_CLI_UNOPTIMIZED=ON compiles the
# command line's own sources at -O0 (CMakeLists.txt; session 32). -no-pie
# links the sanitizer build's programs at a fixed address: as position-
# independent executables the loader applied 782k relocations (the sanitizers'
# metadata) at every start, 0.1 s of each command-line run and 0.035 s of each
# test's process; the same build relinked ran the suite in 601 test-seconds
# instead of 632 (session 42, 2 jobs), within the machine's noise in wall time.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined -no-pie" -DDETEXTURE_FUZZ_SMOKE=OFF \
  -DDETEXTURE_BUILD_PYTHON=OFF -DDETEXTURE_TESTS_UBSAN=OFF -DDETEXTURE_CLI_UNOPTIMIZED=ON >/dev/null
cmake --build build-asan -j "$(nproc)"
echo "test.sh: sanitizer build took $(( $(date +%s) - start )) s"
start=$(date +%s)
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)"
echo "test.sh: sanitizer suite took $(( $(date +%s) - start )) s"
