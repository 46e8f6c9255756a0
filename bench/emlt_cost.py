#!/usr/bin/python3
"""Ensemble MLT's cost per mutation against MLT's, with a breakdown.

Two measurements per scene, both single-threaded:

* CPU time: user CPU seconds of `emlt render --threads 1` at --mpp HIGH minus --mpp LOW,
  divided by the extra mutations, so that the fixed costs (scene loading, bootstrap, the
  direct image, seeding the chains) cancel. Repeated; the minimum of each is used (the
  machine is shared, and load only ever adds time).
* Instructions: valgrind's callgrind, collecting only inside the chain loop (run_chain) and
  EMLT's per-swap rebuild of the path-type tree (EnsembleGuides::build), at --mpp CG_MPP.
  Repeatable to a few parts in a million on a shared machine. Every instruction is put in
  one category: a function of the engine by its name (below), a library function (libm,
  libc, Embree) in the category of its callers, in proportion to what each call costs.

  tree rebuild   EnsembleGuides::build, PathTypeIndex::build (once per swap)
  guide lookup   finding Υ for a step (EnsembleGuides::upsilon, the type's window)
  similarity     eq. 8/9 similarities, guide choice and its selection ratio
  kernel fits    the rest of emlt::ensemble: fitting, sampling and evaluating the kernels
  tracing        Scene::intersect / Scene::visible and Embree under them
  allocation     malloc / free / operator new / delete, whoever calls them
  rest           everything else (path construction, BSDFs, densities, MH, splatting)

A last row gives EMLT's extra instructions per mutation over MLT's, by category.

With --structure it also separates EMLT's driver from its kernels (docs/experiments.md, "Third round"):
`emlt-mlt-mix` runs EMLT's ensembles, swaps and tree rebuilds with MLT's own strategies, and
the `-it32` rows take 32 steps per chain between swaps (what a 1024x1024 image gets from
the paper's it = floor(W H / (|X| + |Y|))) instead of 2 at 256x256. emlt-mlt-mix over mlt
is what the schedule costs by itself; emlt over emlt-it32 what visiting every chain for
two steps at a time costs (each visit fetches the chain's path, every swap the other
half's, from memory).

Per strategy it also prints instructions per proposal (inclusive of everything the
proposal does, tracing included).

Usage:
  bench/emlt_cost.py                         # Cornell box and door ajar, 256x256
  bench/emlt_cost.py --no-cpu                # callgrind only
  bench/emlt_cost.py --structure --no-callgrind   # driver against kernels, CPU time
  bench/emlt_cost.py --method emlt-ani="--integrator emlt --mutations emlt-ani"
"""
import argparse
import collections
import os
import re
import resource
import shlex
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CATEGORIES = ["tree rebuild", "guide lookup", "similarity", "kernel fits", "tracing",
              "allocation", "rest"]
TREE = re.compile(r"emlt::(EnsembleGuides::build|PathTypeIndex::build)\b")
SIMILARITY = re.compile(
    r"emlt::ensemble::(\(anonymous namespace\)::)?(path_similarities|vertex_similarities|"
    r"similarities_to_guides|far_similarity_row|choose_similar_guide|log_selection_ratio|"
    r"choose_guide|guide_log_probability|normalise_weights|normalise_log_weights|guide_weights|"
    r"plain_total|logs_of|similarity_row|similarity4|all_at_least|log_similarities_to_guides|log_vertex_similarity|log_path_similarity|"
    r"guide_vertex|similarity_params|normalise_row_products|plain_path_similarities|plain_sum|"
    r"choose_guide_from_plain|guide_log_probability_from_plain)\b")
LOOKUP = re.compile(r"emlt::ensemble::(guides_for|guides_for_next_step)\b"
                    r"|emlt::(EnsembleGuides::upsilon|PathTypeIndex::(window|find))\b")
ALLOCATION = re.compile(r"^(malloc|free|calloc|realloc|_int_malloc|_int_free|"
                        r"malloc_consolidate|_int_free_merge_chunk|unlink_chunk[.\w]*|"
                        r"tcache_[\w]*|cfree[@.\w]*|operator new|operator delete)\b")
KERNELS = re.compile(r"emlt::ensemble::")
TRACING = re.compile(r"emlt::Scene::(intersect|visible|occluded)\b")
PROPOSE = re.compile(r"emlt::(\w+)::propose\(")


def category_of(name):
    if TREE.search(name):
        return "tree rebuild"
    if LOOKUP.search(name):
        return "guide lookup"
    if SIMILARITY.search(name):
        return "similarity"
    if KERNELS.search(name):
        return "kernel fits"
    if TRACING.search(name):
        return "tracing"
    return "rest"


