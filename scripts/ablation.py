#!/usr/bin/python3
"""Ablation runner: scenes x methods x seeds x budgets, tables, convergence plots, crops, report.

    scripts/ablation.py scripts/experiments/cornell-small.json --out out/ablation-cornell-small --emlt build/emlt

Renders each scene's reference once (cached by the scene's content and the reference
settings), then runs every (scene, budget, method, seed) of the experiment with
`emlt render --reference REF --log run.csv`, one render each, in sequence.  Runs whose
outputs exist are skipped, so an interrupted experiment resumes where it stopped.  Final
metrics come from `emlt compare --json --scene SCENE` on the saved images, so the tables
equal what `emlt compare` prints.  Renders and comparisons go through the Python module built
beside --emlt (BUILD/python: `import emlt`, in this process, the same bits as the binary)
when there is one, else through the binary; `--engine cli` spawns the binary, and `--mpi R`
spawns `mpirun -n R emlt render ...` for every render.  Writes into --out:

  results.csv            one row per run: metrics, seconds, MLT acceptance rates
  table.md               MSE / relMSE / time per scene x method, mean +- std over seeds
  convergence.png        log-log MSE against samples or mutations per pixel (band: seeds' min..max)
  convergence_time.png   log-log MSE against seconds
  strip.png              reference and each method's first-seed image, same tone mapping
  report.html            a page tying them together (relative links, no external files)
  runs/SCENE/METHOD/BUDGET/seed-N/   image.pfm, image.png, run.csv, stats.json (MLT), run.json
  references/SCENE.pfm   copy of the cached reference the runs were measured against

Methods: pt, bdpt, mlt, 'mlt:MIX' (mlt with --mutations MIX), and any method the config
defines by explicit engine arguments.  The config format is described in scripts/README.md.
"""
import argparse
import concurrent.futures
import csv
import hashlib
import json
import os
import re
import shutil
import sys
import tempfile
import threading
import time

from ablation_config import REPO_ROOT, ConfigError, load_config

# The image helpers are tools.images, in the repository's Python package at the root; run as
# scripts/ablation.py, Python puts this folder on the path (for ablation_config), not the root.
sys.path.insert(0, REPO_ROOT)
from tools.engine import EngineError, choose  # noqa: E402

PROG = "ablation"
RESULT_FIELDS = ["scene", "method", "seed", "budget_kind", "budget", "per_pixel", "seconds", "mse", "relmse",
                 "mse_no_emitter", "mean_ratio", "pixels", "image", "mse_net", "reference_floor"]


class RunError(Exception):
    """An engine call failed: reported as one line."""


# ---------------------------------------------------------------------------------------------
# Engine calls


def render(emlt, args, log_path=None):
    """`emlt render ARGS` with the chosen engine (module or binary, tools/engine.py); RunError
    with the engine's one-line error if it fails."""
    try:
        emlt.render(args, log_path=log_path)
    except EngineError as e:
        raise RunError(str(e))


def hash_file(path):
    """SHA-256 of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def scene_files(scene_path):
    """The scene file and every file it references (quoted names that exist relative to its folder)."""
    folder = os.path.dirname(scene_path)
    with open(scene_path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    files = {os.path.abspath(scene_path)}
    for name in re.findall(r"\"([^\"\n]+)\"", text):
        candidate = os.path.normpath(os.path.join(folder, name))
        if os.path.isfile(candidate):
            files.add(candidate)
    return sorted(files)


_SCENE_HASHES = {}


def scene_hash(scene):
    """Hash of the scene's content: its file, the files it references, and its render settings."""
    memo = (scene.path, tuple(scene.engine_args()))
    if memo not in _SCENE_HASHES:
        _SCENE_HASHES[memo] = _scene_hash(scene)
    return _SCENE_HASHES[memo]


def _scene_hash(scene):
    """scene_hash() without the memo."""
    folder = os.path.dirname(scene.path)
    content = [(os.path.relpath(p, folder), hash_file(p)) for p in scene_files(scene.path)]
    return hashlib.sha256(json.dumps([content, scene.engine_args()]).encode()).hexdigest()


def reference_key(config, scene):
    """The cache key of a scene's reference: scene content and settings plus reference settings."""
    settings = config.reference.engine_args() if config.reference.parts == 1 else config.reference.identity()
    if config.indirect_only:
        settings = [settings, "indirect-only", config.reference.direct_spp]
    return hashlib.sha256(json.dumps([scene_hash(scene), settings]).encode()).hexdigest()[:20]


