"""Checks emlt's rough-coating transmittance (src/scene/materials/rough_transmittance.cpp)
against the tables Mitsuba 0.6 ships for its `roughplastic` (data/microfacet/*.dat).

The integral is recomputed here independently of the C++ (numpy, the same substitution:
microfacet normals m distributed as D(m) m.z with u = 1 - s^2, azimuths limited to the
side the direction sees), then compared with Mitsuba's table, read as data and
interpolated as its rtrans.h describes (Catmull-Rom in cos^(1/4), alpha^(1/4) and
eta^(1/4) coordinates):

    T(mu) = integral of (1 - F(w.m)) G1(w, m) G1(w_t, m) D(m) max(0, w.m) / mu dm

    python3 -m tools.conformance.rough_transmittance_check MITSUBA_SOURCE_DIR
    python3 -m tools.conformance.rough_transmittance_check --git-dir MITSUBA.git

Prints the largest differences per distribution (eta 1.5 and 1.33, alpha 0.01 to 1, mu
0.02 to 1). Measured: directional values within 4e-5 (GGX) and 1.6e-4 (Beckmann) of the
tables, hemispherical averages from outside within 4e-5; from inside, where total internal
reflection makes the transmittance drop steeply at the critical angle, Mitsuba's averages
differ from ours by up to 1.5e-3 for GGX at alpha 0.05 to 0.3 (0.4 % of the value: its
tabulated integration; ours satisfy the reciprocity T_out / eta^2 = T_in to 2e-4, its
table to 1.5e-3) and by 3e-3 to 4.5e-3 at alpha 0.01. Takes about a minute.
"""
import argparse
import os
import struct
import subprocess
import sys

import numpy as np


def read_table(data):
    """Mitsuba's rough transmittance file: header, sizes, ranges, then per (block, eta,
    alpha) the theta samples followed by the hemispherical average."""
    if data[:17] != b"MTS_TRANSMITTANCE":
        sys.exit("rough_transmittance_check: not a Mitsuba transmittance table")
    n_eta, n_alpha, n_theta = struct.unpack("<QQQ", data[17:41])
    eta_min, eta_max, alpha_min, alpha_max = struct.unpack("<4f", data[41:57])
    values = np.frombuffer(data[57:], dtype="<f4").astype(np.float64)
    values = values.reshape(2, n_eta, n_alpha, n_theta + 1)
    return {"trans": values[..., :n_theta], "diffuse": values[..., n_theta],
            "eta": (eta_min, eta_max), "alpha": (alpha_min, alpha_max)}


def hermite_weights(x, n):
    """Weights of the n uniform nodes on [0, 1] in a Catmull-Rom interpolant at x (one-sided
    differences at the ends)."""
    t = x * (n - 1)
    k = int(min(max(int(t), 0), n - 2))
    t -= k
    h00, h01 = 2 * t**3 - 3 * t**2 + 1, -2 * t**3 + 3 * t**2
    h10, h11 = t**3 - 2 * t**2 + t, t**3 - t**2
    w = np.zeros(n)
    w[k] += h00
    w[k + 1] += h01
    if k > 0:
        w[k + 1] += 0.5 * h10
        w[k - 1] -= 0.5 * h10
    else:
        w[k + 1] += h10
        w[k] -= h10
    if k + 2 < n:
        w[k + 2] += 0.5 * h11
        w[k] -= 0.5 * h11
    else:
        w[k + 1] += h11
        w[k] -= h11
    return w


def table_value(table, key, eta, alpha, mu=None):
    block = 0
    if eta < 1:
        block, eta = 1, 1 / eta
    lo, hi = table["eta"]
    we = ((max(eta, lo) - lo) / (hi - lo)) ** 0.25
    lo, hi = table["alpha"]
    wa = ((alpha - lo) / (hi - lo)) ** 0.25
    grid = table[key][block]
    value = np.tensordot(hermite_weights(we, grid.shape[0]), grid, axes=1)
    value = np.tensordot(hermite_weights(wa, value.shape[0]), value, axes=1)
    if mu is not None:
        value = np.dot(hermite_weights(mu**0.25, value.shape[0]), value)
    return float(np.clip(value, 0, 1))


def fresnel(c, eta):
    s2 = (1 - c * c) / eta**2
    ct = np.sqrt(np.maximum(1 - s2, 0))
    rs = (c - eta * ct) / (c + eta * ct)
    rp = (eta * c - ct) / (eta * c + ct)
    return np.where(s2 >= 1, 1.0, 0.5 * (rs * rs + rp * rp))


