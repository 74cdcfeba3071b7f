"""Andoyer variables of a free rigid body.

The non-singular variables that replace them near J = 0 are in :mod:`ephem.rotation.poincare`.

Conventions (all angles in radians, vectorised over leading axes):

* Body frame: the principal axes (b1, b2, b3) with moments A <= B <= C, so b3
  is the axis of maximum inertia (the "figure" axis of a short-axis-mode
  rotator). Moments and angular momenta may be in any consistent units; time
  is then in (moment unit) / (momentum unit).
* Euler angles: the 3-1-3 sequence (φ, θ, ψ) of Gurfil et al. (2007, eqs. 1-2):
  R(φ, θ, ψ) = R3(ψ) R1(θ) R3(φ) takes inertial components to body components,
  with the passive rotations R1(a) = [[1, 0, 0], [0, c, s], [0, -s, c]],
  R3(a) = [[c, s, 0], [-s, c, 0], [0, 0, 1]]. A state is (φ, θ, ψ) and the
  body-frame angular momentum L_b = (L1, L2, L3).
* Andoyer variables (λ, μ, ν, Λ, M, N) (Lara 2014 §2; Gurfil et al. 2007 §3.2,
  who write them (h, g, l, H, G, L)): λ is the node of the invariable plane
  (normal to L) on the inertial x-y plane, μ the node of the body's b1-b2
  plane on the invariable plane measured from it, ν the angle from that node to
  b1; M = |L|, Λ = L·ẑ_inertial = M cos I, N = L·b3 = M cos J. Then
  R = R3(ν) R1(J) R3(μ) R1(I) R3(λ) (Lara 2018 eq. 34) and
  L_b = (√(M² − N²) sin ν, √(M² − N²) cos ν, N) (Gurfil et al. eqs. 39, 90-92).
* Hamiltonian (Lara 2014 eq. 1 = Lara 2018 eq. 1):
  H = ½ (sin²ν / A + cos²ν / B)(M² − N²) + N² / (2C), the kinetic energy
  ½ (L1²/A + L2²/B + L3²/C).

The Andoyer angles are singular where the nodes are undefined: μ and ν
separately at J = 0 and J = π (only μ + ν, resp. μ − ν, is defined), λ and μ
at I = 0 and I = π. Worse, near J = 0 the momentum N = M cos J cannot carry J
below ~1e-8 rad (M − N = M J²/2 is lost under the rounding of N). The
Poincaré-type variables of Lara (2018, §2.3, eqs. 7-10)

    x = −√(2(M − N)) sin ν,   X = √(2(M − N)) cos ν,   g = μ + ν,   G = M

are regular at J = 0: x = −L1 √(2/(M + N)), X = L2 √(2/(M + N)), computed here
from the body components so that they keep full relative precision for any
small J. ``hemisphere=-1`` gives the mirror set (x = √(2(M + N)) sin ν,
X = √(2(M + N)) cos ν, g = μ − ν), canonical by (ν, N) -> (−ν, −N) and regular
at J = π. The complex variables of Lara (2018, §3, eqs. 20-24),
x = (u − iU)/√(2ω), X = √(ω/2)(U − iu), g = √κ v, G = V/√κ, turn the main
problem of short-axis-mode rotation into V²/(2Cκ) − (V√κ/C) i u U (eq. 25).

Sources: M. Lara, "Short-axis-mode rotation of a free rigid body by
perturbation series", CeMDA 118 (2014) 221 (seeds/000); M. Lara, "Complex
variables approach to the short-axis-mode rotation of a rigid body", AMNS 3
(2018) 537 (seeds/002); P. Gurfil, A. Elipe, W. Tangren, M. Efroimsky, "The
Serret-Andoyer formalism in rigid-body dynamics: I", Regul. Chaotic Dyn. 12
(2007) 389 (seeds/003). Every formula used here was re-derived and is checked
by tests/rotation/test_andoyer.py (canonicity by numerical Jacobians, Hamiltonians
against the kinetic energy, round trips).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.errors import InvalidInputError


EPS = np.finfo(float).eps
#: |N| may exceed M by this relative amount (rounding of M = |L|) before it is an error
N_OVER_M_SLACK = 8.0 * EPS

# --------------------------------------------------------------------------- validation


def check_finite(field: str, *values) -> None:
    """Raise InvalidInputError if any value is NaN or infinite (NaN would otherwise propagate silently)."""
    for v in values:
        if not np.all(np.isfinite(np.asarray(v, dtype=float))):
            raise InvalidInputError(field, "must be finite (got NaN or infinity)")


def check_moments(moments, allow_spherical: bool = True) -> tuple[float, float, float]:
    """(A, B, C) as floats after checking 0 < A <= B <= C <= A + B.

    The last inequality is the triangle inequality every rigid body obeys
    (C = ∫(x² + y²) dm <= A + B). ``allow_spherical`` False rejects A = B = C,
    for which there is no free motion to compute (every axis is principal).
    """
    try:
        a, b, c = (float(x) for x in moments)
    except (TypeError, ValueError):
        raise InvalidInputError("moments", f"expected three principal moments (A, B, C), got {moments!r}") from None
    check_finite("moments", (a, b, c))
    if not 0.0 < a <= b <= c:
        raise InvalidInputError("moments", f"need 0 < A <= B <= C (A the smallest moment), got ({a}, {b}, {c})")
    if c > (a + b) * (1.0 + 4.0 * EPS):
        raise InvalidInputError("moments", f"C > A + B is impossible for a rigid body, got ({a}, {b}, {c})")
    if not allow_spherical and a == c:
        raise InvalidInputError("moments", "A = B = C: a spherical body has no free motion to compute "
                                "(L is fixed in the body and the body spins uniformly about it)")
    return a, b, c


def check_j(J, field: str = "J") -> np.ndarray:
    """J (rad) as an array after checking 0 <= J <= π (the angle between L and the C axis)."""
    J = np.asarray(J, dtype=float)
    check_finite(field, J)
    if np.any(J < 0.0) or np.any(J > math.pi):
        raise InvalidInputError(field, "the angle between L and the C axis must lie in [0°, 180°]")
    return J


def check_n(M, N) -> tuple[np.ndarray, np.ndarray]:
    """M > 0 and |N| <= M (cos J = N/M), with N clipped to ±M within rounding."""
    M, N = np.asarray(M, dtype=float), np.asarray(N, dtype=float)
    check_finite("M", M)
    check_finite("N", N)
    if np.any(M <= 0.0):
        raise InvalidInputError("M", "the angular momentum M = |L| must be positive")
    if np.any(np.abs(N) > M * (1.0 + N_OVER_M_SLACK)):
        raise InvalidInputError("N", "|N| <= M is required (cos J = N/M, J in [0°, 180°])")
    return M, np.clip(N, -M, M)


# --------------------------------------------------------------------------- inertia parameters


@dataclass(frozen=True)
class InertiaParameters:
    """Andoyer's and Lara's inertia parameters of a body (dimensionless except A, B, C).

    alpha, beta: α(1 + β) = C/A − 1, α(1 − β) = C/B − 1 (Lara 2014 eq. 2);
    omega = √((1 + β)/(1 − β)), the SAM oscillator frequency (Lara 2018 eq. 16);
    kappa = α√(1 − β²) = √((C/A − 1)(C/B − 1)) (Lara 2018 eq. 24; the Euler
    wobble frequency in units of M/C); f = C(B − A)/(A(C − B)), Sadov's
    characteristic (Lara 2018 eq. A1; Gurfil et al. 2007 κ², eq. 139).
    beta is 0 for a sphere by convention; omega and f are infinite when B = C.
    """

    A: float
    B: float
    C: float
    alpha: float
    beta: float
    omega: float
    kappa: float
    f: float


def inertia_parameters(moments) -> InertiaParameters:
    """The parameters of :class:`InertiaParameters` from (A, B, C)."""
    a, b, c = check_moments(moments)
    p, q = (c - a) / a, (c - b) / b          # C/A − 1, C/B − 1 without the cancellation of c/a − 1
    alpha = 0.5 * (p + q)
    beta = (p - q) / (p + q) if p + q > 0.0 else 0.0
    omega = math.sqrt(p / q) if q > 0.0 else math.inf   # √((1+β)/(1−β)) = √(p/q)
    f = c * (b - a) / (a * (c - b)) if c > b else math.inf
    return InertiaParameters(a, b, c, alpha, beta, omega, math.sqrt(p * q), f)


# --------------------------------------------------------------------------- rotations


def rot1_cs(c, s) -> np.ndarray:
    """Passive rotation about x from cos and sin (arrays broadcast); shape (..., 3, 3)."""
    c, s = np.broadcast_arrays(np.asarray(c, dtype=float), np.asarray(s, dtype=float))
    z, o = np.zeros_like(c), np.ones_like(c)
    return np.stack([np.stack([o, z, z], -1), np.stack([z, c, s], -1), np.stack([z, -s, c], -1)], -2)


def rot3_cs(c, s) -> np.ndarray:
    """Passive rotation about z from cos and sin; shape (..., 3, 3)."""
    c, s = np.broadcast_arrays(np.asarray(c, dtype=float), np.asarray(s, dtype=float))
    z, o = np.zeros_like(c), np.ones_like(c)
    return np.stack([np.stack([c, s, z], -1), np.stack([-s, c, z], -1), np.stack([z, z, o], -1)], -2)


def rot1(angle) -> np.ndarray:
    """R1(a) = [[1, 0, 0], [0, cos a, sin a], [0, −sin a, cos a]] (passive), shape (..., 3, 3)."""
    return rot1_cs(np.cos(angle), np.sin(angle))


def rot3(angle) -> np.ndarray:
    """R3(a) = [[cos a, sin a, 0], [−sin a, cos a, 0], [0, 0, 1]] (passive), shape (..., 3, 3)."""
    return rot3_cs(np.cos(angle), np.sin(angle))


def euler_matrix(phi, theta, psi) -> np.ndarray:
    """R = R3(ψ) R1(θ) R3(φ), inertial to body (3-1-3 Euler angles; Gurfil et al. 2007 eq. 2)."""
    check_finite("euler angles", phi, theta, psi)
    return rot3(psi) @ rot1(theta) @ rot3(phi)


def wrap_angle(a):
    """Angle in (−π, π]."""
    return np.pi - np.mod(np.pi - a, 2.0 * np.pi)


def _angles_313(R) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(first, middle, last) angles of R = R3(last) R1(middle) R3(first), stable at middle = 0 and π.

    The outer angles are ill-conditioned as sin(middle) -> 0 and only their sum
    (middle < π/2) or difference (middle > π/2) is defined; taking that
    combination from the regular entries R11 ± R22, R12 ∓ R21 (which carry the
    factor 1 ± cos(middle)) makes the returned triple rebuild R to rounding for
    every middle angle. At middle exactly 0 or π the first angle is 0.
    """
    R = np.asarray(R, dtype=float)
    middle = np.arctan2(np.hypot(R[..., 2, 0], R[..., 2, 1]), R[..., 2, 2])
    first = np.arctan2(R[..., 2, 0], -R[..., 2, 1])
    total = np.arctan2(R[..., 0, 1] - R[..., 1, 0], R[..., 0, 0] + R[..., 1, 1])   # first + last
    diff = np.arctan2(R[..., 0, 1] + R[..., 1, 0], R[..., 0, 0] - R[..., 1, 1])    # first − last
    last = np.where(middle <= 0.5 * np.pi, total - first, first - diff)
    return first, middle, wrap_angle(last)


