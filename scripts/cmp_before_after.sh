#!/usr/bin/env bash
# The same renders by two emlt binaries, compared byte for byte: a change that must leave
# images untouched (a refactoring of a render loop) is checked against the binary built
# before it.
#   scripts/cmp_before_after.sh BEFORE_EMLT AFTER_EMLT [INTEGRATOR...]
# Default integrators: every one (the MCMC ones also with --direct mlt, the direct light
# left to the chains, and EMLT also at --mpp 16, 32 swaps of its ensembles). Each renders
# the Cornell box and the glass Cornell box at a fixed --spp with 1 and 2 threads, under
# `mpirun -n 2` when mpirun is found, and stopped (EMLT_STOP_AFTER, as by Ctrl-C) then
# resumed from its checkpoint with each binary, at each of a few points (samples, then an
# MCMC render's bootstrap and mutations). Exits non-zero on the first difference. Each
# binary also resumes the other one's checkpoints, which must keep their layout (they are
# not compared as bytes: they hold the seconds spent).
set -euo pipefail
before=$1 after=$2
shift 2
integrators=("$@")
[ ${#integrators[@]} -gt 0 ] || integrators=(direct pt bdpt ptracer mlt gamlt emlt pssmlt mmlt)
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
launch=()
if command -v mpirun > /dev/null; then
  launch=(mpirun)
  # Open MPI refuses root and more ranks than cores unless told; MPICH takes neither flag.
  if mpirun --version 2>&1 | grep -qiE "open mpi|openrte"; then
    launch+=(--allow-run-as-root --oversubscribe)
  fi
fi
compared=0
same() {  # NAME: the before and after images of one render
  cmp "$work/before.exr" "$work/after.exr" || { echo "DIFFERS: $1" >&2; exit 1; }
  compared=$((compared + 1))
  echo "same bits: $1"
}
# NAME "STOP..." ARGS...: one render's comparisons; each STOP must fall before its end.
compare() {
  local name=$1 stops=$2
  shift 2
  local args=("$@")
  for threads in 1 2; do
    "$before" "${args[@]}" --threads "$threads" -o "$work/before.exr" > /dev/null 2>> "$work/log"
    "$after" "${args[@]}" --threads "$threads" -o "$work/after.exr" > /dev/null 2>> "$work/log"
    same "$name --threads $threads"
  done
  if [ ${#launch[@]} -gt 0 ]; then
    "${launch[@]}" -n 2 "$before" "${args[@]}" --threads 1 -o "$work/before.exr" > /dev/null 2>> "$work/log"
    "${launch[@]}" -n 2 "$after" "${args[@]}" --threads 1 -o "$work/after.exr" > /dev/null 2>> "$work/log"
    same "$name mpirun -n 2"
  fi
  for stop in $stops; do
    # Stopped after `stop` samples or mutations and resumed: each binary resumes its own
    # checkpoint.
    for which in before after; do
      local binary=$before
      [ "$which" = after ] && binary=$after
      rm -f "$work/$which.ckpt"
      local status=0
      EMLT_STOP_AFTER=$stop "$binary" "${args[@]}" --threads 2 -o "$work/part.exr" \
        --checkpoint "$work/$which.ckpt" > /dev/null 2>&1 || status=$?
      [ "$status" = 130 ] || { echo "$name: the $which render stopped at $stop exited $status" >&2; exit 1; }
      "$binary" "${args[@]}" --threads 1 -o "$work/$which.exr" --resume "$work/$which.ckpt" \
        > /dev/null 2>> "$work/log"
    done
    same "$name stopped at $stop and resumed"
    # Each binary's checkpoint resumed by the other one.
    "$after" "${args[@]}" --threads 1 -o "$work/after.exr" --resume "$work/before.ckpt" \
      > /dev/null 2>> "$work/log"
    same "$name stopped at $stop by the binary before, resumed by the one after"
    "$before" "${args[@]}" --threads 1 -o "$work/before.exr" --resume "$work/after.ckpt" \
      > /dev/null 2>> "$work/log"
    "$after" "${args[@]}" --threads 1 -o "$work/after.exr" --resume "$work/after.ckpt" \
      > /dev/null 2>> "$work/log"
    same "$name stopped at $stop by the binary after, resumed by the one before"
  done
}
for scene in cornell-box cornell-glass; do
  for integrator in "${integrators[@]}"; do
    common=(render "$root/scenes/$scene/scene.json" --integrator "$integrator" --spp 8
            --bootstrap 4000 --width 64 --height 48 -q)
    args=("${common[@]}" --mpp 4)
    case $integrator in
      mlt | gamlt | emlt | pssmlt | mmlt)
        # The direct pass's 12,288 samples, then the chains' 12,288 mutations (the bootstrap
        # counts none): stops in the direct pass and in the chains, and twice in the chains
        # without the direct pass.
        compare "$scene $integrator --direct separate" "8000 20000" "${args[@]}" --direct separate
        compare "$scene $integrator --direct mlt" "2000 9000" "${args[@]}" --direct mlt
        ;;
      *) compare "$scene $integrator" "8000" "${args[@]}" ;;
    esac
    if [ "$integrator" = emlt ]; then
      # Ensembles of 1,536 paths taking one step each between swaps: 32 swaps.
      compare "$scene emlt --mpp 16" "20000 40000" "${common[@]}" --mpp 16 --direct mlt
    fi
  done
done
echo "$compared renders: the same bits before and after"
