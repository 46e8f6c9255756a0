#!/usr/bin/python3
"""Lu's cube-face environment sampler (thesis 004, chapter 3) against the lat-long texel table
and BSDF sampling: variance per direction (N Var).

    scripts/experiments/direct_samplers/cube_env.py --emlt build/emlt --out out/cube-env

Two scenes, written here: a floor and four balls (three diffuse, one rough plastic; their
surfaces face every way) under
  - sunsky: the engine's sun-and-sky model (Mitsuba's `sunsky`: Hosek-Wilkie sky, Preetham
    sun; the sun disk is orders of magnitude brighter than the sky), a low morning sun;
  - studio: a synthetic lat-long studio map (dark surround, two large softboxes, a small hot
    rim light behind the balls and a faint floor bounce), written by this script.

Every method renders with `direct` at the same number of directions per camera ray, --seeds
times. Camera rays go through the pixel centres (a Gaussian pixel filter of 0.003 pixel), so
that the variance across seeds is the direct-lighting estimator's alone. For each pixel
N Var = (variance across seeds) x (directions per pixel); the table gives its mean over the
pixels (and over the colour channels) relative to the lat-long table combined with BSDF
sampling by the balance heuristic (today's default sampler), and the median over pixels of
the per-pixel ratio cube / lat-long (the mean is decided by the brightest pixels; the median
says how the typical pixel fares).

Methods (D directions per camera ray):
  - BSDF only              --mis second-order --mis-alpha 0 (all D from the BSDF)
  - lat-long only          --mis second-order --mis-alpha 1 (all D from the lat-long table)
  - cube-balanced only     the same with --env-sampler cube-balanced (Lu's Eq. 3.4)
  - cube, uniform faces / faces by mass, only: the same with --env-face-balance uniform
                           (mu_f = 1/6, the thesis's Fig. 3.6 comparison) or mass (mu_f ~ I_f,
                           a global luminance CDF over the cube)
  - lat-long + BSDF        --mis balance, D/2 of each
  - cube-balanced + BSDF   --mis balance --env-sampler cube-balanced, D/2 of each (Eq. 3.7),
                           the light half shared by fractional counts (Eqs. 3.5-3.6)
  - the same, faces drawn per sample: --env-face-counts sampled (each light sample draws its
                           face with probability mu_f)
  - cube, uniform faces, + BSDF: the same with uniform faces
  - cube-balanced only / + BSDF, 512 per face: with --env-cube-resolution 512 (the default
                           is a quarter of the map's width, 128 here)

Writes into --out: results.csv, table.md, ratio-<scene>.png (per-pixel N Var ratio,
cube-balanced + BSDF over lat-long + BSDF), bars.png, and runs/ (images; a rerun resumes).
"""
import argparse
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, REPO)
sys.path.insert(0, HERE)

import numpy as np  # noqa: E402

from tools.images import read_pfm, write_pfm  # noqa: E402
from direct_scenes import envmap, latlong_directions, pyplot, sunsky  # noqa: E402

CUBE = ["--env-sampler", "cube-balanced"]
LIGHT_ONLY = ["--mis", "second-order", "--mis-alpha", "1"]
METHODS = {
    "BSDF only": ["--mis", "second-order", "--mis-alpha", "0"],
    "lat-long only": LIGHT_ONLY,
    "cube-balanced only": LIGHT_ONLY + CUBE,
    "cube, uniform faces, only": LIGHT_ONLY + CUBE + ["--env-face-balance", "uniform"],
    "cube, faces by mass, only": LIGHT_ONLY + CUBE + ["--env-face-balance", "mass"],
    "lat-long + BSDF": ["--mis", "balance"],
    "cube-balanced + BSDF": ["--mis", "balance"] + CUBE,
    "cube-balanced + BSDF, faces drawn per sample": ["--mis", "balance"] + CUBE +
                                                    ["--env-face-counts", "sampled"],
    "cube, uniform faces, + BSDF": ["--mis", "balance"] + CUBE + ["--env-face-balance", "uniform"],
    # The default face resolution is a quarter of the map's width (128 for both maps here);
    # a sun of a few texels is drawn closer to its shape from finer faces.
    "cube-balanced only, 512 per face": LIGHT_ONLY + CUBE + ["--env-cube-resolution", "512"],
    "cube-balanced + BSDF, 512 per face": ["--mis", "balance"] + CUBE +
                                          ["--env-cube-resolution", "512"],
}
BASELINE = "lat-long + BSDF"

SUNSKY = sunsky(hour=8)

STUDIO = envmap("studio.pfm")

