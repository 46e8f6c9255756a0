#!/usr/bin/env python3
"""Table 1 from an ablation run of table1.json: MSE per scene and method (mean over seeds,
net of the reference's own noise), MLT's MSE over the method's, the chains' variance across
seeds, time, α's quartiles, and the acceptance of the proposals overall and per strategy
beside the paper's figures.

    summarise.py out/ablation-paper-table1 [more run folders] > table.md
    summarise.py out/ablation-paper-table1 --update docs/paper-setting.md

Reads results.csv, chains.csv and each run's stats.json (written by scripts/ablation.py).
--update replaces what lies between the document's two marker lines (BEGIN, END below)."""
import argparse
import csv
import json
import os
import statistics
import sys

# Table 1 of the paper (MSE at 64 mutations per pixel, indirect light only).
PAPER = {
    "door-ajar": {"MLT": 7.32e-3, "Ani": 4.14e-3, "Lin": 3.86e-3, "EMLT": 3.28e-3},
    "kitchen": {"MLT": 2.19e-2, "Ani": 1.75e-2, "Lin": 1.56e-2, "EMLT": 1.52e-2},
    "bedroom": {"MLT": 1.15e-4, "Ani": 9.28e-5, "Lin": 9.24e-5, "EMLT": 8.34e-5},
    "staircase": {"MLT": 7.42e-5, "Ani": 5.07e-5, "Lin": 4.92e-5, "EMLT": 4.34e-5},
    "classroom": {"MLT": 2.45e-2, "Ani": 1.26e-2, "Lin": 1.32e-2, "EMLT": 1.16e-2},
    "cornell-box": {"MLT": 9.62e-3, "Ani": 4.72e-3, "Lin": 4.34e-3, "EMLT": 3.28e-3},
}
BASELINE = "MLT"
DISPLAY_ORDER = ["MLT", "MLT-mix", "MLT-paper", "GAMLT", "GAMLT-exact", "Ani", "Lin", "EMLT"]
BEGIN = "<!-- table1:begin (scripts/experiments/paper_table1/summarise.py --update) -->"
END = "<!-- table1:end -->"


def load_rows(folder):
    with open(os.path.join(folder, "results.csv")) as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        stats_path = os.path.join(folder, os.path.dirname(row["image"]), "stats.json")
        row["_stats"] = None
        if os.path.exists(stats_path):
            with open(stats_path) as f:
                row["_stats"] = json.load(f)
    return rows


def load_chains(folder):
    """chains.csv's variance per (scene, method); empty where the run left none."""
    path = os.path.join(folder, "chains.csv")
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return {(r["scene"], r["method"]): float(r["chains_variance"]) for r in csv.DictReader(f)}


def alpha_quartiles(runs):
    """α's quartiles over the guided stretches, mean over seeds; '' for methods without α."""
    alphas = [r["_stats"]["ensemble"]["alpha"] for r in runs
              if r["_stats"] and "alpha" in r["_stats"].get("ensemble", {})]
    if not alphas:
        return ""
    return " / ".join(f"{mean([a[k] for a in alphas]):.2f}" for k in ("q1", "median", "q3"))


def overall_acceptance(stats):
    """Accepted over proposed, all strategies together (the paper's "acceptance probability")."""
    proposed = sum(s.get("proposed", 0) for s in stats.get("strategies", []))
    accepted = sum(s.get("accepted", 0) for s in stats.get("strategies", []))
    return accepted / proposed if proposed else float("nan")


