"""The elliptic-function solution of the Euler-Poinsot problem in its core frame.

What
:class:`ephem.rotation.euler_poinsot.FreeRotation` is built from and evaluates.

The equations are those of :mod:`ephem.rotation.euler_poinsot`'s docstring (Landau & Lifshitz, Mechanics, §37;
Gurfil et al. 2007, eqs. 34-36), in the core frame: moments I1 <= I2 <= I3 with I3 the axis L circulates about
(A, B, C for the short-axis mode; C, B, A in the frame P b for the long-axis mode).

- :func:`jacobi_reduced`: sn, cn, dn evaluated on a quarter period only (DLMF 22.4.3; Abramowitz & Stegun
  16.15.1-3 near the separatrix, with the exact 1 − m);
- :func:`differences`: the integrals M², d_up = 2E I3 − M², d_lo = M² − 2E I1, D = M² − 2E I2 as sums of
  squares (no cancellation), whose sign of D gives the mode; :func:`is_stationary`: ω ∥ L;
- :class:`CoreConstants`, :func:`core_constants`: the constants of L1 = a cn u, L2 = s b sn u, L3 = s c dn u
  (amplitudes, p, m, 1 − m, K, Sadov's f, ρ = 1 − Π(−f|m)/K, u0) and :func:`periodic_part`, the 2K-periodic
  part P(u) of the precession angle μ (DLMF 19.25.14; Carlson, Numer. Algorithms 10 (1995) 13);
- :func:`separatrix_constants`, :func:`separatrix_integral`: the closed-form limit D = 0 (m = 1), never evaluated
  through K(1) = ∞.

Accuracy: that of the module docstring of :mod:`ephem.rotation.euler_poinsot` (~1e-15 in the Jacobi functions
for 1 − m > 1e-5; see :func:`jacobi_reduced`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np


# scipy.special's Jacobi and Carlson functions, imported on first use: scipy.special costs 0.15-0.2 s to import,
# which every answer paid at start-up (the ladder imports this module) though only the free wobble calls them
def ellipj(u, m):
    """scipy.special.ellipj (sn, cn, dn, am)."""
    from scipy.special import ellipj as jacobi
    return jacobi(u, m)


def elliprf(x, y, z):
    """scipy.special.elliprf, Carlson's R_F."""
    from scipy.special import elliprf as carlson_rf
    return carlson_rf(x, y, z)


def elliprj(x, y, z, p):
    """scipy.special.elliprj, Carlson's R_J."""
    from scipy.special import elliprj as carlson_rj
    return carlson_rj(x, y, z, p)



# --------------------------------------------------------------------------- elliptic helpers


#: below this 1 − m the Jacobi functions come from the m -> 1 expansion with the exact 1 − m (see below)
NEAR_SEPARATRIX_M1 = 1e-9


def _ellipj_near_one(v, m1: float):
    """sn, cn, dn for 1 − m = m1 small, |v| <= K/2 (Abramowitz & Stegun 16.15.1-3, first order in m1):

    sn = tanh v + ¼ m1 (sinh v cosh v − v) sech²v, cn = sech v − ¼ m1 (sinh v cosh v − v) tanh v sech v,
    dn = sech v + ¼ m1 (sinh v cosh v + v) tanh v sech v.
    scipy's ellipj switches to the same expansion only for 1 − m < 1e-10 and then rebuilds 1 − m from the
    rounded m (1 % error at 1 − m = 1e-14); with the exact m1 the expansion is good to ~3e-16 for
    m1 <= 3e-10 and 1e-14 at 1e-9 on |v| <= K/2 (checked against mpmath at 40 digits).
    """
    ch, sh, th = np.cosh(v), np.sinh(v), np.tanh(v)
    se = 1.0 / ch
    q = 0.25 * m1 * (sh * ch - v)
    return th + q * se * se, se - q * th * se, se + 0.25 * m1 * (sh * ch + v) * th * se


