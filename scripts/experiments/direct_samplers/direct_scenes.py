"""Scenes and the render call shared by the direct-sampler reproductions (bmc.py,
point_sets.py, ...): the engine's sun and sky, lat-long maps in Mitsuba's convention, the
balls-and-floor scene under an environment, an area-lit box, and a resumable `direct` render.

Every scene renders one camera ray per pixel through its centre (a Gaussian pixel filter of
`stddev` pixel, 0.003 unless told), so that an image's error is the direct-lighting
estimator's alone. At 0.003 a pixel whose centre lies within about 0.01 pixel of a silhouette
still sees both sides from seed to seed; at 32 x 32 two such pixels on the big ball's top
made most of the error of every low-discrepancy set at 512 points (point_sets.py uses 1e-5).
"""
import json
import os
import subprocess
import sys

import numpy as np

from tools.images import read_pfm


def sunsky(hour=10, minute=30):
    """Mitsuba's `sunsky` over Vienna on the March equinox: a high-dynamic-range sky whose
    0.54-degree sun disk is orders of magnitude brighter than the sky."""
    return f"""<emitter type="sunsky"><float name="latitude" value="48.2"/>
    <float name="longitude" value="16.37"/><float name="timezone" value="1"/>
    <integer name="year" value="2015"/><integer name="month" value="3"/>
    <integer name="day" value="21"/><float name="hour" value="{hour}"/><float name="minute" value="{minute}"/>
    <float name="turbidity" value="3"/><float name="scale" value="0.5"/>
    <transform name="toWorld"><rotate y="1" angle="-40"/></transform></emitter>"""


def envmap(filename):
    return f"""<emitter type="envmap"><string name="filename" value="{filename}"/></emitter>"""


def latlong_directions(width):
    """Unit directions at the texel centres of a width x width/2 lat-long map in Mitsuba's
    envmap convention (row 0 at the zenith, +Y up, azimuth atan2(x, -z) from the left edge),
    shape (height, width, 3), and the polar angles, shape (height, width)."""
    height = width // 2
    v = (np.arange(height) + 0.5) / height
    u = (np.arange(width) + 0.5) / width
    theta, phi = np.meshgrid(np.pi * v, 2 * np.pi * u, indexing="ij")
    d = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], -1)
    return d, theta


def smooth_map(width=256):
    """A smooth lat-long map: a sky gradient and three broad Gaussian blobs, a dynamic range of
    about 30."""
    d, _ = latlong_directions(width)
    up = np.clip(d[..., 1], -1, 1)
    img = np.zeros(d.shape)
    img += (0.3 + 0.5 * np.clip(up, 0, 1))[..., None] * np.array([0.6, 0.75, 1.0])
    img[up < 0] = [0.15, 0.13, 0.1]
    for centre, sharpness, radiance in (([-0.6, 0.7, 0.4], 6.0, [8.0, 7.5, 7.0]),
                                        ([0.8, 0.3, 0.5], 4.0, [2.0, 2.5, 3.0]),
                                        ([0.1, 0.4, -1.0], 10.0, [6.0, 5.0, 4.0])):
        c = np.array(centre) / np.linalg.norm(centre)
        img += np.exp(sharpness * (d @ c - 1.0))[..., None] * np.array(radiance)
    return img.astype(np.float32)


# Balls and a floor, all glossy (Mitsuba's normalised `phong`, exponents 20, 50 and 80, no
# diffuse term) or all diffuse.
GLOSSY = {
    "big": '<bsdf type="phong"><float name="exponent" value="50"/>'
           '<rgb name="specularReflectance" value="0.8, 0.8, 0.8"/>'
           '<rgb name="diffuseReflectance" value="0, 0, 0"/></bsdf>',
    "left": '<bsdf type="phong"><float name="exponent" value="20"/>'
            '<rgb name="specularReflectance" value="0.8, 0.6, 0.3"/>'
            '<rgb name="diffuseReflectance" value="0, 0, 0"/></bsdf>',
    "right": '<bsdf type="phong"><float name="exponent" value="80"/>'
             '<rgb name="specularReflectance" value="0.3, 0.5, 0.8"/>'
             '<rgb name="diffuseReflectance" value="0, 0, 0"/></bsdf>',
    "floor": '<bsdf type="phong"><float name="exponent" value="20"/>'
             '<rgb name="specularReflectance" value="0.5, 0.5, 0.5"/>'
             '<rgb name="diffuseReflectance" value="0, 0, 0"/></bsdf>',
}
DIFFUSE = {
    "big": '<bsdf type="diffuse"><rgb name="reflectance" value="0.75, 0.75, 0.75"/></bsdf>',
    "left": '<bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.6, 0.3"/></bsdf>',
    "right": '<bsdf type="diffuse"><rgb name="reflectance" value="0.3, 0.5, 0.8"/></bsdf>',
    "floor": '<bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>',
}

