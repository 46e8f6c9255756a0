"""Renders the shipped JSON scenes with the path tracer and tiles them into one image,
each titled with its folder name (default docs/scenes.png).

Needs a built `emlt` and matplotlib (numpy). Scenes whose folder has no scene.json are
skipped with a note. Every scene is rendered at its own default size, so aspect ratios are
kept; the renderer's PNG preview (linear -> sRGB, clamped) is what is shown.

    python3 -m tools.scenes.make_contact_sheet --emlt build/emlt          # 128 spp, docs/scenes.png
    python3 -m tools.scenes.make_contact_sheet --emlt build/emlt --spp 64 --threads 2 -o /tmp/sheet.png
    python3 -m tools.scenes.make_contact_sheet --emlt build/emlt kitchen bedroom  # only these
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

from tools import ROOT

DEFAULT_SCENES = ["cornell-box", "env-sky", "door-ajar", "caustic-pool", "staircase", "bedroom", "kitchen",
                  "classroom", "breakfast-room", "sponza-like"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="*", help="scene folders under scenes/ (default: %(default)s)",
                        default=DEFAULT_SCENES)
    parser.add_argument("--emlt", default=os.path.join(ROOT, "build", "emlt"), help="renderer binary")
    parser.add_argument("--spp", type=int, default=128)
    parser.add_argument("--threads", type=int, default=0, help="0 = all cores")
    parser.add_argument("--columns", type=int, default=4)
    parser.add_argument("--dpi", type=int, default=80, help="figure resolution (cells are 3.2 x 2.75 inches)")
    parser.add_argument("-o", "--output", default=os.path.join(ROOT, "docs", "scenes.png"))
    args = parser.parse_args()

    images = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes:
            scene = os.path.join(ROOT, "scenes", name, "scene.json")
            if not os.path.isfile(scene):
                print(f"skipping {name}: no scenes/{name}/scene.json", file=sys.stderr)
                continue
            png = os.path.join(tmp, name + ".png")
            start = time.time()
            subprocess.run([args.emlt, "render", scene, "--integrator", "pt", "--spp", str(args.spp),
                            "--threads", str(args.threads), "--seed", "1", "-q", "-o", png],
                           check=True, stdout=subprocess.DEVNULL)
            print(f"{name}: {time.time() - start:.1f} s")
            images.append((name, mpimg.imread(png)))
    if not images:
        sys.exit("no scenes rendered")

    cols = min(args.columns, len(images))
    rows = (len(images) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.75 * rows), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for ax, (name, img) in zip(axes.flat, images):
        ax.imshow(img, interpolation="bilinear")
        ax.set_title(name, fontsize=11)
    fig.suptitle(f"emlt scenes, path tracer, {args.spp} spp", fontsize=12)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    fig.savefig(args.output, dpi=args.dpi)
    print(f"wrote {os.path.relpath(args.output, ROOT)}")


if __name__ == "__main__":
    main()
