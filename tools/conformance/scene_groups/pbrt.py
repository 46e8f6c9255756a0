"""pbrt-v4 scenes: each written twice, in pbrt-v4's format (NAME.pbrt, which emlt renders)
and as the same scene in Mitsuba 0.6 XML (NAME.xml, which Mitsuba renders as a reference).
pbrt-v4 itself renders NAME.pbrt as the second reference (suite.json's
"pbrt_v4_reference_spp", tools/conformance/render_pbrt_references.sh). Each scene would fail
if one of pbrt's conventions were read the Mitsuba way:

- pbrt-handedness: pbrt-v4 is left-handed, its camera looks down +z and LookAt puts
  up x dir on the image's right: looking down -z here, world -x is on the right. The scene
  is lopsided (a red ball at x = -0.5, on the image's right, beside the red wall; a white
  panel at x = +0.45), so a mirrored image fails. Its 64x40 film is wider than tall and
  pbrt's fov spans the shorter side: read on the x axis, the image would zoom out.
- pbrt-onesided: area lights emit on their front side only (pbrt's default). A panel whose
  front faces away from the camera, and one turned away by ReverseOrientation, must be
  black; a two-sided reading lights them.
- pbrt-maxdepth: maxdepth counts bounces (1: direct light only); Mitsuba's maxDepth counts
  edges (2 for the same). Off by one, the room is brighter or darker by far more than 1 %.
- pbrt-materials: diffuse, a rough conductor with pbrt's named copper spectra and remapped
  roughness (0.01, alpha = sqrt(roughness) = 0.1: read unremapped, the ball's blurred
  reflection of the room would be sharp), a smooth dielectric of eta 1.5 in a vacuum and a
  checkerboard of pbrt's scale (one check per unit of s).

The Mitsuba side states each convention explicitly: a camera mirrored in x (scale x=-1
before the lookat), fovAxis "smaller", one-sided emitters, maxDepth = maxdepth + 1, and
two-sided diffuse surfaces (pbrt's materials reflect on both sides).
"""

WIDTH, HEIGHT = 64, 40

ROOM = [  # (center, half-extent along u, half-extent along v, reflectance); front = u x v
    ((0, 0, 0), (1, 0, 0), (0, 0, -1), (0.7, 0.7, 0.7)),         # floor, faces +y
    ((0, 2, 0), (1, 0, 0), (0, 0, 1), (0.7, 0.7, 0.7)),          # ceiling, faces -y
    ((0, 1, -1), (1, 0, 0), (0, 1, 0), (0.7, 0.7, 0.7)),         # back wall, faces +z
    ((-1, 1, 0), (0, 0, -1), (0, 1, 0), (0.6, 0.1, 0.08)),       # left wall (x = -1), faces +x
    ((1, 1, 0), (0, 0, 1), (0, 1, 0), (0.12, 0.5, 0.1)),         # right wall (x = +1), faces -x
]
# The lamp is white (equal RGB): pbrt-v4 renders spectrally, and a coloured lamp's spectrum
# times a coloured wall's is not the product of their RGB values. With the earlier warm lamp
# (18, 16, 12) pbrt-v4's blue mean was 0.4-0.6 % below emlt's and Mitsuba's (RGB) images;
# white, the walls' colours still tell left from right and the difference is under 0.25 %.
LIGHT = ((0, 1.98, 0), (0.3, 0, 0), (0, 0, 0.3), (16, 16, 16))  # faces -y, down into the room
EYE, TARGET, UP = (0, 1, 3.4), (0, 0.9, 0), (0, 1, 0)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = sum(x * x for x in a) ** 0.5
    return tuple(x / n for x in a)


def fmt(values):
    return " ".join("%g" % v for v in values)


def corners(c, u, v):
    return [tuple(c[i] + su * u[i] + sv * v[i] for i in range(3))
            for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1))]


# --- pbrt-v4 ------------------------------------------------------------------------------

def pbrt_quad(c, u, v, reverse=False):
    """A trianglemesh over the quad; its winding faces u x v (uv as Mitsuba's rectangle)."""
    p = [x for corner in corners(c, u, v) for x in corner]
    return (("  ReverseOrientation\n" if reverse else "") +
            f'  Shape "trianglemesh" "point3 P" [{fmt(p)}] "integer indices" [0 1 2 0 2 3]\n'
            '    "point2 uv" [0 0 1 0 1 1 0 1]\n')


