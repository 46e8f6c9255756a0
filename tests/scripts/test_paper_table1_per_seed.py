#!/usr/bin/python3
"""CTest 'paper_table1_per_seed': scripts/experiments/paper_table1/per_seed.py on run folders
written here (the layout scripts/ablation.py leaves: run.csv with a row per budget, engine.log
with the engine's "b = ..." line).

    /usr/bin/python3 tests/scripts/test_paper_table1_per_seed.py

Checks each finished run's row (its last budget's MSE and image mean, b, b's printed error and
the bootstrap's size), that a run still going (its last row short of the folder's budget) is
left out, the methods' order as asked, and the one-line errors for a missing scene or method."""
import os
import subprocess
import tempfile
import unittest

from script_env import PYTHON, ROOT

SCRIPT = os.path.join(ROOT, "scripts", "experiments", "paper_table1", "per_seed.py")
HEADER = "per_pixel,seconds,mse,relmse,mse_no_emitter,mean_ratio\n"


def write_run(out, method, seed, rows, b_line=None):
    folder = os.path.join(out, "runs", "stairs", method, "pp-64", f"seed-{seed}")
    os.makedirs(folder)
    with open(os.path.join(folder, "run.csv"), "w") as f:
        f.write(HEADER + "".join(f"{pp},1.0,{mse},0,{mse},{ratio}\n" for pp, mse, ratio in rows))
    if b_line:
        with open(os.path.join(folder, "engine.log"), "w") as f:
            f.write("$ emlt render ...\n" + b_line + "\n")


def run(*args):
    return subprocess.run([PYTHON, SCRIPT, *args], capture_output=True, text=True)


class PerSeed(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.out = self.tmp.name
        write_run(self.out, "MLT", 1, [(32, 40.0, 1.2), (64, 32.92, 1.0713)],
                  "mlt: b = 0.0852681 +- 0.011 (461510 bootstrap samples), 16384 chains")
        write_run(self.out, "MLT", 2, [(64, 0.1949, 0.9961)],
                  "mlt: b = 0.0731525 +- 0.00047 (175582 samples: 100000 bootstrap, 75582 beside "
                  "the chains; the largest 0.0013 of b), 16384 chains")
        write_run(self.out, "PT", 1, [(64, 0.5, 1.001)])  # no normalisation printed
        write_run(self.out, "MLT-4096", 1, [(32, 0.4, 1.0)],  # still going: left out
                  "mlt: b = 0.07 +- 0.001 (100000 bootstrap samples), 4096 chains")

    def tearDown(self):
        self.tmp.cleanup()

    def test_rows(self):
        result = run(self.out, "stairs", "--methods", "MLT,PT,MLT-4096")
        self.assertEqual(result.returncode, 0, result.stderr)
        lines = result.stdout.splitlines()
        self.assertEqual(lines[2], "| MLT | 1 | 32.92 | 1.0713 | 0.08527 | 0.011 | 461,510 |")
        self.assertEqual(lines[3], "| MLT | 2 | 0.1949 | 0.9961 | 0.07315 | 0.00047 | 175,582 |")
        self.assertEqual(lines[4], "| PT | 1 | 0.5 | 1.0010 |  |  |  |")
        self.assertEqual(len(lines), 5, result.stdout)  # the unfinished run is not there

    def test_missing_scene_or_method_is_one_line(self):
        for args in (("nowhere",), ("stairs", "--methods", "EMLT")):
            result = run(self.out, *args)
            self.assertNotEqual(result.returncode, 0)
            self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
            self.assertIn("per_seed:", result.stderr)


if __name__ == "__main__":
    unittest.main()
