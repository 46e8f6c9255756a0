"""Writes the procedural interior scenes of the EMLT test set:

  scenes/staircase/       a two-storey hall: recessed light above the top of the stairs,
                          the space under the gallery and the stairs lit only by bounces
  scenes/bedroom/         the only light is behind thick, partly drawn curtains
  scenes/kitchen/         glossy counters and appliances, back wall washed by hidden
                          under-cabinet lights
  scenes/classroom/       sky and sun entering through a row of windows; desks and chairs
  scenes/breakfast-room/  environment map only, big windows: direct sky and sun dominate
  scenes/sponza-like/     environment map only: an open courtyard with two storeys of arcades

Every scene folder gets scene.json, meshes/*.obj (boxes, extruded stairs, lathe surfaces,
folded curtains, arches) and, where lit by the sky, sky.hdr (made with tools/scenes/make_sky.py's
functions, with the sun moved per scene). All geometry is procedural: no third-party data.

Python 3 and numpy only; deterministic (same command, same bytes). From the repository root:
    python3 -m tools.scenes.make_scenes                    # writes all six scenes
    python3 -m tools.scenes.make_scenes kitchen bedroom    # only these
    python3 -m tools.scenes.make_scenes --out /tmp/scenes  # somewhere else
"""
import argparse
import json
import math
import os

import numpy as np

from tools import ROOT
from tools.scenes import make_sky  # the lat-long sky writer


def fmt(x):
    """Four decimals, no negative zero: short, deterministic OBJ and JSON numbers."""
    v = round(float(x), 4)
    if v == 0.0:
        v = 0.0
    return v


def fmt_str(x):
    s = f"{fmt(x):.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


