#!/usr/bin/python3
"""CTest 'point_sets_script': scripts/experiments/direct_samplers/point_sets.py on 8x8 images.

    /usr/bin/python3 tests/scripts/test_point_sets_script.py --emlt build/emlt

Checks that every set is run at every N, that the reference's renders take the low-discrepancy sets in turn, that the
reported RMSE is that of the kept images against the kept references (less the references'
own error), that the table compares each
set with spherical Fibonacci, and that a second call renders nothing again.
"""
import csv
import glob
import json
import os
import subprocess
import tempfile
import unittest

import numpy as np

from script_env import PYTHON, ROOT, take_emlt_argument
from tools.images import read_pfm

SCRIPT = os.path.join(ROOT, "scripts", "experiments", "direct_samplers", "point_sets.py")
EMLT = take_emlt_argument()
SETS = ("independent", "fibonacci", "sobol", "larcher-pillichshammer", "blue-noise")


def run(out):
    return subprocess.run(
        [PYTHON, SCRIPT, "--emlt", EMLT, "--out", out, "--scenes", "box", "--seeds", "2",
         "--size", "8", "--samples", "4,8", "--ref-samples", "64", "--ref-renders", "2",
         "--threads", "1"],
        capture_output=True, text=True, timeout=300)


class PointSets(unittest.TestCase):
    def test_reports_every_set_against_the_reference(self):
        with tempfile.TemporaryDirectory() as out:
            first = run(out)
            self.assertEqual(first.returncode, 0, first.stderr)
            with open(os.path.join(out, "results.csv")) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual({(r["method"], r["samples"]) for r in rows
                              if r["method"] != "reference"},
                             {(m, n) for m in SETS for n in ("4", "8")})
            names = ("reference-0-fibonacci", "reference-1-sobol")
            refs = np.stack([read_pfm(os.path.join(out, "runs", "box", f"{n}.pfm"))
                             .astype(np.float64) for n in names])
            reference = refs.mean(axis=0)
            for n, expected in zip(names, ("fibonacci", "sobol")):
                with open(os.path.join(out, "runs", "box", f"{n}.pfm.json")) as f:
                    command = " ".join(json.load(f)["command"])
                self.assertIn(f"--direct-sampler {expected} --direct-samples 64", command)
            reference_mse = float(np.mean(refs.var(axis=0, ddof=1))) / 2
            images = [read_pfm(p).astype(np.float64) for p in sorted(glob.glob(
                os.path.join(out, "runs", "box", "sobol", "n8-seed*.pfm")))]
            self.assertEqual(len(images), 2)
            mse = np.mean([np.mean((i - reference) ** 2) for i in images]) - reference_mse
            expected = np.sqrt(max(mse, 0.0)) / np.mean(reference)
            row = next(r for r in rows if r["method"] == "sobol" and r["samples"] == "8")
            self.assertAlmostEqual(float(row["relative_rmse"]), expected, places=9)
            with open(os.path.join(out, "table.md")) as f:
                table = f.read()
            for m in SETS:
                if m != "fibonacci":
                    self.assertIn(f"| box | {m} |", table)
            self.assertIn("+38.7 %", table)
            stamps = {p: os.path.getmtime(p)
                      for p in glob.glob(os.path.join(out, "runs", "**", "*.pfm"), recursive=True)}
            second = run(out)
            self.assertEqual(second.returncode, 0, second.stderr)
            self.assertEqual(stamps, {p: os.path.getmtime(p) for p in stamps})


if __name__ == "__main__":
    unittest.main()
