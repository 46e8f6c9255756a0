#!/usr/bin/env python3
"""The conformance suite's Mitsuba 3 twins (tests/conformance/scenes/mitsuba3/, written by
tools/conformance/make_mitsuba3_scenes.py) against their Mitsuba 0.6 originals: for each
twin, `emlt info` must give the same verdict for both files, and emlt's path tracer must
render both to the same bits (same seed, a few samples per pixel). A name or a value the
Mitsuba 3 reader translates wrongly changes the scene, and so the image or the verdict.

    PYTHONPATH=. tests/conformance/check_mitsuba3.py [--emlt build/emlt] [--scene NAME ...]
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
# Pairs beside the suite's: (name, the 0.6 file, its Mitsuba 3 twin, -D defines).
EXTRA = {"cornell-box": (os.path.join(ROOT, "scenes", "cornell-box", "scene.xml"),
                         os.path.join(ROOT, "scenes", "cornell-box", "scene-mitsuba3.xml"),
                         ["width=48", "height=48", "resx=48", "resy=48"])}
SPP = 2  # the bits are compared, not the noise: a couple of samples exercise every path


def defines_args(defines):
    return [arg for d in defines for arg in ("-D", d)]


def verdict(emlt, scene, defines=()):
    result = subprocess.run([emlt, "info", scene, *defines_args(defines)], capture_output=True,
                            text=True)
    if result.returncode != 0:
        raise RuntimeError(f"emlt info {scene} failed: {result.stderr.strip()}")
    lines = result.stdout.splitlines()
    verdicts = [l for l in lines if l.startswith("verdict")]
    warnings = "\n".join(l.strip() for l in lines if ": line " in l)
    return verdicts[-1].split(None, 1)[1] if verdicts else "(no verdict)", warnings


def render(emlt, scene, out, defines=()):
    args = [emlt, "render", scene, "-o", out, "--integrator", "pt", "--seed", "7", "--spp",
            str(SPP), "--threads", "1", "--quiet", *defines_args(defines)]
    result = subprocess.run(args, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"emlt render {scene} failed: {result.stderr.strip()}")
    with open(out, "rb") as f:
        return f.read()


def check(emlt, name, workdir):
    original, twin, defines = EXTRA.get(name, (
        os.path.join(HERE, "scenes", name + ".xml"),
        os.path.join(HERE, "scenes", "mitsuba3", name + ".xml"), []))
    problems = []
    (v06, _), (v3, warnings3) = verdict(emlt, original, defines), verdict(emlt, twin, defines)
    if v06 != v3:
        problems.append(f"verdict {v3!r} for the twin, {v06!r} for the original\n{warnings3}")
    image06 = render(emlt, original, os.path.join(workdir, name + ".06.pfm"), defines)
    image3 = render(emlt, twin, os.path.join(workdir, name + ".3.pfm"), defines)
    if image06 != image3:
        differing = sum(a != b for a, b in zip(image06, image3)) + abs(len(image06) - len(image3))
        problems.append(f"the images differ ({differing} of {len(image06)} bytes)")
    return name, problems


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--emlt", default=os.path.join(HERE, "..", "..", "build", "emlt"))
    parser.add_argument("--scene", nargs="*", help="twins to check (default: all)")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    manifest = json.load(open(os.path.join(HERE, "mitsuba3.json")))
    names = args.scene or manifest["twins"] + list(EXTRA)
    failures = 0
    with tempfile.TemporaryDirectory() as workdir, \
            concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for name, problems in pool.map(lambda n: check(args.emlt, n, workdir), names):
            print(f"{'FAIL' if problems else 'PASS'} {name}")
            for p in problems:
                print("    " + p.replace("\n", "\n    "))
            failures += bool(problems)
    print(f"{len(names) - failures} of {len(names)} Mitsuba 3 twins render as their originals "
          f"({len(manifest['skipped'])} scenes have no twin: tests/conformance/mitsuba3.json)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
