#!/usr/bin/python3
"""CTest 'chain_variance_script': scripts/chain_variance.py on a 16x16 Cornell box.

    /usr/bin/python3 tests/scripts/test_chain_variance.py --emlt build/emlt

Checks that the direct image the script subtracts is the renderer's own (a method whose
chains have nothing to render leaves exactly zero), that the reported variance is the
variance of the kept images, that the ideal-sampler yardstick matches a simulated
independent sampler, that a second call reuses the images its arguments made (and only
those), that the Python module (the default), the binary and `mpirun -n 2` render the same
bits, and that bad arguments and engine errors fail with one line.
"""
import json
import os
import subprocess
import tempfile
import unittest

import numpy as np

from script_env import PYTHON, ROOT, SCRIPTS, load_program, take_emlt_argument

chain_variance = load_program("scripts/chain_variance.py")
LUMINANCE, ideal_variance_per_mutation, read_image = (
    chain_variance.LUMINANCE, chain_variance.ideal_variance_per_mutation, chain_variance.read_image)

SCRIPT = os.path.join(SCRIPTS, "chain_variance.py")
SCENE = os.path.join(ROOT, "scenes", "cornell-box", "scene.json")
EMLT = take_emlt_argument()
SEEDS = 3


def chain_variance(out, emlt=EMLT, seeds=SEEDS, extra=(), budget="--mpp 8"):
    return subprocess.run(
        [PYTHON, SCRIPT, SCENE, "--emlt", emlt, "--width", "16", "--height", "16", "--threads", "2",
         "--seeds", str(seeds), "--direct-spp", "4", "--budget", budget, "--out", out,
         "--json", os.path.join(out, "figures.json"),
         "--method", "mlt=--integrator mlt", "--method", "direct-only=--integrator mlt --max-depth 2", *extra],
        capture_output=True, text=True, timeout=300)


class ChainVariance(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = cls.tmp.name
        cls.first = chain_variance(cls.out)
        with open(os.path.join(cls.out, "figures.json")) as f:
            cls.figures = {row["method"]: row for row in json.load(f)["methods"]}

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_runs(self):
        self.assertEqual(self.first.returncode, 0, self.first.stdout + self.first.stderr)
        self.assertIn("mlt", self.first.stdout)
        self.assertIn("rendered by the Python module", self.first.stdout)

    def test_the_binary_and_mpirun_render_the_module_s_bits(self):
        for engine in (("--engine", "cli"), ("--mpi", "2")):
            with tempfile.TemporaryDirectory() as out:
                done = chain_variance(out, seeds=2, extra=engine)
                self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
                self.assertNotIn("Python module", done.stdout)
                for name in ("direct.1", "direct.2", "mlt.1", "mlt.2"):
                    with open(os.path.join(out, name + ".pfm"), "rb") as a, \
                            open(os.path.join(self.out, name + ".pfm"), "rb") as b:
                        self.assertEqual(a.read(), b.read(), f"{engine}: {name}")

    def test_direct_image_is_the_renderers_own(self):
        # With at most two segments the chains render nothing: what is left after
        # subtracting the direct image must be exactly zero in every seed.
        row = self.figures["direct-only"]
        self.assertEqual(row["chains_variance"], 0.0)
        self.assertEqual(row["mutations_per_pixel"], 0.0)
        for seed in range(1, SEEDS + 1):
            left = read_image(os.path.join(self.out, f"direct-only.{seed}.pfm")) - read_image(
                os.path.join(self.out, f"direct.{seed}.pfm"))
            self.assertEqual(np.abs(left).max(), 0.0)

    def test_variance_is_that_of_the_kept_images(self):
        chains = np.stack([read_image(os.path.join(self.out, f"mlt.{s}.pfm")) -
                           read_image(os.path.join(self.out, f"direct.{s}.pfm")) for s in range(1, SEEDS + 1)])
        mean = chains.mean(axis=0)
        expected = (((chains - mean) ** 2).sum(axis=0) / (SEEDS - 1)).sum(axis=1).mean()
        row = self.figures["mlt"]
        self.assertGreater(expected, 0.0)
        self.assertAlmostEqual(row["chains_variance"] / expected, 1.0, places=9)
        self.assertAlmostEqual(row["mutations_per_pixel"], 8.0, places=6)

    def test_second_call_reuses_the_images_of_the_same_arguments(self):
        missing = os.path.join(self.out, "no-such-emlt")
        again = chain_variance(self.out, emlt=missing)
        self.assertEqual(again.returncode, 0, again.stdout + again.stderr)
        # Another budget must render again, not report the kept images: with no binary it fails.
        other = chain_variance(self.out, emlt=missing, budget="--mpp 16")
        self.assertEqual(other.returncode, 1)
        self.assertEqual(other.stderr.strip(), f"chain_variance: {missing}: No such file or directory")

    def test_bad_arguments_fail(self):
        with tempfile.TemporaryDirectory() as out:
            one_seed = chain_variance(out, seeds=1)
            self.assertEqual(one_seed.returncode, 2)
            self.assertIn("--seeds", one_seed.stderr)
            no_name = chain_variance(out, extra=("--method", "--integrator mlt"))
            self.assertNotEqual(no_name.returncode, 0)
            self.assertIn("NAME=ARGS", no_name.stderr)
            twice = chain_variance(out, extra=("--method", "mlt=--integrator mlt --mpp 2"))
            self.assertEqual(twice.returncode, 2)
            self.assertIn("given twice", twice.stderr)

    def test_engine_error_is_one_line_naming_the_file(self):
        with tempfile.TemporaryDirectory() as out:
            bad = subprocess.run([PYTHON, SCRIPT, os.path.join(out, "missing.json"), "--emlt", EMLT,
                                  "--budget", "--mpp 1", "--out", out, "--method", "m=--integrator mlt"],
                                 capture_output=True, text=True, timeout=60)
            self.assertEqual(bad.returncode, 1)
            self.assertEqual(len(bad.stderr.strip().splitlines()), 1, bad.stderr)
            self.assertIn("missing.json", bad.stderr)


class IdealYardstick(unittest.TestCase):
    def test_matches_a_simulated_independent_sampler(self):
        # An image with colour: the yardstick must equal the variance of a histogram
        # estimator fed by independent samples drawn in proportion to luminance.
        rng = np.random.default_rng(7)
        image = rng.gamma(2.0, 0.05, size=(400, 3)) * rng.uniform(0.0, 2.0, size=(400, 1))
        image[:20] = 0.0  # pixels the chains never reach
        lum = image @ LUMINANCE
        pixels, mpp, trials = len(lum), 16, 400
        samples = int(mpp * pixels)
        colour = np.zeros_like(image)
        colour[lum > 0] = image[lum > 0] / lum[lum > 0, None]
        errors = []
        for _ in range(trials):
            counts = rng.multinomial(samples, lum / lum.sum())
            estimate = lum.sum() / samples * counts[:, None] * colour
            errors.append(((estimate - image) ** 2).sum(axis=1).mean())
        simulated = np.mean(errors)
        # The yardstick leaves out the -I^2/N term of the multinomial variance, under 1 % here.
        self.assertAlmostEqual(ideal_variance_per_mutation(image) / mpp / simulated, 1.0, delta=0.03)


if __name__ == "__main__":
    unittest.main()
