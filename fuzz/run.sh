#!/usr/bin/env bash
# Builds the fuzz harnesses with clang (ASan + UBSan + libFuzzer) and runs
# each for SECONDS on a copy of the committed seed corpus, with its
# dictionary. Exits non-zero if any run finds a crash, a leak or an oracle
# failure; the input that did it is saved under $FUZZ_BUILD_DIR/artifacts.
#
#   fuzz/run.sh SECONDS [read_ply|read_xyz|read_obj|read_off|read_stl|read_pcd ...]
#                                                    (default: every harness)
#
# Environment: FUZZ_BUILD_DIR (default build-fuzz at the root), FUZZ_CXX
# (default clang++-14), FUZZ_RUNS=N to stop after N executions instead of
# SECONDS, FUZZ_BUILD_ONLY=1 to only build, FUZZ_NO_BUILD=1 to skip the build,
# FUZZ_SANITIZERS=0 for a build without ASan/UBSan (faster long runs).
set -euo pipefail
seconds=${1:?usage: fuzz/run.sh SECONDS [read_ply|read_xyz ...]}
shift
root=$(cd "$(dirname "$0")/.." && pwd)
build=${FUZZ_BUILD_DIR:-$root/build-fuzz}
cxx=${FUZZ_CXX:-clang++-14}
readers=("$@")
[ ${#readers[@]} -eq 0 ] && readers=(read_ply read_xyz read_obj read_off read_stl read_pcd)

if [ -z "${FUZZ_NO_BUILD:-}" ]; then
  launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S "$root/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDETEXTURE_FUZZ_SANITIZERS="${FUZZ_SANITIZERS:-1}" \
    "${launcher[@]}" >/dev/null
  cmake --build "$build" -j "$(nproc)" >/dev/null
fi
[ -n "${FUZZ_BUILD_ONLY:-}" ] && { echo "fuzz harnesses built in $build"; exit 0; }

status=0
for reader in "${readers[@]}"; do
  format=${reader#read_}
  work="$build/corpus-$format"  # new inputs go here, not into the committed seeds
  mkdir -p "$work" "$build/artifacts"
  limit=(-max_total_time="$seconds")
  [ -n "${FUZZ_RUNS:-}" ] && limit=(-runs="$FUZZ_RUNS")
  log="$build/fuzz_$reader.log"
  start=$(date +%s)
  if "$build/fuzz_$reader" "$work" "$root/fuzz/corpus/$format" -dict="$root/fuzz/$format.dict" \
    "${limit[@]}" -max_len=4096 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build/artifacts/$reader-" >"$log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
    echo "fuzz_$reader: $runs executions in $(( $(date +%s) - start )) s, nothing found"
  else
    status=1
    echo "fuzz_$reader: FAILED, see $log; the input is in $build/artifacts:"
    grep -E 'ERROR|oracle|SUMMARY|Test unit written' "$log" | head -20 || tail -20 "$log"
  fi
done
exit $status
