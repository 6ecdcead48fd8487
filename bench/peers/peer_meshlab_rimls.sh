#!/usr/bin/env bash
# peer_meshlab_rimls.sh: MeshLab's RIMLS projection (Oztireli et al. 2009) as a
# detexture peer, run headless through Debian 12's meshlabserver (2020.09).
#
# Usage: peer_meshlab_rimls.sh IN.ply OUT.ply [FILTER_SCALE [SIGMA_N [MAX_FITTING_ITERS
#                              [MAX_PROJECTION_ITERS [PROJECTION_ACCURACY]]]]]
# See --help. The last line of stdout is `seconds: <float>`: the wall time of the
# filter alone, measured between meshlabserver's own log lines that open the
# script and report the projection done (so start-up, loading and saving are
# excluded).
set -euo pipefail

PROGRAM=peer_meshlab_rimls.sh
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
SCRIPT_TEMPLATE="$HERE/rimls.mlx"

usage() {
  cat <<EOF
Usage: $PROGRAM IN.ply OUT.ply [FILTER_SCALE [SIGMA_N [MAX_FITTING_ITERS [MAX_PROJECTION_ITERS [PROJECTION_ACCURACY]]]]]

MeshLab 2020.09 "MLS projection (RIMLS)" (meshlabserver + $SCRIPT_TEMPLATE):
projects every point of IN onto the RIMLS surface of IN itself, writes the
projected points with RIMLS normals (binary PLY), and prints
'seconds: <time of the filter, without start-up and I/O>' as the last line.
Runs under xvfb-run when DISPLAY is unset (meshlabserver needs an OpenGL context).
Single-threaded: MeshLab's MLS projection has no parallel loop.

  IN.ply                PLY with normals (RIMLS needs them)
  OUT.ply               output PLY (must differ from IN)
  FILTER_SCALE          spatial filter scale, relative to the local point spacing
                        MeshLab estimates from 16 nearest neighbours (> 0)      [default 2]
  SIGMA_N               sharpness: width of the normal refitting weight;
                        0.5 sharp .. 2 smooth (> 0)                              [default 0.75]
  MAX_FITTING_ITERS     max refitting iterations; 0 or 1 = plain IMLS (>= 0)     [default 3]
  MAX_PROJECTION_ITERS  max projection iterations per point (>= 1)               [default 15]
  PROJECTION_ACCURACY   projection stop threshold, relative to the mean spacing (> 0) [default 0.0001]

In MeshLab 2020.09 PROJECTION_ACCURACY has no effect: the mean spacing it is
multiplied by is never computed, so the stop test never passes and every point
takes exactly MAX_PROJECTION_ITERS steps (outputs for 1e-4 and 1e-2 are
bit-identical; the time grows linearly with MAX_PROJECTION_ITERS). So
MAX_PROJECTION_ITERS alone sets the cost.
EOF
}

die() {
  echo "$PROGRAM: error: $*" >&2
  exit "${EXIT_CODE:-1}"
}

if [ "$#" -ge 1 ] && { [ "$1" = "-h" ] || [ "$1" = "--help" ]; }; then
  usage
  exit 0
fi
if [ "$#" -lt 2 ] || [ "$#" -gt 7 ]; then
  EXIT_CODE=2 die "expected IN.ply OUT.ply and up to 5 numbers, got $# arguments (run with --help for usage)"
fi

IN="$1"
OUT="$2"
FILTER_SCALE="${3:-2}"
SIGMA_N="${4:-0.75}"
MAX_FITTING_ITERS="${5:-3}"
MAX_PROJECTION_ITERS="${6:-15}"
PROJECTION_ACCURACY="${7:-0.0001}"

is_positive_number() { [[ "$1" =~ ^([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$ ]] && awk -v x="$1" 'BEGIN { exit !(x > 0) }'; }
is_count() { [[ "$1" =~ ^[0-9]+$ ]]; }

is_positive_number "$FILTER_SCALE" || EXIT_CODE=2 die "FILTER_SCALE must be a number > 0, got '$FILTER_SCALE'"
is_positive_number "$SIGMA_N" || EXIT_CODE=2 die "SIGMA_N must be a number > 0, got '$SIGMA_N'"
is_count "$MAX_FITTING_ITERS" || EXIT_CODE=2 die "MAX_FITTING_ITERS must be an integer >= 0, got '$MAX_FITTING_ITERS'"
{ is_count "$MAX_PROJECTION_ITERS" && [ "$MAX_PROJECTION_ITERS" -ge 1 ]; } ||
  EXIT_CODE=2 die "MAX_PROJECTION_ITERS must be an integer >= 1, got '$MAX_PROJECTION_ITERS'"
is_positive_number "$PROJECTION_ACCURACY" ||
  EXIT_CODE=2 die "PROJECTION_ACCURACY must be a number > 0, got '$PROJECTION_ACCURACY'"

{ [ -f "$IN" ] && [ -r "$IN" ]; } || die "cannot read input '$IN': no such file or not readable"
case "$IN" in *.ply | *.PLY) ;; *) die "input '$IN' is not a .ply file; meshlabserver picks its reader by extension" ;; esac
case "$OUT" in *.ply | *.PLY) ;; *) die "output '$OUT' must end in .ply" ;; esac
OUT_DIR="$(dirname -- "$OUT")"
{ [ -d "$OUT_DIR" ] && [ -w "$OUT_DIR" ]; } || die "cannot write output '$OUT': folder '$OUT_DIR' does not exist or is not writable"
if [ -e "$OUT" ] && [ "$(realpath -- "$IN")" = "$(realpath -- "$OUT")" ]; then
  die "output '$OUT' is the input file; refusing to overwrite it"
