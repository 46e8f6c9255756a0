#!/usr/bin/python3
"""CTest 'paper_table1_summary': scripts/experiments/paper_table1/summarise.py on a results.csv
and stats.json files written here (the layout scripts/ablation.py leaves).

    /usr/bin/python3 tests/scripts/test_paper_table1_summary.py

Checks the MSE ratio against MLT (net of the reference's noise, mean over seeds), the overall
acceptance (accepted over proposed, all strategies) and its change against the paper's-mix MLT,
the per-strategy acceptance, the paper's own figures beside ours, and the one-line error for a
folder with no results."""
import csv
import json
import os
import subprocess
import tempfile
import unittest

from script_env import PYTHON, ROOT

SCRIPT = os.path.join(ROOT, "scripts", "experiments", "paper_table1", "summarise.py")


def write_run(folder, scene, method, seed, mse, floor, strategies):
    image = os.path.join("runs", scene, method, "mpp-64", f"seed-{seed}", "image.pfm")
    os.makedirs(os.path.join(folder, os.path.dirname(image)), exist_ok=True)
    with open(os.path.join(folder, os.path.dirname(image), "stats.json"), "w") as f:
        json.dump({"strategies": [{"name": n, "proposed": p, "accepted": a} for n, p, a in strategies]}, f)
    return {"scene": scene, "method": method, "seed": seed, "mse": mse, "mse_net": mse - floor,
            "seconds": 10.0 * seed, "image": image}


class Summary(unittest.TestCase):
    def test_table(self):
        with tempfile.TemporaryDirectory() as folder:
            rows = [
                # MLT: net MSE 4e-3 and 6e-3 -> 5e-3; acceptance 50 %.
                write_run(folder, "door-ajar", "MLT", 1, 5e-3, 1e-3, [("bidir", 100, 20), ("lens", 100, 80)]),
                write_run(folder, "door-ajar", "MLT", 2, 7e-3, 1e-3, [("bidir", 100, 20), ("lens", 100, 80)]),
                # The paper's-mix MLT: acceptance 40 %.
                write_run(folder, "door-ajar", "MLT-mix", 1, 5e-3, 1e-3, [("bidir", 100, 10), ("lens", 100, 70)]),
                # EMLT: net MSE 2e-3 (2.5x), acceptance 46 % (+15 % over 40 %).
                write_run(folder, "door-ajar", "EMLT", 1, 3e-3, 1e-3, [("bidir", 100, 12), ("emlt-lens", 100, 80)]),
            ]
            with open(os.path.join(folder, "results.csv"), "w", newline="") as f:
                writer = csv.DictWriter(f, fieldnames=list(rows[0]))
                writer.writeheader()
                writer.writerows(rows)
            result = subprocess.run([PYTHON, SCRIPT, folder], capture_output=True, text=True, timeout=60)
            self.assertEqual(result.returncode, 0, result.stderr)
            table = result.stdout.split("Acceptance per strategy")[0]
            lines = {tuple(c.strip() for c in line.split("|")[1:3]): line for line in table.splitlines()
                     if line.startswith("| door-ajar")}
            emlt = [c.strip() for c in lines[("door-ajar", "EMLT")].split("|")[1:-1]]
            # scene, method, seeds, MSE, net, MLT / this, seconds, acceptance, over the mix, paper
            self.assertEqual(emlt[2], "1")
            self.assertAlmostEqual(float(emlt[4]), 2e-3)
            self.assertEqual(emlt[5], "2.50")
            self.assertEqual(emlt[7], "0.460")
            self.assertEqual(emlt[8], "+15%")
            self.assertEqual(emlt[9], "0.00328, 2.23")
            mlt = [c.strip() for c in lines[("door-ajar", "MLT")].split("|")[1:-1]]
            self.assertEqual(mlt[2], "2")
            self.assertEqual(mlt[5], "1.00")
            self.assertEqual(mlt[6], "15.0")
            # Per strategy: EMLT's guided lens 0.8, MLT's bidirectional 0.2.
            per_strategy = result.stdout.split("Acceptance per strategy")[1]
            header = [c.strip() for c in per_strategy.splitlines()[2].split("|")[1:-1]]
            row = next(line for line in per_strategy.splitlines() if line.startswith("| door-ajar | EMLT |"))
            cells = dict(zip(header, [c.strip() for c in row.split("|")[1:-1]]))
            self.assertEqual(cells["emlt-lens"], "0.800")
            self.assertEqual(cells["lens"], "")

    def test_missing_results(self):
        with tempfile.TemporaryDirectory() as folder:
            result = subprocess.run([PYTHON, SCRIPT, folder], capture_output=True, text=True, timeout=60)
            self.assertEqual(result.returncode, 1)
            self.assertEqual(len(result.stderr.strip().splitlines()), 1)
            self.assertIn("no results.csv", result.stderr)


if __name__ == "__main__":
    unittest.main()
