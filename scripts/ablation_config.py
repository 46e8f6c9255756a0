"""Experiment configuration for scripts/ablation.py: the method table and the JSON format.

The one place that maps method names to engine arguments is METHODS below.  An
experiment file (scripts/experiments/*.json, format in scripts/README.md) names scenes,
methods, seeds, budgets and the reference; load_config() checks it and resolves it into
plain data classes, raising ConfigError (one line, no traceback) on anything wrong.
"""
import json
import os
import re
import shlex
from dataclasses import dataclass, field

REPO_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class ConfigError(Exception):
    """A problem with the experiment file or the method names: reported as one line."""


# name -> (engine arguments, per-pixel budget flag) or None where the engine has no such
# method yet.  A per-pixel budget of N becomes "--spp N" or "--mpp N"; an equal-time
# budget T becomes "--time T" for every method.  Fill in an entry here when the engine
# gains the method; experiment files can also define methods by explicit arguments.
METHODS = {
    "pt": (["--integrator", "pt"], "--spp"),
    "bdpt": (["--integrator", "bdpt"], "--spp"),
    "mlt": (["--integrator", "mlt"], "--mpp"),  # the engine's default mutation mix
    "gamlt": (["--integrator", "gamlt"], "--mpp"),  # geometry-aware MLT
    # Jakob & Marschner 2012, manifold exploration: bidir and the manifold perturbation.
    "memlt": (["--integrator", "memlt"], "--mpp"),
    "emlt": (["--integrator", "emlt"], "--mpp"),  # ensemble MLT, all strategies
    "emlt-ani": (["--integrator", "emlt", "--mutations", "emlt-ani"], "--mpp"),  # paper Table 1 "Ani"
    "emlt-lin": (["--integrator", "emlt", "--mutations", "emlt-lin"], "--mpp"),  # paper Table 1 "Lin"
    "pssmlt": (["--integrator", "pssmlt"], "--mpp"),  # Kelemen et al. 2002 over the path tracer
    "pssmlt-bdpt": (["--integrator", "pssmlt", "--pss-tracer", "bdpt"], "--mpp"),  # ... over BDPT
    "mmlt": (["--integrator", "mmlt"], "--mpp"),  # Hachisuka et al. 2014, Multiplexed MLT
    # Cline et al. 2005: N seeds per pixel (BDPT samples), their chains --erpt-chains per pixel
    # over the budget (under a time budget, per pass) of 100 steps.
    "erpt": (["--integrator", "erpt"], "--spp"),
    # Ensemble-informed ideas beyond the paper (docs/experiments.md, "Beyond the paper"):
    # the ensemble driver with Veach's mix, then with the density jump and/or the
    # spread-scaled perturbations in place of Veach's lens, caustic and multi-chain moves.
    "emlt-veach": (["--integrator", "emlt", "--mutations", "mlt"], "--mpp"),
    "emlt-jump": (["--integrator", "emlt", "--mutations",
                   "bidir=3,lens=1,emlt-jump=1,caustic=2,multichain=2"], "--mpp"),
    "emlt-jump-near": (["--integrator", "emlt", "--mutations",
                        "bidir=3,lens=1,emlt-jump-near=1,caustic=2,multichain=2"], "--mpp"),
    "emlt-spread": (["--integrator", "emlt", "--mutations",
                     "bidir=3,emlt-spread-lens=2,emlt-spread-caustic=2,emlt-spread-multichain=2"], "--mpp"),
    "emlt-jump-spread": (["--integrator", "emlt", "--mutations",
                          "bidir=3,emlt-spread-lens=1,emlt-jump=1,emlt-spread-caustic=2,"
                          "emlt-spread-multichain=2"], "--mpp"),
}

# "mlt:MIX" names an MLT run with the mutation mix MIX, e.g. "mlt:bidir=1,lens=1".
MIX_PREFIX = "mlt:"

PER_PIXEL = "per_pixel"
SECONDS = "seconds"


@dataclass
class Method:
    """A named way of running the engine: its arguments and the flag its per-pixel budget uses."""
    name: str
    args: list
    budget_flag: str  # "--spp" or "--mpp"
    label: str = ""

    @property
    def is_mlt(self):
        """True when the method runs a Markov chain integrator (writes --stats)."""
        return integrator_of(self.args) not in ("pt", "bdpt", "direct")

    @property
    def dirname(self):
        """A file-system-safe directory name for the method's runs."""
        return safe_name(self.name)