# --------------------------------------------------------------------------------------
# Meshes
# --------------------------------------------------------------------------------------
class Mesh:
    """An indexed polygon mesh written as OBJ; vertices are merged at 1e-4 precision."""

    def __init__(self):
        self.verts = []
        self.faces = []
        self.index = {}

    def vert(self, p):
        key = tuple(fmt(c) for c in p)
        if key not in self.index:
            self.index[key] = len(self.verts)
            self.verts.append(key)
        return self.index[key]

    def poly(self, pts):
        """A convex planar polygon; repeated corners are dropped (so quads may collapse to
        triangles) and polygons with fewer than three distinct corners are skipped."""
        ids = [self.vert(p) for p in pts]
        out = []
        for i in ids:
            if not out or out[-1] != i:
                out.append(i)
        while len(out) > 1 and out[0] == out[-1]:
            out.pop()
        if len(set(out)) < 3 or len(set(out)) != len(out):
            return
        p = np.array([self.verts[i] for i in out])
        n = np.zeros(3)
        for k in range(1, len(p) - 1):
            n += np.cross(p[k] - p[0], p[k + 1] - p[0])
        if np.linalg.norm(n) < 1e-9:
            return
        self.faces.append(out)

    def box(self, lo, hi):
        """Axis-aligned box with outward-facing polygons."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        x0, x1 = min(x0, x1), max(x0, x1)
        y0, y1 = min(y0, y1), max(y0, y1)
        z0, z1 = min(z0, z1), max(z0, z1)
        c = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
             (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
        for f in ((0, 3, 2, 1), (4, 5, 6, 7), (0, 4, 7, 3), (1, 2, 6, 5), (0, 1, 5, 4), (3, 7, 6, 2)):
            self.poly([c[i] for i in f])

    def prism_x(self, x0, x1, zy):
        """Extrusion along x of a convex polygon given as (z, y) corners."""
        a = [(x0, y, z) for z, y in zy]
        b = [(x1, y, z) for z, y in zy]
        self.poly(a[::-1])
        self.poly(b)
        for i in range(len(zy)):
            j = (i + 1) % len(zy)
            self.poly([a[i], a[j], b[j], b[i]])

    def lathe(self, profile, center=(0, 0, 0), segments=24, cap_top=False, cap_bottom=False):
        """Surface of revolution about the vertical axis through center; profile is a list
        of (radius, height) from bottom to top. Radius 0 closes the surface at the axis."""
        cx, cy, cz = center
        rings = []
        for r, y in profile:
            ring = []
            for s in range(segments):
                a = 2.0 * math.pi * s / segments
                ring.append((cx + r * math.cos(a), cy + y, cz + r * math.sin(a)))
            rings.append(ring)
        for j in range(len(rings) - 1):
            lo, hi = rings[j], rings[j + 1]
            for s in range(segments):
                t = (s + 1) % segments
                self.poly([lo[s], hi[s], hi[t], lo[t]])
        if cap_bottom:
            self.poly(rings[0])
        if cap_top:
            self.poly(rings[-1][::-1])

    def add(self, other, rotate_y=0.0, offset=(0, 0, 0)):
        """Merges another mesh, rotated about +y by rotate_y degrees, then translated."""
        a = math.radians(rotate_y)
        c, s = math.cos(a), math.sin(a)
        ox, oy, oz = offset
        moved = [(c * x + s * z + ox, y + oy, -s * x + c * z + oz) for x, y, z in other.verts]
        for f in other.faces:
            self.poly([moved[i] for i in f])

    def triangles(self):
        return sum(len(f) - 2 for f in self.faces)

    def write(self, path, comment):
        lines = [f"# {comment}", "# generated by tools/scenes/make_scenes.py (procedural, no third-party data)"]
        lines += ["v " + " ".join(fmt_str(c) for c in v) for v in self.verts]
        lines += ["f " + " ".join(str(i + 1) for i in f) for f in self.faces]
        with open(path, "w", newline="\n") as f:
            f.write("\n".join(lines) + "\n")


def wall(mesh, axis, c0, c1, urange, vrange, holes=()):
    """A wall slab between c0 and c1 along `axis` ('x', 'y' or 'z'), spanning urange x vrange
    in the other two axes ((z, y) for x, (x, z) for y, (x, y) for z), with rectangular holes
    (u0, u1, v0, v1). Decomposed into boxes, column strip by column strip."""
    us = sorted({urange[0], urange[1]} | {h[0] for h in holes} | {h[1] for h in holes})
    for ua, ub in zip(us[:-1], us[1:]):
        if ub - ua < 1e-6:
            continue
        cut = sorted((h[2], h[3]) for h in holes if h[0] <= ua + 1e-9 and h[1] >= ub - 1e-9)
        v = vrange[0]
        spans = []
        for va, vb in cut:
            if va > v:
                spans.append((v, va))
            v = max(v, vb)
        if v < vrange[1]:
            spans.append((v, vrange[1]))
        for va, vb in spans:
            if axis == "x":
                mesh.box((c0, va, ua), (c1, vb, ub))
            elif axis == "y":
                mesh.box((ua, c0, va), (ub, c1, vb))
            else:
                mesh.box((ua, va, c0), (ub, vb, c1))


def window_frame(mesh, axis, c0, c1, hole, mullions_u=1, mullions_v=1, bar=0.05):
    """A frame lining a hole (u0, u1, v0, v1) of a wall on `axis` (see wall()), with
    mullions_u - 1 vertical and mullions_v - 1 horizontal bars."""
    u0, u1, v0, v1 = hole
    rects = [(u0, u0 + bar, v0, v1), (u1 - bar, u1, v0, v1), (u0, u1, v0, v0 + bar), (u0, u1, v1 - bar, v1)]
    for i in range(1, mullions_u):
        u = u0 + (u1 - u0) * i / mullions_u
        rects.append((u - bar / 2, u + bar / 2, v0, v1))
    for i in range(1, mullions_v):
        v = v0 + (v1 - v0) * i / mullions_v
        rects.append((u0, u1, v - bar / 2, v + bar / 2))
    for ua, ub, va, vb in rects:
        if axis == "x":
            mesh.box((c0, va, ua), (c1, vb, ub))
        else:
            mesh.box((ua, va, c0), (ub, vb, c1))


def room_shell(walls, floor, ceiling, x, y, z, t=0.2, holes=None):
    """Closed room [x0,x1] x [y0,y1] x [z0,z1] from slabs of thickness t outside it; the
    slabs overlap at the edges so no light leaks. holes: {'x0'|'x1'|'z0'|'z1'|'y1': [...]}."""
    holes = holes or {}
    (x0, x1), (y0, y1), (z0, z1) = x, y, z
    wall(floor, "y", y0 - t, y0, (x0 - t, x1 + t), (z0 - t, z1 + t), holes.get("y0", ()))
    wall(ceiling, "y", y1, y1 + t, (x0 - t, x1 + t), (z0 - t, z1 + t), holes.get("y1", ()))
    wall(walls, "x", x0 - t, x0, (z0 - t, z1 + t), (y0, y1), holes.get("x0", ()))
    wall(walls, "x", x1, x1 + t, (z0 - t, z1 + t), (y0, y1), holes.get("x1", ()))
    wall(walls, "z", z0 - t, z0, (x0, x1), (y0, y1), holes.get("z0", ()))
    wall(walls, "z", z1, z1 + t, (x0, x1), (y0, y1), holes.get("z1", ()))


def table(width, depth, height, top=0.04, leg=0.05):
    """Table centred on the origin (x width, z depth), standing on y = 0."""
    m = Mesh()
    m.box((-width / 2, height - top, -depth / 2), (width / 2, height, depth / 2))
    for sx in (-1, 1):
        for sz in (-1, 1):
            x = sx * (width / 2 - leg - 0.03)
            z = sz * (depth / 2 - leg - 0.03)
            m.box((x - leg / 2, 0, z - leg / 2), (x + leg / 2, height - top, z + leg / 2))
    return m


def round_table(radius, height, segments=32):
    m = Mesh()
    m.lathe([(0, height - 0.04), (radius, height - 0.04), (radius, height), (0, height)], segments=segments)
    m.lathe([(0, 0), (0.25, 0), (0.25, 0.03), (0.05, 0.06), (0.04, height - 0.04), (0, height - 0.04)], segments=16)
    return m


def chair(seat=0.44, height=0.45, back=0.42, leg=0.035):
    """Chair centred on the origin, its back towards +z (the sitter faces -z)."""
    m = Mesh()
    h = seat / 2
    m.box((-h, height - 0.04, -h), (h, height, h))
    for sx in (-1, 1):
        for sz in (-1, 1):
            x, z = sx * (h - leg), sz * (h - leg)
            top = height + back if sz > 0 else height - 0.04
            m.box((x - leg / 2, 0, z - leg / 2), (x + leg / 2, top, z + leg / 2))
    m.box((-h + leg / 2, height + back - 0.16, h - leg * 1.5), (h - leg / 2, height + back - 0.02, h - leg / 2))
    m.box((-h + leg / 2, height + 0.12, h - leg * 1.5), (h - leg / 2, height + 0.17, h - leg / 2))
    return m


def curtain(x0, x1, y0, y1, z, folds, depth, columns_per_fold=8):
    """A hanging curtain: a sheet in the plane z folded sinusoidally along x."""
    m = Mesh()
    n = folds * columns_per_fold
    xs = np.linspace(x0, x1, n + 1)
    zs = z + 0.5 * depth * np.sin(np.linspace(0.0, 2.0 * math.pi * folds, n + 1))
    rows = np.linspace(y0, y1, 3)
    for i in range(n):
        for j in range(len(rows) - 1):
            m.poly([(xs[i], rows[j], zs[i]), (xs[i + 1], rows[j], zs[i + 1]),
                    (xs[i + 1], rows[j + 1], zs[i + 1]), (xs[i], rows[j + 1], zs[i])])
    return m


def drape(z0, z1, y0, y1, x, folds, depth, columns_per_fold=6):
    """A banner hanging in the plane x, folded along z (for the courtyard)."""
    m = Mesh()
    n = folds * columns_per_fold
    zs = np.linspace(z0, z1, n + 1)
    xs = x + 0.5 * depth * (1 - np.cos(np.linspace(0.0, 2.0 * math.pi * folds, n + 1)))
    rows = np.linspace(y0, y1, 2)
    for i in range(n):
        m.poly([(xs[i], rows[0], zs[i]), (xs[i + 1], rows[0], zs[i + 1]),
                (xs[i + 1], rows[1], zs[i + 1]), (xs[i], rows[1], zs[i])])
    return m


# --------------------------------------------------------------------------------------
# Scene description helpers
# --------------------------------------------------------------------------------------
def clean(v):
    if isinstance(v, float):
        return fmt(v)
    if isinstance(v, (list, tuple)):
        return [clean(x) for x in v]
    if isinstance(v, dict):
        return {k: clean(x) for k, x in v.items()}
    if isinstance(v, np.generic):
        return clean(v.item())
    return v


def rect_matrix(center, normal, up, width, height):
    """Row-major matrix mapping emlt's [-1,1]^2 rectangle (normal +z) to a width x height
    rectangle at center facing `normal`, its height along `up`."""
    n = np.asarray(normal, float)
    n /= np.linalg.norm(n)
    u = np.cross(np.asarray(up, float), n)
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    a, b = u * width / 2, v * height / 2
    c = center
    return [a[0], b[0], n[0], c[0], a[1], b[1], n[1], c[1], a[2], b[2], n[2], c[2], 0, 0, 0, 1]


def rect_light(name, center, normal, up, width, height, radiance, material="lamp"):
    return {"type": "rectangle", "name": name, "material": material, "emission": radiance,
            "transform": [{"matrix": rect_matrix(center, normal, up, width, height)}]}


class SceneWriter:
    def __init__(self, out_root, name):
        self.dir = os.path.join(out_root, name)
        self.name = name
        os.makedirs(os.path.join(self.dir, "meshes"), exist_ok=True)
        self.meshes = {}
        self.shapes = []

    def mesh(self, name, material, smooth=False):
        """A mesh written to meshes/<name>.obj and referenced as one obj shape."""
        if name not in self.meshes:
            m = Mesh()
            self.meshes[name] = m
            shape = {"type": "obj", "name": name, "file": f"meshes/{name}.obj", "material": material}
            if smooth:
                shape["smooth_normals"] = True
            self.shapes.append(shape)
        return self.meshes[name]

    def write(self, camera, materials, integrator, environment=None, size=(160, 120), spp=16):
        for name, m in self.meshes.items():
            m.write(os.path.join(self.dir, "meshes", f"{name}.obj"), f"{self.name}: {name}")
        cam = dict(camera)
        cam["width"], cam["height"] = "$width", "$height"
        scene = {"camera": cam,
                 "defaults": {"width": size[0], "height": size[1], "spp": spp},
                 "integrator": dict(integrator, spp="$spp"),
                 "materials": materials,
                 "shapes": self.shapes}
        if environment:
            scene["environment"] = environment
        scene = clean(scene)
        # One material / shape per line: readable and diff-friendly.
        out = ["{"]
        keys = list(scene)
        for k, key in enumerate(keys):
            comma = "," if k + 1 < len(keys) else ""
            val = scene[key]
            if key in ("materials",):
                out.append(f'  "{key}": {{')
                items = list(val.items())
                for i, (mk, mv) in enumerate(items):
                    c = "," if i + 1 < len(items) else ""
                    out.append(f"    {json.dumps(mk)}: {json.dumps(mv)}{c}")
                out.append("  }" + comma)
            elif key == "shapes":
                out.append(f'  "{key}": [')
                for i, sv in enumerate(val):
                    c = "," if i + 1 < len(val) else ""
                    out.append(f"    {json.dumps(sv)}{c}")
                out.append("  ]" + comma)
            else:
                out.append(f'  "{key}": {json.dumps(val)}{comma}')
        out.append("}")
        with open(os.path.join(self.dir, "scene.json"), "w", newline="\n") as f:
            f.write("\n".join(out) + "\n")
        tris = sum(m.triangles() for m in self.meshes.values())
        print(f"wrote {os.path.relpath(self.dir, ROOT)}: {len(self.shapes)} shapes, {tris} mesh triangles")


def write_sky(path, sun_direction, sun_radiance=1000.0, width=256):
    """tools/scenes/make_sky.py's sky with the sun moved to sun_direction (towards the sun)."""
    saved = make_sky.SUN_DIRECTION, make_sky.SUN_RADIANCE
    try:
        make_sky.SUN_DIRECTION = np.asarray(sun_direction, float)
        make_sky.SUN_RADIANCE = np.array([1.0, 0.93, 0.82]) * sun_radiance
        height = width // 2
        radiance = make_sky.sky_radiance(make_sky.directions(width, height, make_sky.SUPERSAMPLES)).mean(axis=(2, 3))
        make_sky.write_hdr(path, radiance.astype(np.float32))
    finally:
        make_sky.SUN_DIRECTION, make_sky.SUN_RADIANCE = saved


