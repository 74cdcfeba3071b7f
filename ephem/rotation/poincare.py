"""The non-singular variables that replace Andoyer's near J = 0, and the main problem's action-angles.

Regular at J = 0 (and J = π); the action-angle variables are those of short-axis-mode rotation.

- Poincaré-type variables (Lara 2018 §2.3, eqs. 7-10): x = −√(2(M − N)) sin ν, X = √(2(M − N)) cos ν, g = μ + ν,
  G = M, regular at J = 0 and computed from the body components so that they keep full relative precision for any
  small J; ``hemisphere=-1`` gives the mirror set, regular at J = π (see :mod:`ephem.rotation.andoyer`); the
  main problem and the perturbation in them (Lara 2018 eqs. 15, 19);
- the complex variables (Lara 2018 §3, eqs. 20-24): x = (u − iU)/√(2ω), X = √(ω/2)(U − iu), g = √κ v, G = V/√κ,
  which turn the main problem into V²/(2Cκ) − (V√κ/C) i u U (eq. 25);
- the main problem's action-angle variables (ℓ, g, L, G) for the Lie series (:mod:`ephem.rotation.lie_series`).

Angles in radians, vectorised over leading axes; the conventions are :mod:`ephem.rotation.andoyer`'s.
"""
from __future__ import annotations

import math

import numpy as np

from ..base.errors import InvalidInputError
from .andoyer import (N_OVER_M_SLACK, InertiaParameters, check_finite, check_moments, check_n, check_vector,
                      inertia_parameters, invariable_frame, rot1_cs, rot3, wrap_angle)


# --------------------------------------------------------------------------- the main problem in Poincaré variables


def sam_main_problem_poincare(x, X, G, moments) -> np.ndarray:
    """Eq. 15 of Lara 2018: 𝓜 = G²/(2C) + (G/C) (2α/(1 + ω²)) ½ (X² + ω² x²), a harmonic oscillator of frequency ω."""
    p = _complex_params(moments)
    x, X, G = (np.asarray(v, dtype=float) for v in (x, X, G))
    w2 = p.omega * p.omega
    return 0.5 * G * G / p.C + G / p.C * (2.0 * p.alpha / (1.0 + w2)) * 0.5 * (X * X + w2 * x * x)


def sam_perturbation_poincare(x, X, moments) -> np.ndarray:
    """Eq. 19 of Lara 2018: 𝓟 = −α/(8C) (2ω²/(ω² + 1) x⁴ + 2 x² X² + 2/(ω² + 1) X⁴), a quartic."""
    p = _complex_params(moments)
    x, X = np.asarray(x, dtype=float), np.asarray(X, dtype=float)
    w2 = p.omega * p.omega
    return -p.alpha / (8.0 * p.C) * (2.0 * w2 / (w2 + 1.0) * x ** 4 + 2.0 * x * x * X * X + 2.0 / (w2 + 1.0) * X ** 4)


# --------------------------------------------------------------------------- Poincaré-type variables


def _hemisphere(h) -> int:
    if h not in (1, -1):
        raise InvalidInputError("hemisphere", f"must be +1 (regular at J = 0) or -1 (regular at J = 180°), got {h!r}")
    return int(h)


def poincare_from_andoyer(mu, nu, M, N, hemisphere: int = 1) -> tuple[np.ndarray, ...]:
    """(x, g, X, G) of Andoyer (μ, ν, M, N) (Lara 2018 eqs. 7-10; s = ``hemisphere``):

    x = −s √(2(M − sN)) sin ν, X = √(2(M − sN)) cos ν, g = μ + sν, G = M.
    Canonical: M dμ + N dν − (X dx + G dg) = d(½(M − N) sin 2ν) for s = 1.
    """
    s = _hemisphere(hemisphere)
    M, N = check_n(M, N)
    check_finite("andoyer angles", mu, nu)
    rho = np.sqrt(2.0 * (M - s * N))
    return -s * rho * np.sin(nu), wrap_angle(mu + s * nu), rho * np.cos(nu), M.copy()


