#!/usr/bin/python3
"""Error of the Metropolis chains alone, measured without a reference image.

    scripts/chain_variance.py scenes/cornell-box/scene.json --seeds 3 --budget "--time 10" \\
        --method mlt="--integrator mlt" --method emlt="--integrator emlt"

Why: with direct light rendered separately, an MCMC image is direct + chains.  Its MSE
against a reference also holds the direct image's noise and the reference's own noise, and
at a few seconds on a small image those floors can exceed the chains' error (on the Cornell
box at 64x64 they were 94 % of MLT's MSE in 5 s).  This script renders every method with
seeds 1..K and, for each seed, the very direct image the renderer used (`--integrator direct`
with the same seed and samples gives the same bits), subtracts it, and reports:

  chains' variance   the per-pixel variance across seeds of (image - direct image), summed
                     over RGB and averaged over pixels: the chains' MSE, since the chains are
                     unbiased (the convergence tests check that).
  ideal              the same figure for an ideal sampler that draws independent paths in
                     proportion to the chains' target (luminance) at the same mutations per
                     pixel, assuming one colour per pixel: a yardstick, not a hard bound.
  FIRST/this         the first method's chains' variance over this one's: above 1, this
                     method beats the first.

The mean chains' image over every run of every method stands in for the true one in the
ideal figure.  Runs go one at a time, so equal-time budgets are fair.  Renders go through the
Python module built beside --emlt (BUILD/python), in this process, else through the binary
(--engine cli forces it); --mpi R spawns `mpirun -n R emlt render ...` for each.  Needs numpy.
"""
import argparse
import json
import os
import re
import shlex
import sys
import tempfile

import numpy as np

# The image helpers are tools.images, in the repository's Python package at the root; run as
# scripts/chain_variance.py, Python puts this folder on the path, not the root.
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tools.engine import EngineError, EngineMissing, choose  # noqa: E402
from tools.images import read_pfm  # noqa: E402

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def read_image(path):
    """A PFM as (pixels, 3) float64."""
    return read_pfm(path).reshape(-1, 3).astype(np.float64)


def run(engine, args, output):
    """Renders `emlt render ARGS` unless `output` was made by the same arguments before (--out
    keeps them in OUTPUT.args: the engine, module or binary, may change; what it renders may
    not); on failure exits with the engine's own one-line error."""
    record = output + ".args"
    arguments = shlex.join(["render"] + args)
    if os.path.exists(output) and os.path.exists(record):
        with open(record) as f:
            if f.read() == arguments:
                return
    try:
        engine.render(args)
    except EngineMissing as error:
        sys.exit(f"chain_variance: {error}")
    except EngineError as error:
        sys.exit(f"chain_variance: {os.path.basename(output)}: {error}")
    with open(record, "w") as f:
        f.write(arguments)


