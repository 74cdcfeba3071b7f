"""The torque on the Moon's turning reference frame, over the torus of the Delaunay arguments.

The terms of the linearised equations Λ θ̈ + M1 θ̇ + M0 θ = f of :mod:`ephem.moon.physical_librations` (its module
docstring, eqs. (4)–(6)): the Earth (and the Sun) seen from the Moon by the orbit series of :mod:`ephem.orbit.lunar`,
the rates of the reference frame R = Rz(Ω + π) Rx(I) Rz(F), and the forcing f, stiffness M0 and gyroscopic matrix
M1 at any arguments or on the FFT grid of the torus that the solver works on. Radians and days.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..orbit.lunar import delaunay_rates, gm_km3_day2, moon_position, sun_position
from .libration_frames import GENERAL_PRECESSION_RATE, skew


def perturber_directions_at(args: tuple, sun: bool):
    """The Earth (and the Sun) seen from the Moon at Delaunay arguments ``args`` (five broadcastable arrays), in
    the node frame N: z the ecliptic pole, x toward ecliptic longitude Ω + π (the lunar equator's ascending node).
    Returns ((GM/r³ rad²/day², unit vectors (3, ...)), ...) per perturber: the Moon from :func:`moon_position`
    (Meeus 1998 ch. 47), the Sun from :func:`sun_position`, the Sun's direction from the Moon, not the Earth."""
    lam, bet, r = moon_position(args)
    cb = np.cos(bet)
    moon = np.stack(np.broadcast_arrays(r * cb * np.cos(lam), r * cb * np.sin(lam), r * np.sin(bet)))
    vectors = [("earth", -moon)]
    if sun:
        lam_s, _, r_s = sun_position(args)
        sun_vec = np.stack(np.broadcast_arrays(r_s * np.cos(lam_s), r_s * np.sin(lam_s), np.zeros_like(lam_s)))
        vectors.append(("sun", sun_vec - moon))
    node = np.broadcast_to(args[4], moon.shape[1:]) + math.pi
    c, s = np.cos(node), np.sin(node)
    out = []
    for name, v in vectors:
        d = np.sqrt(np.einsum("i...,i...->...", v, v))
        u = v / d
        out.append((gm_km3_day2(name) / d**3, np.stack([c * u[0] + s * u[1], -s * u[0] + c * u[1], u[2]])))
    return tuple(out)


@lru_cache(maxsize=4)
def perturber_directions(grid: tuple, sun: bool):
    """:func:`perturber_directions_at` on the torus grid (cached: it does not depend on I or the moments)."""
    axes = [2.0 * math.pi * np.arange(n) / n for n in grid]
    return perturber_directions_at(tuple(a.reshape([-1 if i == j else 1 for j in range(5)]) for i, a in enumerate(axes)), sun)


def frame_rates(I: float) -> tuple[float, float, float]:
    """(ν, w3, Ḟ): the reference frame R = Rz(Ω + π) Rx(I) Rz(F) turns in space at ω_R = (Ω̇ − p_A) K + Ḟ p,
    in R's own axes (ν sin F, ν cos F, w3) with ν = (Ω̇ − p_A) sin I, w3 = Ḟ + (Ω̇ − p_A) cos I (rad/day)."""
    rates = delaunay_rates(0.0)
    node = rates[4] - GENERAL_PRECESSION_RATE
    return node * math.sin(I), rates[2] + node * math.cos(I), rates[2]


def linearised_equations(directions, F, I: float, moments: np.ndarray):
    """The linearised equations' terms (module docstring, eqs. (4)–(6)) at the perturbers' ``directions`` (node
    frame) and argument of latitude F (broadcastable): the forcing f (3, ...), the stiffness M0 (3, 3, ...) and
    the gyroscopic matrix M1 (3, 3, F's shape), in R's axes, moments with C = 1."""
    ci, si = math.cos(I), math.sin(I)
    F = np.asarray(F, dtype=float)
    cF, sF = np.cos(F), np.sin(F)
    mom = moments.reshape((3,) + (1,) * F.ndim)
    f = 0.0
    m0 = 0.0
    for gm_r3, v in directions:
        y, z = ci * v[1] + si * v[2], -si * v[1] + ci * v[2]           # Rx(−I)
        u = np.stack(np.broadcast_arrays(cF * v[0] + sF * y, -sF * v[0] + cF * y, z))   # Rz(−F): u in R
        iu = mom * u
        su, siu = skew(u), skew(iu)
        f = f + 3.0 * gm_r3 * np.cross(u, iu, axis=0)
        m0 = m0 + 3.0 * gm_r3 * (np.einsum("ij...,jk...->ik...", siu, su)
                                 - np.einsum("ij...,j,jk...->ik...", su, moments, su))
    nu, w3, fdot = frame_rates(I)
    w = np.stack([nu * sF, nu * cF, np.full(F.shape, w3)])
    wdot = np.stack([nu * fdot * cF, -nu * fdot * sF, np.zeros(F.shape)])
    sw, siw, swd = skew(w), skew(mom * w), skew(wdot)
    Im = np.diag(moments)
    f_kin = -mom * wdot - np.cross(w, mom * w, axis=0)
    m1 = np.einsum("ij,jk...->ik...", Im, sw) - siw + np.einsum("ij...,jk->ik...", sw, Im)
    m0_kin = (np.einsum("ij,jk...->ik...", Im, swd) - np.einsum("ij...,jk...->ik...", siw, sw)
              + np.einsum("ij...,j,jk...->ik...", sw, moments, sw))
    return f + f_kin, m0 + m0_kin, m1


def torus_fields(grid: tuple, sun: bool, I: float, moments: np.ndarray):
    """:func:`linearised_equations` on the torus grid: f (3, grid), M0 (3, 3, grid), M1 (3, 3, NF)."""
    nf = grid[2]
    F = (2.0 * math.pi * np.arange(nf) / nf).reshape(1, 1, nf, 1, 1)
    f, m0, m1 = linearised_equations(perturber_directions(grid, sun), F, I, moments)
    return f, m0, m1.reshape(3, 3, nf)