def render_cached(emlt, args, output):
    """Render `emlt render ARGS -o OUTPUT` unless OUTPUT exists and OUTPUT.args records the same
    arguments (written only after a successful render)."""
    record = output + ".args"
    text = json.dumps(args)
    if os.path.exists(output) and os.path.exists(record):
        with open(record) as f:
            if f.read() == text:
                return output
    os.makedirs(os.path.dirname(output), exist_ok=True)
    render(emlt, args + ["-o", output, "--quiet"], log_path=output + ".log")
    with open(record, "w") as f:
        f.write(text)
    return output


def direct_args(scene, spp, seed, threads):
    """The direct image an MCMC run with --direct separate --direct-spp SPP --seed SEED renders
    first: `--integrator direct` with the same seed and samples gives the same bits."""
    return [scene.path, "--threads", str(threads)] + scene.engine_args() + [
        "--integrator", "direct", "--spp", str(spp), "--seed", str(seed)]


def indirect_args(config):
    """What every MCMC render of an indirect-only experiment adds: direct light rendered apart."""
    return ["--direct", "separate", "--direct-spp", str(config.indirect_direct_spp)] if config.indirect_only else []


def ensure_reference(config, scene, emlt, cache_dir, out_dir):
    """Render (or reuse from the cache) the scene's reference; copy it to out/references/SCENE.pfm.

    The cache key hashes the scene's content, its resolution/depth/parameters and the
    reference settings, so any change to them renders a new reference.  With "parts": K the
    reference is the mean of K renders with seeds seed..seed+K-1, and their spread gives its
    own noise (the floor every MSE against it contains).  In an indirect-only experiment
    each part is its chains alone: an MCMC reference renders direct light separately and
    the same direct image is subtracted (exactly); another integrator's image has a direct
    image of "direct_spp" samples subtracted.  Returns (path, key, noise floor or None).
    """
    from tools.images import read_pfm, write_pfm
    import numpy as np
    ref = config.reference
    key = reference_key(config, scene)
    os.makedirs(cache_dir, exist_ok=True)
    cached = os.path.join(cache_dir, f"{scene.name}-{key}.pfm")
    if os.path.exists(cached):
        print(f"reference {scene.name}: cached {cached}", file=sys.stderr)
    else:
        print(f"reference {scene.name}: rendering ({ref.describe()}"
              f"{', indirect only' if config.indirect_only else ''}) ...", file=sys.stderr, flush=True)
        start = time.monotonic()
        with tempfile.TemporaryDirectory(dir=cache_dir) as tmp:
            parts = []
            for part in range(ref.parts):
                image = os.path.join(tmp, f"part-{part}.pfm")
                args = ref.engine_args(part)
                if config.indirect_only and ref.is_mcmc:
                    args += ["--direct", "separate", "--direct-spp", str(ref.direct_spp)]
                cmd = [scene.path, "-o", image, "--quiet", "--threads", str(config.threads)]
                try:
                    render(emlt, cmd + scene.engine_args() + args, log_path=os.path.join(tmp, f"engine-{part}.log"))
                    pixels = read_pfm(image).astype(np.float64)
                    if config.indirect_only:
                        direct = os.path.join(tmp, f"direct-{part}.pfm")
                        render_cached(emlt, direct_args(scene, ref.direct_spp, ref.seed + part, config.threads),
                                      direct)
                        pixels -= read_pfm(direct)
                except RunError as e:
                    raise RunError(f"reference of {scene.name} failed: {e}")
                parts.append(pixels)
            parts = np.stack(parts)
            mean = parts.mean(axis=0)
            # Variance of the mean, per pixel and channel, averaged like `emlt compare`'s MSE.
            floor = float(parts.var(axis=0, ddof=1).mean() / len(parts)) if len(parts) > 1 else None
            write_pfm(os.path.join(tmp, "reference.pfm"), mean)
            with open(os.path.join(tmp, "reference.json"), "w") as f:
                json.dump({"scene": scene.path, "settings": scene.engine_args(), "reference": ref.identity(),
                           "indirect_only": config.indirect_only, "key": key, "noise_floor_mse": floor,
                           "seconds": round(time.monotonic() - start, 1)}, f, indent=1)
            os.replace(os.path.join(tmp, "reference.json"), cached[:-4] + ".json")
            os.replace(os.path.join(tmp, "reference.pfm"), cached)  # last: a reference exists only once complete
        print(f"reference {scene.name}: {time.monotonic() - start:.1f} s -> {cached}", file=sys.stderr)
    floor = None
    if os.path.exists(cached[:-4] + ".json"):
        with open(cached[:-4] + ".json") as f:
            floor = json.load(f).get("noise_floor_mse")
    local = os.path.join(out_dir, "references", scene.name + ".pfm")
    os.makedirs(os.path.dirname(local), exist_ok=True)
    if not os.path.exists(local) or hash_file(local) != hash_file(cached):
        shutil.copyfile(cached, local)
    return local, key, floor