def euler_from_matrix(R) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """3-1-3 Euler angles (φ, θ, ψ) of an inertial-to-body matrix, θ in [0, π], φ, ψ in (−π, π]."""
    return _angles_313(R)


# --------------------------------------------------------------------------- Andoyer <-> body momentum


def body_momentum_from_andoyer(nu, M, N) -> np.ndarray:
    """L_b = (√(M² − N²) sin ν, √(M² − N²) cos ν, N), shape (..., 3) (Gurfil et al. 2007 eqs. 90-92)."""
    M, N = check_n(M, N)
    check_finite("nu", nu)
    s = np.sqrt((M - N) * (M + N))   # factored: M² − N² loses nothing when N ≈ M
    return np.stack(np.broadcast_arrays(s * np.sin(nu), s * np.cos(nu), N), axis=-1)


def body_momentum_from_j(M, J, nu) -> np.ndarray:
    """L_b = M (sin J sin ν, sin J cos ν, cos J) for J in [0, π] (rad)."""
    J = check_j(J)
    M = np.asarray(M, dtype=float)
    check_finite("M", M)
    check_finite("nu", nu)
    if np.any(M <= 0.0):
        raise InvalidInputError("M", "the angular momentum M = |L| must be positive")
    s = M * np.sin(J)
    return np.stack(np.broadcast_arrays(s * np.sin(nu), s * np.cos(nu), M * np.cos(J)), axis=-1)