SCENE = """<?xml version="1.0" encoding="utf-8"?>
<!-- written by scripts/experiments/direct_samplers/cube_env.py -->
<scene version="0.6.0">
  <integrator type="direct"/>
  <sensor type="perspective">
    <float name="fov" value="45"/>
    <transform name="toWorld"><lookat origin="0, 2.2, 4.2" target="0, 0.45, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="4"/></sampler>
    <film type="hdrfilm">
      <integer name="width" value="64"/><integer name="height" value="64"/>
      <rfilter type="gaussian"><float name="stddev" value="0.003"/></rfilter>
    </film>
  </sensor>
  {emitter}
  <shape type="sphere"><point name="center" x="-1.1" y="0.45" z="0"/><float name="radius" value="0.45"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.75, 0.75, 0.75"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0" y="0.45" z="-0.3"/><float name="radius" value="0.45"/>
    <bsdf type="roughplastic"><float name="alpha" value="0.1"/>
      <rgb name="diffuseReflectance" value="0.6, 0.1, 0.1"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="1.1" y="0.45" z="0"/><float name="radius" value="0.45"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.3, 0.8"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0.3" y="0.2" z="0.9"/><float name="radius" value="0.2"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.7, 0.3"/></bsdf></shape>
  <shape type="rectangle">
    <transform name="toWorld"><scale value="6"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>
  </shape>
</scene>
"""


def studio_map(width=512):
    """A studio-like lat-long map (Mitsuba's envmap convention: row 0 at the zenith, +Y up,
    azimuth atan2(x, -z) from the left edge)."""
    d, theta = latlong_directions(width)
    img = np.zeros(d.shape)
    img[...] = 0.03  # dark surround
    img[theta > 0.55 * np.pi] = [0.06, 0.055, 0.05]  # faint bounce from a grey floor

    def box(centre, half_width, radiance):
        c = np.array(centre, float)
        c /= np.linalg.norm(c)
        # angular box about c: both tangent coordinates within half_width
        t1 = np.cross(c, [0, 1, 0])
        if np.linalg.norm(t1) < 1e-6:
            t1 = np.array([1.0, 0, 0])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(t1, c)
        along = d @ c
        inside = (along > 0) & (np.abs(d @ t1) < half_width[0] * along) & \
                 (np.abs(d @ t2) < half_width[1] * along)
        img[inside] = radiance

    box([-1.0, 0.8, 0.6], (0.45, 0.35), [30.0, 29.0, 27.0])   # key softbox, front left, high
    box([1.0, 0.4, 0.3], (0.35, 0.5), [9.0, 9.5, 10.0])       # fill softbox, right
    box([0.2, 0.5, -1.0], (0.6, 0.04), [400.0, 380.0, 350.0])  # hot rim strip behind the balls
    return img.astype(np.float32)


def write_scenes(out):
    folder = os.path.join(out, "scenes")
    os.makedirs(folder, exist_ok=True)
    studio = os.path.join(folder, "studio.pfm")
    if not os.path.exists(studio):
        write_pfm(studio, studio_map())
    paths = {}
    for name, emitter in (("sunsky", SUNSKY), ("studio", STUDIO)):
        path = os.path.join(folder, f"{name}.xml")
        with open(path, "w") as f:
            f.write(SCENE.replace("{emitter}", emitter))
        paths[name] = path
    return paths