fi

HEADER="$(head -c 65536 -- "$IN" | LC_ALL=C sed -n '1,/^end_header/p')"
printf '%s\n' "$HEADER" | head -n 1 | grep -q '^ply' || die "input '$IN' is not a PLY file (no 'ply' magic on line 1)"
printf '%s\n' "$HEADER" | grep -q '^property [a-z0-9]* nx$' ||
  die "input '$IN' has no normals (nx, ny, nz); RIMLS needs oriented normals"
N_POINTS="$(printf '%s\n' "$HEADER" | awk '$1 == "element" && $2 == "vertex" { print $3; exit }')"
[ -n "$N_POINTS" ] || die "input '$IN' has no 'element vertex' line in its header"

command -v meshlabserver >/dev/null 2>&1 ||
  die "meshlabserver not found; install it with scripts/install_peer_deps.sh (Debian package meshlab)"
[ -f "$SCRIPT_TEMPLATE" ] || die "filter script '$SCRIPT_TEMPLATE' is missing"

RUNNER=()
if [ -z "${DISPLAY:-}" ]; then
  command -v xvfb-run >/dev/null 2>&1 ||
    die "DISPLAY is unset and xvfb-run is not installed; meshlabserver needs an X display for its OpenGL context (install xvfb)"
  RUNNER=(xvfb-run -a)
fi

WORK="$(mktemp -d "${TMPDIR:-/tmp}/peer_meshlab_rimls.XXXXXX")"
trap 'rm -rf -- "$WORK"' EXIT

set_param() {  # set_param NAME VALUE: rewrite value="..." of <Param name="NAME">
  sed -i -E "s|(<Param [^>]*value=\")[^\"]*(\" name=\"$1\"/>)|\1$2\2|" "$WORK/rimls.mlx"
  grep -q "value=\"$2\" name=\"$1\"" "$WORK/rimls.mlx" || die "could not set $1 in the filter script $SCRIPT_TEMPLATE"
}
cp -- "$SCRIPT_TEMPLATE" "$WORK/rimls.mlx"
set_param FilterScale "$FILTER_SCALE"
set_param SigmaN "$SIGMA_N"
set_param MaxRefittingIters "$MAX_FITTING_ITERS"
set_param MaxProjectionIters "$MAX_PROJECTION_ITERS"
set_param ProjectionAccuracy "$PROJECTION_ACCURACY"

# Line-buffered output, each line stamped on arrival: meshlabserver 2020.09
# reports no timings of its own.
# With pipefail, a failure of meshlabserver (or xvfb-run) is the pipeline's status.
STATUS=0
"${RUNNER[@]}" stdbuf -oL -eL meshlabserver -i "$IN" -o "$WORK/out.ply" -m vn -s "$WORK/rimls.mlx" 2>&1 |
  while IFS= read -r line; do printf '%s %s\n' "$EPOCHREALTIME" "$line"; done >"$WORK/log.txt" ||
  STATUS=$?

fail() {
  echo "$PROGRAM: error: $*" >&2
  echo "$PROGRAM: last lines of meshlabserver's output:" >&2
  tail -n 8 "$WORK/log.txt" | cut -c 1-300 >&2
  exit 1
}
[ "$STATUS" -eq 0 ] || fail "meshlabserver failed (exit status $STATUS) on '$IN'"
[ -s "$WORK/out.ply" ] || fail "meshlabserver wrote no output"

START="$(awk '/Starting Script of/ { print $1; exit }' "$WORK/log.txt")"
END_LINE="$(grep -m 1 'Successfully projected [0-9]* vertices' "$WORK/log.txt" || true)"
{ [ -n "$START" ] && [ -n "$END_LINE" ]; } || fail "could not find the filter's start and end in meshlabserver's log"
END="${END_LINE%% *}"
PROJECTED="$(printf '%s\n' "$END_LINE" | sed -E 's/.*Successfully projected ([0-9]+) vertices.*/\1/')"
[ "$PROJECTED" = "$N_POINTS" ] || fail "meshlabserver projected $PROJECTED of the $N_POINTS input points"

mv -f -- "$WORK/out.ply" "$OUT"
echo "parallel: no (MeshLab's MLS projection is single-threaded)"
echo "points: $N_POINTS"
awk -v s="$START" -v e="$END" 'BEGIN { printf "seconds: %.6f\n", e - s }'
