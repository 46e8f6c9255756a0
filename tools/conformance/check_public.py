"""Renders public Mitsuba 0.6 scenes found in a folder with emlt, and with Mitsuba itself
when MITSUBA= names its binary, and prints a table of image means.

    MITSUBA=/path/to/dist/mitsuba tools/conformance/check_public.sh FOLDER
    MITSUBA=/path/to/dist/mitsuba python3 -m tools.conformance.check_public FOLDER   (from the root)
        [--emlt build/emlt] [--scale 0.25] [--spp 256] [--only NAME ...] [--threads N]

emlt renders each scene file as it is (no edits): `emlt info` gives its verdict, and
`emlt render --integrator pt` at the file's own maxDepth renders it, scaled to --scale of
its resolution. Mitsuba renders a copy written beside the original (so that relative
paths still resolve, removed afterwards) with only what a comparison needs changed: a
`path` integrator with the file's maxDepth, the version of a 0.5 file raised to 0.6
(Mitsuba's own upgrade of such files changes nothing else) (scenes name custom integrators such as
'mypath'), an hdrfilm writing PFM at the same scaled size without Mitsuba's logo, and the sample count. Both
estimate the same image, so their means must agree.

These scenes' licences are mostly unstated: they are read from a folder the user fetched,
never copied into this repository.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import numpy as np

from tools import ROOT
from tools.images import read_pfm


def scene_facts(path):
    """Resolution, sample count and maxDepth the file itself declares (defaults resolved)."""
    tree = ET.parse(path)
    root = tree.getroot()
    defaults = {d.get("name"): d.get("value") for d in root.findall("default")}

    def value(node, name, fallback):
        for child in node:
            if child.get("name") == name:
                text = child.get("value", fallback)
                return re.sub(r"\$(\w+)", lambda m: defaults.get(m.group(1), m.group(0)), text)
        return fallback

    film = root.find("sensor/film")
    width = int(float(value(film, "width", 768))) if film is not None else 768
    height = int(float(value(film, "height", 576))) if film is not None else 576
    integrator = root.find("integrator")
    depth = int(float(value(integrator, "maxDepth", -1))) if integrator is not None else -1
    return tree, width, height, depth


def mitsuba_copy(path, tree, width, height, depth, spp):
    """The scene as Mitsuba will render it for the comparison (see the module doc)."""
    root = tree.getroot()
    # Mitsuba 0.6's command line refuses 0.5 files; its upgrade from 0.5 only renumbers.
    if root.get("version", "").startswith("0.5"):
        root.set("version", "0.6.0")
    for old in root.findall("integrator"):
        root.remove(old)
    integrator = ET.Element("integrator", type="path")
    ET.SubElement(integrator, "integer", name="maxDepth", value=str(depth))
    root.insert(0, integrator)
    sensor = root.find("sensor")
    film = sensor.find("film")
    filters = film.findall("rfilter") if film is not None else []
    if film is not None:
        sensor.remove(film)
    film = ET.SubElement(sensor, "film", type="hdrfilm")
    ET.SubElement(film, "integer", name="width", value=str(width))
    ET.SubElement(film, "integer", name="height", value=str(height))
    ET.SubElement(film, "string", name="fileFormat", value="pfm")
    ET.SubElement(film, "string", name="pixelFormat", value="rgb")
    ET.SubElement(film, "boolean", name="banner", value="false")  # Mitsuba stamps its logo
    for f in filters:
        film.append(f)
    sampler = sensor.find("sampler")
    if sampler is None:
        sampler = ET.SubElement(sensor, "sampler", type="independent")
    for child in list(sampler):
        if child.get("name") == "sampleCount":
            sampler.remove(child)
    ET.SubElement(sampler, "integer", name="sampleCount", value=str(spp))
    fd, copy = tempfile.mkstemp(suffix=".xml", prefix=".conformance-", dir=os.path.dirname(path))
    os.close(fd)
    tree.write(copy)
    return copy


def run(args, cwd=None, env=None):
    return subprocess.run(args, capture_output=True, text=True, cwd=cwd, env=env)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder")
    parser.add_argument("--emlt", default=os.path.join(ROOT, "build", "emlt"))
    parser.add_argument("--scale", type=float, default=0.25)
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--only", action="append", help="only files whose name contains this")
    args = parser.parse_args()
    mitsuba = os.environ.get("MITSUBA")

    scenes = []
    for base, _, files in os.walk(args.folder):
        for name in sorted(files):
            if name.endswith(".xml") and not name.startswith(".conformance-"):
                if not args.only or any(o in name for o in args.only):
                    scenes.append(os.path.join(base, name))
    if not scenes:
        print(f"check_public: no .xml scenes under {args.folder}", file=sys.stderr)
        return 2

    print("| scene | emlt verdict | maxDepth | emlt mean / Mitsuba's (R, G, B) | note |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for path in sorted(scenes):
            rel = os.path.relpath(path, args.folder)
            info = run([args.emlt, "info", path])
            if info.returncode != 0:
                print(f"| `{rel}` | does not load | | | {info.stderr.strip().splitlines()[-1]} |")
                continue
            verdict = re.search(r"^verdict\s+(.*)$", info.stdout, re.M).group(1)
            try:
                tree, width, height, depth = scene_facts(path)
            except (ET.ParseError, AttributeError, ValueError) as e:
                print(f"| `{rel}` | {verdict} | | | cannot read its film: {e} |")
                continue
            w, h = max(1, round(width * args.scale)), max(1, round(height * args.scale))
            out = os.path.join(work, "emlt.pfm")
            render = [args.emlt, "render", path, "-o", out, "--integrator", "pt", "--quiet",
                      "--spp", str(args.spp), "--width", str(w), "--height", str(h), "--max-depth", str(depth)]
            if args.threads:
                render += ["--threads", str(args.threads)]
            result = run(render)
            if result.returncode != 0:
                print(f"| `{rel}` | {verdict} | {depth} | | emlt failed: {result.stderr.strip().splitlines()[-1]} |")
                continue
            emlt_mean = read_pfm(out).reshape(-1, 3).mean(axis=0)
            if not mitsuba:
                means = ", ".join(f"{v:.4g}" for v in emlt_mean)
                print(f"| `{rel}` | {verdict} | {depth} | emlt alone: {means} | MITSUBA not set |")
                continue
            copy = mitsuba_copy(path, tree, w, h, depth, args.spp)
            try:
                env = dict(os.environ, LD_LIBRARY_PATH=os.path.dirname(mitsuba))
                reference = os.path.join(work, "mitsuba.pfm")
                threads = str(args.threads or os.cpu_count())
                result = run([mitsuba, "-q", "-p", threads, os.path.basename(copy), "-o", reference],
                             cwd=os.path.dirname(path), env=env)
            finally:
                os.remove(copy)
                for log in os.listdir(os.path.dirname(path)):
                    if log.startswith("mitsuba.") and log.endswith(".log"):
                        os.remove(os.path.join(os.path.dirname(path), log))
            if result.returncode != 0 or not os.path.exists(reference):
                last = (result.stdout + result.stderr).strip().splitlines()
                print(f"| `{rel}` | {verdict} | {depth} | | Mitsuba failed: {last[-1] if last else '?'} |")
                continue
            ratio = emlt_mean / np.maximum(read_pfm(reference).reshape(-1, 3).mean(axis=0), 1e-12)
            worst = float(np.max(np.abs(ratio - 1.0)))
            note = "within 2 %" if worst <= 0.02 else f"off by {100 * worst:.1f} %"
            print(f"| `{rel}` | {verdict} | {depth} | {', '.join(f'{v:.3f}' for v in ratio)} | {note} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
