"""A synchronous rotator (the Moon) as the library serves it: its pole from the Cassini state
(:mod:`ephem.moon.cassini`) behind the one model interface (:class:`~ephem.theory.interface.SpinAxisTheory`).

The body's orbit regresses on its Laplace plane (the catalogue's orbit: its plane and equinox, ``frame``,
with ``node_rate_deg_per_year``; for the Moon the mean ecliptic and equinox of date and Meeus' mean node). Its
pole, by Cassini's laws, stays at a fixed inclination I to the Laplace pole at longitude Ω(t) + 90°. The
served track keeps the catalogue's pole: its mean inclination I and its longitude from Ω + 90° at the pole
epoch t0, with the modelled librations there removed (the mean pole, as every theory's), then turns it with
the node. The Cassini state the theory derives from the moments (I from the torque's balance) is reported
beside it (the precession answer's ``cassini``) and tested against the observed I, not served: the physics
solved is within about 1 % of the observed inclination, the catalogue pole far closer.

Track angles: ψ = −Ω̇ (t − t0) with Ω̇ the node's inertial rate (the precession about the Laplace pole, positive
retrograde as the Earth's),
Δψ and Δε the librations' displacement of the pole in longitude (times sin I: an angle on the sky) and in
inclination, the obliquity θ = i + I + Δε to the orbit of date. Radians and days unless a name says otherwise.

Models, cheapest first (the two above ``cassini`` need a theory of the orbit's periodic terms, ``orbit.theory``:
the Moon's; a user's satellite has the bare Cassini state only):

* ``cassini``: the bare Cassini state: the mean pole turned with the node;
* ``librations``: plus the forced physical librations (:mod:`ephem.moon.physical_librations`), terms above
  :data:`LIBRATION_CUT`;
* ``integration``: the full rigid Moon (:mod:`ephem.moon.rigid_integration`) on the real orbit, started at t0 on the
  librations' state through the catalogue pole.

The mean pole is the catalogue pole with the libration series' displacement at t0 removed (every model shares
it). Each estimate is measured against the next model up (docs/moon.md):

* ``librations`` (``cassini``): every forced libration left out, the sum of the series' pole amplitudes;
* ``truncation`` (``librations``): the terms below the cut, the sum of their amplitudes;
* ``ecliptic_motion`` (``cassini``, ``librations``): the series put the pole on the moving ecliptic of date, the
  real pole lags it by up to v/ω_lat (the ecliptic pole's speed over the free libration in latitude's frequency;
  1.8″): twice, as the catalogue pole at t0 holds that instant's lag;
* ``start`` (``integration``): the rigid body's own Cassini state (the series' I for these moments) against the
  mean pole it starts from: the free libration in latitude that start excites swings the pole by twice the gap;
* ``moments`` (``librations``, ``integration``): the series with the catalogue's moments against those that give
  the observed I and free longitude period (:data:`ephem.moon.physical_librations.EFFECTIVE_BETA_GAMMA`);
* ``physics`` (every model, twice: at t and in the mean pole at t0): what a rigid degree-2 body leaves out, the
  degree-3 field's pole terms (1.15″) and the dissipation's offset (0.26″, Williams et al. 2001).
"""
from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..theory import cost
from ..base.budget import Cost, charge
from .cassini import (SYNCHRONOUS_TOLERANCE, CassiniState, SynchronousOrbit, cassini_state, check_synchronous,
                      free_librations, moment_ratios)
from ..bodies.catalogue import Body
from ..base.constants import (ARCSEC, AU_M, DAY_S, GENERAL_PRECESSION_ARCSEC_PER_CENTURY, GM_CENTER, GM_SUN, J2000_JD,
                              JULIAN_CENTURY_DAYS, JULIAN_YEAR_DAYS, MAS)
