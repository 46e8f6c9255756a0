#!/usr/bin/env python3
"""Tungsten's Multiplexed MLT against emlt's mmlt and pt at equal time on the Cornell box.

The goal set for emlt's mmlt was at most half of Tungsten's MMLT error at 30 s on the
Cornell box. This script writes a Tungsten scene from our own scenes/cornell-box/scene.json
(same OBJ meshes, albedos, emission, camera, box filter, linear HDR output), then renders
Tungsten's `multiplexed_mlt`, emlt's `mmlt` and emlt's `pt` for the same wall-clock budget
and thread count, interleaved seed by seed so that a change in machine load touches all of
them alike. Figures over the pixels that do not see the emitter (`emlt compare --scene`):
  - the variance from seed pairs: half the MSE between the images of seeds (1,2), (3,4)...
  - each method's mean against emlt pt's mean (a bias check between the two renderers).

  TUNGSTEN=/path/to/tungsten bench/tungsten_equal_time.py --out DIR [--time 30]
      [--seeds 1 2 3 4] [--threads 2] [--prefix 'setsid /work/measure/hiprio.sh']
  TUNGSTEN=... bench/tungsten_equal_time.py --out DIR --check-spp 256   # equivalence check:
      Tungsten's path tracer and emlt's pt at equal spp, compared (mean ratio, MSE)

Tungsten checks its time budget after each pass (spp_step = 1 pixel sample, or w*h MMLT
mutations); its timer starts after the scene is loaded and its BVH built, and its MMLT
bootstrap (3 M candidate paths) counts inside the budget, as emlt's does. Build Tungsten
with bench/build_tungsten.sh.
"""
import argparse
import json
import os
import shlex
import shutil
import subprocess
import sys
import time

import pss_equal_time  # bench/pss_equal_time.py, beside this script: compare

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "cornell-box", "scene.json")

EMLT_METHODS = {"emlt-mmlt": ["--integrator", "mmlt"], "emlt-pt": ["--integrator", "pt"]}


def tungsten_scene(scene_path, out_dir, size, integrator, spp, spp_step=1):
    """Writes a Tungsten scene equivalent to our JSON scene; returns its path."""
    with open(scene_path) as f:
        scene = json.load(f)
    cam = scene["camera"]
    if cam.get("fov_axis", "x") != "x" and size != size:  # square image: both axes agree
        raise SystemExit("tungsten_equal_time: only a horizontal fov is converted")
    mesh_dir = os.path.join(out_dir, "meshes")
    os.makedirs(mesh_dir, exist_ok=True)
    bsdfs = [{"name": name, "type": "lambert", "albedo": m["reflectance"]}
             for name, m in scene["materials"].items() if m["type"] == "diffuse"]
    primitives = []
    for shape in scene["shapes"]:
        src = os.path.join(os.path.dirname(scene_path), shape["file"])
        shutil.copy(src, mesh_dir)
        prim = {"type": "mesh", "file": "meshes/" + os.path.basename(src),
                "bsdf": shape["material"], "smooth": False}
        if "emission" in shape:
            prim["emission"] = shape["emission"]
        primitives.append(prim)
    look = cam["lookat"]
    doc = {
        "bsdfs": bsdfs,
        "primitives": primitives,
        "camera": {
            "type": "pinhole",
            "tonemap": "linear",
            "resolution": [size, size],
            "reconstruction_filter": "box",
            "fov": cam["fov"],  # Tungsten's fov spans the image's width
            "transform": {"position": look["origin"], "look_at": look["target"],
                          "up": look["up"]},
        },
        "integrator": dict(integrator, min_bounces=0, max_bounces=64),
        "renderer": {
            "output_file": "", "hdr_output_file": "out.pfm", "overwrite_output_files": True,
            "adaptive_sampling": False, "enable_resume_render": False,
            "stratified_sampler": False, "scene_bvh": True,
            "spp": spp, "spp_step": spp_step, "checkpoint_interval": "0", "timeout": "0",
        },
    }
    path = os.path.join(out_dir, f"{integrator['type']}.json")
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
    return path


def run(prefix, cmd):
    t0 = time.time()
    subprocess.run(prefix + cmd, check=True, stdout=subprocess.DEVNULL)
    return time.time() - t0


