"""The suite's assets (tests/conformance/scenes/assets/): textures (PNG in its bit depths and
colour chunks, JPEG through cjpeg and djpeg, OpenEXR), meshes (OBJ, PLY, Mitsuba's
serialized format) and the environment map, each written by a small standard-library writer
so that the files are the same bytes on every run."""
import math
import os
import shutil
import struct
import subprocess
import sys
import zlib

from tools.conformance.scene_groups import ASSETS
from tools.scenes.make_textured_room import write_png  # 8-bit RGB PNG, standard library


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
