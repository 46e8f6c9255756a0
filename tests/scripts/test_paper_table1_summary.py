#!/usr/bin/python3
"""CTest 'paper_table1_summary': scripts/experiments/paper_table1/summarise.py on a results.csv
and stats.json files written here (the layout scripts/ablation.py leaves).

    /usr/bin/python3 tests/scripts/test_paper_table1_summary.py

Checks the MSE ratio against MLT (net of the reference's noise, mean over seeds), the chains'
variance and its ratio, α's quartiles, the overall acceptance (accepted over proposed, all
strategies) and its change against the paper's-mix MLT, the per-strategy acceptance, the
paper's own figures beside ours, --update's rewrite of a document's marked block, and the
one-line errors for a folder with no results and a document with no block."""
import csv
import json
import os
import subprocess
import tempfile
import unittest

from script_env import PYTHON, ROOT

SCRIPT = os.path.join(ROOT, "scripts", "experiments", "paper_table1", "summarise.py")


def write_run(folder, scene, method, seed, mse, floor, strategies, alpha=None):
    image = os.path.join("runs", scene, method, "mpp-64", f"seed-{seed}", "image.pfm")
    os.makedirs(os.path.join(folder, os.path.dirname(image)), exist_ok=True)
    stats = {"strategies": [{"name": n, "proposed": p, "accepted": a} for n, p, a in strategies]}
    if alpha:
        stats["ensemble"] = {"alpha": dict(zip(("q1", "median", "q3"), alpha))}
    with open(os.path.join(folder, os.path.dirname(image), "stats.json"), "w") as f:
        json.dump(stats, f)
    return {"scene": scene, "method": method, "seed": seed, "mse": mse, "mse_net": mse - floor,
            "seconds": 10.0 * seed, "image": image}


def write_results(folder):
    rows = [
        # MLT: net MSE 4e-3 and 6e-3 -> 5e-3; acceptance 50 %.
        write_run(folder, "door-ajar", "MLT", 1, 5e-3, 1e-3, [("bidir", 100, 20), ("lens", 100, 80)]),
        write_run(folder, "door-ajar", "MLT", 2, 7e-3, 1e-3, [("bidir", 100, 20), ("lens", 100, 80)]),
        # The paper's-mix MLT: acceptance 40 %.
        write_run(folder, "door-ajar", "MLT-mix", 1, 5e-3, 1e-3, [("bidir", 100, 10), ("lens", 100, 70)]),
        # EMLT: net MSE 2e-3 (2.5x), acceptance 46 % (+15 % over 40 %), α quartiles 0.1/0.2/0.4.
        write_run(folder, "door-ajar", "EMLT", 1, 3e-3, 1e-3, [("bidir", 100, 12), ("emlt-lens", 100, 80)],
                  alpha=(0.1, 0.2, 0.4)),
    ]
    with open(os.path.join(folder, "results.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    with open(os.path.join(folder, "chains.csv"), "w") as f:
        f.write("scene,budget_kind,budget,method,seeds,chains_variance\n"
                "door-ajar,mpp,64,MLT,2,0.006\ndoor-ajar,mpp,64,EMLT,2,0.004\n")


class Summary(unittest.TestCase):
    def test_update_rewrites_only_the_block(self):
        with tempfile.TemporaryDirectory() as folder:
            write_results(folder)
            doc = os.path.join(folder, "doc.md")
            begin = "<!-- table1:begin (scripts/experiments/paper_table1/summarise.py --update) -->"
            with open(doc, "w") as f:
                f.write(f"# Title\n\nprose\n{begin}\nold table\n<!-- table1:end -->\nafter\n")
            result = subprocess.run([PYTHON, SCRIPT, folder, "--update", doc], capture_output=True, text=True,
                                    timeout=60)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertEqual(result.stdout, "")
            with open(doc) as f:
                text = f.read()
            self.assertTrue(text.startswith("# Title\n\nprose\n" + begin + "\n| scene | method |"))
            self.assertNotIn("old table", text)
            self.assertTrue(text.endswith("<!-- table1:end -->\nafter\n"))
            self.assertIn("| door-ajar | EMLT |", text)
            # A document without the block: one line naming it, the file untouched.
            with open(doc, "w") as f:
                f.write("no block\n")
            result = subprocess.run([PYTHON, SCRIPT, folder, "--update", doc], capture_output=True, text=True,
                                    timeout=60)
            self.assertEqual(result.returncode, 1)
            self.assertEqual(len(result.stderr.strip().splitlines()), 1)
            self.assertIn("doc.md", result.stderr)
            with open(doc) as f:
                self.assertEqual(f.read(), "no block\n")

    def test_table(self):
        with tempfile.TemporaryDirectory() as folder:
            write_results(folder)
            result = subprocess.run([PYTHON, SCRIPT, folder], capture_output=True, text=True, timeout=60)
            self.assertEqual(result.returncode, 0, result.stderr)
            table = result.stdout.split("Acceptance per strategy")[0]
            lines = {tuple(c.strip() for c in line.split("|")[1:3]): line for line in table.splitlines()
                     if line.startswith("| door-ajar")}
            emlt = [c.strip() for c in lines[("door-ajar", "EMLT")].split("|")[1:-1]]
            # scene, method, seeds, MSE, net, MLT / this, chains' variance, MLT / this by it,
            # seconds, acceptance, over the mix, α's quartiles, paper
            self.assertEqual(emlt[2], "1")
            self.assertAlmostEqual(float(emlt[4]), 2e-3)
            self.assertEqual(emlt[5], "2.50")
            self.assertEqual(emlt[6], "0.004")
            self.assertEqual(emlt[7], "1.50")
            self.assertEqual(emlt[9], "0.460")
            self.assertEqual(emlt[10], "+15%")
            self.assertEqual(emlt[11], "0.10 / 0.20 / 0.40")
            self.assertEqual(emlt[12], "0.00328, 2.23")
            mlt = [c.strip() for c in lines[("door-ajar", "MLT")].split("|")[1:-1]]
            self.assertEqual(mlt[2], "2")
            self.assertEqual(mlt[5], "1.00")
            self.assertEqual(mlt[7], "1.00")
            self.assertEqual(mlt[8], "15.0")
            self.assertEqual(mlt[11], "")
            # No chains.csv row for the paper's-mix MLT: its variance cells stay empty.
            mix = [c.strip() for c in lines[("door-ajar", "MLT-mix")].split("|")[1:-1]]
            self.assertEqual(mix[6:8], ["", ""])
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
