"""Writes the assets of scenes/textured-room/: textures and a lathe-turned "teapot".

Standard library only (zlib + struct), deterministic, output well under 1 MB:
  bricks.png    wall texture (sRGB, 64x64): warm bricks with light mortar lines
  planks.png    floor texture (sRGB, 64x64): wood planks with a grain ripple
  dents.pfm     bump height for the teapot (linear float, 32x32): a hammered pattern
  teapot.obj    a body of revolution with a spout-free lid knob, with vt (u around the
                axis, v along the profile) and smooth normals

From the repository root:  python3 -m tools.scenes.make_textured_room
"""
import argparse
import math
import os
import struct
import zlib

from tools import ROOT

OUT = os.path.join(ROOT, "scenes", "textured-room")


def write_png(path, width, height, pixels):
    """pixels: rows of (r, g, b) byte triples, row 0 at the top. 8-bit RGB, no filter."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + bytes(v for px in row for v in px) for row in pixels)
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def write_pfm(path, width, height, values):
    """Greyscale values as an RGB PFM; rows given top first, stored bottom first."""
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (width, height))
        for row in reversed(values):
            f.write(b"".join(struct.pack("<fff", v, v, v) for v in row))


def bricks(size=64):
    rows = []
    for y in range(size):
        row = []
        course = y // 8
        for x in range(size):
            xs = (x + (8 if course % 2 else 0)) % size
            mortar = y % 8 == 0 or xs % 16 == 0
            if mortar:
                row.append((200, 196, 188))
            else:
                shade = 20 * ((xs // 16 + course) % 3)
                row.append((150 + shade // 2, 70 + shade // 3, 50))
        rows.append(row)
    return rows


def planks(size=64):
    rows = []
    for y in range(size):
        row = []
        for x in range(size):
            plank = x // 16
            grain = 0.5 + 0.5 * math.sin(0.9 * y + 2.7 * plank + 0.8 * math.sin(0.3 * x))
            edge = x % 16 == 0
            base = 0.55 + 0.1 * (plank % 2) + 0.15 * grain
            if edge:
                base *= 0.45
            row.append((int(230 * base), int(160 * base), int(95 * base)))
        rows.append(row)
    return rows


def dents(size=32):
    values = []
    for y in range(size):
        row = []
        for x in range(size):
            u, v = (x + 0.5) / size, (y + 0.5) / size
            row.append(0.5 + 0.25 * math.sin(6 * math.pi * u) * math.sin(4 * math.pi * v))
        values.append(row)
    return values


def teapot(path, segments=48):
    # Profile (radius, height) from the bottom centre up over the lid to its knob.
    profile = [(0.0, 0.0), (0.55, 0.0), (0.78, 0.12), (0.9, 0.35), (0.88, 0.6),
               (0.75, 0.82), (0.55, 0.95), (0.35, 1.0), (0.3, 1.06), (0.12, 1.1),
               (0.14, 1.22), (0.06, 1.28), (0.0, 1.29)]
    lengths = [0.0]
    for (r0, h0), (r1, h1) in zip(profile, profile[1:]):
        lengths.append(lengths[-1] + math.hypot(r1 - r0, h1 - h0))
    lines = ["# lathe-turned teapot body written by tools/scenes/make_textured_room.py"]
    for i, (r, h) in enumerate(profile):
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            lines.append("v %.5f %.5f %.5f" % (r * math.cos(phi), h, r * math.sin(phi)))
            lines.append("vt %.5f %.5f" % (s / segments, 1.0 - lengths[i] / lengths[-1]))
    ring = segments + 1
    for i in range(len(profile) - 1):
        for s in range(segments):
            a, b = i * ring + s + 1, i * ring + s + 2
            c, d = a + ring, b + ring
            # Counter-clockwise seen from outside, so the normal points outwards.
            if profile[i][0] > 0.0:
                lines.append("f %d/%d %d/%d %d/%d" % (a, a, d, d, b, b))
            if profile[i + 1][0] > 0.0:
                lines.append("f %d/%d %d/%d %d/%d" % (a, a, c, c, d, d))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    # No options: the assets always go to scenes/textured-room/; --help says so without writing.
    argparse.ArgumentParser(description=__doc__,
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    os.makedirs(OUT, exist_ok=True)
    write_png(os.path.join(OUT, "bricks.png"), 64, 64, bricks())
    write_png(os.path.join(OUT, "planks.png"), 64, 64, planks())
    write_pfm(os.path.join(OUT, "dents.pfm"), 32, 32, dents())
    teapot(os.path.join(OUT, "teapot.obj"))


if __name__ == "__main__":
    main()