@dataclass
class Scene:
    """One scene of the matrix with the render settings every method shares."""
    name: str
    path: str
    width: int = None
    height: int = None
    max_depth: int = None
    params: dict = field(default_factory=dict)
    crop: list = None
    exposure: float = 0.0

    def engine_args(self):
        """Arguments that fix what is rendered (resolution, depth, -D parameters)."""
        args = []
        if self.width is not None:
            args += ["--width", str(self.width)]
        if self.height is not None:
            args += ["--height", str(self.height)]
        if self.max_depth is not None:
            args += ["--max-depth", str(self.max_depth)]
        for key, value in sorted(self.params.items()):
            args += ["-D", f"{key}={value}"]
        return args


@dataclass
class Budget:
    """Equal work per pixel (kind PER_PIXEL, value = samples or mutations per pixel) or equal time."""
    kind: str
    value: float

    @property
    def tag(self):
        """Directory name of the budget, e.g. 'pp-64' or 'time-2s'."""
        return f"pp-{fmt_number(self.value)}" if self.kind == PER_PIXEL else f"time-{fmt_number(self.value)}s"

    def engine_args(self, method):
        """The budget as engine arguments for method."""
        if self.kind == PER_PIXEL:
            return [method.budget_flag, fmt_number(self.value)]
        return ["--time", fmt_number(self.value)]


@dataclass
class Reference:
    """How each scene's reference image is rendered."""
    integrator: str = "bdpt"
    spp: int = None
    time: float = None
    seed: int = 1000
    args: list = field(default_factory=list)
    mpp: float = None  # MCMC references: mutations per pixel
    parts: int = 1  # independent renders (seeds seed, seed+1, ...) averaged; their spread gives the noise floor
    direct_spp: int = 1  # indirect-only experiments: samples of the direct image subtracted from each part

    @property
    def is_mcmc(self):
        """True when the reference is rendered by a Markov chain integrator."""
        return self.integrator not in ("pt", "bdpt", "direct")

    def engine_args(self, part=0):
        """Engine arguments of one part of the reference render (without scene settings and paths)."""
        args = ["--integrator", self.integrator, "--seed", str(self.seed + part)]
        if self.spp is not None:
            args += ["--spp", str(self.spp)]
        if self.mpp is not None:
            args += ["--mpp", fmt_number(self.mpp)]
        if self.time is not None:
            args += ["--time", fmt_number(self.time)]
        return args + list(self.args)

    def identity(self):
        """Everything that fixes the reference (its cache key)."""
        return [self.engine_args(part) for part in range(self.parts)] + (
            [["parts", self.parts]] if self.parts > 1 else [])

    def describe(self):
        """Short text such as 'bdpt, 4096 spp'."""
        amount = (f"{self.spp} spp" if self.spp is not None else f"{fmt_number(self.mpp)} mpp"
                  if self.mpp is not None else f"{fmt_number(self.time)} s")
        if self.parts > 1:
            amount = f"{self.parts} x {amount}"
        return f"{self.integrator}, {amount}"


@dataclass
class Config:
    """A resolved experiment: every run is scene x budget x method x seed."""
    name: str
    path: str
    description: str
    scenes: list
    methods: list
    seeds: list
    budgets: list
    reference: Reference
    threads: int = 0
    extra_args: list = field(default_factory=list)
    raw: dict = field(default_factory=dict)
    # Indirect light only (EMLT paper 4.1): samples per pixel of the direct image every MCMC
    # run renders separately and the runner subtracts exactly (None: whole images).
    indirect_direct_spp: int = None

    @property
    def indirect_only(self):
        """True when the runs' chains are measured alone against an indirect-only reference."""
        return self.indirect_direct_spp is not None


def fmt_number(value):
    """Shortest decimal text of a number: 64 -> '64', 0.5 -> '0.5'."""
    value = float(value)
    return str(int(value)) if value.is_integer() else repr(value)


