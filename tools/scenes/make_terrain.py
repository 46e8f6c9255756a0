"""Writes the meshes of scenes/env-terrain/ (about 1.03 million triangles, 30 MB) into
scenes/env-terrain/cache/, which git ignores: the performance suite (bench/run.sh) runs
this when the files are missing, so the repository holds only this script.

  terrain.ply   a 2 x 640 x 640-triangle height field of rolling hills with ridges
  rocks.ply     three boulders, each a sphere of 128 x 256 quads displaced by a sum of
                sines (196 608 triangles in all)

Deterministic (sums of sines, no random numbers); binary little-endian PLY with vertex
normals, read by emlt and by Mitsuba 0.6 alike. numpy only.
  python3 -m tools.scenes.make_terrain [--out DIR]      (from the repository root)
"""
import argparse
import os

import numpy as np

from tools import ROOT

DEFAULT_OUT = os.path.join(ROOT, "scenes", "env-terrain", "cache")


def write_ply(path, positions, normals, triangles):
    vertices = np.hstack([positions, normals]).astype("<f4")
    faces = np.zeros(len(triangles), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"] = 3
    faces["i"] = triangles
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(vertices)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        f"element face {len(faces)}\n"
        "property list uchar int vertex_indices\nend_header\n")
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(vertices.tobytes())
        f.write(faces.tobytes())
    os.replace(tmp, path)  # a reader never sees a half-written mesh


def grid_triangles(rows, cols, wrap_cols=False):
    """Two triangles per quad of a (rows+1) x (cols+1) vertex grid (cols if wrapped)."""
    width = cols if wrap_cols else cols + 1
    r, c = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    a = r * width + c
    b = r * width + (c + 1) % width if wrap_cols else a + 1
    d = a + width
    e = b + width
    first = np.stack([a, d, b], axis=-1).reshape(-1, 3)
    second = np.stack([b, d, e], axis=-1).reshape(-1, 3)
    return np.vstack([first, second])


def vertex_normals(positions, triangles):
    p = positions[triangles]
    face = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])  # area-weighted
    normals = np.zeros_like(positions)
    for corner in range(3):
        np.add.at(normals, triangles[:, corner], face)
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def height(x, z):
    return (0.9 * np.sin(0.35 * x) * np.cos(0.27 * z) + 0.45 * np.sin(0.9 * x + 1.3 * z)
            + 0.12 * np.abs(np.sin(2.7 * x - 1.1 * z)) + 0.05 * np.sin(7.3 * x) * np.sin(6.1 * z))


def terrain(n=640, extent=40.0):
    s = np.linspace(-extent / 2, extent / 2, n + 1)
    x, z = np.meshgrid(s, s, indexing="ij")
    positions = np.stack([x, height(x, z), z], axis=-1).reshape(-1, 3)
    triangles = grid_triangles(n, n)
    return positions, triangles


def boulder(centre, radius, phase, rows=128, cols=256):
    theta = np.linspace(0, np.pi, rows + 1)
    phi = np.linspace(0, 2 * np.pi, cols, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    bumps = 1 + 0.12 * np.sin(5 * t + phase) * np.cos(4 * p) + 0.04 * np.sin(17 * t) * np.sin(13 * p + phase)
    r = radius * bumps
    positions = np.stack([r * np.sin(t) * np.cos(p), r * np.cos(t), r * np.sin(t) * np.sin(p)], axis=-1)
    positions = positions.reshape(-1, 3) + np.asarray(centre)
    triangles = grid_triangles(rows, cols, wrap_cols=True)[:, ::-1]  # wound outward
    # The poles' rings collapse to a point: drop the degenerate triangles there.
    p = positions[triangles]
    area = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    return positions, triangles[area > 1e-12]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=DEFAULT_OUT)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    positions, triangles = terrain()
    write_ply(os.path.join(args.out, "terrain.ply"), positions,
              vertex_normals(positions, triangles), triangles)
    count = len(triangles)

    parts = []
    for centre, radius, phase in (((-2.0, 1.6, 2.0), 1.4, 0.0), ((1.8, 1.0, 4.5), 0.9, 1.7),
                                  ((3.5, 1.3, -0.5), 0.7, 3.1)):
        centre = (centre[0], centre[1] + float(height(centre[0], centre[2])) - 0.3, centre[2])
        parts.append(boulder(centre, radius, phase))
    offsets = np.cumsum([0] + [len(p) for p, _ in parts[:-1]])
    positions = np.vstack([p for p, _ in parts])
    triangles = np.vstack([t + o for (_, t), o in zip(parts, offsets)])
    write_ply(os.path.join(args.out, "rocks.ply"), positions,
              vertex_normals(positions, triangles), triangles)
    count += len(triangles)
    print(f"make_terrain: {count} triangles in {os.path.normpath(args.out)}")


if __name__ == "__main__":
    main()
