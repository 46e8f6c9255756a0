#!/usr/bin/env bash
# MPI renders against single-process renders, run by CTest (label mpi):
#   mpi_check.sh EMLT MPIRUN same INTEGRATOR   -n 2 and -n 3 give the single-process bits
#   mpi_check.sh EMLT MPIRUN resume INTEGRATOR a 2-rank render stopped (EMLT_STOP_AFTER) and
#                                              resumed gives the single-process bits
#   mpi_check.sh EMLT MPIRUN failure           a rank that cannot read its scene ends every
#                                              rank with its one-line error, non-zero
#   mpi_check.sh EMLT MPIRUN dark INTEGRATOR   a scene where no bootstrap path carries light:
#                                              its warning printed once, not once a rank
set -euo pipefail
emlt=$1 mpirun=$2 mode=$3 integrator=${4:-}
root=$(cd "$(dirname "$0")/../.." && pwd)
scene=$root/scenes/cornell-box/scene.json
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
launch=("$mpirun")
# Open MPI refuses root and more ranks than cores unless told; MPICH takes neither flag.
if "$mpirun" --version 2>&1 | grep -qiE "open mpi|openrte"; then
  launch+=(--allow-run-as-root --oversubscribe)
fi
args=(render "$scene" --integrator "$integrator" --spp 8 --mpp 8 --width 48 --height 40
      --bootstrap 5000 --threads 1 -q)
fail() { echo "mpi_check: $*" >&2; exit 1; }

case $mode in
  same)
    "$emlt" "${args[@]}" -o "$work/one.exr" > /dev/null
    for ranks in 2 3; do
      "${launch[@]}" -n "$ranks" "$emlt" "${args[@]}" -o "$work/ranks$ranks.exr" > "$work/log" 2>&1 ||
        { cat "$work/log" >&2; fail "$integrator: mpirun -n $ranks failed"; }
      cmp "$work/one.exr" "$work/ranks$ranks.exr" ||
        fail "$integrator: mpirun -n $ranks differs from one process"
      echo "$integrator: mpirun -n $ranks gives the single-process bits"
    done
    ;;
  resume)
    "$emlt" "${args[@]}" -o "$work/one.exr" > /dev/null
    # Each rank stops after this many of its own samples or mutations (a rank has about
    # 7700 samples, and MLT's ranks as many mutations after them): inside the passes, or
    # (MLT) in the direct-light pass and in the chains.
    stops=(2000 5000)
    case $integrator in mlt | gamlt | memlt | emlt | pssmlt | mmlt) stops=(3000 11000) ;; esac
    for stop in "${stops[@]}"; do
      rm -f "$work"/c.ckpt*
      status=0
      "${launch[@]}" -n 2 -x EMLT_STOP_AFTER=$stop "$emlt" "${args[@]}" -o "$work/part.exr" \
        --checkpoint "$work/c.ckpt" > "$work/log" 2>&1 || status=$?
      [ "$status" -ne 0 ] || fail "$integrator: the stopped render exited 0"
      grep -q "stopped by SIGINT" "$work/log" || { cat "$work/log" >&2; fail "no stop reported"; }
      [ -s "$work/c.ckpt" ] && [ -s "$work/c.ckpt.rank1" ] || fail "a rank wrote no checkpoint"
      "${launch[@]}" -n 2 "$emlt" "${args[@]}" -o "$work/resumed.exr" --resume "$work/c.ckpt" \
        > "$work/log" 2>&1 || { cat "$work/log" >&2; fail "$integrator: resume failed"; }
      cmp "$work/one.exr" "$work/resumed.exr" ||
        fail "$integrator: stopped after $stop units and resumed, differs from one process"
      echo "$integrator: stopped after $stop units per rank and resumed: the single-process bits"
    done
    # A checkpoint of 2 ranks is refused by 3, by name.
    status=0
    "${launch[@]}" -n 3 "$emlt" "${args[@]}" -o "$work/x.exr" --resume "$work/c.ckpt" \
      > "$work/log" 2>&1 || status=$?
    [ "$status" -ne 0 ] || fail "a 2-rank checkpoint was accepted by 3 ranks"
    grep -q "checkpoint was made with mpirun -n 2, this run has 3" "$work/log" ||
      { cat "$work/log" >&2; fail "no rank-count mismatch message"; }
    [ ! -e "$work/x.exr" ] || fail "a refused resume wrote an image"
    ;;
  failure)
    status=0
    "${launch[@]}" -n 1 "$emlt" render "$scene" --spp 1 -q -o "$work/f.exr" : \
      -n 1 "$emlt" render "$work/missing.json" --spp 1 -q -o "$work/f.exr" > "$work/log" 2>&1 ||
      status=$?
    [ "$status" -ne 0 ] || fail "a failing rank left the run with status 0"
    [ "$(grep -c '^emlt: error:' "$work/log")" = 1 ] || { cat "$work/log" >&2; fail "expected one error line"; }
    grep -q "^emlt: error: $work/missing.json: file not found" "$work/log" ||
      { cat "$work/log" >&2; fail "the failing rank's error was not printed"; }
    [ ! -e "$work/f.exr" ] || fail "an image was written"
    echo "a rank without its scene: every rank ended, status $status, one error line"
    ;;
  dark)
    # The Cornell box seen from outside, the camera turned away: every camera path leaves
    # into the void, and no light path can reach the image.
    cp -r "$root/scenes/cornell-box/meshes" "$work/"
    sed 's/"target": \[278, 273, -799\]/"target": [278, 273, -801]/' \
      "$root/scenes/cornell-box/scene.json" > "$work/dark.json"
    grep -q -- '-801' "$work/dark.json" || fail "the camera was not turned"
    "${launch[@]}" -n 2 "$emlt" render "$work/dark.json" --integrator "$integrator" --spp 8 \
      --mpp 8 --width 48 --height 40 --bootstrap 5000 --threads 1 -q -o "$work/dark.exr" \
      > "$work/log" 2>&1 || { cat "$work/log" >&2; fail "$integrator: the dark render failed"; }
    count=$(grep -c "warning: no bootstrap .* carries light" "$work/log" || true)
    [ "$count" = 1 ] || { cat "$work/log" >&2; fail "$integrator: the warning came $count times"; }
    echo "$integrator: mpirun -n 2 on a scene without light: one warning"
    ;;
  *) fail "unknown mode $mode" ;;
esac