def diffuse(rgb):
    return {"type": "diffuse", "reflectance": rgb}


WHITE_PAINT = [0.72, 0.71, 0.68]


# --------------------------------------------------------------------------------------
# Staircase
# --------------------------------------------------------------------------------------
def staircase(out):
    s = SceneWriter(out, "staircase")
    W, H, D = 5.0, 5.6, 7.0          # hall: x in [0, W], y in [0, H], z in [0, D]
    G0, G1 = 2.7, 2.9                # gallery slab (upper floor) from z = GZ to the back
    GZ = 4.0
    walls, floor, ceiling = s.mesh("walls", "plaster"), s.mesh("floor", "floor"), s.mesh("ceiling", "plaster")
    # Recessed light well above the top of the stairs: the light sits 0.7 m up a shaft.
    well = (0.15, 1.45, 3.1, 4.7)    # x0, x1, z0, z1
    room_shell(walls, floor, ceiling, (0, W), (0, H), (0, D), holes={"y1": [well]})
    shaft = s.mesh("shaft", "plaster")
    wx0, wx1, wz0, wz1 = well
    top = H + 0.9
    shaft.box((wx0 - 0.1, H, wz0 - 0.1), (wx0, top, wz1 + 0.1))
    shaft.box((wx1, H, wz0 - 0.1), (wx1 + 0.1, top, wz1 + 0.1))
    shaft.box((wx0, H, wz0 - 0.1), (wx1, top, wz0))
    shaft.box((wx0, H, wz1), (wx1, top, wz1 + 0.1))
    shaft.box((wx0 - 0.1, top, wz0 - 0.1), (wx1 + 0.1, top + 0.1, wz1 + 0.1))
    # Gallery slab, with a parapet along its edge except where the stairs arrive.
    gallery = s.mesh("gallery", "plaster")
    SW = 1.15                        # stair width, against the x = 0 wall
    gallery.box((0, G0, GZ), (W, G1, D))
    gallery.box((SW + 0.05, G1, GZ), (W, G1 + 1.0, GZ + 0.12))
    gallery_floor = s.mesh("gallery_floor", "floor")
    gallery_floor.box((0, G1, GZ + 0.12), (W, G1 + 0.01, D))
    gallery_floor.box((0, G1, GZ), (SW + 0.05, G1 + 0.01, GZ + 0.12))
    # Stairs: extruded step columns with a sloping soffit, leaving a wedge of space below.
    stairs = s.mesh("stairs", "wood")
    n = 15
    z0 = GZ - 3.5
    run, rise = (GZ - z0) / n, (G1 + 0.01) / n
    soffit = 0.32

    def under(z):
        return max(0.0, (z - z0) * rise / run - soffit)

    for i in range(n):
        za, zb = z0 + i * run, z0 + (i + 1) * run
        ytop = (i + 1) * rise
        pts = [(za, under(za)), (zb, under(zb)), (zb, ytop), (za, ytop)]
        if under(za) == 0.0 and under(zb) > 0.0:
            zc = z0 + soffit * run / rise
            pts = [(za, 0.0), (zc, 0.0), (zb, under(zb)), (zb, ytop), (za, ytop)] if zc < zb else pts
        stairs.prism_x(0.0, SW, pts)
    # Handrail posts and rail on the open side of the stairs and the gallery edge.
    rail = s.mesh("rail", "dark_wood")
    for i in range(0, n, 3):
        z = z0 + (i + 0.5) * run
        y = (i + 1) * rise
        rail.box((SW - 0.06, y, z - 0.025), (SW - 0.01, y + 0.9, z + 0.025))
    rail.prism_x(SW - 0.08, SW + 0.01, [(z0, 0.9 + rise), (GZ, 0.9 + G1), (GZ, 0.95 + G1), (z0, 0.95 + rise)])
    # Furniture: a bench and cabinet under the gallery, a chest under the stairs, a table
    # and chairs in front, a bookcase and a chair up on the gallery.
    furniture = s.mesh("furniture", "oak")
    furniture.box((2.2, 0, D - 0.5), (4.6, 0.9, D - 0.05))          # low cabinet, back wall
    furniture.box((W - 0.45, 0, 4.6), (W - 0.05, 1.9, 5.6))          # tall cupboard
    furniture.box((0.05, 0, 2.3), (0.8, 0.55, 3.3))                  # chest under the stairs
    furniture.add(table(1.2, 0.8, 0.75), 0, (2.9, 0, 5.3))
    furniture.add(chair(), 180, (2.9, 0, 4.6))
    furniture.add(chair(), 0, (2.9, 0, 6.0))
    furniture.box((2.5, G1, D - 0.4), (4.5, G1 + 2.0, D - 0.05))      # bookcase upstairs
    furniture.add(chair(), 20, (2.0, G1, 5.4))
    books = s.mesh("books", "books")
    for k in range(3):
        y = G1 + 0.1 + 0.6 * k
        books.box((2.55, y, D - 0.38), (4.45, y + 0.45, D - 0.1))
    rug = s.mesh("rug", "rug")
    rug.box((1.8, 0, 0.9), (4.8, 0.01, 3.2))
    # Camera on the lower floor, across from the stairs: the light well and the gallery on
    # the left, the stairs rising towards them, the space under the gallery below.
    camera = {"lookat": {"origin": [4.85, 1.4, 1.0], "target": [0.0, 2.4, 4.2], "up": [0, 1, 0]}, "fov": 85}
    lamp_y = top - 0.001
    shapes_light = rect_light("ceiling light", [(wx0 + wx1) / 2, lamp_y, (wz0 + wz1) / 2], [0, -1, 0], [0, 0, 1],
                              wx1 - wx0 - 0.02, wz1 - wz0 - 0.02, [30, 27, 22])
    s.shapes.append(shapes_light)
    materials = {
        "plaster": diffuse(WHITE_PAINT),
        "floor": diffuse([0.45, 0.35, 0.26]),
        "wood": {"type": "roughplastic", "alpha": 0.25, "diffuse_reflectance": [0.5, 0.32, 0.18], "int_ior": 1.5},
        "dark_wood": diffuse([0.18, 0.11, 0.07]),
        "oak": diffuse([0.55, 0.42, 0.28]),
        "books": diffuse([0.45, 0.2, 0.15]),
        "rug": diffuse([0.35, 0.12, 0.1]),
        "lamp": diffuse(0.8),
    }
    s.write(camera, materials, {"type": "pt", "max_depth": 12})


