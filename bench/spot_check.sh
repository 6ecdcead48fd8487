#!/usr/bin/env bash
# A spot check on models of Debian's assimp-testmodels that neither quality
# suite uses, so that no parameter was chosen on them: each is prepared as a
# real-suite base mesh, textured by synth (100k points, exact ground truth),
# run with the suites' rule (-r 1.5 R, --sigma-s 1.5 R), in auto mode (no
# parameters) and with --ignore-normals, and compared with the input.
#
#   bench/spot_check.sh [BUILD_DIR] [WORK_DIR]
#
# BUILD_DIR (default build) holds detexture and bench/peers/prepare_mesh
# (cmake -DDETEXTURE_BUILD_PEERS=ON). Prints one line per case and run:
# Dmean, Dmax, residual texture (the standard deviation of the signed
# distance) and mean normal error, as `detexture compare` gives them.
set -euo pipefail
build=$(realpath "${1:-build}")
work=${2:-$build/bench-spot}
mkdir -p "$work"
models=/usr/share/assimp/models

# name, model, texture, R, amplitude, Loop levels
cases=(
  "teapot Collada/teapots.DAE bumps 0.03 0.01 2"
  "sphere-with-hole STL/sphereWithHole.stl scales 0.025 0.008 3"
  "bones FBX/huesitos.fbx domes 0.03 0.01 3"
  "shell OBJ/regr01.obj bumps 0.02 0.006 2"
)
for c in "${cases[@]}"; do
  read -r name model texture size amplitude levels <<<"$c"
  stem=$work/$name
  "$build/bench/peers/prepare_mesh" "$models/$model" "$stem.base.ply" --components largest \
    --subdivide "$levels" >"$stem.prepare.log"
  rm -f "$stem.in.ply" "$stem.gt.ply"
  "$build/detexture" synth --base-mesh "$stem.base.ply" --texture "$texture" --layout dense \
    --size "$size" --amplitude "$amplitude" --points 100000 --ground-truth-points 200000 \
    --seed 1 -o "$stem.in.ply" --ground-truth "$stem.gt.ply" >"$stem.synth.log" 2>&1
  r=$(/usr/bin/python3 -c "print(1.5 * $size)")
  "$build/detexture" "$stem.in.ply" -o "$stem.rule.ply" -r "$r" --sigma-s "$r" -f -q
  "$build/detexture" "$stem.in.ply" -o "$stem.auto.ply" -f -q
  "$build/detexture" "$stem.in.ply" -o "$stem.estimated.ply" -r "$r" --sigma-s "$r" -f -q \
    --ignore-normals
  for run in in rule auto estimated; do
    "$build/detexture" compare --json "$stem.$run.ply" "$stem.gt.ply" | /usr/bin/python3 -c "
import json, sys
m = json.load(sys.stdin)
print('%-17s %-9s Dmean %.5f  Dmax %.5f  residual %.5f  normal error %.2f' % (
    '$name', '$run', m['dmean'], m['dmax'], m['signed_std'], m['normal_angle_mean_degrees']))"
  done
done
