#!/usr/bin/python3
"""The EMLT paper's comparison in its own setting: Table-1-like Markdown and Fig.-17-like plots.

    scripts/ablation.py scripts/experiments/paper_setting/paper-setting.json
    scripts/experiments/paper_setting/summarize.py [--out out/ablation-paper-setting] \\
        [--md docs/paper-setting-256.md] [--plots docs/paper-setting]

Reads what the ablation runner wrote (results.csv, chains.csv, the runs' convergence logs) and
writes one Markdown page (MSE of the indirect part per scene and method, each baseline's MSE
over EMLT's next to the paper's figure, render times) and one log-log plot per scene
(PREFIX-SCENE.png: MSE against mutations per pixel, a line per method, mean over seeds).
Every MSE here has the reference's own noise (its 'reference_floor') subtracted.
"""
import argparse
import csv
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))

# Bashford-Rogers et al. 2021: MLT's MSE over EMLT's at 64 mutations per pixel (section 4.1)
# and Table 1 (MLT, Ani, Lin, EMLT).
PAPER_RATIO = {"cornell-box": 2.93, "door-ajar": 2.23, "staircase": 1.71, "bedroom": 1.38, "classroom": 2.11,
               "kitchen": 1.44}
PAPER_TABLE1 = {"door-ajar": (7.32e-3, 4.14e-3, 3.86e-3, 3.28e-3), "kitchen": (2.19e-2, 1.75e-2, 1.56e-2, 1.52e-2),
                "bedroom": (1.15e-4, 9.28e-5, 9.24e-5, 8.34e-5), "staircase": (7.42e-5, 5.07e-5, 4.92e-5, 4.34e-5),
                "classroom": (2.45e-2, 1.26e-2, 1.32e-2, 1.16e-2), "cornell-box": (9.62e-3, 4.72e-3, 4.34e-3, 3.28e-3)}