def pbrt_scene(body, maxdepth=5, light=True):
    room = "".join(f'AttributeBegin\n  Material "diffuse" "rgb reflectance" [{fmt(r)}]\n'
                   f"{pbrt_quad(c, u, v)}AttributeEnd\n" for c, u, v, r in ROOM)
    lamp = ""
    if light:
        c, u, v, L = LIGHT
        lamp = (f'AttributeBegin\n  Material "diffuse" "rgb reflectance" [0 0 0]\n'
                f'  AreaLightSource "diffuse" "rgb L" [{fmt(L)}]\n{pbrt_quad(c, u, v)}AttributeEnd\n')
    return (f"# emlt conformance suite (pbrt-v4); written by tools/conformance/make_scenes.py\n"
            f"LookAt {fmt(EYE)}  {fmt(TARGET)}  {fmt(UP)}\n"
            f'Camera "perspective" "float fov" 40\n'
            f'Film "rgb" "integer xresolution" {WIDTH} "integer yresolution" {HEIGHT}\n'
            f'  "string filename" "out.exr"\n'
            f'PixelFilter "box"\nSampler "independent" "integer pixelsamples" 64\n'
            f'Integrator "path" "integer maxdepth" {maxdepth}\n'
            f"WorldBegin\n{room}{lamp}{body}")


# --- Mitsuba 0.6 -------------------------------------------------------------------------

def xml_quad(c, u, v, bsdf, emitter=""):
    """Mitsuba's rectangle ([-1, 1]^2 at z = 0, facing +z) mapped onto the quad."""
    n = unit(cross(u, v))
    rows = [(u[i], v[i], n[i], c[i]) for i in range(3)] + [(0, 0, 0, 1)]
    matrix = fmt([x for row in rows for x in row])
    return (f'  <shape type="rectangle">\n    <transform name="toWorld"><matrix value="{matrix}"/>'
            f"</transform>\n    {bsdf}{emitter}\n  </shape>\n")


def diffuse_xml(r):
    """pbrt's diffuse reflects on both sides (a panel's back, lit by the walls, too)."""
    return (f'<bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" '
            f'value="{", ".join("%g" % x for x in r)}"/></bsdf></bsdf>')


def xml_scene(body, max_depth=6, light=True):
    room = "".join(xml_quad(c, u, v, diffuse_xml(r)) for c, u, v, r in ROOM)
    lamp = ""
    if light:
        c, u, v, L = LIGHT
        lamp = xml_quad(c, u, v, diffuse_xml((0, 0, 0)),
                        f'\n    <emitter type="area"><rgb name="radiance" value="{", ".join("%g" % x for x in L)}"/></emitter>')
    # pbrt's camera: its LookAt puts up x dir on the image's right, Mitsuba's on the left
    # (hence the mirror), and its fov spans the shorter side.
    o, t, up = (", ".join("%g" % x for x in p) for p in (EYE, TARGET, UP))
    return f"""<?xml version="1.0" encoding="utf-8"?>
<!-- emlt conformance suite: the Mitsuba twin of the pbrt-v4 scene beside it; written by tools/conformance/make_scenes.py -->
<scene version="0.6.0">
  <default name="spp" value="64"/>
  <integrator type="path">
    <integer name="maxDepth" value="{max_depth}"/>
  </integrator>
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <string name="fovAxis" value="smaller"/>
    <transform name="toWorld"><scale x="-1"/><lookat origin="{o}" target="{t}" up="{up}"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="$spp"/></sampler>
    <film type="hdrfilm">
      <integer name="width" value="{WIDTH}"/>
      <integer name="height" value="{HEIGHT}"/>
      <string name="pixelFormat" value="rgb"/>
      <string name="fileFormat" value="pfm"/>
      <rfilter type="box"/>
    </film>
  </sensor>
{room}{lamp}{body}</scene>
"""


# --- the scenes --------------------------------------------------------------------------

def handedness():
    ball_c, ball_r = (-0.5, 0.3, 0.1), 0.3
    box = [((0.45, 0.6, -0.3), (0.2, 0, 0), (0, 0.6, 0))]  # a tall panel on the right, facing +z
    pbrt = (f'AttributeBegin\n  Material "diffuse" "rgb reflectance" [0.8 0.15 0.1]\n'
            f'  Translate {fmt(ball_c)}\n  Shape "sphere" "float radius" {ball_r}\nAttributeEnd\n' +
            "".join(f'AttributeBegin\n  Material "diffuse" "rgb reflectance" [0.9 0.9 0.9]\n'
                    f"{pbrt_quad(c, u, v)}AttributeEnd\n" for c, u, v in box))
    xml = (f'  <shape type="sphere">\n    <point name="center" x="{ball_c[0]}" y="{ball_c[1]}" z="{ball_c[2]}"/>\n'
           f'    <float name="radius" value="{ball_r}"/>\n    {diffuse_xml((0.8, 0.15, 0.1))}\n  </shape>\n' +
           "".join(xml_quad(c, u, v, diffuse_xml((0.9, 0.9, 0.9))) for c, u, v in box))
    return pbrt_scene(pbrt), xml_scene(xml)