# --------------------------------------------------------------------------------------
# Bedroom
# --------------------------------------------------------------------------------------
def bedroom(out):
    s = SceneWriter(out, "bedroom")
    W, H, D = 4.0, 2.7, 5.0
    window = (1.3, 2.7, 0.9, 2.2)                     # x0, x1, y0, y1 in the z = D wall
    walls, floor, ceiling = s.mesh("walls", "paint"), s.mesh("floor", "floor"), s.mesh("ceiling", "ceiling")
    room_shell(walls, floor, ceiling, (0, W), (0, H), (0, D), t=0.25, holes={"z1": [window]})
    # Outside the window: a closed box so the opening is lit only by the panel inside it.
    outside = s.mesh("outside", "paint")
    x0, x1, y0, y1 = window
    outside.box((x0 - 0.1, y0 - 0.1, D + 0.45), (x1 + 0.1, y1 + 0.1, D + 0.55))
    frame = s.mesh("window_frame", "frame")
    window_frame(frame, "z", D + 0.08, D + 0.14, window, mullions_u=2, mullions_v=1, bar=0.06)
    # Thick curtains on a rail 18 cm in front of the wall, drawn almost shut: light leaks
    # through the middle gap and around the edges after bouncing between curtain and wall.
    cz = D - 0.18
    gap = 0.18
    cx = (x0 + x1) / 2
    curtains = s.mesh("curtains", "curtain", smooth=True)
    curtains.add(curtain(x0 - 0.35, cx - gap / 2, 0.35, 2.45, cz, folds=6, depth=0.09))
    curtains.add(curtain(cx + gap / 2, x1 + 0.35, 0.35, 2.45, cz, folds=6, depth=0.09))
    rail = s.mesh("rail", "metal")
    rail.box((x0 - 0.45, 2.46, cz - 0.02), (x1 + 0.45, 2.5, cz + 0.02))
    # Bed against the left wall (x = 0), headboard there.
    bed = s.mesh("bed_frame", "wood")
    bed.box((0.0, 0.0, 2.1), (0.08, 1.1, 3.8))                       # headboard
    bed.box((0.08, 0.1, 2.15), (2.2, 0.32, 3.75))                    # base
    for x in (0.12, 2.12):
        for z in (2.19, 3.67):
            bed.box((x, 0, z), (x + 0.06, 0.1, z + 0.06))
    linen = s.mesh("mattress", "linen")
    linen.box((0.08, 0.32, 2.18), (2.15, 0.55, 3.72))
    linen.box((0.15, 0.55, 2.3), (0.55, 0.68, 2.9))                  # pillows
    linen.box((0.15, 0.55, 3.0), (0.55, 0.68, 3.6))
    duvet = s.mesh("duvet", "duvet")
    duvet.box((0.7, 0.55, 2.12), (2.2, 0.62, 3.78))
    duvet.box((2.18, 0.3, 2.12), (2.22, 0.62, 3.78))
    # Nightstand with a lamp (switched off), a wardrobe, a chest of drawers, a rug, a picture.
    furniture = s.mesh("furniture", "wood")
    furniture.box((0.05, 0, 4.0), (0.5, 0.55, 4.5))
    furniture.box((W - 0.6, 0, 0.9), (W - 0.02, 2.1, 2.5))           # wardrobe
    furniture.box((W - 0.5, 0, 3.2), (W - 0.02, 0.85, 4.4))          # drawers
    handles = s.mesh("handles", "metal")
    for z in (1.65, 1.75):
        handles.box((W - 0.63, 0.95, z - 0.01), (W - 0.6, 1.25, z + 0.01))
    for y in (0.25, 0.55):
        handles.box((W - 0.53, y, 3.7), (W - 0.5, y + 0.03, 3.9))
    shade = s.mesh("lampshade", "shade", smooth=True)
    shade.lathe([(0.0, 0.55), (0.08, 0.55), (0.06, 0.6), (0.015, 0.62), (0.015, 0.8)], center=(0.27, 0, 4.25), segments=16)
    shade.lathe([(0.12, 0.78), (0.08, 0.98)], center=(0.27, 0, 4.25), segments=24)
    rug = s.mesh("rug", "rug")
    rug.box((1.2, 0, 1.4), (3.2, 0.012, 4.2))
    picture = s.mesh("picture", "picture")
    picture.box((W - 0.03, 1.3, 3.3), (W - 0.01, 1.9, 4.3))
    # The panel light behind the curtains: in the window opening, facing into the room.
    s.shapes.append(rect_light("window panel", [cx, (y0 + y1) / 2, D + 0.3], [0, 0, -1], [0, 1, 0],
                               x1 - x0, y1 - y0, [60, 55, 45]))
    camera = {"lookat": {"origin": [3.35, 1.55, 0.3], "target": [1.7, 1.1, 4.6], "up": [0, 1, 0]}, "fov": 70}
    materials = {
        "paint": diffuse([0.75, 0.7, 0.6]),
        "ceiling": diffuse(0.8),
        "floor": {"type": "roughplastic", "alpha": 0.3, "diffuse_reflectance": [0.42, 0.3, 0.2], "int_ior": 1.5},
        "frame": diffuse(0.8),
        "curtain": diffuse([0.55, 0.2, 0.15]),
        "metal": {"type": "roughconductor", "alpha": 0.3, "material": "Al"},
        "wood": diffuse([0.45, 0.3, 0.18]),
        "linen": diffuse([0.8, 0.78, 0.72]),
        "duvet": diffuse([0.25, 0.35, 0.55]),
        "shade": diffuse([0.85, 0.8, 0.65]),
        "rug": diffuse([0.6, 0.55, 0.4]),
        "picture": diffuse([0.2, 0.4, 0.35]),
        "lamp": diffuse(0.8),
    }
    s.write(camera, materials, {"type": "pt", "max_depth": 12})


