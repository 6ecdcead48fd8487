#!/usr/bin/env bash
# A spot check on models of Debian's assimp-testmodels that neither quality
# suite uses, so that no parameter was chosen on them: each is prepared as a
# real-suite base mesh, textured by synth (100k points, exact ground truth),
# run with the suites' rule (-r 1.5 R, --sigma-s 1.5 R), in auto mode (no
# parameters) and with --ignore-normals, and compared with the input.
#
#   bench/spot_check.sh [--peers] [--broad] [--coarse] [--auto] [BUILD_DIR] [WORK_DIR]
#
# BUILD_DIR (default build) holds detexture and bench/peers/prepare_mesh
# (cmake -DDETEXTURE_BUILD_PEERS=ON). Prints one line per case and run:
# Dmean, Dmax, residual texture (the standard deviation of the signed
# distance) and mean normal error, as `detexture compare` gives them.
#
# Then a wider check, the rule only: ten more models, each with the three
# kinds of relief of the real suite (sparse bumps R 0.012, dense scales R
# 0.015, dense domes R 0.02, as synth makes them), 30 cases. Each line says
# where the result is worse than the input (RES: residual texture, NERR:
# normal error) or its Dmax over 1.25 times the input's (DMAX), issue 9's
# criteria; a count of each ends the run.
#
# Then the same ten models with waves and grooves (dense waves R 0.015, sparse
# U and V grooves R 0.02, 0.006 deep), 30 more cases in WORK_DIR/waves, the
# rule only, with the same flags and counts (no peers: see bench/README.md).
#
# --broad: then also five more models (and the thing again), each with all
# six reliefs above, 36 cases in WORK_DIR/broad, the rule only, with the same
# flags and counts (session 23's broad check).
#
# --coarse: then also the ten models of the wider check without subdivision
# (Loop level 0: the faceted bases as the files hold them, facets as large
# as the texture or larger), each with all six reliefs, 60 cases in
# WORK_DIR/coarse, the rule only, with the same flags and counts.
#
# --auto: every case of the wider, waves, broad and coarse checks also runs in
# auto mode (no parameters: r from estimate_texture_scale), compared with the
# input and with the rule's run: a line per case (auto's r over the rule's,
# its flags against the input, its residual texture and normal error over
# the rule's), and per check the same counts plus the geometric means of
# those two ratios. About twice the time.
#
# --peers: then also run the five tuned peers on the 30 cases and rank
# detexture among them (bench/spot_check_peers.py; about 35 minutes on 2
# cores the first time, then cached).
#
# SPOT_FLAGS (environment): more detexture options for every rule run, so
# that an option's old behaviour can be checked side by side, e.g.
# SPOT_FLAGS='--cells-max-depth 0' bench/spot_check.sh --broad build-prof /tmp/old
set -euo pipefail
peers=0
broad=0
coarse=0
auto=0
while [ "${1:-}" = --peers ] || [ "${1:-}" = --broad ] || [ "${1:-}" = --coarse ] ||
  [ "${1:-}" = --auto ]; do
  [ "$1" = --peers ] && peers=1
  [ "$1" = --broad ] && broad=1
  [ "$1" = --coarse ] && coarse=1
  [ "$1" = --auto ] && auto=1
  shift
done
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
  "$build/detexture" "$stem.in.ply" -o "$stem.rule.ply" -r "$r" --sigma-s "$r" -f -q ${SPOT_FLAGS:-}
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