def seed_references(config, emlt, references, out_dir):
    """Indirect-only experiments: per (scene, seed) the reference each run is measured against,
    the indirect reference plus that seed's exact direct image, so that the engine's own log
    and `emlt compare` see only the chains' error.  Returns {(scene, seed): (path, direct path)}."""
    from tools.images import read_pfm, write_pfm
    import numpy as np
    out = {}
    for scene in config.scenes:
        indirect = read_pfm(references[scene.name][0]).astype(np.float64)
        for seed in config.seeds:
            direct = render_cached(emlt, direct_args(scene, config.indirect_direct_spp, seed, config.threads),
                                   os.path.join(out_dir, "direct", scene.name, f"seed-{seed}.pfm"))
            path = os.path.join(out_dir, "references", f"{scene.name}.seed-{seed}.pfm")
            image = (indirect + read_pfm(direct)).astype(np.float32)
            if not os.path.exists(path) or not np.array_equal(read_pfm(path), image):
                write_pfm(path, image)
            out[(scene.name, seed)] = (path, direct)
    return out


# ---------------------------------------------------------------------------------------------
# Runs


class Run:
    """One engine call: scene x budget x method x seed, in its own directory."""

    def __init__(self, config, scene, budget, method, seed, out_dir):
        self.config, self.scene, self.budget, self.method, self.seed = config, scene, budget, method, seed
        self.dir = os.path.join(out_dir, "runs", scene.name, method.dirname, budget.tag, f"seed-{seed}")
        self.image = os.path.join(self.dir, "image.pfm")
        self.log = os.path.join(self.dir, "run.csv")
        self.stats = os.path.join(self.dir, "stats.json")
        self.marker = os.path.join(self.dir, "run.json")

    def engine_args(self):
        """The run's engine arguments, without paths (also its identity for resuming)."""
        return (["--seed", str(self.seed), "--threads", str(self.config.threads)] + self.scene.engine_args()
                + self.method.args + self.budget.engine_args(self.method) + self.config.extra_args
                + indirect_args(self.config))

    def key(self, reference_key):
        """What must match for a finished run to be reused."""
        return {"scene": scene_hash(self.scene), "reference": reference_key, "args": self.engine_args()}

    def is_done(self, reference_key):
        """True when the run finished with the same settings (its outputs and marker exist)."""
        needed = [self.image, self.marker] + ([self.stats] if self.method.is_mlt else [])
        if not all(os.path.exists(p) for p in needed):
            return False
        try:
            with open(self.marker) as f:
                return json.load(f).get("key") == self.key(reference_key)
        except (OSError, ValueError):
            return False

    def execute(self, emlt, reference, reference_key):
        """Render; the marker run.json is written last, so only complete runs count as done."""
        os.makedirs(self.dir, exist_ok=True)
        if os.path.exists(self.marker):
            os.remove(self.marker)
        cmd = [self.scene.path, "-o", self.image, "--quiet", "--reference", reference,
               "--log", self.log] + (["--stats", self.stats] if self.method.is_mlt else []) + self.engine_args()
        start = time.monotonic()
        render(emlt, cmd, log_path=os.path.join(self.dir, "engine.log"))
        wall = time.monotonic() - start
        with open(self.marker, "w") as f:
            json.dump({"key": self.key(reference_key), "engine": emlt.describe(), "arguments": ["render"] + cmd,
                       "wall_seconds": round(wall, 3)}, f, indent=1)
        return wall

    def describe(self):
        """Progress text: scene method seed budget."""
        return f"{self.scene.name} {self.method.name} seed {self.seed} {self.budget.tag}"


def plan_runs(config, out_dir):
    """Every run of the experiment in a fixed order: scene, budget, method, seed."""
    return [Run(config, scene, budget, method, seed, out_dir)
            for scene in config.scenes for budget in config.budgets
            for method in config.methods for seed in config.seeds]


