#!/usr/bin/python3
"""emlt against Mitsuba 0.6 in interleaved pairs: side by side when the machine's speed drifts.

  MITSUBA=.../dist/mitsuba bench/mitsuba_pairs.py [--pairs 7] [--integrators pt,bdpt,mlt]
                                                   [--scenes cornell-box,...] [--door DOOR_XML]
                                                   [--work-scale 16]

compare_mitsuba.sh runs each renderer's repeats one after the other; on a shared virtual
machine whose speed moves by 10-20 % from one minute to the next (seen on the 2-core machine
of 26 Nov: Mitsuba's pt on the Cornell box at 0.76 and 0.99 M samples/s an hour apart), the
ratio of two medians taken minutes apart carries that drift. Here each pair is one emlt run
and, straight after it, one Mitsuba run of the same scene file and work (the suite's, see
bench/suite.py: SCENES), alternating which goes first; the ratio is taken within each pair,
and the median and range of the pairs' ratios are printed. Whole-process wall clock, 2
threads, as in the suite.

`mlt` runs with direct light inside the chains on both sides (emlt's `--direct mlt`, Mitsuba's
`directSamples` -1). The suite's work is a few seconds per run, where each renderer's fixed
start (loading, BVH, the MLT bootstrap; Mitsuba's `mlt` spends 2-4 s there) weighs heavily;
`--work-scale N` multiplies every count by N for renders of 20-60 s, where the chains' own
speed decides.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import suite  # bench/suite.py, beside this script: the suite's scenes, work and Mitsuba scene copies


def wall(cmd, env=None):
    start = time.monotonic()
    subprocess.run(cmd, cwd=suite.ROOT, env=env, check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    return time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mitsuba", default=os.environ.get("MITSUBA"))
    parser.add_argument("--build", default=os.path.join(suite.ROOT, "build"))
    parser.add_argument("--pairs", type=int, default=7)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--integrators", default="pt,bdpt")
    parser.add_argument("--scenes", default=",".join(s.name for s in suite.SCENES))
    parser.add_argument("--door", help="the public door-mlt.xml, added as veach-door")
    parser.add_argument("--work-scale", type=int, default=1,
                        help="multiply the suite's samples or mutations per pixel (long renders)")
    args = parser.parse_args()
    if args.work_scale < 1:
        sys.exit("mitsuba_pairs.py: --work-scale must be a whole number of at least 1")
    unknown = set(args.integrators.split(",")) - {"pt", "bdpt", "mlt"}
    if unknown:
        sys.exit(f"mitsuba_pairs.py: --integrators: unknown {','.join(sorted(unknown))} (pt, bdpt, mlt)")
    if not args.mitsuba:
        sys.exit("mitsuba_pairs.py: set MITSUBA=.../dist/mitsuba or pass --mitsuba")
    scenes = [s for s in suite.SCENES if s.name in args.scenes.split(",")]
    if args.door:
        scenes.append(suite.Scene("veach-door", os.path.abspath(args.door), 384, 256, 16, 4, 16))
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.dirname(os.path.abspath(args.mitsuba)))
    emlt = os.path.join(args.build, "emlt")
    print(f"{args.threads} threads; whole-process wall clock; {args.pairs} interleaved pairs per row; "
          "ratio = Mitsuba's time / emlt's (emlt's speed over Mitsuba's)")
    print("| scene | integrator | work | emlt s (median) | Mitsuba s (median) | ratio: median (range) |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="emlt-pairs-") as tmp:
        for scene in scenes:
            path = scene.path if os.path.isabs(scene.path) else os.path.join(suite.ROOT, scene.path)
            if scene.name == "env-terrain":  # its meshes are generated on first use
                subprocess.run([sys.executable, "-m", "tools.scenes.make_terrain"],
                               cwd=suite.ROOT, check=True, stdout=subprocess.DEVNULL)
            for integrator in args.integrators.split(","):
                count = args.work_scale * {"pt": scene.pt_spp, "bdpt": scene.bdpt_spp,
                                           "mlt": scene.mpp}[integrator]
                work = ["--mpp", str(count), "--direct", "mlt"] if integrator == "mlt" else ["--spp", str(count)]
                variant = suite.mitsuba_variant(path, integrator, count, scene.width, scene.height,
                                                os.path.join(tmp, f"{scene.name}-{integrator}.xml"))
                emlt_cmd = [emlt, "render", path, "--integrator", integrator, "--threads", str(args.threads),
                            "--seed", "1", "--width", str(scene.width), "--height", str(scene.height),
                            *work, "-o", os.path.join(tmp, "emlt.exr"), "--quiet"]
                mitsuba_cmd = [args.mitsuba, "-q", "-p", str(args.threads), "-a", os.path.dirname(path),
                               variant, "-o", os.path.join(tmp, "mitsuba.exr")]
                ours, theirs, ratios = [], [], []
                for k in range(args.pairs):
                    if k % 2 == 0:
                        a = wall(emlt_cmd)
                        b = wall(mitsuba_cmd, env)
                    else:
                        b = wall(mitsuba_cmd, env)
                        a = wall(emlt_cmd)
                    ours.append(a)
                    theirs.append(b)
                    ratios.append(b / a)
                print(f"| {scene.name} | {integrator} | {count} {'mpp' if integrator == 'mlt' else 'spp'} | {statistics.median(ours):.2f} | "
                      f"{statistics.median(theirs):.2f} | {statistics.median(ratios):.2f}x "
                      f"({min(ratios):.2f}-{max(ratios):.2f}) |", flush=True)
    print(f"load average after: {os.getloadavg()[0]:.2f}; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")


if __name__ == "__main__":
    main()