def parse_callgrind(path):
    """Self cost per function, and (calls, inclusive cost) per call edge. Functions are
    (object, name) pairs; names are callgrind's demangled ones."""
    names = {"ob": {}, "fn": {}}
    self_cost = collections.Counter()
    edges = {}
    ob = fn = None
    cob = cfn = None
    pending_call = None

    def lookup(kind, value):
        m = re.match(r"\((\d+)\)(?: (.*))?$", value)
        if not m:
            return value
        if m.group(2) is not None:
            names[kind][m.group(1)] = m.group(2)
        return names[kind][m.group(1)]

    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if not line or line.startswith("#"):
                continue
            c = line[0]
            if c.isdigit() or c in "+-*":
                cost = int(line.split()[-1]) if len(line.split()) > 1 else 0
                if pending_call is not None:
                    key, calls = pending_call
                    old = edges.get(key, (0, 0))
                    edges[key] = (old[0] + calls, old[1] + cost)
                    pending_call = None
                else:
                    self_cost[(ob, fn)] += cost
                continue
            key, _, value = line.partition("=")
            if key == "ob":
                ob = lookup("ob", value)
            elif key == "fn":
                fn = lookup("fn", value)
                cob = None
            elif key == "cob":
                cob = lookup("ob", value)
            elif key == "cfn":
                cfn = lookup("fn", value)
            elif key == "calls":
                calls = int(value.split()[0])
                callee = (cob if cob is not None else ob, cfn)
                pending_call = (((ob, fn), callee), calls)
                cob = None
    return self_cost, edges


def breakdown(path, engine_object):
    self_cost, edges = parse_callgrind(path)
    callers = collections.defaultdict(list)
    for (caller, callee), (_, cost) in edges.items():
        if caller != callee:
            callers[callee].append((caller, cost))
    functions = set(self_cost) | {f for e in edges for f in e}
    own = {f: f[0] == engine_object for f in functions}
    # Category shares: fixed for the engine's functions and the allocator, callers' weighted
    # mix for the other library functions.
    share = {}
    for f in functions:
        if ALLOCATION.search(f[1] or ""):
            share[f] = {"allocation": 1.0}
            own[f] = True
        elif own[f]:
            share[f] = {category_of(f[1]): 1.0}
    for _ in range(64):
        changed = False
        for f in functions:
            if own[f]:
                continue
            mix = collections.Counter()
            total = 0
            for caller, cost in callers[f]:
                if caller in share:
                    for cat, s in share[caller].items():
                        mix[cat] += s * cost
                    total += cost
            new = {c: v / total for c, v in mix.items()} if total > 0 else {"rest": 1.0}
            if share.get(f) != new:
                share[f] = new
                changed = True
        if not changed:
            break
    result = collections.Counter()
    for f, cost in self_cost.items():
        for cat, s in share.get(f, {"rest": 1.0}).items():
            result[cat] += cost * s
    proposals = collections.defaultdict(lambda: [0, 0])
    for (caller, callee), (calls, cost) in edges.items():
        m = PROPOSE.search(callee[1] or "")
        if m and "run_chain" in (caller[1] or ""):
            proposals[m.group(1)][0] += calls
            proposals[m.group(1)][1] += cost
    return result, proposals


def render_command(args, scene, method_args, mpp, out):
    return ([args.emlt, "render", scene, "--width", str(args.size), "--height", str(args.size),
             "--threads", "1", "--seed", str(args.seed), "-q", "--bootstrap", "10000",
             "--direct-spp", "1", "--mpp", str(mpp), "-o", out] + shlex.split(method_args))


