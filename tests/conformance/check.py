#!/usr/bin/env python3
"""The Mitsuba 0.6 conformance check: renders scenes of tests/conformance/suite.json with
emlt and compares them with Mitsuba's own images in tests/conformance/references/.

    PYTHONPATH=. tests/conformance/check.py [--emlt build/emlt] [--scene NAME ...]
        [--integrator pt ...] [--table docs/conformance.md] [--json FILE]
    (from the repository root: it reads images with tools.images; CTest sets PYTHONPATH)

For each scene and integrator emlt renders the scene twice (seeds 1 and 2). Two numbers
decide:
  * the image mean, per colour channel, of the two renders' average over the reference's:
    within 1 % (channels with under 2 % of the brightest channel's mean are compared in
    absolute terms, against 1 % of that brightest mean);
  * the per-pixel error: the mean squared difference from the reference over the noise
    expected from the renders themselves (estimated from the difference between the two
    seeds) plus the reference's (estimated from its sample count). A correct renderer
    gives about 1 (0.5 to 1.6 measured over seed pairs on this suite: fireflies and
    emitter edges make the estimate itself noisy), so the limit is 2; a shifted, blurred,
    flipped or wrongly coloured image gives far more (a box-filtered image against a
    Gaussian-filtered reference: 14).
A scene whose entry names an `emlt_scene` (NAME.pbrt: the same scene in pbrt-v4's format)
is rendered by emlt from that file; Mitsuba's reference is still of NAME.xml. When the entry
also sets `pbrt_v4_reference_spp`, the same two renders are compared, by the same two numbers,
with pbrt-v4's own image of NAME.pbrt (references/pbrt-v4/NAME.pfm, rendered with that many
samples by tools/conformance/render_pbrt_references.sh): a second result for the scene, whose
reference is "pbrt-v4".
A scene may list known differences ("known": {"reason": ..., "integrators": [...]}) in
the manifest: those are reported as XFAIL and do not fail the run; one that passes is
reported as XPASS so that the entry can be removed. Exit status 1 when any other check
fails, 2 on a usage error or a missing reference.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
try:
    from tools.images import read_pfm  # the package at the repository root, on PYTHONPATH
except ModuleNotFoundError as error:  # run by hand without it: say how, not a traceback
    print(f"check.py: {error}: run it with the repository root on PYTHONPATH "
          f"(CTest sets it; by hand: PYTHONPATH={os.path.relpath(ROOT)} {sys.argv[0]} ...)",
          file=sys.stderr)
    sys.exit(2)  # a usage error, as the docstring counts them

MEAN_TOLERANCE = 0.01
ERROR_RATIO_LIMIT = 2.0
DEFAULT_SPP = {"pt": 64, "bdpt": 32, "mlt": 64, "direct": 64, "ptracer": 64, "gamlt": 64,
               "memlt": 64, "emlt": 64, "pssmlt": 64, "mmlt": 64, "erpt": 64}
# Integrators whose budget is mutations per pixel (--mpp), not samples.
MUTATION_BUDGET = ("mlt", "gamlt", "memlt", "emlt", "pssmlt", "mmlt")


def load_suite():
    with open(os.path.join(HERE, "suite.json")) as f:
        return json.load(f)["scenes"]


def render(emlt, scene, integrator, budget, seed, out, threads, scene_file=None):
    """Renders one image (of scenes/NAME.xml, or of the entry's `emlt_scene` file: the same
    scene in pbrt-v4's format); returns the warnings emlt printed."""
    args = [emlt, "render", os.path.join(HERE, "scenes", scene_file or scene + ".xml"), "-o", out,
            "--integrator", integrator, "--seed", str(seed), "--quiet"]
    args += ["--mpp", str(budget)] if integrator in MUTATION_BUDGET else ["--spp", str(budget)]
    if threads:
        args += ["--threads", str(threads)]
    result = subprocess.run(args, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"{scene} ({integrator}): emlt failed: {result.stderr.strip()}")
    return [line for line in result.stderr.splitlines() if "warning" in line]


def compare(first, second, reference, budget, reference_spp):
    """The mean ratio per channel, the error ratio and the mean's standard error."""
    if first.shape != reference.shape:
        raise RuntimeError(f"image size {first.shape[1]}x{first.shape[0]} differs from the "
                           f"reference's {reference.shape[1]}x{reference.shape[0]}")
    average = 0.5 * (first + second)
    noise = np.mean((first - second) ** 2) / 4.0          # variance of the average, per value
    # The reference's noise: the same kind of estimator with reference_spp samples against
    # 2 * budget (a rough scale; it is small by construction).
    noise += np.mean((first - second) ** 2) / 2.0 * budget / reference_spp
    error = float(np.mean((average - reference) ** 2))
    ref_mean = reference.reshape(-1, 3).mean(axis=0)
    emlt_mean = average.reshape(-1, 3).mean(axis=0)
    brightest = float(max(ref_mean.max(), 1e-12))
    ratios = []
    for c in range(3):
        if ref_mean[c] >= 0.02 * brightest:
            ratios.append(float(emlt_mean[c] / ref_mean[c]))
        else:  # a nearly black channel: its absolute difference against the brightest
            ratios.append(1.0 + float(emlt_mean[c] - ref_mean[c]) / brightest)
    per_channel_noise = np.mean(((first - second) ** 2).reshape(-1, 3), axis=0) / 4.0
    standard_error = float(np.sqrt(per_channel_noise.max() / (first.shape[0] * first.shape[1]))) / brightest
    return ratios, error / max(noise, 1e-30), standard_error, error


def read_reference(name, kind):
    """The reference image of scene `name`: Mitsuba 0.6's, or pbrt-v4's (kind "pbrt-v4")."""
    folder, script, variable = (("references", "render_references.sh", "MITSUBA") if kind == "Mitsuba 0.6"
                                else (os.path.join("references", "pbrt-v4"), "render_pbrt_references.sh", "PBRT"))
    path = os.path.join(HERE, folder, name + ".pfm")
    if not os.path.exists(path):
        raise FileNotFoundError(f"{name}: no reference image {os.path.relpath(path, ROOT)}; "
                                f"run tools/conformance/{script} with {variable}= set")
    return read_pfm(path)


def verdict(entry, integrator, ratios, error_ratio):
    ok = all(abs(r - 1.0) <= MEAN_TOLERANCE for r in ratios) and error_ratio <= ERROR_RATIO_LIMIT
    known = entry.get("known")
    expected_to_fail = bool(known) and integrator in known.get("integrators", [integrator])
    status = ("XPASS" if ok else "XFAIL") if expected_to_fail else ("PASS" if ok else "FAIL")
    return status, known.get("reason", "") if expected_to_fail else ""


def check_scene(emlt, entry, integrator, threads, workdir):
    """The results for one scene and integrator: against Mitsuba's image, and against
    pbrt-v4's too when the entry has one."""
    name = entry["name"]
    references = [("Mitsuba 0.6", read_reference(name, "Mitsuba 0.6"), entry.get("reference_spp", 4096))]
    if "pbrt_v4_reference_spp" in entry:
        references.append(("pbrt-v4", read_reference(name, "pbrt-v4"), entry["pbrt_v4_reference_spp"]))
    budget = entry.get("spp", {}).get(integrator, DEFAULT_SPP[integrator])
    images, warnings = [], []
    for seed in (1, 2):
        out = os.path.join(workdir, f"{name}.{integrator}.{seed}.pfm")
        warnings = render(emlt, name, integrator, budget, seed, out, threads,
                          entry.get("emlt_scene"))
        images.append(read_pfm(out))
    results = []
    for kind, reference, reference_spp in references:
        ratios, error_ratio, standard_error, mse = compare(images[0], images[1], reference, budget,
                                                           reference_spp)
        status, reason = verdict(entry, integrator, ratios, error_ratio)
        results.append({
            "scene": name, "integrator": integrator, "convention": entry["convention"],
            "reference": kind, "status": status, "mean_ratio": ratios, "error_ratio": error_ratio,
            "mean_standard_error": standard_error, "mse": mse, "budget": budget,
            "warnings": warnings, "reason": reason,
        })
    return results


def write_table(results, path):
    lines = ["| scene | convention | integrator | reference | emlt mean / reference's (R, G, B) | "
             "error / noise | verdict |",
             "|---|---|---|---|---|---|---|"]
    for r in results:
        ratio = ", ".join(f"{v:.3f}" for v in r["mean_ratio"])
        verdict = r["status"] + (f": {r['reason']}" if r["reason"] else "")
        lines.append(f"| `{r['scene']}` | {r['convention']} | {r['integrator']} | {r['reference']} | "
                     f"{ratio} | {r['error_ratio']:.2f} | {verdict} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


CATEGORIES = {"orient": "orientation", "depth": "path depth", "bsdf": "BSDFs", "tex": "textures",
              "spectrum": "spectra", "camera": "camera", "film": "film filter", "shape": "shapes",
              "light": "lights", "transform": "transforms", "normals": "shading normals",
              "pbrt": "pbrt-v4 scenes (against Mitsuba's twins)"}


def write_summary(results, path):
    """One row per group of conventions (the scene names' first word): for the README."""
    groups = {}
    for r in results:
        # The particle tracer's scenes (NAME-ptracer, checked against Mitsuba's ptracer
        # image) form their own group whatever convention they share with NAME, and so do
        # the comparisons with pbrt-v4's own images.
        group = ("pbrt-v4 scenes (against pbrt-v4's images)" if r["reference"] == "pbrt-v4"
                 else "particle tracer" if r["scene"].endswith("-ptracer")
                 else CATEGORIES.get(r["scene"].split("-")[0], r["scene"]))
        groups.setdefault(group, []).append(r)
    lines = ["| conventions | scenes | renders | worst mean ratio | worst error / noise | verdict |",
             "|---|---|---|---|---|---|"]
    for name, rows in groups.items():
        worst = max(rows, key=lambda r: max(abs(v - 1.0) for v in r["mean_ratio"]))
        ratio = min(worst["mean_ratio"], key=lambda v: -abs(v - 1.0))
        failed = [r for r in rows if r["status"] in ("FAIL", "XFAIL")]
        verdict = "all pass" if not failed else ", ".join(
            f"`{r['scene']}` [{r['integrator']}] {r['status'].lower()}" for r in failed)
        lines.append(f"| {name} | {len({r['scene'] for r in rows})} | {len(rows)} | {ratio:.3f} | "
                     f"{max(r['error_ratio'] for r in rows):.2f} | {verdict} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--emlt", default=os.environ.get("EMLT_BINARY", os.path.join(ROOT, "build", "emlt")))
    parser.add_argument("--scene", action="append", help="only these scenes (repeatable)")
    parser.add_argument("--integrator", action="append", help="only these integrators (repeatable)")
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--table", help="write a Markdown table of the results here")
    parser.add_argument("--json", help="write the results as JSON here")
    parser.add_argument("--summary", help="write a Markdown table by group of conventions here")
    args = parser.parse_args()

    suite = load_suite()
    names = {e["name"] for e in suite}
    for wanted in args.scene or []:
        if wanted not in names:
            print(f"conformance: no scene '{wanted}' in suite.json", file=sys.stderr)
            return 2
    results, failures = [], 0
    with tempfile.TemporaryDirectory() as workdir:
        for entry in suite:
            if args.scene and entry["name"] not in args.scene:
                continue
            for integrator in entry["integrators"]:
                if args.integrator and integrator not in args.integrator:
                    continue
                try:
                    rows = check_scene(args.emlt, entry, integrator, args.threads, workdir)
                except FileNotFoundError as e:
                    print(f"conformance: {e}", file=sys.stderr)
                    return 2
                except RuntimeError as e:
                    rows = [{"scene": entry["name"], "integrator": integrator,
                             "convention": entry["convention"], "reference": "Mitsuba 0.6",
                             "status": "FAIL", "mean_ratio": [float("nan")] * 3, "error_ratio": float("nan"),
                             "mean_standard_error": float("nan"), "mse": float("nan"), "budget": 0,
                             "warnings": [], "reason": str(e)}]
                for r in rows:
                    results.append(r)
                    failures += r["status"] == "FAIL"
                    ratio = " ".join(f"{v:.4f}" for v in r["mean_ratio"])
                    against = "" if r["reference"] == "Mitsuba 0.6" else f" vs {r['reference']}"
                    print(f"{r['status']:5} {r['scene']} [{integrator}]{against} mean ratio {ratio} "
                          f"(se {r['mean_standard_error']:.4f}), error/noise {r['error_ratio']:.2f}"
                          + (f" -- {r['reason']}" if r["reason"] else ""))
                for w in rows[0]["warnings"]:
                    print(f"      {w}")
    if args.table:
        write_table(results, args.table)
    if args.summary:
        write_summary(results, args.summary)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    passed = sum(r["status"] in ("PASS", "XPASS") for r in results)
    print(f"conformance: {passed} passed, {failures} failed, "
          f"{sum(r['status'] == 'XFAIL' for r in results)} known differences")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