from ..base.errors import InvalidInputError, NotApplicableError
from ..orbit.lunar import MIN_CUT_MAS, check_cut
from ..orbit.geometry import carry, icrf_to_ecliptic_matrix, lon_lat, unit_vector
from ..orbit.kepler import mean_motion_rad_per_day
from ..forced.precession_nutation import Track
from .libration_series import shipped_series
from .physical_librations import EFFECTIVE_MOMENTS, moon_physical_librations
from .rigid_integration import integrate_synchronous
from ..theory.interface import Estimate, SpinAxisTheory, Spectrum, SpectrumExport
from ..theory.results import (COVERS_ALL_TERMS, COVERS_NOTHING_TRUNCATED, COVERS_TRUNCATION, CassiniState,
                              NutationResult, NutationTerm, PrecessionResult, RateSigmas, selection)
from ..forced.rigid_numerics import quaternion_from_matrix
from ..forced.catalogue_sigmas import dynamical_ellipticity_sigma, moments_function_sigma, no_uncertainty_reasons
from ..forced.uncertainty import SCALAR_KEYS
from ..longterm.averaged_spin import history_arrays
from ..orbit.lunar import delaunay_arguments, delaunay_rates
from ..theory.tracks import ROUNDING
from ..base.units import in_unit

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
THEORY = ("Cassini state of a synchronous rotator (ephem.moon.cassini): the spin axis, the orbit normal and the Laplace "
          "pole coplanar, the pole at fixed inclination to the Laplace plane turning with the orbit's node")
DESCRIPTIONS = {
    "cassini": "the bare Cassini state: the catalogue's mean pole turned with the node (Cassini's laws); the "
               "forced physical librations are left out and counted in the estimate",
    "librations": "the Cassini state with the forced physical librations of the pole (ephem.moon.physical_librations: "
                  "the rigid Moon's response to its orbit's periodic terms, terms above 0.01″)",
    "integration": "the full rigid Moon integrated on the real orbit (ephem.moon.rigid_integration: Euler's equations, "
                   "the Earth's and the Sun's torques), started on the librations' state at the pole epoch",
}
ASSUMPTIONS = [
    "rigid synchronous body, rotation locked to the orbit (long axis toward the primary)",
    "the orbit's node regresses uniformly on the Laplace plane (the Moon: the mean node of Meeus 1998 eq. 47.7 on "
    "the mean ecliptic of date, the ecliptic's motion from IAU 2006, erfa.ecm06)",
    "the pole keeps the catalogue's inclination to the Laplace plane and its longitude from the node + 90° at the "
    "pole epoch (Cassini's third law up to the librations there)",
]


def _frame_matrices(frame: str, jd_tdb: np.ndarray) -> np.ndarray:
    """Rotation matrices (N, 3, 3) from the orbit's reference frame (the Laplace frame) to the ICRF."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    if frame == "ecliptic_of_date":
        import erfa

        return np.swapaxes(erfa.ecm06(t, np.zeros_like(t)), -1, -2)   # ecm06: ICRS -> ecliptic of date
    return np.broadcast_to(icrf_to_ecliptic_matrix().T, (t.size, 3, 3))


def synchronous_orbit(body: Body) -> SynchronousOrbit:
    """The body's mean orbit on its Laplace plane (:class:`~ephem.moon.cassini.SynchronousOrbit`), with the inertial
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
    if series is not None:
        rho0, sigma0, _ = series.angles(np.array([t0]))
        colat -= float(rho0[0])
        lon -= float(sigma0[0]) / math.sin(colat)
    offset = math.remainder(lon - node0 - 0.5 * math.pi, 2.0 * math.pi)
    if not 0.0 < colat < 0.5 * math.pi:
        raise NotApplicableError(body.name, f"the catalogue pole lies {math.degrees(colat):.6g} deg from the Laplace "
                                 "pole: a Cassini state 2 has it between 0 and 90 deg")
    return SynchronousModel(body, orbit, state, colat, offset, node0, frame_rate, t0, o.frame, body.hd, series)


def ecliptic_lag(m: SynchronousModel) -> float:
    """v/ω_lat (rad): how far the real pole lags a Laplace plane moving at v (the ecliptic of date's pole, IAU
    2006's π_A rate), its free libration in latitude turning at ω_lat in the node's frame; 0 on a fixed plane."""
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


