"""What the script tests share: the repository's paths, the Python with numpy, and the emlt
binary under test (`--emlt PATH` on the command line, else $EMLT_BINARY, else build/emlt)."""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPTS = os.path.join(ROOT, "scripts")
sys.path.insert(0, SCRIPTS)  # so that the tests import the scripts' own modules
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable


def take_emlt_argument():
    """The emlt binary to test; removes `--emlt PATH` from sys.argv so unittest never sees it."""
    if len(sys.argv) > 2 and sys.argv[1] == "--emlt":
        path = sys.argv[2]
        del sys.argv[1:3]
        return os.path.abspath(path)
    return os.environ.get("EMLT_BINARY", os.path.join(ROOT, "build", "emlt"))
