#!/usr/bin/env bash
# Renders the conformance suite's reference images with Mitsuba 0.6 itself.
#   MITSUBA=/path/to/dist/mitsuba tools/conformance/render_references.sh [NAME...]
# Each scene of tests/conformance/suite.json (or only the NAMEs given) is rendered to
# tests/conformance/references/NAME.pfm, and the exact command is written beside it as
# NAME.cmd. Mitsuba 0.6 builds with ../shared/tools/build-mitsuba.sh (RGB mode, single
# precision); LD_LIBRARY_PATH is set to the binary's folder.
# Two kinds of film write no PFM. An mfilm in NumPy format writes NAME.npy, which becomes
# the PFM (the same float32 values). A scene whose suite entry sets "reference_film"
# (ldrfilm: tone-mapped 8 bits; tiledhdrfilm: tiled OpenEXR) is rendered from a copy,
# scenes/.reference-NAME.xml, whose film is that one (an hdrfilm writing PFM) with the
# same width, height and filter. A scene whose entry sets "reference_integrator" (a file
# naming a Metropolis integrator, whose image converges to the path tracer's) is rendered from
# such a copy whose integrator is that one, with the file's maxDepth and rrDepth.
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
  film=$(python3 -c 'import json,sys; print(next(s.get("reference_film", "") for s in json.load(open(sys.argv[1]))["scenes"] if s["name"] == sys.argv[2]))' "$suite/suite.json" "$name")
  integrator=$(python3 -c 'import json,sys; print(next(s.get("reference_integrator", "") for s in json.load(open(sys.argv[1]))["scenes"] if s["name"] == sys.argv[2]))' "$suite/suite.json" "$name")
  out=$suite/references/$name.pfm
  tmp=$(mktemp -d)
  scene=scenes/$name.xml
  if [[ -n $film || -n $integrator ]]; then  # the same scene through another film or integrator (see above)
    scene=scenes/.reference-$name.xml
    python3 - "$suite/scenes/$name.xml" "$suite/$scene" "$film" "$integrator" <<'PY'
import sys
import xml.etree.ElementTree as ET
tree = ET.parse(sys.argv[1])
if sys.argv[3]:
    film = tree.find("sensor/film")
    film.set("type", sys.argv[3])
    keep = {"width", "height"}  # and the rfilter; the output format becomes an RGB PFM
    for child in list(film):
        if child.tag != "rfilter" and child.get("name") not in keep:
            film.remove(child)
    for key, value in (("pixelFormat", "rgb"), ("fileFormat", "pfm")):
        ET.SubElement(film, "string", name=key, value=value)
if sys.argv[4]:
    integrator = tree.find("integrator")
    integrator.set("type", sys.argv[4])
    for child in list(integrator):
        if child.get("name") not in {"maxDepth", "rrDepth"}:
            integrator.remove(child)
tree.write(sys.argv[2], encoding="utf-8", xml_declaration=True)
PY
  fi
  cmd=(mitsuba -q -p "$threads" -Dspp="$spp" "$scene" -o "$tmp/$name.pfm")
  start=$(date +%s)
  (cd "$suite" && "$MITSUBA" "${cmd[@]:1}" > "$tmp/log.txt" 2>&1) || { cat "$tmp/log.txt"; echo "render_references: $name failed" >&2; exit 1; }
  if [[ -f $tmp/$name.npy ]]; then  # an mfilm's NumPy array, rows top first
    python3 - "$tmp/$name.npy" "$tmp/$name.pfm" <<'PY'
import ast, struct, sys
data = open(sys.argv[1], "rb").read()
assert data[:6] == b"\x93NUMPY", "not a NumPy file"
size = struct.unpack("<H", data[8:10])[0] if data[6] == 1 else struct.unpack("<I", data[8:12])[0]
start = 10 if data[6] == 1 else 12
header = ast.literal_eval(data[start:start + size].decode("latin1"))
assert header["descr"] == "<f4" and not header["fortran_order"] and len(header["shape"]) == 3, header
height, width, channels = header["shape"]
assert channels == 3, "the mfilm must write pixelFormat rgb"
pixels = data[start + size:]
row = width * 3 * 4
with open(sys.argv[2], "wb") as f:  # PFM: little-endian (scale -1), bottom row first
    f.write(b"PF\n%d %d\n-1.0\n" % (width, height))
    f.write(b"".join(pixels[y * row:(y + 1) * row] for y in reversed(range(height))))
PY
  fi
  mv "$tmp/$name.pfm" "$out"
  [[ -n $film || -n $integrator ]] && rm -f "$suite/$scene"
  printf '# Mitsuba 0.6 (%s, RGB mode, single precision), run in tests/conformance/, %s s%s\n%s\n' \
    "${version:-version unknown}" "$(( $(date +%s) - start ))" \
    "${film:+; $scene is scenes/$name.xml with its film made a $film writing PFM}${integrator:+; $scene is scenes/$name.xml rendered by the integrator $integrator}" \
    "mitsuba -q -p $threads -Dspp=$spp $scene -o references/$name.pfm" > "$suite/references/$name.cmd"
  grep -i "warn\|error" "$tmp/log.txt" | sed "s|^|$name: |" || true
  rm -rf "$tmp"
  echo "$name: $(( $(date +%s) - start )) s"
done
