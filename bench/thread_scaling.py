#!/usr/bin/python3
"""Strong scaling over many threads: the suite's scenes rendered with the same work
at 1 thread and at each count of --threads, whole-process wall clock and the render alone.

  bench/thread_scaling.py --threads 1,4,16 [--door .../door-mlt.xml] [--work 8] [--ceiling]

For a machine with more cores than the 2-core one bench/suite.py --scaling was made on. For
each scene and method (pt, mlt with direct light in the chains) it prints T_n, the efficiency
T_1 / (n T_n) by wall clock and by the render's own time (emlt's closing line: without
loading, BVH build and writing the image), and the CPU time over T_1's (above 1: threads
spinning or contending). --ceiling also runs n single-thread renders at once and gives T_1
over the slowest of them: the machine's own ceiling (shared caches, memory bandwidth, turbo),
which no threading of emlt's can beat; --ceiling-at 4,8,16 measures it at those counts too.
--mitsuba BINARY renders pt, bdpt and mlt with Mitsuba 0.6 at the same counts and work, so
that a mature renderer's efficiency on the same machine stands beside emlt's.
--compute-ceiling does the same for a loop that touches no memory beyond the core's own
caches (a Python loop): where even that slows down with n copies, the loss is the
processors' (shared physical cores, clocks), not memory. --variant LABEL=BUILD_DIR runs a
second build's emlt at the largest count, beside the first, on the same machine (an A/B of a
change). Writes out/thread-scaling/{results.json,table.md}.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import suite  # bench/suite.py, beside this script: the suite's scenes and its process runner


# About a second of interpreted integer work that stays in the core's own caches; it prints
# its own time, so that starting n interpreters at once (slow under some VMs) does not count.
SPIN = ("import time\nt = time.perf_counter()\nx = 0\nfor i in range(12_000_000):\n"
        "    x = (x * 31 + i) & 0xFFFFFFFF\nprint(time.perf_counter() - t)\n")


def compute_ceiling(counts):
    """T1 over the slowest of n copies of SPIN started together, for each n."""
    def walls(copies):
        procs = [subprocess.Popen([sys.executable, "-c", SPIN], stdout=subprocess.PIPE, text=True)
                 for _ in range(copies)]
        return [float(proc.communicate()[0]) for proc in procs]
    one = min(walls(1)[0] for _ in range(2))
    return {str(n): one / max(walls(n)) for n in counts if n > 1}


def table(figures, counts):
    lines = [f"Strong scaling on {figures[0]['cpus']} CPUs ({figures[0]['host']}); efficiency = "
             "T1 / (n Tn), wall clock (the render alone in brackets); CPU = CPU time over T1's; "
             "ceiling = T1 over the slowest of n single-thread renders run at once.", ""]
    head = "| scene | method | T1 s | " + " | ".join(f"{n} threads: s, efficiency (render), CPU" for n in counts[1:])
    lines += [head + " | ceiling |", "|" + "---|" * (4 + len(counts) - 1)]
    for f in figures:
        for method, runs in f["runs"].items():
            one = runs["1"]
            cells = []
            for n in counts[1:]:
                r = runs.get(str(n))
                if not r:
                    cells.append("")
                    continue
                eff = one["wall_s"] / (n * r["wall_s"])
                render = ""
                if "render_s" in r and "render_s" in one:
                    render = f" ({one['render_s'] / (n * r['render_s']):.2f})"
                cells.append(f"{r['wall_s']:.2f}, {eff:.2f}{render}, {r['cpu_s'] / one['cpu_s']:.2f}")
            ceilings = [(k.split(":")[1], v) for k, v in runs.items() if k.startswith("ceiling:")]
            ceiling_cell = ", ".join(f"{n}: {v:.2f}" for n, v in ceilings)
            lines.append(f"| {f['scene']} | {method} | {one['wall_s']:.2f} | " + " | ".join(cells) +
                         f" | {ceiling_cell} |")
    variants = [(f, method, key, r) for f in figures for method, runs in f["runs"].items()
                for key, r in runs.items() if "@" in key]
    if variants:
        lines += ["", "Variants at the largest count (same machine, same run): wall s and efficiency "
                  "against the same T1, beside the main build's.", "",
                  "| scene | method | variant | main: s, efficiency | variant: s, efficiency |",
                  "|---|---|---|---|---|"]
        for f, method, key, r in variants:
            n, label = key.split("@")
            runs = f["runs"][method]
            one, main_run = runs["1"], runs[n]
            lines.append(f"| {f['scene']} | {method} | {label} ({n} threads) | {main_run['wall_s']:.2f}, "
                         f"{one['wall_s'] / (int(n) * main_run['wall_s']):.2f} | {r['wall_s']:.2f}, "
                         f"{one['wall_s'] / (int(n) * r['wall_s']):.2f} |")
    mitsuba = [(f, method, runs) for f in figures for method, runs in f["runs"].items()
               if "mitsuba:1" in runs]
    if mitsuba:
        lines += ["", "Mitsuba 0.6 on the same machine, same scene files and work: T1 s, then wall s and "
                  "efficiency at each count, beside emlt's efficiency.", "",
                  "| scene | method | Mitsuba T1 s | " +
                  " | ".join(f"{n} threads: Mitsuba s, efficiency; emlt's" for n in counts[1:]) + " |",
                  "|" + "---|" * (3 + len(counts) - 1)]
        for f, method, runs in mitsuba:
            one, mine = runs["mitsuba:1"], runs["1"]
            cells = []
            for n in counts[1:]:
                r, e = runs.get(f"mitsuba:{n}"), runs.get(str(n))
                cells.append(f"{r['wall_s']:.2f}, {one['wall_s'] / (n * r['wall_s']):.2f}; "
                             f"{mine['wall_s'] / (n * e['wall_s']):.2f}" if r and e else "")
            lines.append(f"| {f['scene']} | {method} | {one['wall_s']:.2f} | " + " | ".join(cells) + " |")
    compute = figures[0].get("compute_ceiling")
    if compute:
        lines += ["", "Compute-only ceiling (n copies of a cache-resident loop, T1 over the slowest): " +
                  ", ".join(f"{n}: {v:.2f}" for n, v in compute.items())]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default=os.path.join(suite.ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(suite.ROOT, "out", "thread-scaling"))
    parser.add_argument("--threads", default="1,2,4,8,16", help="thread counts, 1 first")
    parser.add_argument("--scenes", help="comma-separated names (default: all of the suite's)")
    parser.add_argument("--door", help="also the public Veach door (its door-mlt.xml), 384x256")
    parser.add_argument("--work", type=float, default=8,
                        help="times the suite table's work (default 8; below 1 for a quick check)")
    parser.add_argument("--methods", default="pt,mlt")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--ceiling", action="store_true",
                        help="also the largest count's single-thread renders at once")
    parser.add_argument("--variant-methods", default="pt,bdpt," + ",".join(suite.MCMC),
                        help="the methods the variants run (default: all)")
    parser.add_argument("--pairs", type=int, default=3,
                        help="runs of each --variant, alternating with the main build's (default 3)")
    parser.add_argument("--ceiling-at", help="counts at which to measure the ceiling (default: the largest)")
    parser.add_argument("--compute-ceiling", action="store_true",
                        help="also the ceiling of a cache-resident loop at every count")
    parser.add_argument("--mitsuba", default=os.environ.get("MITSUBA"),
                        help="Mitsuba 0.6 binary: its pt, bdpt and mlt at the same counts")
    parser.add_argument("--variant", action="append", default=[], metavar="LABEL=BUILD_DIR",
                        help="another build's emlt, run at the largest count beside the main one")
    args = parser.parse_args()
    args.quick = False
    def thread_counts(flag, text):
        try:
            values = [int(n) for n in text.split(",")]
        except ValueError:
            values = []
        if not values or min(values) < 1:
            sys.exit(f"thread_scaling: {flag} takes thread counts such as 1,4,16 (got {text!r})")
        return values

    counts = thread_counts("--threads", args.threads)
    if counts[0] != 1:
        sys.exit("thread_scaling: the first thread count must be 1 (the baseline)")
    scenes = list(suite.SCENES)
    if args.door:
        scenes.append(suite.Scene("veach-door", os.path.abspath(args.door), 384, 256, 16, 4, 16))
    if args.scenes:
        wanted = args.scenes.split(",")
        unknown = sorted(set(wanted) - {s.name for s in scenes})
        if unknown:
            sys.exit(f"thread_scaling: unknown scene(s) {', '.join(unknown)}")
        scenes = [s for s in scenes if s.name in wanted]
    methods = args.methods.split(",")
    if not set(methods) <= {"pt", "bdpt"} | set(suite.MCMC):
        sys.exit(f"thread_scaling: --methods takes pt, bdpt, {', '.join(suite.MCMC)}")
    variants = []
    for spec in args.variant:
        label, _, build = spec.partition("=")
        if not label or not build or "@" in label or not os.access(os.path.join(build, "emlt"), os.X_OK):
            sys.exit(f"thread_scaling: --variant {spec}: want LABEL=BUILD_DIR holding an emlt binary")
        variants.append((label, os.path.join(os.path.abspath(build), "emlt")))
    if args.mitsuba:
        if not os.access(args.mitsuba, os.X_OK):
            sys.exit(f"thread_scaling: --mitsuba {args.mitsuba}: not an executable")
        os.environ["LD_LIBRARY_PATH"] = os.path.dirname(os.path.abspath(args.mitsuba)) + \
            (":" + os.environ["LD_LIBRARY_PATH"] if os.environ.get("LD_LIBRARY_PATH") else "")
    runner = suite.Suite(args)
    ceiling_counts = thread_counts("--ceiling-at", args.ceiling_at) if args.ceiling_at else counts[-1:]
    compute = compute_ceiling(counts) if args.compute_ceiling else None
    if compute:
        print("compute-only ceiling: " + ", ".join(f"{n}: {v:.2f}" for n, v in compute.items()), flush=True)
    figures = []
    for scene in scenes:
        fig = {"scene": scene.name, "size": f"{scene.width}x{scene.height}", "work_factor": args.work,
               "cpus": os.cpu_count(), "host": os.uname().nodename,
               "time": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "runs": {}}
        if compute:
            fig["compute_ceiling"] = compute
        for method in methods:
            count = max(1, round({"pt": scene.pt_spp, "bdpt": scene.bdpt_spp}.get(method, scene.mpp) * args.work))
            runs = {}
            for n in counts:
                runs[str(n)] = runner.emlt_render(scene, method, count, n)
                print(f"{scene.name} {method} {n} threads: {runs[str(n)]['wall_s']:.2f} s", flush=True)
                if args.mitsuba and method in ("pt", "bdpt", "mlt"):
                    # Right after emlt's run at the same count: both see about the same machine.
                    runs[f"mitsuba:{n}"] = runner.mitsuba(scene, method, count, n)
                    print(f"{scene.name} {method} {n} threads, Mitsuba: "
                          f"{runs[f'mitsuba:{n}']['wall_s']:.2f} s", flush=True)
            # Variants alternate with the main build, --pairs times, on a machine whose speed
            # drifts; each keeps its median run, the main build's runs included.
            if variants and method in args.variant_methods.split(","):
                main_emlt, n = runner.emlt, counts[-1]
                alternated = {"main": [runs[str(n)]]}
                for k in range(args.pairs):
                    for label, binary in variants:
                        runner.emlt = binary
                        alternated.setdefault(label, []).append(runner.emlt_render(scene, method, count, n))
                        runner.emlt = main_emlt
                    if k + 1 < args.pairs:
                        alternated["main"].append(runner.emlt_render(scene, method, count, n))
                for label, results in alternated.items():
                    results.sort(key=lambda r: r["wall_s"])
                    median = dict(results[(len(results) - 1) // 2], walls=[r["wall_s"] for r in results])
                    runs[str(n) if label == "main" else f"{n}@{label}"] = median
                    print(f"{scene.name} {method} {n} threads, {label}: " +
                          ", ".join(f"{w:.2f}" for w in median["walls"]) + " s", flush=True)
            if args.ceiling:
                for n in ceiling_counts:
                    if n > 1:
                        runs[f"ceiling:{n}"] = runs["1"]["wall_s"] / max(
                            runner.concurrent_walls(scene, method, count, n))
            fig["runs"][method] = runs
        figures.append(fig)
        os.makedirs(args.out, exist_ok=True)
        with open(os.path.join(args.out, "results.json"), "w") as f:
            json.dump(figures, f, indent=1)
        text = table(figures, counts)
        with open(os.path.join(args.out, "table.md"), "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main()
