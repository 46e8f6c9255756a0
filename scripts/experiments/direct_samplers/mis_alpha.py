#!/usr/bin/python3
"""Lu's MIS split (thesis 004, chapter 5) against the balance, power and max heuristics.

    scripts/experiments/direct_samplers/mis_alpha.py --emlt build/emlt --out out/mis-alpha

Renders each scene with the `direct` integrator, every method at the same number of
directions per camera ray (--directions; balance, power and max take half from each
strategy), --seeds times with different seeds, and measures what the thesis's Tables 5.1 and
5.2 measure: the per-pixel variance across the seeds (the sampling variance), averaged over
pixels and colour channels, relative to the balance heuristic's; and the efficiency
1 / (variance x render seconds), relative to the balance heuristic's. The render seconds are
the engine's own (the preprocessed split's pre-pass included). Methods run interleaved
seed by seed, so that a change in the machine's load falls on all of them alike.

Camera rays go through the pixel centres (a tent filter of radius 0.01 pixel, written into a
copy of each scene whose other files are linked from the original folder): with the usual
jittered rays the variance of what a pixel sees inside its footprint is added to every
method alike and pulls every ratio towards 1 (at 32x32 and 64 directions it hid the
methods' differences entirely); the thesis's "sampling variance" is the estimator's alone.

This drives build/emlt directly rather than scripts/ablation.py: the runner measures error
against a reference image, and the thesis's figure is the variance across independent
renders, which needs no reference.

Writes into --out: results.csv (one row per scene and method), table.md (the table of
docs/direct-samplers.md) and runs/ (the images, kept so that an interrupted run resumes).
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, REPO)

import numpy as np  # noqa: E402

from tools.images import read_pfm  # noqa: E402

SCENES = {
    "veach-plates": os.path.join(HERE, "veach_plates.json"),
    "env-sky": os.path.join(REPO, "scenes", "env-sky", "scene.json"),
    "kitchen": os.path.join(REPO, "scenes", "kitchen", "scene.json"),
    "cornell-glass": os.path.join(REPO, "scenes", "cornell-glass", "scene.json"),
}


def methods(directions, pre_samples):
    half = str(directions // 2)
    return {
        "bsdf only": ["--mis", "second-order", "--mis-alpha", "0", "--direct-samples", half],
        "light only": ["--mis", "second-order", "--mis-alpha", "1", "--direct-samples", half],
        "balance": ["--mis", "balance", "--direct-samples", half],
        "power": ["--mis", "power", "--direct-samples", half],
        "max": ["--mis", "max", "--direct-samples", half],
        "preprocessed": ["--mis", "second-order", "--mis-alpha-estimate", "preprocessed",
                         "--mis-alpha-samples", str(pre_samples), "--direct-samples", half],
        "online": ["--mis", "second-order", "--direct-samples", half],
    }


SECONDS = re.compile(r"spp, ([0-9.eE+-]+) s,")


def link_entries(source, folder, skip):
    for entry in os.listdir(source):
        link = os.path.join(folder, entry)
        if entry != skip and not os.path.lexists(link):
            os.symlink(os.path.join(source, entry), link)


def centred_copy(scene, root):
    """A copy of the JSON scene with centred camera rays. Its folder holds links to the
    original folder's files, and sits beside links to the original's siblings, so that
    relative paths (cornell-glass reads ../cornell-box/meshes) still resolve."""
    source = os.path.dirname(scene)
    folder = os.path.join(root, os.path.basename(source))
    os.makedirs(folder, exist_ok=True)
    link_entries(os.path.dirname(source), root, os.path.basename(source))
    link_entries(source, folder, os.path.basename(scene))
    with open(scene) as f:
        desc = json.load(f)
    desc.setdefault("camera", {})["filter"] = {"type": "tent", "radius": 0.01}
    copy = os.path.join(folder, os.path.basename(scene))
    with open(copy, "w") as f:
        json.dump(desc, f, indent=1)
    return copy


def render(emlt, scene, args, seed, common, out):
    """One render to out (.pfm); returns the engine's seconds (cached next to the image)."""
    meta = out + ".json"
    if os.path.exists(out) and os.path.exists(meta):
        with open(meta) as f:
            return json.load(f)["seconds"]
    os.makedirs(os.path.dirname(out), exist_ok=True)
    cmd = [emlt, "render", scene, "--integrator", "direct", "--seed", str(seed), "-o", out,
           "--quiet"] + common + args
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"mis_alpha: {' '.join(cmd)} failed: {run.stderr.strip()[-400:]}")
    m = SECONDS.search(run.stdout + run.stderr)
    if not m:
        sys.exit(f"mis_alpha: no time in the engine's output: {run.stdout[-300:]}")
    seconds = float(m.group(1))
    with open(meta, "w") as f:
        json.dump({"seconds": seconds, "command": cmd}, f)
    return seconds


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--emlt", default=os.path.join(REPO, "build", "emlt"))
    p.add_argument("--out", default=os.path.join(REPO, "out", "mis-alpha"))
    p.add_argument("--scenes", default="veach-plates,env-sky,kitchen,cornell-glass")
    p.add_argument("--seeds", type=int, default=8)
    p.add_argument("--size", type=int, default=64, help="image width and height")
    p.add_argument("--spp", type=int, default=4, help="camera rays per pixel (the thesis: 4)")
    p.add_argument("--directions", type=int, default=256,
                   help="directions per camera ray (the thesis: N = 256 per light)")
    p.add_argument("--pre-samples", type=int, default=4096,
                   help="preprocessed: pilot directions per pixel (the thesis: 4096)")
    p.add_argument("--threads", type=int, default=1)
    a = p.parse_args()

    common = ["--spp", str(a.spp), "--width", str(a.size), "--height", str(a.size),
              "--threads", str(a.threads)]
    table = methods(a.directions, a.pre_samples)
    rows = []
    for scene_name in a.scenes.split(","):
        scene = centred_copy(SCENES[scene_name], os.path.join(a.out, "scenes", scene_name))
        images = {m: [] for m in table}
        seconds = {m: [] for m in table}
        for seed in range(1, a.seeds + 1):
            for name, args in table.items():
                out = os.path.join(a.out, "runs", scene_name, name.replace(" ", "-"),
                                   f"seed-{seed}.pfm")
                seconds[name].append(render(a.emlt, scene, args, seed, common, out))
                images[name].append(read_pfm(out).astype(np.float64))
        variance = {m: float(np.mean(np.var(np.stack(images[m]), axis=0, ddof=1)))
                    for m in table}
        mean_seconds = {m: float(np.mean(seconds[m])) for m in table}
        base_v, base_t = variance["balance"], mean_seconds["balance"]
        for m in table:
            rows.append({
                "scene": scene_name, "method": m, "variance": variance[m],
                "relative_variance": variance[m] / base_v, "seconds": mean_seconds[m],
                "relative_time": mean_seconds[m] / base_t,
                "relative_efficiency": (base_v * base_t) / (variance[m] * mean_seconds[m]),
                "image_mean": float(np.mean(np.stack(images[m]))),
            })
        print(f"{scene_name}: " + ", ".join(
            f"{r['method']} {r['relative_variance']:.3g}" for r in rows if r["scene"] == scene_name),
            flush=True)

    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    lines = ["| method | " + " | ".join(scenes) + " |", "|---|" + "---|" * len(scenes)]
    for m in table:
        cells = []
        for s in scenes:
            r = next(r for r in rows if r["scene"] == s and r["method"] == m)
            cells.append(f"{r['relative_variance']:.3g} / {r['relative_efficiency']:.3g}")
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write(f"Relative variance / relative efficiency against the balance heuristic; "
                f"{a.size}x{a.size}, {a.spp} camera rays per pixel, {a.directions} directions "
                f"per ray, {a.seeds} seeds, {a.threads} thread(s).\n\n")
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
