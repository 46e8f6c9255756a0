"""The probe scenes of the coverage matrix (coverage_matrix.py): for each Mitsuba 0.6 plugin of
mitsuba06_plugins.json, a tiny scene that uses it where a scene file puts it and sets none of
its parameters, and one scene per value tried for each parameter.

Every probe is the same small scene (a camera, a light, a sphere) with the plugin put in its
place, so that what `emlt info` says about a probe is about that plugin alone. What a probe
needs besides (a nested BSDF for `twosided`, a mesh file for `obj`, the weights of a
`mixturebsdf`) is listed in NEEDS; the values tried for a parameter come from its type and
its default in Mitsuba (value_variants), or from VALUES where a type says too little (a
`distribution` must be one Mitsuba knows).
"""
import re
from xml.sax.saxutils import quoteattr

# Files the probes name, from the conformance suite's assets (the probe folder links them).
ASSETS = "tests/conformance/scenes/assets"

DIFFUSE = '<bsdf type="diffuse"/>'
CHECKER = '<texture type="checkerboard"/>'
BITMAP = '<texture type="bitmap"><string name="filename" value="assets/grid.png"/></texture>'
# Mitsuba refuses a bitmap normal map whose gamma is not given (its texels are not colours).
LINEAR_BITMAP = ('<texture type="bitmap"><string name="filename" value="assets/grid.png"/>'
                 '<float name="gamma" value="1"/></texture>')

# What a plugin needs to be valid in Mitsuba, beside the parameter probed: (parameters as
# (element, name, value), nested XML). A parameter probed replaces its entry here.
NEEDS = {
    ("bsdf", "twosided"): ([], DIFFUSE),
    ("bsdf", "mask"): ([], DIFFUSE),
    ("bsdf", "mixturebsdf"): ([("string", "weights", "0.5, 0.5")], DIFFUSE + DIFFUSE),
    ("bsdf", "blendbsdf"): ([], DIFFUSE + DIFFUSE),
    ("bsdf", "coating"): ([], DIFFUSE),
    ("bsdf", "roughcoating"): ([], DIFFUSE),
    ("bsdf", "bumpmap"): ([], BITMAP + DIFFUSE),
    ("bsdf", "normalmap"): ([], LINEAR_BITMAP + DIFFUSE),
    ("bsdf", "irawan"): ([("string", "filename", "cloth.wvp")], ""),
    ("emitter", "envmap"): ([("string", "filename", "assets/sky.exr")], ""),
    ("texture", "bitmap"): ([("string", "filename", "assets/grid.png")], ""),
    # An mfilm is one pixel by default: too small for a crop window.
    ("film", "mfilm"): ([("integer", "width", "8"), ("integer", "height", "8")], ""),
    ("texture", "scale"): ([], CHECKER),
    ("shape", "obj"): ([("string", "filename", "assets/panel_uv.obj")], DIFFUSE),
    ("shape", "ply"): ([("string", "filename", "assets/ball_ascii.ply")], DIFFUSE),
    ("shape", "serialized"): ([("string", "filename", "assets/shapes.serialized")], DIFFUSE),
    ("shape", "hair"): ([("string", "filename", "strands.hair")], DIFFUSE),
    ("shape", "heightfield"): ([("string", "filename", "assets/grid.png")], DIFFUSE),
    ("shape", "shapegroup"): ([], '<shape type="sphere"/>'),
    ("shape", "instance"): ([], '<ref id="group"/>'),
    ("integrator", "adaptive"): ([], '<integrator type="path"/>'),
    ("integrator", "irrcache"): ([], '<integrator type="path"/>'),
    ("integrator", "multichannel"): ([], '<integrator type="path"/>'),
    ("integrator", "field"): ([("string", "field", "position")], ""),
    ("medium", "heterogeneous"): (
        [], '<volume type="constvolume" name="density"><float name="value" value="1"/></volume>'),
    ("volume", "gridvolume"): ([("string", "filename", "density.vol")], ""),
    ("volume", "volcache"): (
        [], '<volume type="constvolume"><float name="value" value="1"/></volume>'),
    ("volume", "hgridvolume"): ([("string", "filename", "density.vol")], ""),
}
# Elements beside the probe that it refers to: an instance's shape group, and the reverse.
GROUP = ('<shape type="shapegroup" id="group"><shape type="sphere"/></shape>')
BESIDE = {
    ("shape", "instance"): GROUP,
    ("shape", "shapegroup"): '<shape type="instance"><ref id="group"/></shape>',
}