def ideal_variance_per_mutation(chains_mean):
    """Mean over pixels of the variance an ideal independent sampler reaches with one
    mutation per pixel (divide by the mutations per pixel)."""
    image = np.clip(chains_mean, 0.0, None)
    lum = image @ LUMINANCE
    lit = lum > 0
    per_pixel = np.zeros(len(lum))
    per_pixel[lit] = lum.mean() * (image[lit] ** 2).sum(axis=1) / lum[lit]
    return per_pixel.mean()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--method", action="append", required=True, metavar="NAME=ARGS",
                        help="a method: a name and its engine arguments (repeatable)")
    parser.add_argument("--budget", required=True, help='engine budget, e.g. "--time 10" or "--mpp 64"')
    parser.add_argument("--seeds", type=int, default=3, help="seeds 1..K (K >= 2; default 3)")
    parser.add_argument("--direct-spp", type=int, default=512, help="samples of the direct image (default 512)")
    parser.add_argument("--threads", type=int, default=0, help="engine threads (default: all)")
    parser.add_argument("--width", type=int)
    parser.add_argument("--height", type=int)
    parser.add_argument("--emlt", default=os.path.join(os.path.dirname(__file__), "..", "build", "emlt"),
                        help="the emlt binary; its build's Python module renders unless --engine cli")
    parser.add_argument("--engine", choices=("auto", "module", "cli"), default="auto",
                        help="render through the Python module beside --emlt (auto: when built) or the binary")
    parser.add_argument("--mpi", type=int, metavar="R", help="spawn `mpirun -n R emlt render ...` for each render")
    parser.add_argument("--json", help="also write the figures to this JSON file")
    parser.add_argument("--out", help="keep the images here, and reuse those that the same "
                        "engine arguments made (default: a temporary directory)")
    args = parser.parse_args()
    if args.seeds < 2:
        parser.error("--seeds must be at least 2")
    if args.mpi is not None and args.mpi < 1:
        parser.error("--mpi must be at least 1")
    methods = []
    for spec in args.method:
        name, sep, engine_args = spec.partition("=")
        if not sep or not name:
            parser.error(f"--method {spec!r}: expected NAME=ARGS")
        if not re.fullmatch(r"[A-Za-z0-9._-]+", name) or name == "direct":
            parser.error(f"--method {spec!r}: the name must be letters, digits, '.', '_' or '-', "
                         "and not 'direct'")
        if name in (m[0] for m in methods):
            parser.error(f"--method {name}: given twice")
        methods.append((name, shlex.split(engine_args)))

    try:
        engine = choose(args.emlt, args.engine, args.mpi)
    except EngineError as error:
        sys.exit(f"chain_variance: {error}")
    work = args.out or tempfile.mkdtemp(prefix="chain_variance.")
    os.makedirs(work, exist_ok=True)
    common = [args.scene, "--quiet", "--threads", str(args.threads)]
    if args.width:
        common += ["--width", str(args.width)]
    if args.height:
        common += ["--height", str(args.height)]

    direct = {}
    for seed in range(1, args.seeds + 1):
        path = os.path.join(work, f"direct.{seed}.pfm")
        run(engine, [*common, "--integrator", "direct", "--spp", str(args.direct_spp), "--seed", str(seed),
                     "-o", path], path)
        direct[seed] = read_image(path)

    results = []
    for name, engine_args in methods:
        chains, mpp, seconds = [], [], []
        for seed in range(1, args.seeds + 1):
            stem = os.path.join(work, f"{name}.{seed}")
            run(engine, [*common, *engine_args, *shlex.split(args.budget), "--direct", "separate",
                         "--direct-spp", str(args.direct_spp), "--seed", str(seed), "-o", stem + ".pfm",
                         "--stats", stem + ".json"], stem + ".json")
            chains.append(read_image(stem + ".pfm") - direct[seed])
            with open(stem + ".json") as f:
                stats = json.load(f)
            mpp.append(stats["mutations"] / len(direct[seed]))
            seconds.append(stats["seconds"])
        chains = np.stack(chains)
        variance = chains.var(axis=0, ddof=1).sum(axis=1).mean()
        results.append((name, np.mean(mpp), np.mean(seconds), variance, chains.mean(axis=0)))

    ideal_one = ideal_variance_per_mutation(np.mean([r[4] for r in results], axis=0))
    rows = [{"method": name, "mutations_per_pixel": m, "seconds": s, "chains_variance": v,
             "ideal_variance": ideal_one / m if m > 0 else None} for name, m, s, v, _ in results]
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"scene": args.scene, "budget": args.budget, "seeds": args.seeds, "methods": rows}, f,
                      indent=1)

    def ratio(a, b):
        return f"{a / b:.2f}" if a is not None and b else "-"

    first = rows[0]["chains_variance"]
    print(f"{args.scene}, {args.budget}, seeds 1-{args.seeds}, direct light {args.direct_spp} spp")
    print(f"{'method':<16}{'mpp':>10}{'seconds':>9}{'chains var':>12}{'ideal':>11}{'x ideal':>9}"
          f"{rows[0]['method'] + '/this':>12}")
    for row in rows:
        ideal = row["ideal_variance"]
        print(f"{row['method']:<16}{row['mutations_per_pixel']:>10.1f}{row['seconds']:>9.2f}"
              f"{row['chains_variance']:>12.3e}{'-' if ideal is None else f'{ideal:.3e}':>11}"
              f"{ratio(row['chains_variance'], ideal):>9}{ratio(first, row['chains_variance']):>12}")
    print(f"(images in {work}; rendered by {engine.describe()})")


if __name__ == "__main__":
    main()
