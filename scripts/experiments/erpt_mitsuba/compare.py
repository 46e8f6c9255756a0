#!/usr/bin/env python3
"""emlt's erpt and Mitsuba 0.6's erpt on the same scene file, side by side: each at a few
seed counts (the file's sampleCount set by -Dspp / --spp), its wall time, its image's mean
over the reference's and its MSE against the reference; and MSE x seconds, the figure that
stays put as an unbiased render runs longer (lower is better at equal time).

    compare.py --emlt build/emlt --mitsuba /path/to/dist/mitsuba [--scene integrator-erpt]
               [--spp 16,64] [--threads 2] --out DIR > table.md

The scene is a conformance scene (tests/conformance/scenes/NAME.xml, which takes -Dspp) and
the reference its committed image (tests/conformance/references/NAME.pfm)."""
import argparse
import os
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, REPO)
from tools.images import read_pfm  # noqa: E402

SUITE = os.path.join(REPO, "tests", "conformance")


def timed(cmd, cwd, env=None):
    start = time.monotonic()
    result = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"compare: {' '.join(cmd)} failed: {result.stderr.strip() or result.stdout.strip()}")
    return time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--emlt", required=True)
    parser.add_argument("--mitsuba", required=True)
    parser.add_argument("--scene", default="integrator-erpt")
    parser.add_argument("--spp", default="16,64")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--direct-samples", type=int, default=None,
                        help="rewrite the file's directSamples (-1: both leave the direct light "
                             "to the chains)")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    scene = os.path.join("scenes", args.scene + ".xml")
    if args.direct_samples is not None:  # a copy beside the original, for its relative paths
        with open(os.path.join(SUITE, scene)) as f:
            text = f.read()
        marker = '<integer name="directSamples" value="'
        start = text.index(marker) + len(marker)
        text = text[:start] + str(args.direct_samples) + text[text.index('"', start):]
        scene = os.path.join("scenes", f".compare-{args.scene}.xml")
        with open(os.path.join(SUITE, scene), "w") as f:
            f.write(text)
    reference = read_pfm(os.path.join(SUITE, "references", args.scene + ".pfm"))
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.dirname(os.path.abspath(args.mitsuba)))
    print(f"Scene `tests/conformance/scenes/{args.scene}.xml`"
          f"{'' if args.direct_samples is None else f' with directSamples {args.direct_samples}'} against `references/{args.scene}.pfm`, "
          f"{args.threads} threads.\n")
    print("| renderer | spp | seed | seconds | mean / reference | MSE | MSE x seconds |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for spp in [int(s) for s in args.spp.split(",")]:
        for seed in range(1, args.seeds + 1):
            runs = []
            out = os.path.abspath(os.path.join(args.out, f"emlt-{spp}-{seed}.pfm"))
            seconds = timed([os.path.abspath(args.emlt), "render", scene, "--spp", str(spp),
                             "--seed", str(seed), "--threads", str(args.threads), "-q", "-o", out],
                            SUITE)
            runs.append(("emlt erpt", out, seconds))
            # Mitsuba 0.6's samplers draw the same numbers whatever their seed, so its runs
            # differ only by thread scheduling: one run per count.
            if seed == 1:
                out = os.path.abspath(os.path.join(args.out, f"mitsuba-{spp}.pfm"))
                seconds = timed([os.path.abspath(args.mitsuba), "-q", "-p", str(args.threads),
                                 f"-Dspp={spp}", scene, "-o", out], SUITE, env)
                runs.append(("Mitsuba 0.6 erpt", out, seconds))
            for name, path, seconds in runs:
                image = read_pfm(path)
                mse = float(((image - reference) ** 2).mean())
                ratio = float(image.mean() / reference.mean())
                print(f"| {name} | {spp} | {seed if name.startswith('emlt') else '-'} | "
                      f"{seconds:.2f} | {ratio:.4f} | {mse:.3g} | {mse * seconds:.3g} |")
    if args.direct_samples is not None:
        os.remove(os.path.join(SUITE, scene))


if __name__ == "__main__":
    main()
