#!/usr/bin/python3
"""CTest 'bench_emlt_cost_script': bench/emlt_cost.py on a 16x16 Cornell box.

    /usr/bin/python3 tests/scripts/test_bench_emlt_cost.py --emlt build/emlt

Checks that --structure measures EMLT's driver apart from its kernels (the rows it adds are
there, and under callgrind the driver row with MLT's strategies rebuilds the tree but spends
nothing on similarities, while MLT's row does neither) and that the CPU table prints a ratio
per method. No timing is checked.
"""
import os
import re
import shutil
import subprocess
import unittest

from script_env import PYTHON, ROOT, take_emlt_argument

SCRIPT = os.path.join(ROOT, "bench", "emlt_cost.py")
SCENE = os.path.join(ROOT, "scenes", "cornell-box", "scene.json")
EMLT = take_emlt_argument()
TINY = ["--size", "16", "--scene", SCENE, "--repeats", "1", "--mpp-low", "1", "--mpp-high", "2",
        "--callgrind-mpp", "1"]


def bench(*extra):
    result = subprocess.run([PYTHON, SCRIPT, "--emlt", EMLT, *TINY, *extra], capture_output=True,
                            text=True, timeout=240)
    if result.returncode != 0:
        raise AssertionError(result.stdout + result.stderr)
    return result.stdout


class Structure(unittest.TestCase):
    def test_cpu_rows(self):
        out = bench("--structure", "--no-callgrind")
        for name in ("mlt", "emlt", "emlt-mlt-mix", "emlt-it32", "emlt-mlt-mix-it32"):
            self.assertRegex(out, r"\n  " + re.escape(name) + r" +-?[\d.]+ us +-?[\d.]+x mlt", out)

    @unittest.skipUnless(shutil.which("valgrind"), "valgrind not installed")
    def test_driver_row_rebuilds_trees_without_guided_kernels(self):
        out = bench("--structure", "--no-cpu", "--only", "emlt-mlt-mix")
        rows = {}
        table = out.split("Instructions per mutation")[1].split("Instructions per proposal")[0]
        for line in table.splitlines():
            fields = line.split()
            if len(fields) == 10 and fields[0] in ("mlt", "emlt-mlt-mix"):
                rows[fields[0]] = [float(f) for f in fields[1:]]
        self.assertEqual(set(rows), {"mlt", "emlt-mlt-mix"}, out)
        tree, similarity = 0, 2  # columns: tree, lookup, similarity, fits, tracing, ...
        self.assertGreater(rows["emlt-mlt-mix"][tree], 0, out)
        self.assertEqual(rows["emlt-mlt-mix"][similarity], 0, out)
        self.assertEqual(rows["mlt"][tree], 0, out)
        self.assertIn("emlt-mlt-mix BidirectionalMutation", out)
        self.assertNotIn("Guided", out)


if __name__ == "__main__":
    unittest.main()
