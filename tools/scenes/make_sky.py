"""Writes the lat-long sky used by scenes/env-sky: a blue gradient sky, a dim ground and a
small sun ~1e4 times brighter than the sky, as a Radiance .hdr (RGBE) file.

The mapping matches emlt's environment maps (and Mitsuba's): column u = phi / (2 pi), row
v = theta / pi with theta measured from +y (row 0 is straight up), and the direction of a
texel is (sin theta sin phi, cos theta, -sin theta cos phi).

Deterministic: the same arguments always give the same bytes.
    python3 -m tools.scenes.make_sky                  # writes scenes/env-sky/sky.hdr (256 x 128)
    python3 -m tools.scenes.make_sky -o other.hdr --width 512
"""
import argparse
import os

import numpy as np

from tools import ROOT

SUN_DIRECTION = np.array([-0.45, 0.6, -0.65])   # towards the sun: up, front-left of the camera
SUN_ANGULAR_RADIUS_DEG = 2.5                     # enlarged so the disk covers a few texels
SUN_RADIANCE = np.array([1.0, 0.93, 0.82]) * 1000.0
ZENITH = np.array([0.035, 0.063, 0.14])
HORIZON = np.array([0.16, 0.175, 0.19])
GROUND = np.array([0.06, 0.05, 0.04])
SUPERSAMPLES = 4                                 # per texel axis, for a smooth sun edge


def directions(width, height, samples):
    """Unit directions of samples x samples jittered-free subpixel positions per texel."""
    offsets = (np.arange(samples) + 0.5) / samples
    u = (np.arange(width)[None, :, None, None] + offsets[None, None, None, :]) / width
    v = (np.arange(height)[:, None, None, None] + offsets[None, None, :, None]) / height
    u, v = np.broadcast_arrays(u, v)
    phi, theta = 2.0 * np.pi * u, np.pi * v
    return np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], axis=-1)


def sky_radiance(d):
    sun = SUN_DIRECTION / np.linalg.norm(SUN_DIRECTION)
    up = d[..., 1:2]
    # Gradient from the horizon to the zenith above, a flat dim ground below.
    t = np.clip(up, 0.0, 1.0) ** 0.5
    radiance = np.where(up >= 0.0, HORIZON * (1.0 - t) + ZENITH * t, GROUND)
    cos_to_sun = np.clip(d @ sun, -1.0, 1.0)[..., None]
    angle = np.degrees(np.arccos(cos_to_sun))
    # Forward-scattering glow around the sun (brightens the sky near it), then the disk.
    radiance = radiance + np.where(up >= 0.0, 0.2 * np.exp(-angle / 10.0) * np.array([1.0, 0.9, 0.7]), 0.0)
    return np.where(angle <= SUN_ANGULAR_RADIUS_DEG, SUN_RADIANCE, radiance)


def to_rgbe(rgb):
    """Radiance RGBE: shared exponent of the largest channel, 8-bit mantissas."""
    largest = rgb.max(axis=-1)
    mantissa, exponent = np.frexp(largest)
    scale = np.where(largest > 1e-32, mantissa * 256.0 / np.maximum(largest, 1e-32), 0.0)
    out = np.zeros(rgb.shape[:-1] + (4,), dtype=np.uint8)
    out[..., :3] = np.clip(rgb * scale[..., None], 0, 255).astype(np.uint8)
    out[..., 3] = np.where(largest > 1e-32, exponent + 128, 0).astype(np.uint8)
    return out


def write_hdr(path, rgb):
    height, width, _ = rgb.shape
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {height} +X {width}\n".encode("ascii"))
        # Flat scanlines: the largest channel's mantissa is >= 128, so no pixel can be
        # mistaken for the 2,2 marker of a run-length-encoded line.
        f.write(to_rgbe(rgb).tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("-o", "--output", default=os.path.join(ROOT, "scenes", "env-sky", "sky.hdr"))
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--height", type=int, default=None, help="default: width / 2")
    args = parser.parse_args()
    height = args.height or args.width // 2
    radiance = sky_radiance(directions(args.width, height, SUPERSAMPLES)).mean(axis=(2, 3))
    write_hdr(args.output, radiance.astype(np.float32))
    sun_texels = int((radiance.max(axis=-1) > 30.0).sum())
    sky_mean = radiance[radiance.max(axis=-1) < 30.0].mean()
    print(f"wrote {os.path.normpath(args.output)}: {args.width}x{height}, sun {SUN_RADIANCE.max():.0f}, "
          f"mean sky {sky_mean:.3f}, {sun_texels} sun texels")


if __name__ == "__main__":
    main()
