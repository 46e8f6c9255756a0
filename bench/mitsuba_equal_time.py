#!/usr/bin/env python3
"""MLT's error at equal time, emlt against Mitsuba 0.6, on one Mitsuba scene file (the goal:
"on the door an MSE at equal time <= 1/2 of Mitsuba MLT's").

Each seed: Mitsuba's `mlt` renders MPP mutations per pixel (direct light inside the chains,
`directSamples` -1; its sampler's seed set to the seed) and its wall time is taken; then emlt's
`mlt --direct mlt` (with each --variant's flags) renders for the same wall time. Figures per
method: the variance across seeds (every method is unbiased, so this is its MSE), the MSE
against a reference image (a long BDPT render; it includes the reference's own noise) and
each image's mean over the reference's (the normalisation's error shows there).

  MITSUBA=.../dist/mitsuba bench/mitsuba_equal_time.py SCENE.xml --reference REF.exr \
      --out DIR [--mpp 384] [--seeds 1 2 3] [--size 384x256] [--variant LABEL="FLAGS" ...]

Mitsuba 0.6 as released draws the same random numbers whatever the seed: its independent
sampler ignores `seed` (the chains' mutations), and its MLT draws the luminance pass and the
start paths from a generator seeded the same way every run. Its runs' spread then understates
its error (on the door by about a quarter at 128 mutations per pixel: docs/performance.md,
"Mitsuba's seeds"). Give
MITSUBA a build edited by bench/seed_mitsuba.py and pass --vary-luminance-pass: each seed is
then a new draw of everything, as emlt's are. The script checks that the binary honours the
sampler's seed (two tiny renders must differ) and says so in its output and results.json.
Compare like with like otherwise: emlt with `--bootstrap-seed N` in a variant's flags.
"""
import argparse
import json
import os
import shlex
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import suite  # bench/suite.py, beside this script: mitsuba_variant

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EMLT = os.path.join(ROOT, "build", "emlt")


def compare(reference, image):
    out = subprocess.run([EMLT, "compare", "--json", reference, image], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.splitlines()[0])


def mitsuba_honours_seed(mitsuba, scene, out):
    """Whether two tiny path-traced renders of the scene with different sampler seeds differ
    (Mitsuba 0.6 as released ignores the seed and gives the same bits)."""
    variant = os.path.join(out, "mitsuba-seed-check.xml")
    suite.mitsuba_variant(scene, "pt", 1, 16, 16, variant)
    tree = ET.parse(variant)
    for sampler in tree.getroot().iter("sampler"):
        ET.SubElement(sampler, "integer", name="seed", value="$seed")
    tree.write(variant)
    images = []
    for seed in (1, 2):
        image = os.path.join(out, f"mitsuba-seed-check-{seed}.exr")
        subprocess.run([mitsuba, "-q", "-p", "1", "-a", os.path.dirname(os.path.abspath(scene)),
                        "-D", f"seed={seed}", variant, "-o", image], check=True,
                       stdout=subprocess.DEVNULL)
        images.append(image)
    # The pixels, not the files: Mitsuba's EXR header differs from run to run.
    return compare(images[0], images[1])["mse"] > 0.0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scene")
    p.add_argument("--reference", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--mpp", type=int, default=384)
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--size", default="384x256")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--vary-luminance-pass", action="store_true",
                   help="set MTS_LUMINANCE_SEED to the seed for each Mitsuba run: a Mitsuba built by "
                        "bench/seed_mitsuba.py then draws its luminance pass and start paths anew "
                        "each seed (and its chains' numbers from the sampler's seed), so that its "
                        "spread across seeds is its whole error, as emlt's is")
    p.add_argument("--variant", action="append", default=[], metavar='LABEL="FLAGS"',
                   help='an emlt configuration to run at Mitsuba\'s time (repeatable); default: '
                        'emlt="" (its defaults)')
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

    seeds_honoured = mitsuba_honours_seed(mitsuba, args.scene, args.out)
    if not seeds_honoured:
        print("warning: this Mitsuba ignores the sampler's seed: its runs share their chains' "
              "random numbers, so its variance across seeds understates its error "
              "(bench/seed_mitsuba.py makes a build that honours it)", file=sys.stderr)

    variants = [v.split("=", 1) if "=" in v else (v, "") for v in args.variant] or [("emlt", "")]
    images = {"mitsuba": []}
    images.update({label: [] for label, _ in variants})
    rows = []
    for seed in args.seeds:
        mts_img = os.path.join(args.out, f"mitsuba-s{seed}.exr")
        t0 = time.time()
        subprocess.run([mitsuba, "-q", "-p", str(args.threads), "-a",
                        os.path.dirname(os.path.abspath(args.scene)), "-D", f"seed={seed}",
                        variant, "-o", mts_img], check=True, stdout=subprocess.DEVNULL,
                       env=dict(os.environ, **({"MTS_LUMINANCE_SEED": str(seed)}
                                               if args.vary_luminance_pass else {})))
        wall = time.time() - t0
        images["mitsuba"].append(mts_img)
        row = {"seed": seed, "mitsuba_s": wall}
        for label, flags in variants:
            img = os.path.join(args.out, f"{label}-s{seed}.exr")
            cmd = [EMLT, "render", args.scene, "--integrator", "mlt", "--direct", "mlt",
                   "--width", str(w), "--height", str(h), "--threads", str(args.threads),
                   "--seed", str(seed), "--time", f"{wall:.2f}", "-o", img] + shlex.split(flags)
            t0 = time.time()
            log = subprocess.run(cmd, check=True, capture_output=True, text=True)
            row[label + "_s"] = time.time() - t0
            row[label + "_stats"] = [l for l in log.stderr.splitlines() if l.startswith("mlt:")]
            images[label].append(img)
        rows.append(row)
        print(f"seed {seed}: Mitsuba {wall:.1f} s; " +
              ", ".join(f"{label} {row[label + '_s']:.1f} s" for label, _ in variants), flush=True)

    # Variance across seeds: the mean over every pair of half their mean squared difference
    # is the per-pixel sample variance averaged over the image. Every method is unbiased but
    # for Mitsuba's normalisation (fixed across seeds), whose error the mean ratio shows.
    summary = {}
    for label, imgs in images.items():
        pairs = [compare(imgs[a], imgs[b])["mse"] / 2
                 for a in range(len(imgs)) for b in range(a + 1, len(imgs))]
        refs = [compare(args.reference, img) for img in imgs]
        summary[label] = {
            "variance": sum(pairs) / len(pairs) if pairs else float("nan"),
            "mse_vs_reference": sum(r["mse"] for r in refs) / len(refs),
            "mean_ratio": [r["mean_ratio"] for r in refs]}
    print("| method | variance across seeds | / Mitsuba | MSE vs reference | mean / reference |")
    print("|---|---|---|---|---|")
    base = summary["mitsuba"]["variance"]
    for label, sm in summary.items():
        ratios = sm["mean_ratio"]
        print(f"| {label} | {sm['variance']:.4g} | {sm['variance'] / base:.2f} | "
              f"{sm['mse_vs_reference']:.4g} | {min(ratios):.3f}-{max(ratios):.3f} |")
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump({"scene": args.scene, "mpp": args.mpp, "seeds": args.seeds, "rows": rows,
                   "mitsuba_luminance_pass": "per seed" if args.vary_luminance_pass else "fixed",
                   "mitsuba_sampler_seed_honoured": seeds_honoured,
                   "summary": summary, "load": os.getloadavg()}, f, indent=1)


if __name__ == "__main__":
    main()
