#!/usr/bin/python3
"""emlt's performance suite: whole-process figures on four scenes of the repository.

  bench/run.sh [--quick] [--repeat N] [--threads T] [--scenes a,b] [--no-profile] [--scaling]
  MITSUBA=.../dist/mitsuba bench/compare_mitsuba.sh [--door .../veach_door/door-mlt.xml]

For each scene it runs separate processes and prints, per scene:
  * Embree's own incoherent ray rate on that scene (build/emlt_ray_rate: rtcIntersect1 and
    rtcOccluded1, with the few analytic spheres Scene tests outside the BVH, alone on rays
    recorded from a path tracer's walk): the bound;
  * pt and bdpt samples/s, mlt, gamlt and emlt mutations/s: work done over the whole process's
    wall-clock time (loading, bootstrap and direct light included); the MCMC rows also give
    the chains' own rate from --stats;
  * peak memory: the largest maximum resident set size of those processes (wait4 rusage);
  * with --profile (the default): the time per mutation of `mlt` split into intersection and
    occlusion, BSDF/texture/emission evaluation, pdf and MIS computation, proposal,
    splatting, allocation and bookkeeping, from callgrind instruction counts of the chains
    alone (see docs/performance.md, "Method").
With --mitsuba it also renders the same scene files with Mitsuba 0.6 (path, bdpt, mlt with
directSamples -1, so direct light runs inside the chains as emlt's --direct mlt) and prints
the ratios; for mlt also the chains' own ratio, Mitsuba's chains timed as its render less the
same render at 1 mutation per pixel (its start: loading, luminance pass, start paths, which
is most of its time at the suite's work). Results go to out/bench/ (results.json, table.md);
--update-docs copies the table into docs/performance.md between its bench markers.
"""
import argparse
import collections
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

Scene = collections.namedtuple("Scene", "name path width height pt_spp bdpt_spp mpp")

# Work per run: counts, not time budgets, so that Mitsuba does exactly the same work.
# Chosen for a few seconds per run on the 2-core machine.
SCENES = [
    Scene("cornell-box", "scenes/cornell-box/scene.xml", 256, 256, 32, 8, 32),
    Scene("textured-door", "scenes/textured-door/scene.xml", 384, 256, 16, 4, 16),
    Scene("cornell-glass", "scenes/cornell-glass/scene.xml", 256, 256, 32, 8, 32),
    Scene("env-terrain", "scenes/env-terrain/scene.xml", 384, 256, 16, 4, 16),
]
MCMC = ("mlt", "gamlt", "emlt")

# Callgrind breakdown: each function's own instruction count goes to the first category
# whose pattern its name (or object file) matches; a function that matches none hands its
# count on to its callers in proportion to what each call cost (malloc called from a
# proposal counts as allocation, sincos called from a BSDF counts as BSDF).
CATEGORIES = [
    ("intersection", r"libembree|Scene::intersect|Scene::occluded|Scene::visible|mutually_visible|"
                     r"Scene::visit_nearby|rtcIntersect|rtcOccluded"),
    ("allocation", r"^(malloc|free|cfree|realloc|calloc|_int_malloc|_int_free|_int_realloc|"
                   r"malloc_consolidate|operator new|operator delete|tcache|unlink_chunk)"),
    ("splatting", r"[Ss]plat|Film|film|accumulate"),
    ("pdf and MIS", r"pdf|[Dd]ensit|mis_|_mis|[Mm]is[A-Z(]|weight"),
    ("BSDF, texture, emission", r"Bsdf|BSDF|Texture|Microfacet|[Ff]resnel|Plastic|Lambertian|"
                                r"TwoSided|Conductor|Dielectric|Bump|Mirror|Light|Environment|"
                                r"emitted|importance|contribution|factor_along|Material"),
    ("proposal", r"Mutation|Perturbation|perturbation::|propose|regenerate|random_walk|"
                 r"generate_(camera|light)_subpath|trace_to_vertex|make_surface_vertex|"
                 r"connect_vertices|square_to|perturb|Ensemble|ensemble|guide|Cone|cone"),
    ("bookkeeping", r"run_chain|StrategyMix|Rng|accept|Chain|chain"),
]
CATEGORY_NAMES = [name for name, _ in CATEGORIES]


