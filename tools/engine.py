"""How the scripts call the engine: in this process through the Python module (`import emlt`),
or by spawning the emlt binary, which an MPI run needs (`mpirun -n R emlt render ...`).

Both take the same command-line arguments, so a script writes each render once:

    engine = tools.engine.choose("build/emlt")          # the module built beside the binary
    engine.render(["scene.xml", "--integrator", "mlt", "--mpp", "64", "-o", "out.pfm"])

The module renders what the command line renders, bit for bit (tests/scripts/
test_python_module.py), and its options are the command line's flags under their own names,
so an argument list maps onto its keywords: `--max-depth 5` is max_depth="5", a flag given
without a value is True, the one argument that is not a flag is the scene, `-o` is output.
A value is passed as the text the command line would have parsed, so both refuse the same
values with the same words.
"""
import glob
import importlib.util
import os
import shlex
import subprocess
import sys


class EngineError(Exception):
    """A render or comparison failed; the message is the engine's own one line."""


class EngineMissing(EngineError):
    """The binary (or mpirun) could not be started."""


def keywords_of(args):
    """(scene, keywords) of an `emlt render` argument list (without `render`)."""
    scene, keywords = None, {}
    i = 0
    while i < len(args):
        token = args[i]
        if token in ("-o", "--output"):
            name, value, i = "output", args[i + 1] if i + 1 < len(args) else None, i + 2
        elif token.startswith("--"):
            name, sep, value = token[2:].partition("=")
            i += 1
            if not sep:
                value = True
                if i < len(args) and not args[i].startswith("--") and args[i] != "-o":
                    value, i = args[i], i + 1
            name = name.replace("-", "_")
        else:
            if scene is not None:
                raise EngineError(f"two scenes in one render: {scene} and {token}")
            scene, i = token, i + 1
            continue
        if value is None:
            raise EngineError(f"{token} needs a value")
        if name in keywords:
            raise EngineError(f"--{name.replace('_', '-')} given twice")
        keywords[name] = value
    if scene is None:
        raise EngineError("no scene to render")
    return scene, keywords


def module_beside(binary):
    """The module file a build put beside its binary (BUILD/python/emlt*.so), or None."""
    found = sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(binary)), "python", "emlt*.so")))
    return found[0] if found else None


