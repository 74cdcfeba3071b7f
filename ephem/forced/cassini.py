"""The Cassini state of a synchronous rotator: the mean pole of the Moon (Cassini's laws).

A body whose rotation is locked to its orbit (the long axis A toward the primary) and whose orbit plane
precesses uniformly about a fixed plane (the Laplace plane: the ecliptic for the Moon, whose node regresses
in 18.6 yr) keeps its spin axis, its orbit normal and the Laplace pole coplanar, at a fixed obliquity
(Colombo 1966; Peale 1969; Ward 1975). Radians and days; moments (A, B, C) in any common normalisation.

**The torque averaged over a synchronous orbit.** The primary at unit vector u (body axes a, b, c, c the
spin axis at the angle θ from the orbit normal k) adds the potential (3/2)(GM/r³) u·I·u. With x the node of
the equator on the orbit, u = cos λ x + sin λ y and the long axis locked to the primary, a = cos λ x + sin λ
(c × x), so u·c = −sin θ sin λ, u·a = cos²λ + cos θ sin²λ, u·b = sin λ cos λ (cos θ − 1). Over λ:

    <u·I·u> = A (3 + 2 cos θ + 3 cos²θ)/8 + B (1 − cos θ)²/8 + C sin²θ/2,

and the spin axis, L = C n c, turns about k at (dc/dt = P (c × k))

    P(θ) = (3 g / (2 n)) [ (C − A)/C cos θ + (B − A)/(4C) (1 − cos θ) ] · (1 − e²)^(−3/2),

g = GM/a³ of the primary. A synchronous body thus feels C − A (the primary stays near its long axis), where
a fast rotator feels C − (A + B)/2: B − A enters through both, and here also through the (1 − cos θ) term.
(1 − e²)^(−3/2) is the orbit mean of (a/r)³; the optical libration in longitude (2e) moves the primary off
the long axis by (B − A) 2e² relative, left out (0.2 % of P for the Moon).

**The Sun** (a Laplace plane the Sun stays in, as the ecliptic): the body turns under it at the synodic rate,
so it torques as on a fast rotator, about the Laplace pole K: dc/dt += P_s cos I (c × K), P_s = (3 g_s /
(2 n)) (C − (A + B)/2)/C (1 − e_s²)^(−3/2).

**Cassini state 2** (the Moon's: K between the spin pole and the orbit pole, θ = i + I): in the frame turning
with the node at Ω̇ < 0 about K, the angular momentum L = C n c + C Ω̇ (K − cos I c) (the precession's own
angular velocity) must turn with it. Its balance, across the plane of c, k and K:

    n [P(θ) sin θ + P_s cos I sin I] = |Ω̇| (n + |Ω̇| cos I) sin I,       θ = i + I,

solved for I by root finding (:func:`cassini_state`), not fitted. Left out: the balance's second order in P/n
(the full rigid body's mean I exceeds the root by 3.4″ for the Moon on a circular orbit, as P → P (1 + P/2n):
ephem.moon.rigid_integration's tests) and the optical libration's (B − A) 2e² (~15″ in the Moon's I).

Its free modes (:func:`free_librations`) are the linearised rigid body's about the locked state (the
gravity-gradient roll-yaw-pitch equations of a satellite on a circular orbit): the longitude libration,
ω² = 3 g γ H(e) cos⁴(θ/2) with H the orbit mean of (a/r)³ cos 2(f − M) and cos⁴(θ/2) = <(u·a)² − (u·b)²> over
the tilted orbit (the same average as above); the roll-yaw pair (s² + (n² + 3g) β)(s² + n² α) + n² (1 − α)(1 − β) s² = 0, α = (C − B)/A, β =
(C − A)/B, γ = (B − A)/C, whose slow root is the free wobble (in the body) and whose fast one, n + δ, the free
precession of the pole in space at δ; about the Cassini state the latter is the free libration in latitude,
its frequency in the node's frame the linearised balance above.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.errors import NotApplicableError
from ..base.memo import bytes_bounded
from ..bodies.catalogue import SYNCHRONOUS_TOLERANCE
from ..orbit.kepler import solve_kepler

#: Hansen-mean samples of (a/r)³ cos 2(f − M) over an orbit: the trapezoid rule on a periodic analytic
#: function converges geometrically; 512 points give 1e-15 relative at e = 0.5
_ORBIT_SAMPLES = 512


@dataclass(frozen=True)
class SynchronousOrbit:
    """The mean orbit about the primary, elements on the Laplace plane (radians, days).

    The Laplace frame: z the Laplace pole K, x the origin of longitudes on the Laplace plane.
    """

    mean_motion: float            # n, rad/day (sidereal: the synchronous spin rate)
    eccentricity: float
    inclination: float            # i, orbit plane to the Laplace plane
    node_at_epoch: float          # Ω at epoch
    node_rate: float              # dΩ/dt, rad/day (negative: regressing)
    pericentre_at_epoch: float    # argument of pericentre ω
    pericentre_rate: float        # dω/dt, rad/day
    mean_anomaly_at_epoch: float
    epoch: float                  # JD TDB
    primary_gm_over_a3: float     # g = GM/a³ of the primary, rad²/day²
    sun_tidal_rate_sq: float = 0.0      # g_s = GM_sun/a_s³ of the Sun in the Laplace plane (0: no Sun)
    sun_eccentricity: float = 0.0
    sun_longitude_at_epoch: float = 0.0
    sun_mean_motion: float = 0.0

    def node(self, jd_tdb) -> np.ndarray:
        return self.node_at_epoch + self.node_rate * (np.asarray(jd_tdb, dtype=float) - self.epoch)


def moment_ratios(moments) -> tuple[float, float, float]:
    """α = (C − B)/A, β = (C − A)/B, γ = (B − A)/C of the principal moments A <= B <= C."""
    A, B, C = (float(x) for x in moments)
    return (C - B) / A, (C - A) / B, (B - A) / C


def precession_constant(orbit: SynchronousOrbit, moments, obliquity: float) -> float:
    """P(θ), rad/day: the rate at which the primary's torque, averaged over a synchronous orbit, turns the
    spin axis about the orbit normal (see the module docstring)."""
    A, B, C = (float(x) for x in moments)
    e = orbit.eccentricity
    c = math.cos(obliquity)
    return (1.5 * orbit.primary_gm_over_a3 / orbit.mean_motion * ((C - A) / C * c + (B - A) / (4.0 * C) * (1.0 - c))
            * (1.0 - e * e) ** -1.5)


def sun_precession_constant(orbit: SynchronousOrbit, moments) -> float:
    """P_s, rad/day: the Sun's torque on the body, averaged over the synodic rotation and the Sun's orbit, as
    on a fast rotator: the spin axis turns about the Laplace pole at P_s cos I."""
    A, B, C = (float(x) for x in moments)
    es = orbit.sun_eccentricity
    return 1.5 * orbit.sun_tidal_rate_sq / orbit.mean_motion * (C - 0.5 * (A + B)) / C * (1.0 - es * es) ** -1.5


@dataclass(frozen=True)
class CassiniState:
    """The Cassini state 2 of a synchronous body (radians, rad/day)."""

    obliquity: float               # θ: the spin axis from the orbit normal
    equator_inclination: float     # I: the spin axis from the Laplace pole (θ = i + I)
    precession_constant: float     # P(θ), rad/day
    sun_precession_constant: float  # P_s, rad/day
    node_rate: float               # Ω̇, rad/day: the pole's precession about the Laplace pole

    @property
    def precession_rate(self) -> float:
        """ψ̇ = −Ω̇ (rad/day): the pole's precession about the Laplace pole, positive retrograde (the Earth's
        sense)."""
        return -self.node_rate


def bisect_root(f, lo: float, hi: float, xtol: float) -> float:
    """The root of ``f`` in [lo, hi], where f(lo) and f(hi) have opposite signs, by bisection until the bracket is
    narrower than ``xtol`` (or no double lies inside it): about 50 evaluations for the Cassini balance. Bisection and
    not scipy.optimize.brentq, which gives the same root (tests/moon/test_cassini.py) but whose package costs 0.47 s
    to import: the Moon's whole answer at start-up."""
    f_lo = f(lo)
    while hi - lo > xtol:
        mid = 0.5 * (lo + hi)
        if not lo < mid < hi:
            break
        f_mid = f(mid)
        if f_mid == 0.0:
            return mid
        if (f_mid < 0.0) == (f_lo < 0.0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _balance(orbit: SynchronousOrbit, moments, I: float) -> float:
    """The Cassini balance's residual at equator inclination I (rad/day): torque minus the turning of L."""
    n, w = orbit.mean_motion, abs(orbit.node_rate)
    theta = orbit.inclination + I
    torque = precession_constant(orbit, moments, theta) * math.sin(theta) \
        + sun_precession_constant(orbit, moments) * math.cos(I) * math.sin(I)
    return n * torque - w * (n + w * math.cos(I)) * math.sin(I)


def check_synchronous(name: str, spin_rate: float, mean_motion: float) -> None:
    """:class:`NotApplicableError` unless the spin rate is the orbital mean motion to
    :data:`SYNCHRONOUS_TOLERANCE`."""
    ratio = spin_rate / mean_motion
    if abs(ratio - 1.0) > SYNCHRONOUS_TOLERANCE:
        raise NotApplicableError(name, f"the Cassini-state theory is for a synchronous rotator (spin rate / orbital "
                                 f"mean motion ω/n within {SYNCHRONOUS_TOLERANCE:g} of 1); here ω/n = {ratio:.6g}",
                                 ratio=ratio)


def cassini_state(orbit: SynchronousOrbit, moments, name: str = "body") -> CassiniState:
    """The Cassini state 2 (see the module docstring): the equator's inclination I to the Laplace plane from
    the balance of the averaged torque against the node's regression, by bracketing root finding.

    Not applicable (with the reason) without a regressing node, without C > A, or where the balance has no
    root with the spin pole across the Laplace pole from the orbit pole (0 < I < π/2 − i)."""
    A, B, C = (float(x) for x in moments)
    if not (C > B >= A > 0.0):
        raise NotApplicableError(name, f"the Cassini state needs principal moments 0 < A <= B < C, got A={A:.9g}, "
                                 f"B={B:.9g}, C={C:.9g}")
    if not orbit.node_rate < 0.0:
        raise NotApplicableError(name, "the Cassini state needs the orbit's node to regress (node rate < 0) about "
                                 f"its Laplace plane; got {orbit.node_rate:.6g} rad/day")
    if orbit.inclination <= 0.0:
        raise NotApplicableError(name, "an orbit in its Laplace plane (i = 0) does not precess: the spin axis "
                                 "is the orbit normal, no Cassini state to solve")
    hi = 0.5 * math.pi - orbit.inclination
    lo = 1e-12
    if hi <= lo or _balance(orbit, moments, lo) * _balance(orbit, moments, hi) > 0.0:
        raise NotApplicableError(name, f"no Cassini state 2 for this body: the balance of its torque against the "
                                 f"node's regression has no root with the pole between the Laplace pole and the "
                                 f"equator (i = {math.degrees(orbit.inclination):.6g} deg)")
    # xtol: 1e-15 rad, far below any pole error served (0.2 µas)
    I = bisect_root(lambda x: _balance(orbit, moments, x), lo, hi, xtol=1e-15)
    theta = orbit.inclination + I
    return CassiniState(theta, I, precession_constant(orbit, moments, theta),
                        sun_precession_constant(orbit, moments), orbit.node_rate)


def cassini_pole(state: CassiniState, orbit: SynchronousOrbit, jd_tdb) -> np.ndarray:
    """The Cassini pole, unit vectors (N, 3) in the Laplace frame: at ecliptic longitude Ω(t) + 90° and
    colatitude I (Cassini's third law: the spin pole across the Laplace pole from the orbit pole, whose
    longitude is Ω − 90°)."""
    lon = orbit.node(jd_tdb) + 0.5 * math.pi
    s = math.sin(state.equator_inclination)
    return np.stack([s * np.cos(lon), s * np.sin(lon), np.full(np.shape(lon), math.cos(state.equator_inclination))],
                    axis=-1)


def longitude_hansen_factor(e: float) -> float:
    """H(e): the orbit mean of (a/r)³ cos 2(f − M), the restoring torque's factor of the longitude libration
    (1 − 5e²/2 + 13e⁴/16 + …; evaluated exactly by the trapezoid rule over the mean anomaly)."""
    m = np.linspace(0.0, 2.0 * math.pi, _ORBIT_SAMPLES, endpoint=False)
    E = solve_kepler(m, e)
    f = 2.0 * np.arctan2(math.sqrt(1.0 + e) * np.sin(0.5 * E), math.sqrt(1.0 - e) * np.cos(0.5 * E))
    a_r = 1.0 / (1.0 - e * np.cos(E))
    return float(np.mean(a_r**3 * np.cos(2.0 * (f - m))))


@dataclass(frozen=True)
class FreeLibrations:
    """The free modes of a synchronous rigid body about its Cassini state, periods in days."""

    longitude_days: float          # the free libration in longitude (pitch)
    wobble_days: float             # the free wobble, in the body
    precession_space_days: float   # the free precession of the pole in space (the roll-yaw pair's fast root − n)
    latitude_days: float           # the free libration in latitude: that precession in the node's frame


def free_librations(orbit: SynchronousOrbit, moments, state: CassiniState | None = None) -> FreeLibrations:
    """The free-libration periods (see the module docstring): linearised about the locked state on a circular
    orbit (the longitude mode with H(e)), and, for the latitude mode, the Cassini balance linearised about its
    root in the node's frame. A pure function of its frozen arguments, kept per body (~1.3 ms: the Hansen factor's
    Kepler solutions and the latitude mode's differences), which every Moon estimate reads."""
    if state is None:
        state = cassini_state(orbit, moments)
    return _free_librations(orbit, tuple(moments), state)


@bytes_bounded
def _free_librations(orbit: SynchronousOrbit, moments: tuple, state: CassiniState) -> FreeLibrations:
    alpha, beta, gamma = moment_ratios(moments)
    n, g = orbit.mean_motion, orbit.primary_gm_over_a3
    # the primary leaves the equator by up to θ: the (B − A) restoring torque's mean is (B − A) cos⁴(θ/2)
    w_lon = math.sqrt(3.0 * g * gamma * longitude_hansen_factor(orbit.eccentricity)) * math.cos(0.5 * state.obliquity) ** 2
    # (s² + k_r)(s² + k_y) + n²(1 − α)(1 − β) s² = 0 in x = −s² (x = ω²): x² − b x + c = 0
    k_roll, k_yaw = (n * n + 3.0 * g) * beta, n * n * alpha
    b = k_roll + k_yaw + n * n * (1.0 - alpha) * (1.0 - beta)
    c = k_roll * k_yaw
    disc = math.sqrt(b * b - 4.0 * c)
    fast, slow = math.sqrt(0.5 * (b + disc)), math.sqrt(2.0 * c / (b + disc))   # the stable form for the small root
    return FreeLibrations(2.0 * math.pi / w_lon, 2.0 * math.pi / slow, 2.0 * math.pi / (fast - n),
                          2.0 * math.pi / latitude_frequency(orbit, moments, state))


def latitude_frequency(orbit: SynchronousOrbit, moments, state: CassiniState) -> float:
    """The free libration in latitude, rad/day: the small oscillation of the averaged spin axis about the
    Cassini state in the frame turning with the node (the Jacobian of dc/dt = P(θ)(c × k) + P_s (c·K)(c × K)
    − Ω̇ K × c there, by central differences on the unit sphere)."""
    K = np.array([0.0, 0.0, 1.0])
    i = orbit.inclination
    k = np.array([math.sin(i), 0.0, math.cos(i)])           # the orbit pole at longitude 0 in this frame
    I = state.equator_inclination
    c0 = np.array([-math.sin(I), 0.0, math.cos(I)])         # the Cassini pole, across K
    p_s = state.sun_precession_constant
    n, w = orbit.mean_motion, orbit.node_rate

    def rate(c):
        theta = math.acos(min(1.0, float(c @ k)))
        # the torque over L's magnitude along c: L = C (n + Ω̇ (K·c)) c + …, as in the balance
        scale = n / (n - w * float(c @ K))
        return scale * (precession_constant(orbit, moments, theta) * np.cross(c, k) + p_s * float(c @ K)
                        * np.cross(c, K)) - w * np.cross(K, c)

    # tangent basis at c0: e1 along the meridian (toward K), e2 across it
    e2 = np.array([0.0, 1.0, 0.0])
    e1 = np.cross(e2, c0)
    h = 1e-7                      # rad: the central difference's truncation O(h²) ~ 1e-14, rounding ~1e-9
    jac = np.empty((2, 2))
    for col, d in enumerate((e1, e2)):
        plus, minus = c0 + h * d, c0 - h * d
        dv = (rate(plus / np.linalg.norm(plus)) - rate(minus / np.linalg.norm(minus))) / (2.0 * h)
        jac[:, col] = (dv @ e1, dv @ e2)
    det = jac[0, 0] * jac[1, 1] - jac[0, 1] * jac[1, 0]
    return math.sqrt(det)