# Values for parameters whose type says too little: (plugin or None for any, name) ->
# [(element, value)], each a value Mitsuba 0.6 accepts.
VALUES = {
    (None, "distribution"): [("string", "beckmann"), ("string", "ggx"), ("string", "phong")],
    (None, "material"): [("string", "Cu")],
    ("hk", "material"): [("string", "skin1")],
    ("homogeneous", "material"): [("string", "skin1")],
    ("dipole", "material"): [("string", "skin1")],
    ("singlescatter", "material"): [("string", "skin1")],
    (None, "filename"): [],  # given by NEEDS; a probe of it alone says nothing new
    ("ward", "variant"): [("string", "ward"), ("string", "ward-duer"), ("string", "balanced")],
    (None, "fovAxis"): [("string", "x"), ("string", "y"), ("string", "smaller"),
                        ("string", "larger")],
    (None, "focalLength"): [("string", "50mm")],
    (None, "fov"): [("float", "40")],
    ("mixturebsdf", "weights"): [("string", "0.5, 0.5")],
    ("mixturephase", "weights"): [("string", "0.5, 0.5")],
    (None, "wrapMode"): [("string", "repeat"), ("string", "mirror"), ("string", "clamp"),
                         ("string", "zero"), ("string", "one")],
    (None, "wrapModeU"): [("string", "repeat"), ("string", "clamp")],
    (None, "wrapModeV"): [("string", "repeat"), ("string", "clamp")],
    (None, "filterType"): [("string", "ewa"), ("string", "bilinear"), ("string", "nearest")],
    (None, "channel"): [("string", "r")],
    (None, "pixelFormat"): [("string", "rgb"), ("string", "rgba"), ("string", "luminance")],
    (None, "componentFormat"): [("string", "float16"), ("string", "float32")],
    ("hdrfilm", "fileFormat"): [("string", "openexr"), ("string", "rgbe"), ("string", "pfm")],
    ("ldrfilm", "fileFormat"): [("string", "png"), ("string", "jpeg")],
    ("mfilm", "fileFormat"): [("string", "matlab"), ("string", "numpy")],
    ("ldrfilm", "tonemapMethod"): [("string", "gamma"), ("string", "reinhard")],
    (None, "channelNames"): [("string", "R, G, B")],
    ("curvature", "curvature"): [("string", "gaussian"), ("string", "mean")],
    ("field", "field"): [("string", "position"), ("string", "shNormal")],
    ("heterogeneous", "method"): [("string", "woodcock"), ("string", "simpson")],
    ("homogeneous", "strategy"): [("string", "balance")],
    ("perspective_rdist", "kc"): [("string", "0.1, 0.01")],
    ("motion", "config"): [("string", "d")],
    (None, "direction"): [("vector", "0, -1, 0")],
    (None, "sunDirection"): [("vector", "0, 1, 1")],
    (None, "position"): [("point", "0, 1, 0")],
    (None, "p1"): [("point", "0, 0, 1")],
    (None, "radius"): [("float", "0.5")],
    ("box", "radius"): [("float", "0.5")],
    (None, "width"): [("integer", "8")],
    (None, "height"): [("integer", "8")],
    (None, "cropWidth"): [("integer", "4")],
    (None, "cropHeight"): [("integer", "4")],
    (None, "cropOffsetX"): [("integer", "2")],
    (None, "cropOffsetY"): [("integer", "2")],
    (None, "month"): [("integer", "7")],
    (None, "day"): [("integer", "10")],
    (None, "year"): [("integer", "2010")],
    (None, "hour"): [("float", "15")],
    (None, "apertureRadius"): [("float", "0.1")],
    (None, "focusDistance"): [("float", "5")],
    (None, "shutterClose"): [("float", "0")],
    (None, "lineWidth"): [("float", "0.01")],
    (None, "maxSmoothAngle"): [("float", "30")],
    (None, "scramble"): [("integer", "-1")],
    ("sunsky", "sunRadiusScale"): [("float", "1")],
    ("sun", "sunRadiusScale"): [("float", "1")],
    (None, "gamma"): [("float", "2.2")],
    (None, "stddev"): [("float", "0.5")],
    (None, "lobes"): [("integer", "3")],
    (None, "B"): [("float", "0.3333")],
    (None, "C"): [("float", "0.3333")],
    (None, "turbidity"): [("float", "3")],
    (None, "shapeIndex"): [("integer", "0")],
    (None, "emitterSamples"): [("integer", "1")],
    (None, "bsdfSamples"): [("integer", "1")],
    (None, "shadingSamples"): [("integer", "1")],
    (None, "samplingDensity"): [("float", "1")],
    (None, "voxelWidth"): [("float", "0.1")],
    ("homogeneous", "channel"): [("integer", "0")],
    (None, "repeatU"): [("float", "1")],
    (None, "repeatV"): [("float", "1")],
    (None, "initialRadius"): [("float", "0")],
    (None, "cutoffAngle"): [("float", "20")],
    (None, "beamWidth"): [("float", "15")],
    (None, "g"): [("float", "0.8")],
    (None, "time"): [("float", "0")],
    (None, "maxChains"): [("float", "0")],
    (None, "min"): [("point", "0, 0, 0")],
    (None, "max"): [("point", "1, 1, 1")],
    (None, "prefix"): [("string", "grid")],
    (None, "postfix"): [("string", ".vol")],
    (None, "undefined"): [("spectrum", "0")],
}

