#!/usr/bin/python3
"""CTest 'pbrt_survey_script': tools/conformance/pbrt_survey.py on three small scene texts.

    PYTHONPATH=. /usr/bin/python3 tests/scripts/test_pbrt_survey.py --emlt build/emlt

Checks that every stand-in the survey writes is a file emlt reads (a scene naming a PLY
mesh, EXR, HDR, PFM and PNG images and an include that are all missing is exact, and
partial for the include), that an approximated item and a load failure are reported as
such, that only files with a WorldBegin count as scenes, and that a text whose length
differs from the manifest's is named.
"""
import os
import subprocess
import tempfile
import unittest

from script_env import PYTHON, ROOT, take_emlt_argument

EMLT = take_emlt_argument()

HEADER = """LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" 8 "integer yresolution" 8
WorldBegin
"""

# Every file it names is missing: the survey writes each one.
EXACT = 'PixelFilter "box"\n' + HEADER + """
Texture "png" "spectrum" "imagemap" "string filename" "textures/a.png"
Texture "exr" "spectrum" "imagemap" "string filename" "textures/b.exr"
Texture "hdr" "spectrum" "imagemap" "string filename" ["textures/c.hdr"]
Texture "pfm" "float" "imagemap" "string filename" "textures/d.pfm"
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [1 1 1]
  Shape "trianglemesh" "point3 P" [-1 -1 1  1 -1 1  0 1 1] "integer indices" [0 1 2]
AttributeEnd
Material "diffuse" "texture reflectance" "png"
Shape "plymesh" "string filename" "geometry/mesh.ply"
Material "diffuse" "texture reflectance" "exr"
Shape "plymesh" "string filename" "geometry/mesh.ply"
Material "diffuse" "texture reflectance" "hdr"
Shape "plymesh" "string filename" "geometry/mesh.ply"
Shape "plymesh" "string filename" "geometry/mesh.ply" "texture alpha" "pfm"
Include "geometry/big.pbrt"
"""

APPROXIMATED = HEADER + """AreaLightSource "diffuse"
Shape "sphere"
"""

BROKEN = HEADER + "Frobnicate 1\n"


def write(root, rel, text):
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


class PbrtSurvey(unittest.TestCase):
    def test_stand_ins_verdicts_and_manifest(self):
        with tempfile.TemporaryDirectory() as tmp:
            texts = os.path.join(tmp, "texts")
            write(texts, "a/exact.pbrt", EXACT)
            write(texts, "a/materials.pbrt", 'MakeNamedMaterial "m" "string type" "diffuse"\n')
            write(texts, "b/approximated.pbrt", APPROXIMATED)
            write(texts, "c/broken.pbrt", BROKEN)
            manifest = os.path.join(tmp, "manifest.tsv")
            with open(manifest, "w") as f:
                f.write(f"a/exact.pbrt\tabc\t{len(EXACT)}\n")
                f.write(f"b/approximated.pbrt\tabc\t{len(APPROXIMATED) + 1}\n")
            proc = subprocess.run(
                [PYTHON, "-m", "tools.conformance.pbrt_survey", texts, "--emlt", EMLT,
                 "--manifest", manifest, "--summary"],
                cwd=ROOT, capture_output=True, text=True, timeout=120)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            rows = {line.split("`")[1]: line for line in proc.stdout.splitlines()
                    if line.startswith("| `")}
            self.assertEqual(sorted(rows), ["a/exact.pbrt", "b/approximated.pbrt",
                                            "c/broken.pbrt"])
            self.assertIn("| exact (partial) | 1 included text(s) not read.", rows["a/exact.pbrt"])
            self.assertIn("| approximated | approximated: Gaussian pixel filter",
                          rows["b/approximated.pbrt"])
            self.assertIn("| fails to load | c/broken.pbrt: line 5: unknown directive 'Frobnicate'",
                          rows["c/broken.pbrt"])
            self.assertIn("Tally: approximated 1, exact (partial) 1, fails to load 1 (of 3 scenes).",
                          proc.stdout)
            self.assertIn("length differs from the manifest's: b/approximated.pbrt.", proc.stdout)
            # The fetched texts are left as they were: the stand-ins go to a scratch copy.
            self.assertEqual(sorted(os.listdir(os.path.join(texts, "a"))),
                             ["exact.pbrt", "materials.pbrt"])


if __name__ == "__main__":
    unittest.main()
