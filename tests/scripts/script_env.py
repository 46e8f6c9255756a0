"""What the script tests share: the repository's paths, the Python with numpy, the emlt
binary under test (`--emlt PATH` on the command line, else $EMLT_BINARY, else build/emlt)
and a way to import the program a test checks.

The tests import the shared image helpers as `tools.images`, from the package at the
repository root: CTest puts the root on PYTHONPATH; by hand, run them from the root as
`PYTHONPATH=. /usr/bin/python3 tests/scripts/test_X.py`."""
import importlib.util
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPTS = os.path.join(ROOT, "scripts")
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable


def load_program(relative_path):
    """The module of a program in scripts/ or bench/ (ROOT-relative path), loaded from its file.

    Those programs are run as files, not imported from a package, so a test loads the one it
    checks by path rather than adding its folder to sys.path (which would also let any other
    file there shadow a module of the same name)."""
    path = os.path.join(ROOT, relative_path)
    name = os.path.splitext(os.path.basename(path))[0]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # as an import would: dataclasses and pickling look it up there
    spec.loader.exec_module(module)
    return module


def take_emlt_argument():
    """The emlt binary to test; removes `--emlt PATH` from sys.argv so unittest never sees it."""
    if len(sys.argv) > 2 and sys.argv[1] == "--emlt":
        path = sys.argv[2]
        del sys.argv[1:3]
        return os.path.abspath(path)
    return os.environ.get("EMLT_BINARY", os.path.join(ROOT, "build", "emlt"))
