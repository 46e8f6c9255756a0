#!/usr/bin/env bash
# Strong scaling of MPI on this machine: the same render as 1 rank x 2 threads
# and as 2 ranks x 1 thread (mpirun), for each integrator. Efficiency = time(1 x 2) /
# time(2 x 1): 1.0 when splitting the work over processes costs nothing beyond threads.
#   bench/mpi_scaling.sh [SIZE [INTEGRATOR...]]
#   (default: a 256 x 256 Cornell box; pt bdpt mlt emlt, about 70 s in all on 2 idle cores;
#   pssmlt and mmlt on request)
# Prints a Markdown table (docs/scaling.md quotes it); "render s" is what emlt reports (the
# render alone), "wall s" the whole command with MPI's start-up and the scene's loading;
# then the load average before and after (other processes on the cores make the 2-rank run
# wait for whichever rank is not running, see docs/scaling.md), and for EMLT where each
# rank's time went (EMLT_MPI_PROFILE).
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-256}
shift || true
integrators=("$@")
[ ${#integrators[@]} -gt 0 ] || integrators=(pt bdpt mlt emlt)
emlt=${EMLT:-build/emlt}
launch=(mpirun)
if mpirun --version 2>&1 | grep -qiE "open mpi|openrte"; then
  launch+=(--allow-run-as-root --oversubscribe --bind-to none)
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

seconds_of() { sed -n 's/.*, \([0-9.]*\) s, .*/\1/p' "$1" | tail -1; }
now() { date +%s.%N; }

load_before=$(uptime | sed 's/.*load average: //')
echo "| integrator | budget | 1 rank x 2 threads: render s (wall s) | 2 ranks x 1 thread: render s (wall s) | efficiency (render) | same bits |"
echo "|---|---|---|---|---|---|"
for integrator in "${integrators[@]}"; do
  case $integrator in
    pt) flag=--spp budget=256 ;;
    bdpt) flag=--spp budget=64 ;;
    mlt | gamlt) flag=--mpp budget=256 ;;
    emlt | pssmlt | mmlt) flag=--mpp budget=128 ;;
    *) echo "mpi_scaling: unknown integrator $integrator" >&2; exit 1 ;;
  esac
  args=(render scenes/cornell-box/scene.json --integrator "$integrator" "$flag" "$budget"
        --width "$size" --height "$size" -q)
  t0=$(now)
  "$emlt" "${args[@]}" --threads 2 -o "$work/one.exr" > "$work/one.txt" 2>&1
  t1=$(now)
  EMLT_MPI_PROFILE=1 "${launch[@]}" -n 2 "$emlt" "${args[@]}" --threads 1 -o "$work/two.exr" \
    > "$work/two.txt" 2>&1
  grep "profile rank" "$work/two.txt" | sed "s/^emlt: /$integrator /" >> "$work/profile.txt" || true
  t2=$(now)
  one=$(seconds_of "$work/one.txt") two=$(seconds_of "$work/two.txt")
  same=no
  cmp -s "$work/one.exr" "$work/two.exr" && same=yes
  /usr/bin/python3 - "$integrator" "$flag $budget" "$one" "$two" "$t0" "$t1" "$t2" "$same" <<'PY'
import sys
name, budget, one, two, t0, t1, t2, same = sys.argv[1:]
one, two, t0, t1, t2 = map(float, (one, two, t0, t1, t2))
print(f"| {name} | {budget} | {one:.2f} ({t1 - t0:.2f}) | {two:.2f} ({t2 - t1:.2f}) | {one / two:.2f} | {same} |")
PY
done
echo
echo "load average (1, 5, 15 min) before: $load_before; after: $(uptime | sed 's/.*load average: //')"
[ -s "$work/profile.txt" ] && sort "$work/profile.txt"
exit 0
