#!/usr/bin/env bash
# Public Mitsuba 0.6 scenes against Mitsuba itself; see check_public.py for the options.
#   MITSUBA=/path/to/dist/mitsuba tools/conformance/check_public.sh FOLDER
# Runs the module tools.conformance.check_public with the repository root on PYTHONPATH (the
# package's home), from any working directory, so FOLDER may be relative to where you are.
root=$(cd "$(dirname "$0")/../.." && pwd)
export PYTHONPATH="$root${PYTHONPATH:+:$PYTHONPATH}"
exec /usr/bin/python3 -m tools.conformance.check_public "$@"
