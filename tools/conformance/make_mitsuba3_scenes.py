"""Writes the conformance suite's Mitsuba 3 twins: each scene of tests/conformance/scenes/
rewritten in Mitsuba 3 syntax (<scene version="3.0.0">, snake_case names, `to_uv`, `raw`
...) so that Mitsuba 3 means by it what Mitsuba 0.6 means by the original, into
tests/conformance/scenes/mitsuba3/, with tests/conformance/mitsuba3.json listing the twins
and, for each scene left out, why (a plugin or value Mitsuba 3 no longer has, or one it
gives another meaning that no Mitsuba 3 spelling restores). The names follow Mitsuba
3.9.1, as src/scene/loaders/mitsuba3_names.cpp does.

tests/conformance/check_mitsuba3.py renders each scene and its twin with the same seed
and requires the same bits. Standard library only; deterministic.
    python3 -m tools.conformance.make_mitsuba3_scenes        (from the repository root)
"""
import argparse
import json
import os
import re
import struct
import xml.etree.ElementTree as ET

from tools import ROOT

SUITE = os.path.join(ROOT, "tests", "conformance")
SCENES = os.path.join(SUITE, "scenes")
TWINS = os.path.join(SCENES, "mitsuba3")

# 0.6 parameter names and their Mitsuba 3 spelling (one-word names are the same in both).
RENAMED = {
    "toWorld": "to_world", "maxDepth": "max_depth", "rrDepth": "rr_depth",
    "hideEmitters": "hide_emitters", "sampleCount": "sample_count", "fovAxis": "fov_axis",
    "nearClip": "near_clip", "farClip": "far_clip", "focalLength": "focal_length",
    "faceNormals": "face_normals", "flipNormals": "flip_normals",
    "flipTexCoords": "flip_tex_coords", "shapeIndex": "shape_index", "intIOR": "int_ior",
    "extIOR": "ext_ior", "specularReflectance": "specular_reflectance",
    "specularTransmittance": "specular_transmittance",
    "diffuseReflectance": "diffuse_reflectance", "alphaU": "alpha_u", "alphaV": "alpha_v",
    "sampleVisible": "sample_visible", "pixelFormat": "pixel_format",
    "fileFormat": "file_format", "componentFormat": "component_format",
    "highQualityEdges": "sample_border", "wrapMode": "wrap_mode", "filterType": "filter_type",
    "cutoffAngle": "cutoff_angle", "beamWidth": "beam_width", "samplingWeight": "sampling_weight",
    "apertureRadius": "aperture_radius", "focusDistance": "focus_distance",
    "emitterSamples": "emitter_samples", "bsdfSamples": "bsdf_samples",
    "cropOffsetX": "crop_offset_x", "cropOffsetY": "crop_offset_y", "cropWidth": "crop_width",
    "cropHeight": "crop_height",
}
# A BSDF's parameters that 0.6 scales to conserve energy when above 1 (Mitsuba 3 does not).
CONSERVED = {"reflectance", "diffuseReflectance", "specularReflectance", "specularTransmittance",
             "transmittance", "opacity"}
VALUE_TAGS = {"float", "integer", "boolean", "string", "rgb", "srgb", "spectrum", "blackbody",
              "point", "vector", "transform", "texture", "ref"}
# Plugins of 0.6 that Mitsuba 3 does not have.
DROPPED = {"bsdf": {"phong", "ward", "roughdiffuse", "difftrans", "mixturebsdf", "coating",
                    "roughcoating"},
           "texture": {"scale", "gridtexture"}, "integrator": {"bdpt", "mlt", "pssmlt", "erpt"},
           # Mitsuba 3's films are hdrfilm and specfilm; its samplers have no QMC sequences.
           "film": {"ldrfilm", "mfilm", "tiledhdrfilm"}, "sampler": {"halton", "hammersley", "sobol"},
           # Mitsuba 3 has no sky or sun, and its sunsky (3.6) is another model.
           "emitter": {"sky", "sun"}}
UV_PARAMS = ("uvscale", "uscale", "vscale", "uoffset", "voffset")


PRESETS = os.path.join(ROOT, "src", "scene", "materials", "conductor_presets.cpp")
AIR = 1.000277  # 0.6's default exterior IOR of a conductor ("air"); Mitsuba 3 reads none


