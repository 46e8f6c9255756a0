#!/usr/bin/env bash
# Renders the conformance suite's reference images with Mitsuba 0.6 itself.
#   MITSUBA=/path/to/dist/mitsuba tools/conformance/render_references.sh [NAME...]
# Each scene of tests/conformance/suite.json (or only the NAMEs given) is rendered to
# tests/conformance/references/NAME.pfm, and the exact command is written beside it as
# NAME.cmd. Mitsuba 0.6 builds with ../shared/tools/build-mitsuba.sh (RGB mode, single
# precision); LD_LIBRARY_PATH is set to the binary's folder.
set -euo pipefail
: "${MITSUBA:?set MITSUBA to the mitsuba binary (e.g. .../dist/mitsuba)}"
root=$(cd "$(dirname "$0")/../.." && pwd)
suite=$root/tests/conformance
threads=${THREADS:-$(nproc)}
export LD_LIBRARY_PATH="$(dirname "$MITSUBA")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

if (($#)); then names=("$@"); else
  mapfile -t names < <(python3 -c 'import json,sys; [print(s["name"]) for s in json.load(open(sys.argv[1]))["scenes"]]' "$suite/suite.json")
fi
version=$("$MITSUBA" -v 2>&1 | grep -m1 -o 'version [0-9.]*' || true)
for name in "${names[@]}"; do
  spp=$(python3 -c 'import json,sys; print(next(s.get("reference_spp", 4096) for s in json.load(open(sys.argv[1]))["scenes"] if s["name"] == sys.argv[2]))' "$suite/suite.json" "$name")
  out=$suite/references/$name.pfm
  tmp=$(mktemp -d)
  cmd=(mitsuba -q -p "$threads" -Dspp="$spp" "scenes/$name.xml" -o "$tmp/$name.pfm")
  start=$(date +%s)
  (cd "$suite" && "$MITSUBA" "${cmd[@]:1}" > "$tmp/log.txt" 2>&1) || { cat "$tmp/log.txt"; echo "render_references: $name failed" >&2; exit 1; }
  mv "$tmp/$name.pfm" "$out"
  printf '# Mitsuba 0.6 (%s, RGB mode, single precision), run in tests/conformance/, %s s\n%s\n' \
    "${version:-version unknown}" "$(( $(date +%s) - start ))" \
    "mitsuba -q -p $threads -Dspp=$spp scenes/$name.xml -o references/$name.pfm" > "$suite/references/$name.cmd"
  grep -i "warn\|error" "$tmp/log.txt" | sed "s|^|$name: |" || true
  rm -rf "$tmp"
  echo "$name: $(( $(date +%s) - start )) s"
done
