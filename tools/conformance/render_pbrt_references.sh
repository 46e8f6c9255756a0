#!/usr/bin/env bash
# Renders the pbrt-v4 scenes of the conformance suite with pbrt-v4 itself.
#   PBRT=/path/to/build/pbrt tools/conformance/render_pbrt_references.sh [NAME...]
# Each scene of tests/conformance/suite.json that sets "pbrt_v4_reference_spp" (or only the
# NAMEs given) is rendered from scenes/NAME.pbrt to tests/conformance/references/pbrt-v4/NAME.pfm
# with that many samples per pixel, and the exact command, with pbrt's commit, is written
# beside it as NAME.cmd. pbrt-v4 builds with tools/conformance/build-pbrt.sh (CPU only);
# its commit is read from the git checkout the binary was built in (or PBRT_COMMIT).
# pbrt writes PFM itself when the output name ends in .pfm (float32 RGB, as the Mitsuba
# references), so check.py reads both kinds alike; the scenes ask for pbrt's "independent"
# sampler and a box filter of radius 0.5 (the filter emlt's and Mitsuba's renders use).
set -euo pipefail
: "${PBRT:?set PBRT to the pbrt binary (e.g. .../build/pbrt)}"
root=$(cd "$(dirname "$0")/../.." && pwd)
suite=$root/tests/conformance
threads=${THREADS:-$(nproc)}
commit=${PBRT_COMMIT:-$(git -C "$(dirname "$PBRT")" rev-parse HEAD 2>/dev/null || echo unknown)}
mkdir -p "$suite/references/pbrt-v4"

if (($#)); then names=("$@"); else
  mapfile -t names < <(python3 -c 'import json,sys; [print(s["name"]) for s in json.load(open(sys.argv[1]))["scenes"] if "pbrt_v4_reference_spp" in s]' "$suite/suite.json")
fi
for name in "${names[@]}"; do
  spp=$(python3 -c 'import json,sys; print(next(s["pbrt_v4_reference_spp"] for s in json.load(open(sys.argv[1]))["scenes"] if s["name"] == sys.argv[2]))' "$suite/suite.json" "$name")
  tmp=$(mktemp -d)
  cmd=(pbrt --nthreads "$threads" --seed 0 --spp "$spp" --outfile "$tmp/$name.pfm" "scenes/$name.pbrt")
  start=$(date +%s)
  (cd "$suite" && "$PBRT" "${cmd[@]:1}" > "$tmp/log.txt" 2>&1) || { cat "$tmp/log.txt"; echo "render_pbrt_references: $name failed" >&2; exit 1; }
  mv "$tmp/$name.pfm" "$suite/references/pbrt-v4/$name.pfm"
  printf '# pbrt-v4 (commit %s, CPU, built by tools/conformance/build-pbrt.sh), run in tests/conformance/, %s s\n%s\n' \
    "$commit" "$(( $(date +%s) - start ))" \
    "pbrt --nthreads $threads --seed 0 --spp $spp --outfile references/pbrt-v4/$name.pfm scenes/$name.pbrt" \
    > "$suite/references/pbrt-v4/$name.cmd"
  grep -i "warn\|error" "$tmp/log.txt" | grep -v "Output filename supplied on command line" | sed "s|^|$name: |" || true
  rm -rf "$tmp"
  echo "$name: $(( $(date +%s) - start )) s"
done
