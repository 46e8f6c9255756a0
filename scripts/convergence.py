#!/usr/bin/python3
"""Convergence plot: MSE against samples per pixel for emlt's integrators.

Renders a reference once (high spp), then each integrator at 1, 2, 4, ... spp with
several seeds, and plots MSE (mean over pixels and RGB) against spp on log-log axes,
the seeds' spread as a band. Uses only numpy and matplotlib (Debian's python3-*). Renders
through the Python module (`import emlt`, set up by scripts/setup.sh: the same images, bit
for bit, with no files in between) when it imports, else through the binary (--emlt).

    scripts/convergence.py scenes/cornell-box/scene.json --out docs/convergence.png
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

# The image helpers are tools.images, in the repository's Python package at the root; run as
# scripts/convergence.py, Python puts this folder on the path, not the root.
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from tools.images import read_pfm  # noqa: E402  (shared with ablation.py)


# Integrators whose per-pixel budget is mutations (--mpp) rather than samples (--spp).
MCMC_INTEGRATORS = ("mlt", "gamlt", "memlt", "emlt", "pssmlt", "mmlt")


def cli_renderer(emlt, scene, out, extra):
    """Renders by spawning the binary and reading its PFM back."""
    def render(integrator, spp, seed):
        budget = "--mpp" if integrator in MCMC_INTEGRATORS else "--spp"
        cmd = [emlt, "render", scene, "-o", out, "--integrator", integrator, budget, str(spp),
               "--seed", str(seed), "--quiet"] + extra
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        return read_pfm(out)
    return render


def module_renderer(module, scene_path, size, max_depth):
    """Renders in this process through `import emlt`: the scene is loaded once."""
    scene = module.load(scene_path)

    def render(integrator, spp, seed):
        budget = {"mpp" if integrator in MCMC_INTEGRATORS else "spp": spp}
        image, _ = module.render(scene, integrator, seed=seed, width=size, height=size,
                                 max_depth=max_depth, progress=False, **budget)
        return image
    return render


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--out", default="convergence.png")
    parser.add_argument("--emlt", default="build/emlt")
    parser.add_argument("--integrators", default="pt,direct")
    parser.add_argument("--max-spp", type=int, default=64)
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--size", type=int, default=128, help="image width and height")
    parser.add_argument("--max-depth", type=int, default=-1)
    args = parser.parse_args()

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    extra = ["--width", str(args.size), "--height", str(args.size), "--max-depth", str(args.max_depth)]
    spps = [2 ** k for k in range(0, int(np.log2(args.max_spp)) + 1)]
    try:
        import emlt as module
    except ImportError:
        module = None
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "img.pfm")
        if module is not None:
            render_at = module_renderer(module, args.scene, args.size, args.max_depth)
        else:
            print("convergence: no Python module (import emlt); rendering with " + args.emlt,
                  file=sys.stderr)
            render_at = cli_renderer(args.emlt, args.scene, out, extra)
        references = {}
        fig, ax = plt.subplots(figsize=(6, 4.2))
        for integrator in args.integrators.split(","):
            # Each integrator converges to its own reference (direct is one bounce only).
            print(f"reference: {integrator} at {args.reference_spp} spp", file=sys.stderr)
            references[integrator] = render_at(integrator, args.reference_spp, 1000)
            errors = np.zeros((args.seeds, len(spps)))
            for s in range(args.seeds):
                for i, spp in enumerate(spps):
                    image = render_at(integrator, spp, s + 1)
                    errors[s, i] = np.mean((image - references[integrator]) ** 2)
            mean = errors.mean(axis=0)
            ax.loglog(spps, mean, "o-", label=integrator)
            ax.fill_between(spps, errors.min(axis=0), errors.max(axis=0), alpha=0.25)
            for spp, e in zip(spps, mean):
                print(f"{integrator}\t{spp}\t{e:.6g}")
        ax.loglog(spps, mean[0] / np.array(spps, dtype=float), "k--", lw=0.8, label="1/N")
        ax.set_xlabel("samples per pixel")
        ax.set_ylabel("MSE against own reference")
        ax.set_title(os.path.basename(os.path.dirname(os.path.abspath(args.scene))))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.out, dpi=110)
        print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
