#!/usr/bin/python3
"""CTest 'python_module': the `emlt` Python module against the `emlt` command line.

    PYTHONPATH=.:build/python /usr/bin/python3 tests/scripts/test_python_module.py --emlt build/emlt

Checks that emlt.render gives the command line's image bit for bit (several integrators,
options as keywords, defines, a checkpoint resumed through keywords), that every flag of
`emlt render` is a keyword and a bad argument raises with the command line's words, that a
render stopped from Python (KeyboardInterrupt from the progress callback, or a real SIGINT)
returns a finite image normalised for the work done, that the GIL is released while it
renders, and that emlt.load and emlt.compare give what `emlt info --json` and
`emlt compare --json` give.
"""
import contextlib
import importlib.util
import io
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import numpy as np

from script_env import ROOT, take_emlt_argument
from tools.images import read_pfm

import emlt

EMLT = take_emlt_argument()
SCENE = os.path.join(ROOT, "scenes", "cornell-box", "scene.json")
TINY = dict(width=16, height=16, seed=7, threads=2)


def cli(*args):
    return subprocess.run([EMLT, *args], capture_output=True, text=True, timeout=120)


def cli_render(out, *args):
    run = cli("render", SCENE, "-q", "--width", "16", "--height", "16", "--seed", "7",
              "--threads", "2", "-o", out, *args)
    if run.returncode != 0:
        raise AssertionError(run.stderr)
    return read_pfm(out)


