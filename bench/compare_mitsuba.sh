#!/usr/bin/env bash
# The performance suite side by side with Mitsuba 0.6 in one run: the same scene files, the
# same work (samples or mutations per pixel) and threads, whole-process figures and ratios.
#   MITSUBA=/path/to/dist/mitsuba bench/compare_mitsuba.sh [DOOR_XML] [suite options...]
# Mitsuba 0.6 builds with ../shared/tools/build-mitsuba.sh. DOOR_XML, optional, is the public
# Veach door (e.g. /tmp/public/scenes/veach_door/door-mlt.xml; not in the repository), run at
# 384x256 as a fifth scene. Mitsuba's MLT runs with directSamples -1 (direct light inside the
# chains), emlt's with --direct mlt. Extra options go to bench/suite.py (--repeat 3 for
# medians, --no-profile, --scenes ...).
set -euo pipefail
: "${MITSUBA:?set MITSUBA to the Mitsuba 0.6 binary (e.g. .../dist/mitsuba; see ../shared/tools/build-mitsuba.sh)}"
root=$(cd "$(dirname "$0")/.." && pwd)
args=()
if (($#)) && [[ $1 != -* ]]; then args+=(--door "$1"); shift; fi
exec "$root/bench/run.sh" --mitsuba "$MITSUBA" --out "$root/out/bench-mitsuba" "${args[@]}" "$@"
