"""A synchronous rotator's pole from its Cassini state (:mod:`ephem.forced.cassini`): the Moon family's model.

The body's orbit regresses on its Laplace plane (the catalogue's orbit: its plane and equinox, ``frame``,
with ``node_rate_deg_per_year``; for the Moon the mean ecliptic and equinox of date and Meeus' mean node). Its
pole, by Cassini's laws, stays at a fixed inclination I to the Laplace pole at longitude Ω(t) + 90°. The
served track keeps the catalogue's pole: its mean inclination I and its longitude from Ω + 90° at the pole
epoch t0, with the modelled librations there removed (the mean pole, as every theory's), then turns it with
the node (:class:`SynchronousModel`, :func:`synchronous_model`). The Cassini state the theory derives from the
moments (I from the torque's balance) is kept beside it (``state``) and tested against the observed I, not
served: the physics solved is within about 1 % of the observed inclination, the catalogue pole far closer.

Track angles: ψ = −Ω̇ (t − t0) with Ω̇ the node's inertial rate (the precession about the Laplace pole, positive
retrograde as the Earth's), Δψ and Δε the librations' displacement of the pole in longitude (times sin I: an angle
on the sky) and in inclination, the obliquity θ = i + I + Δε to the orbit of date. The ``integration`` model's
track is :func:`integrate_track` (the full rigid Moon, :mod:`ephem.moon.rigid_integration`).

The Moon (a body with a theory of its orbit's periodic terms) carries what lunar laser ranging adds
(:mod:`ephem.moon.orientation`): its mean pole is the Cassini state at the observed inclination (not the catalogue's
IAU pole, 9″ off), lagging behind the moving ecliptic as the physics makes it; ``librations`` adds the free wobble;
and each model computes the whole body frame (:meth:`SynchronousModel.axes`), the mean-Earth/rotation frame, whose
pole is the ``mean_rotation`` axis, and the principal axes turned from it by DE421's constant rotation, whose pole is
the ``figure`` axis. A user's satellite keeps its catalogue pole, and its two axes coincide (no degree-3 field is
known for it). Radians and days unless a name says otherwise.
"""
from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..forced.cassini import CassiniState, SynchronousOrbit, cassini_state, check_synchronous, free_librations
from ..bodies.catalogue import Body
from ..base.centres import GM_CENTER
from ..base.constants import (ARCSEC, AU_M, DAY_S, GENERAL_PRECESSION_ARCSEC_PER_CENTURY, GM_SUN, J2000_JD,
                              JULIAN_CENTURY_DAYS, JULIAN_YEAR_DAYS)
from ..base.errors import NotApplicableError
from ..orbit.geometry import carry, icrf_to_ecliptic_matrix, lon_lat, unit_vector
from ..orbit.kepler import mean_motion_rad_per_day
from ..orbit.lunar import delaunay_arguments
from ..forced.precession_nutation import Track
from .libration_frames import rodrigues
from .libration_series import shipped_series
from .orientation import ecliptic_lag_vector, free_wobble, lag_ratio, lag_rotation, me_to_pa, mean_inclination
from .physical_librations import EFFECTIVE_MOMENTS, moon_physical_librations
from .rigid_integration import integrate_synchronous
from ..forced.rigid_numerics import quaternion_from_matrix, rotation_matrices