# --------------------------------------------------------------------------------------
# Kitchen
# --------------------------------------------------------------------------------------
def kitchen(out):
    s = SceneWriter(out, "kitchen")
    W, H, D = 4.2, 2.6, 4.0
    walls, floor, ceiling = s.mesh("walls", "paint"), s.mesh("floor_slab", "paint"), s.mesh("ceiling", "paint")
    room_shell(walls, floor, ceiling, (0, W), (0, H), (0, D))
    # Back wall tiles (glossy) between counter and upper cabinets.
    tiles = s.mesh("backsplash", "tiles")
    tiles.box((0.05, 0.9, D - 0.01), (W - 0.05, 1.6, D))
    # Base cabinets + worktop along the back wall, fridge at the right end (x = W side).
    FX = W - 0.85
    cabinets = s.mesh("cabinets", "cabinet")
    cabinets.box((0.05, 0.1, D - 0.6), (FX - 0.05, 0.88, D))
    for x in np.arange(0.05, FX - 0.1, 0.6):                          # door gaps as shallow fronts
        cabinets.box((x + 0.01, 0.12, D - 0.615), (min(x + 0.59, FX - 0.06), 0.86, D - 0.6))
    plinth = s.mesh("plinth", "dark")
    plinth.box((0.08, 0, D - 0.56), (FX - 0.08, 0.1, D))
    top = s.mesh("worktop", "granite")
    top.box((0.05, 0.88, D - 0.63), (FX - 0.05, 0.92, D))
    # Upper cabinets left and right of a range hood; lights hidden under them.
    uppers = s.mesh("upper_cabinets", "cabinet")
    spans = [(0.05, 1.5), (2.3, FX - 0.05)]
    for a, b in spans:
        uppers.box((a, 1.6, D - 0.35), (b, 2.3, D))
    hood = s.mesh("hood", "steel")
    hood.box((1.6, 1.75, D - 0.5), (2.2, 1.85, D))
    hood.box((1.75, 1.85, D - 0.3), (2.05, H, D))
    # Oven under the hob, hob, sink.
    oven = s.mesh("oven", "chrome")
    oven.box((1.62, 0.15, D - 0.625), (2.18, 0.8, D - 0.605))
    glass = s.mesh("oven_window", "black_glass")
    glass.box((1.7, 0.3, D - 0.63), (2.1, 0.62, D - 0.62))
    hob = s.mesh("hob", "black_glass")
    hob.box((1.6, 0.92, D - 0.55), (2.2, 0.925, D - 0.05))
    sink = s.mesh("sink", "steel")
    sink.box((0.5, 0.92, D - 0.5), (1.1, 0.93, D - 0.1))
    sink.lathe([(0.015, 0.93), (0.015, 1.25), (0.0, 1.25)], center=(0.8, 0, D - 0.06), segments=8)
    sink.box((0.785, 1.22, D - 0.3), (0.815, 1.25, D - 0.05))
    # Fridge: brushed steel.
    fridge = s.mesh("fridge", "steel")
    fridge.box((FX, 0, D - 0.7), (W - 0.05, 1.95, D))
    handles = s.mesh("handles", "chrome")
    handles.box((FX + 0.06, 0.9, D - 0.74), (FX + 0.08, 1.5, D - 0.7))
    # Kettle (copper lathe surface) and a bowl on the worktop; pots on the hob.
    kettle = s.mesh("kettle", "copper", smooth=True)
    kettle.lathe([(0.0, 0.0), (0.09, 0.0), (0.11, 0.04), (0.115, 0.09), (0.1, 0.15), (0.06, 0.19),
                  (0.025, 0.2), (0.02, 0.22), (0.0, 0.23)], center=(2.7, 0.92, D - 0.3), segments=24)
    pot = s.mesh("pot", "steel", smooth=True)
    pot.lathe([(0.0, 0.0), (0.12, 0.0), (0.12, 0.14), (0.11, 0.14), (0.11, 0.01), (0.0, 0.01)],
              center=(1.75, 0.925, D - 0.35), segments=24)
    bowl = s.mesh("bowl", "ceramic", smooth=True)
    bowl.lathe([(0.0, 0.0), (0.05, 0.0), (0.12, 0.06), (0.14, 0.1), (0.13, 0.1), (0.1, 0.06), (0.0, 0.02)],
               center=(3.0, 0.92, D - 0.35), segments=24)
    # A small table with two stools in the foreground.
    furniture = s.mesh("table", "oak")
    furniture.add(table(1.1, 0.7, 0.76), 0, (1.2, 0, 1.6))
    stool = Mesh()
    stool.lathe([(0.0, 0.6), (0.17, 0.6), (0.17, 0.64), (0.0, 0.64)], segments=16)
    stool.lathe([(0.02, 0.0), (0.02, 0.6)], segments=8)
    stool.lathe([(0.0, 0.0), (0.16, 0.0), (0.16, 0.02), (0.0, 0.02)], segments=16)
    furniture.add(stool, 0, (0.55, 0, 1.6))
    furniture.add(stool, 0, (1.95, 0, 1.3))
    # Floor: tiled rough plastic (checkerboard), a rectangle just above the slab.
    s.shapes.append({"type": "rectangle", "name": "floor", "material": "floor_tiles",
                     "transform": [{"matrix": rect_matrix([W / 2, 0.002, D / 2], [0, 1, 0], [0, 0, 1], W, D)}]})
    # Under-cabinet light strips (facing down, close to the wall): they wash the tiled
    # back wall and the worktop; a dim ceiling panel gives the room some fill.
    for i, (a, b) in enumerate(spans):
        s.shapes.append(rect_light(f"under-cabinet light {i}", [(a + b) / 2, 1.599, D - 0.12], [0, -1, 0],
                                   [0, 0, 1], b - a - 0.1, 0.06, [140, 120, 90]))
    camera = {"lookat": {"origin": [2.6, 1.7, 0.25], "target": [1.9, 1.05, D], "up": [0, 1, 0]}, "fov": 66}
    materials = {
        "paint": diffuse([0.7, 0.68, 0.62]),
        "tiles": {"type": "roughplastic", "alpha": 0.08, "diffuse_reflectance": [0.8, 0.78, 0.72], "int_ior": 1.5},
        "cabinet": {"type": "roughplastic", "alpha": 0.15, "diffuse_reflectance": [0.35, 0.45, 0.4], "int_ior": 1.5},
        "granite": {"type": "roughplastic", "alpha": 0.04, "diffuse_reflectance": [0.06, 0.055, 0.05], "int_ior": 1.55},
        "dark": diffuse(0.05),
        "steel": {"type": "roughconductor", "alpha": 0.2, "material": "Al"},
        "chrome": {"type": "roughconductor", "alpha": 0.08, "material": "Cr"},
        "copper": {"type": "roughconductor", "alpha": 0.1, "material": "Cu"},
        "black_glass": {"type": "roughplastic", "alpha": 0.03, "diffuse_reflectance": 0.02, "int_ior": 1.5},
        "ceramic": {"type": "roughplastic", "alpha": 0.1, "diffuse_reflectance": [0.7, 0.25, 0.1], "int_ior": 1.5},
        "oak": {"type": "roughplastic", "alpha": 0.3, "diffuse_reflectance": [0.5, 0.35, 0.2], "int_ior": 1.5},
        "floor_tiles": {"type": "roughplastic", "alpha": 0.15, "int_ior": 1.5,
                        "diffuse_reflectance": {"type": "checkerboard", "color0": [0.6, 0.58, 0.55],
                                                "color1": [0.15, 0.14, 0.13], "uvscale": 8}},
        "lamp": diffuse(0.8),
    }
    s.write(camera, materials, {"type": "pt", "max_depth": 12})


