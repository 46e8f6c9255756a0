#!/usr/bin/python3
"""Szécsi et al.'s adaptive sampling for environment mapping (seed 001) against BSDF sampling,
environment-table sampling and MIS: L2 error (RMSE) against directions per pixel, and CPU time
per direction.

    scripts/experiments/direct_samplers/adaptive.py --emlt build/emlt --out out/adaptive

Scenes, written here: a floor and four balls seen from above, all diffuse ("diffuse") or the
balls glossy (Phong exponent 5, the paper's Fig. 7, and a rough plastic; "glossy"), under
  - sunsky: the engine's sun-and-sky model (Mitsuba's `sunsky`, a low morning sun: a disk of
    0.54 degrees orders of magnitude brighter than the sky);
  - lobe: the paper's analytic sky of section 4.5.1, L = 1 + 319 max(0, w.s)^8, dynamic range
    1 to 320 as in its Fig. 6, rasterised to a 512x256 lat-long map.

Every method renders with `direct`, one camera ray per pixel through its centre (a Gaussian
filter of 0.003 pixel: the error is the direct-lighting estimator's alone), D directions per
pixel, --seeds times; the RMSE against a reference (MIS with 4096 directions per pixel) is
averaged over the seeds (as squared error). Methods (D directions per pixel):
  - BSDF           --mis second-order --mis-alpha 0: all D by BSDF sampling, the paper's
                   "classic BRDF sampling" baseline (independent points; the paper used a
                   Halton sequence with a random start, see docs/direct-samplers.md)
  - env table      --mis second-order --mis-alpha 1: all D from the lat-long luminance table
  - MIS            --mis power (the engine's default): D/2 of each
  - Halton cells, equal  --direct-sampler adaptive --adaptive-initial 65536: the same cells
                   split evenly, never by the error: Halton points with a random first index
                   through the cosine map, which for a diffuse surface is the paper's own
                   baseline (BRDF sampling by a randomly started Halton sequence); it
                   computes no derivatives
  - adaptive       --direct-sampler adaptive: D directions, the paper's diffuse (cosine)
                   parametrisation, one root cell, robustness c = 1
  - adaptive, c = 16  the same with --adaptive-robustness 16 (closer to equal cells)
  - adaptive, global  the same with --adaptive-parametrisation global (section 4.1)

Writes into --out: results.csv, table.md, adaptive.png (RMSE against D), runs/.
"""
import argparse
import csv
import json
import os
import resource
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, REPO)
sys.path.insert(0, HERE)

import numpy as np  # noqa: E402

from tools.images import read_pfm, write_pfm  # noqa: E402
from direct_scenes import envmap, latlong_directions, pyplot, sunsky  # noqa: E402

METHODS = {
    "BSDF": ["--mis", "second-order", "--mis-alpha", "0"],
    "env table": ["--mis", "second-order", "--mis-alpha", "1"],
    "MIS": ["--mis", "power"],
    "Halton cells, equal": ["--direct-sampler", "adaptive", "--adaptive-initial", "65536"],
    "adaptive": ["--direct-sampler", "adaptive"],
    "adaptive, c = 16": ["--direct-sampler", "adaptive", "--adaptive-robustness", "16"],
    "adaptive, global": ["--direct-sampler", "adaptive", "--adaptive-parametrisation", "global"],
}
REFERENCE = ["--mis", "power"]
REFERENCE_DIRECTIONS = 4096

SUNSKY = sunsky(hour=8)

LOBE = envmap("lobe.pfm")

DIFFUSE_BALLS = ['<bsdf type="diffuse"><rgb name="reflectance" value="0.75, 0.75, 0.75"/></bsdf>',
                 '<bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.1, 0.1"/></bsdf>',
                 '<bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.3, 0.8"/></bsdf>']
GLOSSY_BALLS = ['<bsdf type="phong"><float name="exponent" value="5"/>'
                '<rgb name="specularReflectance" value="0.6, 0.6, 0.6"/>'
                '<rgb name="diffuseReflectance" value="0.1, 0.1, 0.1"/></bsdf>',
                '<bsdf type="roughplastic"><float name="alpha" value="0.1"/>'
                '<rgb name="diffuseReflectance" value="0.6, 0.1, 0.1"/></bsdf>',
                '<bsdf type="phong"><float name="exponent" value="20"/>'
                '<rgb name="specularReflectance" value="0.5, 0.5, 0.6"/>'
                '<rgb name="diffuseReflectance" value="0.1, 0.15, 0.3"/></bsdf>']

