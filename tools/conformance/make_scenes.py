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
import math
import os
import shutil
import struct
import subprocess
import sys
import zlib

from tools import ROOT
from tools.scenes.make_textured_room import write_png  # 8-bit RGB PNG, standard library

SUITE = os.path.join(ROOT, "tests", "conformance")
SCENES = os.path.join(SUITE, "scenes")
ASSETS = os.path.join(SCENES, "assets")

# ---------------------------------------------------------------------------------------
# Assets


def write_exr(path, width, height, rgb):
    """An uncompressed scanline OpenEXR file of 32-bit float R, G, B (rows top first)."""
    def attribute(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value

    channels = b"".join(c + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in (b"B", b"G", b"R"))
    window = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = (b"\x76\x2f\x31\x01" + struct.pack("<i", 2) +
              attribute("channels", "chlist", channels + b"\0") +
              attribute("compression", "compression", b"\0") +
              attribute("dataWindow", "box2i", window) +
              attribute("displayWindow", "box2i", window) +
              attribute("lineOrder", "lineOrder", b"\0") +
              attribute("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0)) +
              attribute("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    line_bytes = 3 * 4 * width
    first = len(header) + 8 * height
    table = b"".join(struct.pack("<Q", first + y * (8 + line_bytes)) for y in range(height))
    lines = []
    for y, row in enumerate(rgb):
        data = b"".join(struct.pack("<%df" % width, *(px[c] for px in row)) for c in (2, 1, 0))
        lines.append(struct.pack("<ii", y, line_bytes) + data)
    with open(path, "wb") as f:
        f.write(header + table + b"".join(lines))


def colour_grid(width, height):
    """An asymmetric colour pattern (so flips and offsets show), values in [0, 1]."""
    rows = []
    for y in range(height):
        row = []
        for x in range(width):
            r = 0.15 + 0.8 * x / (width - 1)
            g = 0.15 + 0.7 * (1 - y / (height - 1))
            b = 0.9 if (x // 4 + y // 4) % 2 == 0 else 0.1
            if x < width // 4 and y < height // 4:  # a marker in the top left corner
                r, g, b = 0.95, 0.95, 0.2
            row.append((r, g, b))
        rows.append(row)
    return rows


def to_bytes(rows):
    return [[tuple(int(round(255 * c)) for c in px) for px in row] for row in rows]


def write_png_chunks(path, width, height, rows, bits=8, gama=None, srgb=False):
    """An RGB PNG of `bits`-bit samples (rows of integer triples, or quadruples for RGBA;
    row 0 at the top), with a gAMA chunk (the file gamma, e.g. 1.0 or 1 / 2.2) and/or an
    sRGB chunk when asked."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    sample = ">H" if bits == 16 else ">B"
    raw = b"".join(b"\x00" + b"".join(struct.pack(sample, v) for px in row for v in px)
                   for row in rows)
    extra = b""
    if srgb:
        extra += chunk(b"sRGB", b"\x00")
    if gama is not None:
        extra += chunk(b"gAMA", struct.pack(">I", int(round(gama * 100000))))
    with open(path, "wb") as f:
        colour_type = 6 if len(rows[0][0]) == 4 else 2
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bits, colour_type, 0, 0, 0)) +
                extra + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def write_jpeg(path, width, height, pixels, options):
    """Encodes rows of byte triples with cjpeg (its `options`), and writes libjpeg's default
    decode of the result to `path` + ".ppm"."""
    for tool in ("cjpeg", "djpeg"):
        if not shutil.which(tool):
            sys.exit(f"make_scenes: {tool} not found (apt-get install libjpeg-turbo-progs)")
    ppm = b"P6\n%d %d\n255\n" % (width, height) + bytes(v for row in pixels for px in row for v in px)
    jpeg = subprocess.run(["cjpeg", *options], input=ppm, capture_output=True, check=True).stdout
    with open(path, "wb") as f:
        f.write(jpeg)
    decoded = subprocess.run(["djpeg", "-pnm", path], capture_output=True, check=True).stdout
    with open(path + ".ppm", "wb") as f:
        f.write(decoded)


def write_obj(path, positions, normals, uvs, faces):
    """faces: lists of 1-based vertex indices (shared by v, vt and vn where present)."""
    with open(path, "w") as f:
        for p in positions:
            f.write("v %g %g %g\n" % p)
        for t in uvs:
            f.write("vt %g %g\n" % t)
        for n in normals:
            f.write("vn %g %g %g\n" % n)
        for face in faces:
            if normals and uvs:
                f.write("f " + " ".join("%d/%d/%d" % (i, i, i) for i in face) + "\n")
            elif normals:
                f.write("f " + " ".join("%d//%d" % (i, i) for i in face) + "\n")
            elif uvs:
                f.write("f " + " ".join("%d/%d" % (i, i) for i in face) + "\n")
            else:
                f.write("f " + " ".join(str(i) for i in face) + "\n")


def write_serialized(path, meshes):
    """Mitsuba's serialized mesh format, version 4, single precision; each mesh is
    (name, positions, normals or None, uvs or None, triangles)."""
    offsets = []
    body = b""
    for name, positions, normals, uvs, triangles in meshes:
        flags = 0x1000  # single precision
        if normals:
            flags |= 0x0001
        if uvs:
            flags |= 0x0002
        payload = struct.pack("<I", flags) + name.encode() + b"\0"
        payload += struct.pack("<QQ", len(positions), len(triangles))
        payload += b"".join(struct.pack("<fff", *p) for p in positions)
        if normals:
            payload += b"".join(struct.pack("<fff", *n) for n in normals)
        if uvs:
            payload += b"".join(struct.pack("<ff", *t) for t in uvs)
        payload += b"".join(struct.pack("<III", *t) for t in triangles)
        offsets.append(len(body))
        body += struct.pack("<HH", 0x041C, 4) + zlib.compress(payload, 9)
    body += b"".join(struct.pack("<Q", o) for o in offsets) + struct.pack("<I", len(meshes))
    with open(path, "wb") as f:
        f.write(body)


def write_ply(path, positions, normals, faces, binary, colors=None, color_type="uchar"):
    """colors: one (r, g, b) per vertex, stored as color_type (uchar 0..255 or float)."""
    header = ["ply", "format %s 1.0" % ("binary_little_endian" if binary else "ascii"),
              "comment emlt conformance asset", "element vertex %d" % len(positions),
              "property float x", "property float y", "property float z"]
    if normals:
        header += ["property float nx", "property float ny", "property float nz"]
    if colors:
        header += ["property %s %s" % (color_type, c) for c in ("red", "green", "blue")]
    header += ["element face %d" % len(faces), "property list uchar int vertex_indices",
               "end_header"]
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode())
        for i, p in enumerate(positions):
            values = list(p) + (list(normals[i]) if normals else [])
            if binary:
                f.write(struct.pack("<%df" % len(values), *values))
                if colors:
                    f.write(struct.pack("<3B" if color_type == "uchar" else "<3f", *colors[i]))
            else:
                if colors:
                    values += list(colors[i])
                f.write((" ".join("%g" % v for v in values) + "\n").encode())
        for face in faces:
            if binary:
                f.write(struct.pack("<B%di" % len(face), len(face), *face))
            else:
                f.write((" ".join(str(v) for v in [len(face)] + list(face)) + "\n").encode())


def uv_sphere(rings=12, segments=16):
    positions, normals, triangles = [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            positions.append(n)
            normals.append(n)
    row = segments + 1
    for r in range(rings):
        for s in range(segments):
            a, b = r * row + s, r * row + s + 1
            c, d = a + row, b + row
            if r != 0:
                triangles.append((a, b, c))
            if r != rings - 1:
                triangles.append((b, d, c))
    return positions, normals, triangles


def write_assets():
    os.makedirs(ASSETS, exist_ok=True)
    grid = colour_grid(32, 32)
    write_png(os.path.join(ASSETS, "grid.png"), 32, 32, to_bytes(grid))
    # PNG's own curve (Mitsuba reads the gAMA chunk unless an sRGB chunk is there) and
    # 16-bit samples. The exponent 1.5 is far enough from sRGB's curve (a mid grey 0.5 is
    # 0.35 against 0.21) for a render to tell them apart; 2.2 would be too close to it.
    grid8 = to_bytes(grid)
    write_png_chunks(os.path.join(ASSETS, "grid-gama1.png"), 32, 32, grid8, gama=1.0)
    write_png_chunks(os.path.join(ASSETS, "grid-gama15.png"), 32, 32, grid8, gama=1 / 1.5)
    write_png_chunks(os.path.join(ASSETS, "grid-srgb-gama15.png"), 32, 32, grid8, gama=1 / 1.5,
                     srgb=True)
    # The colour grid with the holes pattern as its alpha channel (for bitmap `channel`).
    write_png_chunks(os.path.join(ASSETS, "grid-alpha.png"), 32, 32,
                     [[px + (0 if ((x // 8) + (y // 8)) % 2 else 255,) for x, px in enumerate(row)]
                      for y, row in enumerate(grid8)])
    write_png_chunks(os.path.join(ASSETS, "grid16.png"), 32, 32,
                     [[tuple(int(round(65535 * c)) for c in px) for px in row] for row in grid],
                     bits=16)
    # Baseline with 2x2 chroma subsampling (cjpeg's default), and a progressive grey file.
    write_jpeg(os.path.join(ASSETS, "grid.jpg"), 32, 32, to_bytes(grid), ["-quality", "90"])
    write_jpeg(os.path.join(ASSETS, "grid-grey.jpg"), 32, 32, to_bytes(grid),
               ["-quality", "90", "-grayscale", "-progressive"])
    write_exr(os.path.join(ASSETS, "grid.exr"), 32, 32, grid)
    heights = [[(0.5 + 0.5 * math.sin(2 * math.pi * x / 8) * math.sin(2 * math.pi * y / 8),) * 3
                for x in range(32)] for y in range(32)]
    write_png(os.path.join(ASSETS, "bumps.png"), 32, 32, to_bytes(heights))
    holes = [[(0.0,) * 3 if ((x // 8) + (y // 8)) % 2 else (1.0,) * 3 for x in range(32)]
             for y in range(32)]
    write_png(os.path.join(ASSETS, "holes.png"), 32, 32, to_bytes(holes))
    # A tangent-space normal map (RGB = (n + 1) / 2, read with gamma 1): dimples tilting
    # the normal up to about 35 degrees along both uv axes, so that the light from above
    # shades the panel unevenly.
    normals = []
    for y in range(32):
        row = []
        for x in range(32):
            nx = 0.7 * math.sin(2 * math.pi * x / 16)
            ny = 0.5 * math.cos(2 * math.pi * y / 16)
            length = math.sqrt(nx * nx + ny * ny + 1.0)
            row.append(tuple(0.5 * (c / length) + 0.5 for c in (nx, ny, 1.0)))
        normals.append(row)
    write_png(os.path.join(ASSETS, "normals.png"), 32, 32, to_bytes(normals))
    # A lat-long environment: a bright warm blob above the horizon on one side, a blue sky
    # gradient, a dark ground; asymmetric so that a rotation shows.
    env = []
    for y in range(32):
        row = []
        for x in range(64):
            theta = math.pi * (y + 0.5) / 32
            phi = 2 * math.pi * (x + 0.5) / 64
            up = math.cos(theta)
            sky = (0.2 + 0.3 * max(up, 0), 0.3 + 0.4 * max(up, 0), 0.6 + 0.6 * max(up, 0))
            if up < 0:
                sky = (0.08, 0.06, 0.04)
            d = (phi - 1.2) ** 2 + (theta - 1.0) ** 2
            if d < 0.08:
                sky = (12.0, 9.0, 5.0)
            row.append(sky)
        env.append(row)
    write_exr(os.path.join(ASSETS, "sky.exr"), 64, 32, env)

    # The door scene's lamp: a quad wound to face up (+y) whose vertex normals face down.
    quad = [(-1, 0, -1), (-1, 0, 1), (1, 0, 1), (1, 0, -1)]
    wound_up = [(1, 2, 3, 4)]  # (p2-p1) x (p3-p1) = (0,0,2) x (2,0,2) = +y
    write_obj(os.path.join(ASSETS, "lamp_normals_down.obj"), quad, [(0, -1, 0)] * 4, [], wound_up)
    # A textured quad in the xy plane facing +z, with uvs (v up in the file).
    panel = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    write_obj(os.path.join(ASSETS, "panel_uv.obj"), panel, [], [(0, 0), (1, 0), (1, 1), (0, 1)],
              [(1, 2, 3, 4)])
    # The same quad facing +z by winding, with vertex normals facing -z.
    write_obj(os.path.join(ASSETS, "panel_normals_back.obj"), panel, [(0, 0, -1)] * 4, [],
              [(1, 2, 3, 4)])
    sphere_p, sphere_n, sphere_t = uv_sphere()
    write_serialized(os.path.join(ASSETS, "shapes.serialized"), [
        ("quad", [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], None, None, [(0, 1, 2), (0, 2, 3)]),
        ("ball", sphere_p, sphere_n, None, sphere_t),
    ])
    write_ply(os.path.join(ASSETS, "ball_ascii.ply"), sphere_p, sphere_n,
              [t for t in sphere_t], binary=False)
    # A panel whose vertex normals lean 60 degrees off its face towards +x (strictNormals):
    # directions below the panel but above its shading plane are where the modes differ.
    lean = (math.sin(math.radians(60)), 0, math.cos(math.radians(60)))
    write_obj(os.path.join(ASSETS, "panel_normals_lean.obj"), panel, [lean] * 4, [], [(1, 2, 3, 4)])
    # Vertex colours: a quad fanned about its centre, a different colour at every corner
    # (8-bit, binary, sRGB-encoded by default), and the same geometry with float colours
    # (ASCII, read as linear with srgb false).
    fan = [(0, 0, 0), (-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    fan_faces = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 1)]
    write_ply(os.path.join(ASSETS, "quad_colors_uchar.ply"), fan, None, fan_faces, binary=True,
              colors=[(200, 200, 200), (230, 20, 20), (20, 200, 30), (30, 40, 220), (240, 220, 10)])
    write_ply(os.path.join(ASSETS, "quad_colors_float.ply"), fan, None, fan_faces, binary=False,
              colors=[(0.05, 0.05, 0.05), (0.9, 0.6, 0.1), (0.1, 0.8, 0.8), (0.7, 0.1, 0.6), (0.3, 0.3, 0.9)],
              color_type="float")
    prism = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1), (0, 1.5, 0)]
    write_ply(os.path.join(ASSETS, "pyramid_binary.ply"), prism, None,
              [(0, 1, 2, 3), (0, 4, 1), (1, 4, 2), (2, 4, 3), (3, 4, 0)], binary=True)


# ---------------------------------------------------------------------------------------
# Scenes

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


def build():
    s = {}  # name -> (convention, xml, integrators)
    pt_bdpt = ["pt", "bdpt"]

    # --- orientation
    s["orient-obj-emitter"] = ("OBJ emitter oriented by its vertex normals (down), not its winding (up)",
        scene("", light=obj("lamp_normals_down.obj", DIFFUSE % "0",
                            '<scale x="0.3" z="0.3"/><translate y="1.98"/>',
                            "") .replace("</shape>", "<emitter type=\"area\">%s</emitter>\n  </shape>" % DEFAULT_RADIANCE)
              + sphere(WHITE)), pt_bdpt + ["mlt"])
    s["orient-facenormals"] = ("faceNormals: the same lamp oriented by its winding (emits up)",
        scene("", light=obj("lamp_normals_down.obj", DIFFUSE % "0",
                            '<scale x="0.3" z="0.3"/><translate y="1.7"/>',
                            '    <boolean name="faceNormals" value="true"/>\n')
              .replace("</shape>", "<emitter type=\"area\">%s</emitter>\n  </shape>" % DEFAULT_RADIANCE)
              + sphere(WHITE)), pt_bdpt)
    s["orient-flipnormals"] = ("flipNormals on a rectangle emitter (faces down) and on an OBJ with normals",
        scene(obj("panel_normals_back.obj", '<bsdf type="diffuse"/>', PANEL,
                  '    <boolean name="flipNormals" value="true"/>\n'),
              light=ROOM_LIGHT.replace('<rotate x="1" angle="90"/>', '<rotate x="1" angle="-90"/>')
              .replace("</emitter>", "</emitter>\n    <boolean name=\"flipNormals\" value=\"true\"/>")
              % DEFAULT_RADIANCE), pt_bdpt)
    s["orient-onesided-back"] = ("a one-sided diffuse panel seen from its back is black",
        scene(rect(DIFFUSE % "0.8, 0.8, 0.8", '<scale x="0.6" y="0.6"/><rotate y="1" angle="180"/>'
                   '<translate y="0.8" z="-0.2"/>')), pt_bdpt)
    s["orient-twosided"] = ("twosided makes the back of a panel reflect like its front",
        scene(rect('<bsdf type="twosided">' + DIFFUSE % "0.8, 0.8, 0.8" + "</bsdf>",
                   '<scale x="0.6" y="0.6"/><rotate y="1" angle="180"/><translate y="0.8" z="-0.2"/>')),
        pt_bdpt)
    s["orient-obj-normals-back"] = ("an OBJ panel whose vertex normals face away is its back side",
        scene(obj("panel_normals_back.obj", DIFFUSE % "0.8, 0.8, 0.8", PANEL)), pt_bdpt)

    # --- depth
    for depth in (1, 2, 3, 8):
        s[f"depth-{depth}"] = (f"maxDepth {depth}", scene(sphere(WHITE), integ=integrator(max_depth=depth)),
                               pt_bdpt + ["mlt"])
    s["depth-unbounded"] = ("maxDepth -1 (Russian roulette from rrDepth 5)",
                            scene(sphere(WHITE), integ=integrator(max_depth=-1)), pt_bdpt + ["mlt"])
    s["depth-rr1"] = ("rrDepth 1 changes no expectation", scene(sphere(WHITE), integ=integrator(max_depth=-1, rr_depth=1)),
                      pt_bdpt + ["mlt"])

    # --- BSDFs
    bsdfs = {
        "bsdf-plastic": ("plastic", '<bsdf type="plastic"><rgb name="diffuseReflectance" value="0.6, 0.15, 0.1"/>'
                         '<float name="intIOR" value="1.5"/></bsdf>'),
        "bsdf-roughplastic": ("roughplastic, beckmann, nonlinear false",
                              '<bsdf type="roughplastic"><string name="distribution" value="beckmann"/>'
                              '<float name="alpha" value="0.2"/><rgb name="diffuseReflectance" value="0.1, 0.3, 0.6"/></bsdf>'),
        "bsdf-roughplastic-nonlinear": ("roughplastic, ggx, nonlinear true",
                                        '<bsdf type="roughplastic"><string name="distribution" value="ggx"/>'
                                        '<float name="alpha" value="0.3"/><boolean name="nonlinear" value="true"/>'
                                        '<rgb name="diffuseReflectance" value="0.1, 0.5, 0.2"/></bsdf>'),
        "bsdf-conductor-cu": ("conductor, named material Cu", '<bsdf type="conductor"><string name="material" value="Cu"/></bsdf>'),
        "bsdf-roughconductor-beckmann": ("roughconductor, beckmann, Au, alpha 0.2",
                                         '<bsdf type="roughconductor"><string name="material" value="Au"/>'
                                         '<float name="alpha" value="0.2"/></bsdf>'),
        "bsdf-roughconductor-ggx": ("roughconductor, ggx, Al, specularReflectance",
                                    '<bsdf type="roughconductor"><string name="distribution" value="ggx"/>'
                                    '<string name="material" value="Al"/><float name="alpha" value="0.3"/>'
                                    '<rgb name="specularReflectance" value="0.9, 0.8, 0.5"/></bsdf>'),
        "bsdf-roughconductor-phong": ("roughconductor, phong distribution",
                                      '<bsdf type="roughconductor"><string name="distribution" value="phong"/>'
                                      '<string name="material" value="Cu"/><float name="alpha" value="0.25"/></bsdf>'),
        "bsdf-roughconductor-aniso": ("roughconductor, ggx, alphaU and alphaV",
                                      '<bsdf type="roughconductor"><string name="distribution" value="ggx"/>'
                                      '<string name="material" value="Ag"/><float name="alphaU" value="0.05"/>'
                                      '<float name="alphaV" value="0.4"/></bsdf>'),
        "bsdf-dielectric": ("dielectric, intIOR 1.5", '<bsdf type="dielectric"><float name="intIOR" value="1.5"/></bsdf>'),
        "bsdf-roughdielectric": ("roughdielectric, beckmann alpha 0.15",
                                 '<bsdf type="roughdielectric"><float name="alpha" value="0.15"/>'
                                 '<string name="intIOR" value="bk7"/></bsdf>'),
        "bsdf-thindielectric": ("thindielectric", '<bsdf type="thindielectric"><float name="intIOR" value="1.5"/></bsdf>'),
    }
    bsdfs["bsdf-roughdielectric-aniso"] = ("roughdielectric, ggx, alphaU 0.08 and alphaV 0.35",
                                           '<bsdf type="roughdielectric"><string name="distribution" value="ggx"/>'
                                           '<float name="alphaU" value="0.08"/><float name="alphaV" value="0.35"/></bsdf>')
    bsdfs["bsdf-roughdielectric-phong"] = ("roughdielectric, phong, alpha 0.2",
                                           '<bsdf type="roughdielectric"><string name="distribution" value="phong"/>'
                                           '<float name="alpha" value="0.2"/></bsdf>')
    for name, (conv, bsdf) in bsdfs.items():
        s[name] = (conv, scene(sphere(bsdf)), pt_bdpt + (["mlt"] if name == "bsdf-dielectric" else []))
    # Textured specular tints of the dielectrics (Mitsuba reads numbers or textures): a
    # smooth and a rough glass sphere whose transmittance follows a checkerboard.
    tint = ('<texture type="checkerboard" name="specularTransmittance">'
            '<rgb name="color0" value="1, 0.6, 0.3"/><rgb name="color1" value="0.3, 0.6, 1"/>'
            '<float name="uscale" value="4"/><float name="vscale" value="2"/></texture>')
    s["bsdf-specular-tint-texture"] = (
        "checkerboard specularTransmittance of a dielectric and a roughdielectric",
        scene(sphere('<bsdf type="dielectric">' + tint + '</bsdf>', "-0.45, 0.4, 0", 0.4) +
              sphere('<bsdf type="roughdielectric"><float name="alpha" value="0.2"/>' + tint + '</bsdf>',
                     "0.45, 0.4, -0.1", 0.4)), ["pt"])
    # ensureEnergyConservation: reflectances above 1 scaled to 0.99 of their maximum, each
    # parameter on its own (a plastic's diffuse part here, not its specular one).
    s["bsdf-energy-conservation"] = (
        "reflectances above 1 scaled to 0.99 over their maximum (diffuse 1.6, plastic diffuse 1.3)",
        scene(sphere(DIFFUSE % "1.6, 0.8, 0.4", "-0.45, 0.4, 0", 0.4) +
              sphere('<bsdf type="plastic"><rgb name="diffuseReflectance" value="1.3, 1, 0.5"/></bsdf>',
                     "0.45, 0.4, -0.1", 0.4)), ["pt"])
    # The classic analytic BRDFs Mitsuba 0.6 ships beside the microfacet ones, on the sphere
    # (every pair of angles at once). Oren-Nayar is rough enough here to differ from a
    # Lambertian by 10-20 % in its brightest and darkest parts.
    classic = {
        "bsdf-roughdiffuse": ("roughdiffuse (Oren-Nayar, full model), alpha 0.7",
            '<bsdf type="roughdiffuse"><rgb name="reflectance" value="0.75, 0.5, 0.3"/>'
            '<float name="alpha" value="0.7"/></bsdf>'),
        "bsdf-roughdiffuse-fast": ("roughdiffuse, useFastApprox, alpha 0.9, reflectance named diffuseReflectance",
            '<bsdf type="roughdiffuse"><rgb name="diffuseReflectance" value="0.3, 0.6, 0.7"/>'
            '<float name="alpha" value="0.9"/><boolean name="useFastApprox" value="true"/></bsdf>'),
        "bsdf-roughdiffuse-texture": ("roughdiffuse, checkerboard alpha (0.05 and 1.2) and reflectance",
            '<bsdf type="roughdiffuse">'
            '<texture type="checkerboard" name="reflectance"><rgb name="color0" value="0.8, 0.7, 0.2"/>'
            '<rgb name="color1" value="0.2, 0.4, 0.8"/><float name="uscale" value="4"/><float name="vscale" value="2"/></texture>'
            '<texture type="checkerboard" name="alpha"><spectrum name="color0" value="0.05"/><spectrum name="color1" value="1.2"/>'
            '<float name="uscale" value="6"/><float name="vscale" value="3"/></texture></bsdf>'),
        "bsdf-phong": ("phong, exponent 40, specularReflectance and diffuseReflectance",
            '<bsdf type="phong"><float name="exponent" value="40"/><rgb name="specularReflectance" value="0.4, 0.35, 0.3"/>'
            '<rgb name="diffuseReflectance" value="0.2, 0.3, 0.5"/></bsdf>'),
        "bsdf-phong-defaults": ("phong defaults (exponent 30, specular 0.2, diffuse 0.5)", '<bsdf type="phong"/>'),
        "bsdf-phong-energy": ("phong whose reflectances sum above 1 (scaled to 0.99 of their largest sum)",
            '<bsdf type="phong"><float name="exponent" value="10"/><spectrum name="specularReflectance" value="0.6"/>'
            '<rgb name="diffuseReflectance" value="0.8, 0.5, 0.3"/></bsdf>'),
        "bsdf-phong-texture": ("phong, checkerboard exponent (5 and 200) and diffuseReflectance",
            '<bsdf type="phong">'
            '<texture type="checkerboard" name="exponent"><spectrum name="color0" value="5"/><spectrum name="color1" value="200"/>'
            '<float name="uscale" value="6"/><float name="vscale" value="3"/></texture>'
            '<texture type="checkerboard" name="diffuseReflectance"><rgb name="color0" value="0.6, 0.2, 0.1"/>'
            '<rgb name="color1" value="0.1, 0.3, 0.5"/><float name="uscale" value="4"/><float name="vscale" value="2"/></texture>'
            '<spectrum name="specularReflectance" value="0.3"/></bsdf>'),
        "bsdf-ward": ("ward, balanced (the default), alphaU 0.05 and alphaV 0.3 along the sphere's dp/du",
            '<bsdf type="ward"><float name="alphaU" value="0.05"/><float name="alphaV" value="0.3"/>'
            '<rgb name="specularReflectance" value="0.5, 0.45, 0.4"/><rgb name="diffuseReflectance" value="0.15, 0.2, 0.3"/></bsdf>'),
        "bsdf-ward-original": ("ward, variant ward (Ward's own normalisation), alpha 0.15",
            '<bsdf type="ward"><string name="variant" value="ward"/><float name="alpha" value="0.15"/>'
            '<spectrum name="specularReflectance" value="0.4"/><rgb name="diffuseReflectance" value="0.4, 0.2, 0.1"/></bsdf>'),
        "bsdf-ward-duer": ("ward, variant ward-duer, alpha 0.2, default reflectances",
            '<bsdf type="ward"><string name="variant" value="ward-duer"/><float name="alpha" value="0.2"/></bsdf>'),
        "bsdf-ward-texture": ("ward, checkerboard alphaU (0.03 and 0.4), alphaV from alpha 0.1, checkerboard diffuseReflectance",
            '<bsdf type="ward"><float name="alpha" value="0.1"/>'
            '<texture type="checkerboard" name="alphaU"><spectrum name="color0" value="0.03"/><spectrum name="color1" value="0.4"/>'
            '<float name="uscale" value="6"/><float name="vscale" value="3"/></texture>'
            '<texture type="checkerboard" name="diffuseReflectance"><rgb name="color0" value="0.5, 0.3, 0.1"/>'
            '<rgb name="color1" value="0.1, 0.2, 0.5"/><float name="uscale" value="4"/><float name="vscale" value="2"/></texture>'
            '<spectrum name="specularReflectance" value="0.35"/></bsdf>'),
        "bsdf-difftrans": ("difftrans: a sphere letting light through both its sides diffusely",
            '<bsdf type="difftrans"><rgb name="transmittance" value="0.8, 0.6, 0.3"/></bsdf>'),
    }
    for name, (conv, bsdf) in classic.items():
        s[name] = (conv, scene(sphere(bsdf)), pt_bdpt + ["mlt"])
    # A diffuser under the lamp: the room is lit only through it, and it is seen from below.
    s["bsdf-difftrans-diffuser"] = ("difftrans: a checkerboard diffuseTransmittance panel under the lamp lights the room",
        scene(sphere(WHITE) + rect('<bsdf type="difftrans"><texture type="checkerboard" name="diffuseTransmittance">'
                                   '<rgb name="color0" value="0.9, 0.8, 0.6"/><rgb name="color1" value="0.3, 0.5, 0.9"/>'
                                   '<float name="uscale" value="2"/><float name="vscale" value="2"/></texture></bsdf>',
                                   '<scale x="0.45" y="0.45"/><rotate x="1" angle="90"/><translate y="1.8"/>')),
        pt_bdpt + ["mlt"])
    # Weighted sums of BSDFs. The mixture's weights sum above 1 and are divided by their sum
    # (ensureEnergyConservation); the second sphere keeps its weights and mixes in a delta
    # lobe. The blend's weight is a number on the sphere and a bitmap's channel mean on the
    # panel, between a diffuse and a smooth gold mirror.
    gold = '<bsdf type="conductor"><string name="material" value="Au"/></bsdf>'
    s["bsdf-mixturebsdf"] = ("mixturebsdf: weights 0.6, 0.7 (scaled to sum 1) of diffuse and rough copper; "
                             "0.3; 0.5 of gold and diffuse without energy conservation",
        scene(sphere('<bsdf type="mixturebsdf"><string name="weights" value="0.6, 0.7"/>' +
                     DIFFUSE % "0.8, 0.3, 0.2" +
                     '<bsdf type="roughconductor"><string name="material" value="Cu"/>'
                     '<string name="distribution" value="ggx"/><float name="alpha" value="0.2"/></bsdf></bsdf>',
                     "-0.42, 0.4, 0", 0.4) +
              sphere('<bsdf type="mixturebsdf"><string name="weights" value="0.3; 0.5"/>'
                     '<boolean name="ensureEnergyConservation" value="false"/>' + gold +
                     DIFFUSE % "0.2, 0.5, 0.8" + '</bsdf>', "0.45, 0.35, 0.1", 0.35)),
        pt_bdpt + ["mlt"])
    s["bsdf-blendbsdf"] = ("blendbsdf: weight 0.3 between diffuse and rough plastic; a bitmap weight between diffuse and gold",
        scene(sphere('<bsdf type="blendbsdf"><float name="weight" value="0.3"/>' + DIFFUSE % "0.3, 0.7, 0.4" +
                     '<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.1"/>'
                     '<rgb name="diffuseReflectance" value="0.7, 0.2, 0.1"/></bsdf></bsdf>', "-0.45, 0.35, 0.1", 0.35) +
              rect('<bsdf type="blendbsdf"><texture type="bitmap" name="weight">' + bitmap() + '</texture>' +
                   DIFFUSE % "0.8, 0.8, 0.8" + gold + '</bsdf>',
                   '<scale x="0.4" y="0.4"/><rotate y="1" angle="-20"/><translate x="0.45" y="0.7" z="-0.3"/>')),
        pt_bdpt + ["mlt"])
    # Rough plastic seen and lit at grazing angles: a panel over the floor, a low camera.
    # Mitsuba weights the base by the rough coating's transmittance, which at grazing
    # angles is far above the smooth 1 - F (GGX alpha 0.12: 0.64 against 0.43 at cos 0.1).
    low_camera = sensor(96, 48, 45, transform='<lookat origin="0, 0.3, 2.4" target="0, 0.12, -1" up="0, 1, 0"/>')
    # A low lamp behind the camera lights the panel at grazing angles too.
    grazing_light = ('  <shape type="rectangle">\n    <transform name="toWorld"><scale x="0.4" y="0.12"/>'
                     '<rotate y="1" angle="180"/><translate y="0.14" z="2.6"/></transform>\n'
                     '    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>\n'
                     '    <emitter type="area"><rgb name="radiance" value="30, 27, 22"/></emitter>\n  </shape>\n')
    floor_panel = '<scale value="0.99"/><rotate x="1" angle="-90"/><translate y="0.005"/>'
    rough_floors = {
        "bsdf-roughplastic-ggx-grazing": ("roughplastic, ggx alpha 0.12, intIOR 1.5, at grazing angles",
            '<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.12"/>'
            '<float name="intIOR" value="1.5"/><rgb name="diffuseReflectance" value="0.55, 0.45, 0.3"/></bsdf>'),
        "bsdf-roughplastic-ggx-rough-nonlinear": ("roughplastic, ggx alpha 0.5, nonlinear true, at grazing angles",
            '<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.5"/>'
            '<boolean name="nonlinear" value="true"/><rgb name="diffuseReflectance" value="0.2, 0.5, 0.7"/></bsdf>'),
        "bsdf-roughplastic-beckmann-defaults": ("roughplastic defaults (beckmann alpha 0.1, polypropylene, diffuse 0.5), at grazing angles",
            '<bsdf type="roughplastic"/>'),
        "bsdf-roughplastic-alpha-texture": ("roughplastic, ggx with a checkerboard alpha (0.02 and 0.3), at grazing angles",
            '<bsdf type="roughplastic"><string name="distribution" value="ggx"/>'
            '<texture type="checkerboard" name="alpha"><spectrum name="color0" value="0.02"/><spectrum name="color1" value="0.3"/>'
            '<float name="uscale" value="3"/><float name="vscale" value="3"/></texture>'
            '<rgb name="diffuseReflectance" value="0.6, 0.3, 0.2"/></bsdf>'),
        # The same view of the rough conductor and of a rough dielectric interface over the
        # diffuse floor: Mitsuba evaluates both without tables (a measurement, that they
        # have no such difference).
        "bsdf-roughconductor-grazing": ("roughconductor, ggx alpha 0.12, Cu, at grazing angles",
            '<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.12"/>'
            '<string name="material" value="Cu"/></bsdf>'),
        "bsdf-roughdielectric-grazing": ("roughdielectric, ggx alpha 0.12, intIOR 1.5, over a diffuse floor at grazing angles",
            '<bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.12"/>'
            '<float name="intIOR" value="1.5"/></bsdf>'),
    }
    for name, (conv, bsdf) in rough_floors.items():
        s[name] = (conv, scene(rect(bsdf, floor_panel), light=ROOM_LIGHT % DEFAULT_RADIANCE + grazing_light,
                               cam=low_camera), pt_bdpt)
    # Anisotropy on a mesh follows dp/du of its uvs (turned 30 degrees off the panel's edges).
    s["bsdf-roughconductor-aniso-mesh"] = ("roughconductor, beckmann, alphaU 0.05 and alphaV 0.3 on an OBJ with uvs",
        scene(obj("panel_uv.obj", '<bsdf type="roughconductor"><string name="material" value="Cr"/>'
                  '<float name="alphaU" value="0.05"/><float name="alphaV" value="0.3"/></bsdf>',
                  '<rotate z="1" angle="30"/><scale x="0.6" y="0.6"/><rotate x="1" angle="-60"/>'
                  '<translate y="0.6" z="-0.2"/>')), pt_bdpt)
    s["bsdf-mask"] = ("mask: opacity from a bitmap",
                      scene(rect('<bsdf type="mask"><texture type="bitmap" name="opacity">' + bitmap("holes.png") +
                                 '</texture>' + DIFFUSE % "0.8, 0.8, 0.3" + "</bsdf>", PANEL)), pt_bdpt)
    s["tex-channel-alpha"] = ("mask opacity from an RGBA PNG's alpha (bitmap channel a, linear)",
                              scene(rect('<bsdf type="mask"><texture type="bitmap" name="opacity">' +
                                         bitmap("grid-alpha.png", '<string name="channel" value="a"/>') +
                                         '</texture>' + DIFFUSE % "0.8, 0.8, 0.3" + "</bsdf>", PANEL)), ["pt"])
    s["tex-channel-g"] = ("bitmap channel g: the green channel, sRGB-decoded, as a grey texture",
                          scene(rect(TEXTURED % bitmap("grid-alpha.png", '<string name="channel" value="g"/>'),
                                     PANEL)), ["pt"])
    s["bsdf-bumpmap"] = ("bumpmap: a bitmap height field scaled by a scale texture",
                         scene(rect('<bsdf type="bumpmap"><texture type="scale"><float name="scale" value="0.02"/>'
                                    '<texture type="bitmap">' + bitmap("bumps.png") + '</texture></texture>' +
                                    DIFFUSE % "0.8, 0.8, 0.8" + "</bsdf>",
                                    '<scale x="0.9" y="0.9"/><rotate x="1" angle="-90"/><translate y="0.01"/>')), pt_bdpt)

    # --- coatings (Mitsuba's own model, not a layered simulation) and the normal map
    coated_diffuse = ('<bsdf type="coating"><float name="intIOR" value="1.7"/><float name="thickness" value="0.5"/>'
                      '<rgb name="sigmaA" value="0.2, 0.6, 1.2"/>' + DIFFUSE % "0.8, 0.75, 0.6" + '</bsdf>')
    coated_metal = ('<bsdf type="coating"><string name="intIOR" value="water"/><rgb name="specularReflectance" value="0.8"/>'
                    '<bsdf type="roughconductor"><string name="material" value="Au"/><string name="distribution" value="ggx"/>'
                    '<float name="alpha" value="0.2"/></bsdf></bsdf>')
    s["bsdf-coating"] = ("coating: intIOR 1.7, thickness 0.5, sigmaA over a diffuse; water over a rough gold (ggx 0.2)",
        scene(sphere(coated_diffuse, "-0.45, 0.38, 0.1", 0.38) + sphere(coated_metal, "0.45, 0.38, 0", 0.38)),
        pt_bdpt + ["mlt"])
    s["bsdf-coating-delta-texture"] = ("coating over a smooth conductor (a delta under the delta); a checkerboard sigmaA over a diffuse panel",
        scene(sphere('<bsdf type="coating"><float name="intIOR" value="1.4"/>'
                     '<bsdf type="conductor"><string name="material" value="Cu"/></bsdf></bsdf>', "0.45, 0.3, 0.2", 0.3) +
              rect('<bsdf type="coating"><float name="thickness" value="2"/>'
                   '<texture type="checkerboard" name="sigmaA"><rgb name="color0" value="0.05, 0.1, 0.2"/>'
                   '<rgb name="color1" value="0.6, 0.3, 0.05"/><float name="uscale" value="3"/><float name="vscale" value="3"/></texture>' +
                   DIFFUSE % "0.7, 0.7, 0.7" + '</bsdf>',
                   '<scale x="0.45" y="0.45"/><rotate y="1" angle="25"/><translate x="-0.35" y="0.8" z="-0.3"/>')),
        pt_bdpt)
    s["bsdf-roughcoating"] = ("roughcoating: ggx alpha 0.15 over a diffuse; beckmann alpha 0.3, thickness 2, sigmaA over a rough copper",
        scene(sphere('<bsdf type="roughcoating"><string name="distribution" value="ggx"/><float name="alpha" value="0.15"/>' +
                     DIFFUSE % "0.2, 0.5, 0.8" + '</bsdf>', "-0.45, 0.38, 0.1", 0.38) +
              sphere('<bsdf type="roughcoating"><float name="alpha" value="0.3"/><float name="intIOR" value="1.6"/>'
                     '<float name="thickness" value="2"/><rgb name="sigmaA" value="0.05, 0.2, 0.4"/>'
                     '<bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.1"/></bsdf></bsdf>',
                     "0.45, 0.38, 0", 0.38)),
        pt_bdpt + ["mlt"])
    s["bsdf-roughcoating-alpha-texture"] = ("roughcoating, ggx with a checkerboard alpha (0.03 and 0.4) over a diffuse panel; beckmann over a smooth conductor (Mitsuba weighs a nested delta by its sampling weight alone)",
        scene(rect('<bsdf type="roughcoating"><string name="distribution" value="ggx"/>'
                   '<texture type="checkerboard" name="alpha"><spectrum name="color0" value="0.03"/><spectrum name="color1" value="0.4"/>'
                   '<float name="uscale" value="3"/><float name="vscale" value="3"/></texture>' +
                   DIFFUSE % "0.75, 0.45, 0.25" + '</bsdf>',
                   '<scale x="0.45" y="0.45"/><rotate y="1" angle="25"/><rotate x="1" angle="-30"/><translate x="-0.35" y="0.7" z="-0.3"/>') +
              sphere('<bsdf type="roughcoating"><float name="alpha" value="0.2"/>'
                     '<bsdf type="conductor"><string name="material" value="Ag"/></bsdf></bsdf>', "0.45, 0.3, 0.2", 0.3)),
        pt_bdpt)
    s["bsdf-normalmap"] = ("normalmap: a gamma-1 bitmap of tangent-space normals over a rough plastic, on a panel lit from above",
        scene(rect('<bsdf type="normalmap"><texture type="bitmap">' + bitmap("normals.png", '<float name="gamma" value="1"/>') +
                   '</texture><bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/>'
                   '<rgb name="diffuseReflectance" value="0.3, 0.5, 0.7"/></bsdf></bsdf>',
                   '<scale x="0.7" y="0.7"/><rotate x="1" angle="-25"/><translate y="0.75" z="-0.3"/>')),
        pt_bdpt)

    s["bsdf-default"] = ("shapes naming no BSDF: a one-sided diffuse 0.5, black on an emitter",
                         scene('  <shape type="sphere">\n    ' + point("center", "-0.45, 0.35, 0.1") +
                               '<float name="radius" value="0.35"/>\n  </shape>\n' +
                               '  <shape type="rectangle">\n    <transform name="toWorld"><scale x="0.3" y="0.4"/>'
                               '<rotate y="1" angle="160"/><translate x="0.45" y="0.6" z="-0.2"/></transform>\n  </shape>\n' +
                               '  <shape type="rectangle">\n    <transform name="toWorld"><scale x="0.5" y="0.3"/>'
                               '<translate y="1.2" z="-0.98"/></transform>\n    <emitter type="area">'
                               '<rgb name="radiance" value="2, 2.5, 3"/></emitter>\n  </shape>\n'), pt_bdpt)

    # --- textures (on a panel facing the camera)
    def panel_tex(params, file="grid.png"):
        return rect(TEXTURED % bitmap(file, params), PANEL)
    s["tex-png-srgb"] = ("an 8-bit PNG is sRGB-decoded", scene(panel_tex("")), pt_bdpt)
    s["tex-png-gamma"] = ("gamma 1 overrides a PNG's sRGB curve",
                          scene(panel_tex('<float name="gamma" value="1"/>')), pt_bdpt)
    s["tex-jpg-srgb"] = ("a JPEG is sRGB-decoded, its chroma upsampled as libjpeg does",
                         scene(panel_tex("", "grid.jpg")), pt_bdpt)
    s["tex-jpg-grey"] = ("a grey (progressive) JPEG gives three equal channels",
                         scene(panel_tex("", "grid-grey.jpg")), pt_bdpt)
    pt_only = ["pt"]  # the texels are the subject; one integrator reads them as any other
    s["tex-png-gama-linear"] = ("a PNG whose gAMA chunk says 1.0 is linear",
                                scene(panel_tex("", "grid-gama1.png")), pt_only)
    s["tex-png-gama-15"] = ("a PNG whose gAMA chunk says 1/1.5 is decoded as v^1.5",
                            scene(panel_tex("", "grid-gama15.png")), pt_only)
    s["tex-png-srgb-chunk"] = ("an sRGB chunk outranks a gAMA chunk",
                               scene(panel_tex("", "grid-srgb-gama15.png")), pt_only)
    s["tex-png-16bit"] = ("a 16-bit PNG keeps its 16-bit samples", scene(panel_tex("", "grid16.png")),
                          pt_only)
    s["tex-gamma-15"] = ("bitmap gamma 1.5 replaces the file's sRGB curve",
                         scene(panel_tex('<float name="gamma" value="1.5"/>')), pt_only)
    s["tex-exr-linear"] = ("an EXR texture is linear", scene(panel_tex("", "grid.exr")), pt_bdpt)
    s["tex-uv-transform"] = ("uscale/vscale and uoffset/voffset with repeat",
                             scene(panel_tex('<float name="uscale" value="3"/><float name="vscale" value="2"/>'
                                             '<float name="uoffset" value="0.25"/><float name="voffset" value="0.1"/>')),
                             pt_bdpt)
    s["tex-wrap-zero-one"] = ("uvscale 2 with wrapModeU zero and wrapModeV one",
                              scene(panel_tex('<float name="uvscale" value="2"/><string name="wrapModeU" value="zero"/>'
                                              '<string name="wrapModeV" value="one"/>')), pt_only)
    s["tex-wrap-clamp"] = ("uvscale 2 with wrapMode clamp",
                           scene(panel_tex('<float name="uvscale" value="2"/><string name="wrapMode" value="clamp"/>')),
                           pt_bdpt)
    s["tex-wrap-mirror"] = ("uvscale 2.5 with wrapMode mirror",
                            scene(panel_tex('<float name="uvscale" value="2.5"/><string name="wrapMode" value="mirror"/>')),
                            pt_bdpt)
    s["tex-obj-fliptexcoords"] = ("OBJ texture coordinates flipped by default, and not with flipTexCoords false",
                                  scene(obj("panel_uv.obj", TEXTURED % bitmap(),
                                            '<scale x="0.45" y="0.45"/><translate x="-0.5" y="0.8" z="-0.2"/>') +
                                        obj("panel_uv.obj", TEXTURED % bitmap(),
                                            '<scale x="0.45" y="0.45"/><translate x="0.5" y="0.8" z="-0.2"/>',
                                            '    <boolean name="flipTexCoords" value="false"/>\n')), pt_bdpt)
    s["tex-ewa-default"] = ("a bitmap with Mitsuba's default EWA filtering, minified on a receding floor",
                            scene(rect('<bsdf type="diffuse"><texture type="bitmap" name="reflectance">'
                                       '<string name="filename" value="assets/grid.png"/><float name="uvscale" value="6"/>'
                                       '</texture></bsdf>',
                                       '<scale value="0.98"/><rotate x="1" angle="-90"/><translate y="0.01"/>')), pt_bdpt)
    s["tex-checkerboard"] = ("checkerboard colours and uscale",
                             scene(rect('<bsdf type="diffuse"><texture type="checkerboard" name="reflectance">'
                                        '<rgb name="color0" value="0.1, 0.2, 0.7"/><rgb name="color1" value="0.8, 0.7, 0.1"/>'
                                        '<float name="uscale" value="4"/><float name="vscale" value="3"/></texture></bsdf>',
                                        PANEL)), pt_bdpt)
    # gridtexture (colours, lineWidth, uvscale, uoffset), and a checkerboard whose negative
    # uoffset puts u = 0 inside the panel: Mitsuba truncates the cell index towards zero, so
    # the two cells beside u = 0 share a colour.
    s["tex-grid"] = ("gridtexture, and a checkerboard across u = 0",
                     scene(rect('<bsdf type="diffuse"><texture type="gridtexture" name="reflectance">'
                                '<rgb name="color0" value="0.1, 0.3, 0.7"/><rgb name="color1" value="0.9, 0.8, 0.2"/>'
                                '<float name="lineWidth" value="0.08"/><float name="uvscale" value="3"/>'
                                '<float name="uoffset" value="0.3"/></texture></bsdf>',
                                '<scale x="0.45" y="0.45"/><translate x="-0.48" y="0.8" z="-0.2"/>') +
                           rect('<bsdf type="diffuse"><texture type="checkerboard" name="reflectance">'
                                '<rgb name="color0" value="0.1, 0.2, 0.7"/><rgb name="color1" value="0.8, 0.7, 0.1"/>'
                                '<float name="uscale" value="1.5"/><float name="uoffset" value="-0.75"/>'
                                '<float name="vscale" value="2"/></texture></bsdf>',
                                '<scale x="0.45" y="0.45"/><translate x="0.48" y="0.8" z="-0.2"/>')), pt_bdpt)
    vertex_colors = '<bsdf type="diffuse"><texture type="vertexcolors" name="reflectance"/></bsdf>'
    s["tex-vertexcolors"] = ("vertexcolors: PLY colours interpolated barycentrically; uchar / 255 "
                             "sRGB-decoded (binary), float as stored with srgb false (ASCII)",
                             scene('  <shape type="ply">\n    <string name="filename" value="assets/quad_colors_uchar.ply"/>\n'
                                   '    <transform name="toWorld"><scale x="0.45" y="0.6"/><translate x="-0.48" y="0.8" z="-0.2"/></transform>\n    ' +
                                   vertex_colors + '\n  </shape>\n'
                                   '  <shape type="ply">\n    <string name="filename" value="assets/quad_colors_float.ply"/>\n'
                                   '    <boolean name="srgb" value="false"/>\n'
                                   '    <transform name="toWorld"><scale x="0.45" y="0.6"/><translate x="0.48" y="0.8" z="-0.2"/></transform>\n    ' +
                                   vertex_colors + '\n  </shape>\n'), pt_bdpt)
    s["tex-sphere-uv"] = ("a bitmap on a sphere uses Mitsuba's sphere parametrisation",
                          scene(sphere(TEXTURED % bitmap()), cam=sensor()), pt_bdpt)

    # --- spectra
    cbox_white = ("400:0.343, 404:0.445, 408:0.551, 412:0.624, 416:0.665, 420:0.687, 424:0.708, 428:0.723, "
                  "432:0.715, 436:0.71, 440:0.745, 444:0.758, 448:0.739, 452:0.767, 456:0.777, 460:0.765, "
                  "464:0.751, 468:0.745, 472:0.748, 476:0.729, 480:0.745, 484:0.757, 488:0.753, 492:0.75, "
                  "496:0.746, 500:0.747, 504:0.735, 508:0.732, 512:0.739, 516:0.734, 520:0.725, 524:0.721, "
                  "528:0.733, 532:0.725, 536:0.732, 540:0.743, 544:0.744, 548:0.748, 552:0.728, 556:0.716, "
                  "560:0.733, 564:0.726, 568:0.713, 572:0.74, 576:0.754, 580:0.764, 584:0.752, 588:0.736, "
                  "592:0.734, 596:0.741, 600:0.74, 604:0.732, 608:0.745, 612:0.755, 616:0.751, 620:0.744, "
                  "624:0.731, 628:0.733, 632:0.744, 636:0.731, 640:0.712, 644:0.708, 648:0.729, 652:0.73, "
                  "656:0.727, 660:0.707, 664:0.703, 668:0.729, 672:0.75, 676:0.76, 680:0.751, 684:0.739, "
                  "688:0.724, 692:0.73, 696:0.74, 700:0.737")
    cbox_light = "400:0, 500:8, 600:15.6, 700:18.4"
    s["spectrum-forms"] = ("one value, three values, rgb, srgb hex and a wavelength list as reflectances",
                           scene(sphere('<bsdf type="diffuse"><spectrum name="reflectance" value="%s"/></bsdf>' % cbox_white,
                                        center="-0.45, 0.3, 0", radius=0.3) +
                                 sphere('<bsdf type="diffuse"><spectrum name="reflectance" value="0.2, 0.5, 0.8"/></bsdf>',
                                        center="0.45, 0.3, 0", radius=0.3) +
                                 sphere('<bsdf type="diffuse"><srgb name="reflectance" value="#c08040"/></bsdf>',
                                        center="0, 0.3, 0.45", radius=0.3) +
                                 sphere('<bsdf type="diffuse"><spectrum name="reflectance" value="0.4"/></bsdf>',
                                        center="0, 0.9, -0.3", radius=0.3)), pt_bdpt)
    s["spectrum-emitter"] = ("an emitter's radiance as a wavelength list (the classic Cornell box's lamp)",
                             scene(sphere(WHITE), light=ROOM_LIGHT % ('<spectrum name="radiance" value="%s"/>' % cbox_light)),
                             pt_bdpt)
    s["spectrum-blackbody"] = ("an emitter's radiance as a blackbody with scale",
                               scene(sphere(WHITE), light=ROOM_LIGHT % '<blackbody name="radiance" temperature="3200K" scale="0.012"/>'),
                               pt_bdpt)

    # --- camera and film (non-square where the axis matters)
    for axis in ("x", "y", "diagonal", "smaller", "larger"):
        s[f"camera-fovaxis-{axis}"] = (f"fovAxis {axis} on a 96x64 image",
                                       scene(sphere(WHITE), cam=sensor(96, 64, 40, axis)), pt_bdpt)
    s["camera-fovaxis-y-portrait"] = ("fovAxis smaller on a 48x80 portrait image",
                                      scene(sphere(WHITE), cam=sensor(48, 80, 40, "smaller")), pt_bdpt)
    s["camera-matrix"] = ("camera toWorld as rotate + translate (no lookat)",
                          scene(sphere(WHITE), cam=sensor(transform='<rotate y="1" angle="188"/><rotate x="1" angle="6"/>'
                                                                    '<translate x="-0.3" y="1.1" z="3.2"/>')), pt_bdpt)
    s["shape-transforms"] = ("scale, rotate, translate and matrix on shapes",
                             scene('  <shape type="cube">\n    <transform name="toWorld"><scale x="0.3" y="0.5" z="0.2"/>'
                                   '<rotate y="1" angle="30"/><translate x="-0.4" y="0.5"/></transform>\n    ' + WHITE +
                                   '\n  </shape>\n' +
                                   rect(DIFFUSE % "0.3, 0.6, 0.8",
                                        '<matrix value="0.3 0 0.1 0.45  0 0.4 0 0.5  -0.1 0 0.3 0.1  0 0 0 1"/>')), pt_bdpt)
    # Mitsuba's parser takes <lookAt> as well as <lookat>, and without `up` builds the frame
    # from its coordinateSystem() of the viewing direction: a textured panel shows the turn
    # about its normal, and a panel facing straight up has a frame where (0, 1, 0) has none.
    s["transform-lookAt"] = ("<lookAt> (camera, and panels without up) beside translate, rotate, scale and matrix",
                             scene(rect(TEXTURED % bitmap(), '<scale value="0.45"/><lookAt origin="-0.4, 0.85, -0.3" target="0.2, 1.1, 3"/>') +
                                   rect(DIFFUSE % "0.8, 0.5, 0.2", '<scale x="0.55" y="0.18"/><lookat origin="0.3, 0.02, 0.9" target="0.3, 3, 0.91"/>') +
                                   '  <shape type="cube">\n    <transform name="toWorld"><scale x="0.2" y="0.3" z="0.2"/>'
                                   '<rotate x="0.3" y="1" z="0.2" angle="35"/><translate x="0.5" y="0.3" z="-0.4"/></transform>\n    ' + WHITE +
                                   '\n  </shape>\n' +
                                   rect(DIFFUSE % "0.2, 0.4, 0.8", '<matrix value="0.25 0 0.1 0.3  0 0.3 0 1.2  -0.1 0 0.25 -0.6  0 0 0 1"/>'),
                                   cam=sensor(transform='<lookAt origin="0.2, 1.1, 3.3" target="0, 0.85, 0" up="0.1, 1, 0"/>')),
                             pt_bdpt)
    s["film-gaussian"] = ("the film's default reconstruction filter (gaussian)",
                          scene(sphere(WHITE), cam=sensor(rfilter=None)), pt_bdpt + ["mlt"])
    # Filters with negative lobes, tabulated as Mitsuba tabulates them: the ceiling light seen
    # directly is an edge of about 30:1, which rings; the room fills the frame, so the border
    # pixels' renormalisation shows too.
    s["film-mitchell"] = ("mitchell filter, B 0.2 and C 0.6 (negative lobes)",
                          scene(sphere(WHITE), cam=sensor(rfilter="mitchell", rfilter_params=
                                '<float name="B" value="0.2"/><float name="C" value="0.6"/>')),
                          pt_bdpt + ["mlt"])
    s["film-catmullrom"] = ("catmullrom filter (negative lobes)",
                            scene(sphere(WHITE), cam=sensor(rfilter="catmullrom")), pt_bdpt + ["mlt"])
    s["film-lanczos"] = ("lanczos filter, 2 lobes (negative lobes)",
                         scene(sphere(WHITE), cam=sensor(rfilter="lanczos", rfilter_params=
                               '<integer name="lobes" value="2"/>')), pt_bdpt + ["mlt"])

    # --- shading normals: a level panel above the floor whose vertex normals lean 60 degrees
    # towards the green wall. strictNormals true drops the directions that the geometric and
    # the shading normal put on different sides; false lets the shading normal alone decide,
    # so the panel also gathers light from below it (a leak). On a closed convex mesh the two
    # agree: such directions end inside the mesh, or the one-sided BSDF turns them away.
    leaning = obj("panel_normals_lean.obj", DIFFUSE % "0.8, 0.8, 0.8",
                  '<scale value="0.55"/><rotate x="1" angle="-90"/><translate y="0.45" z="0.1"/>')
    s["normals-strict"] = ("strictNormals true: no light through a panel's leaning shading normals",
                           scene(leaning, integ=integrator(strict_normals=True)), pt_bdpt + ["mlt"])
    s["normals-loose"] = ("strictNormals false (Mitsuba's default): the shading normal decides",
                          scene(leaning, integ=integrator(strict_normals=False)), pt_bdpt + ["mlt"])

    # --- shapes and lights
    s["shape-sphere-disk-cube"] = ("sphere, disk and cube",
                                   scene(sphere(WHITE, "-0.5, 0.3, 0", 0.3) +
                                         '  <shape type="disk">\n    <transform name="toWorld"><scale value="0.3"/>'
                                         '<rotate y="1" angle="20"/><translate x="0.45" y="0.8" z="-0.5"/></transform>\n    ' +
                                         DIFFUSE % "0.8, 0.4, 0.2" + '\n  </shape>\n' +
                                         '  <shape type="cube">\n    <transform name="toWorld"><scale value="0.2"/>'
                                         '<translate x="0.4" y="0.2" z="0.2"/></transform>\n    ' + WHITE + '\n  </shape>\n'),
                                   pt_bdpt)
    s["shape-cylinder"] = ("cylinder (open, p0/p1/radius)",
                           scene('  <shape type="cylinder">\n    ' + point("p0", "0, 0.1, 0") + point("p1", "0.2, 1.1, -0.1") +
                                 '<float name="radius" value="0.3"/>\n    ' +
                                 '<bsdf type="twosided">' + DIFFUSE % "0.8, 0.6, 0.3" + '</bsdf>\n  </shape>\n'), pt_bdpt)
    s["shape-serialized"] = ("serialized meshes chosen by shapeIndex",
                             scene('  <shape type="serialized">\n    <string name="filename" value="assets/shapes.serialized"/>'
                                   '<integer name="shapeIndex" value="1"/>\n    <transform name="toWorld"><scale value="0.5"/>'
                                   '<translate y="0.5"/></transform>\n    ' + WHITE + '\n  </shape>\n'
                                   '  <shape type="serialized">\n    <string name="filename" value="assets/shapes.serialized"/>'
                                   '<integer name="shapeIndex" value="0"/>\n    <transform name="toWorld"><scale value="0.3"/>'
                                   '<translate x="0.6" y="1.2" z="-0.5"/></transform>\n    ' + DIFFUSE % "0.2, 0.4, 0.8" +
                                   '\n  </shape>\n'), pt_bdpt)
    s["shape-ply"] = ("PLY meshes, ASCII with normals and binary with quads",
                      scene('  <shape type="ply">\n    <string name="filename" value="assets/ball_ascii.ply"/>\n'
                            '    <transform name="toWorld"><scale value="0.35"/><translate x="-0.4" y="0.35"/></transform>\n    ' +
                            WHITE + '\n  </shape>\n'
                            '  <shape type="ply">\n    <string name="filename" value="assets/pyramid_binary.ply"/>\n'
                            '    <transform name="toWorld"><scale value="0.35"/><translate x="0.4"/></transform>\n    ' +
                            DIFFUSE % "0.8, 0.5, 0.2" + '\n  </shape>\n'), pt_bdpt)
    s["shape-instance"] = ("shapegroup and instance",
                           scene('  <shape type="shapegroup" id="pair">\n' + sphere(WHITE, "0, 0.2, 0", 0.2) +
                                 sphere(DIFFUSE % "0.2, 0.3, 0.8", "0.3, 0.15, 0.2", 0.15) + '  </shape>\n'
                                 '  <shape type="instance">\n    <ref id="pair"/>\n    <transform name="toWorld">'
                                 '<translate x="-0.5"/></transform>\n  </shape>\n'
                                 '  <shape type="instance">\n    <ref id="pair"/>\n    <transform name="toWorld">'
                                 '<rotate y="1" angle="90"/><scale value="1.3"/><translate x="0.4" z="-0.2"/></transform>\n'
                                 '  </shape>\n'), pt_bdpt)
    s["light-sphere"] = ("an emissive sphere", scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35),
                                                      light='  <shape type="sphere">\n    ' + point("center", "0.45, 1.3, 0") +
                                                            '<float name="radius" value="0.15"/>\n    <emitter type="area">'
                                                            '<rgb name="radiance" value="10, 8, 6"/></emitter>\n  </shape>\n'),
                         pt_bdpt)
    s["light-constant"] = ("constant environment emitter", scene(sphere(WHITE) + rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>'),
                                                                 light='  <emitter type="constant"><rgb name="radiance" value="0.8, 0.9, 1.2"/></emitter>\n',
                                                                 walls=False), pt_bdpt)
    # hideEmitters (Mitsuba's path tracer): the ceiling light, in view, is black, and so is
    # the sky seen past the room; what they light is not. emlt's other integrators leave
    # out the same one-segment paths, so all three are checked against Mitsuba's path image.
    s["light-hide-emitters"] = ("hideEmitters: an area light seen directly is black",
                          scene(sphere(WHITE), integ=integrator(hide_emitters=True)), pt_bdpt + ["mlt"])
    s["light-hide-emitters-env"] = ("hideEmitters: the sky seen directly is black",
                              scene(sphere(WHITE) + rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>'),
                                    light='  <emitter type="constant"><rgb name="radiance" value="0.8, 0.9, 1.2"/></emitter>\n',
                                    walls=False, integ=integrator(hide_emitters=True)), pt_bdpt + ["mlt"])
    s["light-envmap"] = ("envmap orientation (toWorld) and scale",
                         scene(sphere('<bsdf type="roughconductor"><string name="material" value="Al"/><float name="alpha" value="0.05"/></bsdf>') +
                               rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>'),
                               light='  <emitter type="envmap"><string name="filename" value="assets/sky.exr"/>'
                                     '<float name="scale" value="1.5"/><transform name="toWorld"><rotate y="1" angle="60"/></transform></emitter>\n',
                               walls=False), pt_bdpt)
    # An envmap's gamma replaces the map's curve, as a bitmap's does: a float map's values
    # are bent by it too (v^2.2 here).
    s["light-envmap-gamma"] = ("envmap gamma 2.2 over a float map (its values bent to v^2.2)",
                               scene(sphere(WHITE) + rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>'),
                                     light='  <emitter type="envmap"><string name="filename" value="assets/sky.exr"/>'
                                           '<float name="gamma" value="2.2"/></emitter>\n',
                                     walls=False), ["pt"])

    # Mitsuba's daylight emitters rasterise their radiance into a lat-long map for a nested
    # envmap; these check emlt's map of each (model, sun position, frame, scales). The sun
    # stays out of view: only its light, and the sky, are seen.
    floor = rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>')
    s["light-sky"] = ("sky: Hosek-Wilkie model, turbidity, albedo, stretch, explicit sunDirection",
                      scene(sphere('<bsdf type="roughconductor"><string name="material" value="Al"/><float name="alpha" value="0.05"/></bsdf>') + floor,
                            light='  <emitter type="sky"><float name="turbidity" value="4.5"/><rgb name="albedo" value="0.1, 0.4, 0.8"/>'
                                  '<float name="stretch" value="1.2"/><vector name="sunDirection" x="0.5" y="0.55" z="-0.4"/>'
                                  '<integer name="resolution" value="128"/><float name="scale" value="3"/></emitter>\n',
                            walls=False), pt_bdpt)
    s["light-sun"] = ("sun: Preetham solar disk (sunRadiusScale, turbidity), explicit sunDirection",
                      scene(sphere(WHITE, "-0.2, 0.45, 0", 0.45) + sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.55, 0.2, 0.4", 0.2) + floor,
                            light='  <emitter type="sun"><vector name="sunDirection" x="-0.6" y="0.7" z="0.3"/>'
                                  '<float name="turbidity" value="5"/><float name="sunRadiusScale" value="4"/>'
                                  '<integer name="resolution" value="128"/><float name="scale" value="0.5"/></emitter>\n',
                            walls=False), pt_bdpt)
    s["light-sunsky"] = ("sunsky: sun position from latitude/longitude/date/time, toWorld, scale/skyScale/sunScale",
                         scene(sphere(WHITE, "-0.2, 0.45, 0", 0.45) + sphere(DIFFUSE % "0.2, 0.3, 0.8", "0.55, 0.2, 0.4", 0.2) + floor,
                               light='  <emitter type="sunsky"><float name="latitude" value="48.2"/><float name="longitude" value="16.37"/>'
                                     '<float name="timezone" value="1"/><integer name="year" value="2015"/><integer name="month" value="3"/>'
                                     '<integer name="day" value="21"/><float name="hour" value="10"/><float name="minute" value="45"/>'
                                     '<float name="turbidity" value="3.5"/><float name="scale" value="0.6"/><float name="skyScale" value="1.5"/>'
                                     '<transform name="toWorld"><rotate y="1" angle="-70"/></transform></emitter>\n',
                               walls=False), pt_bdpt)

    # Delta lights: no surface, found only by light sampling (never by a BSDF sample), never
    # seen from the camera. Each light stays out of view. The point and the directional light
    # go through every integrator (the path layer's delta vertices, each MCMC kernel).
    every_integrator = ["pt", "bdpt", "mlt", "gamlt", "emlt", "pssmlt", "mmlt"]
    point_light = ('  <emitter type="point"><point name="position" x="0.2" y="1.9" z="1.6"/>'
                   '<rgb name="intensity" value="3, 2.5, 2"/></emitter>\n')
    s["light-point"] = ("point light: intensity in W/sr, no cosine at the light, invisible",
                        scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35) +
                              sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.45, 0.25, -0.3", 0.25),
                              light=point_light), every_integrator)
    spot = ('  <emitter type="spot"><transform name="toWorld"><lookat origin="0.6, 1.9, 1.2" '
            'target="-0.2, 0, -0.3" up="0, 1, 0"/></transform><rgb name="intensity" value="9, 8, 6"/>'
            '<float name="cutoffAngle" value="28"/><float name="beamWidth" value="16"/>%s</emitter>\n')
    s["light-spot"] = ("spot light: cutoffAngle and beamWidth (falloff linear in angle), toWorld lookat",
                       scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35), light=spot % ""),
                       pt_bdpt + ["mlt"])
    s["light-spot-texture"] = ("spot light projecting a bitmap texture over its cone",
                               scene(sphere(WHITE, "0.3, 0.3, -0.2", 0.3),
                                     light=spot % ('<texture type="bitmap" name="texture">%s</texture>'
                                                   % bitmap())), pt_bdpt)
    s["light-directional"] = ("directional light: irradiance at normal incidence, 'direction', shadows",
                              scene(sphere(WHITE, "-0.2, 0.45, 0", 0.45) +
                                    sphere(DIFFUSE % "0.2, 0.3, 0.8", "0.55, 0.2, 0.4", 0.2) + floor,
                                    light='  <emitter type="directional"><vector name="direction" '
                                          'x="0.5" y="-1" z="-0.35"/><rgb name="irradiance" '
                                          'value="2, 1.8, 1.5"/></emitter>\n',
                                    walls=False), every_integrator)
    s["light-sun-directional"] = ("sun with sunRadiusScale 0: a directional light of the sun disk's irradiance",
                                  scene(sphere(WHITE, "-0.2, 0.45, 0", 0.45) + floor,
                                        light='  <emitter type="sun"><vector name="sunDirection" x="-0.6" '
                                              'y="0.7" z="0.3"/><float name="turbidity" value="4"/>'
                                              '<float name="sunRadiusScale" value="0"/>'
                                              '<float name="scale" value="0.5"/></emitter>\n',
                                        walls=False), pt_bdpt)

    # A collimated beam: one point, one direction, rendered only by light tracing (Mitsuba's
    # path tracer draws nothing of it): against Mitsuba's ptracer, the beam hitting the back
    # of the sphere (the spot, a single bright point, out of view), which lights the room.
    s["light-collimated-ptracer"] = (
        "collimated beam: power along one ray, only light tracing renders it",
        scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35),
              light='  <emitter type="collimated"><transform name="toWorld"><lookat origin="-0.3, 1.9, -0.9" '
                    'target="-0.3, 0.6, -0.25" up="0, 0, 1"/></transform><rgb name="power" value="6, 5, 4"/></emitter>\n',
              integ=integrator(kind="ptracer")),
        ["ptracer", "bdpt", "mlt"])

    # --- the particle tracer: scenes above with <integrator type="ptracer">, whose references
    # are Mitsuba's ptracer images, not its path tracer's. They differ where a particle tracer
    # means something else: light reaching the camera only through a delta BSDF is black, and
    # a non-box filter's splats lose the part of the footprint that falls off the image. The
    # sky seen directly is drawn (Mitsuba's particles leave a sphere round the scene).
    ptracer = {
        "depth-3": "ptracer, maxDepth 3: lights seen directly, direct and one indirect bounce",
        "depth-unbounded": "ptracer, maxDepth -1 (Russian roulette from rrDepth 5)",
        "bsdf-roughconductor-ggx": "ptracer through a rough conductor (ggx)",
        "bsdf-roughdielectric": "ptracer through rough glass (adjoint refraction)",
        "bsdf-dielectric": "ptracer: smooth glass is black, its caustic is not",
        "tex-checkerboard": "ptracer on a textured panel",
        "light-sphere": "ptracer from an emissive sphere",
        "light-constant": "ptracer under a constant environment, the sky seen directly drawn",
        "light-envmap": "ptracer under an envmap (rotated, scaled), the sky seen directly drawn",
        "light-point": "ptracer from a point light",
        "light-directional": "ptracer from a directional light (rays from a disk covering the scene)",
    }
    for base, convention in ptracer.items():
        xml = s[base][1].replace('<integrator type="path">', '<integrator type="ptracer">')
        assert 'type="ptracer"' in xml, base
        s[base + "-ptracer"] = (convention, xml, ["ptracer"])
    # The room fills the frame, so that the border pixels, which lose the part of the
    # Gaussian footprint off the image, are lit.
    s["film-gaussian-border-ptracer"] = (
        "ptracer splats through the gaussian filter: border pixels keep only the footprint inside",
        scene(sphere(WHITE), cam=sensor(fov=28, rfilter=None), integ=integrator(kind="ptracer")),
        ["ptracer"])
    # The same through a filter with negative lobes: the splats carry the signed table.
    s["film-mitchell-border-ptracer"] = (
        "ptracer splats through a mitchell filter (B 0.2, C 0.6): signed weights, no renormalisation",
        scene(sphere(WHITE), cam=sensor(fov=28, rfilter="mitchell",
                                        rfilter_params='<float name="B" value="0.2"/><float name="C" value="0.6"/>'),
              integ=integrator(kind="ptracer")),
        ["ptracer"])
    add_plugin_scenes(s)
    return s


def add_plugin_scenes(s):
    """Scenes that name the plugins no other scene names: a thin lens, the tent and gaussian
    filters, the direct, bdpt and mlt integrators, every sampler and every film."""
    pt_bdpt = ["pt", "bdpt"]
    # Depth of field: the near sphere is in focus, the far one and the back wall are not.
    near_far = (sphere(WHITE, "-0.4, 0.3, 0.7", 0.3) + sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.45, 0.4, -0.55", 0.4) +
                rect(TEXTURED % bitmap(), '<scale value="0.5"/><translate x="-0.2" y="1.2" z="-0.98"/>'))
    s["camera-thinlens"] = ("thinlens: apertureRadius 0.1, focusDistance 2.75 (near sphere sharp, back wall blurred)",
        scene(near_far, cam=sensor(kind="thinlens", params='\n    <float name="fov" value="50"/>'
                                   '\n    <float name="apertureRadius" value="0.1"/>'
                                   '\n    <float name="focusDistance" value="2.75"/>')),
        pt_bdpt + ["mlt"])
    # Mitsuba's tent has a fixed radius of one pixel (it reads no parameter).
    s["film-tent"] = ("tent filter (Mitsuba's fixed radius of 1 pixel)",
                      scene(sphere(WHITE), cam=sensor(rfilter="tent")), pt_bdpt)
    s["film-gaussian-stddev"] = ("a named gaussian filter, stddev 0.8 (radius 3.2 pixels)",
                                 scene(sphere(WHITE), cam=sensor(rfilter="gaussian",
                                       rfilter_params='<float name="stddev" value="0.8"/>')),
                                 pt_bdpt + ["mlt"])

    # Mitsuba's direct integrator: the emission seen by the camera (hideEmitters false) plus
    # one bounce of light, sampled from the lights and from the BSDF and combined by MIS;
    # rendered by emlt's `direct`, which means the same. A rough conductor makes the BSDF
    # samples matter; the walls add no indirect light.
    glossy = '<bsdf type="roughconductor"><string name="material" value="Au"/><float name="alpha" value="0.15"/></bsdf>'
    direct_subject = sphere(WHITE, "-0.4, 0.35, 0", 0.35) + sphere(glossy, "0.4, 0.35, -0.2", 0.35)
    s["integrator-direct"] = ("direct integrator: emitters seen directly, one bounce of MIS direct light",
        scene(direct_subject, integ='  <integrator type="direct">\n    <integer name="emitterSamples" value="2"/>'
                                    '\n    <integer name="bsdfSamples" value="2"/>\n  </integrator>\n'),
        ["direct"])
    # Mitsuba's own bidirectional path tracer and MLT make these references (maxDepth 4).
    bidir_subject = sphere(WHITE, "-0.4, 0.35, 0", 0.35) + sphere(glossy, "0.4, 0.35, -0.2", 0.35)
    s["integrator-bdpt"] = ("Mitsuba's bdpt, maxDepth 4, against emlt's bdpt",
                            scene(bidir_subject, integ=integrator(kind="bdpt", max_depth=4)), ["bdpt"])
    # Files naming Mitsuba's Metropolis integrators: their images converge to the path
    # tracer's, and Mitsuba's own MLT image is too noisy to be a reference (at 16,384
    # mutations per pixel emlt's mean agreed within 0.7 % but the per-pixel error was 5.6
    # times the renders' noise), so the reference is Mitsuba's path tracer on the same file
    # ("reference_integrator" in suite.json). The tuning parameters are read as notes.
    s["integrator-mlt"] = ("a file naming Mitsuba's mlt (maxDepth 4) renders with emlt's mlt; reference: Mitsuba's path tracer",
        scene(bidir_subject, integ='  <integrator type="mlt">\n    <integer name="maxDepth" value="4"/>'
                                   '\n    <integer name="luminanceSamples" value="50000"/>'
                                   '\n    <boolean name="manifoldPerturbation" value="false"/>\n  </integrator>\n'),
        ["mlt"])
    s["integrator-pssmlt"] = ("a file naming Mitsuba's pssmlt (maxDepth 4) renders with emlt's pssmlt; reference: Mitsuba's path tracer",
        scene(bidir_subject, integ='  <integrator type="pssmlt">\n    <integer name="maxDepth" value="4"/>'
                                   '\n    <boolean name="bidirectional" value="true"/>'
                                   '\n    <float name="pLarge" value="0.3"/>\n  </integrator>\n'),
        ["pssmlt"])

    # Parallel projection: toWorld's scale sizes the film (x in [-1.1, 1.1], y over the
    # aspect's share of it); a view from above one corner shows two walls and the floor.
    # The path-space integrators see the film point as the projection of the first vertex.
    s["camera-orthographic"] = ("orthographic: parallel rays from toWorld's scaled film square",
        scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35) + sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.45, 0.25, 0.4", 0.25),
              cam=sensor(96, 64, kind="orthographic", params="",
                         transform='<scale x="1.1" y="1.1"/><lookat origin="1.2, 1.7, 3" target="0, 0.8, 0" up="0, 1, 0"/>')),
        ["pt", "bdpt", "mlt"])
    # Mitsuba's particle tracer reaches the orthographic film too (each vertex at its
    # projection, W_e 1/A); its image is the reference (the particle tracer's, above).
    s["camera-orthographic-ptracer"] = (
        "ptracer into an orthographic camera: each vertex splatted at its projection on the film",
        s["camera-orthographic"][1].replace('<integrator type="path">', '<integrator type="ptracer">'),
        ["ptracer"])

    # A sampler changes only the sequence of samples: each must give the same image.
    for kind in ("stratified", "halton", "hammersley", "ldsampler", "sobol"):
        s[f"sampler-{kind}"] = (f"{kind} sampler: the same image as the independent one",
                                scene(sphere(WHITE), cam=sensor(sampler=kind)), ["pt"])

    # Films. mfilm writes NumPy's format, which the reference script turns into a PFM: a
    # linear reference of the film itself. ldrfilm (tone-mapped 8-bit PNG) and tiledhdrfilm
    # (tiled OpenEXR) give none; their references are Mitsuba's hdrfilm images of the same
    # scene ("reference_film" in suite.json), so that they prove only what a film means
    # for the image's radiance: its width, height and reconstruction filter.
    s["film-mfilm"] = ("mfilm (NumPy, rgb): width, height and filter, a linear reference of its own",
                       scene(sphere(WHITE), cam=sensor(80, 48, 40, rfilter="tent", film="mfilm", film_params=
                             '\n      <string name="fileFormat" value="numpy"/>'
                             '\n      <string name="pixelFormat" value="rgb"/>')), ["pt"])
    s["film-ldrfilm"] = ("ldrfilm: width, height and filter against hdrfilm (emlt writes linear radiance)",
                         scene(sphere(WHITE), cam=sensor(48, 72, 40, rfilter="gaussian",
                               rfilter_params='<float name="stddev" value="0.3"/>', film="ldrfilm", film_params=
                               '\n      <string name="pixelFormat" value="rgb"/>')), ["pt"])
    s["film-tiledhdrfilm"] = ("tiledhdrfilm: width, height and filter against hdrfilm",
                              scene(sphere(WHITE), cam=sensor(96, 56, 45, rfilter="mitchell", film="tiledhdrfilm",
                                    film_params='\n      <string name="pixelFormat" value="rgb"/>')), ["pt"])
    # A crop window renders its part of the film alone, framed by the whole film (not
    # re-framed), and filters its border pixels as an image's (the default Gaussian).
    s["film-crop"] = ("crop window 64x40 at (20, 28) of a 96x72 film: the window alone, framed by the film",
                      scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35) + sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.45, 0.25, 0.4", 0.25),
                            cam=sensor(96, 72, 45, rfilter="gaussian", film_params=HDR_PFM +
                                       '\n      <integer name="cropOffsetX" value="20"/>'
                                       '\n      <integer name="cropOffsetY" value="28"/>'
                                       '\n      <integer name="cropWidth" value="64"/>'
                                       '\n      <integer name="cropHeight" value="40"/>')), pt_bdpt)
    # Mitsuba 0.6's box reads a radius: each sample counts for every pixel within it.
    s["film-box-radius"] = ("box filter of radius 1.5 (a sample counts for the pixels within 1.5 on each axis)",
                            scene(sphere(WHITE), cam=sensor(rfilter="box",
                                  rfilter_params='<float name="radius" value="1.5"/>')), pt_bdpt)


def main():
    # No options: the suite always goes to tests/conformance/; --help says so without writing.
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    write_assets()
    os.makedirs(SCENES, exist_ok=True)
    manifest = []
    for name, (convention, xml, integrators) in build().items():
        with open(os.path.join(SCENES, name + ".xml"), "w") as f:
            f.write(xml)
        manifest.append({"name": name, "convention": convention, "integrators": integrators})
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