# Parameters Mitsuba reads only together: a probe of one gives the other the same value.
# A crop window's offset with its size: the size alone defaults to the film's, which an
# offset pushes off the film (Mitsuba refuses that).
COMPANIONS = {"alphaU": "alphaV", "alphaV": "alphaU", "cropOffsetX": "cropWidth",
              "cropOffsetY": "cropHeight"}

NUMBER = r"-?(?:\d+\.?\d*|\.\d+)(?:[eE]-?\d+)?"


def number_in(text, integer):
    """The value a default text gives, when it is a plain number ("0.5f", "30", "1e-2f",
    "0.1, i.e. ..."); None for an expression or words."""
    text = text.strip()
    match = re.fullmatch(r"(" + NUMBER + r")f?", text) or re.match(r"(" + NUMBER + r")\b", text)
    if not match:
        return None
    value = match.group(1)
    if integer:
        return value if re.fullmatch(r"-?\d+", value) else None
    return value


def words_in(text):
    """A string default: "\"balanced\"" from the code, "Cu / copper" or "bk7 / 1.5046" from
    the manual -> the first word."""
    match = re.fullmatch(r'"([^"]*)"', text.strip())
    if match:
        return match.group(1) or None
    match = re.match(r"([A-Za-z][\w-]*)", text.strip())
    return match.group(1) if match else None


def value_variants(category, plugin, param):
    """[(element, value)]: the values a probe sets `param` to, one scene each. Booleans are
    tried both ways and a parameter that takes a texture also as one, since the loader
    may read one value and not the other."""
    name = param["name"]
    if (plugin, name) in VALUES:
        return VALUES[(plugin, name)]
    if (None, name) in VALUES:
        return VALUES[(None, name)]
    types = param.get("types") or [param.get("type", "")]
    defaults = [param.get("code_default", ""), param.get("default", "")]
    variants = []
    for kind in types:
        if kind in ("float", "integer"):
            value = next((v for v in (number_in(d, kind == "integer") for d in defaults) if v),
                         None)
            if value is None and kind == "float":  # the manual's "bk7 / 1.5046"
                found = re.search(NUMBER, param.get("default", ""))
                value = found.group(0) if found else None
            variants.append((kind, value or ("0.5" if kind == "float" else "4")))
        elif kind == "boolean":
            variants += [("boolean", "true"), ("boolean", "false")]
        elif kind == "spectrum":
            value = next((v for v in (number_in(d, False) for d in defaults) if v), None)
            variants.append(("rgb", value or "0.5"))
        elif kind == "string":
            value = next((v for v in (words_in(d) for d in defaults) if v), None)
            if value:
                variants.append(("string", value))
        elif kind == "transform":
            variants.append(("transform", None))
        elif kind in ("point", "vector"):
            value = re.findall(NUMBER, param.get("default", ""))
            variants.append((kind, ", ".join(value) if len(value) == 3 else "0, 0, 1"))
        elif kind == "texture":
            variants.append(("texture", None))
    # Each (element, value) once: a parameter typed "float or texture" twice in the manual.
    seen, unique = set(), []
    for element, value in variants:
        if (element, value) not in seen:
            seen.add((element, value))
            unique.append((element, value))
    return unique


