"""The free rigid body's periods and Sadov's action-angle variables, from the exact solution.

The exact Euler-Poinsot solution is
(:mod:`ephem.rotation.euler_poinsot`).

- :func:`free_motion_periods`: the wobble and precession periods of a body from its moments, rotation period and
  wobble amplitude (:class:`FreePeriods`);
- :func:`sadov_action_angle`: Sadov's (1970) action-angle variables of the free rigid body from Andoyer's
  (:class:`SadovVariables`).

Moments normalised by C, time in days unless a name says otherwise.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.constants import ARCSEC
from ..base.errors import InvalidInputError
from .andoyer import N_OVER_M_SLACK, check_finite, check_moments, wrap_angle
from .elliptic_solution import elliprf, elliprj
from .euler_poinsot import FreeRotation


# --------------------------------------------------------------------------- periods for users


@dataclass(frozen=True)
class FreePeriods:
    """Free-motion periods, in the unit of the rotation period given (see :func:`free_motion_periods`)."""

    mode: str
    wobble_period: float        # L about the C (A) axis in the body frame: 4K(m)/p
    precession_period: float    # the figure axis about L in space: 2π/n_μ
    euler_period: float         # the J -> 0, A = B formula 2π A/(ω (C − A)) with ω = M/C, for comparison
    elliptic_parameter: float


def free_motion_periods(moments, rotation_period: float, wobble_arcsec: float = 0.0,
                        nu_deg: float = 0.0) -> FreePeriods:
    """Wobble and precession periods of a body with M = 2π C / ``rotation_period`` (nominal ω = M/C).

    ``wobble_arcsec`` is J, the angle between L and the C axis (0 to 648000");
    ``nu_deg`` is Andoyer's ν at that J (ν = 0 puts L in the B-C plane, where
    the short-axis J is largest). Periods are in the unit of ``rotation_period``.
    """
    A, B, C = check_moments(moments, allow_spherical=False)
    check_finite("rotation_period", rotation_period)
    if not rotation_period > 0.0:
        raise InvalidInputError("rotation_period", "must be positive")
    J = float(wobble_arcsec) * ARCSEC
    M = 2.0 * math.pi * C / rotation_period
    fr = FreeRotation.from_andoyer((A, B, C), M, J, math.radians(nu_deg))
    euler = 2.0 * math.pi * A / ((M / C) * (C - A))
    return FreePeriods(fr.mode, fr.wobble_period, fr.precession_period, euler, fr.elliptic_parameter)


# --------------------------------------------------------------------------- Sadov's action-angle variables


@dataclass(frozen=True)
class SadovVariables:
    """Sadov's action-angle variables (ℓ, g, L, G) and their frequencies (Lara 2018 Appendix, eqs. A1-A11).

    n_ell is ∂H/∂L = −πp/(2K) (negative for N > 0: ℓ decreases with time);
    n_g = ∂H/∂G by eq. A7. Mirror states (N < 0) are mapped by (ν, N) -> (−ν, −N).
    """

    ell: np.ndarray
    g: np.ndarray
    L: np.ndarray
    G: np.ndarray
    n_ell: np.ndarray
    n_g: np.ndarray
    m: np.ndarray


def sadov_action_angle(mu, nu, M, N, moments) -> SadovVariables:
    """Sadov's variables of short-axis-mode states given in Andoyer variables (radians).

    Eqs. (Lara 2018 A1-A10, with f = C(B−A)/(A(C−B)), m from A4):
    ψ: cos ψ = √(1+f) sin ν/√(1 + f sin²ν), sin ψ = cos ν/√(1 + f sin²ν)  (A5)
    ℓ = −π F(ψ|m)/(2K)                                                      (A8)
    g = μ + √(1+f) √((f+m)/f) [Π(−f|m) F(ψ|m)/K − Π(−f, ψ|m)]               (A9)
    L = (2M/π) √(1+f) √((f+m)/f) [Π(−f|m) − m K/(f+m)]                      (A10)
    n_g = −(L/G) n_ℓ + (G/A)(1 − (C−A) f/(C (f+m)))                          (A7)
    evaluated in Carlson's forms with √(f/(f+m)) = c/M (the amplitude of N over
    M), so that A = B (f = 0) is the regular limit. The seed's eq. A6 prints
    n_ℓ with a + sign; ℓ of eq. A8 decreases in time for N > 0 and eq. A7 only
    gives the right n_g with n_ℓ < 0, so n_ℓ = −πp/(2K) here (see the tests).
    """
    A, B, C = check_moments(moments, allow_spherical=False)
    mu, nu, M, N = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (mu, nu, M, N)))
    check_finite("andoyer variables", mu, nu, M, N)
    flip = N < 0.0
    nu, N = np.where(flip, -nu, nu), np.abs(N)
    if np.any(N > M * (1.0 + N_OVER_M_SLACK)) or np.any(M <= 0.0):
        raise InvalidInputError("N", "|N| <= M and M > 0 are required")
    sj = np.sqrt(np.maximum((M - N) * (M + N), 0.0))
    l1, l2, l3 = sj * np.sin(nu), sj * np.cos(nu), N
    d_up = l1 * l1 * (C - A) / A + l2 * l2 * (C - B) / B
    d_lo = l2 * l2 * (B - A) / B + l3 * l3 * (C - A) / C
    D = l3 * l3 * (C - B) / C - l1 * l1 * (B - A) / A
    if np.any(D <= 0.0) or C == B:
        raise InvalidInputError("state", "Sadov's variables (Lara 2018 Appendix) need short-axis-mode rotation "
                                "(energy below the separatrix value M²/(2B)) and B < C")
    f = C * (B - A) / (A * (C - B))
    m = (B - A) * d_up / ((C - B) * d_lo)
    m1 = (C - A) * D / ((C - B) * d_lo)
    K = elliprf(0.0, m1, 1.0)
    rj = elliprj(0.0, m1, 1.0, 1.0 + f)
    q = np.sqrt(C * d_lo / (C - A)) / M                       # √(f/(f+m)) = c/M
    p = np.sqrt((C - B) * d_lo / (A * B * C))
    # ψ and its reduction to [−π/2, π/2): F(ψ) = 2kK + F(ψ_r); the A9 bracket is π-periodic in ψ
    psi = np.arctan2(np.cos(nu), math.sqrt(1.0 + f) * np.sin(nu))
    k = np.floor((psi + 0.5 * np.pi) / np.pi)
    psi_r = psi - k * np.pi
    s, c = np.sin(psi_r), np.cos(psi_r)
    delta2 = c * c + m1 * s * s                               # 1 − m sin²ψ without cancellation
    F = s * elliprf(c * c, delta2, 1.0) + 2.0 * k * K
    bracket = f / 3.0 * (s ** 3 * elliprj(c * c, delta2, 1.0, 1.0 + f * s * s) - rj * (F - 2.0 * k * K) / K)
    sqf = math.sqrt(1.0 + f)
    ell = -0.5 * np.pi * F / K
    g = mu + sqf * bracket / q                                # √((f+m)/f) = 1/q; bracket carries the factor f
    L = 2.0 * M * K / np.pi * sqf * (q - f / q * rj / (3.0 * K))
    n_ell = -0.5 * np.pi * p / K
    n_g = -(L / M) * n_ell + M / A * (1.0 - (C - A) / C * q * q)
    return SadovVariables(ell, wrap_angle(g), L, M.copy(), n_ell, n_g, m)
