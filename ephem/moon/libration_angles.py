"""The Moon's libration angles: the Cassini state's turning frame R, and Eckhardt's ρ, σ, τ from the rotation θ.

R = Rz(Ω + π) Rx(I) Rz(F) (:func:`reference_frame`; eq. (R) of :mod:`ephem.moon.physical_librations`'s docstring)
turns uniformly, and the principal axes are B = R exp([θ×]). Eckhardt's (1981) variables are B's 3-1-3 Euler angles
from the ecliptic of date (eq. (E)): exactly, on the solver's grid (:func:`euler_angles`); and ρ's constant to first
order in θ, ρ = θ1 cos F − θ2 sin F, which the solver moves into the inclination I (:func:`rho_constant`,
:func:`remove_rho_constant`). Radians.
"""
from __future__ import annotations

import math

import numpy as np

from ..orbit.lunar import delaunay_arguments
from .libration_frames import skew


def reference_frame(jd_tdb, equator_inclination: float, node=None) -> np.ndarray:
    """R = Rz(Ω + π) Rx(I) Rz(F) (..., 3, 3): the Cassini state's uniformly turning frame (its columns: x toward
    the mean Earth, z the Cassini pole), from the mean ecliptic and equinox of date. Ω and F are the Delaunay
    arguments (IERS 2010 eq. 5.43); ``node`` replaces Ω."""
    args = delaunay_arguments(np.asarray(jd_tdb, dtype=float))
    om = args[..., 4] if node is None else np.asarray(node, dtype=float)
    F = args[..., 2]
    a, ci, si = om + math.pi, math.cos(equator_inclination), math.sin(equator_inclination)
    ca, sa, cf, sf = np.cos(a), np.sin(a), np.cos(F), np.sin(F)
    # Rz(a) Rx(I) Rz(F), written out
    return np.stack([
        np.stack([ca * cf - sa * ci * sf, -ca * sf - sa * ci * cf, sa * si], axis=-1),
        np.stack([sa * cf + ca * ci * sf, -sa * sf + ca * ci * cf, -ca * si], axis=-1),
        np.stack([si * sf, si * cf, np.full(np.shape(F), ci)], axis=-1)], axis=-2)


def euler_angles(theta_grid: np.ndarray, I: float, grid: tuple) -> np.ndarray:
    """Eckhardt's (ρ, σ, τ) (3, grid), exactly, from θ on the grid: with the principal axes B = Rz(Ω + π) M,
    M = Rx(I) Rz(F) exp([θ×]) = Rz(Δφ) Rx(I + ρ) Rz(F + Δψ) (3-1-3 Euler angles from the ecliptic of date,
    signed by atan2), σ = sin I Δφ and τ = Δφ + Δψ (the prime meridian's longitude along the node and the
    equator, less its mean L + π)."""
    th = theta_grid
    angle = np.sqrt(np.einsum("i...,i...->...", th, th))
    safe = np.where(angle > 0.0, angle, 1.0)
    k = skew(th)
    kk = np.einsum("ij...,jk...->ik...", k, k)
    q = (np.eye(3).reshape(3, 3, 1, 1, 1, 1, 1) + (np.sin(safe) / safe) * k + ((1.0 - np.cos(safe)) / safe**2) * kk)
    nf = grid[2]
    F = (2.0 * math.pi * np.arange(nf) / nf).reshape(1, 1, nf, 1, 1)
    cf, sf = np.cos(F), np.sin(F)
    # Rz(F) q, then Rx(I): only rows 1..3 of the result are needed as below
    r0 = cf * q[0] - sf * q[1]
    r1 = sf * q[0] + cf * q[1]
    r2 = q[2]
    ci, si = math.cos(I), math.sin(I)
    m0 = r0
    m1 = ci * r1 - si * r2
    m2 = si * r1 + ci * r2
    # M13 = sin Δφ sin θ, M23 = −cos Δφ sin θ, M31 = sin θ sin ψ, M32 = sin θ cos ψ, M33 = cos θ
    dphi = np.arctan2(m0[2], -m1[2])
    incl = np.arctan2(np.hypot(m0[2], m1[2]), m2[2])
    psi = np.arctan2(m2[0], m2[1])
    dpsi = np.angle(np.exp(1j * (psi - F)))
    return np.stack([incl - I, math.sin(I) * dphi, dphi + dpsi])


def rho_constant(spec: np.ndarray) -> float:
    """The constant of ρ = θ1 cos F − θ2 sin F (first order in θ) from θ's spectrum."""
    zero = (0, 0)
    t1p, t1m = spec[(0,) + zero + (1,) + zero], spec[(0,) + zero + (-1,) + zero]
    t2p, t2m = spec[(1,) + zero + (1,) + zero], spec[(1,) + zero + (-1,) + zero]
    return float((0.5 * (t1m + t1p) - (t2m - t2p) / 2j).real)


def remove_rho_constant(spec: np.ndarray, rho0: float) -> None:
    """θ −= ρ0 (cos F, −sin F, 0): what turning the reference frame R by ρ0 about the equator's node does to θ
    (to first order); the caller adds ρ0 to I."""
    zero = (0, 0)
    spec[(0,) + zero + (1,) + zero] -= 0.5 * rho0
    spec[(0,) + zero + (-1,) + zero] -= 0.5 * rho0
    spec[(1,) + zero + (1,) + zero] -= 0.5j * rho0
    spec[(1,) + zero + (-1,) + zero] += 0.5j * rho0