def compare(emlt, reference, images):
    return pss_equal_time.compare(reference, images, emlt=emlt)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", required=True)
    p.add_argument("--tungsten", default=os.environ.get("TUNGSTEN"))
    p.add_argument("--emlt", default=os.path.join(ROOT, "build", "emlt"))
    p.add_argument("--time", type=float, default=30)
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--prefix", default="", help="command put before every timed render")
    p.add_argument("--check-spp", type=int, metavar="SPP")
    args = p.parse_args()
    if not args.tungsten:
        raise SystemExit("tungsten_equal_time: set TUNGSTEN or pass --tungsten")
    os.makedirs(args.out, exist_ok=True)
    prefix = shlex.split(args.prefix)
    scene_dir = os.path.join(args.out, "tungsten-scene")
    common = ["--width", str(args.size), "--height", str(args.size),
              "--threads", str(args.threads)]

    def tungsten(scene, out, seed, seconds=None):
        cmd = [args.tungsten, "--threads", str(args.threads), "--seed", str(seed),
               "-e", os.path.abspath(out), scene]
        if seconds is not None:
            cmd[1:1] = ["--timeout", f"{seconds}s"]
        return run(prefix, cmd)

    if args.check_spp:
        pt = tungsten_scene(SCENE, scene_dir, args.size, {"type": "path_tracer"},
                            args.check_spp, spp_step=args.check_spp)
        a = os.path.join(args.out, "tungsten-pt-check.pfm")
        b = os.path.join(args.out, "emlt-pt-check.pfm")
        tungsten(pt, a, 1)
        run(prefix, [args.emlt, "render", SCENE, *common, "--integrator", "pt", "--spp",
                     str(args.check_spp), "--seed", "1", "-o", b])
        r = compare(args.emlt, b, [a])[0]
        print(json.dumps(r))
        return

    mmlt = tungsten_scene(SCENE, scene_dir, args.size, {"type": "multiplexed_mlt"}, 1 << 30)
    images = {m: [] for m in ["tungsten-mmlt", *EMLT_METHODS]}
    walls = {m: [] for m in images}
    load = [os.getloadavg()]
    for seed in args.seeds:  # interleaved: one seed of every method, then the next
        for m in images:
            img = os.path.join(args.out, f"{m}-s{seed}.pfm")
            if m == "tungsten-mmlt":
                wall = tungsten(mmlt, img, seed, args.time)
            else:
                wall = run(prefix, [args.emlt, "render", SCENE, *common, *EMLT_METHODS[m],
                                    "--time", str(args.time), "--seed", str(seed), "-o", img])
            print(f"{m} seed {seed}: {wall:.1f} s (load {os.getloadavg()[0]:.1f})",
                  file=sys.stderr, flush=True)
            images[m].append(img)
            walls[m].append(wall)
        load.append(os.getloadavg())

    results = {}
    pt_images = images["emlt-pt"]
    for m, imgs in images.items():
        pairs = [compare(args.emlt, imgs[i], [imgs[i + 1]])[0]["mse_no_emitter"] / 2
                 for i in range(0, len(imgs) - 1, 2)]
        ratios = [r["mean_ratio"] for r in compare(args.emlt, pt_images[0], imgs)]
        results[m] = {"seed_pair_variance": pairs, "mean_ratio_vs_emlt_pt_s1": ratios,
                      "wall_s": walls[m]}
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump({"time_s": args.time, "threads": args.threads, "size": args.size,
                   "seeds": args.seeds, "load": load, "results": results}, f, indent=1)

    base = sum(results["tungsten-mmlt"]["seed_pair_variance"]) / len(
        results["tungsten-mmlt"]["seed_pair_variance"])
    print("| method | variance from seed pairs | / Tungsten MMLT | mean / emlt pt | wall s |")
    print("|---|---|---|---|---|")
    for m, row in results.items():
        var = sum(row["seed_pair_variance"]) / len(row["seed_pair_variance"])
        mean_ratio = sum(row["mean_ratio_vs_emlt_pt_s1"]) / len(row["mean_ratio_vs_emlt_pt_s1"])
        wall = sum(row["wall_s"]) / len(row["wall_s"])
        print(f"| {m} | {var:.3g} | {var / base:.2f} | {mean_ratio:.4f} | {wall:.1f} |")


if __name__ == "__main__":
    main()