def mean(values):
    values = [v for v in values if v is not None]
    return statistics.fmean(values) if values else float("nan")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", nargs="+", help="ablation output folders (with results.csv)")
    parser.add_argument("--update", metavar="DOC",
                        help="write the tables into DOC between its marker lines instead of printing them")
    args = parser.parse_args(argv)
    rows = []
    chains = {}
    for folder in args.folders:
        if not os.path.exists(os.path.join(folder, "results.csv")):
            print(f"summarise.py: error: {folder}: no results.csv (run scripts/ablation.py first)",
                  file=sys.stderr)
            return 1
        rows += load_rows(folder)
        chains.update(load_chains(folder))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    # The baselines first, then GAMLT-like, the paper's ablation and anything else, whatever
    # order the runs were made in.
    found = list(dict.fromkeys(r["method"] for r in rows))
    methods = [m for m in DISPLAY_ORDER if m in found] + [m for m in found if m not in DISPLAY_ORDER]

    def cell(scene, method):
        return [r for r in rows if r["scene"] == scene and r["method"] == method]

    out = []
    out.append("| scene | method | seeds | MSE | MSE net of the reference | MLT / this | chains' variance | "
               "MLT / this, by it | seconds | acceptance | over MLT, paper's mix | α: quartiles | "
               "paper: MSE, MLT / this |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for scene in scenes:
        base = cell(scene, BASELINE)
        base_net = mean([float(r["mse_net"]) for r in base]) if base else float("nan")
        mix = cell(scene, "MLT-mix")
        mix_acceptance = mean([overall_acceptance(r["_stats"]) for r in mix if r["_stats"]])
        paper = PAPER.get(scene, {})
        for method in methods:
            runs = cell(scene, method)
            if not runs:
                continue
            mse = mean([float(r["mse"]) for r in runs])
            net = mean([float(r["mse_net"]) for r in runs])
            seconds = mean([float(r["seconds"]) for r in runs if r["seconds"]])
            acceptance = mean([overall_acceptance(r["_stats"]) for r in runs if r["_stats"]])
            relative = acceptance / mix_acceptance if mix_acceptance == mix_acceptance else float("nan")
            # Blank where the same-mix MLT was not run.
            relative_text = f"{relative - 1.0:+.0%}" if relative == relative else ""
            variance = chains.get((scene, method))
            base_variance = chains.get((scene, BASELINE))
            variance_text = f"{variance:.4g}" if variance is not None else ""
            variance_ratio = f"{base_variance / variance:.2f}" if variance and base_variance else ""
            paper_text = ""
            if method in paper:
                paper_text = f"{paper[method]:.3g}, {paper['MLT'] / paper[method]:.2f}"
            out.append(f"| {scene} | {method} | {len(runs)} | {mse:.4g} | {net:.4g} | "
                       f"{base_net / net:.2f} | {variance_text} | {variance_ratio} | {seconds:.1f} | "
                       f"{acceptance:.3f} | {relative_text} | {alpha_quartiles(runs)} | {paper_text} |")
    out.append("")
    out.append("Acceptance per strategy (mean over seeds of accepted / proposed):")
    out.append("")
    strategies = sorted({s["name"] for r in rows if r["_stats"] for s in r["_stats"].get("strategies", [])})
    out.append("| scene | method | " + " | ".join(strategies) + " |")
    out.append("|---|---|" + "---|" * len(strategies))
    for scene in scenes:
        for method in methods:
            runs = [r for r in cell(scene, method) if r["_stats"]]
            if not runs:
                continue
            values = []
            for name in strategies:
                rates = [s["accepted"] / s["proposed"] for r in runs for s in r["_stats"]["strategies"]
                         if s["name"] == name and s.get("proposed")]
                values.append(f"{mean(rates):.3f}" if rates else "")
            out.append(f"| {scene} | {method} | " + " | ".join(values) + " |")
    text = "\n".join(out)
    if not args.update:
        print(text)
        return 0
    try:
        with open(args.update) as f:
            doc = f.read()
    except OSError as e:
        print(f"summarise.py: error: {args.update}: {e.strerror}", file=sys.stderr)
        return 1
    if BEGIN not in doc or END not in doc or doc.index(BEGIN) > doc.index(END):
        print(f"summarise.py: error: {args.update}: no '{BEGIN}' ... '{END}' block", file=sys.stderr)
        return 1
    head, rest = doc.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    temporary = args.update + ".tmp"
    with open(temporary, "w") as f:
        f.write(head + BEGIN + "\n" + text + "\n" + END + tail)
    os.replace(temporary, args.update)
    return 0


if __name__ == "__main__":
    sys.exit(main())