# ----------------------------------------------------------------------------- the theory's interface


#: Meeus (1998) eq. 47.7's T² coefficient of the lunar node, deg per century²: the node's acceleration (tides
#: and the Earth's eccentricity) that a linear node leaves out; over millennia it is the phase's error
NODE_ACCELERATION_DEG_PER_CENTURY2 = 0.0020708


@dataclass(frozen=True, eq=False)
class CassiniHistory:
    """A synchronous rotator's pole over long spans: the Cassini state carried along the moving Laplace plane.

    The plane is the primary's orbit plane (the Moon's Laplace plane is the ecliptic of date, to the 8″ of the
    Earth's J2 left out), taken from the primary's orbit history; the pole keeps its inclination I to it and
    turns with the node, whose inertial rate (``SynchronousOrbit.node_rate``) is driven by the Sun and scales with
    the Earth's orbit as (1 − e²)^(−3/2) (the solar tide's mean strength). The node's acceleration of Meeus' T²
    term (tides, left out) is the estimate's ``node_phase`` term, I times the node's phase error; the libration and
    the other terms of the ``cassini`` model's estimate are the ``librations`` term."""

    model: SynchronousModel
    librations: float
    orbit_body: str = "Earth"
    source: str = "the Cassini state (ephem.moon.cassini) turned with the node along the primary's orbit plane"

    def cost(self, span_years: float, epochs: int):
        """The Cassini pole at ``epochs`` epochs and the node's quadrature (:func:`ephem.theory.cost.cassini_history`)."""
        return cost.cassini_history(epochs)

    def history(self, orbit, years, progress=None):
        m = self.model
        years = np.asarray(years, dtype=float)
        t0 = (m.pole_epoch - J2000_JD) / JULIAN_YEAR_DAYS
        e0 = float(orbit.eccentricity_at(t0))
        fine = np.unique(np.concatenate([np.linspace(min(years.min(), t0), max(years.max(), t0), 4001), years, [t0]]))
        rate = m.orbit.node_rate * JULIAN_YEAR_DAYS * ((1.0 - e0**2) / (1.0 - orbit.eccentricity_at(fine) ** 2)) ** 1.5
        turned = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(fine))])
        turned -= np.interp(t0, fine, turned)
        node = m.node_at_pole_epoch + np.interp(years, fine, turned)
        plane = orbit.pole_at(years)
        z = np.array([0.0, 0.0, 1.0])
        i, incl = m.orbit.inclination, m.inclination
        lon = node + 0.5 * math.pi + m.longitude_offset
        orbit_pole = carry(z, plane, np.stack([math.sin(i) * np.sin(node), -math.sin(i) * np.cos(node),
                                               np.full(node.shape, math.cos(i))], axis=-1))
        spin = carry(z, plane, np.stack([math.sin(incl) * np.cos(lon), math.sin(incl) * np.sin(lon),
                                         np.full(node.shape, math.cos(incl))], axis=-1))
        centuries = (years - t0) / 100.0
        phase = np.minimum(np.radians(NODE_ACCELERATION_DEG_PER_CENTURY2) * centuries**2, math.pi)
        terms = {"librations": np.full(years.shape, self.librations),
                 "node_phase": 2.0 * math.sin(incl) * np.sin(0.5 * phase)}
        # the obliquity i + I does not depend on the node's phase: only the librations move it
        obliquity_terms = {"librations": np.full(years.shape, self.librations)}
        return history_arrays(years, spin, orbit_pole, -(node - m.node_at_pole_epoch), terms, obliquity_terms, (),
                              t0, np.zeros(years.shape), 0)


