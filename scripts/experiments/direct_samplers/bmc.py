#!/usr/bin/python3
"""Bayesian Monte Carlo with spherical Gaussians (Marques et al., TVCG 2013; seed 002 and seed
000 chapter 3) against Monte Carlo importance sampling and spherical Fibonacci: relative RMSE
against the number of directions per shading point, and its fitted log-log slope beside the
paper's (BMC n^-0.72, MC importance sampling n^-0.50, [BMC] Fig. 5).

    scripts/experiments/direct_samplers/bmc.py --emlt build/emlt --out out/bmc

Scenes, written here: balls and a floor, all glossy (Mitsuba's normalised `phong`, exponents
20, 50 and 80, no diffuse term: the paper's figures measure the glossy component) or all
diffuse, each under
  - sunsky: the engine's sun and sky (Mitsuba's `sunsky`), a high-dynamic-range sky whose sun
    disk is orders of magnitude brighter than the sky;
  - smooth: a smooth synthetic lat-long map written by this script (a sky gradient and three
    broad Gaussian blobs, a dynamic range of about 30).

Methods, each with D directions per shading point (D = 16 ... 512):
  - MC BSDF        D independent BSDF samples (--mis second-order --mis-alpha 0): the paper's
                   MCIS;
  - MC MIS         D/2 light and D/2 BSDF samples, power heuristic (the engine's default);
  - Fibonacci MIS  the same with randomised spherical Fibonacci sets (--direct-sampler fibonacci);
  - BMC            --direct-sampler bmc: D directions (D/2 per lobe where there are two), the
                   fast hyperparameter rule.
Camera rays go through the pixel centres (a Gaussian pixel filter of 0.003 pixel) and one per
pixel, so that the error is the direct-lighting estimator's alone. The reference is the mean of
two Fibonacci MIS renders (other seeds) of --ref-directions directions per pixel; its own mean
squared error, a quarter of theirs from each other, is subtracted from every method's (it would
otherwise set a floor under the curves). The error is the RMSE over pixels, channels and seeds,
relative to the reference image's mean (the paper's RMSE is absolute; a slope does not care).

Writes into --out: results.csv, table.md, bmc.png (log-log plots), and runs/ (images; a rerun
resumes).
"""
import argparse
import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, REPO)
sys.path.insert(0, HERE)

import numpy as np  # noqa: E402

from tools.images import write_pfm  # noqa: E402
from direct_scenes import (DIFFUSE, GLOSSY, balls_scene, envmap, pyplot, render_direct,  # noqa: E402
                           smooth_map, sunsky)