def user_seconds(command):
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--emlt", default=os.path.join(ROOT, "build", "emlt"))
    parser.add_argument("--scene", action="append",
                        help="scene file (default: the Cornell box and the door-ajar room)")
    parser.add_argument("--size", type=int, default=256, help="width and height")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--method", action="append", metavar="NAME=ARGS",
                        help="extra method (default: mlt and emlt with their own mixes)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--mpp-low", type=int, default=16)
    parser.add_argument("--mpp-high", type=int, default=48)
    parser.add_argument("--callgrind-mpp", type=int, default=4)
    parser.add_argument("--no-cpu", action="store_true")
    parser.add_argument("--no-callgrind", action="store_true")
    parser.add_argument("--only", action="append", metavar="NAME",
                        help="measure only these methods (mlt is measured anyway: the ratios "
                             "are to it)")
    parser.add_argument("--structure", action="store_true",
                        help="add emlt-mlt-mix, emlt-it32 and emlt-mlt-mix-it32 (the driver's "
                             "cost apart from the kernels')")
    parser.add_argument("--keep", metavar="DIR",
                        help="keep the callgrind profiles in DIR (SCENE-METHOD.cg)")
    args = parser.parse_args()
    scenes = args.scene or [os.path.join(ROOT, "scenes", s, "scene.json")
                            for s in ("cornell-box", "door-ajar")]
    # MLT's chain count is fixed to what its default gives from 16 mutations per pixel on,
    # so that the low and high runs set up the same chains.
    methods = [("mlt", "--integrator mlt --chains 16384"), ("emlt", "--integrator emlt")]
    if args.structure:
        methods += [("emlt-mlt-mix", "--integrator emlt --mutations mlt"),
                    ("emlt-it32", "--integrator emlt --ensemble-iterations 32"),
                    ("emlt-mlt-mix-it32",
                     "--integrator emlt --mutations mlt --ensemble-iterations 32")]
    for m in args.method or []:
        name, _, method_args = m.partition("=")
        methods.append((name, method_args))
    if args.only:
        methods = [m for m in methods if m[0] == "mlt" or m[0] in args.only]
    pixels = args.size * args.size
    engine = os.path.realpath(args.emlt)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "image.pfm")
        for scene in scenes:
            label = os.path.basename(os.path.dirname(scene))
            print(f"== {label} {args.size}x{args.size}, 1 thread, seed {args.seed}")
            cpu = {}
            if not args.no_cpu:
                for name, method_args in methods:
                    low = min(user_seconds(render_command(args, scene, method_args, args.mpp_low, out))
                              for _ in range(args.repeats))
                    high = min(user_seconds(render_command(args, scene, method_args, args.mpp_high, out))
                               for _ in range(args.repeats))
                    cpu[name] = (high - low) / ((args.mpp_high - args.mpp_low) * pixels) * 1e6
                print(f"CPU time per mutation (user, --mpp {args.mpp_high} minus {args.mpp_low}, "
                      f"min of {args.repeats}):")
                for name, _ in methods:
                    print(f"  {name:12s} {cpu[name]:6.3f} us   {cpu[name] / cpu['mlt']:5.2f}x mlt")
            if args.no_callgrind:
                continue
            per_mutation = {}
            for name, method_args in methods:
                cg = os.path.join(args.keep or tmp, f"{label}-{name}.cg")
                command = (["valgrind", "--tool=callgrind", f"--callgrind-out-file={cg}",
                            "--toggle-collect=*run_chain*",
                            "--toggle-collect=emlt::EnsembleGuides::build*"] +
                           render_command(args, scene, method_args, args.callgrind_mpp, out))
                subprocess.run(command, check=True, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
                costs, proposals = breakdown(cg, engine)
                mutations = args.callgrind_mpp * pixels
                per_mutation[name] = ({c: costs[c] / mutations for c in CATEGORIES},
                                      {k: (v[0], v[1] / v[0]) for k, v in proposals.items() if v[0]})
            print(f"Instructions per mutation (callgrind, --mpp {args.callgrind_mpp}, chain loop "
                  f"and tree rebuild only):")
            print("  " + f"{'':12s}" + "".join(f"{c:>14s}" for c in CATEGORIES) +
                  f"{'total':>10s}{'x mlt':>8s}")
            mlt_total = sum(per_mutation["mlt"][0].values())
            for name, _ in methods:
                cats = per_mutation[name][0]
                total = sum(cats.values())
                print("  " + f"{name:12s}" + "".join(f"{cats[c]:14.0f}" for c in CATEGORIES) +
                      f"{total:10.0f}{total / mlt_total:8.2f}")
            if "emlt" in per_mutation:
                extra = {c: per_mutation["emlt"][0][c] - per_mutation["mlt"][0][c]
                         for c in CATEGORIES}
                print("  " + f"{'emlt - mlt':12s}" + "".join(f"{extra[c]:14.0f}" for c in CATEGORIES) +
                      f"{sum(extra.values()):10.0f}")
            print("Instructions per proposal, by strategy (share of proposals):")
            for name, _ in methods:
                props = per_mutation[name][1]
                count = sum(v[0] for v in props.values())
                row = ", ".join(f"{k} {v[1]:.0f} ({v[0] / count:.0%})"
                                for k, v in sorted(props.items()))
                print(f"  {name:12s} {row}")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