def import_module(path=None):
    """The module from `path` (a built emlt*.so), else `import emlt` from Python's path."""
    if path is None:
        import emlt
        return emlt
    loaded = sys.modules.get("emlt")
    if loaded is not None and os.path.abspath(getattr(loaded, "__file__", "")) == os.path.abspath(path):
        return loaded
    spec = importlib.util.spec_from_file_location("emlt", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules["emlt"] = module
    return module


class ModuleEngine:
    """Renders in this process; the module releases the GIL, so threads can render at once."""

    kind = "module"

    def __init__(self, module):
        self.module = module

    def version(self):
        return f"emlt {self.module.__version__}"

    def describe(self):
        return f"the Python module {self.module.__file__}"

    def render(self, args, log_path=None):
        """Renders `emlt render ARGS`; returns the statistics dict (the module's)."""
        scene, keywords = keywords_of(args)
        call = "emlt.render(" + ", ".join([repr(scene)] + [f"{k}={v!r}" for k, v in keywords.items()]) + ")"
        try:
            _, stats = self.module.render(scene, progress=False, **keywords)
        except self.module.Error as e:
            message = str(e).strip().splitlines() or ["render failed"]
            self._log(log_path, call, message)
            raise EngineError(message[-1])
        self._log(log_path, call, [f"{kind}: {text}" for kind, text in stats.get("warnings", [])])
        return stats

    def compare(self, reference, images, scene=None):
        """`emlt compare --json [--scene SCENE] REFERENCE IMAGES...`: a figures dict per image."""
        try:
            return [self.module.compare(reference, image, scene=scene) for image in images]
        except self.module.Error as e:
            raise EngineError(str(e).strip())

    @staticmethod
    def _log(path, call, lines):
        if path:
            with open(path, "w") as f:
                f.write("\n".join([call] + list(lines)) + "\n")


class CliEngine:
    """Spawns the binary, under `launcher` (e.g. ["mpirun", "-n", "4"]) when one is given."""

    kind = "cli"

    def __init__(self, binary, launcher=()):
        self.binary = binary
        self.launcher = list(launcher)

    def version(self):
        out = subprocess.run([self.binary, "--version"], capture_output=True, text=True)
        return out.stdout.strip() or out.stderr.strip()

    def describe(self):
        return " ".join(self.launcher + [self.binary])

    def run(self, args, log_path=None, launched=True):
        """Runs `emlt ARGS` (under the launcher when `launched`); the CompletedProcess, or
        EngineError with the engine's last error line."""
        cmd = (self.launcher if launched else []) + [self.binary] + list(args)
        try:
            result = subprocess.run(cmd, capture_output=True, text=True)
        except OSError as e:
            raise EngineMissing(f"{cmd[0]}: {e.strerror}")
        if log_path:
            with open(log_path, "w") as f:
                f.write("$ " + shlex.join(cmd) + "\n" + result.stdout + result.stderr)
        if result.returncode != 0:
            lines = [line for line in (result.stderr + result.stdout).splitlines() if line.strip()]
            errors = [line for line in lines if "error" in line.lower()]
            raise EngineError((errors or lines or [f"exit status {result.returncode}"])[-1].strip())
        return result

    def render(self, args, log_path=None):
        """Renders `emlt render ARGS`; returns None (the statistics are in --stats FILE)."""
        self.run(["render"] + list(args), log_path)

    def compare(self, reference, images, scene=None):
        """`emlt compare --json [--scene SCENE] REFERENCE IMAGES...`: a figures dict per image
        (one process per 200 images)."""
        import json
        figures = []
        for i in range(0, len(images), 200):
            part = list(images[i:i + 200])
            args = ["compare", reference] + part + ["--json"] + (["--scene", scene] if scene else [])
            # A comparison is one process whatever renders: under mpirun each rank would print it.
            output = self.run(args, launched=False).stdout
            lines = [line for line in output.splitlines() if line.strip().startswith("{")]
            if len(lines) != len(part):
                raise EngineError(f"emlt compare printed {len(lines)} results for {len(part)} images")
            figures += [json.loads(line) for line in lines]
        return figures


def mpi_launcher(ranks):
    """`mpirun -n RANKS`; Open MPI also told to run as root and on more ranks than cores
    (as tests/mpi/mpi_check.sh does), which MPICH needs no flag for."""
    launcher = ["mpirun"]
    try:
        version = subprocess.run(["mpirun", "--version"], capture_output=True, text=True).stdout
    except OSError:
        raise EngineMissing("mpirun not found (apt-get install openmpi-bin)")
    if "open mpi" in version.lower() or "openrte" in version.lower():
        launcher += ["--allow-run-as-root", "--oversubscribe"]
    return launcher + ["-n", str(ranks)]


def choose(binary, kind="auto", mpi_ranks=None):
    """The engine a script renders with.

    kind "auto": the module built beside `binary` (BUILD/python) when there is one, else the
    binary; "module": the module beside the binary, else `import emlt` from Python's path;
    "cli": the binary. mpi_ranks R: `mpirun -n R BINARY` (the module runs one process)."""
    if kind not in ("auto", "module", "cli"):
        raise EngineError(f"unknown engine '{kind}' (auto, module or cli)")
    if mpi_ranks is not None:
        if kind == "module":
            raise EngineError("an MPI run spawns the binary: use the cli engine with mpirun")
        return CliEngine(binary, mpi_launcher(mpi_ranks))
    if kind == "cli":
        return CliEngine(binary)
    path = module_beside(binary)
    if path is None and kind == "auto":
        return CliEngine(binary)
    try:
        return ModuleEngine(import_module(path))
    except ImportError as e:
        raise EngineError(f"no Python module emlt ({e}); build it with scripts/setup.sh, or use the cli engine")