def smith_g1(kind, alpha, vz, v_dot_m):
    tan = np.sqrt(np.maximum(1 - vz * vz, 0)) / np.maximum(np.abs(vz), 1e-30)
    if kind == "ggx":
        g = 2 / (1 + np.sqrt(1 + (alpha * tan) ** 2))
    else:  # Walter et al.'s rational fit, as Mitsuba's Beckmann
        a = 1 / np.maximum(alpha * tan, 1e-30)
        g = np.where(a >= 1.6, 1.0, (3.535 * a + 2.181 * a * a) / (1 + 2.276 * a + 2.577 * a * a))
    return np.where(v_dot_m * vz <= 0, 0.0, g)


def transmittance(kind, alpha, eta, mu, nodes=48):
    x, w = np.polynomial.legendre.leggauss(nodes)
    x, w = 0.5 * (x + 1), 0.5 * w
    s, ws = x, w * 2 * x                       # u = 1 - s^2
    tan2 = alpha**2 * (1 - s * s) / (s * s) if kind == "ggx" else -2 * alpha**2 * np.log(s)
    cos_m = 1 / np.sqrt(1 + tan2)
    sin_m = np.sqrt(tan2) * cos_m
    sin_i = np.sqrt(1 - mu * mu)
    with np.errstate(divide="ignore"):
        bound = np.where(sin_m * sin_i > 0, -cos_m * mu / (sin_m * sin_i), -2.0)
    phi_max = np.arccos(np.clip(bound, -1, 1))
    phi = phi_max[:, None] * x[None, :]
    m = np.stack([sin_m[:, None] * np.cos(phi), sin_m[:, None] * np.sin(phi),
                  np.broadcast_to(cos_m[:, None], phi.shape)], -1)
    wi = np.array([sin_i, 0.0, mu])
    c = m @ wi
    f = fresnel(np.maximum(c, 1e-12), eta)
    s2 = (1 - c * c) / eta**2
    ct = np.sqrt(np.maximum(1 - s2, 0))
    wt = -wi / eta + (c / eta - ct)[..., None] * m
    g = smith_g1(kind, alpha, mu, c) * smith_g1(kind, alpha, wt[..., 2], np.sum(wt * m, -1))
    value = np.where((c > 0) & (s2 < 1), (1 - f) * g * c / (mu * cos_m[:, None]), 0.0)
    weight = ws[:, None] * w[None, :] * phi_max[:, None] / np.pi
    return float(np.sum(value * weight))


def diffuse(kind, alpha, eta, nodes=32):
    pieces = [(0.0, 1.0)] if eta >= 1 else [(0.0, np.sqrt(1 - eta**2)), (np.sqrt(1 - eta**2), 1.0)]
    x, w = np.polynomial.legendre.leggauss(nodes)
    total = 0.0
    for lo, hi in pieces:
        for xi, wi in zip(lo + (hi - lo) * 0.5 * (x + 1), (hi - lo) * 0.5 * w):
            total += wi * 2 * xi * transmittance(kind, alpha, eta, xi, nodes)
    return total


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("source", nargs="?", help="a Mitsuba 0.6 source folder")
    parser.add_argument("--git-dir", help="a Mitsuba 0.6 git repository (bare is fine)")
    args = parser.parse_args()
    for kind in ("ggx", "beckmann"):
        name = f"data/microfacet/{kind}.dat"
        if args.git_dir:
            data = subprocess.run(["git", "--git-dir", args.git_dir, "show", f"HEAD:{name}"],
                                  capture_output=True, check=True).stdout
        elif args.source:
            data = open(os.path.join(args.source, name), "rb").read()
        else:
            sys.exit("rough_transmittance_check: give a Mitsuba source folder or --git-dir")
        table = read_table(data)
        worst = {"directional": 0.0, "average outside": 0.0, "average inside": 0.0, "reciprocity": 0.0}
        for eta in (1.5, 1.33):
            for alpha in (0.01, 0.05, 0.12, 0.3, 0.6, 1.0):
                for mu in (1.0, 0.7, 0.4, 0.2, 0.1, 0.05, 0.02):
                    ours = transmittance(kind, alpha, eta, mu)
                    worst["directional"] = max(worst["directional"], abs(ours - table_value(table, "trans", eta, alpha, mu)))
                outside, inside = diffuse(kind, alpha, eta), diffuse(kind, alpha, 1 / eta)
                worst["average outside"] = max(worst["average outside"], abs(outside - table_value(table, "diffuse", eta, alpha)))
                worst["average inside"] = max(worst["average inside"], abs(inside - table_value(table, "diffuse", 1 / eta, alpha)))
                worst["reciprocity"] = max(worst["reciprocity"], abs(outside / eta**2 - inside))
        print(f"{kind}: largest |ours - Mitsuba's table|: " +
              ", ".join(f"{k} {v:.1e}" for k, v in worst.items() if k != "reciprocity") +
              f"; ours |T_out / eta^2 - T_in| {worst['reciprocity']:.1e}")


if __name__ == "__main__":
    main()