SCENE = """<?xml version="1.0" encoding="utf-8"?>
<!-- written by scripts/experiments/direct_samplers/adaptive.py -->
<scene version="0.6.0">
  <integrator type="direct"/>
  <sensor type="perspective">
    <float name="fov" value="45"/>
    <transform name="toWorld"><lookat origin="0, 2.2, 4.2" target="0, 0.45, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
    <film type="hdrfilm">
      <integer name="width" value="64"/><integer name="height" value="64"/>
      <rfilter type="gaussian"><float name="stddev" value="0.003"/></rfilter>
    </film>
  </sensor>
  {emitter}
  <shape type="sphere"><point name="center" x="-1.1" y="0.45" z="0"/><float name="radius" value="0.45"/>{b0}</shape>
  <shape type="sphere"><point name="center" x="0" y="0.45" z="-0.3"/><float name="radius" value="0.45"/>{b1}</shape>
  <shape type="sphere"><point name="center" x="1.1" y="0.45" z="0"/><float name="radius" value="0.45"/>{b2}</shape>
  <shape type="sphere"><point name="center" x="0.3" y="0.2" z="0.9"/><float name="radius" value="0.2"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.7, 0.3"/></bsdf></shape>
  <shape type="rectangle">
    <transform name="toWorld"><scale value="6"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>
  </shape>
</scene>
"""


def lobe_map(width=512):
    """Section 4.5.1's sky, L_sky + L_sun max(0, w.s)^s with L_sky = 1, L_sun = 319, s = 8, in
    Mitsuba's envmap convention (row 0 at the zenith, +Y up, azimuth atan2(x, -z))."""
    d, theta = latlong_directions(width)
    s = np.array([-0.5, 0.6, 0.4])
    s /= np.linalg.norm(s)
    lum = 1.0 + 319.0 * np.maximum(d @ s, 0.0) ** 8
    return np.repeat(lum[..., None], 3, axis=2).astype(np.float32)


def write_scenes(out):
    folder = os.path.join(out, "scenes")
    os.makedirs(folder, exist_ok=True)
    lobe = os.path.join(folder, "lobe.pfm")
    if not os.path.exists(lobe):
        write_pfm(lobe, lobe_map())
    paths = {}
    for sky, emitter in (("sunsky", SUNSKY), ("lobe", LOBE)):
        for finish, balls in (("diffuse", DIFFUSE_BALLS), ("glossy", GLOSSY_BALLS)):
            path = os.path.join(folder, f"{sky}-{finish}.xml")
            with open(path, "w") as f:
                f.write(SCENE.replace("{emitter}", emitter).replace("{b0}", balls[0])
                        .replace("{b1}", balls[1]).replace("{b2}", balls[2]))
            paths[f"{sky}-{finish}"] = path
    return paths


def child_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_engine(cmd):
    before = child_cpu_seconds()
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"adaptive: {' '.join(cmd)} failed: {run.stderr.strip()[-400:]}")
    return child_cpu_seconds() - before


def load_seconds(emlt, scene):
    """CPU seconds of loading the scene and writing an image: a 1x1 render, least of three."""
    cmd = [emlt, "render", scene, "--integrator", "direct", "--quiet", "--spp", "1",
           "--width", "1", "--height", "1", "--threads", "1", "--direct-samples", "1", "-o",
           os.path.join(tempfile.gettempdir(), f"adaptive-load-{os.getpid()}.pfm")]
    return min(run_engine(cmd) for _ in range(3))


