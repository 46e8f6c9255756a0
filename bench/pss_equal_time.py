#!/usr/bin/env python3
"""Equal-time error of the MCMC baselines on the Cornell box.

Every method renders the same scene for the same wall-clock budget, several seeds each,
runs interleaved so that a change in machine load touches every method alike. Two figures
per method, over the pixels that do not see the emitter (`emlt compare --scene`):
  - MSE against a reference image (--reference; a long path-traced render), and
  - the variance from seed pairs: half the mean squared difference of two seeds' images,
    which needs no reference (every method is unbiased, so its MSE is its variance).

  bench/pss_equal_time.py --out DIR [--time 30] [--seeds 1 2 3 4] [--reference REF.exr]
  bench/pss_equal_time.py --out DIR --make-reference SECONDS   # the reference, by pt
"""
import argparse
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EMLT = os.path.join(ROOT, "build", "emlt")
SCENE = os.path.join(ROOT, "scenes", "cornell-box", "scene.json")

METHODS = {
    "pt": ["--integrator", "pt"],
    "mlt": ["--integrator", "mlt"],
    "pssmlt": ["--integrator", "pssmlt"],
    "pssmlt-bdpt": ["--integrator", "pssmlt", "--pss-tracer", "bdpt"],
    "mmlt": ["--integrator", "mmlt"],
}


def render(args, out, extra, seconds=None, seed=1):
    cmd = [EMLT, "render", SCENE, "--width", str(args.size), "--height", str(args.size),
           "--threads", str(args.threads), "--seed", str(seed), "-o", out] + extra
    if seconds is not None:
        cmd += ["--time", str(seconds)]
    t0 = time.time()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.time() - t0


def compare(reference, images, emlt=EMLT):
    """`emlt compare --json` of each image against the reference, over the Cornell box's
    pixels that do not see the emitter (also used by tungsten_equal_time.py)."""
    out = subprocess.run([emlt, "compare", "--json", "--scene", SCENE, reference] + images,
                         check=True, capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.strip()]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", required=True)
    p.add_argument("--time", type=float, default=30)
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    p.add_argument("--methods", nargs="+", default=list(METHODS))
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--reference")
    p.add_argument("--make-reference", type=float, metavar="SECONDS")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)

    if args.make_reference:
        ref = os.path.join(args.out, "reference.exr")
        render(args, ref, ["--integrator", "pt"], args.make_reference, seed=1000)
        print(ref)
        return

    images = {m: [] for m in args.methods}
    for seed in args.seeds:  # interleaved: one seed of every method, then the next
        for m in args.methods:
            img = os.path.join(args.out, f"{m}-s{seed}.exr")
            if not os.path.exists(img):
                wall = render(args, img, METHODS[m], args.time, seed)
                print(f"{m} seed {seed}: {wall:.1f} s", file=sys.stderr, flush=True)
            images[m].append(img)

    results = {}
    for m, imgs in images.items():
        row = {}
        pairs = [compare(imgs[i], [imgs[i + 1]])[0]["mse_no_emitter"] / 2
                 for i in range(0, len(imgs) - 1, 2)]
        row["seed_pair_variance"] = pairs
        if args.reference:
            row["mse_vs_reference"] = [r["mse_no_emitter"] for r in compare(args.reference, imgs)]
        results[m] = row
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump({"time_s": args.time, "threads": args.threads, "size": args.size,
                   "load_before": os.getloadavg(), "results": results}, f, indent=1)

    base = results.get("pt")
    print(f"| method | variance from seed pairs | MSE vs reference | / pt |")
    print(f"|---|---|---|---|")
    for m, row in results.items():
        var = sum(row["seed_pair_variance"]) / max(1, len(row["seed_pair_variance"]))
        mse = row.get("mse_vs_reference")
        mse_mean = sum(mse) / len(mse) if mse else None
        key = mse_mean if mse_mean is not None else var
        if base:
            bm = base.get("mse_vs_reference")
            bkey = sum(bm) / len(bm) if bm else sum(base["seed_pair_variance"]) / len(
                base["seed_pair_variance"])
            ratio = f"{key / bkey:.2f}"
        else:
            ratio = "-"
        mse_txt = f"{mse_mean:.3g}" if mse_mean is not None else "-"
        print(f"| {m} | {var:.3g} | {mse_txt} | {ratio} |")


if __name__ == "__main__":
    main()