class SynchronousTheory(SpinAxisTheory, SpectrumExport):
    """A synchronous rotator (the Moon) under its primary: the Cassini state and its ladder."""

    summary = "the Cassini-state theory of a synchronous rotator (the Moon)"
    models = ("cassini", "librations", "integration")
    descriptions = DESCRIPTIONS

    @classmethod
    def serves(cls, body: Body, perturbers: tuple[str, ...]) -> bool:
        """A synchronous rotator torqued by its orbit's centre (the Sun's torque on a satellite is in the theory)."""
        o = body.orbit
        ratio = body.spin_rate_rad_per_day / mean_motion_rad_per_day(o.a_au, o.center)
        return abs(ratio - 1.0) <= SYNCHRONOUS_TOLERANCE and o.center in perturbers

    @property
    def model(self) -> SynchronousModel:
        return synchronous_model(self.body)

    @classmethod
    def how_to_reach(cls, body: Body) -> str:
        return "it models synchronous rotators (spin period = orbital period), such as the Moon"

    def default_model(self, order: int | None) -> str:
        return "cassini" if self.body.orbit.theory is None else "librations"

    def check_request(self, model: str | None, order: int | None) -> None:
        check_body(self.body)
        no_order(self.body, order)
        if self.axis != "figure":
            raise NotApplicableError(self.body.name, "the Cassini-state theory serves the figure axis (the pole of "
                                     "a synchronous body); its angular momentum differs from it by the precession's "
                                     "own angular velocity, not modelled: ask for axis=figure")
        if model in ("librations", "integration") and self.body.orbit.theory is None:
            raise NotApplicableError(self.body.name, no_orbit_theory(model))

    # --- cost: known before the work (data/cost_model.toml, benchmarks/bench_cost.py)

    def _setup_cost(self) -> tuple:
        return (cost.synchronous_estimates(),) + (() if series_built(self.body) else (cost.libration_series(),))

    def choice_cost(self, start: float, stop: float, count: int) -> Cost:
        return Cost(self._setup_cost())

    def track_cost(self, model, order, start, stop, count, free_wobble, rotation_scale=False) -> Cost:
        model = model or self.default_model(order)
        terms = 0 if model == "cassini" else self._terms_kept()
        parts = self._setup_cost() + (cost.synchronous_track(count, terms),)
        if model == "integration":
            t0 = self.body.pole.epoch_jd_tdb
            parts += (cost.synchronous_integration(max(stop, t0) - min(start, t0), count),)
        return Cost(parts)

    def _terms_kept(self) -> int:
        """Terms of the cut series (the Moon's: 57); before the series is built, that count."""
        if series_built(self.body) and self.body.orbit.theory is not None:
            return len(libration_series(self.body).truncated(LIBRATION_CUT))
        return LIBRATION_TERMS_KEPT

    def answer_cost(self, order: int | None, nutation: bool = False, tolerance: bool = False) -> Cost:
        return Cost(self._setup_cost())

    # --- estimates

    def estimates(self, jd_tdb) -> list[Estimate]:
        m = self.model
        if m.series is None:
            why = no_orbit_theory("librations")
            return [Estimate("cassini", None, {"rounding": ROUNDING}, unestimated=("librations",)),
                    Estimate("librations", None, {}, available=False, why_not=why),
                    Estimate("integration", None, {}, available=False, why_not=no_orbit_theory("integration"))]
        physics, ecliptic = 2.0 * PHYSICS_OMITTED, 2.0 * ecliptic_lag(m)
        moments = moments_bound(self.body)
        return [
            Estimate("cassini", None, {"librations": float(m.series.pole_amplitudes.sum()),
                                       "ecliptic_motion": ecliptic, "physics": physics, "rounding": ROUNDING}),
            Estimate("librations", None, {"truncation": m.series.omitted_bound(LIBRATION_CUT)[0], "moments": moments,
                                          "ecliptic_motion": ecliptic, "physics": physics, "rounding": ROUNDING}),
            Estimate("integration", None, {"start": 2.0 * abs(m.inclination - m.series.equator_inclination),
                                           "moments": moments, "integration": INTEGRATION_ERROR, "physics": physics,
                                           "rounding": ROUNDING}),
        ]

    def named(self, jd_tdb, model, order):
        name = model or self.default_model(order)
        return next(e for e in self.estimates(jd_tdb) if e.rung == name)

    def track(self, est, model, order, t0, step, count) -> Track:
        return self.track_at(model, order, self.grid(t0, step, count))

    def track_at(self, model, order, jd_tdb, free_wobble=False) -> Track:
        m = self.model
        model = model or self.default_model(order)
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        if model == "cassini":
            return m.track(t)
        if model == "librations":
            rho, sigma, _ = m.series.truncated(LIBRATION_CUT).angles(t)
            return m.track(t, sigma, rho)
        return integrate_track(m, t)

    def describe(self, est, model, order, with_wobble) -> dict:
        m = self.model
        b = self.body
        warnings = []
        if m.series is None:
            warnings.append(no_orbit_theory("librations"))
        return {
            "theory": THEORY, "eccentricity_order": None, "assumptions": list(ASSUMPTIONS), "warnings": warnings,
            "spin_orbit_ratio": b.spin_rate_rad_per_day / mean_motion_rad_per_day(b.orbit.a_au, b.orbit.center),
            "min_spin_orbit_ratio": 0.0, "pole_epoch_jd_tdb": m.pole_epoch, "orbit_epoch_jd_tdb": b.orbit.epoch_jd_tdb,
        }

    def secular_spin(self) -> CassiniHistory:
        """The Cassini state along the primary's moving orbit plane (:class:`CassiniHistory`); the primary's orbit
        history must be known (the Moon's: the Earth's)."""
        self.check_request(None, None)
        if self.body.orbit.center != "Earth":
            raise NotApplicableError(self.body.name, "the long-term Cassini state follows the primary's orbit plane, "
                                     "whose history is shipped for the Earth only (the Moon's primary)")
        cassini = next(e for e in self.estimates(np.array([self.model.pole_epoch])) if e.rung == "cassini")
        return CassiniHistory(self.model, cassini.total)

    def spectrum(self, aim_mas: float, mid_centuries: float, jd_tdb=None, psi=None) -> Spectrum:
        """The node's circle (a base at 0 with the precession's sidebands: the circle's projection on RA and Dec,
        :data:`CIRCLE_SIDEBANDS`) and, with a libration series, its terms above a hundredth of ``aim_mas`` as
        bases, their Delaunay phases linear about ``mid_centuries``."""
        m = self.model
        rate = m.precession_rate
        labels, theta0, theta1, amp = [None], [0.0], [0.0], [0.0]
        if m.series is not None:
            s = m.series.truncated(LIBRATION_CUT)
            keep = np.nonzero(s.pole_amplitudes > 0.01 * aim_mas * MAS)[0]
            mult = s.multipliers[keep].astype(float)
            jd_m = J2000_JD + mid_centuries * JULIAN_CENTURY_DAYS
            phase = np.degrees(mult @ delaunay_arguments(np.array(jd_m)))
            freq = np.degrees(mult @ delaunay_rates(mid_centuries)) * JULIAN_CENTURY_DAYS
            sign = np.where(freq < 0.0, -1.0, 1.0)
            labels += [tuple(int(v) for v in row) for row in s.multipliers[keep]]
            theta1 += list(sign * freq)
            theta0 += list((sign * phase - sign * freq * mid_centuries) % 360.0)
            amp += list(s.pole_amplitudes[keep] / MAS)
        return Spectrum(tuple(labels), np.array(theta0), np.array(theta1), np.array(amp),
                        math.degrees(rate * (J2000_JD - m.pole_epoch)) % 360.0,
                        math.degrees(rate) * JULIAN_CENTURY_DAYS, CIRCLE_SIDEBANDS,
                        "Delaunay multipliers (l, l', F, D, Omega) of a physical libration term; none: the node's circle")

    # --- the precession and nutation answers

    def precession(self, order: int | None, tolerance: float | None, start: float) -> PrecessionResult:
        b = self.body
        check_body(b)
        no_order(b, order)
        charge(self.answer_cost(order), b.name)
        m = self.model
        info = self.describe(None, "cassini", None, False)
        info["assumptions"].append(
            "precession_rate_arcsec_per_year: the node's inertial regression (the pole turns with it about the "
            "Laplace pole); obliquity_deg: the mean pole's θ = i + I to the orbit; scaling_factor_arcsec_per_year: "
            "2 P(0), twice the synchronous torque's precession constant (ephem.moon.cassini)")
        # the rate and the mean obliquity are the bare Cassini state's: nothing truncated
        return PrecessionResult(b, m.obliquity, m.hd, m.scaling_factor, m.precession_rate, rate_sigmas(b, m),
                                uncertainty_summary(b), info,
                                selection(self, "cassini", None, None, 1e3 * (time.perf_counter() - start),
                                          tolerance, covers=COVERS_NOTHING_TRUNCATED),
                                derived_cassini_state(m))

    def nutation(self, order: int | None, tolerance: float | None, cut_mas, start: float) -> NutationResult:
        b = self.body
        check_body(b)
        no_order(b, order)
        if tolerance is not None and cut_mas is not None:
            raise InvalidInputError("cut_mas", "give either cut_mas or tolerance_mas, not both", b.name)
        m = self.model
        if m.series is None:
            if cut_mas is not None:
                raise NotApplicableError(b.name, no_orbit_theory("librations"))
            cut = None
        elif cut_mas is not None:
            cut = check_cut(in_unit(cut_mas, "mas", "cut_mas")) * MAS
        elif tolerance is not None:
            cut = cut_for_tolerance(m.series, tolerance, b.name)
        else:
            cut = LIBRATION_CUT
        charge(self.answer_cost(order, nutation=True), b.name)
        name = "cassini" if m.series is None else "librations"
        info = self.describe(None, name, None, False)
        terms, omitted = (), None
        if m.series is not None:
            series = m.series.truncated(cut)
            omitted = m.series.omitted_bound(cut)[0]
            terms = nutation_terms(series)
            info["assumptions"].append(
                "terms: the forced physical librations of the pole, Δψ = σ (the pole's displacement across its "
                "meridian, toward increasing ecliptic longitude of date: sin I times the equator's node shift) and "
                "Δε = ρ (the equator's inclination less its mean), each Σ S sin φ + C cos φ with φ the multipliers · "
                "(l, l′, F, D, Ω) (IERS 2010 eq. 5.43); Eckhardt's (1981) variables, ephem.moon.physical_librations")
        if omitted is not None and not omitted > 0.0:
            omitted = None          # every term kept: nothing truncated here (issue 29: an estimate of 0 is no bound)
        chosen = selection(self, name, None, omitted, 1e3 * (time.perf_counter() - start), tolerance,
                           None if omitted is None else {"truncation": omitted},
                           covers=COVERS_TRUNCATION if omitted is not None else COVERS_ALL_TERMS,
                           cut_mas=None if cut is None else cut / MAS)
        half = (0.0, 0.0) if m.series is None else half_peak_to_peak(m.series.truncated(cut))
        # Δψ = σ is already the pole's displacement: its amplitude is not scaled by sin ε
        return NutationResult(b, "Delaunay arguments l, l′, F, D, Ω (IERS 2010 eq. 5.43)",
                              math.radians(b.orbit.mean_anomaly_deg), b.orbit.epoch_jd_tdb, m.orbit.mean_motion,
                              m.obliquity, terms, 1.0, half, (None, None), uncertainty_summary(b), info, chosen)