def andoyer_from_poincare(x, g, X, G, hemisphere: int = 1) -> tuple[np.ndarray, ...]:
    """(μ, ν, M, N) of (x, g, X, G) (Lara 2018 eqs. 11-14): N = s(G − ½(x² + X²)), sin ν = −s x/ρ, cos ν = X/ρ.

    ν = 0 at the pole x = X = 0 (J = 0 for s = 1, J = π for s = −1).
    """
    s = _hemisphere(hemisphere)
    check_finite("poincare variables", x, g, X, G)
    x, X, G = (np.asarray(v, dtype=float) for v in (x, X, G))
    if np.any(G <= 0.0):
        raise InvalidInputError("G", "G = M = |L| must be positive")
    half = 0.5 * (x * x + X * X)    # M − sN
    if np.any(half > 2.0 * G * (1.0 + N_OVER_M_SLACK)):
        raise InvalidInputError("x, X", "½(x² + X²) = M − sN must not exceed 2M")
    nu = np.arctan2(-s * x, X)
    return wrap_angle(g - s * nu), nu, G.copy(), s * (G - half)


def poincare_from_attitude(R, L_body, hemisphere: int = 1) -> tuple[np.ndarray, ...]:
    """(λ, x, g, Λ, X, G) of an attitude and body momentum, regular at J = 0 (s = 1) or J = π (s = −1).

    x = −s L1 √(2/(M + sN)), X = L2 √(2/(M + sN)) (since M² − N² = (M − sN)(M + sN)): the body
    components carry J at full relative precision, ν is never formed. g = μ + sν
    comes from the regular entries of Q = R R_invᵀ (see :func:`andoyer_from_attitude`).
    """
    s = _hemisphere(hemisphere)
    R = np.asarray(R, dtype=float)
    check_finite("attitude", R)
    L = check_vector("L_body", L_body)
    G = np.einsum("...ji,...j->...i", R, L)
    lam, Lam, M, R_inv = invariable_frame(G)
    Q = R @ np.swapaxes(R_inv, -1, -2)
    # own hemisphere (sN >= 0): k = √(2/(M + sN)), regular at the pole. Other hemisphere: the same k
    # written √(2(M − sN))/h, h = √(L1² + L2²), finite up to its pole where ν (so x : X) is undefined
    # and ν = 0 is taken.
    L1, L2, L3 = L[..., 0], L[..., 1], L[..., 2]
    own = s * L3 >= 0.0
    h = np.hypot(L1, L2)
    k_own = np.sqrt(2.0 / np.where(own, M + s * L3, M))
    k_far = np.sqrt(2.0 * (M - s * L3)) / np.where(h > 0.0, h, 1.0)
    at_far_pole = ~own & (h == 0.0)
    k = np.where(own, k_own, k_far)
    L1 = np.where(at_far_pole, 0.0, L1)
    L2 = np.where(at_far_pole, 1.0, L2)
    if s == 1:
        g = np.arctan2(Q[..., 0, 1] - Q[..., 1, 0], Q[..., 0, 0] + Q[..., 1, 1])
    else:
        g = np.arctan2(Q[..., 0, 1] + Q[..., 1, 0], Q[..., 0, 0] - Q[..., 1, 1])
    return lam, -s * L1 * k, g, Lam, L2 * k, M


