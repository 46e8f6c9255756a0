#!/usr/bin/python3
"""Instructions per sample or mutation, emlt and (optionally) Mitsuba 0.6, by callgrind.

  bench/instructions.py [--mitsuba .../dist/mitsuba] [--scenes cornell-box,textured-door]
                        [--integrators pt,bdpt,mlt,pssmlt-pt,pssmlt-bdpt] [--door DOOR_XML]

Each renderer runs one thread under `valgrind --tool=callgrind` twice on the same scene, at
two amounts of work (samples or mutations per pixel, the same for both renderers); the
difference of the two runs' total instruction counts over the difference of their work is
the cost of one more sample or mutation, free of what does not grow with the work (loading,
the BVH build, the MLT bootstrap with a fixed sample count and chain count, writing the
image). Instruction counts repeat from run to run, unlike times on a shared machine, but
they are not time: a cache miss costs more than its instructions, an instruction of one
renderer may do more than one of the other (SIMD). The lead's wall-clock side by side is
bench/compare_mitsuba.sh; this is the repeatable figure for before/after comparisons.

Valgrind cannot execute AVX-512: a Mitsuba built with -march=native on an AVX-512 machine
dies with SIGILL under it; build one for callgrind with -march=x86-64-v3 in its config.py.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

import suite  # bench/suite.py, beside this script: the scenes and Mitsuba's copy of a scene file

ROOT = suite.ROOT

# integrator -> (emlt flags, Mitsuba integrator element)
INTEGRATORS = {
    "pt": (["--integrator", "pt"], ("path", {})),
    "bdpt": (["--integrator", "bdpt"], ("bdpt", {})),
    "mlt": (["--integrator", "mlt", "--direct", "mlt"], ("mlt", {"directSamples": "-1"})),
    # Ours alone (Mitsuba has no geometry-aware MLT): the cone's cost against mlt's.
    "gamlt": (["--integrator", "gamlt", "--direct", "mlt"], None),
    "pssmlt-pt": (["--integrator", "pssmlt", "--pss-tracer", "pt", "--direct", "mlt"],
                  ("pssmlt", {"directSamples": "-1", "bidirectional": "false"})),
    "pssmlt-bdpt": (["--integrator", "pssmlt", "--pss-tracer", "bdpt", "--direct", "mlt"],
                    ("pssmlt", {"directSamples": "-1", "bidirectional": "true"})),
}
MCMC = ("mlt", "gamlt", "pssmlt-pt", "pssmlt-bdpt")


def callgrind_total(cmd, scratch, env=None):
    out = os.path.join(scratch, "callgrind.out")
    if os.path.exists(out):
        os.remove(out)
    proc = subprocess.run(["valgrind", "--tool=callgrind", "--dump-instr=no", f"--callgrind-out-file={out}"]
                          + cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.returncode != 0:
        sys.exit(f"instructions: failed ({proc.returncode}): {' '.join(cmd)}\n{proc.stdout[-2000:]}")
    with open(out) as f:
        for line in f:
            m = re.match(r"(?:totals|summary):\s+(\d+)", line)
            if m:
                return int(m.group(1))
    sys.exit(f"instructions: no total in {out}")


def mitsuba_file(scene_path, integrator, count, width, height, bootstrap, out):
    kind, params = INTEGRATORS[integrator][1]
    suite.mitsuba_variant(scene_path, "pt", count, width, height, out)
    import xml.etree.ElementTree as ET
    tree = ET.parse(out)
    element = tree.getroot().find("integrator")
    element.set("type", kind)
    for name, value in params.items():
        ET.SubElement(element, "boolean" if value in ("true", "false") else "integer", name=name, value=value)
    if integrator in MCMC:
        ET.SubElement(element, "integer", name="luminanceSamples", value=str(bootstrap))
    tree.write(out)
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("--mitsuba", help="Mitsuba 0.6's dist/mitsuba (LD_LIBRARY_PATH is set to its folder)")
    p.add_argument("--scenes", default="cornell-box,textured-door")
    p.add_argument("--door", help="the public Veach door's door-mlt.xml, as the scene 'veach-door'")
    p.add_argument("--integrators", default="pt,bdpt,mlt,pssmlt-pt,pssmlt-bdpt")
    p.add_argument("--size", default="96x64", help="image size WxH (default 96x64)")
    p.add_argument("--levels", default="2,6", help="the two amounts of work per pixel (default 2,6)")
    p.add_argument("--chains", type=int, default=256, help="emlt's chains in the MCMC runs")
    p.add_argument("--bootstrap", type=int, default=5000, help="bootstrap samples of the MCMC runs")
    p.add_argument("--emlt-only", action="store_true")
    args = p.parse_args()
    width, height = (int(x) for x in args.size.split("x"))
    low, high = (int(x) for x in args.levels.split(","))
    scenes = {s.name: s.path for s in suite.SCENES}
    if args.door:
        scenes["veach-door"] = args.door
    emlt = os.path.join(args.build, "emlt")
    scratch = tempfile.mkdtemp(prefix="emlt-instr-")
    env_mitsuba = dict(os.environ)
    if args.mitsuba:
        env_mitsuba["LD_LIBRARY_PATH"] = os.path.dirname(os.path.abspath(args.mitsuba))
    print(f"callgrind instructions per unit of work, one thread, {width}x{height}, "
          f"levels {low} and {high} per pixel (difference of the two runs)")
    print("| scene | integrator | emlt | Mitsuba | Mitsuba / emlt |")
    print("|---|---|---|---|---|")
    for name in args.scenes.split(",") + (["veach-door"] if args.door else []):
        path = scenes[name]
        for integrator in args.integrators.split(","):
            flags = INTEGRATORS[integrator][0]
            totals = []
            for level in (low, high):
                cmd = [emlt, "render", path, "--threads", "1", "--seed", "1", "-q", "--width", str(width),
                       "--height", str(height), "-o", os.path.join(scratch, "emlt.pfm")] + flags
                if integrator in MCMC:
                    cmd += ["--mpp", str(level), "--chains", str(args.chains), "--bootstrap", str(args.bootstrap)]
                else:
                    cmd += ["--spp", str(level)]
                totals.append(callgrind_total(cmd, scratch))
            work = (high - low) * width * height
            ours = (totals[1] - totals[0]) / work
            theirs = None
            if args.mitsuba and not args.emlt_only and INTEGRATORS[integrator][1]:
                mt = []
                for level in (low, high):
                    xml = mitsuba_file(path, integrator, level, width, height, args.bootstrap,
                                       os.path.join(scratch, "mitsuba.xml"))
                    mt.append(callgrind_total([args.mitsuba, "-q", "-p", "1", "-a",
                                               os.path.dirname(os.path.abspath(path)), xml, "-o",
                                               os.path.join(scratch, "mitsuba.exr")], scratch, env_mitsuba))
                theirs = (mt[1] - mt[0]) / work
            ratio = f"{theirs / ours:.2f}" if theirs else "-"
            print(f"| {name} | {integrator} | {ours:,.0f} | {f'{theirs:,.0f}' if theirs else '-'} | {ratio} |",
                  flush=True)


if __name__ == "__main__":
    main()