def probe_methods(config, methods, emlt):
    """Fail fast: render 2x2 pixels at budget 1 with each method, raising RunError naming a bad one."""
    scene = config.scenes[0]
    with tempfile.TemporaryDirectory() as tmp:
        for method in methods:
            args = list(method.args)
            if method.is_mlt and "--bootstrap" not in args:
                args += ["--bootstrap", "64"]
            cmd = [scene.path, "-o", os.path.join(tmp, "probe.pfm"), "--quiet", "--width", "2",
                   "--height", "2", "--threads", "1", method.budget_flag, "1"] + args + config.extra_args
            try:
                render(emlt, cmd)
            except RunError as e:
                raise RunError(f"method '{method.name}' does not run in this engine: {e}")


def run_reference(run, references):
    """(reference path, reference key) a run is measured against."""
    path, key = references[run.scene.name][:2]
    seeded = references.get((run.scene.name, run.seed))
    return (seeded[0] if seeded else path), key


def execute_runs(runs, emlt, references, jobs):
    """Run what is not done yet, printing '[k/N] scene method seed budget ...' lines on stderr.

    Returns (number executed, number skipped).  Stops at the first failing run (RunError).
    """
    total = len(runs)
    pending = []
    skipped = 0
    for k, run in enumerate(runs, 1):
        if run.is_done(references[run.scene.name][1]):
            skipped += 1
        else:
            pending.append((k, run))
    if skipped:
        print(f"{skipped} of {total} runs already done, skipped", file=sys.stderr)
    lock = threading.Lock()
    tty = sys.stderr.isatty()

    def one(item):
        k, run = item
        reference, key = run_reference(run, references)
        if jobs == 1 and tty:
            print(f"[{k}/{total}] {run.describe()} ...", end="", file=sys.stderr, flush=True)
        try:
            wall = run.execute(emlt, reference, key)
        except RunError as e:
            if jobs == 1 and tty:
                print(" failed", file=sys.stderr)
            raise RunError(f"method '{run.method.name}' failed on {run.scene.name} (seed {run.seed}, "
                           f"{run.budget.tag}): {e}; see {os.path.join(run.dir, 'engine.log')}")
        with lock:
            if jobs == 1 and tty:
                print(f" {wall:.1f} s", file=sys.stderr, flush=True)
            else:
                print(f"[{k}/{total}] {run.describe()} ... {wall:.1f} s", file=sys.stderr, flush=True)

    if jobs == 1:
        for item in pending:
            one(item)
    else:
        with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
            futures = [pool.submit(one, item) for item in pending]
            for future in futures:
                future.result()
    return len(pending), skipped


# ---------------------------------------------------------------------------------------------
# Results


def read_log(path):
    """The convergence log of a run as a list of dicts of floats ([] when the engine wrote none:
    an MCMC render whose chains had nothing to do, e.g. direct light alone)."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return [{k: (float(v) if v not in ("", None) else None) for k, v in row.items()} for row in csv.DictReader(f)]


def compare_metrics(emlt, reference, images, scene_path):
    """`emlt compare --json --scene SCENE REF IMAGES...`: a dict image path -> metrics dict."""
    try:
        return dict(zip(images, emlt.compare(reference, images, scene=scene_path)))
    except EngineError as e:
        raise RunError(f"emlt compare: {e}")


def collect_results(config, runs, emlt, references, out_dir):
    """One row per run: final metrics from `emlt compare`, seconds from the log, MLT acceptance."""
    rows = []
    for scene in config.scenes:
        scene_runs = [r for r in runs if r.scene.name == scene.name]
        metrics = {}
        for reference in dict.fromkeys(run_reference(r, references)[0] for r in scene_runs):
            metrics.update(compare_metrics(emlt, reference, [r.image for r in scene_runs
                                                             if run_reference(r, references)[0] == reference],
                                           scene.path))
        floor = references[scene.name][2]
        for run in scene_runs:
            m = metrics[run.image]
            log = read_log(run.log)
            row = {"scene": scene.name, "method": run.method.name, "seed": run.seed, "budget_kind": run.budget.kind,
                   "budget": run.budget.value, "per_pixel": log[-1]["per_pixel"] if log else None,
                   "seconds": log[-1]["seconds"] if log else None, "mse": m["mse"], "relmse": m["relmse"],
                   "mse_no_emitter": m.get("mse_no_emitter"), "mean_ratio": m["mean_ratio"],
                   "pixels": m["pixels"], "image": os.path.relpath(run.image, out_dir),
                   "mse_net": m["mse"] - floor if floor is not None else None, "reference_floor": floor}
            if run.method.is_mlt and os.path.exists(run.stats):
                with open(run.stats) as f:
                    stats = json.load(f)
                for strategy in stats.get("strategies", []):
                    row["acceptance_" + strategy["name"]] = strategy.get("mean_acceptance")
            row["_log"] = log
            rows.append(row)
    return rows


def run_reference_for_strip(config, scene, references):
    """The image the strip shows as the reference: in an indirect-only experiment the first
    seed's (indirect reference + that seed's direct image), comparable with the runs' images."""
    seeded = references.get((scene.name, config.seeds[0]))
    return seeded[0] if seeded else references[scene.name][0]