# --------------------------------------------------------------------------------------
# Classroom
# --------------------------------------------------------------------------------------
def classroom(out):
    s = SceneWriter(out, "classroom")
    W, H, D = 8.0, 3.2, 7.0
    windows = [(z, z + 1.5, 0.9, 2.8) for z in (0.8, 2.8, 4.8)]      # in the x = 0 wall
    walls, floor, ceiling = s.mesh("walls", "paint"), s.mesh("floor", "floor"), s.mesh("ceiling", "ceiling")
    room_shell(walls, floor, ceiling, (0, W), (0, H), (0, D), t=0.25, holes={"x0": windows})
    frames = s.mesh("window_frames", "frame")
    for w in windows:
        window_frame(frames, "x", -0.16, -0.1, w, mullions_u=2, mullions_v=2, bar=0.06)
        frames.box((-0.25, w[2] - 0.04, w[0] - 0.05), (0.1, w[2], w[1] + 0.05))  # sill
    # Blackboard on the front wall (z = D), teacher's desk, pupils' desks and chairs.
    board = s.mesh("blackboard", "blackboard")
    board.box((2.0, 0.95, D - 0.03), (6.5, 2.2, D))
    board_frame = s.mesh("board_frame", "oak")
    board_frame.box((1.95, 0.9, D - 0.08), (6.55, 0.95, D))
    desks = s.mesh("desks", "oak")
    chairs = s.mesh("chairs", "chair")
    steel = s.mesh("desk_frames", "steel")
    for row in range(3):
        for col in range(3):
            x = 1.7 + 2.1 * col
            z = 1.2 + 1.5 * row
            desks.box((x - 0.6, 0.72, z - 0.3), (x + 0.6, 0.75, z + 0.3))
            for sx in (-1, 1):
                steel.box((x + sx * 0.55 - 0.02, 0, z - 0.25), (x + sx * 0.55 + 0.02, 0.72, z - 0.21))
                steel.box((x + sx * 0.55 - 0.02, 0, z + 0.21), (x + sx * 0.55 + 0.02, 0.72, z + 0.25))
                steel.box((x + sx * 0.55 - 0.02, 0.05, z - 0.25), (x + sx * 0.55 + 0.02, 0.09, z + 0.25))
            for dx in (-0.3, 0.3):
                chairs.add(chair(seat=0.4, height=0.44, back=0.38), 180, (x + dx, 0, z - 0.55))
    desks.box((5.0, 0.74, D - 1.4), (6.6, 0.78, D - 0.8))               # teacher's desk
    desks.box((5.02, 0, D - 1.38), (5.1, 0.74, D - 0.82))
    desks.box((6.5, 0, D - 1.38), (6.58, 0.74, D - 0.82))
    desks.box((5.1, 0.3, D - 0.85), (6.5, 0.74, D - 0.82))
    shelves = s.mesh("shelves", "oak")
    for y in (0.0, 0.5, 1.0, 1.5):
        shelves.box((W - 0.4, y, 1.0), (W - 0.02, y + 0.03, 4.0))
    shelves.box((W - 0.4, 0, 0.97), (W - 0.02, 1.53, 1.0))
    shelves.box((W - 0.4, 0, 4.0), (W - 0.02, 1.53, 4.03))
    books = s.mesh("books", "books")
    for k, y in enumerate((0.03, 0.53, 1.03)):
        books.box((W - 0.35, y, 1.1 + 0.2 * k), (W - 0.05, y + 0.3, 3.4 - 0.3 * k))
    write_sky(os.path.join(s.dir, "sky.hdr"), make_sky.SUN_DIRECTION)
    camera = {"lookat": {"origin": [7.5, 1.75, 0.3], "target": [3.0, 1.0, 6.0], "up": [0, 1, 0]}, "fov": 72}
    materials = {
        "paint": diffuse([0.75, 0.73, 0.65]),
        "ceiling": diffuse(0.8),
        "floor": {"type": "roughplastic", "alpha": 0.25, "diffuse_reflectance": [0.45, 0.33, 0.22], "int_ior": 1.5},
        "frame": diffuse(0.85),
        "blackboard": {"type": "roughplastic", "alpha": 0.3, "diffuse_reflectance": [0.04, 0.09, 0.06], "int_ior": 1.5},
        "oak": diffuse([0.6, 0.45, 0.28]),
        "chair": diffuse([0.2, 0.3, 0.5]),
        "steel": {"type": "roughconductor", "alpha": 0.3, "material": "Al"},
        "books": diffuse([0.5, 0.25, 0.15]),
    }
    s.write(camera, materials, {"type": "pt", "max_depth": 10},
            environment={"type": "envmap", "file": "sky.hdr", "scale": 6})