#: terms of the Moon's series above :data:`LIBRATION_CUT` (the cost before it is built)
LIBRATION_TERMS_KEPT = 60


def no_orbit_theory(model: str) -> str:
    return (f"the '{model}' model follows the orbit's periodic terms, which the library has for the Moon only (its "
            "catalogue orbit's theory, Meeus 1998 ch. 47); a user's satellite gets the bare Cassini state "
            "(model=cassini)")


def cut_for_tolerance(series, tolerance: float, name: str) -> float:
    """The largest amplitude cut (rad) whose omitted terms move the pole by no more than ``tolerance``."""
    amp = np.sort(np.maximum(series.pole_amplitudes, series.tau_amplitudes))
    for cut in amp[::-1]:
        if series.omitted_bound(float(cut))[0] <= tolerance:
            return float(cut)
    return MIN_CUT_MAS * MAS


def nutation_terms(series) -> tuple[NutationTerm, ...]:
    """The nutation terms of a libration series (radians; Δψ = σ, Δε = ρ; no 1σ: the librations are not
    propagated), largest pole amplitude first."""
    out = []
    order = np.argsort(-series.pole_amplitudes, kind="stable")
    for i in order:
        freq = float(series.frequencies[i])
        sigma, rho = series.sigma[i], series.rho[i]           # (cos, sin) coefficients
        out.append(NutationTerm(None, tuple(int(x) for x in series.multipliers[i]),
                                2.0 * math.pi / freq if freq else math.inf,
                                float(sigma[1]), float(sigma[0]), float(rho[1]), float(rho[0])))
    return tuple(out)


