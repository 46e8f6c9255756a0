#!/usr/bin/python3
"""CTest 'mis_alpha_script': scripts/experiments/direct_samplers/mis_alpha.py on 8x8 images.

    /usr/bin/python3 tests/scripts/test_mis_alpha.py --emlt build/emlt

Checks that every method is run and reported against the balance heuristic, that the
reported variance is the per-pixel variance of the kept images across seeds, that the
scene copy sends camera rays through the pixel centres, and that a second call renders
nothing again.
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

SCRIPT = os.path.join(ROOT, "scripts", "experiments", "direct_samplers", "mis_alpha.py")
EMLT = take_emlt_argument()


def run(out):
    return subprocess.run(
        [PYTHON, SCRIPT, "--emlt", EMLT, "--out", out, "--scenes", "veach-plates", "--seeds", "2",
         "--size", "8", "--spp", "1", "--directions", "8", "--pre-samples", "16"],
        capture_output=True, text=True, timeout=300)


class MisAlpha(unittest.TestCase):
    def test_reports_every_method_against_balance(self):
        with tempfile.TemporaryDirectory() as out:
            first = run(out)
            self.assertEqual(first.returncode, 0, first.stderr)
            with open(os.path.join(out, "results.csv")) as f:
                rows = {r["method"]: r for r in csv.DictReader(f)}
            self.assertEqual(set(rows), {"bsdf only", "light only", "balance", "power", "max",
                                         "preprocessed", "online"})
            self.assertEqual(float(rows["balance"]["relative_variance"]), 1.0)
            images = np.stack([read_pfm(p).astype(np.float64) for p in sorted(
                glob.glob(os.path.join(out, "runs", "veach-plates", "balance", "seed-*.pfm")))])
            self.assertEqual(len(images), 2)
            self.assertAlmostEqual(float(rows["balance"]["variance"]),
                                   float(np.mean(np.var(images, axis=0, ddof=1))), places=12)
            scene = glob.glob(os.path.join(out, "scenes", "veach-plates", "*", "veach_plates.json"))
            with open(scene[0]) as f:
                self.assertEqual(json.load(f)["camera"]["filter"], {"type": "tent", "radius": 0.01})
            table = open(os.path.join(out, "table.md")).read()
            self.assertEqual(table.count("| method |"), 4)
            stamps = {p: os.path.getmtime(p) for p in glob.glob(os.path.join(out, "runs", "**", "*.pfm"),
                                                                  recursive=True)}
            second = run(out)
            self.assertEqual(second.returncode, 0, second.stderr)
            self.assertEqual(stamps, {p: os.path.getmtime(p) for p in stamps})


if __name__ == "__main__":
    unittest.main()
