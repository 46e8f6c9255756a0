#!/usr/bin/python3
"""CTest 'ablation_scripts': runs the tiny ablation (scripts/experiments/ci-tiny.json) and checks it.

    PYTHONPATH=. EMLT_BINARY=build/emlt /usr/bin/python3 tests/scripts/test_ablation.py   (from the root)
    PYTHONPATH=. /usr/bin/python3 tests/scripts/test_ablation.py --emlt build/emlt

Checks that every output exists, that results.csv and table.md equal `emlt compare --json`
on the saved images (recomputed here, and the MSE once more with numpy), that a second
run skips every run, that an unknown method fails with a one-line error, and that --scenes DIR
finds a scene missing from the repository under DIR.
"""
import csv
import json
import math
import os
import re
import shutil
import subprocess
import tempfile
import unittest

from script_env import PYTHON, ROOT, SCRIPTS, load_program, take_emlt_argument
from tools.images import mse as numpy_mse, read_pfm

SCRIPT = os.path.join(SCRIPTS, "ablation.py")
CONFIG = os.path.join(SCRIPTS, "experiments", "ci-tiny.json")
EMLT = take_emlt_argument()


def run_ablation(config, out, cache, extra=()):
    """Run scripts/ablation.py; returns the CompletedProcess (text, stdout and stderr captured)."""
    return subprocess.run([PYTHON, SCRIPT, config, "--out", out, "--emlt", EMLT, "--cache", cache, *extra],
                          capture_output=True, text=True, timeout=300)


def within_rounding(text, exact):
    """True when the printed number text is exact rounded to text's significant digits."""
    printed = float(text)
    mantissa = text.lower().split("e")[0]
    digits = len(mantissa.replace("-", "").replace(".", "").lstrip("0")) or 1
    if exact == 0:
        return printed == 0
    ulp = 10.0 ** (math.floor(math.log10(abs(exact))) - digits + 1)
    return abs(printed - exact) <= 0.5 * ulp * (1 + 1e-9) + 1e-300


def parse_table_md(path):
    """table.md -> {section title: {scene: {method: (mean text, std text, bold)}}}."""
    sections, title, header = {}, None, None
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if line.startswith("## "):
                title, header = line[3:], None
                sections[title] = {}
            elif line.startswith("|") and title is not None:
                cells = [c.strip() for c in line.strip("|").split("|")]
                if header is None:
                    header = cells
                elif not set(cells[0]) <= set("-:"):
                    row = {}
                    for method, cell in zip(header[1:], cells[1:]):
                        bold = cell.startswith("**")
                        match = re.fullmatch(r"\**([-+0-9.e]+) ± ([-+0-9.e]+)\**", cell)
                        if match:
                            row[method] = (match.group(1), match.group(2), bold)
                    sections[title][cells[0]] = row
    return sections


