#!/usr/bin/env bash
# The same renders by two emlt binaries, compared byte for byte: a change that must leave
# images untouched (a refactoring of a render loop) is checked against the binary built
# before it.
#   scripts/cmp_before_after.sh BEFORE_EMLT AFTER_EMLT [INTEGRATOR...]
# Default integrators: direct pt bdpt mlt (mlt for the direct-light pass it renders on the
# pixel driver). Each renders the Cornell box and the glass Cornell box at a fixed --spp
# with 1 and 2 threads, under `mpirun -n 2` when mpirun is found, and stopped
# (EMLT_STOP_AFTER, as by Ctrl-C) then resumed from its checkpoint with each binary. Exits
# non-zero on the first difference. The second binary also resumes the first one's
# checkpoints, which must keep their layout.
set -euo pipefail
before=$1 after=$2
shift 2
integrators=("$@")
[ ${#integrators[@]} -gt 0 ] || integrators=(direct pt bdpt mlt)
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
for scene in cornell-box cornell-glass; do
  for integrator in "${integrators[@]}"; do
    args=(render "$root/scenes/$scene/scene.json" --integrator "$integrator" --spp 8 --mpp 4
          --bootstrap 4000 --width 64 --height 48 -q)
    name="$scene $integrator"
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
    # Stopped a third of the way (samples, then MLT's mutations) and resumed: each binary
    # resumes its own checkpoint.
    for which in before after; do
      binary=$before
      [ "$which" = after ] && binary=$after
      rm -f "$work/$which.ckpt"
      status=0
      EMLT_STOP_AFTER=8000 "$binary" "${args[@]}" --threads 2 -o "$work/part.exr" \
        --checkpoint "$work/$which.ckpt" > /dev/null 2>&1 || status=$?
      [ "$status" = 130 ] || { echo "$name: the stopped $which render exited $status" >&2; exit 1; }
      "$binary" "${args[@]}" --threads 1 -o "$work/$which.exr" --resume "$work/$which.ckpt" \
        > /dev/null 2>> "$work/log"
    done
    same "$name stopped and resumed"
    # The checkpoint of the binary before, resumed by the one after.
    "$after" "${args[@]}" --threads 1 -o "$work/after.exr" --resume "$work/before.ckpt" \
      > /dev/null 2>> "$work/log"
    same "$name stopped by the binary before, resumed by the one after"
  done
done
echo "$compared renders: the same bits before and after"