# --------------------------------------------------------------------------------------
# Breakfast room
# --------------------------------------------------------------------------------------
def breakfast_room(out):
    s = SceneWriter(out, "breakfast-room")
    W, H, D = 6.0, 3.0, 5.0
    side = (0.4, 4.6, 0.35, 2.75)        # nearly the whole x = 0 wall is glass (open)
    back = (0.8, 3.6, 0.35, 2.75)        # a second big window in the z = D wall
    walls, floor, ceiling = s.mesh("walls", "paint"), s.mesh("floor", "floor"), s.mesh("ceiling", "ceiling")
    room_shell(walls, floor, ceiling, (0, W), (0, H), (0, D), holes={"x0": [side], "z1": [back]})
    frames = s.mesh("window_frames", "frame")
    window_frame(frames, "x", -0.12, -0.06, side, mullions_u=4, mullions_v=2, bar=0.06)
    window_frame(frames, "z", D + 0.06, D + 0.12, back, mullions_u=3, mullions_v=2, bar=0.06)
    # Round table, four chairs, tableware, a vase and a fruit bowl.
    tx, tz = 2.3, 2.5
    table_mesh = s.mesh("table", "table")
    table_mesh.add(round_table(0.65, 0.75), 0, (tx, 0, tz))
    chairs = s.mesh("chairs", "chair")
    for k in range(4):
        a = 45 + 90 * k
        r = 0.85
        chairs.add(chair(), 90 - a, (tx + r * math.cos(math.radians(a)), 0, tz + r * math.sin(math.radians(a))))
    plates = s.mesh("plates", "porcelain", smooth=True)
    for k in range(4):
        a = math.radians(45 + 90 * k)
        plates.lathe([(0.0, 0.0), (0.07, 0.0), (0.12, 0.015), (0.125, 0.02), (0.07, 0.008), (0.0, 0.008)],
                     center=(tx + 0.42 * math.cos(a), 0.751, tz + 0.42 * math.sin(a)), segments=24)
    vase = s.mesh("vase", "glaze", smooth=True)
    vase.lathe([(0.0, 0.0), (0.06, 0.0), (0.09, 0.06), (0.095, 0.14), (0.06, 0.24), (0.04, 0.3), (0.05, 0.33),
                (0.04, 0.33), (0.03, 0.3), (0.0, 0.3)], center=(tx, 0.751, tz), segments=24)
    stems = s.mesh("flowers", "leaves")
    for k in range(5):
        a = 2 * math.pi * k / 5
        stems.box((tx + 0.02 * math.cos(a) - 0.004, 1.05, tz + 0.02 * math.sin(a) - 0.004),
                  (tx + 0.06 * math.cos(a) + 0.004, 1.25 + 0.03 * k, tz + 0.06 * math.sin(a) + 0.004))
    s.shapes += [{"type": "sphere", "name": f"blossom {k}", "material": "blossom", "radius": 0.035,
                  "center": [tx + 0.06 * math.cos(2 * math.pi * k / 5), 1.27 + 0.03 * k,
                             tz + 0.06 * math.sin(2 * math.pi * k / 5)]} for k in range(5)]
    bowl = s.mesh("bowl", "porcelain", smooth=True)
    bx, bz = tx + 0.25, tz - 0.22
    bowl.lathe([(0.0, 0.0), (0.05, 0.0), (0.11, 0.05), (0.13, 0.09), (0.12, 0.09), (0.09, 0.05), (0.0, 0.015)],
               center=(bx, 0.751, bz), segments=24)
    s.shapes += [{"type": "sphere", "name": f"orange {k}", "material": "orange", "radius": 0.04,
                  "center": [bx + dx, 0.82 + dy, bz + dz]}
                 for k, (dx, dy, dz) in enumerate([(-0.04, 0, 0), (0.04, 0, 0.01), (0, 0, -0.05), (0.0, 0.06, 0.0)])]
    # Sideboard on the right wall, a pendant lamp shade (off), a plant pot.
    side_board = s.mesh("sideboard", "table")
    side_board.box((W - 0.5, 0.1, 1.2), (W - 0.02, 0.9, 3.4))
    side_board.box((W - 0.48, 0, 1.25), (W - 0.05, 0.1, 3.35))
    shade = s.mesh("pendant", "brass", smooth=True)
    shade.lathe([(0.0, 2.35), (0.06, 2.35), (0.2, 2.2), (0.21, 2.17), (0.2, 2.17), (0.06, 2.33), (0.01, 2.36),
                 (0.01, 3.0)], center=(tx, 0, tz), segments=24)
    pot = s.mesh("plant_pot", "terracotta", smooth=True)
    pot.lathe([(0.0, 0.0), (0.15, 0.0), (0.2, 0.4), (0.18, 0.4), (0.17, 0.35), (0.0, 0.35)], center=(0.8, 0, 4.3))
    s.shapes.append({"type": "sphere", "name": "bush", "material": "leaves", "center": [0.8, 0.7, 4.3], "radius": 0.35})
    rug = s.mesh("rug", "rug")
    rug.box((1.2, 0, 1.4), (3.4, 0.01, 3.6))
    write_sky(os.path.join(s.dir, "sky.hdr"), [-0.6, 0.55, -0.35])
    camera = {"lookat": {"origin": [5.5, 1.6, 0.45], "target": [1.5, 1.0, 3.4], "up": [0, 1, 0]}, "fov": 70}
    materials = {
        "paint": diffuse([0.78, 0.75, 0.68]),
        "ceiling": diffuse(0.8),
        "floor": {"type": "roughplastic", "alpha": 0.2, "diffuse_reflectance": [0.5, 0.36, 0.22], "int_ior": 1.5},
        "frame": diffuse(0.85),
        "table": {"type": "roughplastic", "alpha": 0.2, "diffuse_reflectance": [0.45, 0.3, 0.18], "int_ior": 1.5},
        "chair": diffuse([0.8, 0.78, 0.72]),
        "porcelain": {"type": "roughplastic", "alpha": 0.05, "diffuse_reflectance": 0.85, "int_ior": 1.5},
        "glaze": {"type": "roughplastic", "alpha": 0.05, "diffuse_reflectance": [0.1, 0.25, 0.6], "int_ior": 1.5},
        "leaves": diffuse([0.12, 0.3, 0.08]),
        "blossom": diffuse([0.9, 0.85, 0.2]),
        "orange": diffuse([0.85, 0.35, 0.05]),
        "brass": {"type": "roughconductor", "alpha": 0.15, "material": "Au"},
        "terracotta": diffuse([0.6, 0.3, 0.18]),
        "rug": diffuse([0.55, 0.2, 0.15]),
    }
    s.write(camera, materials, {"type": "pt", "max_depth": 10},
            environment={"type": "envmap", "file": "sky.hdr", "scale": 3})


