"""Image helpers shared by tools/, scripts/ and the tests (numpy only).

PFM is the format the scripts read: it is what ``emlt render -o X.pfm`` writes, raw
little- or big-endian float32 with the bottom row first.  Tone mapping here is the one
every figure uses, so crops of different methods are shown exactly the same way.
"""
import numpy as np


def read_pfm(path):
    """Read a PFM file into a float32 array of shape (height, width, channels), top row first."""
    with open(path, "rb") as f:
        header = f.readline().strip()
        if header not in (b"PF", b"Pf"):
            raise ValueError(f"{path}: not a PFM file")
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    channels = 3 if header == b"PF" else 1
    image = data[: width * height * channels].reshape(height, width, channels)
    return np.flipud(image).astype(np.float32)  # PFM stores the bottom row first


def write_pfm(path, image):
    """Write an (height, width, 3) or (height, width) float array as little-endian PFM."""
    image = np.asarray(image, dtype="<f4")
    if image.ndim == 2:
        image = image[:, :, None]
    height, width, channels = image.shape
    if channels not in (1, 3):
        raise ValueError("PFM holds 1 or 3 channels")
    with open(path, "wb") as f:
        f.write(b"PF\n" if channels == 3 else b"Pf\n")
        f.write(f"{width} {height}\n-1.0\n".encode())
        f.write(np.ascontiguousarray(np.flipud(image)).tobytes())


def crop(image, rect):
    """Cut the rectangle rect = (x, y, w, h) (pixels, origin top left) out of image; None keeps all."""
    if rect is None:
        return image
    x, y, w, h = (int(v) for v in rect)
    if x < 0 or y < 0 or w <= 0 or h <= 0 or x + w > image.shape[1] or y + h > image.shape[0]:
        raise ValueError(f"crop {x},{y},{w},{h} lies outside the {image.shape[1]}x{image.shape[0]} image")
    return image[y:y + h, x:x + w]


def srgb_encode(linear):
    """The sRGB transfer function applied to linear values in [0, 1]."""
    linear = np.clip(linear, 0.0, 1.0)
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1.0 / 2.4) - 0.055)


def tonemap(image, exposure=0.0):
    """Linear radiance -> displayable sRGB in [0, 1]: scale by 2^exposure, clip, sRGB-encode.

    Non-finite pixels (NaN, inf) are shown black so that a broken pixel cannot hide the others.
    """
    image = np.nan_to_num(np.asarray(image, dtype=np.float64), nan=0.0, posinf=0.0, neginf=0.0)
    if image.shape[-1] == 1:
        image = np.repeat(image, 3, axis=-1)
    return srgb_encode(image * 2.0 ** exposure)


def mse(image, reference):
    """Mean over pixels and RGB channels of the squared difference (the engine's 'mse')."""
    return float(np.mean((np.asarray(image, np.float64) - np.asarray(reference, np.float64)) ** 2))
