#!/usr/bin/env python3
"""Asks Mitsuba 0.6 itself for texels of the maps its sky, sun and sunsky emitters build,
for tests/unit/sky_test.cpp (written to tests/unit/data/mitsuba_sky_probes.json).

Mitsuba keeps those maps to itself, so each texel is measured: a `radiancemeter` sensor
at the origin looks through the texel's centre (the emitter's toWorld applied), where
the nested envmap's bilinear lookup returns that texel alone (up to the half-float
storage of Mitsuba's MIP map, a few 1e-4 relative). Texels around the sun are found
first from a coarse `spherical` render of the whole sky (its brightest pixel).

  MITSUBA=/work/mitsuba/dist/mitsuba python3 -m tools.sky.make_sky_probes
"""
import json
import math
import os
import pathlib
import subprocess
import tempfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "tests" / "unit" / "data" / "mitsuba_sky_probes.json"
MITSUBA = os.environ.get("MITSUBA", "/work/mitsuba/dist/mitsuba")


def rot(axis, degrees):
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    x, y, z = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.array([[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                     [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                     [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])


# name, emitter body (XML), its toWorld as a 3x3 matrix, map resolution, whether a sun shows
CASES = [
    ("sky_direction",
     '<float name="turbidity" value="4.5"/><rgb name="albedo" value="0.1, 0.4, 0.8"/>'
     '<float name="stretch" value="1.3"/><vector name="sunDirection" x="0.3" y="0.6" z="-0.5"/>'
     '<integer name="resolution" value="64"/><float name="scale" value="2"/>',
     np.eye(3), 64, False),
    ("sky_date_extend",
     '<float name="turbidity" value="10"/><boolean name="extend" value="true"/>'
     '<integer name="resolution" value="32"/><float name="hour" value="9.5"/>'
     '<transform name="toWorld"><rotate x="1" angle="90"/></transform>',
     rot((1, 0, 0), 90), 32, False),
    ("sun_direction",
     '<vector name="sunDirection" x="-0.4" y="0.5" z="0.2"/><float name="turbidity" value="5"/>'
     '<float name="sunRadiusScale" value="4"/><integer name="resolution" value="128"/>'
     '<float name="scale" value="0.5"/>',
     np.eye(3), 128, True),
    ("sunsky_date",
     '<float name="latitude" value="48.2"/><float name="longitude" value="16.37"/>'
     '<float name="timezone" value="1"/><integer name="year" value="2015"/>'
     '<integer name="month" value="3"/><integer name="day" value="21"/>'
     '<float name="hour" value="10"/><float name="minute" value="45"/>'
     '<float name="second" value="30"/><float name="turbidity" value="2.5"/>'
     '<float name="stretch" value="1.1"/><float name="sunRadiusScale" value="3"/>'
     '<float name="scale" value="0.7"/><float name="sunScale" value="0.25"/>'
     '<srgb name="albedo" value="#80a040"/><integer name="resolution" value="96"/>'
     '<transform name="toWorld"><rotate x="1" angle="90"/><rotate z="1" angle="30"/></transform>',
     rot((0, 0, 1), 30) @ rot((1, 0, 0), 90), 96, True),
]


def run(tmp, name, sensor, emitter_type, body):
    xml = tmp / f"{name}.xml"
    xml.write_text(f'<scene version="0.6.0"><integrator type="path"/>{sensor}'
                   f'<emitter type="{emitter_type}">{body}</emitter></scene>')
    env = dict(os.environ, LD_LIBRARY_PATH=str(pathlib.Path(MITSUBA).parent))
    subprocess.run([MITSUBA, "-q", "-p", "1", str(xml), "-o", str(tmp / name)], check=True,
                   env=env, capture_output=True)
    return tmp / name


def texel_direction(x, y, w, h):
    theta, phi = (y + 0.5) * math.pi / h, (x + 0.5) * 2 * math.pi / w
    return np.array([math.sin(phi) * math.sin(theta), math.cos(theta),
                     -math.cos(phi) * math.sin(theta)])


def probe(tmp, emitter_type, body, to_world, x, y, w, h):
    d = to_world @ texel_direction(x, y, w, h)
    up = np.array([0.123, 0.456, 0.789])
    sensor = ('<sensor type="radiancemeter"><transform name="toWorld">'
              f'<lookat origin="0,0,0" target="{d[0]!r},{d[1]!r},{d[2]!r}" '
              f'up="{up[0]},{up[1]},{up[2]}"/></transform>'
              '<film type="mfilm"><string name="pixelFormat" value="rgb"/>'
              '<string name="fileFormat" value="numpy"/></film>'
              '<sampler type="independent"><integer name="sampleCount" value="1"/></sampler>'
              '</sensor>')
    out = run(tmp, "probe", sensor, emitter_type, body)
    return [float(v) for v in np.load(str(out) + ".npy").ravel()]


def brightest_texel(tmp, emitter_type, body, to_world, w, h):
    """The map texel the sun falls into, from a spherical render of the world."""
    sensor = ('<sensor type="spherical"><film type="hdrfilm"><integer name="width" value="256"/>'
              '<integer name="height" value="128"/><string name="fileFormat" value="pfm"/>'
              '<rfilter type="box"/></film><sampler type="independent">'
              '<integer name="sampleCount" value="4"/></sampler></sensor>')
    out = run(tmp, "scan", sensor, emitter_type, body)
    data = open(str(out) + ".pfm", "rb").read()
    header = data.split(b"\n", 3)
    sw, sh = map(int, header[1].split())
    img = np.frombuffer(header[3], dtype="<f4").reshape(sh, sw, 3)[::-1]
    # Mitsuba's filtered lookups of this render put spurious bright streaks along the
    # poles (a ray-differential artefact of the spherical sensor): the test cases keep their
    # sun away from the poles, and the search skips the polar rows.
    band = sh // 8
    sums = img.sum(axis=2)[band:sh - band]
    y, x = np.unravel_index(np.argmax(sums), sums.shape)
    y += band
    world = texel_direction(x, y, sw, sh)
    local = to_world.T @ world
    theta = math.acos(max(-1.0, min(1.0, local[1])))
    phi = math.atan2(local[0], -local[2]) % (2 * math.pi)
    return int(phi / (2 * math.pi) * w), int(theta / math.pi * h)


def main():
    cases = []
    with tempfile.TemporaryDirectory() as t:
        tmp = pathlib.Path(t)
        for name, body, to_world, res, has_sun in CASES:
            emitter_type = name.split("_")[0]
            w, h = res, res // 2
            rng = np.random.default_rng(len(cases) + 1)
            texels = {(int(rng.integers(w)), int(rng.integers(h))) for _ in range(16)}
            texels |= {(0, 0), (w - 1, h - 1), (w // 3, h // 2 - 1), (w // 2, h // 2)}
            if has_sun:
                sx, sy = brightest_texel(tmp, emitter_type, body, to_world, w, h)
                texels |= {((sx + dx) % w, min(max(sy + dy, 0), h - 1))
                           for dx in range(-2, 3) for dy in range(-2, 3)}
            probes = []
            for x, y in sorted(texels):
                probes.append({"x": x, "y": y,
                               "rgb": probe(tmp, emitter_type, body, to_world, x, y, w, h)})
            cases.append({"name": name, "xml": f'<emitter type="{emitter_type}">{body}</emitter>',
                          "width": w, "height": h, "probes": probes})
            print(name, len(probes), "texels")
    OUT.write_text(json.dumps({
        "about": "Texels of Mitsuba 0.6's sky/sun/sunsky maps, measured with its radiancemeter "
                 "(tools/sky/make_sky_probes.py); x, y in the emitter's own map.",
        "cases": cases}, indent=1) + "\n")
    print("wrote", OUT)


if __name__ == "__main__":
    main()