def load_average():
    try:
        return open("/proc/loadavg").read().split()[0]
    except OSError:
        return "?"


def run(cmd, cwd=None, log=None):
    """Runs cmd; returns (wall seconds, peak resident MB, user+sys CPU seconds, output)."""
    with tempfile.TemporaryFile() as out:
        start = time.monotonic()
        proc = subprocess.Popen(cmd, cwd=cwd, stdout=out, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.monotonic() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        text = out.read().decode(errors="replace")
    if log:
        log.write("$ " + " ".join(cmd) + f"\n{text}\n[{wall:.2f} s, {usage.ru_maxrss / 1024:.0f} MB]\n")
    if proc.returncode != 0:
        sys.exit(f"bench: {' '.join(cmd)} failed ({proc.returncode}):\n{text[-2000:]}")
    return wall, usage.ru_maxrss / 1024.0, usage.ru_utime + usage.ru_stime, text


def median_run(repeat, cmd, **kwargs):
    runs = [run(cmd, **kwargs) for _ in range(repeat)]
    walls = [r[0] for r in runs]
    pick = runs[walls.index(sorted(walls)[(len(walls) - 1) // 2])]
    return pick


class Suite:
    def __init__(self, args):
        self.args = args
        self.emlt = os.path.join(args.build, "emlt")
        self.ray_rate = os.path.join(args.build, "emlt_ray_rate")
        for tool in (self.emlt, self.ray_rate):
            if not os.access(tool, os.X_OK):
                sys.exit(f"bench: {tool} not found (build first: cmake --build {args.build})")
        os.makedirs(args.out, exist_ok=True)
        self.scratch = tempfile.mkdtemp(prefix="emlt-bench-")
        self.log = open(os.path.join(args.out, "log.txt"), "w")

    def size_flags(self, scene):
        return ["--width", str(scene.width), "--height", str(scene.height)]

    def emlt_render(self, scene, integrator, count, threads, extra=()):
        image = os.path.join(self.scratch, f"{scene.name}-{integrator}.exr")
        stats = os.path.join(self.scratch, f"{scene.name}-{integrator}.json")
        cmd = [self.emlt, "render", scene.path, "--integrator", integrator, "--threads", str(threads),
               "--seed", "1", "-o", image] + self.size_flags(scene)
        if integrator in MCMC:
            cmd += ["--mpp", str(count), "--direct", "mlt", "--stats", stats]
        else:
            cmd += ["--spp", str(count)]
        wall, rss, cpu, text = median_run(self.args.repeat, cmd + list(extra), cwd=ROOT, log=self.log)
        work = scene.width * scene.height * count
        result = {"wall_s": wall, "peak_mb": rss, "cpu_s": cpu, "work": work, "rate": work / wall}
        # The render alone, as emlt's closing line gives it: without loading the scene and
        # building the BVH, and without writing the image.
        closing = re.search(r", ([0-9.]+) s, [0-9.]+ M ", text)
        if closing:
            result["render_s"] = float(closing.group(1))
        if integrator in MCMC:
            with open(stats) as f:
                st = json.load(f)
            result["work"] = st["mutations"]
            result["rate"] = st["mutations"] / wall
            result["chain_rate"] = st.get("chain_mutations_per_second")
        return result

    def ray_bound(self, scene, threads):
        seconds = "0.3" if self.args.quick else "1"
        _, rss, _, text = run([self.ray_rate, scene.path, "--threads", str(threads), "--seconds", seconds,
                               "-D", f"width={scene.width}", "-D", f"height={scene.height}"],
                              cwd=ROOT, log=self.log)
        fields = dict(kv.split("=", 1) for kv in text.split() if "=" in kv)
        return {"intersect": float(fields["intersect_rays_per_s"]),
                "occluded": float(fields["occluded_rays_per_s"]),
                "triangles": int(fields["triangles"])}

    def profile(self, scene):
        """Callgrind on one thread, chains only (--toggle-collect); instructions per mutation."""
        if not shutil.which("valgrind"):
            return None
        out = os.path.join(self.scratch, f"{scene.name}.callgrind")
        mpp = 1 if self.args.quick else 2
        # Half resolution: callgrind runs some 50x slower; the chains' mix per mutation does
        # not depend on the image size.
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
               f"--toggle-collect={self.args.profile_function}",
               self.emlt, "render", scene.path, "--integrator", "mlt", "--threads", "1", "--seed", "1",
               "--mpp", str(mpp), "--direct", "mlt", "--bootstrap", "10000",
               "--width", str(scene.width // 2), "--height", str(scene.height // 2),
               "-o", os.path.join(self.scratch, "profile.exr")]
        run(cmd, cwd=ROOT, log=self.log)
        totals = callgrind_breakdown(out)
        mutations = (scene.width // 2) * (scene.height // 2) * mpp
        total = sum(totals.values())
        if total == 0:
            print(f"bench: warning: callgrind counted nothing inside {self.args.profile_function} "
                  "(renamed? see --profile-function); no breakdown", file=sys.stderr)
            return None
        return {"instructions_per_mutation": total / mutations,
                "share": {k: v / total for k, v in totals.items()}}

    def concurrent_walls(self, scene, integrator, count, copies):
        """Wall times of `copies` single-thread renders started together."""
        procs = []
        for i in range(copies):
            cmd = [self.emlt, "render", scene.path, "--integrator", integrator, "--threads", "1",
                   "--seed", "1", "-q", "-o", os.path.join(self.scratch, f"pair{i}.exr")] + \
                self.size_flags(scene)
            cmd += ["--mpp", str(count), "--direct", "mlt"] if integrator in MCMC else ["--spp", str(count)]
            procs.append((time.monotonic(), subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL,
                                                             stderr=subprocess.DEVNULL)))
        walls = []
        for start, proc in procs:
            if proc.wait() != 0:
                sys.exit(f"bench: a concurrent {integrator} render of {scene.name} failed")
            walls.append(time.monotonic() - start)
        return walls

    def mitsuba(self, scene, integrator, count, threads):
        xml = mitsuba_variant(scene.path, integrator, count, scene.width, scene.height,
                              os.path.join(self.scratch, f"{scene.name}-{integrator}.xml"))
        def command(scene_file):
            return [self.args.mitsuba, "-q", "-p", str(threads), "-a",
                    os.path.dirname(os.path.abspath(scene.path)), scene_file, "-o",
                    os.path.join(self.scratch, f"{scene.name}-{integrator}-mitsuba.exr")]
        wall, rss, cpu, _ = median_run(self.args.repeat, command(xml), cwd=ROOT, log=self.log)
        pixels = scene.width * scene.height
        work = pixels * count
        result = {"wall_s": wall, "peak_mb": rss, "cpu_s": cpu, "work": work, "rate": work / wall}
        if integrator == "mlt" and count > 1:
            # Mitsuba's MLT spends seconds before its chains start (loading, the luminance
            # pass, the start paths), which in the suite's short runs is most of its time.
            # The same render at 1 mutation per pixel measures that start; the rest of the
            # time is the chains', comparable with emlt's chain rate from its statistics.
            start_xml = mitsuba_variant(scene.path, integrator, 1, scene.width, scene.height,
                                        os.path.join(self.scratch, f"{scene.name}-{integrator}-start.xml"))
            start, _, _, _ = median_run(self.args.repeat, command(start_xml), cwd=ROOT, log=self.log)
            result["start_s"] = start
            if wall > start:
                result["chain_rate"] = pixels * (count - 1) / (wall - start)
        return result

    def scene_figures(self, scene):
        a, t = self.args, self.args.threads
        quick = 8 if a.quick else 1
        pt_spp, bdpt_spp, mpp = (max(1, n // quick) for n in (scene.pt_spp, scene.bdpt_spp, scene.mpp))
        fig = {"scene": scene.name, "path": scene.path, "size": f"{scene.width}x{scene.height}",
               "threads": t, "repeat": a.repeat, "load_before": load_average(),
               "time": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
        fig["rays"] = self.ray_bound(scene, t)
        if a.mitsuba:
            fig["mitsuba"] = {}
        # With Mitsuba, each of its runs follows emlt's of the same method, so that the two
        # see about the same load from the rest of the machine.
        for integrator, count in (("pt", pt_spp), ("bdpt", bdpt_spp)) + tuple((k, mpp) for k in MCMC):
            fig[integrator] = self.emlt_render(scene, integrator, count, t)
            if a.mitsuba and integrator in ("pt", "bdpt", "mlt"):
                fig["mitsuba"][integrator] = self.mitsuba(scene, integrator, count, t)
        fig["peak_mb"] = max(fig[k]["peak_mb"] for k in ("pt", "bdpt") + MCMC)
        if a.profile:
            fig["profile"] = self.profile(scene)
        if a.scaling:
            fig["scaling"] = {}
            for integrator, count in (("pt", pt_spp), ("mlt", mpp)):
                count *= a.scaling_work  # longer runs: the fixed serial parts weigh less
                one = self.emlt_render(scene, integrator, count, 1)
                many = self.emlt_render(scene, integrator, count, t)
                pair = self.concurrent_walls(scene, integrator, count, t)
                entry = {
                    "threads": t, "work_factor": a.scaling_work,
                    "wall_1": one["wall_s"], "wall_2": many["wall_s"],
                    "cpu_1": one["cpu_s"], "cpu_2": many["cpu_s"],
                    "efficiency": one["wall_s"] / (t * many["wall_s"]),
                    # Extra CPU time the T-thread run spends (1 = none): contention or
                    # threads spinning, as opposed to the machine's other load.
                    "cpu_ratio": many["cpu_s"] / one["cpu_s"],
                    # The machine's own ceiling: T single-thread renders at once, each
                    # against one alone (1 = the cores do not slow each other down).
                    "hardware_efficiency": one["wall_s"] / max(pair)}
                if "render_s" in one and "render_s" in many and many["render_s"] > 0:
                    entry["render_1"], entry["render_2"] = one["render_s"], many["render_s"]
                    entry["render_efficiency"] = one["render_s"] / (t * many["render_s"])
                fig["scaling"][integrator] = entry
        fig["load_after"] = load_average()
        return fig


def mitsuba_variant(path, integrator, count, width, height, out):
    """The scene file with the integrator, sample count and film size replaced, for Mitsuba
    (which has no command-line flags for them). Everything else is untouched; relative file
    names resolve through `mitsuba -a <scene folder>`."""
    tree = ET.parse(path)
    scene = tree.getroot()
    # Mitsuba 0.6's command line refuses 0.5 files (the public door); its own upgrade of such
    # files only renumbers the version.
    if scene.get("version", "").startswith("0.5"):
        scene.set("version", "0.6.0")
    old = scene.find("integrator")
    depth = "-1"
    if old is not None:
        for child in old.iter("integer"):
            if child.get("name") == "maxDepth":
                depth = child.get("value")
        if depth.startswith("$"):
            defaults = {d.get("name"): d.get("value") for d in scene.findall("default")}
            depth = defaults.get(depth[1:], "-1")
        index = list(scene).index(old)
        scene.remove(old)
    else:
        index = 0
    new = ET.Element("integrator", type={"pt": "path", "bdpt": "bdpt", "mlt": "mlt"}[integrator])
    ET.SubElement(new, "integer", name="maxDepth", value=depth)
    if integrator == "mlt":
        # Direct light inside the chains (emlt's --direct mlt); Mitsuba's default bootstrap.
        ET.SubElement(new, "integer", name="directSamples", value="-1")
        ET.SubElement(new, "integer", name="luminanceSamples", value="100000")
    scene.insert(index, new)
    for sampler in scene.iter("sampler"):
        for child in sampler:
            if child.get("name") == "sampleCount":
                child.set("value", str(count))
    for film in scene.iter("film"):
        film.set("type", "hdrfilm")  # an ldrfilm would tonemap; the format does not matter here
        for child in list(film):
            if child.tag != "rfilter" and child.get("name") not in ("width", "height"):
                film.remove(child)
        for child in list(film):
            if child.get("name") in ("width", "height", "banner"):
                film.remove(child)
        ET.SubElement(film, "integer", name="width", value=str(width))
        ET.SubElement(film, "integer", name="height", value=str(height))
        ET.SubElement(film, "boolean", name="banner", value="false")
    tree.write(out)
    return out


def parse_callgrind(path):
    """Returns (self cost per function, {callee: {caller: inclusive cost of the calls}},
    object file per function) from a callgrind output file (event Ir only)."""
    names, objects = {}, {}
    self_cost = collections.Counter()
    callers = collections.defaultdict(collections.Counter)
    fn_object = {}

    def name(table, text):
        m = re.match(r"\((\d+)\)(?: (.*))?", text)
        if not m:
            return text
        if m.group(2) is not None:
            table[m.group(1)] = m.group(2)
        return table.get(m.group(1), text)

    current, current_ob, callee, pending_call = None, "", None, False
    cob = ""
    with open(path, errors="replace") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line:
                continue
            c = line[0]
            if line.startswith("ob="):
                current_ob = name(objects, line[3:])
            elif line.startswith("fn="):
                current = name(names, line[3:])
                fn_object.setdefault(current, current_ob)
            elif line.startswith("cob="):
                cob = name(objects, line[4:])
            elif line.startswith("cfn="):
                callee = name(names, line[4:])
                fn_object.setdefault(callee, cob or current_ob)
                cob = ""
            elif line.startswith("calls="):
                pending_call = True
            elif c.isdigit() or c in "+-*":
                parts = line.split()
                cost = int(parts[1]) if len(parts) > 1 else 0
                if pending_call:
                    callers[callee][current] += cost
                    pending_call = False
                elif current is not None:
                    self_cost[current] += cost
    return self_cost, callers, fn_object


def callgrind_breakdown(path):
    self_cost, callers, fn_object = parse_callgrind(path)
    patterns = [(cat, re.compile(p)) for cat, p in CATEGORIES]
    # Demangled names carry their parameter lists; classify on the name up to them, so that
    # a parameter type (a Film& argument) does not decide the category.
    def direct(fn):
        base = fn.replace("(anonymous namespace)", "").split("(")[0] or fn
        for cat, pattern in patterns:
            if pattern.search(base) or pattern.search(fn_object.get(fn, "")):
                return cat
        return None

    memo = {}

    def shares(fn, depth=0):
        if fn in memo:
            return memo[fn]
        cat = direct(fn)
        if cat:
            result = {cat: 1.0}
        elif depth > 40 or not callers.get(fn):
            result = {"bookkeeping": 1.0}
        else:
            memo[fn] = {"bookkeeping": 1.0}  # a cycle ends here
            total = sum(callers[fn].values())
            result = collections.Counter()
            if total == 0:
                result["bookkeeping"] = 1.0
            else:
                for caller, cost in callers[fn].items():
                    for cat, s in shares(caller, depth + 1).items():
                        result[cat] += s * cost / total
        memo[fn] = dict(result)
        return memo[fn]

    totals = collections.Counter({cat: 0 for cat in CATEGORY_NAMES})
    for fn, cost in self_cost.items():
        for cat, s in shares(fn).items():
            totals[cat] += cost * s
    return totals


def mega(x):
    return f"{x / 1e6:.2f}"


def table(figures, args):
    lines = []
    lines.append(f"{args.threads} threads; whole-process rates (work / wall-clock time of the process, "
                 "loading included; for the MCMC methods the chains' own rate in brackets); M = 10^6 per second.")
    lines.append("")
    lines.append("| scene | triangles | Embree incoherent rays (closest / shadow) | pt samples | bdpt samples "
                 "| mlt mutations | gamlt mutations | emlt mutations | peak memory |")
    lines.append("|---|---|---|---|---|---|---|---|---|")
    for f in figures:
        mc = " | ".join(f"{mega(f[k]['rate'])} ({mega(f[k]['chain_rate'])})" for k in MCMC)
        lines.append(f"| {f['scene']} ({f['size']}) | {f['rays']['triangles']:,} | "
                     f"{mega(f['rays']['intersect'])} / {mega(f['rays']['occluded'])} | "
                     f"{mega(f['pt']['rate'])} | {mega(f['bdpt']['rate'])} | {mc} | {f['peak_mb']:.0f} MB |")
    profiled = [f for f in figures if f.get("profile")]
    if profiled:
        lines.append("")
        lines.append("Time per `mlt` mutation (callgrind instructions of the chains alone, 1 thread, "
                     "half resolution; share of the total):")
        lines.append("")
        lines.append("| scene | instructions / mutation | " + " | ".join(CATEGORY_NAMES) + " |")
        lines.append("|---|---|" + "---|" * len(CATEGORY_NAMES))
        for f in profiled:
            p = f["profile"]
            lines.append(f"| {f['scene']} | {p['instructions_per_mutation']:,.0f} | " +
                         " | ".join(f"{100 * p['share'][c]:.0f} %" for c in CATEGORY_NAMES) + " |")
    scaled = [f for f in figures if f.get("scaling")]
    if scaled:
        lines.append("")
        lines.append(f"Strong scaling, 1 to {args.threads} threads (efficiency = T1 / ({args.threads} "
                     f"T{args.threads}), wall clock; CPU ratio = CPU time with {args.threads} threads over 1, "
                     "where 1.00 means no extra work):")
        lines.append("")
        lines.append(f"Render alone = the same from emlt's closing line (without loading, BVH build and "
                     f"writing the image); machine ceiling = one 1-thread render's wall time over the "
                     f"slowest of {args.threads} run at once (below 1: the cores slow each other down, "
                     "whatever the program).")
        lines.append("")
        lines.append(f"| scene | integrator | T1 | T{args.threads} | efficiency | render alone | "
                     "machine ceiling | CPU ratio |")
        lines.append("|---|---|---|---|---|---|---|---|")
        for f in scaled:
            for k, s in f["scaling"].items():
                render = f"{s['render_efficiency']:.2f}" if "render_efficiency" in s else "-"
                ceiling = f"{s['hardware_efficiency']:.2f}" if "hardware_efficiency" in s else "-"
                lines.append(f"| {f['scene']} | {k} | {s['wall_1']:.2f} s | {s['wall_2']:.2f} s | "
                             f"{s['efficiency']:.2f} | {render} | {ceiling} | {s['cpu_ratio']:.2f} |")
    compared = [f for f in figures if f.get("mitsuba")]
    if compared:
        lines.append("")
        lines.append("Side by side with Mitsuba 0.6 (same scene files, same work, same threads): emlt / Mitsuba "
                     "whole-process rates in M/s, then the ratio emlt over Mitsuba by wall clock and, after the "
                     "semicolon, by CPU time (work per CPU second, user + system: steadier than wall clock "
                     "when other processes share the machine)" +
                     (". For mlt, in brackets, the chains alone: emlt's rate from its statistics, Mitsuba's "
                      "from its time less that of the same render at 1 mutation per pixel (its loading, "
                      "luminance pass and start paths), which is most of its time in these short runs; long "
                      "renders approach the chains' ratio:"
                      if any(f["mitsuba"]["mlt"].get("chain_rate") for f in compared) else ":"))
        lines.append("")
        lines.append("| scene | pt samples | bdpt samples | mlt mutations (direct in the chains) "
                     "| peak memory pt | peak memory mlt |")
        lines.append("|---|---|---|---|---|---|")
        for f in compared:
            m = f["mitsuba"]
            cells = [f"{mega(f[k]['rate'])} / {mega(m[k]['rate'])} ({f[k]['rate'] / m[k]['rate']:.2f}x; "
                     f"{(f[k]['work'] / f[k]['cpu_s']) / (m[k]['work'] / m[k]['cpu_s']):.2f}x)"
                     for k in ("pt", "bdpt", "mlt")]
            if f["mlt"].get("chain_rate") and m["mlt"].get("chain_rate"):
                ours, theirs = f["mlt"]["chain_rate"], m["mlt"]["chain_rate"]
                cells[2] += f" [chains {mega(ours)} / {mega(theirs)} ({ours / theirs:.2f}x)]"
            cells += [f"{f[k]['peak_mb']:.0f} / {m[k]['peak_mb']:.0f} MB" for k in ("pt", "mlt")]
            lines.append(f"| {f['scene']} | " + " | ".join(cells) + " |")
    loads = ", ".join(f"{f['scene']} {f['load_before']}-{f['load_after']}" for f in figures)
    lines.append("")
    lines.append(f"Load average (1 min) before-after each scene: {loads}; {os.cpu_count()} CPUs; "
                 f"{figures[0].get('time', '') if figures else ''}; repeats: {args.repeat} (median).")
    return "\n".join(lines) + "\n"


def update_docs(markdown, path):
    text = open(path).read()
    begin, end = "<!-- bench:begin -->", "<!-- bench:end -->"
    if begin not in text or end not in text:
        sys.exit(f"bench: {path} has no {begin} ... {end} markers")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    with open(path, "w") as f:
        f.write(head + begin + "\n" + markdown + end + tail)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "bench"))
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=1, help="runs per figure; the median is reported")
    parser.add_argument("--quick", action="store_true", help="an eighth of the work, no profile (CI smoke run)")
    parser.add_argument("--scenes", help="comma-separated names (default: all)")
    parser.add_argument("--no-profile", dest="profile", action="store_false")
    parser.add_argument("--profile-function", default="emlt::(anonymous namespace)::run_chain*",
                        help="callgrind collects inside this function only (the chains)")
    parser.add_argument("--scaling", action="store_true", help="also pt and mlt at 1 thread and at --threads, with the efficiency")
    parser.add_argument("--scaling-work", type=int, default=4,
                        help="the scaling runs do this many times the table's work (default 4)")
    parser.add_argument("--mitsuba", default=os.environ.get("MITSUBA"), help="Mitsuba 0.6 binary: side by side")
    parser.add_argument("--door", help="also the public Veach door (its door-mlt.xml), 384x256")
    parser.add_argument("--update-docs", action="store_true", help="write the table into docs/performance.md")
    parser.add_argument("--from-json", help="no runs: the table of an earlier run's results.json")
    args = parser.parse_args()
    if args.from_json:
        with open(args.from_json) as f:
            figures = json.load(f)
        args.repeat = figures[0].get("repeat", "?") if figures else "?"
        args.threads = figures[0]["threads"] if figures else args.threads
        markdown = table(figures, args)
        print(markdown)
        if args.update_docs:
            update_docs(markdown, os.path.join(ROOT, "docs", "performance.md"))
        return
    if args.quick:
        args.profile = False
    if args.mitsuba:
        os.environ["LD_LIBRARY_PATH"] = os.path.dirname(os.path.abspath(args.mitsuba)) + \
            (":" + os.environ["LD_LIBRARY_PATH"] if os.environ.get("LD_LIBRARY_PATH") else "")

    scenes = list(SCENES)
    if args.scenes:
        wanted = args.scenes.split(",")
        unknown = set(wanted) - {s.name for s in scenes}
        if unknown:
            sys.exit(f"bench: unknown scene(s) {', '.join(sorted(unknown))}")
        scenes = [s for s in scenes if s.name in wanted]
    if args.door:
        scenes.append(Scene("veach-door", os.path.abspath(args.door), 384, 256, 16, 4, 16))
    if any(s.name == "env-terrain" for s in scenes) and not os.path.exists(
            os.path.join(ROOT, "scenes", "env-terrain", "cache", "rocks.ply")):
        python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
        subprocess.run([python, "-m", "tools.scenes.make_terrain"], cwd=ROOT, check=True)

    suite = Suite(args)
    figures = []
    try:
        for scene in scenes:
            print(f"bench: {scene.name} ...", file=sys.stderr, flush=True)
            figures.append(suite.scene_figures(scene))
    finally:
        shutil.rmtree(suite.scratch, ignore_errors=True)
    markdown = table(figures, args)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(figures, f, indent=1)
    with open(os.path.join(args.out, "table.md"), "w") as f:
        f.write(markdown)
    print(markdown)
    if args.update_docs:
        update_docs(markdown, os.path.join(ROOT, "docs", "performance.md"))


if __name__ == "__main__":
    main()