class AblationTest(unittest.TestCase):
    """The tiny ablation, run once for all tests of the class."""

    @classmethod
    def setUpClass(cls):
        if not os.path.exists(EMLT):
            raise unittest.SkipTest(f"emlt binary not found at {EMLT} (set EMLT_BINARY)")
        cls.tmp = tempfile.TemporaryDirectory(prefix="emlt-ablation-")
        cls.out = os.path.join(cls.tmp.name, "out")
        cls.cache = os.path.join(cls.tmp.name, "cache")
        cls.first = run_ablation(CONFIG, cls.out, cls.cache)
        if cls.first.returncode != 0:
            raise AssertionError(f"ablation failed:\n{cls.first.stderr}")
        with open(os.path.join(cls.out, "results.csv"), newline="") as f:
            cls.rows = list(csv.DictReader(f))
        with open(CONFIG) as f:
            cls.config = json.load(f)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def expected_runs(self):
        """(method, seed, budget tag) of every run the config names."""
        budgets = [f"pp-{b}" for b in self.config["budgets"].get("per_pixel", [])]
        budgets += [f"time-{b:g}s" for b in self.config["budgets"].get("seconds", [])]
        return [(m, s, b) for b in budgets for m in self.config["methods"] for s in self.config["seeds"]]

    def test_outputs_exist(self):
        for name in ("results.csv", "table.md", "convergence.png", "convergence_time.png", "strip.png",
                     "report.html", "references/cornell-box.pfm"):
            path = os.path.join(self.out, name)
            self.assertTrue(os.path.isfile(path) and os.path.getsize(path) > 0, name)
        for method, seed, budget in self.expected_runs():
            run_dir = os.path.join(self.out, "runs", "cornell-box", method, budget, f"seed-{seed}")
            files = ["image.pfm", "image.png", "run.csv", "run.json"] + (["stats.json"] if method == "mlt" else [])
            for name in files:
                self.assertTrue(os.path.isfile(os.path.join(run_dir, name)), f"{run_dir}/{name}")
        self.assertEqual(len(self.rows), len(self.expected_runs()))
        with open(os.path.join(self.out, "report.html")) as f:
            page = f.read()
        for name in ("convergence.png", "convergence_time.png", "strip.png", "results.csv"):
            self.assertIn(name, page)

    def compare(self):
        """`emlt compare --json --scene` on every saved image: {relative image path: metrics}."""
        reference = os.path.join(self.out, "references", "cornell-box.pfm")
        images = [os.path.join(self.out, row["image"]) for row in self.rows]
        scene = os.path.join(ROOT, "scenes", "cornell-box", "scene.json")
        result = subprocess.run([EMLT, "compare", reference] + images + ["--json", "--scene", scene],
                                capture_output=True, text=True, check=True)
        objects = [json.loads(line) for line in result.stdout.splitlines() if line.startswith("{")]
        self.assertEqual(len(objects), len(images))
        return {row["image"]: obj for row, obj in zip(self.rows, objects)}

    def test_results_equal_compare(self):
        metrics = self.compare()
        reference = read_pfm(os.path.join(self.out, "references", "cornell-box.pfm"))
        for row in self.rows:
            m = metrics[row["image"]]
            for key in ("mse", "relmse", "mse_no_emitter", "mean_ratio"):
                self.assertEqual(float(row[key]), m[key], f"{row['image']} {key}")
            image = read_pfm(os.path.join(self.out, row["image"]))
            self.assertAlmostEqual(numpy_mse(image, reference) / m["mse"], 1.0, places=4)
            if row["method"] == "mlt":
                self.assertTrue(row["acceptance_bidir"], "MLT rows carry acceptance rates")

    def test_table_equals_compare(self):
        metrics = self.compare()
        sections = parse_table_md(os.path.join(self.out, "table.md"))
        budgets = [("per_pixel", b, f"{b} samples/mutations per pixel") for b in self.config["budgets"]["per_pixel"]]
        budgets += [("seconds", b, f"equal time, {b:g} s") for b in self.config["budgets"]["seconds"]]
        for metric, title in (("mse", "MSE"), ("relmse", "relMSE")):
            for kind, value, caption in budgets:
                section = sections[f"{title} at {caption}"]["cornell-box"]
                means = {}
                for method in self.config["methods"]:
                    values = [metrics[r["image"]][metric] for r in self.rows if r["method"] == method
                              and r["budget_kind"] == kind and float(r["budget"]) == value]
                    self.assertEqual(len(values), len(self.config["seeds"]))
                    mean = sum(values) / len(values)
                    std = math.sqrt(sum((v - mean) ** 2 for v in values) / (len(values) - 1))
                    mean_text, std_text, _bold = section[method]
                    self.assertTrue(within_rounding(mean_text, mean), f"{title} {caption} {method}: {mean_text} vs {mean}")
                    self.assertTrue(within_rounding(std_text, std), f"{title} {caption} {method}: {std_text} vs {std}")
                    means[method] = mean
                best = min(means, key=means.get)
                self.assertEqual([m for m, cell in section.items() if cell[2]], [best], f"{title} {caption}: bold")

    def test_second_run_skips_everything(self):
        images = [os.path.join(self.out, row["image"]) for row in self.rows]
        before = {p: os.stat(p).st_mtime_ns for p in images}
        again = run_ablation(CONFIG, self.out, self.cache)
        self.assertEqual(again.returncode, 0, again.stderr)
        n = len(self.expected_runs())
        self.assertIn(f"0 runs rendered, {n} skipped", again.stderr)
        self.assertIn("cached", again.stderr)  # the reference comes from the cache
        self.assertEqual(before, {p: os.stat(p).st_mtime_ns for p in images})

    def test_the_binary_and_mpirun_render_the_module_s_bits(self):
        # The runs above went through the Python module built beside the binary; spawning the
        # binary under `mpirun -n 2` must give every fixed-budget image bit for bit (the binary
        # alone: test_chain_variance.py).
        budget = self.config["budgets"]["per_pixel"][0]
        first = os.path.join(self.out, "runs", "cornell-box", "mlt", f"pp-{budget}", "seed-1")
        with open(os.path.join(first, "run.json")) as f:
            self.assertIn("Python module", json.load(f)["engine"])
        config = dict(self.config, seeds=[1], budgets={"per_pixel": [budget]})
        config["scenes"] = [dict(self.config["scenes"][0], path=os.path.join(ROOT, "scenes/cornell-box/scene.json"))]
        path = os.path.join(self.tmp.name, "fixed-budget.json")
        with open(path, "w") as f:
            json.dump(config, f)
        for engine in (("--mpi", "2"),):
            out = os.path.join(self.tmp.name, "spawned-" + engine[0].strip("-"))
            result = run_ablation(path, out, self.cache, ("--no-report",) + engine)
            self.assertEqual(result.returncode, 0, result.stderr)
            for method in self.config["methods"]:
                run_dir = os.path.join("runs", "cornell-box", method, f"pp-{budget}", "seed-1")
                with open(os.path.join(out, run_dir, "run.json")) as f:
                    self.assertNotIn("Python module", json.load(f)["engine"])
                with open(os.path.join(out, run_dir, "image.pfm"), "rb") as a, \
                        open(os.path.join(self.out, run_dir, "image.pfm"), "rb") as b:
                    self.assertEqual(a.read(), b.read(), f"{engine}: {method}")

    def bad_method(self, methods, name):
        """Run a copy of the tiny config with methods; assert a one-line error naming name."""
        config = dict(self.config, methods=methods)
        config["scenes"] = [dict(self.config["scenes"][0], path=os.path.join(ROOT, "scenes/cornell-box/scene.json"))]
        path = os.path.join(self.tmp.name, f"bad-{name}.json")
        with open(path, "w") as f:
            json.dump(config, f)
        result = run_ablation(path, os.path.join(self.tmp.name, "bad-out"), self.cache)
        self.assertNotEqual(result.returncode, 0)
        lines = [line for line in result.stderr.splitlines() if line.strip()]
        errors = [line for line in lines if "error" in line]
        self.assertEqual(len(errors), 1, result.stderr)
        self.assertIn(f"'{name}'", errors[0])
        self.assertNotIn("Traceback", result.stderr)

    def test_unknown_method_fails_with_one_line(self):
        self.bad_method(["pt", "no-such-method"], "no-such-method")

    def test_method_the_engine_rejects_fails_with_one_line(self):
        self.bad_method({"pt": {}, "odd-mix": {"mutations": "no-such-strategy=1"}}, "odd-mix")