class PythonModule(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.scene = emlt.load(SCENE)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.tmp.name, name)

    def test_render_is_the_command_lines_bit_for_bit(self):
        cases = [
            ("pt", dict(spp=4), ["--spp", "4"]),
            ("bdpt", dict(spp=2, max_depth=4), ["--spp", "2", "--max-depth", "4"]),
            ("mlt", dict(mpp=2, bootstrap=2000), ["--mpp", "2", "--bootstrap", "2000"]),
            ("pssmlt", dict(mpp=2, large_step=0.5), ["--mpp", "2", "--large-step", "0.5"]),
        ]
        for integrator, keywords, flags in cases:
            with self.subTest(integrator=integrator):
                image, stats = emlt.render(self.scene, integrator, progress=False, **TINY,
                                           **keywords)
                expected = cli_render(self.path(integrator + ".pfm"), "--integrator", integrator,
                                      *flags)
                self.assertEqual(image.shape, (16, 16, 3))
                self.assertEqual(image.dtype, np.float32)
                self.assertTrue(np.array_equal(image, expected), integrator)
                self.assertEqual(stats["integrator"], integrator)
                if stats["mcmc"]:  # the chains' figures, as --stats writes them
                    self.assertEqual(stats["chains"]["mutations"], stats["samples"])
                self.assertFalse(stats["interrupted"])

    def test_every_flag_of_the_command_line_is_a_keyword(self):
        flags = set(re.findall(r"^\s+(?:-\w,)?(--[\w-]+)", cli("render", "--help").stdout, re.M))
        flags -= {"--help"}
        keywords = emlt.keywords()
        self.assertGreater(len(flags), 40)
        self.assertEqual({flag for flag, _ in keywords.values()}, flags)
        for keyword, (flag, _) in keywords.items():
            self.assertEqual("--" + keyword.replace("_", "-"), flag)

    def test_a_checkpoint_resumed_through_keywords(self):
        checkpoint = self.path("run.ckpt")
        emlt.render(self.scene, "pt", progress=False, spp=2, checkpoint=checkpoint, **TINY)
        resumed, stats = emlt.render(self.scene, "pt", progress=False, spp=6, resume=checkpoint,
                                     **TINY)
        whole, _ = emlt.render(self.scene, "pt", progress=False, spp=6, **TINY)
        self.assertTrue(np.array_equal(resumed, whole))
        self.assertEqual(stats["checkpoint"], checkpoint)

    def test_bad_arguments_raise_with_the_command_lines_words(self):
        for keywords, flags in [
            (dict(max_depth=-3), ["--max-depth=-3"]),
            (dict(spp=2.5), ["--spp=2.5"]),
            (dict(width=0), ["--width=0"]),
            (dict(mis="best"), ["--mis=best"]),
            (dict(checkpoint_interval=5.0), ["--checkpoint-interval=5.0"]),
        ]:
            with self.subTest(keywords=keywords):
                run = cli("render", SCENE, "-o", self.path("bad.exr"), *flags)
                self.assertNotEqual(run.returncode, 0)
                words = run.stderr.strip().removeprefix("emlt: error: ")
                with self.assertRaises(ValueError) as raised:
                    emlt.render(self.scene, progress=False, **keywords)
                self.assertIsInstance(raised.exception, emlt.Error)
                self.assertEqual(str(raised.exception), words)
        with self.assertRaisesRegex(TypeError, "no option --no-such-option"):
            emlt.render(self.scene, no_such_option=1)
        with self.assertRaises(ValueError):
            emlt.load(self.path("missing.xml"))

    def test_a_render_stopped_from_python_returns_a_normalised_image(self):
        calls = []

        def stop_once_started(status):
            calls.append(status)
            if status["phase"] and status["done"] > 0:
                raise KeyboardInterrupt

        # A budget far beyond the test's time: only the stop ends it.
        image, stats = emlt.render(self.scene, "pt", progress=stop_once_started,
                                   spp=1 << 20, **TINY)
        self.assertTrue(stats["interrupted"])
        self.assertGreater(stats["per_pixel"], 0)
        self.assertLess(stats["per_pixel"], 1 << 20)
        self.assertTrue(np.isfinite(image).all())
        full, _ = emlt.render(self.scene, "pt", progress=False, spp=64, **TINY)
        # Normalised for the work done: the same brightness as a finished render.
        self.assertAlmostEqual(image.mean() / full.mean(), 1.0, delta=0.15)
        self.assertTrue({"phase", "done", "total", "fraction", "elapsed"} <= set(calls[0]))
        # The stop is not left behind for the next render.
        again, stats = emlt.render(self.scene, "pt", progress=False, spp=2, **TINY)
        self.assertFalse(stats["interrupted"])

    def test_ctrl_c_stops_the_render_and_returns_what_was_done(self):
        program = (
            "import emlt, numpy\n"
            "print('rendering', flush=True)\n"
            f"image, stats = emlt.render({SCENE!r}, 'pt', progress=False, spp=1 << 20,"
            " width=16, height=16, threads=2)\n"
            "print(stats['interrupted'], stats['per_pixel'] > 0, numpy.isfinite(image).all())\n")
        child = subprocess.Popen([sys.executable, "-c", program], stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True)
        self.assertEqual(child.stdout.readline().strip(), "rendering")
        time.sleep(0.5)
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
        self.assertEqual(child.returncode, 0, err)
        self.assertEqual(out.split(), ["True", "True", "True"])

    def test_the_interpreter_runs_while_rendering(self):
        # The GIL is released during the render: another Python thread keeps counting.
        counted, done = [0], threading.Event()

        def count():
            while not done.is_set():
                counted[0] += 1

        counter = threading.Thread(target=count)
        counter.start()
        try:
            emlt.render(self.scene, "pt", progress=False, time=0.3, **TINY)
        finally:
            done.set()
            counter.join()
        self.assertGreater(counted[0], 10000)

    @unittest.skipUnless(importlib.util.find_spec("tqdm"), "tqdm is not installed")
    def test_progress_true_draws_a_tqdm_bar_to_its_end(self):
        with contextlib.redirect_stderr(io.StringIO()) as drawn:
            emlt.render(self.scene, "pt", spp=4, **TINY)
        self.assertIn("100%", drawn.getvalue())

    def test_defines_and_output_as_the_command_line(self):
        xml = os.path.join(ROOT, "scenes", "cornell-box", "scene.xml")
        scene = emlt.load(xml, width=16, height=12, spp=2)
        self.assertEqual((scene.width, scene.height), (16, 12))
        self.assertEqual(scene.defines, {"width": "16", "height": "12", "spp": "2"})
        out = self.path("defines.pfm")
        image, _ = emlt.render(scene, "pt", progress=False, seed=7, threads=2, output=out)
        run = cli("render", xml, "-q", "-D", "width=16", "-D", "height=12", "-D", "spp=2",
                  "--integrator", "pt", "--seed", "7", "--threads", "2",
                  "-o", self.path("defines-cli.pfm"))
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertTrue(np.array_equal(image, read_pfm(self.path("defines-cli.pfm"))))
        self.assertTrue(np.array_equal(image, read_pfm(out)))

    def test_an_error_in_the_callback_stops_the_render_and_is_raised(self):
        def fail(status):
            raise RuntimeError("callback failed")

        with self.assertRaisesRegex(RuntimeError, "callback failed"):
            emlt.render(self.scene, "pt", progress=fail, spp=1 << 20, **TINY)

    def test_load_gives_info_verdict_and_warnings(self):
        info = json.loads(cli("info", "--json", SCENE).stdout)
        self.assertEqual(self.scene.verdict, info["verdict"])
        self.assertEqual(self.scene.warnings, info["warnings"])
        self.assertEqual((self.scene.width, self.scene.height), (256, 256))

    def test_compare_gives_the_command_lines_metrics(self):
        reference = cli_render(self.path("ref.pfm"), "--spp", "8")
        image = cli_render(self.path("img.pfm"), "--spp", "2")
        run = cli("compare", "--json", self.path("ref.pfm"), self.path("img.pfm"))
        expected = json.loads(run.stdout)
        metrics = emlt.compare(reference, image)
        for key in ("mse", "relmse", "mean_ratio", "pixels", "mse_no_emitter"):
            self.assertEqual(metrics[key], expected[key], key)
        self.assertEqual(emlt.compare(self.path("ref.pfm"), image)["mse"], expected["mse"])
        cropped = cli("compare", "--json", "--crop", "2,3,8,9", self.path("ref.pfm"),
                      self.path("img.pfm"))
        self.assertEqual(emlt.compare(reference, image, crop=(2, 3, 8, 9))["mse"],
                         json.loads(cropped.stdout)["mse"])
        error_map = emlt.error_map(reference, image)
        self.assertEqual((error_map.shape, error_map.dtype), ((16, 16, 3), np.float32))
        self.assertTrue(((error_map >= 0) & (error_map <= 1)).all())


if __name__ == "__main__":
    unittest.main()