METHODS = {
    "MC BSDF": lambda d: ["--mis", "second-order", "--mis-alpha", "0", "--direct-samples", str(d // 2)],
    "MC MIS": lambda d: ["--direct-samples", str(d // 2)],
    "Fibonacci MIS": lambda d: ["--direct-sampler", "fibonacci", "--direct-samples", str(d // 2)],
    "BMC": lambda d: ["--direct-sampler", "bmc", "--direct-samples", str(d // 2)],
}
PAPER_SLOPES = {"MC BSDF": -0.50, "BMC": -0.72}

def write_scenes(out):
    folder = os.path.join(out, "scenes")
    os.makedirs(folder, exist_ok=True)
    smooth = os.path.join(folder, "smooth.pfm")
    if not os.path.exists(smooth):
        write_pfm(smooth, smooth_map())
    paths = {}
    for material_name, materials in (("glossy", GLOSSY), ("diffuse", DIFFUSE)):
        for light_name, emitter in (("sunsky", sunsky()), ("smooth", envmap("smooth.pfm"))):
            path = os.path.join(folder, f"{material_name}-{light_name}.xml")
            with open(path, "w") as f:
                f.write(balls_scene("bmc.py", emitter, materials))
            paths[f"{material_name}, {light_name}"] = path
    return paths


def render(emlt, scene, args, seed, common, out):
    return render_direct(emlt, scene, args, seed, common, out, "bmc")


def slope(ns, errors):
    return float(np.polyfit(np.log(ns), np.log(errors), 1)[0])


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--emlt", default=os.path.join(REPO, "build", "emlt"))
    p.add_argument("--out", default=os.path.join(REPO, "out", "bmc"))
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--directions", default="16,32,64,128,256,512")
    p.add_argument("--ref-directions", type=int, default=32768)
    p.add_argument("--threads", type=int, default=2)
    a = p.parse_args()

    scenes = write_scenes(a.out)
    ns = [int(x) for x in a.directions.split(",")]
    common = ["--spp", "1", "--threads", str(a.threads)]
    rows = []
    for scene_name, scene in scenes.items():
        slug = scene_name.replace(", ", "-")
        refs = [render(a.emlt, scene, METHODS["Fibonacci MIS"](a.ref_directions), seed, common,
                       os.path.join(a.out, "runs", slug, f"reference-{seed}.pfm"))
                for seed in (1000, 1001)]
        reference = 0.5 * (refs[0] + refs[1])
        reference_mse = float(np.mean((refs[0] - refs[1]) ** 2)) / 4.0
        scale = float(np.mean(reference))
        rows.append({"scene": scene_name, "method": "reference", "directions": a.ref_directions,
                     "relative_rmse": float(np.sqrt(reference_mse) / scale)})
        for m, args in METHODS.items():
            for n in ns:
                errors = []
                for seed in range(1, a.seeds + 1):
                    name = "".join(c if c.isalnum() else "-" for c in m)
                    img = render(a.emlt, scene, args(n), seed, common,
                                 os.path.join(a.out, "runs", slug, name, f"d{n}-seed{seed}.pfm"))
                    errors.append(np.mean((img - reference) ** 2))
                mse = max(float(np.mean(errors)) - reference_mse, 0.0)
                rows.append({"scene": scene_name, "method": m, "directions": n,
                             "relative_rmse": float(np.sqrt(mse) / scale)})
            print(scene_name, m, " ".join(f"{r['relative_rmse']:.3g}" for r in rows
                                          if r["scene"] == scene_name and r["method"] == m),
                  flush=True)

    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    names = list(scenes)
    floors = "; ".join(f"{r['scene']} {r['relative_rmse']:.2g}" for r in rows
                       if r["method"] == "reference")
    lines = [f"48x48, one camera ray per pixel through its centre, {a.seeds} seeds; relative RMSE "
             f"against the mean of two Fibonacci MIS renders of {a.ref_directions} directions, "
             f"whose own relative RMSE ({floors}) is taken out; D directions per shading point.",
             "", "| scene | method | " + " | ".join(f"D={n}" for n in ns) + " | slope | paper |",
             "|---|---|" + "---|" * len(ns) + "---|---|"]
    slopes = {}
    for s in names:
        for m in METHODS:
            e = [r["relative_rmse"] for r in rows if r["scene"] == s and r["method"] == m]
            slopes[(s, m)] = slope(ns, e)
            paper = PAPER_SLOPES.get(m)
            lines.append(f"| {s} | {m} | " + " | ".join(f"{x:.3g}" for x in e) +
                         f" | {slopes[(s, m)]:.2f} | " + (f"{paper:.2f}" if paper else "") + " |")
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    plt = pyplot("bmc")
    if plt is None:
        return
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 4))
    for ax, s in zip(axes, names):
        for m in METHODS:
            e = [r["relative_rmse"] for r in rows if r["scene"] == s and r["method"] == m]
            ax.loglog(ns, e, "o-", label=f"{m} ({slopes[(s, m)]:.2f})")
        ax.set_title(s)
        ax.set_xlabel("directions per shading point")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("relative RMSE")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "bmc.png"), dpi=110)


if __name__ == "__main__":
    main()
