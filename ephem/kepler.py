"""Two-body orbit: Kepler's equation, anomalies and the orbit's orientation.

Pure numerics: angles in radians, times in days, distances in AU.
"""
from __future__ import annotations

import math

import numpy as np

from .constants import AU_M, DAY_S, GM_CENTER


def mean_motion_rad_per_day(a_au: float, center: str = "Sun", mass_ratio: float = 0.0) -> float:
    """Keplerian mean motion n = sqrt(GM (1 + m/M) / a^3), rad/day.

    ``mass_ratio`` is the orbiting body's mass over the centre's (negligible
    for asteroids; 1/328900.56 for the Earth-Moon barycentre).
    """
    gm = GM_CENTER[center] * (1.0 + mass_ratio)
    a_m = a_au * AU_M
    return math.sqrt(gm / a_m**3) * DAY_S


def solve_kepler(mean_anomaly, e: float):
    """Eccentric anomaly E from mean anomaly M and eccentricity e (0 <= e < 1).

    Vectorised Newton iteration with Markley's-style safe start E0 = M + e sin M
    (E0 = pi for e > 0.8); converges to machine precision in a few steps for any
    e < 1. Returns an array shaped like ``mean_anomaly``.
    """
    m = np.remainder(np.asarray(mean_anomaly, dtype=float), 2.0 * math.pi)
    if e == 0.0:
        return m
    ecc = np.where(m < math.pi, m + 0.85 * e, m - 0.85 * e) if e > 0.8 else m + e * np.sin(m)
    for _ in range(50):
        f = ecc - e * np.sin(ecc) - m
        step = f / (1.0 - e * np.cos(ecc))
        ecc = ecc - step
        if np.all(np.abs(step) < 1e-15):
            break
    return ecc


def true_anomaly(mean_anomaly, e: float):
    """True anomaly ν (radians, same shape as M) of a Keplerian ellipse."""
    ecc = solve_kepler(mean_anomaly, e)
    beta = e / (1.0 + math.sqrt(1.0 - e * e))
    # signed and free of the (1+e)/(1-e) overflow of the half-angle tangent form
    return ecc + 2.0 * np.arctan2(beta * np.sin(ecc), 1.0 - beta * np.cos(ecc))


def radius_over_a(mean_anomaly, e: float):
    """r/a = 1 - e cos E."""
    return 1.0 - e * np.cos(solve_kepler(mean_anomaly, e))


def orbit_basis(i: float, node: float, peri: float) -> np.ndarray:
    """Unit vectors (P, Q, W) of the orbit, as rows, in the frame of the elements.

    P points to pericentre, Q is P advanced 90 degrees in the direction of
    motion, W = P x Q is the orbit normal (the orbital angular momentum).
    W = (sin i sin Ω, -sin i cos Ω, cos i); Petit et al. (2014) eq. 26 prints
    +cos Ω sin i for the second component, a sign slip.
    """
    ci, si = math.cos(i), math.sin(i)
    cn, sn = math.cos(node), math.sin(node)
    cw, sw = math.cos(peri), math.sin(peri)
    p = np.array([cn * cw - sn * sw * ci, sn * cw + cn * sw * ci, sw * si])
    q = np.array([-cn * sw - sn * cw * ci, -sn * sw + cn * cw * ci, cw * si])
    w = np.array([sn * si, -cn * si, ci])
    return np.vstack([p, q, w])


def orbit_normal(i: float, node: float) -> np.ndarray:
    """Unit normal W of the orbit plane (direction of the orbital angular momentum)."""
    return np.array([math.sin(node) * math.sin(i), -math.cos(node) * math.sin(i), math.cos(i)])
