"""The pieces every scene of the suite is made of: the open box of a room (floor, ceiling,
back wall, a red and a green side wall) lit by a small area light under the ceiling, the
camera, the integrator, the shapes and the BSDF and texture snippets the groups share."""

DIFFUSE = '<bsdf type="diffuse"><rgb name="reflectance" value="%s"/></bsdf>'
ROOM_LIGHT = """  <shape type="rectangle">
    <transform name="toWorld"><scale x="0.3" y="0.3"/><rotate x="1" angle="90"/><translate y="1.98"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
    <emitter type="area">%s</emitter>
  </shape>
"""
DEFAULT_RADIANCE = '<rgb name="radiance" value="18, 16, 12"/>'


def room(walls=True):
    """The open box: floor y=0, ceiling y=2, back wall z=-1, red x=-1, green x=+1."""
    if not walls:
        return ""
    pieces = [
        ("0.7, 0.7, 0.7", '<rotate x="1" angle="-90"/>'),                             # floor
        ("0.7, 0.7, 0.7", '<rotate x="1" angle="90"/><translate y="2"/>'),             # ceiling
        ("0.7, 0.7, 0.7", '<translate y="1" z="-1"/>'),                                # back
        ("0.6, 0.1, 0.08", '<rotate y="1" angle="90"/><translate x="-1" y="1"/>'),     # red
        ("0.12, 0.5, 0.1", '<rotate y="1" angle="-90"/><translate x="1" y="1"/>'),     # green
    ]
    return "".join('  <shape type="rectangle">\n    <transform name="toWorld">%s</transform>\n'
                   '    %s\n  </shape>\n' % (t, DIFFUSE % c) for c, t in pieces)


HDR_PFM = ('\n      <string name="pixelFormat" value="rgb"/>'
           '\n      <string name="fileFormat" value="pfm"/>')


def sensor(width=64, height=64, fov=50, fov_axis=None, transform=None, rfilter="box",
           rfilter_params="", kind="perspective", params=None, sampler="independent",
           film="hdrfilm", film_params=HDR_PFM):
    """The camera: a perspective one unless `kind` says otherwise; `params` replaces the
    fov (an orthographic camera has none), `film_params` the film's output format."""
    transform = transform or '<lookat origin="0, 1, 3.4" target="0, 0.9, 0" up="0, 1, 0"/>'
    axis = '\n    <string name="fovAxis" value="%s"/>' % fov_axis if fov_axis else ""
    if params is None:
        params = f'\n    <float name="fov" value="{fov}"/>{axis}'
    filt = ""
    if rfilter:
        filt = ('\n      <rfilter type="%s">%s</rfilter>' % (rfilter, rfilter_params) if rfilter_params
                else '\n      <rfilter type="%s"/>' % rfilter)
    return f"""  <sensor type="{kind}">{params}
    <transform name="toWorld">{transform}</transform>
    <sampler type="{sampler}"><integer name="sampleCount" value="$spp"/></sampler>
    <film type="{film}">
      <integer name="width" value="{width}"/>
      <integer name="height" value="{height}"/>{film_params}{filt}
    </film>
  </sensor>
"""


def integrator(kind="path", max_depth=6, rr_depth=None, hide_emitters=False, strict_normals=None):
    extra = '\n    <integer name="rrDepth" value="%d"/>' % rr_depth if rr_depth is not None else ""
    if hide_emitters:
        extra += '\n    <boolean name="hideEmitters" value="true"/>'
    if strict_normals is not None:
        extra += '\n    <boolean name="strictNormals" value="%s"/>' % str(strict_normals).lower()
    return (f'  <integrator type="{kind}">\n    <integer name="maxDepth" value="{max_depth}"/>'
            f'{extra}\n  </integrator>\n')


def scene(subject, light=None, walls=True, cam=None, integ=None):
    light = ROOM_LIGHT % DEFAULT_RADIANCE if light is None else light
    return ('<?xml version="1.0" encoding="utf-8"?>\n<!-- emlt conformance suite; written by '
            'tools/conformance/make_scenes.py -->\n<scene version="0.6.0">\n'
            '  <default name="spp" value="64"/>\n' + (integ or integrator()) +
            (cam or sensor()) + room(walls) + light + subject + "</scene>\n")


def point(name, xyz):
    """Mitsuba 0.6's <point> takes x, y and z attributes (no 'value')."""
    x, y, z = (v.strip() for v in xyz.split(","))
    return f'<point name="{name}" x="{x}" y="{y}" z="{z}"/>'


def sphere(bsdf, center="0, 0.55, 0", radius=0.55):
    return (f'  <shape type="sphere">\n    {point("center", center)}\n'
            f'    <float name="radius" value="{radius}"/>\n    {bsdf}\n  </shape>\n')


def rect(bsdf, transform, extra=""):
    return (f'  <shape type="rectangle">\n    <transform name="toWorld">{transform}</transform>\n'
            f'    {bsdf}{extra}\n  </shape>\n')


def obj(filename, bsdf, transform, params=""):
    return (f'  <shape type="obj">\n    <string name="filename" value="assets/{filename}"/>\n'
            f'{params}    <transform name="toWorld">{transform}</transform>\n    {bsdf}\n  </shape>\n')


WHITE = DIFFUSE % "0.75, 0.75, 0.75"
PANEL = '<scale x="0.6" y="0.6"/><translate y="0.8" z="-0.2"/>'  # faces the camera (+z)
TEXTURED = '<bsdf type="diffuse"><texture type="bitmap" name="reflectance">%s</texture></bsdf>'


def bitmap(file="grid.png", params=""):
    return f'<string name="filename" value="assets/{file}"/><string name="filterType" value="bilinear"/>{params}'