# The wider check (see the top). name, model, Loop levels.
wide=(
  "dwarf COB/dwarf.cob 1"
  "epileptic X/BCN_Epileptic.X 1"
  "suzanne BLEND/Suzanne_248.blend 2"
  "faerie MD2/faerie.md2 1"
  "sydney MD2/sydney.md2 1"
  "at-at Q3D/E-AT-AT.q3o 1"
  "jeep MS3D/jeep1.ms3d 1"
  "thing Ogre/TheThing/Mesh.mesh.xml 1"
  "axe BLEND/yxa_1.blend 1"
  "mocap ASE/MotionCaptureROM.ase 1"
)
reliefs=("bumps sparse 0.012 0.004" "scales dense 0.015 0.005" "domes dense 0.02 0.006")
wave_reliefs=("waves dense 0.015 0.005" "u-grooves sparse 0.02 0.006" "v-grooves sparse 0.02 0.006")
# check_case DIR FLAGS NAME BASE TEXTURE LAYOUT SIZE AMPLITUDE: synth's relief
# on BASE, the rule's run, one line against the input, its flags to FLAGS.
check_case() {
  local dir=$1 flags=$2 name=$3 base=$4 texture=$5 layout=$6 size=$7 amplitude=$8
  local stem=$dir/$name r
  rm -f "$stem.in.ply" "$stem.gt.ply"
  "$build/detexture" synth --base-mesh "$base" --texture "$texture" --layout "$layout" \
    --size "$size" --amplitude "$amplitude" --points 100000 --ground-truth-points 200000 \
    --seed 1 -o "$stem.in.ply" --ground-truth "$stem.gt.ply" >"$stem.synth.log" 2>&1
  r=$(/usr/bin/python3 -c "print(1.5 * $size)")
  "$build/detexture" "$stem.in.ply" -o "$stem.rule.ply" -r "$r" --sigma-s "$r" -f -q ${SPOT_FLAGS:-}
  "$build/detexture" compare --json "$stem.in.ply" "$stem.gt.ply" >"$stem.in.json"
  "$build/detexture" compare --json "$stem.rule.ply" "$stem.gt.ply" >"$stem.rule.json"
  /usr/bin/python3 - "$stem" "$name" "$flags" <<'PY'
import json, sys
stem, name, flags = sys.argv[1:]
a = json.load(open(stem + '.in.json'))
b = json.load(open(stem + '.rule.json'))
ratio = b['dmax'] / a['dmax']
worse = [f for f, bad in (('RES', b['signed_std'] > a['signed_std']),
                          ('NERR', b['normal_angle_mean_degrees'] > a['normal_angle_mean_degrees']),
                          ('DMAX', ratio > 1.25)) if bad]
print('%-19s residual %.5f -> %.5f  normal error %5.2f -> %5.2f  Dmax x%.2f  %s' % (
    name, a['signed_std'], b['signed_std'], a['normal_angle_mean_degrees'],
    b['normal_angle_mean_degrees'], ratio, ' '.join(worse)))
open(flags, 'a').write(' '.join(worse) + '\n')
PY
  [ "$auto" = 1 ] || return 0
  "$build/detexture" "$stem.in.ply" -o "$stem.auto.ply" -f -q --stats "$stem.auto.stats.json"
  "$build/detexture" compare --json "$stem.auto.ply" "$stem.gt.ply" >"$stem.auto.json"
  /usr/bin/python3 - "$stem" "$name" "${flags%.txt}-auto.txt" "$r" <<'PY'
import json, sys
stem, name, flags, r = sys.argv[1:]
a = json.load(open(stem + '.in.json'))
b = json.load(open(stem + '.rule.json'))
c = json.load(open(stem + '.auto.json'))
radius = json.load(open(stem + '.auto.stats.json'))['radius']
ratio = c['dmax'] / a['dmax']
worse = [f for f, bad in (('RES', c['signed_std'] > a['signed_std']),
                          ('NERR', c['normal_angle_mean_degrees'] > a['normal_angle_mean_degrees']),
                          ('DMAX', ratio > 1.25)) if bad]
res, nerr = c['signed_std'] / b['signed_std'], c['normal_angle_mean_degrees'] / b['normal_angle_mean_degrees']
print('%-19s auto: r x%.2f the rule\'s, residual x%.2f, normal error x%.2f the rule\'s  Dmax x%.2f  %s' % (
    name, radius / float(r), res, nerr, ratio, ' '.join(worse)))
open(flags, 'a').write('%s %.6f %.6f %.6f\n' % (','.join(worse) or '-', radius / float(r), res, nerr))
PY
}

# check_model DIR FLAGS NAME MODEL LEVELS RELIEF...: prepare MODEL as
# DIR/NAME.base.ply, then check_case each RELIEF ("texture layout size
# amplitude") on it.
check_model() {
  local dir=$1 flags=$2 name=$3 model=$4 levels=$5 relief texture layout size amplitude
  shift 5
  "$build/bench/peers/prepare_mesh" "$models/$model" "$dir/$name.base.ply" --components largest \
    --subdivide "$levels" >"$dir/$name.prepare.log"
  for relief in "$@"; do
    read -r texture layout size amplitude <<<"$relief"
    check_case "$dir" "$flags" "$name-$texture" "$dir/$name.base.ply" "$texture" "$layout" \
      "$size" "$amplitude"
  done
}