#: The Sun's mean orbit seen from a body of the Earth's neighbourhood: 1 AU, e = 0.0167 (Simon et al. 1994)
SUN_ECCENTRICITY = 0.0167086
#: multiples of the node angle a kernel fits the Cassini pole's circle with: in RA and Dec the circle of radius I about
#: the Laplace pole has harmonics falling as (I / (90° − δ_K))^j, (1.57°/23.4°)^j for the Moon: 8 is under 0.1 mas
CIRCLE_SIDEBANDS = 8
#: the ``librations`` model's amplitude cut (rad): terms whose pole and τ amplitudes are both below 0.01″ are left
#: out (57 of 796 kept for the Moon; the omitted ones move the pole by 0.21″ at most, the series' evaluation
#: costs 3.6 µs an epoch instead of 70)
LIBRATION_CUT = 0.01 * ARCSEC
#: the rigid degree-2 body's omissions on the pole (rad): the degree-3 field's terms in l ± F (up to 1.15″,
#: tests/moon/test_physical_librations.py) and the dissipation's constant offset (0.26″, Williams et al. 2001)
PHYSICS_OMITTED = (1.15 + 0.26) * ARCSEC
#: IAU 2006's π_A rate, the ecliptic pole's speed (arcsec per Julian century; Capitaine et al. 2003, P03)
ECLIPTIC_POLE_ARCSEC_PER_CENTURY = 46.998973
#: the integration's tolerance (DOP853 rtol): the pole's global error over three node periods 0.002″ at 1e-8
#: (ephem.moon.rigid_integration), 0.02″ at 1e-7
INTEGRATION_RTOL = 1e-8
INTEGRATION_ERROR = 0.005 * ARCSEC

