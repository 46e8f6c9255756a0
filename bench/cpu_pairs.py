#!/usr/bin/python3
"""Which CPUs slow each other down: a one-thread render pinned to CPU 0 alone, then beside an
identical one pinned to each other CPU in turn (the cause of a many-thread loss).

  bench/cpu_pairs.py [--scene scenes/cornell-box/scene.xml] [--methods pt,mlt] [--work 16]

Each figure is the pinned render's own rate (samples or the chains' mutations per second, from
emlt's statistics, so loading and the bootstrap do not count) beside CPU j over its rate alone.
A virtual machine that reports one thread per core may still place two virtual CPUs on one
physical core (SMT siblings): such pairs show up as the slow ones, and code that needs more of
a core's own caches (instruction cache, L1/L2 data) loses more there. Where the pinning is not
honoured (some sandboxes), every pair looks alike. Writes out/cpu-pairs/results.json.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


MCMC = ("mlt", "gamlt", "emlt")


def command(args, method, cpu, stats, image):
    cmd = ["taskset", "-c", str(cpu), os.path.join(args.build, "emlt"), "render", args.scene,
           "--integrator", method, "--threads", "1", "--seed", "1", "-q", "-o", image]
    if method not in MCMC:
        return cmd + ["--spp", str(args.work)]
    return cmd + ["--mpp", str(args.work), "--direct", "mlt", "--stats", stats]


def rate(method, stats_path, output):
    """The chains' own rate (MCMC), or the render's from emlt's closing line (M samples/s)."""
    if method in MCMC:
        with open(stats_path) as f:
            return float(json.load(f)["chain_mutations_per_second"])
    found = re.search(r"([0-9.]+) M samples/s", output)
    if not found:
        sys.exit(f"cpu_pairs: no rate in emlt's output: {output[-300:]}")
    return float(found.group(1)) * 1e6


def run_together(args, method, cpus, scratch):
    procs = []
    for k, cpu in enumerate(cpus):
        stats = os.path.join(scratch, f"{method}-{k}.json")
        image = os.path.join(scratch, f"{method}-{k}.exr")
        procs.append((stats, subprocess.Popen(command(args, method, cpu, stats, image), cwd=ROOT,
                                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT)))
    rates = []
    for stats, proc in procs:
        output = proc.communicate()[0].decode(errors="replace")
        if proc.returncode != 0:
            sys.exit(f"cpu_pairs: a {method} render failed: {output[-500:]}")
        rates.append(rate(method, stats, output))
    return rates


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--scene", default="scenes/cornell-box/scene.xml")
    parser.add_argument("--methods", default="pt,mlt")
    parser.add_argument("--work", type=int, default=16, help="samples or mutations per pixel")
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "cpu-pairs"))
    args = parser.parse_args()
    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < 2:
        sys.exit("cpu_pairs: needs at least two CPUs")
    scratch = tempfile.mkdtemp(prefix="emlt-pairs-")
    results = {"cpus": cpus, "scene": args.scene, "work": args.work, "methods": {}}
    for method in args.methods.split(","):
        alone = max(run_together(args, method, [cpus[0]], scratch)[0] for _ in range(2))
        pairs = {}
        for cpu in cpus[1:]:
            pairs[str(cpu)] = run_together(args, method, [cpus[0], cpu], scratch)[0] / alone
        results["methods"][method] = {"alone": alone, "pairs": pairs}
        print(f"{method}: alone {alone / 1e6:.3f} M/s; beside CPU j, over alone: " +
              " ".join(f"{cpu}:{v:.2f}" for cpu, v in pairs.items()), flush=True)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