# --------------------------------------------------------------------------------------
# Sponza-like courtyard
# --------------------------------------------------------------------------------------
def arcade(stone, column_mesh, xa, t, zs, y0, y_spring, y_top, col_r, segments=16):
    """A storey of arches in the plane x in [xa, xa + t] (t may be negative): round columns
    at zs from y0 to y_spring under square capitals, piers above them and a spandrel wall
    with a semicircular arch (a tessellated half-cylinder intrados) between each pair."""
    xf, xb = sorted((xa, xa + t))
    xc = (xf + xb) / 2
    pier = 0.5 * abs(t) + 0.05
    cap = 0.18
    for z in zs:
        column_mesh.lathe([(0.0, y0), (col_r + 0.08, y0), (col_r + 0.08, y0 + 0.2), (col_r, y0 + 0.28),
                           (col_r * 0.9, y_spring - cap - 0.1), (col_r + 0.03, y_spring - cap - 0.05),
                           (col_r + 0.03, y_spring - cap), (0.0, y_spring - cap)], center=(xc, 0, z), segments=12)
        stone.box((xc - pier, y_spring - cap, z - pier), (xc + pier, y_spring, z + pier))
    for z in zs:                                                       # piers above capitals
        stone.box((xf, y_spring, z - pier + 0.05), (xb, y_top, z + pier - 0.05))
    for za, zb in zip(zs[:-1], zs[1:]):
        a, b = za + pier - 0.05, zb - pier + 0.05
        zc, r = (a + b) / 2, (b - a) / 2
        pts = [(zc - r * math.cos(math.pi * i / segments), y_spring + r * math.sin(math.pi * i / segments))
               for i in range(segments + 1)]
        for (z1, y1), (z2, y2) in zip(pts[:-1], pts[1:]):
            for x in (xf, xb):
                stone.poly([(x, y1, z1), (x, y2, z2), (x, y_top, z2), (x, y_top, z1)])
            stone.poly([(xf, y1, z1), (xb, y1, z1), (xb, y2, z2), (xf, y2, z2)])


def sponza_like(out):
    s = SceneWriter(out, "sponza-like")
    CX, L = 4.0, 10.0                 # courtyard x in [-CX, CX], z in [-L, L]
    G = 2.6                           # gallery depth behind the arcades
    T = 0.5                           # arcade wall thickness
    floor = s.mesh("floor", "paving")
    floor.box((-CX - T - G - 0.3, -0.3, -L - 0.3), (CX + T + G + 0.3, 0.0, L + 0.3))
    stone = s.mesh("stone", "stone")
    columns = s.mesh("columns", "column", smooth=False)
    storeys = [(0.0, 2.7, 4.2), (4.5, 6.5, 7.8)]       # (floor, spring, top of arcade wall)
    zs = list(np.linspace(-L + 0.25, L - 0.25, 9))
    for side in (-1, 1):
        xa = side * CX                                 # courtyard face of the arcade
        xback = side * (CX + T + G)                    # gallery back wall
        for y0, ys, yt in storeys:
            arcade(stone, columns, xa, side * T, zs, y0, ys, yt, 0.2)
            # gallery ceiling / upper floor slab and the back wall
            s0, s1 = sorted((xa, xback))
            stone.box((s0, yt, -L - 0.3), (s1, yt + 0.3, L + 0.3))
        b0, b1 = sorted((xback, xback + side * 0.3))
        stone.box((b0, 0.0, -L - 0.3), (b1, 8.1, L + 0.3))
        # Upper-storey balustrade between the columns, and a cornice above everything.
        for za, zb in zip(zs[:-1], zs[1:]):
            p0, p1 = sorted((xa, xa + side * T))
            stone.box((p0 + 0.1, 4.5, za + 0.3), (p1 - 0.1, 5.35, zb - 0.3))
        c0, c1 = sorted((xa - side * 0.25, xa + side * T))
        stone.box((c0, 8.1, -L - 0.3), (c1, 8.35, L + 0.3))
    # End walls closing the courtyard and galleries, with a blind arch relief.
    for e in (-1, 1):
        z0, z1 = sorted((e * L, e * (L + 0.3)))
        stone.box((-CX - T - G - 0.3, 0, z0), (CX + T + G + 0.3, 9.5, z1))
        rz = e * L - e * 0.1
        r0, r1 = sorted((e * L, rz))
        stone.box((-2.0, 0, r0), (-1.6, 4.5, r1))
        stone.box((1.6, 0, r0), (2.0, 4.5, r1))
        stone.box((-2.0, 4.5, r0), (2.0, 5.1, r1))
    # Drapes hanging from the upper balustrade into the courtyard, in three colours.
    for side in (-1, 1):
        for k, (za, zb) in enumerate(zip(zs[:-1], zs[1:])):
            if k % 2:
                continue
            name = ["drape_red", "drape_green", "drape_blue"][(k // 2 + (side > 0)) % 3]
            m = s.mesh(name, name.split("_")[1] + "_cloth", smooth=True)
            m.add(drape(za + 0.45, zb - 0.45, 2.4, 5.3, side * (CX - 0.02), folds=3, depth=-side * 0.12))
    # A fountain in the middle of the courtyard.
    fountain = s.mesh("fountain", "stone", smooth=True)
    fountain.lathe([(0.0, 0.0), (1.6, 0.0), (1.6, 0.5), (1.45, 0.5), (1.45, 0.2), (0.3, 0.2), (0.25, 1.2),
                    (0.8, 1.3), (0.85, 1.4), (0.2, 1.45), (0.15, 1.9), (0.0, 2.0)], center=(0, 0, 1.0), segments=32)
    sun = [0.45, 0.82, 0.36]
    write_sky(os.path.join(s.dir, "sky.hdr"), sun)
    camera = {"lookat": {"origin": [0.6, 1.7, -9.0], "target": [-0.3, 4.3, 6.0], "up": [0, 1, 0]}, "fov": 75}
    materials = {
        "paving": diffuse([0.45, 0.42, 0.38]),
        "stone": diffuse([0.62, 0.56, 0.46]),
        "column": {"type": "roughplastic", "alpha": 0.3, "diffuse_reflectance": [0.6, 0.55, 0.48], "int_ior": 1.5},
        "red_cloth": diffuse([0.55, 0.08, 0.06]),
        "green_cloth": diffuse([0.1, 0.4, 0.12]),
        "blue_cloth": diffuse([0.08, 0.15, 0.5]),
    }
    s.write(camera, materials, {"type": "pt", "max_depth": 10},
            environment={"type": "envmap", "file": "sky.hdr", "scale": 1})


SCENES = {
    "staircase": staircase,
    "bedroom": bedroom,
    "kitchen": kitchen,
    "classroom": classroom,
    "breakfast-room": breakfast_room,
    "sponza-like": sponza_like,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="*", help="any of " + ", ".join(SCENES) + " (default: all)")
    parser.add_argument("--out", default=os.path.join(ROOT, "scenes"), help="scenes folder (default: repo scenes/)")
    args = parser.parse_args()
    unknown = [n for n in args.scenes if n not in SCENES]
    if unknown:
        parser.error("unknown scene(s): " + ", ".join(unknown))
    for name in args.scenes or list(SCENES):
        SCENES[name](args.out)


if __name__ == "__main__":
    main()