def jacobi_reduced(u, m: float, m1: float, K: float):
    """sn, cn, dn of u and of its reduction r = u − 2Kj in [−K, K), plus r.

    Returns (sn, cn, dn, sn_r, cn_r, dn_r, r). ``m1`` = 1 − m is passed
    separately because near the separatrix it is known far better than
    1 − m. Arguments are first reduced modulo 2K (sn, cn change sign, dn does
    not), then |r| > K/2 is mapped to v = K − |r| <= K/2 with sn = cd(v),
    cn = k' sd(v), dn = k' nd(v) (DLMF 22.4.3), so that the functions are
    only evaluated on |v| <= K/2: by scipy's ellipj (Cephes), or for
    m1 < NEAR_SEPARATRIX_M1 by :func:`_ellipj_near_one`. Accuracy: ~1e-15 for
    1 − m > 1e-5; Cephes' AGM loses up to ~2e-13 (relative) for 5e-9 < 1 − m < 1e-6,
    far below the motion's own sensitivity ε/(1 − m) there.

    K must be K(m) computed from m1 (e.g. R_F(0, m1, 1)): from the rounded m it
    would be off by ~ε/(2 m1), a visible phase error near the separatrix.
    """
    u = np.asarray(u, dtype=float)
    j = np.floor((u + K) / (2.0 * K))
    r = u - 2.0 * K * j
    sign_j = 1.0 - 2.0 * np.mod(j, 2.0)        # (−1)^j
    ar = np.abs(r)
    far = ar > 0.5 * K
    v = np.where(far, K - ar, ar)
    if m1 < NEAR_SEPARATRIX_M1:
        sn_v, cn_v, dn_v = _ellipj_near_one(v, m1)
    else:
        sn_v, cn_v, dn_v, _ = ellipj(v, m)
    k1 = math.sqrt(m1)
    sn_a = np.where(far, cn_v / dn_v, sn_v)
    cn_r = np.where(far, k1 * sn_v / dn_v, cn_v)
    dn_r = np.where(far, k1 / dn_v, dn_v)
    sn_r = np.where(r < 0.0, -sn_a, sn_a)
    return sign_j * sn_r, sign_j * cn_r, dn_r, sn_r, cn_r, dn_r, r


def _incomplete_first_kind(sn, cn, dn, K: float):
    """F(φ|m) from sin φ, cos φ and Δ = √(1 − m sin²φ), for φ in (−π, π] (Carlson: F = s R_F(c², Δ², 1))."""
    core = sn * elliprf(cn * cn, dn * dn, 1.0)
    return np.where(cn >= 0.0, core, np.copysign(2.0 * K, sn) - core)


# --------------------------------------------------------------------------- the integrals


def differences(L, I1: float, I2: float, I3: float):
    """(M², d_up, d_lo, D) = (|L|², 2E I3 − M², M² − 2E I1, M² − 2E I2) as sums with no cancellation."""
    l1, l2, l3 = (float(x) for x in L)
    q1, q2, q3 = l1 * l1, l2 * l2, l3 * l3
    d_up = q1 * (I3 - I1) / I1 + q2 * (I3 - I2) / I2
    d_lo = q2 * (I2 - I1) / I2 + q3 * (I3 - I1) / I3
    D = q3 * (I3 - I2) / I3 - q1 * (I2 - I1) / I1
    return q1 + q2 + q3, d_up, d_lo, D


def is_stationary(L, A: float, B: float, C: float) -> bool:
    """True when ω = I⁻¹L is parallel to L (ω × L = 0 exactly): rotation about a principal axis."""
    l1, l2, l3 = (float(x) for x in L)
    return l2 * l3 * (1.0 / B - 1.0 / C) == 0.0 and l3 * l1 * (1.0 / A - 1.0 / C) == 0.0 \
        and l1 * l2 * (1.0 / A - 1.0 / B) == 0.0


