#!/usr/bin/env bash
# emlt's performance suite: prints the table of docs/performance.md for the four bench scenes
# (Embree's ray bound, pt/bdpt samples/s, mlt/gamlt/emlt mutations/s, peak memory and the
# per-mutation profile). Options: bench/suite.py --help (--quick, --repeat 3, --scaling,
# --update-docs ...). Writes out/bench/{table.md,results.json,log.txt}.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
python=python3
[ -x /usr/bin/python3 ] && python=/usr/bin/python3
exec "$python" "$root/bench/suite.py" "$@"
