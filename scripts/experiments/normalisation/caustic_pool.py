#!/usr/bin/env python3
"""b against BDPT on the caustic pool: does the image's brightness match BDPT's within the
error the engine prints, with and without the normalisation drawn beside the chains?

    caustic_pool.py --emlt build/emlt --out DIR [--size 32] [--mpp 65536] [--seeds 6]

For each seed: `mlt --direct mlt` (so the image's mean luminance is b itself) at --mpp with
the default --normalisation-rate, and a short run at rate 0 (the bootstrap's b alone, which
does not depend on the budget); BDPT's mean luminance over --bdpt-seeds runs of --bdpt-spp is
the reference, with its standard error across those runs. Writes DIR/results.csv and prints
a markdown table: each b, its printed error, z = (b - BDPT) / sqrt(error^2 + BDPT's error^2),
and the mean z^2 of each setting (1 when the errors are honest)."""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, REPO)
from tools.images import read_pfm  # noqa: E402

SCENE = os.path.join(REPO, "scenes", "caustic-pool", "scene.json")


def render(emlt, out, name, args):
    image = os.path.join(out, name + ".pfm")
    stats = os.path.join(out, name + ".json")
    if not os.path.exists(image):
        cmd = [emlt, "render", SCENE, "-q", "-o", image] + args
        if "mlt" in args:
            cmd += ["--stats", stats]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return image, stats


def mean_luminance(path):
    pixels = read_pfm(path)
    lum = 0.212671 * pixels[..., 0] + 0.715160 * pixels[..., 1] + 0.072169 * pixels[..., 2]
    return float(lum.mean())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--emlt", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--size", type=int, default=32)
    parser.add_argument("--mpp", type=float, default=65536)
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--bdpt-spp", type=int, default=4096)
    parser.add_argument("--bdpt-seeds", type=int, default=4)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    size = ["--width", str(args.size), "--height", str(args.size)]

    bdpt = [mean_luminance(render(args.emlt, args.out, f"bdpt-{s}",
                                  size + ["--integrator", "bdpt", "--spp", str(args.bdpt_spp),
                                          "--seed", str(s)])[0])
            for s in range(1, args.bdpt_seeds + 1)]
    reference = sum(bdpt) / len(bdpt)
    ref_error = math.sqrt(sum((x - reference) ** 2 for x in bdpt) / (len(bdpt) - 1) / len(bdpt))

    rows = []
    for setting, extra in (("bootstrap alone", ["--normalisation-rate", "0", "--mpp", "1"]),
                           ("beside the chains", ["--mpp", f"{args.mpp:g}"])):
        for seed in range(1, args.seeds + 1):
            name = f"mlt-{'r0' if 'bootstrap' in setting else 'default'}-{seed}"
            image, stats_path = render(args.emlt, args.out, name,
                                       size + ["--integrator", "mlt", "--direct", "mlt",
                                               "--seed", str(seed)] + extra)
            with open(stats_path) as f:
                st = json.load(f)
            b, err = st["b"], st["b_standard_error"]
            z = (b - reference) / math.sqrt(err ** 2 + ref_error ** 2)
            rows.append({"setting": setting, "seed": seed, "b": b, "error": err,
                         "samples": st.get("b_samples", st["bootstrap_samples"]),
                         "largest_share": st.get("b_largest_share", 0.0),
                         "image_mean": mean_luminance(image), "z": z,
                         "normalisation_seconds": st.get("normalisation_seconds", 0.0),
                         "seconds": st["seconds"]})
    with open(os.path.join(args.out, "results.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

    print(f"BDPT: {reference:.6g} +- {ref_error:.2g} ({args.bdpt_seeds} runs of {args.bdpt_spp} spp, "
          f"{args.size}x{args.size})\n")
    print("| setting | seed | b | printed error | samples behind b | largest sample / b | "
          "image mean / BDPT | z | normalisation s / render s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['setting']} | {r['seed']} | {r['b']:.5g} | {r['error']:.2g} | {r['samples']:,} | "
              f"{r['largest_share']:.2g} | {r['image_mean'] / reference:.4f} | {r['z']:+.2f} | "
              f"{r['normalisation_seconds']:.1f} / {r['seconds']:.1f} |")
    print()
    for setting in ("bootstrap alone", "beside the chains"):
        zs = [r["z"] for r in rows if r["setting"] == setting]
        print(f"- {setting}: mean z^2 = {sum(z * z for z in zs) / len(zs):.2f} over {len(zs)} seeds")


if __name__ == "__main__":
    main()
