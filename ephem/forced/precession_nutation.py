"""Precession-nutation model of one body: geometry + Kinoshita's theory, evaluated over time.

The catalogue pole is the *instantaneous* spin axis at its epoch t0; the
theory's mean pole differs from it by the nutation (Δψ(t0), Δε(t0)), which is
removed here (:func:`ephem.forced.kinoshita.mean_pole`: three fixed-point passes; the correction is
second order).

The track follows the issue's definition, in the frame of the orbit and the
mean equinox at t0:

    ψ(t) = (ψ̇ − Ω_gp) (t - t0) + Δψ(t),    ε(t) = ε̄0 + Δε(t)

and the spin axis s(t) = (sin ε sin ψ, sin ε cos ψ, cos ε): s turns about
the orbit normal by -ψ (ψ̇ > 0 is retrograde, as the Earth's precession). ψ̇ is the torque's rate
(Kinoshita); Ω_gp the geodesic (de Sitter) precession, a rotation about the orbit normal in the orbital
sense (:mod:`ephem.orbit.relativity`), which every track carries as what the stars see (``track_rate``). It
is applied as that rotation of the torque's solution: what it leaves (the equinox's extra drift re-phasing
the nutation, and the periodic part of the instantaneous geodesic rate) is an error term of the ladder
(:func:`ephem.sun.bounds.geodesic_bounds`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bodies.catalogue import DEFAULT_DATASET, Body, resolve_body
from ..base.errors import InvalidInputError, NotApplicableError
from ..orbit.geometry import icrf_to_ecliptic_matrix, spin_geometry, unit_vector
from ..orbit.hansen import LAPLACE_LIMIT, exact_unavailable
from ..orbit.harmonics import MAX_SHIFT, cos_sin_shifted, uniform_cos_sin
from ..orbit.kepler import mean_motion_rad_per_day
from ..orbit.relativity import geodesic_precession_rate
from ..base.memo import bytes_bounded
from .kinoshita import NutationSeries, eccentricity_factor, mean_pole, nutation_series, precession_rate, scaling_factor

#: Rotation-averaging needs the spin much faster than the orbital motion. Against the full rigid
#: body (ephem.forced.rigid_body, docs/rigid_body_study.md) the averaged theory's figure axis is off by 10% of
#: the pole's motion over an orbit at ω/n = 25 for the catalogue Eros ((B-A)/C = 0.73, the worst
#: shape), 5-11 for near-axisymmetric bodies, and by order 1 below ω/n = 3: refuse below 30.
MIN_SPIN_ORBIT_RATIO = 30.0
#: highest e-order of the truncated Hansen coefficients a model accepts (omit the order for exact ones)
MAX_ORDER = 30


@dataclass(frozen=True)
class Track:
    """Spin-axis track over epochs (radians; times JD TDB)."""

    jd_tdb: np.ndarray
    psi: np.ndarray
    delta_psi: np.ndarray
    delta_epsilon: np.ndarray
    obliquity: np.ndarray
    pole_ra: np.ndarray
    pole_dec: np.ndarray


@dataclass(frozen=True)
class PrecessionNutation:
    """The forced precession and nutation of one body, first order in the torque.

    Rates in rad/day, angles in radians, times JD TDB.
    """

    body: str
    dataset: str
    hd: float
    mean_motion: float           # n, rad/day
    spin_rate: float             # ω, rad/day
    eccentricity: float
    scaling_factor: float        # K = 3 n² H_d / ω, rad/day
    obliquity: float             # mean obliquity ε̄0 at the pole epoch
    equinox_to_pericentre: float  # θ̄ from the mean equinox at t0
    precession_rate: float       # ψ̇, rad/day
    nutation: NutationSeries
    pole_epoch: float            # t0
    orbit_epoch: float
    mean_anomaly_at_epoch: float  # M at orbit_epoch
    nutation_at_pole_epoch: tuple[float, float]  # (Δψ(t0), Δε(t0))
    icrf_from_orbit: np.ndarray  # columns: mean equinox, W × equinox, W in ICRF
    order: int | None
    #: Ω_gp (rad/day), the geodesic precession about the orbit normal (:mod:`ephem.orbit.relativity`); 0 for a
    #: model of the torque alone (the full rigid body's reference, which measures rotation averaging)
    geodesic_rate: float = 0.0

    @property
    def track_rate(self) -> float:
        """The track's mean ψ̇ (rad/day): the torque's rate less the geodesic precession (module docstring)."""
        return self.precession_rate - self.geodesic_rate

    @property
    def spin_orbit_ratio(self) -> float:
        return self.spin_rate / self.mean_motion

    def mean_anomaly(self, jd_tdb) -> np.ndarray:
        return self.mean_anomaly_at_epoch + self.mean_motion * (np.asarray(jd_tdb, dtype=float) - self.orbit_epoch)

    def nutation_at(self, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """Δψ, Δε (radians) at epochs (JD TDB)."""
        return self.nutation.evaluate(self.mean_anomaly(jd_tdb))

    def angles(self, jd_tdb) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """ψ, Δψ, Δε and ε (radians) at epochs: the cheap part of a track."""
        t = np.asarray(jd_tdb, dtype=float)
        dpsi, deps = self.nutation_at(t)
        psi = self.track_rate * (t - self.pole_epoch) + dpsi
        return psi, dpsi, deps, self.obliquity + deps

    def angles_grid(self, jd_start: float, step_days: float, count: int):
        """As :meth:`angles` on the grid t_j = jd_start + j step_days (no trig per epoch)."""
        t = jd_start + step_days * np.arange(count)
        m_start = float(self.mean_anomaly(jd_start))
        dpsi, deps = self.nutation.evaluate_uniform(m_start, self.mean_motion * step_days, count)
        psi = self.track_rate * (t - self.pole_epoch) + dpsi
        return t, psi, dpsi, deps, self.obliquity + deps

    def first_order_error_bound(self, span_days: float) -> float:
        """Estimated upper bound (radians) on the pole error the first-order theory leaves over a span.

        Two second-order effects grow with time: the equinox drifts by ψ̇ T while the
        nutation phases are held fixed (error ≲ 2 A |ψ̇| T, A the largest nutation
        semi-amplitude), and the nutation feeds back into the torque's coefficients
        (a secular drift ≲ K² f(e)² T / (8 n), f(e) = (1 - e²)^(-3/2)). Order-of-magnitude
        estimate, checked against the numerical integration in the tests (it must
        never be exceeded there).
        """
        half_psi, half_eps = self.nutation.semi_peak_to_peak()
        amp = max(half_psi, half_eps)
        f = eccentricity_factor(self.eccentricity)
        rate = 2.0 * amp * abs(self.precession_rate) + self.scaling_factor**2 * f * f / (8.0 * self.mean_motion)
        return abs(span_days) * rate

    @property
    def catalogue_pole_orbit(self) -> np.ndarray:
        """The catalogue pole (the spin axis at the pole epoch, mean pole plus nutation there), a unit vector (3,)
        in the orbit frame: where every integration and offset starts."""
        dpsi0, deps0 = self.nutation_at_pole_epoch
        return self.pole_orbit_frame(dpsi0, self.obliquity + deps0)

    def pole_orbit_frame(self, psi, eps) -> np.ndarray:
        """Spin-axis unit vectors (..., 3) in the frame of the orbit and mean equinox at t0."""
        se = np.sin(eps)
        return np.stack([se * np.sin(psi), se * np.cos(psi), np.cos(eps)], axis=-1)

    def track(self, jd_tdb) -> Track:
        """Track at any epochs (JD TDB)."""
        t = np.asarray(jd_tdb, dtype=float)
        return self.track_from_angles(t, *self.angles(t))

    def track_grid(self, jd_start: float, step_days: float, count: int) -> Track:
        """Track on an evenly spaced grid: the same numbers as :meth:`track`, faster.

        ψ = ψ̇ (t - t0) + Δψ and ε = ε̄0 + Δε: the linear part of ψ is evenly spaced
        (angle addition) and the nutation is small (short Taylor series), so no
        trigonometric call per epoch remains but the final atan2's; the pole is
        computed by cache-sized blocks.
        """
        t, psi, dpsi, deps, eps = self.angles_grid(jd_start, step_days, count)
        if count == 0 or max(np.max(np.abs(dpsi)), np.max(np.abs(deps))) > MAX_SHIFT:
            return self.track_from_angles(t, psi, dpsi, deps, eps)
        ra = np.empty(count)
        dec = np.empty(count)
        psi_start = self.track_rate * (jd_start - self.pole_epoch)
        ce0, se0 = math.cos(self.obliquity), math.sin(self.obliquity)
        for start, c, s in uniform_cos_sin(psi_start, self.track_rate * step_days, count):
            sl = slice(start, start + c.size)
            cos_psi, sin_psi = cos_sin_shifted(c, s, dpsi[sl])
            cos_eps, sin_eps = cos_sin_shifted(ce0, se0, deps[sl])
            self._pole_into(sin_eps * sin_psi, sin_eps * cos_psi, cos_eps, ra[sl], dec[sl])
        return Track(t, psi, dpsi, deps, eps, ra, dec)

    def track_from_angles(self, t, psi, dpsi, deps, eps) -> Track:
        """The track whose angles (radians) at the epochs ``t`` are given (any theory's ψ, Δψ, Δε, ε in this
        model's orbit frame), with the pole's RA and Dec."""
        ra = np.empty(t.shape)
        dec = np.empty(t.shape)
        se = np.sin(eps)
        self._pole_into(se * np.sin(psi), se * np.cos(psi), np.cos(eps), ra, dec)
        return Track(t, psi, dpsi, deps, eps, ra, dec)

    def _pole_into(self, x, y, z, ra, dec) -> None:
        """RA in [0, 2π) and Dec of the orbit-frame unit vectors (x, y, z), written into ra, dec."""
        r = self.icrf_from_orbit
        xi = r[0, 0] * x + r[0, 1] * y + r[0, 2] * z
        yi = r[1, 0] * x + r[1, 1] * y + r[1, 2] * z
        zi = r[2, 0] * x + r[2, 1] * y + r[2, 2] * z
        np.arctan2(yi, xi, out=ra)
        ra += (ra < 0.0) * (2.0 * math.pi)
        np.arctan2(zi, np.sqrt(xi * xi + yi * yi), out=dec)  # unit vectors: no overflow to guard



def check_applicable(body: Body, spin_rate: float, mean_motion: float) -> None:
    """Refuse bodies whose rotation is too slow to average the torque over (a synchronous one, as the Moon, is
    served by :mod:`ephem.moon.family` instead)."""
    ratio = spin_rate / mean_motion
    if ratio < MIN_SPIN_ORBIT_RATIO:
        synchronous = abs(ratio - 1.0) < 0.01
        what = "synchronous with its orbit" if synchronous else "slow compared with its orbital motion"
        raise NotApplicableError(
            body.name,
            f"the rotation is {what} (spin rate / orbital mean motion ω/n = {ratio:.4g}); Kinoshita's theory "
            f"averages the torque over the rotation and needs ω/n >= {MIN_SPIN_ORBIT_RATIO:g} (below, its pole "
            f"departs from the full rigid body's by more than 10% of the forced motion)"
            + ("; a synchronous rotator's pole is served by the Cassini-state theory (ephem.moon.family) when its "
               "orbit's centre torques it (the catalogue's perturbers)" if synchronous else ""),
            ratio=ratio, threshold=MIN_SPIN_ORBIT_RATIO)


def check_domain(body: Body, order: int | None = None) -> None:
    """The theory's domain, checked before any work: a fast enough rotation (:func:`check_applicable`)
    and, for exact coefficients, an eccentricity whose Fourier series can be summed."""
    orb = body.orbit
    check_applicable(body, body.spin_rate_rad_per_day, mean_motion_rad_per_day(orb.a_au, orb.center))
    why = exact_unavailable(orb.e) if order is None else None
    if why is not None:
        raise NotApplicableError(body.name, why)


def build_model(body: Body, order: int | None = None) -> PrecessionNutation:
    """Precession-nutation model of ``body``.

    ``order`` None uses exact Hansen coefficients; an integer truncates them
    at that power of e (the paper: 4).
    """
    orb = body.orbit
    n = mean_motion_rad_per_day(orb.a_au, orb.center)
    omega = body.spin_rate_rad_per_day
    check_domain(body, order)
    K = scaling_factor(n, omega, body.hd)

    ecl_from_icrf = icrf_to_ecliptic_matrix()
    s_ecl = ecl_from_icrf @ unit_vector(math.radians(body.pole.ra_deg), math.radians(body.pole.dec_deg))
    i, node, peri = (math.radians(x) for x in (orb.i_deg, orb.node_deg, orb.peri_deg))
    geo = spin_geometry(s_ecl, i, node, peri, body.name)

    t0 = body.pole.epoch_jd_tdb
    m0 = math.radians(orb.mean_anomaly_deg)
    m_t0 = m0 + n * (t0 - orb.epoch_jd_tdb)
    last = {}

    def nutation_at_pole_epoch(eps_trial: float, theta_trial: float) -> tuple[float, float]:
        last["series"] = nutation_series(K, n, eps_trial, orb.e, theta_trial, order)
        dpsi_a, deps_a = last["series"].evaluate(np.array([m_t0]))
        return float(dpsi_a[0]), float(deps_a[0])

    # the series of the last pass reproduces the catalogue pole at t0 exactly (see mean_pole)
    eps_mean, theta_mean, dpsi0, deps0 = mean_pole(geo.obliquity, geo.equinox_to_pericentre, nutation_at_pole_epoch)
    series = last["series"]

    gamma, y_true, w = geo.orbit_frame
    x_mean = math.cos(dpsi0) * gamma + math.sin(dpsi0) * y_true
    frame_ecl = np.vstack([x_mean, np.cross(w, x_mean), w])  # rows in ecliptic
    icrf_from_orbit = ecl_from_icrf.T @ frame_ecl.T

    return PrecessionNutation(
        body=body.name, dataset=body.dataset, hd=body.hd, mean_motion=n, spin_rate=omega,
        eccentricity=orb.e, scaling_factor=K, obliquity=eps_mean, equinox_to_pericentre=theta_mean,
        precession_rate=precession_rate(K, eps_mean, orb.e, order), nutation=series,
        pole_epoch=t0, orbit_epoch=orb.epoch_jd_tdb, mean_anomaly_at_epoch=m0,
        nutation_at_pole_epoch=(dpsi0, deps0), icrf_from_orbit=icrf_from_orbit, order=order,
        geodesic_rate=geodesic_precession_rate(orb.a_au, orb.e, orb.center))


def check_order(order: int | None) -> int | None:
    """``order`` if it is None (exact Hansen coefficients) or an integer in [0, MAX_ORDER]; else
    :class:`InvalidInputError` naming ``order``."""
    if order is None:
        return None
    if isinstance(order, bool) or not isinstance(order, int) or order < 0 or order > MAX_ORDER:
        raise InvalidInputError("order", f"eccentricity order must be an integer in [0, {MAX_ORDER}] or omitted "
                                f"for exact Hansen coefficients, got {order!r}")
    return order


@bytes_bounded
def cached_model(body: Body, order: int | None = None) -> PrecessionNutation:
    """:func:`build_model`, memoised (a pure function of immutable inputs). The bodies are the callers' (a
    service's clients'), and a model's size grows with the eccentricity: the cache is bounded in bytes, shared
    with the other per-body caches (:mod:`ephem.base.memo`), not in entries."""
    return build_model(body, order)


def model_for(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None) -> PrecessionNutation:
    """Validated model of a catalogue body (by name or NAIF id) or of a :class:`Body`."""
    b = resolve_body(body, dataset)
    order = check_order(order)
    if order is not None and b.orbit.e > LAPLACE_LIMIT:
        raise InvalidInputError(
            "order", f"e = {b.orbit.e} exceeds the Laplace limit {LAPLACE_LIMIT:.4f}: the e-power series "
            "diverge; omit the order to use exact Hansen coefficients", b.name)
    return cached_model(b, order)