def check_vector(field: str, v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    if v.shape[-1:] != (3,):
        raise InvalidInputError(field, f"expected 3-vectors (..., 3), got shape {v.shape}")
    check_finite(field, v)
    return v


def andoyer_from_body_momentum(L_body) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ν, M, N) of body-frame angular momenta: ν = atan2(L1, L2) (0 when J = 0 or π), M = |L|, N = L3."""
    L = check_vector("L_body", L_body)
    M = np.linalg.norm(L, axis=-1)
    if np.any(M <= 0.0):
        raise InvalidInputError("L_body", "the angular momentum must not vanish")
    return np.arctan2(L[..., 0], L[..., 1]), M, L[..., 2].copy()


def inclination_j(L_body) -> np.ndarray:
    """J = angle between L and the C axis, atan2(√(L1² + L2²), L3): accurate at any J (unlike acos(N/M))."""
    L = check_vector("L_body", L_body)
    return np.arctan2(np.hypot(L[..., 0], L[..., 1]), L[..., 2])


def energy(L_body, moments) -> np.ndarray:
    """Kinetic energy T = ½ (L1²/A + L2²/B + L3²/C) (the Hamiltonian; Gurfil et al. 2007 eq. 38)."""
    a, b, c = check_moments(moments)
    L = check_vector("L_body", L_body)
    return 0.5 * (L[..., 0] ** 2 / a + L[..., 1] ** 2 / b + L[..., 2] ** 2 / c)


def momentum(L_body) -> np.ndarray:
    """M = |L|, the second integral of the torque-free motion."""
    return np.linalg.norm(check_vector("L_body", L_body), axis=-1)


# --------------------------------------------------------------------------- Hamiltonians


def hamiltonian(nu, M, N, moments) -> np.ndarray:
    """Free-rigid-body Hamiltonian in Andoyer variables (Lara 2014 eq. 1; Lara 2018 eq. 1):

    H = ½ (sin²ν / A + cos²ν / B)(M² − N²) + N² / (2C).
    """
    a, b, c = check_moments(moments)
    M, N = check_n(M, N)
    check_finite("nu", nu)
    s, co = np.sin(nu), np.cos(nu)
    return 0.5 * (s * s / a + co * co / b) * (M - N) * (M + N) + 0.5 * N * N / c


def hamiltonian_alpha_beta(nu, M, N, C, alpha, beta) -> np.ndarray:
    """Andoyer's arrangement (Lara 2018 eq. 2; Lara 2014 eq. 3), equal to :func:`hamiltonian`:

    H = M²/(2C) [1 + α(1 − N²/M²) − αβ (1 − N²/M²) cos 2ν].
    """
    M, N = check_n(M, N)
    check_finite("nu", nu)
    s2 = (M - N) * (M + N) / (M * M)   # sin²J
    return 0.5 * M * M / C * (1.0 + alpha * s2 * (1.0 - beta * np.cos(2.0 * nu)))


def sam_main_problem(nu, M, N, moments) -> np.ndarray:
    """Main problem of SAM rotation (Lara 2014 eq. 6 = Lara 2018 eq. 5):

    𝓜 = M²/(2C) [1 + 2α (1 − N/M)(1 − β cos 2ν)]; 𝓜 + 𝓟 = H exactly, since
    sin²J = 2(1 − cos J) − (1 − cos J)².
    """
    p = inertia_parameters(moments)
    M, N = check_n(M, N)
    check_finite("nu", nu)
    return 0.5 / p.C * (M * M + 2.0 * p.alpha * M * (M - N) * (1.0 - p.beta * np.cos(2.0 * nu)))


def sam_perturbation(nu, M, N, moments) -> np.ndarray:
    """Perturbation of SAM rotation (Lara 2014 eq. 7 = Lara 2018 eq. 6): 𝓟 = −M²/(2C) α (1 − N/M)² (1 − β cos 2ν)."""
    p = inertia_parameters(moments)
    M, N = check_n(M, N)
    check_finite("nu", nu)
    return -0.5 / p.C * p.alpha * (M - N) ** 2 * (1.0 - p.beta * np.cos(2.0 * nu))


# --------------------------------------------------------------------------- attitude <-> Andoyer


def invariable_frame(L_inertial) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(λ, Λ, M, R_inv) of inertial angular momenta; R_inv = R1(I) R3(λ) takes inertial to invariable axes.

    The node ê = ẑ × L / |ẑ × L| gives λ = atan2(L_x, −L_y); at I = 0 or π
    (L along ±ẑ) λ = 0. Built from the components, not from angles.
    """
    G1, G2, G3 = L_inertial[..., 0], L_inertial[..., 1], L_inertial[..., 2]
    M = np.linalg.norm(L_inertial, axis=-1)
    h = np.hypot(G1, G2)
    on_axis = h == 0.0
    hs = np.where(on_axis, 1.0, h)
    cl, sl = np.where(on_axis, 1.0, -G2 / hs), np.where(on_axis, 0.0, G1 / hs)
    R_inv = rot1_cs(G3 / M, h / M) @ rot3_cs(cl, sl)
    return np.arctan2(sl, cl), G3.copy(), M, R_inv


