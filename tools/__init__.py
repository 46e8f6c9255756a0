"""emlt's tools outside the engine, as one Python package: scene generators (tools.scenes),
the Mitsuba 0.6 conformance suite's upkeep (tools.conformance) and the image helpers that
they, scripts/ and the tests share (tools.images).

Run a tool as a module from the repository root, e.g. ``python3 -m tools.scenes.make_sky``;
the root is then on Python's path, so the modules import each other as ``tools.…`` without
touching ``sys.path``. See tools/README.md.
"""
import os

# The repository root: the tools' default inputs and outputs (scenes/, tests/conformance/,
# build/emlt, docs/) are named from here, so they do not depend on the working directory.
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