# summarize LABEL FLAGS: the counts, and with --auto auto mode's (FLAGS-auto).
summarize() {
  echo "$1, $(wc -l <"$2") cases: worse residual $(grep -c RES "$2" || true), worse normal" \
    "error $(grep -c NERR "$2" || true), Dmax over 1.25 x the input's $(grep -c DMAX "$2" || true)"
  [ "$auto" = 1 ] || return 0
  /usr/bin/python3 - "$1" "${2%.txt}-auto.txt" <<'PY'
import math, sys
label, path = sys.argv[1:]
rows = [line.split() for line in open(path)]
gm = lambda k: math.exp(sum(math.log(float(x[k])) for x in rows) / len(rows))
print('%s, auto mode, %d cases: worse residual %d, worse normal error %d, Dmax over 1.25 x the '
      "input's %d; r within 0.7-1.5 x the rule's in %d (above %d, below %d); residual x%.3f and "
      "normal error x%.3f the rule's (geometric means)" % (
          label, len(rows), sum('RES' in x[0] for x in rows), sum('NERR' in x[0] for x in rows),
          sum('DMAX' in x[0] for x in rows), sum(0.7 <= float(x[1]) <= 1.5 for x in rows),
          sum(float(x[1]) > 1.5 for x in rows), sum(float(x[1]) < 0.7 for x in rows), gm(2), gm(3)))
PY
}

mkdir -p "$work/wide" "$work/waves"
flags=$work/wide/flags.txt
wave_flags=$work/waves/flags.txt
: >"$flags"
: >"${flags%.txt}-auto.txt"
: >"$wave_flags"
: >"${wave_flags%.txt}-auto.txt"
for c in "${wide[@]}"; do
  read -r name model levels <<<"$c"
  check_model "$work/wide" "$flags" "$name" "$model" "$levels" "${reliefs[@]}"
done
summarize "wider check" "$flags"

# The waves and grooves (see the top): the same ten models, the rule only.
for c in "${wide[@]}"; do
  read -r name model levels <<<"$c"
  for relief in "${wave_reliefs[@]}"; do
    read -r texture layout size amplitude <<<"$relief"
    check_case "$work/waves" "$wave_flags" "$name-$texture" "$work/wide/$name.base.ply" \
      "$texture" "$layout" "$size" "$amplitude"
  done
done
summarize "waves and grooves" "$wave_flags"
if [ "$broad" = 1 ]; then
  # name, model, Loop levels; the thing is the wider check's, again.
  broad_models=(
    "thing Ogre/TheThing/Mesh.mesh.xml 1"
    "grail SMD/holy_grailref.smd 1"
    "dinosaur X/fromtruespace_bin32.x 1"
    "crazy-engine LWO/LXOB_Modo/CrazyEngine.lxo 1"
    "torus BLEND/TorusLightsCams_250_compressed.blend 1"
    "rod X/anim_test.x 1"
  )
  mkdir -p "$work/broad"
  broad_flags=$work/broad/flags.txt
  : >"$broad_flags"
  : >"${broad_flags%.txt}-auto.txt"
  for c in "${broad_models[@]}"; do
    read -r name model levels <<<"$c"
    check_model "$work/broad" "$broad_flags" "$name" "$model" "$levels" "${reliefs[@]}" \
      "${wave_reliefs[@]}"
  done
  summarize "broad check" "$broad_flags"
fi
if [ "$coarse" = 1 ]; then
  mkdir -p "$work/coarse"
  coarse_flags=$work/coarse/flags.txt
  : >"$coarse_flags"
  : >"${coarse_flags%.txt}-auto.txt"
  for c in "${wide[@]}"; do
    read -r name model levels <<<"$c"
    check_model "$work/coarse" "$coarse_flags" "$name" "$model" 0 "${reliefs[@]}" \
      "${wave_reliefs[@]}"
  done
  summarize "coarse check" "$coarse_flags"
fi
if [ "$peers" = 1 ]; then
  "${DETEXTURE_PYTHON:-/usr/bin/python3}" "$(dirname "$0")/spot_check_peers.py" "$build" "$work/wide"
fi