def render(emlt, scene, args, seed, common, out, load):
    """One render to out (.pfm); its CPU seconds less the scene's loading (cached beside it)."""
    meta = out + ".json"
    if os.path.exists(out) and os.path.exists(meta):
        with open(meta) as f:
            return json.load(f)["seconds"]
    os.makedirs(os.path.dirname(out), exist_ok=True)
    cmd = [emlt, "render", scene, "--integrator", "direct", "--seed", str(seed), "-o", out,
           "--quiet"] + common + args
    seconds = max(run_engine(cmd) - load, 1e-6)
    with open(meta, "w") as f:
        json.dump({"seconds": seconds, "command": cmd}, f)
    return seconds


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--emlt", default=os.path.join(REPO, "build", "emlt"))
    p.add_argument("--out", default=os.path.join(REPO, "out", "adaptive"))
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--size", type=int, default=64)
    p.add_argument("--directions", default="8,32,128", help="directions per pixel (even)")
    p.add_argument("--scenes", default="sunsky-diffuse,sunsky-glossy,lobe-diffuse,lobe-glossy")
    a = p.parse_args()

    scenes = write_scenes(a.out)
    directions = [int(x) for x in a.directions.split(",")]
    common = ["--spp", "1", "--width", str(a.size), "--height", str(a.size), "--threads", "1"]
    rows = []
    for name in a.scenes.split(","):
        scene = scenes[name]
        load = load_seconds(a.emlt, scene)
        ref_path = os.path.join(a.out, "runs", name, "reference.pfm")
        render(a.emlt, scene, REFERENCE + ["--direct-samples", str(REFERENCE_DIRECTIONS // 2)],
               1000, common, ref_path, load)
        reference = read_pfm(ref_path).astype(np.float64)
        for d in directions:
            for m, args in METHODS.items():
                slug = "".join(c if c.isalnum() else "-" for c in m).strip("-")
                squared, seconds, means = [], [], []
                for seed in range(1, a.seeds + 1):
                    out = os.path.join(a.out, "runs", name, slug, f"d{d}-seed-{seed}.pfm")
                    seconds.append(render(a.emlt, scene, args + ["--direct-samples", str(d // 2)],
                                          seed, common, out, load))
                    image = read_pfm(out).astype(np.float64)
                    squared.append(np.mean((image - reference) ** 2))
                    means.append(np.mean(image))
                rows.append({
                    "scene": name, "method": m, "directions": d,
                    "rmse": float(np.sqrt(np.mean(squared))),
                    "relative_rmse": float(np.sqrt(np.mean(squared)) / np.mean(reference)),
                    "relative_bias": float((np.mean(means) - np.mean(reference)) /
                                           np.mean(reference)),
                    "us_per_direction": float(1e6 * np.mean(seconds) / (d * a.size * a.size)),
                })
            print(f"{name} D={d}: " + ", ".join(
                f"{r['method']} {r['relative_rmse']:.3g}" for r in rows
                if r["scene"] == name and r["directions"] == d), flush=True)

    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    names = a.scenes.split(",")
    lines = [f"{a.size}x{a.size}, one camera ray per pixel through its centre, {a.seeds} seeds; "
             f"RMSE relative to the reference's mean (MIS, {REFERENCE_DIRECTIONS} directions per "
             f"pixel); in brackets the ratio to BSDF sampling's RMSE at the same D. Time: CPU "
             f"microseconds per direction, one thread, less the scene's loading, mean over D. "
             f"The RMSE includes each method's bias (adaptive sampling's is given below).", ""]
    for name in names:
        lines += [f"**{name}**", "",
                  "| method | " + " | ".join(f"D = {d}" for d in directions) + " | µs/direction |",
                  "|---|" + "---|" * len(directions) + "---|"]
        for m in METHODS:
            cells = []
            for d in directions:
                r = next(r for r in rows if r["scene"] == name and r["method"] == m
                         and r["directions"] == d)
                b = next(r for r in rows if r["scene"] == name and r["method"] == "BSDF"
                         and r["directions"] == d)
                cells.append(f"{r['relative_rmse']:.3g} ({r['rmse'] / b['rmse']:.2f})")
            t = np.mean([r["us_per_direction"] for r in rows
                         if r["scene"] == name and r["method"] == m])
            lines.append(f"| {m} | " + " | ".join(cells) + f" | {t:.3g} |")
        lines += ["", "Bias of the image mean, relative to the reference's (mean over the seeds):",
                  "", "| method | " + " | ".join(f"D = {d}" for d in directions) + " |",
                  "|---|" + "---|" * len(directions)]
        for m in METHODS:
            cells = [f"{100 * next(r for r in rows if r['scene'] == name and r['method'] == m and r['directions'] == d)['relative_bias']:+.2g} %"
                     for d in directions]
            lines.append(f"| {m} | " + " | ".join(cells) + " |")
        lines.append("")
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    plt = pyplot("adaptive")
    if plt is None:
        return
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 3.8))
    for ax, name in zip(np.atleast_1d(axes), names):
        for m in METHODS:
            ys = [next(r for r in rows if r["scene"] == name and r["method"] == m
                       and r["directions"] == d)["relative_rmse"] for d in directions]
            ax.loglog(directions, ys, "o-", label=m)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("directions per pixel")
        ax.set_ylabel("relative RMSE")
    np.atleast_1d(axes)[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "adaptive.png"), dpi=110)


if __name__ == "__main__":
    main()