def f32(x):
    """x rounded to single precision, as emlt stores it."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def conductor_presets():
    """0.6's RGB (eta, k) of each named conductor: emlt's table, which the 0.6 reader uses."""
    text = open(PRESETS).read()
    number = r"\s*(-?[0-9.e+-]+)f"
    rgb = r"\{" + r",".join([number] * 3) + r"\s*\}"
    found = re.findall(r'\{"(\w+)",\s*' + rgb + r",\s*" + rgb + r"\}", text)
    return {m[0]: ([f32(float(v)) for v in m[1:4]], [f32(float(v)) for v in m[4:7]]) for m in found}


def conductor_as_eta_k(node):
    """A conductor named by material (0.6's default Cu) as the explicit eta and k that 0.6
    renders it with (the preset over air's IOR, in single precision): Mitsuba 3 converts
    presets from spectra its own way, so only explicit values mean the same in both."""
    p = params(node)
    name = p["material"].get("value") if "material" in p else "Cu"
    presets = conductor_presets()
    if name not in presets or "extEta" in p:
        raise Skip(f"conductor material '{name}' with no explicit 0.6 RGB in emlt's table")
    air = f32(AIR)
    position = list(node).index(p["material"]) if "material" in p else 0
    if "material" in p:
        node.remove(p["material"])
    for i, (key, values) in enumerate(zip(("eta", "k"), presets[name])):
        value = ", ".join(repr(abs(f32(v / air))) for v in values)
        node.insert(position + i, ET.Element("rgb", {"name": key, "value": value}))


class Skip(Exception):
    """The scene has no Mitsuba 3 twin; the message says why."""


def png_has_gamma_chunk(path):
    """Whether a PNG file carries a gAMA chunk (which Mitsuba 3 does not read)."""
    with open(path, "rb") as f:
        data = f.read()
    pos = 8
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        if kind == b"gAMA":
            return True
        pos += 12 + length
    return False


def params(node):
    return {c.get("name"): c for c in node if c.tag in VALUE_TAGS and c.get("name")}


def rewrite_bitmap(node):
    p = params(node)
    file = p["filename"].get("value")
    for name in ("channel", "wrapModeU", "wrapModeV"):
        if name in p:
            raise Skip(f"bitmap '{name}' has no Mitsuba 3 form")
    if "filterType" not in p:
        raise Skip("a bitmap with 0.6's default EWA filtering (Mitsuba 3 has none)")
    if file.endswith(".png") and png_has_gamma_chunk(os.path.join(SCENES, file)):
        raise Skip("a PNG with a gAMA chunk (Mitsuba 3 reads it as sRGB)")
    if "wrapMode" in p and p["wrapMode"].get("value") not in ("repeat", "mirror", "clamp"):
        raise Skip(f"wrap mode '{p['wrapMode'].get('value')}' (Mitsuba 3 has repeat, mirror, clamp)")
    if "gamma" in p:
        # gamma 1 reads an 8-bit file's values as linear: Mitsuba 3's `raw`.
        if float(p["gamma"].get("value")) != 1.0:
            raise Skip("bitmap gamma other than 1 (Mitsuba 3 knows sRGB and linear only)")
        gamma = p["gamma"]
        gamma.tag, gamma.attrib = "boolean", {"name": "raw", "value": "true"}


def rewrite_uv(node):
    """uvscale/uscale/vscale/uoffset/voffset as Mitsuba 3's to_uv (uv * scale + offset)."""
    p = params(node)
    if not any(name in p for name in UV_PARAMS):
        return
    value = {name: float(p[name].get("value")) for name in UV_PARAMS if name in p}
    uniform = value.get("uvscale", 1.0)
    su, sv = value.get("uscale", uniform), value.get("vscale", uniform)
    ou, ov = value.get("uoffset", 0.0), value.get("voffset", 0.0)
    first = min(list(node).index(p[name]) for name in UV_PARAMS if name in p)
    for name in UV_PARAMS:
        if name in p:
            node.remove(p[name])
    transform = ET.Element("transform", {"name": "to_uv"})
    ET.SubElement(transform, "scale", {"x": "%r" % su, "y": "%r" % sv})
    if ou or ov:
        ET.SubElement(transform, "translate", {"x": "%r" % ou, "y": "%r" % ov})
    node.insert(first, transform)


def rewrite(node, parent=None):
    tag, kind = node.tag, node.get("type")
    if kind in DROPPED.get(tag, ()):
        raise Skip(f"<{tag} type=\"{kind}\"> is not a Mitsuba 3 plugin")
    if node.get("name") == "strictNormals":
        raise Skip("Mitsuba 3's integrators have no strictNormals")
    if tag == "texture" and kind == "vertexcolors":
        raise Skip("Mitsuba 3 reads vertex colours through a mesh_attribute texture, and its "
                   "PLY reader has no srgb switch")
    if tag == "emitter" and kind == "sunsky":
        raise Skip("Mitsuba 3's sunsky (3.6) is another sky model, with other parameters")
    if tag in ("srgb", "blackbody"):
        raise Skip(f"<{tag}> is not a Mitsuba 3 element")
    if tag == "spectrum":
        value = node.get("value", "")
        if ":" in value or node.get("filename"):
            raise Skip("a measured spectrum (Mitsuba 3 converts it with D65 weighting)")
        if len(value.replace(",", " ").split()) == 3:
            node.tag = "rgb"  # 0.6's three-valued spectrum is linear RGB in RGB mode
        elif parent is not None and parent.tag == "emitter":
            node.tag = "rgb"  # Mitsuba 3 gives a uniform emitter spectrum a D65-white tint
    if tag == "lookAt":
        node.tag = "lookat"
    if tag == "emitter" and kind == "envmap" and "gamma" in params(node):
        raise Skip("Mitsuba 3's envmap reads no gamma (its map is linear, or sRGB if 8-bit)")
    if tag == "rfilter" and kind == "box" and "radius" in params(node):
        raise Skip("Mitsuba 3's box filter is half a pixel wide whatever its radius (it reads none)")
    if (parent is not None and parent.tag == "bsdf" and node.get("name") in CONSERVED and
            tag in ("rgb", "spectrum", "float") and
            max(float(v) for v in node.get("value", "0").replace(",", " ").split()) > 1):
        raise Skip("a reflectance above 1, which 0.6 scales to conserve energy and Mitsuba 3 "
                   "leaves as given")
    if tag == "bsdf" and kind in ("conductor", "roughconductor") and "eta" not in params(node):
        conductor_as_eta_k(node)
    if tag == "string" and node.get("name") == "distribution" and node.get("value") not in ("beckmann", "ggx"):
        raise Skip(f"microfacet distribution '{node.get('value')}' (Mitsuba 3 has beckmann and ggx)")
    if tag == "bsdf" and kind == "normalmap":
        # 0.6's normal map neither turns normals facing away from the viewer nor darkens
        # the shading where they lean: Mitsuba 3 does both unless told not to.
        for name in ("flip_invalid_normals", "use_shadowing_function"):
            node.insert(0, ET.Element("boolean", {"name": name, "value": "false"}))
    if tag == "texture" and kind == "bitmap":
        rewrite_bitmap(node)
    if tag == "texture" and kind in ("bitmap", "checkerboard"):
        rewrite_uv(node)
    if tag in VALUE_TAGS and node.get("name") in RENAMED:
        node.set("name", RENAMED[node.get("name")])
    for child in list(node):
        rewrite(child, node)


def twin(xml_text):
    root = ET.fromstring(xml_text)
    root.set("version", "3.0.0")
    rewrite(root)
    # Assets are named from the scene's folder, one level up from the twins'.
    for node in root.iter("string"):
        if node.get("name") == "filename" and node.get("value", "").startswith("assets/"):
            node.set("value", "../" + node.get("value"))
    ET.indent(root, "  ")
    return ('<?xml version="1.0" encoding="utf-8"?>\n<!-- emlt conformance suite, Mitsuba 3 twin; '
            'written by tools/conformance/make_mitsuba3_scenes.py -->\n' +
            ET.tostring(root, encoding="unicode") + "\n")


def main():
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    suite = json.load(open(os.path.join(SUITE, "suite.json")))["scenes"]
    os.makedirs(TWINS, exist_ok=True)
    for old in os.listdir(TWINS):
        if old.endswith(".xml"):
            os.remove(os.path.join(TWINS, old))
    twins, skipped = [], {}
    for entry in suite:
        name = entry["name"]
        try:
            text = twin(open(os.path.join(SCENES, name + ".xml")).read())
        except Skip as reason:
            skipped[name] = str(reason)
            continue
        with open(os.path.join(TWINS, name + ".xml"), "w") as f:
            f.write(text)
        twins.append(name)
    with open(os.path.join(SUITE, "mitsuba3.json"), "w") as f:
        json.dump({"twins": twins, "skipped": skipped}, f, indent=2)
        f.write("\n")
    print(f"wrote {len(twins)} Mitsuba 3 twins to {os.path.relpath(TWINS, ROOT)}; "
          f"{len(skipped)} scenes have none (tests/conformance/mitsuba3.json says why)")


if __name__ == "__main__":
    main()
