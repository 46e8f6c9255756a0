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
import resource
import subprocess
import sys
import tempfile

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


def child_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_engine(cmd):
    """Runs one engine call; returns the CPU seconds it took (user + system)."""
    before = child_cpu_seconds()
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"mis_alpha: {' '.join(cmd)} failed: {run.stderr.strip()[-400:]}")
    return child_cpu_seconds() - before


def load_seconds(emlt, scene, common):
    """CPU seconds of loading the scene and writing an image: a 1x1 render, least of three."""
    cmd = [emlt, "render", scene, "--integrator", "direct", "--quiet", "--spp", "1",
           "--width", "1", "--height", "1", "--threads", "1", "--direct-samples", "1", "-o",
           os.path.join(tempfile.gettempdir(), f"mis-alpha-load-{os.getpid()}.pfm")]
    return min(run_engine(cmd) for _ in range(3))


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


def render(emlt, scene, args, seed, common, out, load):
    """One render to out (.pfm); returns its CPU seconds less the scene's loading (cached
    next to the image). CPU time rather than the clock: on a machine shared with other
    work the clock's seconds of renders doing nearly the same work (balance and power on the
    kitchen) differed by 2.7x."""
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
    p.add_argument("--trim", type=float, default=0.001,
                   help="share of pixels (largest balance variance) left out of the trimmed figure")
    a = p.parse_args()

    common = ["--spp", str(a.spp), "--width", str(a.size), "--height", str(a.size),
              "--threads", str(a.threads)]
    table = methods(a.directions, a.pre_samples)
    rows = []
    for scene_name in a.scenes.split(","):
        scene = centred_copy(SCENES[scene_name], os.path.join(a.out, "scenes", scene_name))
        load = load_seconds(a.emlt, scene, common)
        images = {m: [] for m in table}
        seconds = {m: [] for m in table}
        for seed in range(1, a.seeds + 1):
            for name, args in table.items():
                out = os.path.join(a.out, "runs", scene_name, name.replace(" ", "-"),
                                   f"seed-{seed}.pfm")
                seconds[name].append(render(a.emlt, scene, args, seed, common, out, load))
                images[name].append(read_pfm(out).astype(np.float64))
        pixel_variance = {m: np.mean(np.var(np.stack(images[m]), axis=0, ddof=1), axis=2)
                          for m in table}
        # Trimmed: without the pixels of largest variance under the balance heuristic (a
        # --trim share), where a rare bright sample decides the variance and 8 seeds cannot
        # measure it (cornell-glass: one pixel of the glass ball showing the light through
        # refraction held 71 % of the balance heuristic's variance and moved by 4x between
        # seeds, though every split draws it the same way). Dropping the pixels where balance
        # is worst can only raise the other methods' ratios.
        order = np.argsort(pixel_variance["balance"].ravel())
        keep = np.zeros(order.size, bool)
        keep[order[: order.size - int(np.ceil(a.trim * order.size))]] = True
        variance = {m: float(np.mean(v)) for m, v in pixel_variance.items()}
        trimmed = {m: float(np.mean(v.ravel()[keep])) for m, v in pixel_variance.items()}
        # The same ratio from each half of the seeds: how far the figure itself is settled.
        half = a.seeds // 2

        def halves(m):
            return [float(np.mean(np.var(np.stack(images[m][part]), axis=0, ddof=1).mean(
                axis=2).ravel()[keep])) for part in (slice(0, half), slice(half, None))]

        mean_seconds = {m: float(np.mean(seconds[m])) for m in table}
        base_v, base_t, base_tr = variance["balance"], mean_seconds["balance"], trimmed["balance"]
        for m in table:
            rows.append({
                "scene": scene_name, "method": m, "variance": variance[m],
                "relative_variance": variance[m] / base_v,
                "relative_variance_trimmed": trimmed[m] / base_tr,
                "trimmed_halves": " ".join(
                    f"{x / y:.3g}" for x, y in zip(halves(m), halves("balance"))),
                "cpu_seconds": mean_seconds[m],
                "relative_time": mean_seconds[m] / base_t,
                "relative_efficiency": (base_tr * base_t) / (trimmed[m] * mean_seconds[m]),
                "image_mean": float(np.mean(np.stack(images[m]))),
            })
        print(f"{scene_name}: " + ", ".join(
            f"{r['method']} {r['relative_variance_trimmed']:.3g}" for r in rows
            if r["scene"] == scene_name), flush=True)

    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    scenes = list(dict.fromkeys(r["scene"] for r in rows))

    def table_of(cell):
        out = ["| method | " + " | ".join(scenes) + " |", "|---|" + "---|" * len(scenes)]
        for m in table:
            out.append(f"| {m} | " + " | ".join(
                cell(next(r for r in rows if r["scene"] == s and r["method"] == m))
                for s in scenes) + " |")
        return out

    def trimmed_cell(r):
        lo, hi = sorted(float(x) for x in r["trimmed_halves"].split())
        return f"{r['relative_variance_trimmed']:.3g} ({lo:.2g}-{hi:.2g})"

    lines = [f"{a.size}x{a.size}, {a.spp} camera rays per pixel through the pixel centres, "
             f"{a.directions} directions per ray, {a.seeds} seeds, {a.threads} thread(s); "
             f"against the balance heuristic.", "",
             "Relative variance, all pixels:", ""]
    lines += table_of(lambda r: f"{r['relative_variance']:.3g}")
    lines += ["", f"Relative variance without the {100 * a.trim:g} % of pixels of largest "
              f"balance-heuristic variance (in brackets: from each half of the seeds):", ""]
    lines += table_of(trimmed_cell)
    lines += ["", "Relative CPU time (scene loading subtracted):", ""]
    lines += table_of(lambda r: f"{r['relative_time']:.3g}")
    lines += ["", "Relative efficiency, 1 / (trimmed variance x CPU time):", ""]
    lines += table_of(lambda r: f"{r['relative_efficiency']:.3g}")
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
