#!/usr/bin/env python3
"""emlt and Mitsuba 0.6 on the same scene file, side by side (erpt, or the Metropolis
integrator the file names: mlt with the manifold perturbation is emlt's memlt): each at a
few sample counts (the file's sampleCount set by -Dspp; emlt's --spp, or --mpp for the
Metropolis integrators), its wall time, its image's mean over the reference's and its MSE
against the reference; and MSE x seconds, the figure that stays put as an unbiased render
runs longer (lower is better at equal time).

    compare.py --emlt build/emlt --mitsuba /path/to/dist/mitsuba [--scene integrator-erpt]
               [--spp 16,64] [--threads 2] [--name erpt] [--budget spp] --out DIR > table.md

The scene is a conformance scene (tests/conformance/scenes/NAME.xml, which takes -Dspp) and
the reference its committed image (tests/conformance/references/NAME.pfm), or any scene file
(--scene-file, taking -Dspp) with a reference image (--reference)."""
import argparse
import os
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, REPO)
from tools.images import read_pfm  # noqa: E402

SUITE = os.path.join(REPO, "tests", "conformance")


def timed(cmd, cwd, env=None):
    start = time.monotonic()
    result = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"compare: {' '.join(cmd)} failed: {result.stderr.strip() or result.stdout.strip()}")
    return time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--emlt", required=True)
    parser.add_argument("--mitsuba", required=True)
    parser.add_argument("--scene", default="integrator-erpt")
    parser.add_argument("--spp", default="16,64")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seeds", type=int, default=2)
    parser.add_argument("--direct-samples", type=int, default=None,
                        help="rewrite the file's directSamples (-1: both leave the direct light "
                             "to the chains)")
    parser.add_argument("--name", default="erpt", help="the integrator's name in the table")
    parser.add_argument("--budget", choices=("spp", "mpp"), default="spp",
                        help="emlt's flag for the file's sample count")
    parser.add_argument("--scene-file", help="a scene file instead of a conformance scene")
    parser.add_argument("--reference", help="the scene file's reference image (PFM)")
    parser.add_argument("--integrator-xml",
                        help="replace the file's <integrator> element with this text")
    parser.add_argument("--size", help="WIDTHxHEIGHT for a file that takes $width and $height")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    scene = os.path.join(SUITE, "scenes", args.scene + ".xml")
    if args.scene_file:
        scene = os.path.abspath(args.scene_file)
    workdir = os.path.dirname(scene)
    original = scene
    if args.direct_samples is not None or args.integrator_xml:
        # A copy beside the original, for its relative paths.
        with open(scene) as f:
            text = f.read()
        if args.direct_samples is not None:
            marker = '<integer name="directSamples" value="'
            start = text.index(marker) + len(marker)
            text = text[:start] + str(args.direct_samples) + text[text.index('"', start):]
        if args.integrator_xml:
            start = text.index("<integrator")
            end = text.index("</integrator>", start) + len("</integrator>")
            text = text[:start] + args.integrator_xml + text[end:]
        scene = os.path.join(workdir, ".compare-" + os.path.basename(scene))
        with open(scene, "w") as f:
            f.write(text)
    size_emlt, size_mitsuba = [], []
    if args.size:
        width, height = args.size.split("x")
        size_emlt = ["--width", width, "--height", height]
        # Such a file (scenes/caustic-pool/scene.xml) also names its output format.
        size_mitsuba = [f"-Dwidth={width}", f"-Dheight={height}", "-DfileFormat=pfm"]
    reference = read_pfm(args.reference or os.path.join(SUITE, "references", args.scene + ".pfm"))
    env = dict(os.environ, LD_LIBRARY_PATH=os.path.dirname(os.path.abspath(args.mitsuba)))
    where = os.path.relpath(original, REPO)
    against = (os.path.relpath(os.path.abspath(args.reference), REPO) if args.reference
               else f"references/{args.scene}.pfm")
    print(f"Scene `{where}`"
          f"{'' if args.direct_samples is None else f' with directSamples {args.direct_samples}'}"
          f"{'' if not args.integrator_xml else f' with the integrator `{args.integrator_xml}`'}"
          f"{'' if not args.size else f' at {args.size}'} against `{against}`, "
          f"{args.threads} threads.\n")
    print("| renderer | spp | seed | seconds | mean / reference | MSE | MSE x seconds |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for spp in [int(s) for s in args.spp.split(",")]:
        for seed in range(1, args.seeds + 1):
            runs = []
            out = os.path.abspath(os.path.join(args.out, f"emlt-{spp}-{seed}.pfm"))
            seconds = timed([os.path.abspath(args.emlt), "render", scene, f"--{args.budget}",
                             str(spp), "--seed", str(seed), "--threads", str(args.threads), "-q",
                             *size_emlt, "-o", out], workdir)
            runs.append((f"emlt {args.name}", out, seconds))
            # Mitsuba 0.6's samplers draw the same numbers whatever their seed, so its runs
            # differ only by thread scheduling: one run per count.
            if seed == 1:
                out = os.path.abspath(os.path.join(args.out, f"mitsuba-{spp}.pfm"))
                seconds = timed([os.path.abspath(args.mitsuba), "-q", "-p", str(args.threads),
                                 f"-Dspp={spp}", *size_mitsuba, scene, "-o", out], workdir, env)
                runs.append((f"Mitsuba 0.6 {args.name}", out, seconds))
            for name, path, seconds in runs:
                image = read_pfm(path)
                mse = float(((image - reference) ** 2).mean())
                ratio = float(image.mean() / reference.mean())
                print(f"| {name} | {spp} | {seed if name.startswith('emlt') else '-'} | "
                      f"{seconds:.2f} | {ratio:.4f} | {mse:.3g} | {mse * seconds:.3g} |")
    if scene != original:
        os.remove(scene)


if __name__ == "__main__":
    main()