def chains_variance(config, runs, references):
    """Indirect-only experiments: per (scene, budget, method) the chains' variance across seeds,
    i.e. the per-pixel sample variance (ddof 1) over seeds of (image - that seed's direct image),
    averaged over pixels and channels like `emlt compare`'s MSE (scripts/chain_variance.py's
    figure divided by 3, since it sums the channels).  The chains are unbiased, so this is their
    MSE without any reference; it needs two seeds or more."""
    from tools.images import read_pfm
    import numpy as np
    groups = {}
    for run in runs:
        groups.setdefault((run.scene.name, run.budget.kind, run.budget.value, run.method.name), []).append(run)
    out = []
    for (scene, kind, value, method), members in groups.items():
        if len(members) < 2:
            continue
        chains = np.stack([read_pfm(r.image).astype(np.float64) - read_pfm(references[(scene, r.seed)][1])
                           for r in members])
        out.append({"scene": scene, "budget_kind": kind, "budget": value, "method": method, "seeds": len(members),
                    "chains_variance": float(chains.var(axis=0, ddof=1).mean())})
    return out


def write_chains_csv(chains, path):
    """chains.csv: one row per (scene, budget, method)."""
    fields = ["scene", "budget_kind", "budget", "method", "seeds", "chains_variance"]
    with open(path, "w", newline="") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(fields)
        for row in chains:
            writer.writerow([csv_value(row[k]) for k in fields])


def csv_value(value):
    """Full-precision text of a value (repr of floats round-trips exactly); '' for None."""
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(int(value)) if value.is_integer() and abs(value) < 1e15 else repr(value)
    return str(value)


def write_results_csv(rows, path):
    """results.csv: the fixed columns, then every acceptance_<strategy> column seen, sorted."""
    extra = sorted({k for row in rows for k in row if k.startswith("acceptance_")})
    with open(path, "w", newline="") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(RESULT_FIELDS + extra)
        for row in rows:
            writer.writerow([csv_value(row.get(k)) for k in RESULT_FIELDS + extra])


# ---------------------------------------------------------------------------------------------


def publish_figures(out_dir, prefix):
    """Copy convergence.png and strip.png to PREFIX-convergence.png and PREFIX-strip.png."""
    folder = os.path.dirname(os.path.abspath(prefix))
    os.makedirs(folder, exist_ok=True)
    for name in ("convergence", "strip"):
        target = f"{prefix}-{name}.png"
        shutil.copyfile(os.path.join(out_dir, name + ".png"), target)
        print(f"{PROG}: copied {name}.png to {target}", file=sys.stderr)


def default_emlt():
    """build/emlt in the current directory, else in the repository root."""
    for candidate in ("build/emlt", os.path.join(REPO_ROOT, "build", "emlt")):
        if os.path.exists(candidate):
            return candidate
    return "build/emlt"