def render(emlt, scene, args, seed, common, out):
    if os.path.exists(out):
        return
    os.makedirs(os.path.dirname(out), exist_ok=True)
    cmd = [emlt, "render", scene, "--integrator", "direct", "--seed", str(seed), "-o", out,
           "--quiet"] + common + args
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"cube_env: {' '.join(cmd)} failed: {run.stderr.strip()[-400:]}")
    with open(out + ".json", "w") as f:
        json.dump({"command": cmd}, f)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--emlt", default=os.path.join(REPO, "build", "emlt"))
    p.add_argument("--out", default=os.path.join(REPO, "out", "cube-env"))
    p.add_argument("--seeds", type=int, default=8)
    p.add_argument("--size", type=int, default=64)
    p.add_argument("--spp", type=int, default=4, help="camera rays per pixel")
    p.add_argument("--directions", type=int, default=64, help="directions per camera ray (even)")
    p.add_argument("--threads", type=int, default=2)
    a = p.parse_args()

    scenes = write_scenes(a.out)
    common = ["--spp", str(a.spp), "--width", str(a.size), "--height", str(a.size),
              "--threads", str(a.threads)]
    per_pixel_directions = a.spp * a.directions
    rows, ratio_maps = [], {}
    for scene_name, scene in scenes.items():
        images = {m: [] for m in METHODS}
        for seed in range(1, a.seeds + 1):
            for m, args in METHODS.items():
                # The mixture draws all D directions from one strategy at alpha 0 or 1;
                # balance draws D/2 of each (--direct-samples counts pairs for both).
                extra = ["--direct-samples", str(a.directions // 2)]
                slug = "".join(c if c.isalnum() else "-" for c in m).strip("-")
                out = os.path.join(a.out, "runs", scene_name, slug, f"seed-{seed}.pfm")
                render(a.emlt, scene, args + extra, seed, common, out)
                images[m].append(read_pfm(out).astype(np.float64))
        nvar = {m: per_pixel_directions * np.mean(np.var(np.stack(images[m]), axis=0, ddof=1), axis=2)
                for m in METHODS}
        means = {m: np.mean(np.stack(images[m]), axis=0) for m in METHODS}
        base = nvar[BASELINE]
        lit = base > 0
        ratio = np.where(lit, nvar["cube-balanced + BSDF"] / np.where(lit, base, 1), np.nan)
        ratio_maps[scene_name] = ratio
        half = a.seeds // 2
        for m in METHODS:
            halves = []
            for part in (slice(0, half), slice(half, None)):
                v = [np.mean(np.var(np.stack(images[k][part]), axis=0, ddof=1)) for k in (m, BASELINE)]
                halves.append(v[0] / v[1])
            per_pixel = nvar[m][lit] / base[lit]
            rows.append({
                "scene": scene_name, "method": m,
                "mean_nvar": float(np.mean(nvar[m])),
                "relative_mean_nvar": float(np.mean(nvar[m]) / np.mean(base)),
                "halves": " ".join(f"{x:.3g}" for x in halves),
                "median_pixel_ratio": float(np.median(per_pixel)),
                "pixels_better": float(np.mean(per_pixel < 1.0)),
                "image_mean": float(np.mean(means[m])),
            })
        print(f"{scene_name}: " + ", ".join(
            f"{r['method']} {r['relative_mean_nvar']:.3g}" for r in rows if r["scene"] == scene_name),
            flush=True)

    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    names = list(scenes)
    lines = [f"{a.size}x{a.size}, {a.spp} camera rays per pixel through the pixel centres, "
             f"{a.directions} directions per ray, {a.seeds} seeds. Mean N Var over pixels "
             f"relative to {BASELINE} (in brackets: from each half of the seeds); median over "
             f"pixels of the per-pixel ratio; share of pixels where the method's N Var is below "
             f"{BASELINE}'s; image mean (all methods are unbiased: these agree within noise).", "",
             "| method | " + " | ".join(f"{s} mean N Var | {s} median | {s} pixels better"
                                       for s in names) + " |",
             "|---|" + "---|---|---|" * len(names)]
    for m in METHODS:
        cells = []
        for s in names:
            r = next(r for r in rows if r["scene"] == s and r["method"] == m)
            lo, hi = sorted(float(x) for x in r["halves"].split())
            cells += [f"{r['relative_mean_nvar']:.3g} ({lo:.2g}-{hi:.2g})",
                      f"{r['median_pixel_ratio']:.3g}", f"{100 * r['pixels_better']:.0f} %"]
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    lines += ["", "Image means: " + "; ".join(
        f"{s}: " + ", ".join(f"{r['method']} {r['image_mean']:.4g}" for r in rows if r["scene"] == s)
        for s in names)]
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    plt = pyplot("cube_env")
    if plt is None:
        return
    fig, axes = plt.subplots(1, len(names) + 1, figsize=(5 * (len(names) + 1), 4.2))
    x = np.arange(len(METHODS))
    for k, s in enumerate(names):
        values = [next(r for r in rows if r["scene"] == s and r["method"] == m)["relative_mean_nvar"]
                  for m in METHODS]
        axes[0].bar(x + (k - 0.5) * 0.38, values, 0.38, label=s)
    axes[0].set_yscale("log")
    axes[0].set_xticks(x)
    axes[0].set_xticklabels(list(METHODS), rotation=30, ha="right", fontsize=8)
    axes[0].axhline(1.0, color="k", lw=0.6)
    axes[0].set_ylabel(f"mean N Var / {BASELINE}")
    axes[0].legend()
    for k, s in enumerate(names):
        im = axes[k + 1].imshow(np.log2(ratio_maps[s]), cmap="coolwarm", vmin=-3, vmax=3)
        axes[k + 1].set_title(f"{s}: log2 N Var, cube-balanced / lat-long\n(blue: cube better)",
                              fontsize=9)
        axes[k + 1].axis("off")
        fig.colorbar(im, ax=axes[k + 1], fraction=0.046)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "cube_env.png"), dpi=110)


if __name__ == "__main__":
    main()
