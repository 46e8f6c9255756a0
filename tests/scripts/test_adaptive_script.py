#!/usr/bin/python3
"""CTest 'adaptive_script': scripts/experiments/direct_samplers/adaptive.py on 8x8 images.

    /usr/bin/python3 tests/scripts/test_adaptive_script.py --emlt build/emlt

Checks that every method is run at every sample count, that the reported RMSE is that of the
kept images against the kept reference, that the lobe map is the paper's sky (1 to 320), and
that a second call renders nothing again.
"""
import csv
import glob
import os
import subprocess
import tempfile
import unittest

import numpy as np

from script_env import PYTHON, ROOT, take_emlt_argument
from tools.images import read_pfm

SCRIPT = os.path.join(ROOT, "scripts", "experiments", "direct_samplers", "adaptive.py")
EMLT = take_emlt_argument()


def run(out):
    return subprocess.run(
        [PYTHON, SCRIPT, "--emlt", EMLT, "--out", out, "--scenes", "lobe-diffuse", "--seeds", "2",
         "--size", "8", "--directions", "4,8"],
        capture_output=True, text=True, timeout=300)


class Adaptive(unittest.TestCase):
    def test_reports_every_method_against_the_reference(self):
        with tempfile.TemporaryDirectory() as out:
            first = run(out)
            self.assertEqual(first.returncode, 0, first.stderr)
            with open(os.path.join(out, "results.csv")) as f:
                rows = list(csv.DictReader(f))
            self.assertEqual({(r["method"], r["directions"]) for r in rows},
                             {(m, d) for m in ("BSDF", "env table", "MIS", "Halton cells, equal",
                                               "adaptive", "adaptive, c = 16", "adaptive, global")
                              for d in ("4", "8")})
            reference = read_pfm(os.path.join(out, "runs", "lobe-diffuse", "reference.pfm"))
            images = [read_pfm(p).astype(np.float64) for p in sorted(glob.glob(
                os.path.join(out, "runs", "lobe-diffuse", "adaptive", "d8-seed-*.pfm")))]
            self.assertEqual(len(images), 2)
            rmse = np.sqrt(np.mean([np.mean((i - reference) ** 2) for i in images]))
            row = next(r for r in rows if r["method"] == "adaptive" and r["directions"] == "8")
            self.assertAlmostEqual(float(row["rmse"]), rmse, places=9)
            lobe = read_pfm(os.path.join(out, "scenes", "lobe.pfm"))
            self.assertAlmostEqual(float(lobe.min()), 1.0, places=5)
            self.assertGreater(float(lobe.max()), 300.0)
            stamps = {p: os.path.getmtime(p) for p in glob.glob(os.path.join(out, "runs", "**", "*.pfm"),
                                                                  recursive=True)}
            second = run(out)
            self.assertEqual(second.returncode, 0, second.stderr)
            self.assertEqual(stamps, {p: os.path.getmtime(p) for p in stamps})


if __name__ == "__main__":
    unittest.main()
