"""The Earth's pole integrated under DE421's Moon and Sun: the numerical reference of the lunisolar series.

The independent route to the series of :mod:`ephem.earth.lunisolar`: the averaged torque of the geocentric
Moon and Sun read from the DE421 kernel, integrated by classical RK4 (docs/earth.md), which holds the
precession rate, the nutation and the second-order coupling the series leaves out
(:func:`ephem.earth.lunisolar.precession_nutation_coupling`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.constants import ARCSEC, J2000_JD
from ..orbit.de421 import barycentric, check_span
from ..orbit.de421_header import GM_DE421, GM_SUN_DE421
from ..orbit.geometry import icrf_to_ecliptic_matrix
from ..orbit.lunar import obliquity_arcsec
from .lunisolar import PERTURBERS, earth_spin_rate, resolve_hd


@dataclass(frozen=True)
class NumericalPole:
    """Angular-momentum axis integrated under DE421's Moon and Sun (radians; JD TDB).

    ψ and ε are referred to the fixed mean ecliptic and equinox of J2000
    (:func:`ephem.orbit.geometry.icrf_to_ecliptic_matrix`): s = (sin ε sin ψ, sin ε cos ψ, cos ε).
    """

    jd_tdb: np.ndarray
    psi: np.ndarray
    epsilon: np.ndarray
    step_days: float


def integrate_de421(jd_start: float, jd_stop: float, hd, step_days: float = 0.5, perturbers=PERTURBERS,
                    epoch: float = J2000_JD, initial: tuple | None = None) -> NumericalPole:
    """Integrate ds/dt = Σ (3 GM H_d/(ω r³)) (s·r̂)(r̂×s) with the geocentric Moon and Sun of DE421.

    Classical RK4 on a uniform grid of ``step_days`` (the torque varies on the 13.66-day scale at
    the fastest; 0.5 d leaves < 1 µas), forwards and backwards from ``epoch``, with the positions
    read from the kernel at every half step in one vectorised call. ``initial`` = (ψ, ε) at
    ``epoch`` in the J2000 ecliptic frame; default (0, ε_A(J2000)), i.e. the mean pole of J2000
    (the nutation then only offsets the run by a constant). The starting ψ matters: an error x
    in it shifts every nutation phase by x times the argument's Ω multiplier.
    """
    if not jd_start <= epoch <= jd_stop:
        raise ValueError(f"epoch {epoch} outside [{jd_start}, {jd_stop}]")
    check_span("Earth", jd_start, jd_stop)
    hd = resolve_hd(hd)
    rot = icrf_to_ecliptic_matrix()
    coef = 3.0 * hd / earth_spin_rate()
    psi0, eps0 = initial if initial is not None else (0.0, obliquity_arcsec(0.0) * ARCSEC)
    s0 = (math.sin(eps0) * math.sin(psi0), math.sin(eps0) * math.cos(psi0), math.cos(eps0))
    legs = []
    for end in (jd_start, jd_stop):
        if end == epoch:
            continue
        n = math.ceil(abs(end - epoch) / step_days)
        h = (end - epoch) / n
        half = epoch + 0.5 * h * np.arange(2 * n + 1)
        earth = barycentric(399, half)
        rows = []
        for name in perturbers:
            naif, gm = (301, GM_DE421[301]) if name == "moon" else (10, GM_SUN_DE421)
            r = (barycentric(naif, half) - earth) @ rot.T      # au, ecliptic and equinox J2000
            r2 = np.einsum("ij,ij->i", r, r)
            rows.append(np.column_stack([coef * gm / (r2 * r2 * np.sqrt(r2)), r]))
        table = np.concatenate(rows, axis=1).tolist()   # per half step: [w1, x1, y1, z1, w2, ...]
        s = s0
        out = np.empty((n + 1, 3))
        out[0] = s
        for i in range(n):
            a, b, c = table[2 * i], table[2 * i + 1], table[2 * i + 2]
            k1 = _torque(a, s)
            k2 = _torque(b, _axpy(0.5 * h, k1, s))
            k3 = _torque(b, _axpy(0.5 * h, k2, s))
            k4 = _torque(c, _axpy(h, k3, s))
            s = tuple(si + (h / 6.0) * (p1 + 2.0 * p2 + 2.0 * p3 + p4)
                      for si, p1, p2, p3, p4 in zip(s, k1, k2, k3, k4))
            out[i + 1] = s
        legs.append((half[::2], out))
    if not legs:
        legs.append((np.array([epoch]), np.array([s0])))
    jd = np.concatenate([leg[0][::-1] if leg[0][-1] < epoch else leg[0] for leg in legs])
    vec = np.concatenate([leg[1][::-1] if leg[0][-1] < epoch else leg[1] for leg in legs])
    jd, idx = np.unique(jd, return_index=True)
    vec = vec[idx]
    vec /= np.linalg.norm(vec, axis=1, keepdims=True)
    return NumericalPole(jd, np.arctan2(vec[:, 0], vec[:, 1]), np.arccos(np.clip(vec[:, 2], -1.0, 1.0)),
                         float(step_days))


def _axpy(a, x, y):
    return (y[0] + a * x[0], y[1] + a * x[1], y[2] + a * x[2])


def _torque(row, s):
    """Σ_j w_j (r_j·s)(r_j × s) for row = [w1, x1, y1, z1, w2, x2, y2, z2, ...] (plain floats)."""
    sx, sy, sz = s
    fx = fy = fz = 0.0
    for j in range(0, len(row), 4):
        w, x, y, z = row[j], row[j + 1], row[j + 2], row[j + 3]
        d = w * (x * sx + y * sy + z * sz)
        fx += d * (y * sz - z * sy)
        fy += d * (z * sx - x * sz)
        fz += d * (x * sy - y * sx)
    return (fx, fy, fz)