EMLT = "EMLT"
BASELINES = ["MLT-12", "MLT-128", "MLT-1024", "MLT-16384", "GAMLT-12", "GAMLT-16384"]


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_log(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return [{k: float(v) for k, v in row.items() if v not in ("", None)} for row in csv.DictReader(f)]


def git_commit():
    try:
        return subprocess.run(["git", "-C", ROOT, "log", "-1", "--format=%h %cd", "--date=short"],
                              capture_output=True, text=True).stdout.strip()
    except OSError:
        return "unknown"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "ablation-paper-setting"),
                        help="the ablation runner's output folder")
    parser.add_argument("--md", default=os.path.join(ROOT, "docs", "paper-setting-256.md"))
    parser.add_argument("--plots", default=os.path.join(ROOT, "docs", "paper-setting"),
                        help="plot prefix: PREFIX-SCENE.png")
    parser.add_argument("--long", help="also summarize chain-length.json's output folder (e.g. "
                        "out/ablation-paper-setting-long)")
    parser.add_argument("--commit", help="the engine commit that made the runs (default: this checkout's HEAD)")
    args = parser.parse_args()

    rows = read_csv(os.path.join(args.out, "results.csv"))
    chains_rows = read_csv(os.path.join(args.out, "chains.csv")) if os.path.exists(
        os.path.join(args.out, "chains.csv")) else []
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    methods = list(dict.fromkeys(r["method"] for r in rows))
    seeds = sorted({int(r["seed"]) for r in rows})

    def values(scene, method, key):
        return np.array([float(r[key]) for r in rows if r["scene"] == scene and r["method"] == method])

    floor = {s: float(next(r["reference_floor"] for r in rows if r["scene"] == s)) for s in scenes}
    net = {(s, m): values(s, m, "mse_net") for s in scenes for m in methods}
    seconds = {(s, m): values(s, m, "seconds") for s in scenes for m in methods}
    chains = {(r["scene"], r["method"]): float(r["chains_variance"]) for r in chains_rows}
    # chain_variance.py sits in scripts/ and the image helpers in the package tools/ at the root:
    # neither folder is on the path of a script run from scripts/experiments/paper_setting/.
    sys.path[:0] = [ROOT, os.path.join(ROOT, "scripts")]
    from chain_variance import ideal_variance_per_mutation
    from tools.images import read_pfm
    mpp = float(rows[0]["budget"])
    ideal = {s: ideal_variance_per_mutation(read_pfm(os.path.join(args.out, "references", f"{s}.pfm"))
                                            .reshape(-1, 3).astype(np.float64)) / mpp / 3 for s in scenes}

    lines = ["# The EMLT paper's comparison on look-alike scenes at 256×256 (it = 2)", "",
             "Not the paper's setting: its scenes run at their own resolution, where it is about 28; that comparison, on Bitterli's scenes themselves, is [paper-setting.md](paper-setting.md). Here the schedule degenerates (it = 2 steps per path between swaps), which alone costs EMLT 1.2–1.3× MLT's time, and the figures predate the fixes of the paper's mix and readings listed in [emlt-fidelity.md](emlt-fidelity.md).", "",
             "Made by `scripts/experiments/paper_setting/` (see its README): "
             f"`scripts/ablation.py scripts/experiments/paper_setting/paper-setting.json` then `summarize.py`. "
             f"Engine commit {args.commit or git_commit()}; seeds {', '.join(map(str, seeds))}; 256×256 (staircase 256×192), "
             "64 mutations per pixel, indirect light only (direct light rendered separately and subtracted "
             "exactly), bidirectional mutation at 1/3 and the other strategies equal, the paper's adaptive α, "
             "`--threads 2` on a shared 2-core machine.", "",
             "MSE is `emlt compare`'s (mean over pixels and RGB channels) of the chains' image against an "
             "indirect-only reference (two independent MLT renders, 16,384 chains, 256 mutations per pixel each), "
             "minus the reference's own noise (the variance of the mean of its two parts: "
             + ", ".join(f"{s} {floor[s]:.2e}" for s in scenes) + "). The chains' variance is the per-pixel "
             "variance across the seeds of (image − that seed's direct image), averaged the same way: the chains' "
             "MSE with no reference at all (scripts/chain_variance.py's figure, divided by 3 because that one sums "
             "the channels).", "",
             "## MSE at 64 mutations per pixel (mean ± std over seeds; Table 1-like)", "",
             "| scene | " + " | ".join(methods) + " |", "|---|" + "---:|" * len(methods)]
    for s in scenes:
        best = min(methods, key=lambda m: net[(s, m)].mean())
        cells = []
        for m in methods:
            v = net[(s, m)]
            text = f"{v.mean():.3e} ± {v.std(ddof=1) if len(v) > 1 else 0:.1e}"
            cells.append(f"**{text}**" if m == best else text)
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    if chains:
        lines += ["", "## Chains' variance across seeds at 64 mutations per pixel (no reference)", "",
                  "'ideal': an independent sampler drawing paths in proportion to the chains' target (luminance) "
                  "at the same mutations per pixel (scripts/chain_variance.py's yardstick, from the reference "
                  "image): the room left for any Markov chain, roughly; expected-value splatting can go below it.", "",
                  "| scene | ideal | " + " | ".join(methods) + " |", "|---|---:|" + "---:|" * len(methods)]
        for s in scenes:
            lines.append(f"| {s} | {ideal[s]:.2e} | " + " | ".join(
                f"{chains[(s, m)]:.3e}" if (s, m) in chains else "–" for m in methods) + " |")

    lines += ["", "## Each baseline's MSE over EMLT's (above 1: EMLT better)", "",
              "EMLT here is the paper's configuration (|X| = |Y| = 16,384, it = 2). Each cell: ratio of the mean "
              "reference MSEs / ratio of the chains' variances. The paper's figure is MLT's MSE over EMLT's.", "",
              "| scene | paper | " + " | ".join(b for b in BASELINES if b in methods) + " |",
              "|---|---:|" + "---:|" * sum(b in methods for b in BASELINES)]
    for s in scenes:
        cells = []
        for b in BASELINES:
            if b not in methods:
                continue
            ratio = net[(s, b)].mean() / net[(s, EMLT)].mean()
            cv = chains.get((s, b), np.nan) / chains.get((s, EMLT), np.nan)
            cells.append(f"{ratio:.2f} / {cv:.2f}")
        paper = PAPER_RATIO.get(s)
        lines.append(f"| {s} | {paper:.2f} | " + " | ".join(cells) + " |" if paper else
                     f"| {s} | – | " + " | ".join(cells) + " |")

    lines += ["", "## The ablation against the paper's Table 1 (MLT's MSE over each variant's)", "",
              "| scene | source | MLT | Ani | Lin | EMLT |", "|---|---|---:|---:|---:|---:|"]
    for s in scenes:
        if s in PAPER_TABLE1:
            p = PAPER_TABLE1[s]
            lines.append(f"| {s} | paper | 1.00 | {p[0] / p[1]:.2f} | {p[0] / p[2]:.2f} | {p[0] / p[3]:.2f} |")
        for baseline in ("MLT-12", "MLT-16384"):
            if baseline in methods and all(m in methods for m in ("Ani", "Lin", EMLT)):
                base = net[(s, baseline)].mean()
                lines.append(f"| {s} | ours, MLT = {baseline} | 1.00 | " + " | ".join(
                    f"{base / net[(s, m)].mean():.2f}" for m in ("Ani", "Lin", EMLT)) + " |")

    lines += ["", "## Render time (s, mean over seeds; chains, bootstrap and direct image)", "",
              "| scene | " + " | ".join(methods) + " |", "|---|" + "---:|" * len(methods)]
    for s in scenes:
        lines.append(f"| {s} | " + " | ".join(f"{seconds[(s, m)].mean():.1f}" for m in methods) + " |")
    if "MLT-16384" in methods and EMLT in methods:
        lines += ["", "EMLT's time over MLT-16384's (the paper: +18 %): " + ", ".join(
            f"{s} {seconds[(s, EMLT)].mean() / seconds[(s, 'MLT-16384')].mean():.2f}×" for s in scenes) +
            ". Wall-clock on a machine shared with other jobs: rough."]
    md_dir = os.path.dirname(os.path.abspath(args.md))
    lines += ["", "## Convergence (Fig. 17-like)", ""] + [
        f"![{s}: MSE against mutations per pixel]({os.path.relpath(f'{args.plots}-{s}.png', md_dir)})"
        for s in scenes]
    lines.append("")
    os.makedirs(os.path.dirname(os.path.abspath(args.md)), exist_ok=True)
    with open(args.md, "w") as f:
        f.write("\n".join(lines))
    print(f"wrote {args.md}", file=sys.stderr)

    plot_scenes(args.out, rows, scenes, methods, floor, len(seeds), args.plots)
    if args.long:
        long_rows = read_csv(os.path.join(args.long, "results.csv"))
        long_chains = {(r["scene"], r["method"]): float(r["chains_variance"])
                       for r in read_csv(os.path.join(args.long, "chains.csv"))}
        long_scenes = list(dict.fromkeys(r["scene"] for r in long_rows))
        long_methods = list(dict.fromkeys(r["method"] for r in long_rows))
        long_floor = {s: float(next(r["reference_floor"] for r in long_rows if r["scene"] == s)) for s in long_scenes}
        budget = float(long_rows[0]["budget"])
        plot_scenes(args.long, long_rows, long_scenes, long_methods, long_floor, len(seeds), f"{args.plots}-long",
                    f", {budget:g} mutations per pixel", subtract=False)
        with open(args.md, "a") as f:
            f.write("\n".join(["", f"## Longer chains: {budget:g} mutations per pixel", "",
                                f"`chain-length.json`: the same setting at {budget:g} mutations per pixel, so that each "
                                f"of EMLT's 32,768 paths takes {budget * 65536 / 32768:g} steps (64 mutations per pixel "
                                "at 512×512 would give as many). The reference is the same, and its own noise is "
                                "about MLT's MSE at this budget: the chains' variance (no reference) is the figure to "
                                "read.", "",
                                "| scene | " + " | ".join(long_methods) + " | MLT-12 / EMLT | MLT-16384 / EMLT |",
                                "|---|" + "---:|" * (len(long_methods) + 2)] +
                               [f"| {s} | " + " | ".join(f"{long_chains[(s, m)]:.3e}" for m in long_methods) + " | "
                                + " | ".join(f"{long_chains[(s, b)] / long_chains[(s, EMLT)]:.2f}"
                                             for b in ("MLT-12", "MLT-16384")) + " |" for s in long_scenes]
                               + [""] + [f"![{s}, {budget:g} mutations per pixel]"
                                         f"({os.path.relpath(f'{args.plots}-long-{s}.png', md_dir)})"
                                         for s in long_scenes]) + "\n")