def half_peak_to_peak(series) -> tuple[float, float]:
    """Half the peak-to-peak σ and ρ (radians) over one node period from J2000, sampled every 0.25 d."""
    rho, sigma, _ = series.angles(J2000_JD + np.arange(0.0, 6800.0, 0.25))
    return 0.5 * float(np.ptp(sigma)), 0.5 * float(np.ptp(rho))


def derived_cassini_state(m: SynchronousModel) -> CassiniState:
    """The Cassini state the theory derives (the answer's ``cassini`` object), beside the served mean pole."""
    alpha, beta, gamma = moment_ratios(m.body.moments)
    free = free_librations(m.orbit, m.body.moments, m.state)
    return CassiniState(m.inclination, m.state.equator_inclination, m.state.obliquity, m.orbit.inclination,
                        m.orbit.node_rate, beta, gamma, free.longitude_days, free.latitude_days,
                        free.precession_space_days, free.wobble_days)


def rate_sigmas(b: Body, m: SynchronousModel) -> RateSigmas:
    """The precession answer's 1σ where the inputs have one: H_d and K = 2 P(0) ∝ (C − A)/C from the moments' σ
    and correlation (the Moon's: lunar laser ranging's β and γ); the rate is the orbit node's and the mean
    obliquity the catalogue pole's, neither with a published σ (None)."""
    A, B, C = b.moments
    polar = (C - A) / C
    sigma_polar = moments_function_sigma(b, lambda a, _b, c: (c - a) / c)
    return RateSigmas(None, dynamical_ellipticity_sigma(b),
                      None if sigma_polar is None else abs(m.scaling_factor) * sigma_polar / polar, None)