def attitude_from_poincare(lam, x, g, Lam, X, G, hemisphere: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """(R, L_b) of (λ, x, g, Λ, X, G), without passing through ν (regular at the pole of the hemisphere).

    With ρ² = x² + X² = 2(M − sN): L_b = (−s x, X, 0)·√((M + sN)/2) + (0, 0, N)
    and R = R3(ν) R1(J) R3(μ) R1(I) R3(λ) rebuilt as W R3(g) R1(I) R3(λ), where
    W = R3(ν) R1(J) R3(−sν) is formed from (sin ν, cos ν) sin J and cos J only.
    """
    s = _hemisphere(hemisphere)
    check_finite("poincare variables", lam, x, g, Lam, X, G)
    x, X, G, Lam = (np.asarray(v, dtype=float) for v in (x, X, G, Lam))
    _, Lam = check_n(G, Lam)
    half = 0.5 * (x * x + X * X)
    N = s * (G - half)
    w = np.sqrt(np.maximum(G + s * N, 0.0) / 2.0)  # √((M + sN)/2)
    L = np.stack(np.broadcast_arrays(-s * x * w, X * w, N), axis=-1)
    M = G
    # unit vector of L in the body frame and the rotation W = R3(ν) R1(J) R3(−sν)
    e1, e2, cJ = L[..., 0] / M, L[..., 1] / M, N / M     # e1 = sJ sν, e2 = sJ cν
    W = _w_matrix(e1, e2, cJ, s)
    sI = np.sqrt((M - Lam) * (M + Lam)) / M
    return W @ rot3(g) @ rot1_cs(Lam / M, sI) @ rot3(lam), L


def _w_matrix(e1, e2, cJ, s: int) -> np.ndarray:
    """W = R3(ν) R1(J) R3(−sν) from e1 = sJ sν, e2 = sJ cν and cos J, with a = 1/(1 + s cJ).

    Expanding the product and using sin²J = (1 − cJ)(1 + cJ) leaves only e1, e2,
    cJ and a, which stay finite at the pole of the hemisphere (J = 0 for s = 1,
    J = π for s = −1), so ν is never formed:
    s = 1:  [[1 − a e1², −a e1 e2, e1], [−a e1 e2, 1 − a e2², e2], [−e1, −e2, cJ]];
    s = −1: [[1 − a e1², a e1 e2, e1], [−a e1 e2, a e2² − 1, e2], [e1, −e2, cJ]].
    """
    den = 1.0 + s * cJ
    far_pole = den <= 0.0        # the other hemisphere's pole: ν undefined there, ν = 0 taken (W = R1(J))
    a = 1.0 / np.where(far_pole, 1.0, den)
    if s == 1:
        W = np.stack([
            np.stack([1.0 - a * e1 * e1, -a * e1 * e2, e1], -1),
            np.stack([-a * e1 * e2, 1.0 - a * e2 * e2, e2], -1),
            np.stack([-e1, -e2, cJ], -1)], -2)
    else:
        W = np.stack([
            np.stack([1.0 - a * e1 * e1, a * e1 * e2, e1], -1),
            np.stack([-a * e1 * e2, a * e2 * e2 - 1.0, e2], -1),
            np.stack([e1, -e2, cJ], -1)], -2)
    return np.where(far_pole[..., None, None], rot1_cs(cJ, np.zeros_like(cJ)), W)


def hamiltonian_poincare(x, X, G, moments) -> np.ndarray:
    """The free-rigid-body Hamiltonian in the Poincaré-type variables (s = 1), no α, β needed:

    H = G²/(2C) + ¼ (2G − ½ρ²) [(1/A − 1/C) x² + (1/B − 1/C) X²], ρ² = x² + X²,
    which is ½ Σ L_i²/I_i with L1² = x²(M + N)/2, L2² = X²(M + N)/2, M + N = 2G − ½ρ².
    """
    a, b, c = check_moments(moments)
    x, X, G = (np.asarray(v, dtype=float) for v in (x, X, G))
    plus = 2.0 * G - 0.5 * (x * x + X * X)   # M + N
    return 0.5 * G * G / c + 0.25 * plus * ((c - a) / (a * c) * x * x + (c - b) / (b * c) * X * X)


# --------------------------------------------------------------------------- complex variables


def _complex_params(moments) -> InertiaParameters:
    p = inertia_parameters(moments)
    if p.A == p.C:
        raise InvalidInputError("moments", "A = B = C: the SAM oscillator has zero frequency (no complex variables)")
    if p.B == p.C:
        raise InvalidInputError("moments", "B = C: the SAM oscillator frequency ω = √((1+β)/(1−β)) is infinite")
    return p


def complex_from_poincare(x, g, X, G, moments) -> tuple[np.ndarray, ...]:
    """(u, v, U, V) of (x, g, X, G) (Lara 2018 eqs. 20-24 with Ω = ω, κ = √((C/A − 1)(C/B − 1))):

    u = ½(√(2ω) x + i √(2/ω) X), U = ½(√(2/ω) X + i √(2ω) x), v = g/√κ, V = √κ G.
    For real (x, X), U = i ū, so u U = i|u|² and the main problem (eq. 25) is real.
    """
    p = _complex_params(moments)
    check_finite("poincare variables", x, g, X, G)
    a = math.sqrt(2.0 * p.omega) * np.asarray(x, dtype=float)
    b = math.sqrt(2.0 / p.omega) * np.asarray(X, dtype=float)
    sk = math.sqrt(p.kappa)
    return 0.5 * (a + 1j * b), np.asarray(g, dtype=float) / sk, 0.5 * (b + 1j * a), sk * np.asarray(G, dtype=float)


def poincare_from_complex(u, v, U, V, moments) -> tuple[np.ndarray, ...]:
    """(x, g, X, G) of (u, v, U, V): x = (u − iU)/√(2ω), X = √(ω/2)(U − iu), g = √κ v, G = V/√κ.

    x and X are returned complex (Lara treats u and U as independent); they are
    real, to rounding, for the images of real states (U = i ū).
    """
    p = _complex_params(moments)
    u, U = np.asarray(u, dtype=complex), np.asarray(U, dtype=complex)
    sk = math.sqrt(p.kappa)
    return ((u - 1j * U) / math.sqrt(2.0 * p.omega), sk * np.asarray(v), math.sqrt(0.5 * p.omega) * (U - 1j * u),
            np.asarray(V) / sk)


def sam_main_problem_complex(u, U, V, moments) -> np.ndarray:
    """Main problem of SAM rotation in complex variables (Lara 2018 eq. 25): V²/(2Cκ) − (V√κ/C) i u U."""
    p = _complex_params(moments)
    return V * V / (2.0 * p.C * p.kappa) - V * math.sqrt(p.kappa) / p.C * 1j * np.asarray(u) * np.asarray(U)


def sam_perturbation_complex(u, U, moments) -> np.ndarray:
    """Perturbation of SAM rotation in complex variables (Lara 2018 eq. 26): α/(4C) [2u²U² − iβ(u³U − uU³)].

    Main problem plus perturbation is the full free-rigid-body Hamiltonian.
    """
    p = _complex_params(moments)
    u, U = np.asarray(u), np.asarray(U)
    return p.alpha / (4.0 * p.C) * (2.0 * u * u * U * U - 1j * p.beta * (u ** 3 * U - u * U ** 3))


# --------------------------------------------------------------------------- main-problem action-angle variables


def _beta_for_sam(moments) -> InertiaParameters:
    p = inertia_parameters(moments)
    if p.A == p.C or p.B == p.C:
        raise InvalidInputError("moments", "the SAM main problem needs B < C (β < 1) and a non-spherical body")
    return p


def sam_action_angle_from_andoyer(mu, nu, M, N, moments) -> tuple[np.ndarray, ...]:
    """Action-angle variables (ℓ, g, L, G) of the main problem of SAM rotation (Lara 2014 eqs. 22-25):

    sin ℓ = −√(1+β) sin ν / √(1 − β cos 2ν), cos ℓ = √(1−β) cos ν / √(1 − β cos 2ν),
    g = μ + ν, G = M, L = (M − N)(1 − β cos 2ν)/√(1 − β²).
    Equivalently x = √(2L/ω) sin ℓ, X = √(2ωL) cos ℓ (Lara 2018 eq. 17).
    """
    p = _beta_for_sam(moments)
    M, N = check_n(M, N)
    check_finite("andoyer angles", mu, nu)
    be = p.beta
    c2 = np.cos(2.0 * nu)
    ell = np.arctan2(-math.sqrt(1.0 + be) * np.sin(nu), math.sqrt(1.0 - be) * np.cos(nu))
    L = (M - N) * (1.0 - be * c2) / math.sqrt(1.0 - be * be)
    return ell, wrap_angle(mu + nu), L, M.copy()


def andoyer_from_sam_action_angle(ell, g, L, G, moments) -> tuple[np.ndarray, ...]:
    """Inverse of :func:`sam_action_angle_from_andoyer` (Lara 2014 eqs. 18-21):

    sin ν = −√(1−β) sin ℓ / √(1 + β cos 2ℓ), cos ν = √(1+β) cos ℓ / √(1 + β cos 2ℓ),
    μ = g − ν, M = G, N = G − L (1 + β cos 2ℓ)/√(1 − β²).
    """
    p = _beta_for_sam(moments)
    check_finite("action-angle variables", ell, g, L, G)
    be = p.beta
    nu = np.arctan2(-math.sqrt(1.0 - be) * np.sin(ell), math.sqrt(1.0 + be) * np.cos(ell))
    N = np.asarray(G, dtype=float) - np.asarray(L, dtype=float) * (1.0 + be * np.cos(2.0 * ell)) / math.sqrt(1.0 - be * be)
    return wrap_angle(g - nu), nu, np.asarray(G, dtype=float).copy(), N
