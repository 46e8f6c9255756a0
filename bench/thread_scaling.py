#!/usr/bin/python3
"""Strong scaling over many threads (issue 24): the suite's scenes rendered with the same work
at 1 thread and at each count of --threads, whole-process wall clock and the render alone.

  bench/thread_scaling.py --threads 1,4,16 [--door .../door-mlt.xml] [--work 8] [--ceiling]

For a machine with more cores than the 2-core one bench/suite.py --scaling was made on. For
each scene and method (pt, mlt with direct light in the chains) it prints T_n, the efficiency
T_1 / (n T_n) by wall clock and by the render's own time (emlt's closing line: without
loading, BVH build and writing the image), and the CPU time over T_1's (above 1: threads
spinning or contending). --ceiling also runs n single-thread renders at once and gives T_1
over the slowest of them: the machine's own ceiling (shared caches, memory bandwidth, turbo),
which no threading of emlt's can beat. Writes out/thread-scaling/{results.json,table.md}.
"""
import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import suite  # noqa: E402  (the suite's scenes and its process runner)


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
            ceiling = runs.get("ceiling")
            ceiling_cell = f"{ceiling:.2f}" if ceiling else ""
            lines.append(f"| {f['scene']} | {method} | {one['wall_s']:.2f} | " + " | ".join(cells) +
                         f" | {ceiling_cell} |")
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
    args = parser.parse_args()
    args.quick = False
    counts = [int(n) for n in args.threads.split(",")]
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
    runner = suite.Suite(args)
    figures = []
    for scene in scenes:
        fig = {"scene": scene.name, "size": f"{scene.width}x{scene.height}", "work_factor": args.work,
               "cpus": os.cpu_count(), "host": os.uname().nodename,
               "time": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "runs": {}}
        for method in methods:
            count = max(1, round({"pt": scene.pt_spp, "bdpt": scene.bdpt_spp}.get(method, scene.mpp) * args.work))
            runs = {}
            for n in counts:
                runs[str(n)] = runner.emlt_render(scene, method, count, n)
                print(f"{scene.name} {method} {n} threads: {runs[str(n)]['wall_s']:.2f} s", flush=True)
            if args.ceiling and counts[-1] > 1:
                runs["ceiling"] = runs["1"]["wall_s"] / max(runner.concurrent_walls(scene, method, count,
                                                                                  counts[-1]))
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
