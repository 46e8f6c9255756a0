#!/usr/bin/env bash
# The checkpoints' long-render check: a long MLT render killed with SIGINT at a random moment and
# resumed is bit-identical to the same render run without interruption.
#   scripts/long_resume_check.sh [MPP] [SIZE]   (defaults: 65536 mutations per pixel on the
#   Cornell box at 128 x 128, about ten minutes on two cores)
# Renders once without interruption (D seconds), then again, sends SIGINT at a random moment
# between 5 % and 95 % of D, resumes it, and compares the files.
set -euo pipefail
cd "$(dirname "$0")/.."
mpp=${1:-65536}
size=${2:-128}
emlt=${EMLT:-build/emlt}
out=${OUT:-build/long-resume}
mkdir -p "$out"
rm -f "$out"/*.exr "$out"/render.ckpt
args=(render scenes/cornell-box/scene.json --integrator mlt --mpp "$mpp" --width "$size"
      --height "$size" -q)

start=$(date +%s.%N)
"$emlt" "${args[@]}" -o "$out/uninterrupted.exr"
duration=$(echo "$(date +%s.%N) - $start" | bc)
moment=$(/usr/bin/python3 -c "import random; print(round($duration * random.uniform(0.05, 0.95), 1))")
echo "uninterrupted: ${duration} s; stopping the second render after ${moment} s"

"$emlt" "${args[@]}" -o "$out/interrupted.exr" --checkpoint "$out/render.ckpt" \
  --checkpoint-interval 60 &
pid=$!
sleep "$moment"
kill -INT "$pid"
status=0
wait "$pid" || status=$?
echo "stopped render exited with status $status"
[ "$status" = 130 ] || { echo "expected status 130" >&2; exit 1; }
"$emlt" "${args[@]}" -o "$out/resumed.exr" --resume "$out/render.ckpt"
if cmp "$out/uninterrupted.exr" "$out/resumed.exr"; then
  echo "bit-identical: $out/uninterrupted.exr and $out/resumed.exr"
else
  echo "the resumed render differs from the uninterrupted one" >&2
  exit 1
fi