class IndirectOnlyTest(unittest.TestCase):
    """"indirect_only": the runs' direct image is subtracted exactly, so only the chains are measured."""

    def run_config(self, name, **changes):
        """Run a small indirect-only config (changed by changes) into a fresh folder; returns (result, out)."""
        config = {"name": name, "scenes": [os.path.join(ROOT, "scenes/cornell-box/scene.json")],
                  "width": 16, "height": 16,
                  "methods": {"mlt": {"args": "--integrator mlt --bootstrap 2048 --chains 16"},
                              "emlt": {"args": "--integrator emlt --bootstrap 2048"}},
                  "seeds": [1, 2], "budgets": {"per_pixel": [4]},
                  "reference": {"integrator": "mlt", "mpp": 16, "parts": 2, "args": "--bootstrap 2048"},
                  "indirect_only": {"direct_spp": 4}, "threads": 1}
        config.update(changes)
        path = os.path.join(self.tmp.name, name + ".json")
        with open(path, "w") as f:
            json.dump(config, f)
        out = os.path.join(self.tmp.name, name)
        return run_ablation(path, out, os.path.join(self.tmp.name, "cache")), out

    def setUp(self):
        if not os.path.exists(EMLT):
            self.skipTest(f"emlt binary not found at {EMLT} (set EMLT_BINARY)")
        self.tmp = tempfile.TemporaryDirectory(prefix="emlt-ablation-indirect-")
        self.addCleanup(self.tmp.cleanup)

    def rows(self, out, name):
        with open(os.path.join(out, name), newline="") as f:
            return list(csv.DictReader(f))

    def test_direct_light_alone_measures_zero(self):
        # With paths of at most two segments the chains have nothing to do: every image is its
        # seed's direct image, bit for bit, and the indirect reference is black.  A runner that
        # let direct light into the chains (--direct mlt) or subtracted another seed's or
        # sample count's direct image would measure a positive MSE here.
        result, out = self.run_config("direct-only", max_depth=2)
        self.assertEqual(result.returncode, 0, result.stderr)
        rows = self.rows(out, "results.csv")
        self.assertEqual(len(rows), 4)
        for row in rows:
            self.assertEqual(float(row["mse"]), 0.0, row["image"])
        self.assertFalse(read_pfm(os.path.join(out, "references", "cornell-box.pfm")).any())
        for row in self.rows(out, "chains.csv"):
            self.assertEqual(float(row["chains_variance"]), 0.0, row["method"])

    def test_mse_is_the_chains_against_the_indirect_reference(self):
        result, out = self.run_config("indirect")
        self.assertEqual(result.returncode, 0, result.stderr)
        reference = read_pfm(os.path.join(out, "references", "cornell-box.pfm")).astype("float64")
        self.assertGreater(reference.mean(), 0.0)
        rows = self.rows(out, "results.csv")
        chains = {}
        for row in rows:
            direct = read_pfm(os.path.join(out, "direct", "cornell-box", f"seed-{row['seed']}.pfm"))
            image = read_pfm(os.path.join(out, row["image"])).astype("float64")
            alone = image - direct
            chains.setdefault(row["method"], []).append(alone)
            expected = ((alone - reference) ** 2).mean()
            self.assertAlmostEqual(float(row["mse"]) / expected, 1.0, places=4, msg=row["image"])
            floor = float(row["reference_floor"])
            self.assertGreater(floor, 0.0)
            self.assertAlmostEqual(float(row["mse_net"]), float(row["mse"]) - floor, places=12)
        for row in self.rows(out, "chains.csv"):
            a, b = chains[row["method"]]
            variance = (((a - b) ** 2) / 2).mean()  # sample variance of two values, ddof 1
            self.assertAlmostEqual(float(row["chains_variance"]) / variance, 1.0, places=6, msg=row["method"])
        with open(os.path.join(out, "table.md")) as f:
            table = f.read()
        self.assertIn("indirect light only", table)
        self.assertIn("Chains' variance across seeds", table)

    def test_methods_that_render_direct_light_are_refused(self):
        result, _out = self.run_config("with-pt", methods=["pt", "mlt"])
        self.assertEqual(result.returncode, 2)
        self.assertIn("indirect_only", result.stderr)
        self.assertNotIn("Traceback", result.stderr)


