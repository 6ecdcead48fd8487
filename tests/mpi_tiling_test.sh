#!/usr/bin/env bash
# mpi_tiling_test.sh DETEXTURE MPIEXEC NP: `mpirun -np NP detexture --mpi` on
# loopback gives the single-process out-of-core output byte for byte, and
# leaves no temporary files. Run by ctest (tests/CMakeLists.txt).
set -euo pipefail
detexture=$1 mpiexec=$2 np=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/detexture_mpi_test.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir "$work/tmp"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
"$detexture" synth --shape sphere --texture bumps -n 8000 --ground-truth-points 100 \
  -o "$work/in.ply" > /dev/null
args=(-q -r 0.1 --tile 0.6 --halo 2r --temp-dir "$work/tmp")
"$detexture" "$work/in.ply" -o "$work/single.ply" "${args[@]}"
"$mpiexec" --oversubscribe -np "$np" "$detexture" "$work/in.ply" -o "$work/mpi.ply" \
  "${args[@]}" --mpi --stats "$work/stats.json"
cmp "$work/single.ply" "$work/mpi.ply"
[ -z "$(ls -A "$work/tmp")" ] || { echo "temporary files left: $(ls "$work/tmp")"; exit 1; }
# Every rank ran a tile (8 tiles over NP <= 4 ranks, balanced by points).
for ((r = 0; r < np; r++)); do
  grep -q "\"rank\": $r}" "$work/stats.json" || { echo "rank $r ran no tile"; exit 1; }
done
# A tile failing on any rank fails the run (exit 5), and leaves no output.
if "$mpiexec" --oversubscribe -np "$np" "$detexture" "$work/in.ply" -o "$work/fail.ply" \
  "${args[@]}" --memory-limit 50k --mpi 2> "$work/err.txt"; then
  echo "the failing run succeeded"; exit 1
fi
grep -q "failed: the neighborhoods would need" "$work/err.txt"
[ ! -e "$work/fail.ply" ] && [ -z "$(ls -A "$work/tmp")" ] && [ -z "$(ls -A "$work" | grep '^\.')" ]
echo "mpi_tiling_test: $np ranks, identical output"
