#!/usr/bin/env python3
"""Per-seed figures of one scene of an ablation run: each method's MSE, its image mean over
the reference's, and the normalisation b with the error the engine printed for it and the
samples it came from, so that a seed whose error is the normalisation's shows as such.

    per_seed.py OUT SCENE [--methods M1,M2,...] > table.md

OUT is an ablation folder (scripts/ablation.py: OUT/runs/SCENE/METHOD/pp-N/seed-S/ with
run.csv, the last row the run's final figures, and engine.log, where an MCMC run prints
"b = B +- E (N bootstrap samples)", or with samples drawn beside the chains
"b = B +- E (N samples: M bootstrap, K beside the chains; ...)")."""
import argparse
import csv
import os
import re
import sys

B_LINE = re.compile(r"b = ([0-9.eE+-]+) \+- ([0-9.eE+-]+) \((?:(\d+) bootstrap samples\)|(\d+) samples: )")


def final_row(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return rows[-1] if rows else None


def normalisation(log_path):
    """(b, its printed error, the samples behind it), or None when the log has no such line."""
    if not os.path.exists(log_path):
        return None
    with open(log_path) as f:
        match = B_LINE.search(f.read())
    if not match:
        return None
    return float(match.group(1)), float(match.group(2)), int(match.group(3) or match.group(4))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out")
    parser.add_argument("scene")
    parser.add_argument("--methods", default=None, help="comma-separated, in this order")
    args = parser.parse_args()
    scene_dir = os.path.join(args.out, "runs", args.scene)
    if not os.path.isdir(scene_dir):
        sys.exit(f"per_seed: {scene_dir}: no runs of scene '{args.scene}'")
    methods = args.methods.split(",") if args.methods else sorted(os.listdir(scene_dir))
    print("| method | seed | MSE | image mean / reference | b | b's printed error | samples behind b |")
    print("|---|---|---|---|---|---|---|")
    for method in methods:
        method_dir = os.path.join(scene_dir, method)
        if not os.path.isdir(method_dir):
            sys.exit(f"per_seed: {method_dir}: no runs of method '{method}'")
        for budget in sorted(os.listdir(method_dir)):
            seeds = sorted(os.listdir(os.path.join(method_dir, budget)), key=lambda s: int(s.split("-")[1]))
            for seed in seeds:
                run = os.path.join(method_dir, budget, seed)
                row = final_row(os.path.join(run, "run.csv")) if os.path.exists(os.path.join(run, "run.csv")) else None
                # A run still going has written only its earlier budgets' rows.
                if row is None or budget.startswith("pp-") and float(row["per_pixel"]) != float(budget[3:]):
                    continue
                b = normalisation(os.path.join(run, "engine.log"))
                b_cells = f"{b[0]:.4g} | {b[1]:.2g} | {b[2]:,}" if b else " |  | "
                print(f"| {method} | {seed.split('-')[1]} | {float(row['mse']):.4g} | "
                      f"{float(row['mean_ratio']):.4f} | {b_cells} |")


if __name__ == "__main__":
    main()