# The head every scene of these scripts shares: the direct integrator and a 40-degree camera
# at `{origin}` looking at `{target}`, one camera ray per pixel through a Gaussian filter of
# `{stddev}` pixels (tiny: the variance across seeds is then the direct estimate's alone).
HEAD = """<?xml version="1.0" encoding="utf-8"?>
<!-- written by scripts/experiments/direct_samplers/{writer} -->
<scene version="0.6.0">
  <integrator type="direct"/>
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="{origin}" target="{target}" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
    <film type="hdrfilm">
      <integer name="width" value="48"/><integer name="height" value="48"/>
      <rfilter type="gaussian"><float name="stddev" value="{stddev}"/></rfilter>
    </film>
  </sensor>
"""

BALLS = HEAD.replace("{origin}", "0, 1.6, 4.0").replace("{target}", "0, 0.5, 0") + """  {emitter}
  <shape type="sphere"><point name="center" x="0" y="0.6" z="0"/><float name="radius" value="0.6"/>
    {big}</shape>
  <shape type="sphere"><point name="center" x="-1.2" y="0.35" z="0.4"/><float name="radius" value="0.35"/>
    {left}</shape>
  <shape type="sphere"><point name="center" x="1.2" y="0.35" z="0.4"/><float name="radius" value="0.35"/>
    {right}</shape>
  <shape type="rectangle">
    <transform name="toWorld"><scale value="5"/><rotate x="1" angle="-90"/></transform>
    {floor}
  </shape>
</scene>
"""


def balls_scene(writer, emitter, materials, stddev="0.003"):
    text = BALLS.replace("{writer}", writer).replace("{emitter}", emitter)
    text = text.replace("{stddev}", stddev)
    for key, bsdf in materials.items():
        text = text.replace("{" + key + "}", bsdf)
    return text


# A Cornell-like box lit by a small square area light under its ceiling (the [SF] paper's
# kind of interior): white, red and green diffuse walls, a diffuse block and a glossy ball.
# No environment: every light is the area light, found by light sampling (a point of the
# unit square becomes a point on the light) and by BSDF sampling. The camera is a little off
# the box's axis: centred, the pixel centres at 32 x 32 fell on the floor's corners with the
# walls, whose shading then turned on the camera ray's last digits, seed by seed.
BOX = HEAD.replace("{origin}", "0.037, 1.013, 3.9").replace("{target}", "0.037, 1.013, 0") + """  <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.72, 0.71, 0.68"/></bsdf>
  <shape type="rectangle"><transform name="toWorld"><rotate x="1" angle="-90"/><translate y="0"/></transform>
    <ref id="white"/></shape>
  <shape type="rectangle"><transform name="toWorld"><rotate x="1" angle="90"/><translate y="2"/></transform>
    <ref id="white"/></shape>
  <shape type="rectangle"><transform name="toWorld"><translate y="1" z="-1"/></transform>
    <ref id="white"/></shape>
  <shape type="rectangle"><transform name="toWorld"><rotate y="1" angle="90"/><translate x="-1" y="1"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.63, 0.065, 0.05"/></bsdf></shape>
  <shape type="rectangle"><transform name="toWorld"><rotate y="1" angle="-90"/><translate x="1" y="1"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.14, 0.45, 0.09"/></bsdf></shape>
  <shape type="cube"><transform name="toWorld"><scale x="0.3" y="0.6" z="0.3"/><rotate y="1" angle="20"/>
    <translate x="-0.4" y="0.6" z="-0.3"/></transform><ref id="white"/></shape>
  <shape type="sphere"><point name="center" x="0.45" y="0.35" z="0.3"/><float name="radius" value="0.35"/>
    <bsdf type="phong"><float name="exponent" value="30"/>
      <rgb name="specularReflectance" value="0.6, 0.6, 0.6"/>
      <rgb name="diffuseReflectance" value="0.1, 0.1, 0.1"/></bsdf></shape>
  <shape type="rectangle"><transform name="toWorld"><scale value="0.25"/><rotate x="1" angle="90"/>
    <translate y="1.99"/></transform>
    <emitter type="area"><rgb name="radiance" value="17, 12, 4"/></emitter></shape>
</scene>
"""


def box_scene(writer, stddev="0.003"):
    return BOX.replace("{writer}", writer).replace("{stddev}", stddev)


def pyplot(script):
    """matplotlib's pyplot on the Agg backend, or None (said once) where it is not installed."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print(f"{script}: matplotlib missing, no plots")
        return None
    return plt


def render_direct(emlt, scene, args, seed, common, out, who):
    """Renders `scene` with the direct integrator into out (.pfm) unless a previous call did
    (then the image on disk is returned: a rerun resumes); the command is kept beside it."""
    if not os.path.exists(out):
        os.makedirs(os.path.dirname(out), exist_ok=True)
        cmd = [emlt, "render", scene, "--integrator", "direct", "--seed", str(seed), "-o", out,
               "--quiet"] + common + args
        run = subprocess.run(cmd, capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit(f"{who}: {' '.join(cmd)} failed: {run.stderr.strip()[-400:]}")
        with open(out + ".json", "w") as f:
            json.dump({"command": cmd}, f)
    return read_pfm(out).astype(np.float64)
