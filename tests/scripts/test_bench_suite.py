#!/usr/bin/python3
"""CTest 'bench_suite': the performance suite (bench/suite.py) in its --quick mode on the
Cornell box, and its callgrind breakdown on a hand-written profile. No timing is checked:
only that the suite runs end to end, that every figure it reports is a positive rate, and
that the breakdown attributes instructions as docs/performance.md says.

    /usr/bin/python3 tests/scripts/test_bench_suite.py --build build
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

from script_env import ROOT, load_program

suite = load_program("bench/suite.py")

BUILD = os.path.join(ROOT, "build")
if "--build" in sys.argv:
    i = sys.argv.index("--build")
    BUILD = sys.argv[i + 1]
    del sys.argv[i:i + 2]

# A callgrind file: run_chain (bookkeeping, self 10) calls propose (proposal, self 20),
# which calls sincos (no category, self 30) and BitmapTexture::eval (BSDF, self 5); the
# Bsdf's pdf (self 7) calls sincos too. sincos's 30 must split 2:1 between proposal and
# pdf by what the two calls cost (20 and 10), and malloc (called from propose) is allocation.
PROFILE = """version: 1
events: Ir
ob=(1) /build/emlt
fn=(1) emlt::(anonymous namespace)::run_chain(Chain&)
0 10
cfn=(2) emlt::BidirectionalMutation::propose(emlt::Path const&)
calls=1 0
0 135
fn=(2)
0 20
cob=(2) /lib/libm.so.6
cfn=(3) __sincos_fma
calls=2 0
0 20
cfn=(4) emlt::(anonymous namespace)::BitmapTexture::eval(glm::vec2 const&) const
calls=1 0
0 5
cfn=(5) emlt::(anonymous namespace)::RoughPlastic::pdf(emlt::BsdfContext const&) const
calls=1 0
0 17
cob=(3) /lib/libc.so.6
cfn=(6) malloc
calls=1 0
0 3
ob=(2)
fn=(3)
0 30
ob=(1)
fn=(4)
0 5
fn=(5)
0 7
cob=(2)
cfn=(3)
calls=1 0
0 10
ob=(3)
fn=(6)
0 3
"""


class Breakdown(unittest.TestCase):
    def test_categories_and_propagation(self):
        with tempfile.NamedTemporaryFile("w", suffix=".callgrind", delete=False) as f:
            f.write(PROFILE)
        try:
            totals = suite.callgrind_breakdown(f.name)
        finally:
            os.unlink(f.name)
        self.assertAlmostEqual(totals["bookkeeping"], 10)
        self.assertAlmostEqual(totals["proposal"], 20 + 30 * 2 / 3)
        self.assertAlmostEqual(totals["pdf and MIS"], 7 + 30 / 3)
        self.assertAlmostEqual(totals["BSDF, texture, emission"], 5)
        self.assertAlmostEqual(totals["allocation"], 3)
        self.assertAlmostEqual(totals["intersection"], 0)
        self.assertAlmostEqual(sum(totals.values()), 75)


class QuickRun(unittest.TestCase):
    def test_cornell_box(self):
        with tempfile.TemporaryDirectory() as out:
            result = subprocess.run(
                [sys.executable, os.path.join(ROOT, "bench", "suite.py"), "--quick", "--scenes", "cornell-box",
                 "--build", BUILD, "--out", out], capture_output=True, text=True, timeout=600)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            self.assertIn("| cornell-box (256x256) | 32 |", result.stdout)
            with open(os.path.join(out, "results.json")) as f:
                (figures,) = json.load(f)
            self.assertGreater(figures["rays"]["intersect"], 0)
            self.assertGreater(figures["rays"]["occluded"], 0)
            for integrator in ("pt", "bdpt", "mlt", "gamlt", "emlt"):
                self.assertGreater(figures[integrator]["rate"], 0, integrator)
                self.assertEqual(figures[integrator]["work"], 256 * 256 * (4 if integrator in suite.MCMC else
                                                                         {"pt": 4, "bdpt": 1}[integrator]),
                                 integrator)
            self.assertGreater(figures["peak_mb"], 1)
            with open(os.path.join(out, "table.md")) as f:
                self.assertEqual(f.read(), result.stdout.rstrip("\n") + "\n")

    def test_unknown_scene_is_refused(self):
        result = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "suite.py"), "--scenes", "nope",
                                 "--build", BUILD], capture_output=True, text=True)
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("unknown scene(s) nope", result.stderr)


class ThreadScaling(unittest.TestCase):
    """bench/thread_scaling.py at a sliver of the work, 1 and 2 threads: the figures it
    reports are the runs it made (no timing is checked)."""

    def test_cornell_box_at_one_and_two_threads(self):
        with tempfile.TemporaryDirectory() as out:
            # The same build as a variant: it runs (alternating with the main one) for mlt only.
            result = subprocess.run(
                [sys.executable, os.path.join(ROOT, "bench", "thread_scaling.py"), "--threads", "1,2",
                 "--work", "0.125", "--scenes", "cornell-box", "--ceiling", "--build", BUILD, "--out", out,
                 "--variant", f"same={BUILD}", "--variant-methods", "mlt", "--pairs", "2",
                 "--compute-ceiling"],
                capture_output=True, text=True, timeout=600)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            with open(os.path.join(out, "results.json")) as f:
                (figure,) = json.load(f)
            self.assertEqual(set(figure["runs"]), {"pt", "mlt"})
            self.assertEqual(set(figure["compute_ceiling"]), {"2"})
            self.assertGreater(figure["compute_ceiling"]["2"], 0)
            for method, runs in figure["runs"].items():
                variant = {"2@same"} if method == "mlt" else set()
                self.assertEqual(set(runs), {"1", "2", "ceiling:2"} | variant, method)
                # The suite's 32 samples (or mutations) per pixel at an eighth: 4.
                self.assertEqual(runs["1"]["work"], 256 * 256 * 4, method)
                self.assertEqual(runs["2"]["work"], runs["1"]["work"], method)
                self.assertGreater(runs["ceiling:2"], 0, method)
            # Two runs each of the main build and the variant at 2 threads, the median kept.
            mlt = figure["runs"]["mlt"]
            for key in ("2", "2@same"):
                self.assertEqual(len(mlt[key]["walls"]), 2, key)
                self.assertEqual(mlt[key]["wall_s"], min(mlt[key]["walls"]), key)
                self.assertEqual(mlt[key]["work"], mlt["1"]["work"], key)
            with open(os.path.join(out, "table.md")) as f:
                table = f.read()
            self.assertIn("| cornell-box | pt |", table)
            self.assertIn("| cornell-box | mlt |", table)
            self.assertIn("| cornell-box | mlt | same (2 threads) |", table)
            self.assertIn("Compute-only ceiling", table)

    def test_bad_arguments_are_refused(self):
        for args, message in ((["--threads", "2,4"], "the first thread count must be 1"),
                              (["--scenes", "nope"], "unknown scene(s) nope"),
                              (["--methods", "pt,nope"], "--methods takes"),
                              (["--variant", "nolabel"], "want LABEL=BUILD_DIR"),
                              (["--ceiling-at", "4,x"], "--ceiling-at takes thread counts"),
                              (["--threads", "1,0"], "--threads takes thread counts")):
            result = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "thread_scaling.py"),
                                     "--build", BUILD] + args, capture_output=True, text=True)
            self.assertNotEqual(result.returncode, 0, args)
            self.assertIn(message, result.stderr, args)


if __name__ == "__main__":
    unittest.main()
