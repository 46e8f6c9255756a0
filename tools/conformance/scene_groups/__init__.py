"""The scenes of the Mitsuba 0.6 conformance suite, by group, as tools/conformance/make_scenes.py
writes them: the assets they read (assets), the pieces they are made of (pieces), and one
module a group, each adding its scenes with add_scenes(s). make_scenes calls the groups in
one fixed order, which is the order of the manifest, tests/conformance/suite.json."""
import os

from tools import ROOT

SUITE = os.path.join(ROOT, "tests", "conformance")
SCENES = os.path.join(SUITE, "scenes")
ASSETS = os.path.join(SCENES, "assets")