def parameter_xml(category, element, name, value):
    """One parameter as a scene file writes it."""
    if element == "transform":
        if category == "sensor":
            return ('<transform name="%s"><lookat origin="0, 0, -5" target="0, 0, 0" '
                    'up="0, 1, 0"/></transform>' % name)
        return '<transform name="%s"><translate z="0.1"/></transform>' % name
    if element == "texture":
        return '<texture type="checkerboard" name=%s/>' % quoteattr(name)
    if element in ("point", "vector"):
        x, y, z = [v.strip() for v in value.split(",")]
        return '<%s name=%s x="%s" y="%s" z="%s"/>' % (element, quoteattr(name), x, y, z)
    return "<%s name=%s value=%s/>" % (element, quoteattr(name), quoteattr(value))


def plugin_element(category, plugin, params, extra=""):
    """The plugin's element with `params` [(element, name, value)] and what it needs."""
    needed, nested = NEEDS.get((category, plugin), ([], ""))
    params = list(params) + [(e, COMPANIONS[n], v) for e, n, v in params if n in COMPANIONS]
    given = {name for _, name, _ in params}
    body = [parameter_xml(category, e, n, v) for e, n, v in needed if n not in given]
    body += [parameter_xml(category, e, n, v) for e, n, v in params]
    tag = category
    attributes = ' type="%s"' % plugin
    if category == "texture":
        attributes += ' name="reflectance"'
    if category == "medium":
        attributes += ' name="interior"'
    if category == "volume":
        attributes += ' name="density"'
    if (category, plugin) == ("shape", "shapegroup"):
        attributes += ' id="group"'
    return "<%s%s>%s%s%s</%s>" % (tag, attributes, "".join(body), nested, extra, tag)


CAMERA = ('<float name="fov" value="40"/><transform name="toWorld"><lookat origin="0, 0, -5" '
          'target="0, 0, 0" up="0, 1, 0"/></transform>')
LIGHT_PLACE = ('<shape type="rectangle"><transform name="toWorld"><translate y="2"/></transform>'
               '%s</shape>')
AREA = '<emitter type="area"><rgb name="radiance" value="1"/></emitter>'


def scene(category, plugin, params):
    """The probe scene (text) for `plugin` with `params` set."""
    element = plugin_element(category, plugin, params)
    integrator = '<integrator type="path"/>'
    sensor_type, sensor_params = "perspective", CAMERA
    sampler = '<sampler type="independent"/>'
    rfilter = '<rfilter type="box"/>'
    film = None
    light = AREA
    shapes, top = [], []
    if category == "integrator":
        integrator = element
    elif category == "sensor":
        sensor_type, sensor_params = plugin, "".join(
            parameter_xml(category, e, n, v) for e, n, v in params)
    elif category == "sampler":
        sampler = element
    elif category == "rfilter":
        rfilter = element
    elif category == "film":
        film = plugin_element(category, plugin, params, rfilter)
    elif category == "emitter":
        if plugin == "area":
            light = element
        else:
            top.append(element)
    elif category == "bsdf":
        shapes.append('<shape type="sphere">%s</shape>' % element)
    elif category == "texture":
        shapes.append('<shape type="sphere"><bsdf type="diffuse">%s</bsdf></shape>' % element)
    elif category == "shape":
        shapes.append(element)
        beside = BESIDE.get((category, plugin))
        if beside:
            shapes.append(beside)
    elif category in ("medium", "subsurface"):
        shapes.append('<shape type="sphere">%s%s</shape>' % (DIFFUSE, element))
    elif category == "phase":
        shapes.append('<shape type="sphere">%s<medium type="homogeneous" name="interior">%s'
                      '</medium></shape>' % (DIFFUSE, element))
    elif category == "volume":
        shapes.append('<shape type="sphere">%s<medium type="heterogeneous" name="interior">%s'
                      '</medium></shape>' % (DIFFUSE, element))
    else:
        raise ValueError("no place for a %s" % category)
    if film is None:
        film = ('<film type="hdrfilm"><integer name="width" value="8"/>'
                '<integer name="height" value="8"/>%s</film>' % rfilter)
    shapes.insert(0, '<shape type="sphere"><float name="radius" value="0.5"/>%s</shape>' % DIFFUSE)
    lines = ['<scene version="0.6.0">', integrator,
             '<sensor type="%s">%s%s%s</sensor>' % (sensor_type, sensor_params, sampler, film),
             LIGHT_PLACE % light] + top + shapes + ["</scene>"]
    return "\n".join(lines) + "\n"
