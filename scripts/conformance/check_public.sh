#!/usr/bin/env bash
# Public Mitsuba 0.6 scenes against Mitsuba itself; see check_public.py for the options.
#   MITSUBA=/path/to/dist/mitsuba scripts/conformance/check_public.sh FOLDER
exec /usr/bin/python3 "$(dirname "$0")/check_public.py" "$@"
