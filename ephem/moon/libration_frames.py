"""The Moon's frames in small rotations: the general precession that turns the frame of date, [v×] and exp([θ×]).

Shared by the libration series (:mod:`ephem.moon.libration_series`), the torque on the reference frame
(:mod:`ephem.moon.libration_forcing`) and the solver (:mod:`ephem.moon.physical_librations`), below all three so
that none reaches the others through them. Radians and days.
"""
from __future__ import annotations

import numpy as np

from ..base.constants import ARCSEC, GENERAL_PRECESSION_ARCSEC_PER_CENTURY, JULIAN_CENTURY_DAYS

#: p_A, the general precession in longitude (IERS Conventions 2010 eq. 5.39, Capitaine et al. 2003), rad/day: the
#: rate at which the mean equinox of date, the origin of Ω and of the Moon's longitude, regresses. The frame of
#: date turns at −p_A about the ecliptic pole, so the node turns in space at Ω̇ − p_A.
GENERAL_PRECESSION_RATE = GENERAL_PRECESSION_ARCSEC_PER_CENTURY * ARCSEC / JULIAN_CENTURY_DAYS


def skew(v: np.ndarray) -> np.ndarray:
    """[v×] for v of shape (3, ...): shape (3, 3, ...)."""
    z = np.zeros_like(v[0])
    return np.array([[z, -v[2], v[1]], [v[2], z, -v[0]], [-v[1], v[0], z]])


def rodrigues(th: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """exp([θ×]) and the right Jacobian J_r(θ) (ω = Q^T w + J_r θ̇ for Q = exp([θ×])), (3, 3, ...)."""
    angle = np.sqrt(np.einsum("i...,i...->...", th, th))
    small = angle < 1e-4
    safe = np.where(small, 1.0, angle)
    a2 = angle * angle
    # series below 1e-4 rad (Taylor to a⁴: 1e-20 left), closed forms above
    s1 = np.where(small, 1.0 - a2 / 6.0 + a2 * a2 / 120.0, np.sin(safe) / safe)
    c1 = np.where(small, 0.5 - a2 / 24.0 + a2 * a2 / 720.0, (1.0 - np.cos(safe)) / safe**2)
    d1 = np.where(small, 1.0 / 6.0 - a2 / 120.0 + a2 * a2 / 5040.0, (safe - np.sin(safe)) / safe**3)
    k = skew(th)
    kk = np.einsum("ij...,jk...->ik...", k, k)
    eye = np.eye(3).reshape((3, 3) + (1,) * (th.ndim - 1))
    return eye + s1 * k + c1 * kk, eye - c1 * k + d1 * kk
