#!/usr/bin/python3
"""Randomised point sets for direct lighting, the spherical Fibonacci papers' experiment
([SF] Tab. 1 = [T] Tab. 2.1, seeds 000 chapter 2 and 002): RMSE against the number of points
per set for independent, spherical Fibonacci, scrambled Sobol, scrambled
Larcher-Pillichshammer and blue-noise-like points, and each set's RMSE at 512 points and the
points it needs to match spherical Fibonacci's RMSE at 512, beside the papers' "up to" +38.7 %
/ +36.6 % / +8.7 % and +56 % / +49.1 % / +17.8 % (Sobol / blue noise (BNOT) / L-P).

    scripts/experiments/direct_samplers/point_sets.py --emlt build/emlt --out out/point_sets

Scenes (direct_scenes.py): balls and a floor, all diffuse or all glossy (normalised Phong,
exponents 20-80), under a smooth lat-long map ("smooth", dynamic range about 30) or the
engine's sun and sky ("sunsky": a 0.54-degree sun orders of magnitude brighter than the sky);
and "box", a Cornell-like interior lit by a small area light under its ceiling (diffuse walls,
a glossy ball), the papers' kind of scene.

Every method renders `direct`, one camera ray per pixel through its centre (a Gaussian filter
of 1e-5 pixel), with N light samples and N BSDF samples per pixel (--direct-samples N: two
sets of N points, one fed to light sampling, one to BSDF sampling; MIS by the power
heuristic), --seeds times:
  - independent             i.i.d. uniform points
  - fibonacci               spherical Fibonacci in the square (Lambert's map), random rotation
                            and Cranley-Patterson shift
  - sobol                   the first N points of Sobol's (0,2)-sequence, random digit
                            scrambling (Kollig-Keller)
  - larcher-pillichshammer  the L-P (0,m,2)-net (a net at powers of two only), scrambled alike
  - blue-noise              a periodic set with a large minimum distance, toroidal shift
The reference is the mean of --ref-renders renders of --ref-samples points per set (other
seeds), drawn in turn by spherical Fibonacci, Sobol, L-P and blue-noise sets: each is
unbiased and independent of the images it judges, and at 32,768 points they reach the
accuracy the low-discrepancy sets need at 512, which independent sampling would reach only
with hundreds of times as many (under the sun, on glossy balls, an independent reference's
own error was above the sets' error at 384 points). Its own mean squared error, the renders'
spread over their count (which holds for renders of different variances too), is subtracted
from every method's. The error is the RMSE over pixels, channels and seeds, relative to the
reference's mean. N = 384 is not a power of two: there Sobol's first points are a 256-net and
a 128-net, L-P's are no net at all.

Writes into --out: results.csv, table.md, point_sets.png (log-log plots), runs/ (images; a
rerun resumes).
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
from direct_scenes import (DIFFUSE, GLOSSY, balls_scene, box_scene, envmap, pyplot,  # noqa: E402
                           render_direct, smooth_map, sunsky)

METHODS = ["independent", "fibonacci", "sobol", "larcher-pillichshammer", "blue-noise"]
LABELS = {"independent": "independent", "fibonacci": "spherical Fibonacci", "sobol": "Sobol",
          "larcher-pillichshammer": "Larcher-Pillichshammer", "blue-noise": "blue noise"}
# [SF] Tab. 1 / [T] Tab. 2.1: the text's "up to" figures (RMSE at 512 rays over SF, rays to
# match SF), then the range over the table's 12 entries per set (3 scenes, glossy and diffuse,
# Lambert and Shirley-Chiu projections).
PAPER = {"sobol": ("+38.7 %", "+56 %", "+2.1 … +38.7 %", "+3.1 … +56.0 %"),
         "blue-noise": ("+36.6 % (BNOT)", "+49.1 %", "+1.2 … +36.6 %", "+1.6 … +53.4 %"),
         "larcher-pillichshammer": ("+8.7 %", "+17.8 %", "+0.6 … +24.6 %", "+0.4 … +29.8 %")}
# The pixel filter's width in pixels: camera rays through the pixel centres, closer than the
# default 0.003, which leaves silhouette pixels whose error no point set reduces.
STDDEV = "0.00001"
# The reference's renders take these sets in turn (see above).
REFERENCE_SETS = ["fibonacci", "sobol", "larcher-pillichshammer", "blue-noise"]
SCENES = ["diffuse-smooth", "glossy-smooth", "diffuse-sunsky", "glossy-sunsky", "box"]


def write_scenes(out):
    folder = os.path.join(out, "scenes")
    os.makedirs(folder, exist_ok=True)
    smooth = os.path.join(folder, "smooth.pfm")
    if not os.path.exists(smooth):
        write_pfm(smooth, smooth_map())
    texts = {"box": box_scene("point_sets.py", STDDEV)}
    for material_name, materials in (("diffuse", DIFFUSE), ("glossy", GLOSSY)):
        for light_name, emitter in (("smooth", envmap("smooth.pfm")), ("sunsky", sunsky())):
            texts[f"{material_name}-{light_name}"] = balls_scene("point_sets.py", emitter,
                                                                  materials, STDDEV)
    paths = {}
    for name, text in texts.items():
        paths[name] = os.path.join(folder, f"{name}.xml")
        with open(paths[name], "w") as f:
            f.write(text)
    return paths


def method_args(method, n):
    return ["--direct-sampler", method, "--direct-samples", str(n)]


def local_slope(ns, errors, last=3):
    """Log-log slope through the last `last` powers of two (the rays-to-match extrapolation)."""
    pts = [(n, e) for n, e in zip(ns, errors) if n & (n - 1) == 0][-last:]
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--emlt", default=os.path.join(REPO, "build", "emlt"))
    p.add_argument("--out", default=os.path.join(REPO, "out", "point_sets"))
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--size", type=int, default=32)
    p.add_argument("--samples", default="16,32,64,128,256,384,512",
                   help="points per set (light and BSDF sets each)")
    p.add_argument("--ref-samples", type=int, default=32768)
    p.add_argument("--ref-renders", type=int, default=4)
    p.add_argument("--scenes", default=",".join(SCENES))
    p.add_argument("--threads", type=int, default=2)
    a = p.parse_args()

    paths = write_scenes(a.out)
    names = a.scenes.split(",")
    ns = [int(x) for x in a.samples.split(",")]
    top = max(ns)
    common = ["--spp", "1", "--width", str(a.size), "--height", str(a.size), "--threads",
              str(a.threads)]
    rows, curves, per_seed = [], {}, {}
    for name in names:
        scene = paths[name]
        ref_sets = [REFERENCE_SETS[k % len(REFERENCE_SETS)] for k in range(a.ref_renders)]
        refs = np.stack([render_direct(a.emlt, scene, method_args(ref_sets[k], a.ref_samples),
                                       1000 + k, common,
                                       os.path.join(a.out, "runs", name,
                                                    f"reference-{k}-{ref_sets[k]}.pfm"),
                                       "point_sets")
                         for k in range(a.ref_renders)])
        reference = refs.mean(axis=0)
        # The mean's own squared error: the renders' per-pixel variance over their count.
        reference_mse = float(np.mean(refs.var(axis=0, ddof=1))) / a.ref_renders
        scale = float(np.mean(reference))
        rows.append({"scene": name, "method": "reference", "samples": a.ref_samples,
                     "relative_rmse": float(np.sqrt(reference_mse) / scale)})
        for m in METHODS:
            errors = []
            for n in ns:
                mses = []
                for seed in range(1, a.seeds + 1):
                    img = render_direct(a.emlt, scene, method_args(m, n), seed, common,
                                        os.path.join(a.out, "runs", name, m,
                                                     f"n{n}-seed{seed}.pfm"),
                                        "point_sets")
                    mses.append(float(np.mean((img - reference) ** 2)))
                per_seed[(name, m, n)] = [max(x - reference_mse, 0.0) for x in mses]
                rmse = float(np.sqrt(max(np.mean(mses) - reference_mse, 0.0)) / scale)
                errors.append(rmse)
                rows.append({"scene": name, "method": m, "samples": n, "relative_rmse": rmse})
            curves[(name, m)] = errors
            print(name, m, " ".join(f"{e:.3g}" for e in errors), flush=True)

    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)

    floors = "; ".join(f"{r['scene']} {r['relative_rmse']:.2g}" for r in rows
                       if r["method"] == "reference")
    lines = [f"{a.size}x{a.size} pixels, one camera ray per pixel through its centre, {a.seeds} "
             f"seeds; N light and N BSDF points per pixel. Relative RMSE against the mean of "
             f"{a.ref_renders} renders of {a.ref_samples} points per set (by "
             f"{', '.join(REFERENCE_SETS[:a.ref_renders])}), whose own "
             f"relative RMSE ({floors}) is taken out.", "",
             "Relative RMSE against N:", "",
             "| scene | set | " + " | ".join(f"N={n}" for n in ns) + " | slope |",
             "|---|---|" + "---|" * len(ns) + "---|"]
    for s in names:
        for m in METHODS:
            e = curves[(s, m)]
            powers = [(n, x) for n, x in zip(ns, e) if n & (n - 1) == 0]
            fit = np.polyfit(np.log([q[0] for q in powers]), np.log([q[1] for q in powers]), 1)[0]
            lines.append(f"| {s} | {m} | " + " | ".join(f"{x:.3g}" for x in e) +
                         f" | {fit:.2f} |")

    i_top = ns.index(top)
    lines += ["", f"At N = {top} against spherical Fibonacci: RMSE over SF's (± a jackknife "
              f"standard error over the seeds) and the points the set needs to reach SF's "
              f"RMSE at {top} (extrapolated along the set's slope through its last three "
              f"powers of two), beside [SF] Tab. 1.", "",
              "| scene | set | RMSE over SF | points to match SF | paper: up to (RMSE, rays) | "
              "paper: range over Tab. 1 |", "|---|---|---|---|---|---|"]
    summary = []
    for s in names:
        sf = curves[(s, "fibonacci")][i_top]
        for m in METHODS:
            if m == "fibonacci":
                continue
            e = curves[(s, m)]
            ratio = e[i_top] / sf
            # Jackknife over seeds of the RMSE ratio.
            a_seeds, b_seeds = per_seed[(s, m, top)], per_seed[(s, "fibonacci", top)]
            k = len(a_seeds)
            if k > 1:
                jack = [np.sqrt(np.mean(np.delete(a_seeds, j)) / np.mean(np.delete(b_seeds, j)))
                        for j in range(k)]
                se = float(np.sqrt((k - 1) / k * np.sum((np.array(jack) - np.mean(jack)) ** 2)))
            else:
                se = float("nan")
            slope = local_slope(ns, e)
            needed = top * ratio ** (-1.0 / slope) if slope < 0 else float("inf")
            paper = PAPER.get(m, ("—", "—", "—", "—"))
            summary.append({"scene": s, "method": m, "ratio": ratio, "se": se, "needed": needed})
            lines.append(f"| {s} | {m} | {100 * (ratio - 1):+.1f} % ± {100 * se:.1f} | "
                         f"{needed:.0f} ({100 * (needed / top - 1):+.0f} %) | "
                         f"{paper[0]}, {paper[1]} | {paper[2]}, {paper[3]} |".replace("inf", "∞"))
    if 384 in ns and 256 in ns and 512 in ns:
        i256, i384, i512 = ns.index(256), ns.index(384), ns.index(512)
        lines += ["", "At N = 384 (not a power of two): RMSE over the log-log line through "
                  "N = 256 and 512 (0 % on the line; above it, the set lost structure there).",
                  "", "| scene | " + " | ".join(METHODS) + " |", "|---|" + "---|" * len(METHODS)]
        for s in names:
            cells = []
            for m in METHODS:
                e = curves[(s, m)]
                line = np.exp(np.interp(np.log(384), np.log([256, 512]),
                                        np.log([e[i256], e[i512]])))
                cells.append(f"{100 * (e[i384] / line - 1):+.1f} %")
            lines.append(f"| {s} | " + " | ".join(cells) + " |")
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(a.out, "summary.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["scene", "method", "ratio", "se", "needed"])
        w.writeheader()
        w.writerows(summary)
    print("\n".join(lines))

    plt = pyplot("point_sets")
    if plt is None:
        return
    fig, axes = plt.subplots(1, len(names), figsize=(3.3 * len(names), 3.4), squeeze=False)
    for ax, s in zip(axes[0], names):
        for m in METHODS:
            ax.loglog(ns, curves[(s, m)], "o-", ms=3, lw=1, label=LABELS[m])
        ax.set_title(s, fontsize=9)
        ax.set_xlabel("points per set N", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", lw=0.3)
    axes[0][0].set_ylabel("relative RMSE", fontsize=8)
    axes[0][0].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "point_sets.png"), dpi=80)


if __name__ == "__main__":
    main()