def _frame_matrices(frame: str, jd_tdb: np.ndarray) -> np.ndarray:
    """Rotation matrices (N, 3, 3) from the orbit's reference frame (the Laplace frame) to the ICRF."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    if frame == "ecliptic_of_date":
        import erfa

        return np.swapaxes(erfa.ecm06(t, np.zeros_like(t)), -1, -2)   # ecm06: ICRS -> ecliptic of date
    return np.broadcast_to(icrf_to_ecliptic_matrix().T, (t.size, 3, 3))


def synchronous_orbit(body: Body) -> SynchronousOrbit:
    """The body's mean orbit on its Laplace plane (:class:`~ephem.forced.cassini.SynchronousOrbit`), with the inertial
    node rate; :class:`NotApplicableError` where the record lacks what the Cassini state needs."""
    o = body.orbit
    if o.node_rate_deg_per_year is None:
        raise NotApplicableError(body.name, "a synchronous rotator's pole follows its orbit's node (the Cassini "
                                 "state): give the node's rate on the Laplace plane (orbit.node_rate_deg_per_year; "
                                 "the orbit's i and node are taken on that plane)")
    rate = math.radians(o.node_rate_deg_per_year) / JULIAN_YEAR_DAYS
    if o.frame == "ecliptic_of_date":      # the equinox of date regresses at p_A: the node's inertial rate
        rate -= GENERAL_PRECESSION_ARCSEC_PER_CENTURY * ARCSEC / JULIAN_CENTURY_DAYS
    n = body.spin_rate_rad_per_day
    g = GM_CENTER[o.center] * DAY_S**2 / (o.a_au * AU_M) ** 3
    sun = {} if o.center == "Sun" else dict(
        sun_tidal_rate_sq=GM_SUN * DAY_S**2 / AU_M**3, sun_eccentricity=SUN_ECCENTRICITY)
    return SynchronousOrbit(n, o.e, math.radians(o.i_deg), math.radians(o.node_deg), rate, math.radians(o.peri_deg),
                            0.0, math.radians(o.mean_anomaly_deg), o.epoch_jd_tdb, g, **sun)


def check_body(body: Body) -> None:
    """Not applicable (with the reason) unless ``body`` is a synchronous rotator with moments and a node rate."""
    o = body.orbit
    check_synchronous(body.name, body.spin_rate_rad_per_day, mean_motion_rad_per_day(o.a_au, o.center))
    if body.moments is None:
        raise NotApplicableError(body.name, "the Cassini state of a synchronous rotator needs its three principal "
                                 "moments (A, B, C): it feels B − A as well as C − A")
    synchronous_orbit(body)


@dataclass(frozen=True, eq=False)
class SynchronousModel:
    """The served Cassini-state model of one body (radians, days)."""

    body: Body
    orbit: SynchronousOrbit
    state: CassiniState                  # derived from the moments: reported, not served
    inclination: float                   # I of the catalogue's mean pole (served)
    longitude_offset: float              # the mean pole's longitude minus (Ω(t0) + 90°)
    node_at_pole_epoch: float            # Ω(t0) on the reference plane of the orbit's frame
    node_rate_of_frame: float            # dΩ/dt on that frame (of date: with the equinox's precession)
    pole_epoch: float
    frame: str
    hd: float = field(default=0.0)
    #: the forced physical librations (the Moon's), or None where the orbit has no theory of its periodic terms
    series: object = field(default=None, repr=False)
    #: the Moon's orientation beyond the rigid degree-2 theory (:mod:`ephem.moon.orientation`), or None (a user's
    #: satellite): the spin pole's lag behind the moving ecliptic over the orbit normal's (:func:`lag_ratio`)
    lag_ratio: float | None = None
    #: the free wobble (:class:`~ephem.moon.orientation.FreeWobble`), or None
    wobble: object = field(default=None, repr=False)
    #: ME → PA coordinates (3, 3) (:func:`~ephem.moon.orientation.me_to_pa`), or None: the principal axes taken as the
    #: mean rotation frame
    me_to_pa: object = field(default=None, repr=False)

    @property
    def obliquity(self) -> float:
        """θ = i + I: the mean pole from the orbit normal (Cassini state 2)."""
        return self.orbit.inclination + self.inclination

    @property
    def precession_rate(self) -> float:
        """−Ω̇ (rad/day, inertial): positive retrograde, the Earth's sense."""
        return -self.orbit.node_rate

    @property
    def scaling_factor(self) -> float:
        """K = 2 P(0) (rad/day): twice the torque's precession constant about the orbit normal, the synchronous
        analogue of a fast rotator's K (whose rate is K cos ε / 2 on a circular orbit)."""
        A, B, C = self.body.moments
        e = self.orbit.eccentricity
        return 3.0 * self.orbit.primary_gm_over_a3 / self.orbit.mean_motion * (C - A) / C * (1.0 - e * e) ** -1.5

    def node(self, jd_tdb) -> np.ndarray:
        return self.node_at_pole_epoch + self.node_rate_of_frame * (np.asarray(jd_tdb, dtype=float) - self.pole_epoch)

    @property
    def llr(self) -> bool:
        """Whether the model carries the Moon's lunar-laser-ranging orientation (:mod:`ephem.moon.orientation`)."""
        return self.lag_ratio is not None

    def axes(self, jd_tdb, librations: bool = True, wobble: bool = True, figure: bool = False) -> np.ndarray:
        """The body axes (N, 3, 3; columns X toward the mean Earth, Y, Z the pole) in the mean ecliptic and equinox
        of date (the Moon's model, :attr:`llr`): the Cassini frame Rz(Ω + π) Rx(I) Rz(F) displaced by the libration
        series' ρ, σ, τ (``librations``; 3-1-3 Euler angles φ = Ω + π + σ / sin I, θ = I + ρ, ψ = F + τ − σ / sin I,
        Ω and F the Delaunay arguments), moved in space by the lag behind the moving ecliptic, turned in the body by
        the free wobble (``wobble``): the mean-Earth/rotation frame; with ``figure``, the principal axes, that frame
        turned by the constant PA–ME rotation."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        axes = self._forced_axes(t, librations)
        if self.lag_ratio:
            axes = lag_rotation(ecliptic_lag_vector(t, self.orbit.node_rate, self.lag_ratio)) @ axes
        if wobble and self.wobble is not None:
            axes = self.wobble.apply(axes, t)
        if figure and self.me_to_pa is not None:
            axes = axes @ self.me_to_pa.T
        return axes

    def poles(self, jd_tdb, librations: bool = True, wobble: bool = True, figure: bool = False) -> np.ndarray:
        """The pole (N, 3) of :meth:`axes` in the ecliptic and equinox of date, computed as the forced axes times the
        pole's body vector (the wobble and the PA–ME rotation act on that vector alone) and moved by the lag to first
        order (|δ|²/2 < 1e-9 rad): a third of the work of the whole frame."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        u = np.broadcast_to(np.array([0.0, 0.0, 1.0]) if not figure or self.me_to_pa is None else self.me_to_pa[2],
                            (t.size, 3))
        if wobble and self.wobble is not None:
            u = u + np.cross(self.wobble.rotation(t), u)          # exp([w×]) u, |w| < 1e-4: second order 1e-9 rad
        pole = np.einsum("nij,nj->ni", self._forced_axes(t, librations), u)
        if self.lag_ratio:
            r = np.cross(np.array([0.0, 0.0, 1.0]), ecliptic_lag_vector(t, self.orbit.node_rate, self.lag_ratio))
            pole = pole + np.cross(r, pole)
        return pole

    def _forced_axes(self, t: np.ndarray, librations: bool) -> np.ndarray:
        """The Cassini frame displaced by the libration series (``librations``), (N, 3, 3): :meth:`axes` without
        the lag and the wobble."""
        args = delaunay_arguments(t)
        I = self.inclination
        if librations and self.series is not None:
            rho, sigma, tau = self.series.truncated(LIBRATION_CUT).angles(t)
        else:
            rho = sigma = tau = np.zeros(t.shape)
        dphi = sigma / math.sin(I)
        phi, theta, psi = args[:, 4] + math.pi + dphi, I + rho, args[:, 2] + tau - dphi
        cp, sp, ct, st, cs, ss = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi)
        return np.stack([np.stack([cp * cs - sp * ct * ss, -cp * ss - sp * ct * cs, sp * st], axis=-1),
                         np.stack([sp * cs + cp * ct * ss, -sp * ss + cp * ct * cs, -cp * st], axis=-1),
                         np.stack([st * ss, st * cs, ct], axis=-1)], axis=-2)

    def track_of_poles(self, jd_tdb, poles) -> Track:
        """The track of pole vectors (N, 3) in the orbit's frame of date: Δψ (the displacement along the Laplace
        plane's longitude from the mean pole at Ω + 90°, times sin I) and Δε (in inclination from I)."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        lon, lat = lon_lat(poles)
        deps = 0.5 * math.pi - lat - self.inclination
        dpsi = np.remainder(lon - self.node(t) - 0.5 * math.pi - self.longitude_offset + math.pi,
                            2.0 * math.pi) - math.pi
        ra, dec = lon_lat(np.einsum("nij,nj->ni", _frame_matrices(self.frame, t), poles))
        psi = self.precession_rate * (t - self.pole_epoch)
        return Track(t, psi, dpsi * math.sin(self.inclination), deps, self.orbit.inclination + 0.5 * math.pi - lat,
                     ra, dec)

    def track(self, jd_tdb, dpsi=None, deps=None) -> Track:
        """The pole at JD TDB: the mean pole turned with the node, displaced by the librations (Δψ: along the
        Laplace plane's longitude, an angle on the sky; Δε: in inclination; radians, or None)."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        zero = np.zeros(t.shape)
        dpsi = zero if dpsi is None else dpsi
        deps = zero if deps is None else deps
        incl = self.inclination + deps
        lon = self.node(t) + 0.5 * math.pi + self.longitude_offset + dpsi / math.sin(self.inclination)
        s = np.sin(incl)
        v = np.stack([s * np.cos(lon), s * np.sin(lon), np.cos(incl)], axis=-1)
        ra, dec = lon_lat(np.einsum("nij,nj->ni", _frame_matrices(self.frame, t), v))
        psi = self.precession_rate * (t - self.pole_epoch)      # inertial: the ecliptic of date's equinox moves
        return Track(t, psi, dpsi, deps, self.orbit.inclination + incl, ra, dec)


def _laplace_lon_lat(body: Body) -> tuple[float, float]:
    """The catalogue pole's longitude and colatitude (radians) in the orbit's frame at the pole epoch."""
    v = unit_vector(math.radians(body.pole.ra_deg), math.radians(body.pole.dec_deg))
    lon, lat = lon_lat(_frame_matrices(body.orbit.frame, np.array([body.pole.epoch_jd_tdb]))[0].T @ v)
    return float(lon), 0.5 * math.pi - float(lat)


_series_lock = threading.Lock()
_series: dict = {}


def libration_series(body: Body, moments=None):
    """The forced physical librations of ``body`` (:func:`ephem.moon.physical_librations.moon_physical_librations`
    with its moments, or ``moments``): the shipped series of those moments (data/moon_librations), else built
    once per process (about 2 s); None where the orbit has no theory of its periodic terms."""
    if body.orbit.theory != "meeus1998_moon":
        return None
    key = tuple(float(x) for x in (body.moments if moments is None else moments))
    with _series_lock:
        if key not in _series:
            _series[key] = shipped_series(key) or moon_physical_librations(key)
        return _series[key]


def series_built(body: Body) -> bool:
    """Whether a request for ``body`` finds its libration series (and the effective moments' one) built."""
    if body.orbit.theory != "meeus1998_moon":
        return True
    wanted = [tuple(float(x) for x in m) for m in (body.moments, EFFECTIVE_MOMENTS)]
    with _series_lock:
        return all(m in _series or shipped_series(m) is not None for m in wanted)


@lru_cache(maxsize=64)
def synchronous_model(body: Body) -> SynchronousModel:
    """The Cassini-state model of ``body`` (:func:`check_body` first): the mean pole is the catalogue pole less
    the librations' displacement at the pole epoch."""
    check_body(body)
    orbit = synchronous_orbit(body)
    state = cassini_state(orbit, body.moments, body.name)
    o = body.orbit
    frame_rate = math.radians(o.node_rate_deg_per_year) / JULIAN_YEAR_DAYS
    t0 = body.pole.epoch_jd_tdb
    node0 = math.radians(o.node_deg) + frame_rate * (t0 - o.epoch_jd_tdb)
    lon, colat = _laplace_lon_lat(body)
    series = libration_series(body)
    if series is not None and o.frame == "ecliptic_of_date":
        # the Moon: the Cassini state at the observed I, its node at Ω + 90° (Cassini's third law), the lag and the
        # free wobble, and the principal axes turned from the mean rotation frame (ephem.moon.orientation)
        colat = mean_inclination()[0]
        free = free_librations(orbit, body.moments, state)
        ratio = lag_ratio(colat, orbit.inclination, orbit.node_rate, free.precession_space_days)
        return SynchronousModel(body, orbit, state, colat, 0.0, node0, frame_rate, t0, o.frame, body.hd, series,
                                ratio, free_wobble(), me_to_pa())
    if series is not None:
        rho0, sigma0, _ = series.angles(np.array([t0]))
        colat -= float(rho0[0])
        lon -= float(sigma0[0]) / math.sin(colat)
    offset = math.remainder(lon - node0 - 0.5 * math.pi, 2.0 * math.pi)
    if not 0.0 < colat < 0.5 * math.pi:
        raise NotApplicableError(body.name, f"the catalogue pole lies {math.degrees(colat):.6g} deg from the Laplace "
                                 "pole: a Cassini state 2 has it between 0 and 90 deg")
    return SynchronousModel(body, orbit, state, colat, offset, node0, frame_rate, t0, o.frame, body.hd, series)


@lru_cache(maxsize=64)     # the model's alone (its free librations: ~5 ms), the models kept as synchronous_model keeps them
def ecliptic_lag(m: SynchronousModel) -> float:
    """v/ω_lat (rad): a user's satellite's bound on how far the real pole lags a Laplace plane moving at v (the
    ecliptic of date's pole, IAU 2006's π_A rate), its free libration in latitude turning at ω_lat in the node's frame;
    0 on a fixed plane. The Moon's model carries the lag itself, 7.3″ (:func:`ephem.moon.orientation.lag_ratio`: the
    free precession in space, slower than ω_lat, sets it)."""
    if m.frame != "ecliptic_of_date":
        return 0.0
    v = ECLIPTIC_POLE_ARCSEC_PER_CENTURY * ARCSEC / JULIAN_CENTURY_DAYS
    return v * free_librations(m.orbit, m.body.moments, m.state).latitude_days / (2.0 * math.pi)


@lru_cache(maxsize=16)
def moments_bound(body: Body) -> float:
    """The largest pole difference (rad) between the libration series with the catalogue's moments and with the
    effective ones (which give the observed I and free longitude period), over one node period daily, the terms
    above the cut."""
    a = libration_series(body).truncated(LIBRATION_CUT)
    b = libration_series(body, tuple(EFFECTIVE_MOMENTS)).truncated(LIBRATION_CUT)
    t = J2000_JD + np.arange(0.0, 6800.0, 0.5)
    (ra, sa, _), (rb, sb, _) = a.angles(t), b.angles(t)
    return float(np.max(np.hypot(ra - rb, sa - sb)))


def integrate_track(m: SynchronousModel, jd_tdb) -> Track:
    """The ``integration`` model's track: the rigid Moon on its real orbit (:func:`ephem.moon.rigid_integration.
    integrate_synchronous`), started at t0 on the librations' attitude and angular velocity, its pole turned onto
    the catalogue pole."""
    import erfa

    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    t0 = m.pole_epoch
    series = m.series
    attitude = series.attitude(np.array([t0]))[0]                        # ecliptic of date
    catalogue = _frame_matrices(m.frame, np.array([t0]))[0].T @ unit_vector(
        math.radians(m.body.pole.ra_deg), math.radians(m.body.pole.dec_deg))
    attitude = carry(attitude[:, 2], catalogue, attitude.T).T          # its columns turned onto the catalogue pole
    to_j2000 = erfa.ecm06(J2000_JD, 0.0) @ erfa.ecm06(t0, 0.0).T
    omega = series.angular_velocity(np.array([t0]), inertial=True)[0]
    y0 = np.concatenate([omega / m.orbit.mean_motion, quaternion_from_matrix(to_j2000 @ attitude)])
    run = integrate_synchronous(m.body.moments, m.orbit, t0, t, real_moon=True, y0=y0, rtol=INTEGRATION_RTOL,
                                atol=INTEGRATION_RTOL * 1e-3)
    icrf = run.figure_axis @ icrf_to_ecliptic_matrix()                   # rows: J2000 ecliptic -> ICRF
    of_date = np.einsum("nij,nj->ni", erfa.ecm06(t, np.zeros_like(t)), icrf)
    lon, lat = lon_lat(of_date)
    deps = 0.5 * math.pi - lat - m.inclination
    dpsi = np.remainder(lon - m.node(t) - 0.5 * math.pi - m.longitude_offset + math.pi, 2.0 * math.pi) - math.pi
    return m.track(t, dpsi * math.sin(m.inclination), deps)


def integrate_axes(m: SynchronousModel, jd_tdb, figure: bool = False, wobble: bool = True) -> np.ndarray:
    """The Moon's ``integration`` model (:attr:`SynchronousModel.llr`): the rigid Moon with the effective moments
    (:data:`~ephem.moon.physical_librations.EFFECTIVE_MOMENTS`, whose Cassini state lies at the observed I) on its real
    orbit, started at the pole epoch on the ``librations`` model's frame (the lag and the free wobble included) and
    angular velocity; its body axes (N, 3, 3) in the ecliptic and equinox of date, the mean rotation frame, or with
    ``figure`` the principal axes (:meth:`SynchronousModel.axes`); without ``wobble``, started without the free wobble
    (the forced figure axis's)."""
    import erfa

    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    t0 = m.pole_epoch
    start = np.array([t0])
    to_j2000 = erfa.ecm06(J2000_JD, 0.0) @ erfa.ecm06(t0, 0.0).T
    omega = m.series.angular_velocity(start, inertial=True)[0]
    if wobble and m.wobble is not None:     # a free wobble moves the axes, not the rotation: ω held in space
        omega = rodrigues(m.wobble.rotation(start).T)[0][:, :, 0].T @ omega
    y0 = np.concatenate([omega / m.orbit.mean_motion,
                         quaternion_from_matrix(to_j2000 @ m.axes(start, wobble=wobble)[0])])
    run = integrate_synchronous(EFFECTIVE_MOMENTS, m.orbit, t0, t, real_moon=True, y0=y0, rtol=INTEGRATION_RTOL,
                                atol=INTEGRATION_RTOL * 1e-3)
    # body -> J2000 ecliptic -> ICRF -> ecliptic of date
    axes = erfa.ecm06(t, np.zeros_like(t)) @ icrf_to_ecliptic_matrix().T @ rotation_matrices(run.quaternion)
    if figure and m.me_to_pa is not None:
        axes = axes @ m.me_to_pa.T
    return axes
