"""The exact torque-free motion of a rigid body (the Euler-Poinsot problem) in Jacobi elliptic functions.

Conventions are those of :mod:`ephem.rotation.andoyer`: principal moments A <= B <= C
along the body axes b1, b2, b3; body-frame angular momentum L_b = (L1, L2, L3);
attitude R (inertial to body); Andoyer variables (λ, μ, ν, Λ, M, N). Moments
and momenta in any consistent units; time t then in (moment)/(momentum), e.g.
days for moments normalised by C and M = C ω with ω in rad/day.

The body-frame motion (Landau & Lifshitz, Mechanics, §37; Gurfil et al. 2007,
eqs. 34-36): with the integrals M² = |L|², 2E = L1²/A + L2²/B + L3²/C and

    d_up = 2EC − M² = L1² (C−A)/A + L2² (C−B)/B >= 0,
    d_lo = M² − 2EA = L2² (B−A)/B + L3² (C−A)/C >= 0,
    D    = M² − 2EB = L3² (C−B)/C − L1² (B−A)/A

(written as sums of squares so that no cancellation ever occurs),

* short-axis mode, D > 0 (L circulates about the C axis):
  L1 = a cn u, L2 = s b sn u, L3 = s c dn u, u = p (t − t0) + u0, s = sign L3, p > 0,
  a² = A d_up/(C−A), b² = B d_up/(C−B), c² = C d_lo/(C−A),
  p² = (C−B) d_lo/(ABC), m = k² = (B−A) d_up/((C−B) d_lo),
  1 − m = (C−A) D/((C−B) d_lo);
* long-axis mode, D < 0 (L circulates about the A axis): the same formulas in
  the frame b' = P b, P = [[0, 0, 1], [0, −1, 0], [1, 0, 0]] (a proper rotation,
  P² = 1) with moments (C, B, A) — Euler's equations are invariant under this
  map, and every radicand above stays positive (the "equivalence between
  short- and long-axis modes" of Lara 2014 §1) — except that p < 0 there
  (a p = b c (I3 − I2)/(I2 I3) changes sign with I3 − I2);
* separatrix, D = 0 (exactly, m = 1): L1 = s1 a sech u, L2 = s1 s3 M tanh u,
  L3 = s3 c sech u, s1 = sign L1, s3 = sign L3 — the closed-form limit, never
  evaluated through K(1) = ∞;
* stationary rotation (ω ∥ L: about a principal axis, or in the degenerate
  plane of an axisymmetric body): L constant.

The wobble period of L about the C (or A) axis in the body frame is 4K(m)/p;
as J -> 0 it tends to Euler's 2π/(ω3 κ), κ = √((C/A − 1)(C/B − 1)), and for
A = B to 2π A/(ω3 (C − A)).

The precession of the body about L in space follows from Andoyer's
μ̇ = ∂H/∂M = M (sin²ν/A + cos²ν/B) = M (L1²/A + L2²/B)/(L1² + L2²). With
L1² + L2² = a² (1 + f sn²u), f = C(B−A)/(A(C−B)) (Sadov's characteristic):

    μ̇ = M/C + M (C−A)/(AC) / (1 + f sn²u),
    μ(t) = μ0 + n_μ (t − t0) + [M (C−A)/(AC p)] (P(u) − P(u0)),
    n_μ  = M/A − [M (C−A)/(AC)] ρ,     ρ = 1 − Π(−f|m)/K(m) = (f/3) R_J(0, 1−m, 1, 1+f)/K(m),
    P(u) = ρ u_r − (f/3) sn³ R_J(cn², dn², 1, 1 + f sn²)    (u_r = u reduced to [−K, K), 2K-periodic),

from Π(n; φ|m) = F(φ|m) + (n/3) sin³φ R_J(cos²φ, 1 − m sin²φ, 1, 1 − n sin²φ)
(DLMF 19.25.14 with its arguments scaled by sin²φ; Carlson, Numer. Algorithms
10 (1995) 13). 2π/n_μ is the precession period of the figure axis about L.
It equals Sadov's n_g (Lara 2018 eq. A7) — see :func:`ephem.rotation.free_periods.sadov_action_angle` —
and tends to M/A for A = B (uniform precession), to (M/C)(1 + κ) as J -> 0 and
to M/B at the separatrix. On the separatrix itself
∫du/(1 + f tanh²u) = [u + √f arctan(√f tanh u)]/(1 + f).

The constants of these forms and the special functions they need (sn, cn, dn reduced to a quarter period,
the integrals without cancellation, ρ and P(u), the separatrix's) are in :mod:`ephem.rotation.elliptic_solution`;
:class:`FreeRotation` here builds them from an initial state and evaluates the motion.

A spherical body (A = B = C) is rejected (InvalidInputError): L is then fixed
in the body and the body turns uniformly about it at M/A, so there is no
wobble and no precession to compute, and the mode, the elliptic parameter and
β are all undefined (0/0).

Validity and accuracy: exact for a rigid body without torques. Measured
against a 40-digit mpmath integration of Euler's equations over three wobble
periods: 8e-16 (short- and long-axis, m ~ 0.1-0.2, and Eros), 1e-13 at
1 − m = 2e-3; against DOP853 at rtol 1e-13 (ephem.forced.rigid_body) the body momentum
agrees to ~1e-14 |L| and the attitude to ~1e-13-1e-12 (the integrator's
error). Near the separatrix the motion itself is ill-conditioned: the period
4K/p grows like ln(1/(1 − m)) and a relative error ε in the initial state
shifts the phase by ~ε/(1 − m) (measured 5e-11 at 1 − m = 2e-6); that is
inherent, not a defect of the formulas. Cost (vectorised, per epoch): body
momentum 0.2-0.3 µs, attitude 0.7 µs, Andoyer variables 0.8-1.1 µs, Sadov's
variables 1.0 µs; constructing a :class:`FreeRotation` ~0.2 ms.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .andoyer import (andoyer_from_attitude, body_momentum_from_j, check_finite, check_moments, invariable_frame, rot1,
                      rot1_cs, rot3, rot3_cs, wrap_angle)
from .elliptic_solution import (CoreConstants, core_constants, differences, is_stationary, jacobi_reduced,
                                periodic_part, separatrix_constants, separatrix_integral)
from ..base.constants import ARCSEC
from ..base.errors import InvalidInputError


#: the long-axis-mode frame map b' = P b (moments (A, B, C) -> (C, B, A)); P = Pᵀ = P⁻¹, det P = +1
P_LAM = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])

# --------------------------------------------------------------------------- the solution


@dataclass(frozen=True)
class FigureAxisPath:
    """The figure axis (C for short-axis and separatrix motion, A for long-axis) about L, seen in space.

    opening_arcsec: angle between the figure axis and L (J, or J' for the A axis);
    azimuth_deg: its position angle about L in the invariable plane, from the
    plane's node on the inertial x-y plane (μ − 90°), wrapped to (−180, 180];
    offset_arcsec: (N, 2) tangent-plane offsets J (cos az, sin az).
    """

    opening_arcsec: np.ndarray
    azimuth_deg: np.ndarray
    offset_arcsec: np.ndarray


@dataclass(frozen=True)
class FreeRotation:
    """The exact torque-free motion from an initial state; evaluate at any times (vectorised).

    Build with :meth:`from_body_momentum` (from an angular velocity ω_b: L_b = I ω_b) or :meth:`from_andoyer`.
    ``mode`` is 'short-axis', 'long-axis' or 'separatrix'; ``stationary`` is True for rotation about a principal axis
    (or about any axis of the degenerate plane of an axisymmetric body).
    Frequencies are in rad per time unit, periods in time units.

    Internally L is divided by a power of two s (exactly) so that max |L_i| is
    in [0.5, 1), and components below 1e-150 of that are set to 0: their
    squares would underflow, and their share of M² and 2E (< 1e-300) is far
    below rounding. L(t) = s L_n(s t) maps the result back (Euler's equations
    are quadratic in L).
    """

    moments: tuple[float, float, float]
    L0: np.ndarray              # body-frame angular momentum at t0
    R0: np.ndarray              # attitude at t0, inertial to body
    t0: float
    mode: str
    stationary: bool
    M: float
    energy: float
    _s: float                    # the power-of-two scale of L
    _Ln: np.ndarray              # L0 / s, in the core frame, tiny components flushed
    _core: CoreConstants | None          # elliptic constants for L0/s (None: separatrix or stationary)
    _perm: bool                  # core frame is P b (long-axis mode)
    _mu0: float                  # precession angle of the core frame at t0
    _R_inv: np.ndarray           # inertial -> invariable frame
    _sep: tuple | None           # separatrix constants (a, c, p, s1, s3, f, u0) for L0/s
    _rate_stationary: float      # μ̇ of stationary rotation for L0/s

    # ------------------------------------------------------------------ construction

    @classmethod
    def from_body_momentum(cls, moments, L_body, t0: float = 0.0, attitude=None) -> FreeRotation:
        """From the body-frame angular momentum at t0 and optionally the attitude R0 (inertial to body).

        Without an attitude the invariable frame is taken as the inertial one
        (L along +z, I = 0, λ = 0) with μ0 = 0.
        """
        A, B, C = check_moments(moments, allow_spherical=False)
        L = np.asarray(L_body, dtype=float).reshape(-1)
        if L.shape != (3,):
            raise InvalidInputError("L_body", f"expected one 3-vector, got shape {np.shape(L_body)}")
        check_finite("L_body", L)
        check_finite("t0", t0)
        if not np.any(L != 0.0):
            raise InvalidInputError("L_body", "the angular momentum must not vanish")
        R0 = _default_attitude(L) if attitude is None else _check_attitude(attitude)
        return cls._build((A, B, C), L, R0, float(t0))

    @classmethod
    def from_andoyer(cls, moments, M: float, J: float, nu: float, mu: float = 0.0, lam: float = 0.0,
                     inc: float = 0.0, t0: float = 0.0) -> FreeRotation:
        """From M, J = angle(L, C axis) in [0, π], ν, and optionally μ, λ and I = angle(L, inertial z) (rad)."""
        L = body_momentum_from_j(M, J, nu)
        check_finite("andoyer angles", mu, lam, inc)
        if not 0.0 <= inc <= math.pi:
            raise InvalidInputError("inc", "I must lie in [0°, 180°]")
        # from the angles themselves: andoyer_matrix's sin J = √((M−N)(M+N))/M cancels below ~1″
        R0 = rot3(nu) @ rot1(J) @ rot3(mu) @ rot1(inc) @ rot3(lam)
        return cls.from_body_momentum(moments, L, t0, R0)

    @classmethod
    def _build(cls, moments, L, R0, t0) -> FreeRotation:
        A, B, C = moments
        scale = 2.0 ** math.frexp(float(np.abs(L).max()))[1]       # exact: a power of two
        Ln = L / scale
        Ln = np.where(np.abs(Ln) < 1e-150, 0.0, Ln)
        M2, d_up, d_lo, D = differences(Ln, A, B, C)
        mode = "short-axis" if D > 0.0 else "long-axis" if D < 0.0 else "separatrix"
        stationary = is_stationary(Ln, A, B, C)
        perm = mode == "long-axis"
        Lc = P_LAM @ Ln if perm else Ln
        Ic = (C, B, A) if perm else (A, B, C)
        _, _, _, R_inv = invariable_frame(R0.T @ Ln)
        Rc = (P_LAM @ R0 if perm else R0) @ R_inv.T   # = R3(ν) R1(J) R3(μ) in the core frame
        mu0 = float(_mu_from_q(Rc, Lc))
        core = sep = None
        rate = 0.0
        if stationary:
            h2 = Lc[0] ** 2 + Lc[1] ** 2
            rate = math.sqrt(M2) * (Lc[0] ** 2 / Ic[0] + Lc[1] ** 2 / Ic[1]) / h2 if h2 > 0.0 \
                else math.sqrt(M2) / Ic[2]
        elif mode == "separatrix":
            sep = separatrix_constants(Ln, A, B, C, math.sqrt(M2), d_up, d_lo)
        else:
            _, du, dl, Dc = differences(Lc, *Ic)
            core = core_constants(Lc, *Ic, M2, du, dl, Dc)
        energy = 0.5 * (Ln[0] ** 2 / A + Ln[1] ** 2 / B + Ln[2] ** 2 / C) * scale * scale
        return cls((A, B, C), L.copy(), R0.copy(), t0, mode, stationary, math.sqrt(M2) * scale, energy, scale,
                   Lc, core, perm, mu0, R_inv, sep, rate)

    @property
    def _Mn(self) -> float:
        return self.M / self._s

    def _tau(self, t) -> np.ndarray:
        """Normalised time s (t − t0)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        check_finite("t", t)
        return (t - self.t0) * self._s

    # ------------------------------------------------------------------ body frame

    def _core_momentum(self, tau) -> tuple[np.ndarray, tuple | None]:
        """L/s in the core frame at normalised times, and the reduced elliptic values (for μ)."""
        if self.stationary:
            return np.broadcast_to(self._Ln, (tau.size, 3)).copy(), None
        if self._sep is not None:
            a, c, p, s1, s3, _f, u0 = self._sep
            u = u0 + p * tau
            sech, th = 1.0 / np.cosh(np.clip(u, -700.0, 700.0)), np.tanh(u)
            L = np.stack([s1 * a * sech, s1 * s3 * self._Mn * th, s3 * c * sech], axis=-1)
            return L, (u,)
        k = self._core
        sn, cn, dn, sn_r, cn_r, dn_r, r = jacobi_reduced(k.u0 + k.p * tau, k.m, k.m1, k.K)
        L = np.stack([k.a * cn, k.s3 * k.b * sn, k.s3 * k.c * dn], axis=-1)
        return L, (sn_r, cn_r, dn_r, r)

    def body_momentum(self, t) -> np.ndarray:
        """Body-frame angular momentum L_b(t), shape (N, 3)."""
        Lc, _ = self._core_momentum(self._tau(t))
        return (Lc @ P_LAM.T if self._perm else Lc) * self._s

    def angular_velocity(self, t) -> np.ndarray:
        """Body-frame angular velocity ω_b = I⁻¹ L_b, shape (N, 3)."""
        return self.body_momentum(t) / np.asarray(self.moments)

    # ------------------------------------------------------------------ precession

    def _core_mu(self, tau, aux) -> np.ndarray:
        """Precession angle μ of the core frame (the node of its 1-2 plane on the invariable plane)."""
        Mn = self._Mn
        if self.stationary:
            return self._mu0 + self._rate_stationary * tau
        if self._sep is not None:
            _a, _c, p, _s1, _s3, f, u0 = self._sep
            A, _, C = self.moments
            coef = Mn * (C - A) / (A * C * p)
            return self._mu0 + Mn / C * tau + coef * (separatrix_integral(aux[0], f) - separatrix_integral(u0, f))
        k = self._core
        coef = Mn * (k.I3 - k.I1) / (k.I1 * k.I3 * k.p)
        n_mu = self.precession_frequency / self._s
        return self._mu0 + n_mu * tau + coef * (periodic_part(k, *aux) - k.P0)

    @property
    def wobble_frequency(self) -> float:
        """2π over the period of L about the C (A) axis in the body frame: πp/(2K); 0 on the separatrix.

        For stationary rotation about C or A, the J -> 0 limit (Euler's frequency);
        about B or in a degenerate plane, 0.
        """
        if self._core is not None:
            return math.pi * abs(self._core.p) / (2.0 * self._core.K) * self._s
        if self.stationary:
            return _linear_wobble(self._Ln, self._perm, self.moments, self.M)
        return 0.0

    @property
    def wobble_period(self) -> float:
        """4K(m)/p (time units); infinite on the separatrix or where no wobble exists."""
        return _period(self.wobble_frequency)

    @property
    def precession_frequency(self) -> float:
        """Mean rate n_μ of the figure axis about L in space (rad/time); see the module docstring.

        Separatrix: M/B (the limit from either side). Stationary rotation about
        C or A: the J -> 0 limit (M/I3)(1 + κ) of the core frame.
        """
        if self._core is not None:
            k = self._core
            return self.M / k.I1 - self.M * (k.I3 - k.I1) / (k.I1 * k.I3) * k.rho
        if self._sep is not None:
            return self.M / self.moments[1]
        return _stationary_precession(self._Ln, self._perm, self.moments, self.M, self._rate_stationary * self._s)

    @property
    def precession_period(self) -> float:
        """2π/|n_μ|: the period of the figure axis about L in space (time units)."""
        return _period(self.precession_frequency)

    @property
    def elliptic_rate(self) -> float:
        """|du/dt| = |p|, the rate of the Jacobi argument (1/time); 0 for stationary rotation."""
        if self._core is not None:
            return abs(self._core.p) * self._s
        return self._sep[2] * self._s if self._sep is not None else 0.0

    @property
    def complementary_parameter(self) -> float:
        """1 − m, computed from D = M² − 2EB without cancellation (0 on the separatrix, 1 when stationary)."""
        if self._core is not None:
            return self._core.m1
        return 0.0 if self._sep is not None else 1.0

    @property
    def elliptic_parameter(self) -> float:
        """m = k² of the Jacobi functions (1 on the separatrix, 0 for stationary rotation)."""
        if self._core is not None:
            return self._core.m
        return 1.0 if self._sep is not None else 0.0

    # ------------------------------------------------------------------ attitude

    def _core_attitude(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(R_core(t), L_core(t)/s, μ_core(t)): R_core = R3(ν) R1(J) R3(μ) R_inv in the core frame."""
        tau = self._tau(t)
        Lc, aux = self._core_momentum(tau)
        mu = self._core_mu(tau, aux)
        return _nu_j_matrix(Lc, self._Mn) @ rot3(mu) @ self._R_inv, Lc, mu

    def attitude(self, t) -> np.ndarray:
        """Attitude matrices R(t), inertial to body, shape (N, 3, 3)."""
        Rc, _, _ = self._core_attitude(t)
        return P_LAM @ Rc if self._perm else Rc

    def andoyer(self, t) -> tuple[np.ndarray, ...]:
        """Andoyer variables (λ, μ, ν, Λ, M, N) at t (C-axis convention of :mod:`ephem.rotation.andoyer`)."""
        Rc, Lc, mu = self._core_attitude(t)
        if self._perm:
            lam, mu_b, nu, Lam, M, N = andoyer_from_attitude(P_LAM @ Rc, Lc @ P_LAM.T)
            return lam, mu_b, nu, Lam * self._s, M * self._s, N * self._s
        lam, Lam, _, _ = invariable_frame(self.R0.T @ self._Ln)
        n = Lc.shape[0]
        nu = np.where(np.hypot(Lc[:, 0], Lc[:, 1]) > 0.0, np.arctan2(Lc[:, 0], Lc[:, 1]), 0.0)
        return (np.full(n, float(lam)), wrap_angle(mu), nu, np.full(n, float(Lam) * self._s), np.full(n, self.M),
                Lc[:, 2] * self._s)

    def figure_axis(self, t) -> FigureAxisPath:
        """The figure axis about L in space: opening angle (arcsec), azimuth (deg), offsets (arcsec)."""
        tau = self._tau(t)
        Lc, aux = self._core_momentum(tau)
        mu = self._core_mu(tau, aux)
        opening = np.arctan2(np.hypot(Lc[:, 0], Lc[:, 1]), Lc[:, 2])
        az = wrap_angle(mu - 0.5 * math.pi)
        off = np.stack([opening * np.cos(az), opening * np.sin(az)], axis=-1) / ARCSEC
        return FigureAxisPath(opening / ARCSEC, np.degrees(az), off)


# --------------------------------------------------------------------------- pieces of the solution


def _period(frequency: float) -> float:
    """2π/|frequency|, infinite (without an overflow warning) for a zero or subnormal-small frequency."""
    f = abs(frequency)
    return 2.0 * math.pi / f if f > 2.0 * math.pi / np.finfo(float).max else math.inf


def _default_attitude(L) -> np.ndarray:
    """R0 = R3(ν) R1(J): the invariable frame as the inertial one, μ0 = 0 (L scaled first: |L|² may overflow)."""
    Ln = L / np.abs(L).max()
    return _nu_j_matrix(Ln[None, :], float(np.linalg.norm(Ln)))[0]


def _check_attitude(R) -> np.ndarray:
    R = np.asarray(R, dtype=float)
    if R.shape != (3, 3):
        raise InvalidInputError("attitude", f"expected a 3x3 rotation matrix, got shape {R.shape}")
    check_finite("attitude", R)
    if np.abs(R @ R.T - np.eye(3)).max() > 1e-9 or np.linalg.det(R) < 0.0:
        raise InvalidInputError("attitude", "not a proper rotation matrix (R Rᵀ = 1, det R = +1)")
    return R


def _nu_j_matrix(L, M: float) -> np.ndarray:
    """R3(ν) R1(J) from body momenta (N, 3) without trigonometry: sν = L1/h, cν = L2/h, sJ = h/M, cJ = L3/M.

    At h = 0 (J = 0 or π) ν = 0 by convention.
    """
    h = np.hypot(L[:, 0], L[:, 1])
    zero = h == 0.0
    hs = np.where(zero, 1.0, h)
    sn, cn = np.where(zero, 0.0, L[:, 0] / hs), np.where(zero, 1.0, L[:, 1] / hs)
    return rot3_cs(cn, sn) @ rot1_cs(L[:, 2] / M, h / M)


def _mu_from_q(Q, L) -> float:
    """μ of Q = R3(ν) R1(J) R3(μ) with ν from L, through the regular μ ± ν (see ephem.rotation.andoyer)."""
    h = math.hypot(L[0], L[1])
    nu = math.atan2(L[0], L[1]) if h > 0.0 else 0.0
    if math.atan2(h, L[2]) <= 0.5 * math.pi:
        return math.atan2(Q[0, 1] - Q[1, 0], Q[0, 0] + Q[1, 1]) - nu
    return math.atan2(Q[0, 1] + Q[1, 0], Q[0, 0] - Q[1, 1]) + nu


def _linear_wobble(Lc, perm: bool, moments, M: float) -> float:
    """Euler's small-amplitude wobble frequency for rotation about the core frame's axis 3 (C, or A when
    ``perm``); 0 about B or in a degenerate plane. ``Lc`` is the (scaled) core-frame momentum."""
    if Lc[0] != 0.0 or Lc[1] != 0.0:
        return 0.0
    I1, I2, I3 = (moments[2], moments[1], moments[0]) if perm else moments
    return M / I3 * math.sqrt((I3 - I1) * (I3 - I2) / (I1 * I2))


def _stationary_precession(Lc, perm: bool, moments, M: float, rate: float) -> float:
    """J -> 0 limit of n_μ, (M/I3)(1 + κ), for rotation about the core axis 3; else the stationary rate."""
    if Lc[0] != 0.0 or Lc[1] != 0.0:
        return rate
    I1, I2, I3 = (moments[2], moments[1], moments[0]) if perm else moments
    return M / I3 * (1.0 + math.sqrt((I3 - I1) * (I3 - I2) / (I1 * I2)))