class ScenesDirTest(unittest.TestCase):
    """--scenes DIR: a scene path missing from the repository is looked up by its folder name under DIR."""

    MISSING = "scenes/emlt-test-not-in-repo/scene.json"  # a folder the repository does not have

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory(prefix="emlt-ablation-scenes-")
        self.addCleanup(self.tmp.cleanup)
        self.dir = os.path.join(self.tmp.name, "downloads")
        os.makedirs(self.dir)

    def add_scene(self, folder):
        """A copy of scenes/cornell-box (scene.json and its meshes) as DIR/folder."""
        shutil.copytree(os.path.join(ROOT, "scenes", "cornell-box"), os.path.join(self.dir, folder))
        return os.path.join(self.dir, folder, "scene.json")

    def write_config(self, scenes, **changes):
        config = {"name": "scenes-dir", "scenes": scenes, "width": 8, "height": 8, "methods": ["pt"],
                  "seeds": [1], "budgets": {"per_pixel": [2]}, "reference": {"integrator": "pt", "spp": 8},
                  "threads": 1}
        config.update(changes)
        path = os.path.join(self.tmp.name, "config.json")
        with open(path, "w") as f:
            json.dump(config, f)
        return path

    def test_paths_resolve_in_the_repository_first_then_under_dir(self):
        ablation_config = load_program("scripts/ablation_config.py")
        ConfigError, load_config = ablation_config.ConfigError, ablation_config.load_config
        self.assertFalse(os.path.exists(os.path.join(ROOT, self.MISSING)))
        found = self.add_scene("emlt-test-not-in-repo")
        bitterli = self.add_scene("emlt-test-download")  # Bitterli's download folder X for scenes/bitterli-X
        with open(self.add_scene("cornell-box"), "w") as f:
            f.write("not the repository's scene")  # DIR/cornell-box must not shadow the repository's
        config = self.write_config([self.MISSING, "scenes/bitterli-emlt-test-download/scene.json",
                                    "scenes/cornell-box/scene.json"])
        scenes = load_config(config, self.dir).scenes
        self.assertEqual([(s.name, s.path) for s in scenes],
                         [("emlt-test-not-in-repo", found), ("bitterli-emlt-test-download", bitterli),
                          ("cornell-box", os.path.join(ROOT, "scenes", "cornell-box", "scene.json"))])
        with self.assertRaises(ConfigError) as raised:  # without --scenes, as before
            load_config(config)
        self.assertEqual(str(raised.exception),
                         f"scene '{self.MISSING}' not found (looked next to the config and in {ROOT})")
        with self.assertRaises(ConfigError) as raised:  # not under DIR either: the file and where it was looked for
            load_config(self.write_config(["scenes/emlt-test-nowhere/scene.xml"]), self.dir)
        message = str(raised.exception)
        self.assertNotIn("\n", message)
        self.assertIn("scene 'scenes/emlt-test-nowhere/scene.xml' not found", message)
        self.assertIn(os.path.join(self.dir, "emlt-test-nowhere", "scene.xml"), message)

    def test_runs_a_scene_found_under_dir_and_fails_in_one_line_without(self):
        if not os.path.exists(EMLT):
            self.skipTest(f"emlt binary not found at {EMLT} (set EMLT_BINARY)")
        scene = self.add_scene("emlt-test-not-in-repo")
        config = self.write_config([self.MISSING])
        out, cache = os.path.join(self.tmp.name, "out"), os.path.join(self.tmp.name, "cache")
        missing = run_ablation(config, out, cache)
        self.assertEqual(missing.returncode, 2, missing.stderr)
        self.assertEqual([line for line in missing.stderr.splitlines() if line.strip()],
                         [f"ablation: error: scene '{self.MISSING}' not found "
                          f"(looked next to the config and in {ROOT})"])
        result = run_ablation(config, out, cache, ["--scenes", self.dir])
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(os.path.join(out, "results.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([(r["scene"], r["method"]) for r in rows], [("emlt-test-not-in-repo", "pt")])
        records = [os.path.join(cache, n) for n in os.listdir(cache) if n.endswith(".json")]
        self.assertEqual(len(records), 1)
        with open(records[0]) as f:
            self.assertEqual(json.load(f)["scene"], scene)  # the reference rendered DIR's copy
        wrong = run_ablation(config, out, cache, ["--scenes", os.path.join(self.tmp.name, "no-such-dir")])
        self.assertEqual(wrong.returncode, 2)
        self.assertIn("--scenes", wrong.stderr)
        self.assertNotIn("Traceback", wrong.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