def andoyer_from_attitude(R, L_body) -> tuple[np.ndarray, ...]:
    """Andoyer variables (λ, μ, ν, Λ, M, N) of an attitude R (inertial to body) and body momentum L_b.

    ν = atan2(L1, L2); μ is taken from Q = R R_inv^T = R3(ν) R1(J) R3(μ) through
    the regular combination μ + ν (J <= π/2) or μ − ν (J > π/2), so that μ and
    ν together carry the attitude to rounding even where they are separately
    ill-conditioned (J -> 0 or π). What the chart cannot carry there is J
    itself: N = M cos J resolves J only to ~ε/sin J (√(2ε) at the poles), so
    :func:`andoyer_matrix` rebuilds R to ~ε/sin J, not to ε; the Poincaré-type
    variables (:func:`poincare_from_attitude`) do not have that loss.
    Conventions at the singular points: λ = 0 when I = 0 or π, ν = 0 when
    J = 0 or π.
    """
    R = np.asarray(R, dtype=float)
    check_finite("attitude", R)
    L = check_vector("L_body", L_body)
    G = np.einsum("...ji,...j->...i", R, L)          # inertial components, Rᵀ L_b
    lam, Lam, M, R_inv = invariable_frame(G)
    Q = R @ np.swapaxes(R_inv, -1, -2)
    nu, _, N = andoyer_from_body_momentum(L)
    J = inclination_j(L)
    total = np.arctan2(Q[..., 0, 1] - Q[..., 1, 0], Q[..., 0, 0] + Q[..., 1, 1])   # μ + ν
    diff = np.arctan2(Q[..., 0, 1] + Q[..., 1, 0], Q[..., 0, 0] - Q[..., 1, 1])    # μ − ν
    mu = wrap_angle(np.where(J <= 0.5 * np.pi, total - nu, diff + nu))
    return lam, mu, nu, Lam, M, N