def one_sided():
    # Three small lamps in view: the first faces the camera (+z); the second faces away
    # (-z); the third is written facing the camera but turned away by ReverseOrientation.
    lamps = [((-0.55, 1.2, 0), (0.15, 0, 0), (0, 0.15, 0), False),
             ((0.0, 1.2, 0), (-0.15, 0, 0), (0, 0.15, 0), False),
             ((0.55, 1.2, 0), (0.15, 0, 0), (0, 0.15, 0), True)]
    L = (4, 4, 4)
    pbrt = "".join(f'AttributeBegin\n  Material "diffuse" "rgb reflectance" [0 0 0]\n'
                   f'  AreaLightSource "diffuse" "rgb L" [{fmt(L)}]\n{pbrt_quad(c, u, v, rev)}AttributeEnd\n'
                   for c, u, v, rev in lamps)
    emitter = f'\n    <emitter type="area"><rgb name="radiance" value="{", ".join("%g" % x for x in L)}"/></emitter>'
    xml = "".join(xml_quad(c, (-u[0], u[1], u[2]) if rev else u, v, diffuse_xml((0, 0, 0)), emitter)
                  for c, u, v, rev in lamps)
    return pbrt_scene(pbrt), xml_scene(xml)


def max_depth():
    ball = 'AttributeBegin\n  Material "diffuse" "rgb reflectance" [0.75 0.75 0.75]\n  Translate 0 0.55 0\n  Shape "sphere" "float radius" 0.55\nAttributeEnd\n'
    xml = (f'  <shape type="sphere">\n    <point name="center" x="0" y="0.55" z="0"/>\n'
           f'    <float name="radius" value="0.55"/>\n    {diffuse_xml((0.75, 0.75, 0.75))}\n  </shape>\n')
    return pbrt_scene(ball, maxdepth=2), xml_scene(xml, max_depth=3)


def materials():
    pbrt = """AttributeBegin
  Material "conductor" "spectrum eta" "metal-Cu-eta" "spectrum k" "metal-Cu-k" "float roughness" 0.01
  Translate -0.45 0.4 -0.1
  Shape "sphere" "float radius" 0.4
AttributeEnd
AttributeBegin
  Material "dielectric" "float eta" 1.5
  Translate 0.5 0.3 0.35
  Shape "sphere" "float radius" 0.3
AttributeEnd
AttributeBegin
  Texture "checks" "spectrum" "checkerboard" "float uscale" 4 "float vscale" 4
    "rgb tex1" [0.8 0.8 0.8] "rgb tex2" [0.1 0.1 0.4]
  Material "diffuse" "texture reflectance" "checks"
""" + pbrt_quad((0, 1.1, -0.95), (0.5, 0, 0), (0, 0.5, 0)) + "AttributeEnd\n"
    checks = ('<bsdf type="twosided"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance">'
              '<rgb name="color0" value="0.8, 0.8, 0.8"/><rgb name="color1" value="0.1, 0.1, 0.4"/>'
              '<float name="uscale" value="2"/><float name="vscale" value="2"/></texture></bsdf></bsdf>')
    xml = ("""  <shape type="sphere">
    <point name="center" x="-0.45" y="0.4" z="-0.1"/>
    <float name="radius" value="0.4"/>
    <bsdf type="roughconductor"><string name="distribution" value="ggx"/><string name="material" value="Cu"/><float name="alpha" value="0.1"/><float name="extEta" value="1"/></bsdf>
  </shape>
  <shape type="sphere">
    <point name="center" x="0.5" y="0.3" z="0.35"/>
    <float name="radius" value="0.3"/>
    <bsdf type="dielectric"><float name="intIOR" value="1.5"/><float name="extIOR" value="1"/></bsdf>
  </shape>
""" + xml_quad((0, 1.1, -0.95), (0.5, 0, 0), (0, 0.5, 0), checks))
    return pbrt_scene(pbrt), xml_scene(xml)


SCENES = {
    "pbrt-handedness": ("pbrt-v4: left-handed camera (world +x on the image's right), fov on the shorter side", handedness),
    "pbrt-onesided": ("pbrt-v4: area lights one-sided, ReverseOrientation turns them", one_sided),
    "pbrt-maxdepth": ("pbrt-v4: maxdepth 2 counts bounces (Mitsuba's maxDepth 3)", max_depth),
    "pbrt-materials": ("pbrt-v4: conductor (metal-Cu, roughness 0.01 remapped to alpha 0.1), dielectric, checkerboard", materials),
}


def add_scenes(s):
    """Adds the group's Mitsuba twins to `s` (name -> (convention, xml, integrators))."""
    for name, (convention, make) in SCENES.items():
        s[name] = (convention, make()[1], ["pt"])


def add_pbrt_scenes(p):
    """Adds the pbrt-v4 files emlt renders: name -> text."""
    for name, (_, make) in SCENES.items():
        p[name] = make()[0]
