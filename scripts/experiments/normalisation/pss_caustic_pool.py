#!/usr/bin/env python3
"""pssmlt's and mmlt's images against BDPT on the caustic pool with a small bootstrap: does
the image match BDPT's within the error the engine prints for b?

    pss_caustic_pool.py --emlt build/emlt --out DIR [--integrator pssmlt] [--size 16]
        [--max-depth 8] [--bootstrap 2048] [--mpp 4096] [--seeds 8] [--old-emlt OLD]

For each seed: the integrator at --mpp with --bootstrap samples, and the same with OLD (an
emlt built before the chains' part of the image was scaled by the converging b, whose image
is scaled by the bootstrap's b) when given. BDPT's mean luminance over --bdpt-seeds runs of
--bdpt-spp is the reference, with its standard error across them. Prints, per run, the image
mean over BDPT's, b and its printed error, and z = (image mean - BDPT) / sqrt((b's relative
error x image mean)^2 + BDPT's error^2); per setting, the mean z^2 (1 when the errors are
honest) and the spread of b over the seeds against the mean printed error."""
import argparse
import json
import math
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, REPO)
from tools.images import read_pfm  # noqa: E402

SCENE = os.path.join(REPO, "scenes", "caustic-pool", "scene.json")


def mean_luminance(path):
    pixels = read_pfm(path)
    lum = 0.212671 * pixels[..., 0] + 0.715160 * pixels[..., 1] + 0.072169 * pixels[..., 2]
    return float(lum.mean())


def render(emlt, out, name, args, stats):
    image = os.path.join(out, name + ".pfm")
    stats_path = os.path.join(out, name + ".json")
    if not os.path.exists(image):
        cmd = [emlt, "render", SCENE, "-q", "-o", image] + args
        if stats:
            cmd += ["--stats", stats_path]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return image, stats_path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--emlt", required=True)
    parser.add_argument("--old-emlt")
    parser.add_argument("--out", required=True)
    parser.add_argument("--integrator", default="pssmlt", choices=["pssmlt", "mmlt"])
    parser.add_argument("--size", type=int, default=16)
    parser.add_argument("--max-depth", type=int, default=8)
    parser.add_argument("--bootstrap", type=int, default=2048)
    parser.add_argument("--mpp", type=float, default=4096)
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--bdpt-spp", type=int, default=4096)
    parser.add_argument("--bdpt-seeds", type=int, default=4)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    common = ["--width", str(args.size), "--height", str(args.size), "--max-depth",
              str(args.max_depth), "--threads", str(args.threads)]

    bdpt = [mean_luminance(render(args.emlt, args.out, f"bdpt-{s}",
                                  common + ["--integrator", "bdpt", "--spp", str(args.bdpt_spp),
                                            "--seed", str(s)], False)[0])
            for s in range(1, args.bdpt_seeds + 1)]
    reference = sum(bdpt) / len(bdpt)
    ref_error = math.sqrt(sum((x - reference) ** 2 for x in bdpt) / (len(bdpt) - 1) / len(bdpt))
    print(f"BDPT {reference:.6f} +- {ref_error:.2g}")

    settings = [("converging b", args.emlt)]
    if args.old_emlt:
        settings.append(("bootstrap's b", args.old_emlt))
    for label, emlt in settings:
        bs, errors, z2 = [], [], 0.0
        for seed in range(1, args.seeds + 1):
            name = f"{args.integrator}-{'old' if emlt == args.old_emlt else 'new'}-{seed}"
            image, stats_path = render(
                emlt, args.out, name,
                common + ["--integrator", args.integrator, "--bootstrap", str(args.bootstrap),
                          "--mpp", f"{args.mpp:g}", "--seed", str(seed)], True)
            with open(stats_path) as f:
                st = json.load(f)
            mean = mean_luminance(image)
            b, err = st["b"], st["b_standard_error"]
            z = (mean - reference) / math.hypot(err / b * mean, ref_error)
            z2 += z * z / args.seeds
            bs.append(b)
            errors.append(err)
            print(f"{label} seed {seed}: image / BDPT {mean / reference:.4f}, b {b:.6f} +- {err:.2g} "
                  f"(bootstrap {st['bootstrap_b']:.6f}, {st['b_samples']} samples, largest "
                  f"{st['b_largest_share']:.2g} of b), z {z:+.2f}")
        b_mean = sum(bs) / len(bs)
        spread = math.sqrt(sum((x - b_mean) ** 2 for x in bs) / (len(bs) - 1))
        print(f"{label}: mean z^2 {z2:.2f}; b {b_mean:.6f}, spread over seeds {spread / b_mean:.2%}, "
              f"mean printed error {sum(errors) / len(errors) / b_mean:.2%}")


if __name__ == "__main__":
    main()