def andoyer_matrix(lam, mu, nu, Lam, M, N) -> np.ndarray:
    """R = R3(ν) R1(J) R3(μ) R1(I) R3(λ), inertial to body, with cos I = Λ/M, cos J = N/M (Lara 2018 eq. 34)."""
    M, N = check_n(M, N)
    _, Lam = check_n(M, Lam)
    check_finite("andoyer angles", lam, mu, nu)
    sJ = np.sqrt((M - N) * (M + N)) / M
    sI = np.sqrt((M - Lam) * (M + Lam)) / M
    return rot3(nu) @ rot1_cs(N / M, sJ) @ rot3(mu) @ rot1_cs(Lam / M, sI) @ rot3(lam)


def andoyer_from_euler(phi, theta, psi, L_body) -> tuple[np.ndarray, ...]:
    """Andoyer variables (λ, μ, ν, Λ, M, N) of 3-1-3 Euler angles and the body-frame angular momentum."""
    return andoyer_from_attitude(euler_matrix(phi, theta, psi), L_body)


def euler_from_andoyer(lam, mu, nu, Lam, M, N) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(φ, θ, ψ, L_b): the 3-1-3 Euler angles and body-frame angular momentum of Andoyer variables."""
    R = andoyer_matrix(lam, mu, nu, Lam, M, N)
    phi, theta, psi = euler_from_matrix(R)
    return phi, theta, psi, body_momentum_from_andoyer(nu, M, N)


def euler_momenta(theta, psi, L_body) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Momenta (Φ, Θ, Ψ) conjugate to the Euler angles (φ, θ, ψ) (Gurfil et al. 2007 eqs. 40-42):

    Φ = L1 sθ sψ + L2 sθ cψ + L3 cθ (= Λ, the inertial z component),
    Θ = L1 cψ − L2 sψ, Ψ = L3 (= N).
    """
    L = check_vector("L_body", L_body)
    st, ct, sp, cp = np.sin(theta), np.cos(theta), np.sin(psi), np.cos(psi)
    l1, l2, l3 = L[..., 0], L[..., 1], L[..., 2]
    return l1 * st * sp + l2 * st * cp + l3 * ct, l1 * cp - l2 * sp, l3.copy()


