#!/usr/bin/env python3
"""MLT's error at equal time, emlt against Mitsuba 0.6, on one Mitsuba scene file (issue 24:
"on the door an MSE at equal time <= 1/2 of Mitsuba MLT's").

Each seed: Mitsuba's `mlt` renders MPP mutations per pixel (direct light inside the chains,
`directSamples` -1; its sampler's seed set to the seed) and its wall time is taken; then emlt's
`mlt --direct mlt` renders for the same wall time. Both against a reference image (a long
BDPT render, e.g. by Mitsuba: see --reference), MSE over all pixels, plus each image's mean
ratio to the reference (the normalisation b's error shows there).

  MITSUBA=.../dist/mitsuba bench/mitsuba_equal_time.py SCENE.xml --reference REF.exr \
      --out DIR [--mpp 384] [--seeds 1 2 3] [--size 384x256] [--emlt-args "..."]

Mitsuba's MLT draws its luminance pass and seed paths from a fixed stream (its replayable
sampler's own generator), whatever the sampler's seed: its normalisation error is one draw
shared by every seed, so its seeds' spread understates its error. Only the reference shows it.
"""
import argparse
import json
import os
import shlex
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import suite  # noqa: E402  (mitsuba_variant)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EMLT = os.path.join(ROOT, "build", "emlt")


def compare(reference, image):
    out = subprocess.run([EMLT, "compare", "--json", reference, image], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.splitlines()[0])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene")
    p.add_argument("--reference", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--mpp", type=int, default=384)
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--size", default="384x256")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--emlt-args", default="", help="extra emlt render flags")
    p.add_argument("--label", default="emlt")
    args = p.parse_args()
    mitsuba = os.environ.get("MITSUBA")
    if not mitsuba:
        sys.exit("set MITSUBA to the Mitsuba 0.6 binary")
    os.makedirs(args.out, exist_ok=True)
    w, h = (int(v) for v in args.size.split("x"))
    variant = os.path.join(args.out, "mitsuba-mlt.xml")
    suite.mitsuba_variant(args.scene, "mlt", args.mpp, w, h, variant)
    tree = ET.parse(variant)
    for sampler in tree.getroot().iter("sampler"):
        ET.SubElement(sampler, "integer", name="seed", value="$seed")
    tree.write(variant)

    rows = []
    for seed in args.seeds:
        mts_img = os.path.join(args.out, f"mitsuba-s{seed}.exr")
        t0 = time.time()
        subprocess.run([mitsuba, "-q", "-p", str(args.threads), "-a",
                        os.path.dirname(os.path.abspath(args.scene)), "-D", f"seed={seed}",
                        variant, "-o", mts_img], check=True, stdout=subprocess.DEVNULL)
        wall = time.time() - t0
        emlt_img = os.path.join(args.out, f"{args.label}-s{seed}.exr")
        cmd = [EMLT, "render", args.scene, "--integrator", "mlt", "--direct", "mlt",
               "--width", str(w), "--height", str(h), "--threads", str(args.threads),
               "--seed", str(seed), "--time", f"{wall:.2f}", "-o", emlt_img]
        cmd += shlex.split(args.emlt_args)
        t0 = time.time()
        log = subprocess.run(cmd, check=True, capture_output=True, text=True)
        emlt_wall = time.time() - t0
        m, e = compare(args.reference, mts_img), compare(args.reference, emlt_img)
        row = {"seed": seed, "mitsuba_s": wall, "emlt_s": emlt_wall,
               "mitsuba_mse": m["mse"], "emlt_mse": e["mse"],
               "mitsuba_mean_ratio": m["mean_ratio"], "emlt_mean_ratio": e["mean_ratio"],
               "emlt_stats": log.stderr.strip().splitlines()[-6:]}
        rows.append(row)
        print(f"seed {seed}: Mitsuba {wall:.1f} s MSE {m['mse']:.4g} (mean {m['mean_ratio']:.4f})"
              f" | {args.label} {emlt_wall:.1f} s MSE {e['mse']:.4g} (mean {e['mean_ratio']:.4f})",
              flush=True)
    mm = sum(r["mitsuba_mse"] for r in rows) / len(rows)
    em = sum(r["emlt_mse"] for r in rows) / len(rows)
    print(f"mean MSE: Mitsuba {mm:.4g}, {args.label} {em:.4g}, ratio {em / mm:.3f}")
    with open(os.path.join(args.out, f"results-{args.label}.json"), "w") as f:
        json.dump({"scene": args.scene, "mpp": args.mpp, "rows": rows,
                   "load": os.getloadavg()}, f, indent=1)


if __name__ == "__main__":
    main()