def uncertainty_summary(b: Body) -> dict:
    inputs = sorted(k for k in b.values if k.split(".")[0] in ("orbit", "pole", "rotation", "inertia")
                    and not k.endswith(".epoch"))
    unpropagated = [k for k in inputs if b.values[k].uncertainty is None]
    with_sigma = [k for k in ("inertia.A", "inertia.B", "inertia.C") if k in b.values
                  and b.values[k].uncertainty]
    dominant = {k: None for k in SCALAR_KEYS}
    if with_sigma:
        dominant["dynamical_ellipticity"] = dominant["scaling_factor_arcsec_per_year"] = "inertia.A"
    return {"method": "linear over the moments (their 1-sigma and correlation, for the Moon from lunar laser "
                      "ranging) for H_d and K; the rate is the orbit node's and the mean obliquity the catalogue "
                      "pole's, neither with a published sigma, and the physical librations are not propagated "
                      "(each build of their series costs seconds): those are unknown (null), not zero",
            "complete": not unpropagated, "dominant_input": dominant, "unpropagated_inputs": unpropagated,
            "no_uncertainty_reasons": no_uncertainty_reasons(b, unpropagated),
            "assumptions": ["the moments' errors as their derivation gives them (ephem.bodies.inertia)"]}


def no_order(body: Body, order) -> None:
    if order is not None:
        raise NotApplicableError(body.name, f"an e-order (order={order!r}) truncates the fast-rotator theory's "
                                 "Hansen coefficients; the Cassini-state theory of a synchronous rotator has none")