def safe_name(name):
    """Replace characters that are awkward in file names (':', '=', ',', spaces, ...) by '_'."""
    return re.sub(r"[^A-Za-z0-9._+-]", "_", name)


def integrator_of(args):
    """The value of --integrator in an argument list (None when absent)."""
    for i, arg in enumerate(args):
        if arg == "--integrator" and i + 1 < len(args):
            return args[i + 1]
        if arg.startswith("--integrator="):
            return arg.split("=", 1)[1]
    return None


def builtin_method(name):
    """The built-in method called name; ConfigError if it is unknown or not in the engine yet."""
    if name.startswith(MIX_PREFIX) and len(name) > len(MIX_PREFIX):
        mix = name[len(MIX_PREFIX):]
        return Method(name, ["--integrator", "mlt", "--mutations", mix], "--mpp")
    if name not in METHODS:
        known = ", ".join(METHODS)
        raise ConfigError(f"unknown method '{name}' (built-in: {known}, or 'mlt:MIX' for a mutation mix; "
                          f"other methods need \"args\" in the config's \"methods\")")
    entry = METHODS[name]
    args, flag = entry
    return Method(name, list(args), flag)


def parse_method(name, spec):
    """A Method from a config entry: spec is None/{} (built-in) or an object with args/mutations."""
    if spec is None or spec == {}:
        return builtin_method(name)
    if not isinstance(spec, dict):
        raise ConfigError(f"method '{name}': expected an object such as {{\"args\": [...]}}, got {spec!r}")
    unknown = set(spec) - {"args", "mutations", "budget", "label"}
    if unknown:
        raise ConfigError(f"method '{name}': unknown keys {sorted(unknown)}")
    if "args" in spec:
        args = spec["args"]
        args = shlex.split(args) if isinstance(args, str) else [str(a) for a in args]
    elif "mutations" in spec:
        args = ["--integrator", "mlt", "--mutations", str(spec["mutations"])]
    else:
        args = builtin_method(name).args
    if integrator_of(args) is None:
        raise ConfigError(f"method '{name}': its args need --integrator")
    budget = spec.get("budget")
    if budget is None:
        budget = "spp" if integrator_of(args) in ("pt", "bdpt", "direct") else "mpp"
    if budget not in ("spp", "mpp"):
        raise ConfigError(f"method '{name}': \"budget\" must be \"spp\" or \"mpp\"")
    return Method(name, args, "--" + budget, spec.get("label", ""))


BITTERLI_PREFIX = "bitterli-"  # scenes/bitterli-X/ holds Bitterli's scene X (his download's folder X/)


def scenes_dir_candidates(path, scenes_dir):
    """Where --scenes DIR may hold the scene at path: DIR/FOLDER/FILE for the path's last folder
    FOLDER and file FILE, then DIR/X/FILE when FOLDER is bitterli-X (Bitterli's own folder name)."""
    folder = os.path.basename(os.path.dirname(os.path.normpath(path)))
    names = [folder]
    if folder.startswith(BITTERLI_PREFIX) and len(folder) > len(BITTERLI_PREFIX):
        names.append(folder[len(BITTERLI_PREFIX):])
    return [os.path.normpath(os.path.join(scenes_dir, name, os.path.basename(path))) for name in names]


def resolve_path(path, config_dir, scenes_dir=None):
    """A scene path from the config: next to the config file first, then in the repository root
    (then the working directory).  With scenes_dir (--scenes DIR), a path found in none of these is
    looked up by its folder name under DIR (scenes_dir_candidates)."""
    if os.path.isabs(path):
        if scenes_dir is None or os.path.exists(path):
            return path
        looked = "not there"
    else:
        for base in (config_dir, REPO_ROOT, os.getcwd()):
            candidate = os.path.normpath(os.path.join(base, path))
            if os.path.exists(candidate):
                return candidate
        looked = f"looked next to the config and in {REPO_ROOT}"
    if scenes_dir is None:
        raise ConfigError(f"scene '{path}' not found ({looked})")
    candidates = scenes_dir_candidates(path, scenes_dir)
    for candidate in candidates:
        if os.path.isfile(candidate):
            return candidate
    raise ConfigError(f"scene '{path}' not found ({looked}, nor at {' or '.join(candidates)} for --scenes)")