@dataclass(frozen=True)
class CoreConstants:
    """Constants of the short-axis-mode form in the core frame (moments I1, I2, I3; I3 the circulation axis)."""

    I1: float
    I2: float
    I3: float
    a: float
    b: float
    c: float
    s3: float
    p: float
    m: float
    m1: float
    K: float
    f: float
    rho: float
    u0: float
    P0: float        # the periodic part P(u0)


def core_constants(L, I1: float, I2: float, I3: float, M2: float, d_up: float, d_lo: float, D: float) -> CoreConstants:
    """The elliptic-function solution L1 = a cn u, L2 = s b sn u, L3 = s c dn u (see euler_poinsot's docstring)."""
    a = math.sqrt(I1 * d_up / (I3 - I1))
    b = math.sqrt(I2 * d_up / (I3 - I2))
    c = math.sqrt(I3 * d_lo / (I3 - I1))
    # du/dt: + in the short-axis frame; − in the long-axis one, where (C, B, A) reverses every sign of
    # Euler's equations that the amplitudes' square roots cannot carry (a p = b c (I3 − I2)/(I2 I3))
    p = math.copysign(math.sqrt((I3 - I2) * d_lo / (I1 * I2 * I3)), I3 - I2)
    m = (I2 - I1) * d_up / ((I3 - I2) * d_lo) + 0.0   # + 0.0: no −0.0 when I1 = I2
    m1 = (I3 - I1) * D / ((I3 - I2) * d_lo)
    K = float(elliprf(0.0, m1, 1.0))
    f = I3 * (I2 - I1) / (I1 * (I3 - I2))
    rho = f / 3.0 * float(elliprj(0.0, m1, 1.0, 1.0 + f)) / K
    s3 = math.copysign(1.0, float(L[2]))
    cn0 = min(max(float(L[0]) / a, -1.0), 1.0)
    sn0 = min(max(s3 * float(L[1]) / b, -1.0), 1.0)
    dn0 = abs(float(L[2])) / c
    u0 = float(_incomplete_first_kind(np.float64(sn0), np.float64(cn0), np.float64(dn0), K))
    core = CoreConstants(I1, I2, I3, a, b, c, s3, p, m, m1, K, f, rho, u0, 0.0)
    reduced = jacobi_reduced(np.array([u0]), m, m1, K)[3:]
    return replace(core, P0=float(periodic_part(core, *reduced)[0]))


def periodic_part(core: CoreConstants, sn_r, cn_r, dn_r, r):
    """P(u) = ρ u_r − (f/3) sn³ R_J(cn², dn², 1, 1 + f sn²), the 2K-periodic part of ∫du/(1 + f sn²u)."""
    s2 = sn_r * sn_r
    return core.rho * r - core.f / 3.0 * sn_r * s2 * elliprj(cn_r * cn_r, dn_r * dn_r, 1.0, 1.0 + core.f * s2)


# --------------------------------------------------------------------------- the separatrix


def separatrix_constants(L, A, B, C, M, d_up, d_lo) -> tuple:
    """(a, c, p, s1, s3, f, u0) of L1 = s1 a sech u, L2 = s1 s3 M tanh u, L3 = s3 c sech u (D = 0, A < B < C).

    sinh u0 = tanh u0 / sech u0 = s1 s3 L2 / √(L1² + L3²) since a² + c² = M² there.
    """
    a = math.sqrt(A * d_up / (C - A))
    c = math.sqrt(C * d_lo / (C - A))
    p = math.sqrt((C - B) * d_lo / (A * B * C))
    s1, s3 = math.copysign(1.0, L[0]), math.copysign(1.0, L[2])
    u0 = math.asinh(s1 * s3 * L[1] / math.hypot(L[0], L[2]))
    return a, c, p, s1, s3, C * (B - A) / (A * (C - B)), u0


def separatrix_integral(u, f: float):
    """∫0^u du/(1 + f tanh²u) = [u + √f arctan(√f tanh u)]/(1 + f) (the m = 1 limit of Π(−f; am u|m))."""
    sf = math.sqrt(f)
    return (u + sf * np.arctan(sf * np.tanh(u))) / (1.0 + f)