def default_cache():
    """$XDG_CACHE_HOME/emlt/references (~/.cache/emlt/references)."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "emlt", "references")


def parse_args(argv):
    """Command-line options."""
    parser = argparse.ArgumentParser(prog="ablation.py", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("config", help="experiment file (JSON), e.g. scripts/experiments/cornell-small.json")
    parser.add_argument("--out", help="output directory (default: out/ablation-<config name>)")
    parser.add_argument("--emlt", default=None,
                        help="the emlt binary (default: build/emlt); its build's Python module renders unless "
                             "--engine cli")
    parser.add_argument("--engine", choices=("auto", "module", "cli"), default="auto",
                        help="render through the Python module beside --emlt (auto: when it was built) or by "
                             "spawning the binary")
    parser.add_argument("--mpi", type=int, metavar="R", default=None,
                        help="spawn every render as `mpirun -n R emlt render ...` (the binary, with MPI)")
    parser.add_argument("--jobs", type=int, default=1,
                        help="renders at a time, each a process of the binary (default 1; more distorts the "
                             "time columns)")
    parser.add_argument("--cache", default=None,
                        help="reference cache directory (default: $XDG_CACHE_HOME/emlt/references)")
    parser.add_argument("--scenes", metavar="DIR", default=None,
                        help="look up a scene whose path is not in the repository by its folder name under DIR: "
                             "scenes/X/scene.xml as DIR/X/scene.xml, and scenes/bitterli-X/scene.xml also as "
                             "DIR/X/scene.xml (e.g. a folder of Bitterli's downloads)")
    parser.add_argument("--no-report", action="store_true", help="run and write results.csv only")
    parser.add_argument("--figures", metavar="PREFIX",
                        help="also copy convergence.png and strip.png to PREFIX-convergence.png and "
                             "PREFIX-strip.png (docs/comparing-methods.md's figures: --figures docs/ablation)")
    return parser.parse_args(argv)


def main(argv=None):
    """Entry point: returns the exit status (0 ok, 1 run failure, 2 configuration error)."""
    args = parse_args(argv)
    if args.scenes is not None and not os.path.isdir(args.scenes):
        print(f"{PROG}: error: --scenes: no folder {args.scenes}", file=sys.stderr)
        return 2
    try:
        config = load_config(args.config, os.path.abspath(args.scenes) if args.scenes is not None else None)
    except ConfigError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    emlt = os.path.abspath(args.emlt or default_emlt())
    if not (os.path.isfile(emlt) and os.access(emlt, os.X_OK)):
        print(f"{PROG}: error: emlt binary not found at {emlt} (build it, or pass --emlt)", file=sys.stderr)
        return 2
    if args.jobs < 1:
        print(f"{PROG}: error: --jobs must be at least 1", file=sys.stderr)
        return 2
    if args.mpi is not None and args.mpi < 1:
        print(f"{PROG}: error: --mpi must be at least 1", file=sys.stderr)
        return 2
    # The module renders one image at a time per process: N renders at once are N processes.
    kind = args.engine
    if args.jobs > 1 and kind == "module":
        print(f"{PROG}: error: --jobs {args.jobs} needs the binary (the Python module renders one image at a "
              "time): drop --engine module", file=sys.stderr)
        return 2
    if args.jobs > 1:
        kind = "cli"
    try:
        emlt = choose(emlt, kind, args.mpi)
    except EngineError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    out_dir = os.path.abspath(args.out or os.path.join("out", f"ablation-{config.name}"))
    os.makedirs(out_dir, exist_ok=True)
    cache_dir = os.path.abspath(args.cache or default_cache())
    started = time.monotonic()
    try:
        runs = plan_runs(config, out_dir)
        keys = {scene.name: reference_key(config, scene) for scene in config.scenes}
        todo = [r for r in runs if not r.is_done(keys[r.scene.name])]
        probe_methods(config, list({r.method.name: r.method for r in todo}.values()), emlt)
        references = {scene.name: ensure_reference(config, scene, emlt, cache_dir, out_dir)
                      for scene in config.scenes}
        if config.indirect_only:
            references.update(seed_references(config, emlt, references, out_dir))
        executed, skipped = execute_runs(runs, emlt, references, args.jobs)
        rows = collect_results(config, runs, emlt, references, out_dir)
        write_results_csv(rows, os.path.join(out_dir, "results.csv"))
        chains = chains_variance(config, runs, references) if config.indirect_only else []
        if chains:
            write_chains_csv(chains, os.path.join(out_dir, "chains.csv"))
        if not args.no_report:
            import ablation_report
            ablation_report.write_report(config, rows, out_dir, emlt.version(),
                                         {scene.name: run_reference_for_strip(config, scene, references)
                                          for scene in config.scenes}, chains)
            if args.figures:
                publish_figures(out_dir, args.figures)
    except RunError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"\n{PROG}: interrupted; run the same command again to resume", file=sys.stderr)
        return 130
    except ConfigError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    print(f"{PROG}: {executed} runs rendered, {skipped} skipped, {time.monotonic() - started:.1f} s; "
          f"wrote {os.path.join(out_dir, 'report.html')}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
