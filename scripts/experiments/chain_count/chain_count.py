#!/usr/bin/env python3
"""How the number of chains changes a Metropolis render's error at a fixed budget: emlt at
each chain count and seed, its wall time, and its MSE against a reference image (or, with
no reference, the variance across seeds: the mean over seed pairs of half their mean squared
difference). Prints a markdown table; the images stay in --out.

    chain_count.py --emlt build/emlt --scene scenes/caustic-pool/scene.json --size 64x64 \\
        --integrator mlt --mpp 1024,4096 --chains 1024,4096,16384 --seeds 3 \\
        --reference docs/bench/2026-12-02-memlt-mitsuba/caustic-pool-64-reference.pfm \\
        --out DIR > table.md

--chains 0 is the default rule (MltIntegrator::default_chain_count)."""
import argparse
import itertools
import os
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, REPO)
from tools.images import read_pfm  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--emlt", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--size", help="WIDTHxHEIGHT")
    parser.add_argument("--integrator", default="",
                        help="emlt's --integrator (default: the one the file names)")
    parser.add_argument("--mpp", default="1024")
    parser.add_argument("--chains", default="0")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--reference")
    parser.add_argument("--extra", default="", help="more emlt flags, space-separated")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    reference = read_pfm(args.reference) if args.reference else None
    size = []
    if args.size:
        width, height = args.size.split("x")
        size = ["--width", width, "--height", height]
    print(f"`{os.path.relpath(os.path.abspath(args.scene), REPO)}`"
          f"{' at ' + args.size if args.size else ''}"
          f"{', `--integrator ' + args.integrator + '`' if args.integrator else ''}"
          f"{' ' + args.extra if args.extra else ''}, {args.threads} threads, seeds 1-{args.seeds}; "
          + ("MSE against `" + os.path.relpath(os.path.abspath(args.reference), REPO) + "`"
             if reference is not None else "variance across seeds") + ".\n")
    column = "MSE per seed" if reference is not None else "variance across seeds"
    print(f"| mpp | chains | {column} | figure | seconds (mean) | figure x seconds |")
    print("|---:|---:|---|---:|---:|---:|")
    for mpp in [int(m) for m in args.mpp.split(",")]:
        for chains in [int(c) for c in args.chains.split(",")]:
            images, seconds = [], []
            for seed in range(1, args.seeds + 1):
                out = os.path.join(args.out, f"{mpp}-{chains}-{seed}.pfm")
                cmd = [args.emlt, "render", args.scene,
                       *(["--integrator", args.integrator] if args.integrator else []),
                       "--mpp", str(mpp), "--seed", str(seed), "--threads", str(args.threads),
                       "-q", *size, *args.extra.split(), "-o", out]
                if chains:
                    cmd += ["--chains", str(chains)]
                start = time.monotonic()
                subprocess.run(cmd, check=True)
                seconds.append(time.monotonic() - start)
                images.append(read_pfm(out))
            if reference is not None:
                errors = sorted(float(((i - reference) ** 2).mean()) for i in images)
                shown = ", ".join(f"{e:.3g}" for e in errors)
                median = errors[len(errors) // 2]
            else:
                pairs = [float(((a - b) ** 2).mean()) / 2
                         for a, b in itertools.combinations(images, 2)]
                median = sum(pairs) / len(pairs)
                shown = f"{median:.3g}"
            mean_seconds = sum(seconds) / len(seconds)
            print(f"| {mpp} | {chains or 'default'} | {shown} | {median:.3g} | "
                  f"{mean_seconds:.2f} | {median * mean_seconds:.3g} |")


if __name__ == "__main__":
    main()