def _int_or_none(value, what):
    if value is None:
        return None
    if not isinstance(value, int) or isinstance(value, bool):
        raise ConfigError(f"{what} must be an integer, got {value!r}")
    return value


def parse_scene(entry, defaults, config_dir, scenes_dir=None):
    """A Scene from a config entry (a path string or an object with "path")."""
    if isinstance(entry, str):
        entry = {"path": entry}
    if not isinstance(entry, dict) or "path" not in entry:
        raise ConfigError(f"scene entry {entry!r} needs a \"path\"")
    unknown = set(entry) - {"path", "name", "width", "height", "max_depth", "params", "crop", "exposure"}
    if unknown:
        raise ConfigError(f"scene {entry['path']}: unknown keys {sorted(unknown)}")
    path = resolve_path(entry["path"], config_dir, scenes_dir)
    # A scene found under --scenes keeps the name of the folder the config gives (Bitterli's
    # veach-ajar/ found for scenes/bitterli-veach-ajar/ is named bitterli-veach-ajar).
    found_in_scenes_dir = scenes_dir is not None and path in scenes_dir_candidates(entry["path"], scenes_dir)
    named = entry["path"] if found_in_scenes_dir else path
    name = entry.get("name") or os.path.basename(os.path.dirname(named)) or os.path.splitext(os.path.basename(path))[0]
    crop = entry.get("crop")
    if crop is not None and (not isinstance(crop, list) or len(crop) != 4 or not all(isinstance(v, int) for v in crop)):
        raise ConfigError(f"scene {name}: \"crop\" must be [x, y, width, height] in pixels")
    return Scene(
        name=safe_name(name), path=path,
        width=_int_or_none(entry.get("width", defaults.get("width")), f"scene {name}: width"),
        height=_int_or_none(entry.get("height", defaults.get("height")), f"scene {name}: height"),
        max_depth=_int_or_none(entry.get("max_depth", defaults.get("max_depth")), f"scene {name}: max_depth"),
        params=dict(entry.get("params", {})), crop=crop,
        exposure=float(entry.get("exposure", defaults.get("exposure", 0.0))))


def parse_methods(value):
    """Methods from a list of names or an object name -> spec; order is kept (table columns)."""
    if isinstance(value, list):
        items = [(v, None) if isinstance(v, str) else (v.get("name"), {k: x for k, x in v.items() if k != "name"})
                 for v in value]
    elif isinstance(value, dict):
        items = list(value.items())
    else:
        raise ConfigError("\"methods\" must be a list of names or an object name -> {\"args\": [...]}")
    methods, seen = [], set()
    for name, spec in items:
        if not isinstance(name, str) or not name:
            raise ConfigError(f"method entry {spec!r} has no name")
        if safe_name(name) in seen:
            raise ConfigError(f"method '{name}' is listed twice")
        seen.add(safe_name(name))
        methods.append(parse_method(name, spec))
    return methods


def parse_budgets(value):
    """Budgets from {"per_pixel": [...], "seconds": [...]} (either may be missing)."""
    if not isinstance(value, dict) or not (set(value) <= {PER_PIXEL, SECONDS}):
        raise ConfigError("\"budgets\" must be an object with \"per_pixel\" and/or \"seconds\" lists")
    budgets = []
    for kind in (PER_PIXEL, SECONDS):
        values = value.get(kind, [])
        if not isinstance(values, list) or not all(isinstance(v, (int, float)) and v > 0 for v in values):
            raise ConfigError(f"budgets.{kind} must be a list of positive numbers")
        if kind == PER_PIXEL and not all(float(v).is_integer() for v in values):
            raise ConfigError("budgets.per_pixel must be whole numbers")
        budgets += [Budget(kind, v) for v in sorted(set(values))]
    if not budgets:
        raise ConfigError("\"budgets\" names no budget")
    return budgets


