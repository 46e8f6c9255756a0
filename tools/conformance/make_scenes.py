"""Writes the Mitsuba 0.6 conformance suite: tests/conformance/scenes/*.xml, their assets
and tests/conformance/suite.json (the manifest the check reads).

Every scene is small (64x64 unless the camera is the subject) and isolates one convention
of Mitsuba 0.6 in a simple room of our own making: an open box (floor, ceiling, back wall,
a red and a green side wall) lit by a small area light under the ceiling, with the
subject in the middle. Reference images are rendered by Mitsuba itself
(tools/conformance/render_references.sh) and compared with emlt's by
tests/conformance/check.py.

Standard library only, except for the JPEG textures, which are encoded by cjpeg and
decoded by djpeg (Debian's libjpeg-turbo-progs: libjpeg's defaults, which Mitsuba reads
JPEG with); their decoded texels go beside them as .ppm for tests/unit/image_io_test.cpp.
Deterministic: run it again and nothing changes.
    python3 -m tools.conformance.make_scenes        (from the repository root)
"""
import argparse
import json
import os

from tools import ROOT
from tools.conformance.scene_groups import SCENES, SUITE
from tools.conformance.scene_groups import (bsdf_wrappers, bsdfs, camera_transforms, depth, films,
                                            lights, normals, orientation, pbrt, plugins, ptracer,
                                            shapes, spectra, textures)
from tools.conformance.scene_groups.assets import write_assets

# The scenes are defined by group in scene_groups/, one module a group; this is the order
# their scenes go into suite.json. The particle tracer's group reuses scenes of the groups
# before it, so it comes after them.
GROUPS = (orientation, depth, bsdfs, bsdf_wrappers, textures, spectra, camera_transforms, films,
          normals, shapes, lights, ptracer, plugins, pbrt)


def build():
    s = {}  # name -> (convention, xml, integrators)
    for group in GROUPS:
        group.add_scenes(s)
    return s


def main():
    # No options: the suite always goes to tests/conformance/; --help says so without writing.
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    write_assets()
    os.makedirs(SCENES, exist_ok=True)
    manifest = []
    # Scenes written in pbrt-v4's format too (NAME.pbrt): emlt renders that file, Mitsuba
    # the XML twin (the entry's emlt_scene, which tests/conformance/check.py reads).
    pbrt_files = {}
    for group in GROUPS:
        if hasattr(group, "add_pbrt_scenes"):
            group.add_pbrt_scenes(pbrt_files)
    for name, (convention, xml, integrators) in build().items():
        with open(os.path.join(SCENES, name + ".xml"), "w") as f:
            f.write(xml)
        entry = {"name": name, "convention": convention, "integrators": integrators}
        if name in pbrt_files:
            with open(os.path.join(SCENES, name + ".pbrt"), "w") as f:
                f.write(pbrt_files[name])
            entry["emlt_scene"] = name + ".pbrt"
        manifest.append(entry)
    path = os.path.join(SUITE, "suite.json")
    old = {}
    if os.path.exists(path):  # keep hand-set fields (spp, known differences) of existing entries
        for entry in json.load(open(path))["scenes"]:
            old[entry["name"]] = entry
    for entry in manifest:
        for key, value in old.get(entry["name"], {}).items():
            entry.setdefault(key, value)
    with open(path, "w") as f:
        json.dump({"scenes": manifest}, f, indent=2)
        f.write("\n")
    print(f"wrote {len(manifest)} scenes to {os.path.relpath(SCENES, ROOT)}")


if __name__ == "__main__":
    main()
