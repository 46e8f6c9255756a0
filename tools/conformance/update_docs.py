"""Regenerates the conformance figures in the docs from a run of the suite.

    python3 -m tools.conformance.update_docs [--emlt build/emlt]      (from the repository root)

Runs tests/conformance/check.py over every scene, writes the full per-scene table to
docs/conformance.md and the summary by group of conventions into README.md between its
`<!-- conformance:begin -->` and `<!-- conformance:end -->` markers.
"""
import argparse
import os
import subprocess
import sys
import tempfile

from tools import ROOT

BEGIN, END = "<!-- conformance:begin -->", "<!-- conformance:end -->"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--emlt", default=os.path.join(ROOT, "build", "emlt"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as work:
        table, summary = os.path.join(work, "table.md"), os.path.join(work, "summary.md")
        # check.py imports tools.images: it runs with the repository root on its PYTHONPATH,
        # as CTest runs it.
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            p for p in (ROOT, os.environ.get("PYTHONPATH")) if p))
        run = subprocess.run([sys.executable, os.path.join(ROOT, "tests", "conformance", "check.py"),
                              "--emlt", args.emlt, "--table", table, "--summary", summary],
                             capture_output=True, text=True, env=env)
        if not os.path.exists(table):
            print(run.stdout + run.stderr, file=sys.stderr)
            return 1
        tally = run.stdout.strip().splitlines()[-1]
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True).stdout.strip()
        with open(os.path.join(ROOT, "docs", "conformance.md"), "w") as f:
            f.write("# Conformance with Mitsuba 0.6 and pbrt-v4, scene by scene\n\n"
                    "Written by `python3 -m tools.conformance.update_docs` (engine at commit "
                    f"{commit}): every scene of `tests/conformance/`, rendered by emlt with each "
                    "integrator it lists (two seeds) and compared with Mitsuba 0.6's own image; "
                    "the `pbrt-*` scenes, which emlt reads in pbrt-v4's format, are compared with "
                    "pbrt-v4's own image as well (reference *pbrt-v4*: rendered by pbrt-v4 built "
                    "with `tools/conformance/build-pbrt.sh`, see `tests/conformance/references/pbrt-v4/`). "
                    "*Mean / reference's* is per colour channel (within 1 % passes); *error / noise* "
                    "is the mean squared difference from the reference image over what the renders' "
                    "own noise explains (about 1 when they agree; 2 fails). See "
                    "[compatibility.md](compatibility.md) for what the scenes cover.\n\n"
                    f"Result: {tally.replace('conformance: ', '')}.\n\n")
            f.write(open(table).read())
        readme_path = os.path.join(ROOT, "README.md")
        readme = open(readme_path).read()
        if BEGIN not in readme or END not in readme:
            print("update_docs: README.md has no conformance markers", file=sys.stderr)
            return 1
        head, rest = readme.split(BEGIN, 1)
        _, tail = rest.split(END, 1)
        with open(readme_path, "w") as f:
            f.write(head + BEGIN + "\n" + open(summary).read() + END + tail)
        print(tally)
    return 0


if __name__ == "__main__":
    sys.exit(main())