def parse_reference(value):
    """Reference settings: integrator, spp or time, seed, extra args."""
    value = dict(value or {})
    unknown = set(value) - {"integrator", "spp", "mpp", "time", "seed", "args", "parts", "direct_spp"}
    if unknown:
        raise ConfigError(f"reference: unknown keys {sorted(unknown)}")
    ref = Reference(integrator=value.get("integrator", "bdpt"), spp=value.get("spp"), time=value.get("time"),
                    seed=value.get("seed", 1000), args=value.get("args", []), mpp=value.get("mpp"),
                    parts=value.get("parts", 1), direct_spp=value.get("direct_spp", 1))
    if isinstance(ref.args, str):
        ref.args = shlex.split(ref.args)
    for key in ("parts", "direct_spp"):
        if not isinstance(getattr(ref, key), int) or getattr(ref, key) < 1:
            raise ConfigError(f"reference: \"{key}\" must be a positive integer")
    if ref.spp is None and ref.time is None and ref.mpp is None:
        if ref.is_mcmc:
            raise ConfigError("reference: an MCMC reference needs \"mpp\" or \"time\"")
        ref.spp = 1024
    return ref


def parse_indirect_only(value, methods, reference):
    """"indirect_only": {"direct_spp": N} -> N; None when absent or false."""
    if value is None or value is False:
        return None
    if not isinstance(value, dict) or set(value) - {"direct_spp"} or not isinstance(value.get("direct_spp"), int) \
            or value["direct_spp"] < 1:
        raise ConfigError("\"indirect_only\" must be {\"direct_spp\": N} with N >= 1 (samples of the direct image)")
    unfit = [m.name for m in methods if not m.is_mlt]
    if unfit:
        raise ConfigError(f"indirect_only: methods {unfit} render direct light themselves; only MCMC methods "
                          "(direct light rendered separately and subtracted) can be measured on the indirect part")
    if integrator_of(reference.args) is not None:
        raise ConfigError("reference: give the integrator as \"integrator\", not in \"args\"")
    return value["direct_spp"]


def load_config(path, scenes_dir=None):
    """Read and check an experiment file; returns a Config or raises ConfigError.  scenes_dir
    (--scenes DIR) is where scenes missing from the repository are looked up (resolve_path)."""
    try:
        with open(path) as f:
            raw = json.load(f)
    except OSError as e:
        raise ConfigError(f"cannot read config {path}: {e.strerror}")
    except json.JSONDecodeError as e:
        raise ConfigError(f"{path}: invalid JSON: {e}")
    if not isinstance(raw, dict):
        raise ConfigError(f"{path}: the config must be a JSON object")
    known = {"name", "description", "scenes", "methods", "seeds", "budgets", "reference", "width", "height",
             "max_depth", "exposure", "threads", "extra_args", "indirect_only"}
    unknown = set(raw) - known
    if unknown:
        raise ConfigError(f"{path}: unknown keys {sorted(unknown)}")
    config_dir = os.path.dirname(os.path.abspath(path))
    for key in ("scenes", "methods", "budgets"):
        if key not in raw:
            raise ConfigError(f"{path}: missing \"{key}\"")
    defaults = {k: raw[k] for k in ("width", "height", "max_depth", "exposure") if k in raw}
    scenes = [parse_scene(s, defaults, config_dir, scenes_dir) for s in raw["scenes"]]
    if not scenes:
        raise ConfigError(f"{path}: no scenes")
    if len({s.name for s in scenes}) != len(scenes):
        raise ConfigError(f"{path}: scene names must differ (give \"name\" to scenes in same-named folders)")
    seeds = raw.get("seeds", [1])
    if not isinstance(seeds, list) or not seeds or not all(isinstance(s, int) and s >= 0 for s in seeds):
        raise ConfigError(f"{path}: \"seeds\" must be a non-empty list of non-negative integers")
    extra = raw.get("extra_args", [])
    methods = parse_methods(raw["methods"])
    reference = parse_reference(raw.get("reference"))
    return Config(
        name=raw.get("name") or os.path.splitext(os.path.basename(path))[0],
        path=os.path.abspath(path), description=raw.get("description", ""),
        scenes=scenes, methods=methods, seeds=list(dict.fromkeys(seeds)),
        budgets=parse_budgets(raw["budgets"]), reference=reference,
        indirect_direct_spp=parse_indirect_only(raw.get("indirect_only"), methods, reference),
        threads=int(raw.get("threads", 0)),
        extra_args=shlex.split(extra) if isinstance(extra, str) else [str(a) for a in extra], raw=raw)