def plot_scenes(out, rows, scenes, methods, floor, nseeds, prefix, budget_text="", subtract=True):
    """PREFIX-SCENE.png: log-log MSE against mutations per pixel, the reference's own noise
    subtracted (subtract) or drawn as a line."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    style = {"MLT-12": ("tab:green", ":"), "MLT-128": ("tab:green", "-."), "MLT-1024": ("tab:green", "--"),
             "MLT-16384": ("tab:green", "-"), "GAMLT-12": ("tab:red", ":"), "GAMLT-16384": ("tab:red", "-"),
             "Ani": ("tab:purple", "--"), "Lin": ("tab:orange", "--"), "EMLT-12": ("tab:cyan", ":"),
             "EMLT-128": ("tab:cyan", "-."), "EMLT-1024": ("tab:blue", ":"),
             EMLT: ("tab:blue", "-")}
    for s in scenes:
        fig, ax = plt.subplots(figsize=(5.2, 4.0))
        for m in methods:
            logs = [read_log(os.path.join(out, r["image"].replace("image.pfm", "run.csv")))
                    for r in rows if r["scene"] == s and r["method"] == m]
            logs = [log for log in logs if log]
            if not logs:
                continue
            common = sorted(set.intersection(*({row["per_pixel"] for row in log} for log in logs)))
            mse = [np.mean([next(row["mse"] for row in log if row["per_pixel"] == pp) for log in logs])
                   - (floor[s] if subtract else 0.0) for pp in common]
            color, dash = style.get(m, ("k", "-"))
            ax.loglog(common, mse, dash, color=color, marker="o", ms=2.5, lw=1.3, label=m)
        if not subtract:
            ax.axhline(floor[s], color="gray", lw=0.8, ls="--", label="reference's own noise")
        ax.set_xscale("log", base=2)
        ax.set_xlabel("mutations per pixel")
        ax.set_ylabel("MSE (indirect" + (", reference noise subtracted)" if subtract else ")"))
        ax.set_title(f"{s}: indirect only, mean of {nseeds} seeds{budget_text}", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        path = f"{prefix}-{s}.png"
        fig.savefig(path, dpi=80, metadata={"Software": None})
        plt.close(fig)
        print(f"wrote {path}", file=sys.stderr)


if __name__ == "__main__":
    main()
