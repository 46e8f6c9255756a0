#!/usr/bin/python3
"""CTest 'layers': scripts/check_layers.py finds no include running up the engine's layers
(docs/architecture.md), and it does find one when it is there: an upward include, a file in
a folder no layer names, and a private header of a layer above are each planted in a copy
of the engine's folders and must be reported.

    /usr/bin/python3 tests/scripts/test_check_layers.py"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "check_layers.py")


def run(root):
    return subprocess.run([sys.executable, SCRIPT, "--root", root], capture_output=True, text=True)


class CheckLayers(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.copy = tempfile.mkdtemp(prefix="emlt-layers-")
        for top in ("include", "src", "mutations"):
            shutil.copytree(os.path.join(ROOT, top), os.path.join(cls.copy, top))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.copy)

    def plant(self, relative, text):
        path = os.path.join(self.copy, relative)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)
        self.addCleanup(os.remove, path)

    def test_the_repository_is_clean(self):
        result = run(ROOT)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertIn("no include runs up the layers", result.stdout)

    def test_an_upward_include_is_reported(self):
        self.plant("src/scene/planted.cpp", '#include "emlt/integrators/mlt/mlt_integrator.h"\n')
        result = run(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn("src/scene/planted.cpp:1: scene includes emlt/integrators/mlt/mlt_integrator.h "
                      "of integrators/mlt, a layer above", result.stdout)

    def test_the_registry_sits_above_every_integrator(self):
        self.plant("src/integrators/mlt/planted.cpp", '#include "emlt/integrators/registry.h"\n')
        result = run(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn("integrators/mlt includes emlt/integrators/registry.h", result.stdout)

    def test_private_headers_and_mutations_are_placed_too(self):
        self.plant("src/path/planted.cpp", '#include "src/scene/loaders/mitsuba_parser.h"\n'
                   '#include "mutations/bidirectional.h"\n')
        self.plant("src/core/planted.cpp", '#include "src/image/image_file.h"\n')
        result = run(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn("src/path/planted.cpp:2: path includes mutations/bidirectional.h", result.stdout)
        self.assertIn("src/core/planted.cpp:1: core includes src/image/image_file.h of image",
                      result.stdout)
        # The parser is in scene/loaders, below path: allowed.
        self.assertNotIn("src/path/planted.cpp:1:", result.stdout)

    def test_a_folder_no_layer_names_is_reported(self):
        self.plant("src/newroom/thing.cpp", "int x;\n")
        result = run(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn("src/newroom/thing.cpp: in no layer", result.stdout)


if __name__ == "__main__":
    unittest.main()
