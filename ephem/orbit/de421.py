"""The Sun's position seen from a body, from the JPL ephemeris DE421 (offline).

The fixed-orbit theory takes the Sun's direction from a Keplerian ellipse;
this module gives the real one, from a moving, perturbed orbit:

* planets in DE421 (Earth, Mars, ...): Sun minus planet, straight from the
  kernel (``de421.bsp`` shipped by ``skyfield-data``; Folkner, Williams &
  Boggs 2009, IPN Progress Report 42-178);
* heliocentric asteroids: their orbit integrated from the catalogue's
  osculating elements under the Sun and the DE421 planets (see
  :func:`integrate_heliocentric`).

Either way the result is a :class:`SunPath`, a piecewise Chebyshev fit of the
Sun's geometric position relative to the body (no light time): au, ICRF axes
(the DE421 frame), time argument a TDB Julian date. DE421 spans 1899-07-29 to
2053-10-09 TDB; outside it :class:`~ephem.base.errors.NotApplicableError` is raised.

Accuracy (measured, tests/orbit/test_against_de421.py): the fit reproduces its source to
< 1e-11 of the Sun's distance (2e-13 for Earth, Mars, Ceres, Vesta over
1900-2050; 5e-12 for Itokawa, whose Earth encounters need 8-day pieces). The
integrator started from DE421's Mars follows DE421's Mars to 4e-8 au after 10
years and 6e-7 au after 100: the rest is the asteroids DE421 includes and we
leave out (adding Ceres and Vesta alone brings it to 1.3e-7 au). The elements
themselves (MPC: 1e-5 deg, 1e-7 au) limit an asteroid's path more than that,
and much more for a near-Earth asteroid far from its epoch: a 1e-5 deg change
of Itokawa's mean anomaly moves its 1900-2050 path by 2e-3 au (3.5 arcsec in
its orbit normal), through its Earth encounters.
"""
from __future__ import annotations

import math
import threading
import warnings
from collections import OrderedDict
from functools import lru_cache
from operator import mul

import numpy as np

from ..base.budget import checkpoint
from ..base.constants import AU_M
from ..base.errors import NotApplicableError
from .de421_header import C_AU_PER_DAY, GM_DE421, GM_SUN_DE421, PERTURBERS
from .geometry import icrf_to_ecliptic_matrix
from .kepler import orbit_basis, solve_kepler_scalar

# ----------------------------------------------------------------- constants

#: Relative accuracy a fitted path must reach (checked, see SunPath.fit_error_au).
FIT_TOLERANCE = 1e-11


# ----------------------------------------------------------------- the kernel

@lru_cache(maxsize=1)
def _loader():
    import skyfield_data
    from skyfield.api import Loader

    with warnings.catch_warnings():
        # skyfield-data warns that its Earth-orientation file (finals2000A.all)
        # is out of date; we never use it (TDB dates, no Earth rotation).
        warnings.filterwarnings("ignore", message="The file finals2000A.all has expired",
                                category=RuntimeWarning)
        path = skyfield_data.get_skyfield_data_path()
    return Loader(path, verbose=False)


@lru_cache(maxsize=1)
def kernel():
    """The DE421 kernel (a skyfield ``SpiceKernel``), opened once, never downloaded."""
    return _loader()("de421.bsp")


@lru_cache(maxsize=1)
def timescale():
    """skyfield timescale from its built-in tables (no finals file, no network)."""
    return _loader().timescale(builtin=True)


@lru_cache(maxsize=1)
def de421_span() -> tuple[float, float]:
    """(first, last) TDB Julian date covered by every segment of the kernel."""
    segs = [s.spk_segment for s in kernel().segments]
    return max(s.start_jd for s in segs), min(s.end_jd for s in segs)


def _chain(naif: int) -> list:
    """SPK segments leading from the solar-system barycentre (0) to ``naif``."""
    by_target = {s.target: s for s in kernel().segments}
    chain = []
    while naif != 0:
        seg = by_target[naif]
        chain.append(seg.spk_segment)
        naif = seg.center
    return chain


def barycentric(naif: int, jd_tdb, velocity: bool = False, jd2=0.0):
    """Barycentric ICRF position (N, 3) of a DE421 body, au; with velocity (au/day) if asked.

    The date is ``jd_tdb + jd2`` (days): give a round ``jd_tdb`` and the rest in
    ``jd2`` to keep sub-microsecond timing (a single float JD resolves 40 us,
    in which the Earth moves 1.2 m, 8e-12 of its distance to the Sun).
    """
    jd, jd2 = (np.ravel(a) for a in np.broadcast_arrays(
        np.atleast_1d(np.asarray(jd_tdb, dtype=float)), np.asarray(jd2, dtype=float)))
    pos = np.zeros((3, jd.size))
    vel = np.zeros((3, jd.size))
    for seg in _chain(naif):
        if velocity:
            p, v = seg.compute_and_differentiate(jd, jd2)
            vel += v
        else:
            p = seg.compute(jd, jd2)
        pos += p
    km_per_au = AU_M / 1e3
    if velocity:
        return pos.T / km_per_au, vel.T / km_per_au
    return pos.T / km_per_au


def heliocentric(naif: int, jd_tdb, velocity: bool = False, jd2=0.0):
    """Heliocentric ICRF position (N, 3) of a DE421 body, au (and velocity, au/day);
    date ``jd_tdb + jd2`` as in :func:`barycentric`."""
    if velocity:
        p, v = barycentric(naif, jd_tdb, True, jd2)
        ps, vs = barycentric(10, jd_tdb, True, jd2)
        return p - ps, v - vs
    return barycentric(naif, jd_tdb, jd2=jd2) - barycentric(10, jd_tdb, jd2=jd2)


def tdb_date(jd: float) -> str:
    """The calendar date (YYYY-MM-DD, TDB) of a Julian date TDB, for messages."""
    return timescale().tdb_jd(jd).tdb_strftime("%Y-%m-%d")


def check_span(body: str, start_jd_tdb: float, stop_jd_tdb: float, what: str = "asked for") -> None:
    """Raise NotApplicableError unless [start, stop] lies inside DE421."""
    lo, hi = de421_span()
    if not (lo <= start_jd_tdb <= stop_jd_tdb <= hi):
        raise NotApplicableError(
            body, f"the real Sun direction is available only within DE421's span, "
                  f"{tdb_date(lo)} to {tdb_date(hi)} TDB (JD {lo} to {hi}); "
                  f"{what} JD {start_jd_tdb} to {stop_jd_tdb}")


# ----------------------------------------------------------------- Chebyshev fits

def _cheb_nodes(degree: int) -> np.ndarray:
    k = np.arange(degree + 1)
    return np.cos(np.pi * (k + 0.5) / (degree + 1))


def _cheb_fit_matrix(degree: int) -> np.ndarray:
    """M with coefficients = values_at_nodes @ M (discrete Chebyshev transform)."""
    n = degree + 1
    k = np.arange(n)
    m = (2.0 / n) * np.cos(np.pi * np.outer(k + 0.5, k) / n)
    m[:, 0] *= 0.5
    return m


class ChebyshevTable:
    """Piecewise Chebyshev fit of a vector function on [0, length] (days), ``n`` equal intervals.

    The argument is an offset ``u`` from the table's own origin, so that dates
    keep their full precision. ``coef`` has shape (n, degree + 1, ncomp); it is
    built from ``func(u) -> (N, ncomp)`` sampled at the Chebyshev nodes of every
    interval in one vectorised call.
    """

    def __init__(self, func, length: float, interval: float, degree: int):
        self.length, self.degree = float(length), degree
        self.n = max(1, math.ceil(length / interval - 1e-9))
        self.h = length / self.n
        u = self.h * (np.arange(self.n)[:, None] + 0.5 * (1.0 + _cheb_nodes(degree)[None, :]))
        values = np.asarray(func(u.ravel()), dtype=float).reshape(self.n, degree + 1, -1)
        self.coef = np.einsum("ikc,kj->ijc", values, _cheb_fit_matrix(degree))

    def __call__(self, u) -> np.ndarray:
        """Values at offsets ``u`` (1-d), shape (N, ncomp)."""
        s = np.asarray(u, dtype=float) / self.h
        k = np.clip(np.floor(s).astype(int), 0, self.n - 1)
        x = (2.0 * (s - k) - 1.0)[:, None]
        c = self.coef[k]                       # (N, degree+1, ncomp)
        b1, b2 = np.zeros(c[:, 0].shape), 0.0
        for j in range(self.degree, 0, -1):    # Clenshaw
            b1, b2 = 2.0 * x * b1 - b2 + c[:, j], b1
        return x * b1 - b2 + c[:, 0]

    def derivative(self) -> ChebyshevTable:
        """The table of d/du (per day), same intervals, one degree less."""
        from numpy.polynomial import chebyshev

        der = object.__new__(ChebyshevTable)
        der.length, der.degree, der.n, der.h = self.length, self.degree - 1, self.n, self.h
        der.coef = chebyshev.chebder(self.coef, axis=1) * (2.0 / self.h)
        return der

    def basis(self, u: float):
        """(interval index, [T_0(x), ..., T_degree(x)]) at one offset, in plain Python."""
        s = u / self.h
        k = min(int(s), self.n - 1) if s > 0.0 else 0
        x = 2.0 * (s - k) - 1.0
        tj = [1.0, x]
        x2 = 2.0 * x
        for _ in range(self.degree - 1):
            tj.append(x2 * tj[-1] - tj[-2])
        return k, tj


# ----------------------------------------------------------------- the path

class SunPath:
    """The Sun's geometric position relative to a body, au, ICRF axes, TDB dates.

    ``position(jd)`` is vectorised, ``position_scalar(t)`` a plain-Python
    evaluation for ODE right-hand sides. Both evaluate a piecewise Chebyshev
    fit (``interval_days`` long, degree ``degree``) of the source, which is
    called as ``func(u)`` with ``u`` days after ``start``. ``fit_error_au`` is
    the largest distance between fit and source found halfway between the
    fit's nodes, where it is largest; ``fit_error_rel`` is that error over the
    Sun's distance. ``source`` says where the positions come from.
    """

    def __init__(self, body: str, func, start: float, stop: float, source: str,
                 interval: float = 16.0, degree: int = 14):
        self.body, self.source = body, source
        self.start_jd_tdb, self.stop_jd_tdb = float(start), float(stop)
        nodes = _cheb_nodes(degree)
        x = np.concatenate([[1.0], 0.5 * (nodes[1:] + nodes[:-1]), [-1.0]])
        while True:
            table = ChebyshevTable(func, stop - start, interval, degree)
            u = (table.h * (np.arange(table.n)[:, None] + 0.5 * (1.0 + x[None, :]))).ravel()
            truth = np.asarray(func(u))
            if not np.all(np.isfinite(truth)):
                raise RuntimeError(f"{body}: the source gave non-finite positions")
            dist = np.linalg.norm(truth, axis=1)
            err = np.linalg.norm(table(u) - truth, axis=1)
            if np.max(err / dist) < FIT_TOLERANCE or interval < 1.0:
                break
            interval /= 2.0
        self._table, self._derivative = table, None
        self.interval_days, self.degree = table.h, degree
        self.fit_error_au, self.fit_error_rel = float(err.max()), float(np.max(err / dist))
        # per-interval coefficient tuples (x, y, z) of Python floats for the scalar path
        self._rows = [tuple(map(tuple, c.T.tolist())) for c in table.coef]

    def __repr__(self):
        return (f"SunPath({self.body!r}, JD {self.start_jd_tdb}..{self.stop_jd_tdb}, {self.source}, "
                f"fit error {self.fit_error_rel:.1e})")

    def _outside(self, lo: float, hi: float) -> ValueError:
        return ValueError(f"{self.body}: JD {lo}..{hi} is outside the path's span "
                          f"JD {self.start_jd_tdb}..{self.stop_jd_tdb}")

    def position(self, jd_tdb) -> np.ndarray:
        """Sun minus body, (N, 3) au, ICRF, at TDB Julian dates ``jd_tdb``."""
        jd = np.atleast_1d(np.asarray(jd_tdb, dtype=float)).ravel()
        if jd.min() < self.start_jd_tdb or jd.max() > self.stop_jd_tdb:
            raise self._outside(jd.min(), jd.max())
        return self._table(jd - self.start_jd_tdb)   # exact difference: no precision lost

    def position_scalar(self, t: float) -> tuple[float, float, float]:
        """Sun minus body (x, y, z) au at one TDB Julian date, in plain Python."""
        if not self.start_jd_tdb <= t <= self.stop_jd_tdb:
            raise self._outside(t, t)
        k, tj = self._table.basis(t - self.start_jd_tdb)
        cx, cy, cz = self._rows[k]
        return sum(map(mul, tj, cx)), sum(map(mul, tj, cy)), sum(map(mul, tj, cz))

    def velocity(self, jd_tdb) -> np.ndarray:
        """Time derivative of :meth:`position`, (N, 3) au/day (the fit's derivative)."""
        jd = np.atleast_1d(np.asarray(jd_tdb, dtype=float)).ravel()
        if jd.min() < self.start_jd_tdb or jd.max() > self.stop_jd_tdb:
            raise self._outside(jd.min(), jd.max())
        if self._derivative is None:
            self._derivative = self._table.derivative()
        return self._derivative(jd - self.start_jd_tdb)

    def orbit_normal(self, jd_tdb) -> np.ndarray:
        """Unit normal of the osculating heliocentric orbit (r x v of the body about
        the Sun, direction of the orbital angular momentum), (N, 3), ICRF."""
        w = np.cross(self.position(jd_tdb), self.velocity(jd_tdb))
        return w / np.linalg.norm(w, axis=1, keepdims=True)

    def direction(self, jd_tdb) -> np.ndarray:
        """Unit vector(s) towards the Sun, (N, 3), ICRF."""
        p = self.position(jd_tdb)
        return p / np.linalg.norm(p, axis=1, keepdims=True)


# ----------------------------------------------------------------- asteroid orbits

def elements_to_state(orbit, gm: float = GM_SUN_DE421) -> tuple[np.ndarray, np.ndarray]:
    """Heliocentric ICRF position (au) and velocity (au/day) from catalogue elements.

    The elements are osculating, heliocentric, ecliptic and equinox J2000
    (MPC/JPL); ``gm`` in au^3/day^2 (default k^2, the value they are computed
    with). The ecliptic is turned into the ICRF with the transpose of
    :func:`ephem.orbit.geometry.icrf_to_ecliptic_matrix`.
    """

    a, e = orbit.a_au, orbit.e
    p, q, _ = orbit_basis(math.radians(orbit.i_deg), math.radians(orbit.node_deg),
                          math.radians(orbit.peri_deg))
    ecc = solve_kepler_scalar(math.radians(orbit.mean_anomaly_deg), e)
    ce, se, b = math.cos(ecc), math.sin(ecc), math.sqrt(1.0 - e * e)
    n = math.sqrt(gm / a**3)
    r = a * (ce - e) * p + a * b * se * q
    v = (n * a / (1.0 - e * ce)) * (-se * p + b * ce * q)
    rot = icrf_to_ecliptic_matrix().T
    return rot @ r, rot @ v


def perturber_table(start: float, stop: float, perturbers=PERTURBERS) -> ChebyshevTable:
    """Chebyshev table, in days after ``start``, of the perturbers' heliocentric
    positions and of the Sun's Newtonian acceleration by them (the indirect
    term): columns [x1, y1, z1, x2, ..., ax, ay, az], au and au/day^2.

    8-day intervals, degree 13: every column is fitted to ~1e-13 of its size.
    """
    gm = np.array([GM_DE421[p] for p in perturbers])

    def func(u):
        sun = barycentric(10, start, jd2=u)
        pos = np.stack([barycentric(p, start, jd2=u) - sun for p in perturbers], axis=1)  # (N, P, 3)
        r3 = np.linalg.norm(pos, axis=2) ** 3
        indirect = np.einsum("p,npc->nc", gm, pos / r3[..., None])
        return np.concatenate([pos.reshape(len(u), -1), indirect], axis=1)

    return ChebyshevTable(func, stop - start, 8.0, 13)


def integrate_heliocentric(r0, v0, t0: float, start: float, stop: float, *,
                           perturbers=PERTURBERS, gm_scale: float = 1.0,
                           gm_sun: float = GM_SUN_DE421, gm_self: float = 0.0,
                           relativity: bool = True, rtol: float = 1e-13):
    """Integrate a body's heliocentric orbit from state (r0 au, v0 au/day) at TDB JD t0.

    Equations (heliocentric frame, ICRF axes, au and days): the Sun's pull on
    the body with G(M + m) (``gm_self`` = Gm, zero for an asteroid), the
    planets' direct pull and the indirect term (the Sun's acceleration by the
    planets), all point masses with DE421 GMs and DE421 positions, plus the
    Sun's 1PN Schwarzschild term, GM/(c^2 r^3) [(4 GM/r - v^2) r + 4 (r.v) v]
    (PPN beta = gamma = 1; the Schwarzschild term of IERS Conventions 2010,
    ch. 10). ``gm_scale`` multiplies every planet mass (0: two-body motion).
    scipy DOP853 (rtol 1e-13: 3e-9 au on Mars after a century), forward and
    backward from t0, covering [start, stop].

    Returns ``states(jd, jd2=0)``: (N, 6) heliocentric states at TDB dates
    ``jd + jd2``, from DOP853's dense output (within 1e-13 au of the step
    values); ``states.nfev`` counts the right-hand-side calls.
    """
    from scipy.integrate import solve_ivp

    lo, hi = min(start, t0), max(stop, t0)
    table = perturber_table(lo, hi, perturbers)
    coef, shift = table.coef, t0 - lo
    gms = [gm_scale * GM_DE421[p] for p in perturbers]
    mu, c2 = gm_sun + gm_self, C_AU_PER_DAY**2
    gr = gm_sun / c2 if relativity else 0.0

    def rhs(tau, state):   # tau: days after t0. Plain Python: 11 us a call, 2.5x numpy's
        checkpoint()    # the service's backstop
        k, tj = table.basis(tau + shift)
        row = np.dot(tj, coef[k]).tolist()
        x, y, z, vx, vy, vz = state.tolist()
        ax, ay, az = -gm_scale * row[-3], -gm_scale * row[-2], -gm_scale * row[-1]
        for j, gm in enumerate(gms):
            dx, dy, dz = row[3 * j] - x, row[3 * j + 1] - y, row[3 * j + 2] - z
            d2 = dx * dx + dy * dy + dz * dz
            f = gm / (d2 * math.sqrt(d2))
            ax += f * dx
            ay += f * dy
            az += f * dz
        r2 = x * x + y * y + z * z
        r = math.sqrt(r2)
        g = gr / (r2 * r)
        f = -mu / (r2 * r) + g * (4.0 * gm_sun / r - (vx * vx + vy * vy + vz * vz))
        h = 4.0 * g * (x * vx + y * vy + z * vz)
        return np.array([vx, vy, vz, ax + f * x + h * vx, ay + f * y + h * vy, az + f * z + h * vz])

    y0 = np.concatenate([r0, v0])
    opts = {"method": "DOP853", "rtol": rtol, "atol": 1e-3 * rtol, "dense_output": True}
    legs = []
    for end in (lo - t0, hi - t0):
        if end != 0.0:
            leg = solve_ivp(rhs, (0.0, end), y0, **opts)
            if not leg.success:  # pragma: no cover - DOP853 on a smooth problem
                raise RuntimeError(f"orbit integration failed: {leg.message}")
            legs.append(leg)

    def states(jd, jd2=0.0):
        tau = np.atleast_1d((np.asarray(jd, dtype=float) - t0) + np.asarray(jd2, dtype=float)).ravel()
        out = np.full((tau.size, 6), np.nan)
        for leg in legs:
            a, b = sorted(leg.t[[0, -1]])
            sel = (tau >= a) & (tau <= b)
            out[sel] = leg.sol(tau[sel]).T
        return out

    states.nfev = sum(leg.nfev for leg in legs)
    return states


# ----------------------------------------------------------------- entry point

#: NAIF ids whose position DE421 gives directly (planet centres).
DE421_BODIES = {199, 299, 399, 499}


def _snap(start: float, stop: float) -> tuple[float, float]:
    """Widen a span to whole days (TDB midnights) inside DE421, for cache reuse."""
    lo, hi = de421_span()
    start = max(lo, math.floor(start - 0.5) + 0.5)
    stop = min(hi, max(math.ceil(stop - 0.5) + 0.5, start + 1.0))
    return (start, stop) if stop > start else (stop - 1.0, stop)


def sun_path(body, start_jd_tdb: float, stop_jd_tdb: float) -> SunPath:
    """The Sun's position seen from ``body`` over [start, stop] (TDB JD), as a SunPath.

    ``body`` is a :class:`~ephem.bodies.catalogue.Body` (its name, NAIF id and orbit are read). Planets
    in DE421 (Earth 399, Mars 499, ...) come straight from the kernel; other
    heliocentric bodies are integrated from their osculating elements
    (:func:`integrate_heliocentric`). Raises NotApplicableError for orbits not
    centred on the Sun (the Moon: its orbit is geocentric and its rotation
    synchronous, so the Sun's torque does not average over a spin period as
    the theory assumes) and for spans outside DE421. Paths are cached by body
    and span (widened to whole days).
    """
    if body.orbit.center != "Sun":
        raise NotApplicableError(
            body.name, f"its orbit is centred on the {body.orbit.center}, not the Sun (and a synchronous "
                       "rotator's torque does not average over a spin period): no heliocentric "
                       "Sun path to give")
    if not start_jd_tdb <= stop_jd_tdb:
        raise ValueError(f"start {start_jd_tdb} after stop {stop_jd_tdb}")
    check_span(body.name, start_jd_tdb, stop_jd_tdb)
    if body.naif_id not in DE421_BODIES:
        check_span(body.name, body.orbit.epoch_jd_tdb, body.orbit.epoch_jd_tdb,
                   "the orbit integration starts at its elements' epoch,")
    return _cached_path(body.name, body.naif_id, body.orbit, *_snap(start_jd_tdb, stop_jd_tdb))


def path_kept(body, start_jd_tdb: float, stop_jd_tdb: float) -> bool:
    """Whether :func:`sun_path` keeps the path of ``body`` over [start, stop] (TDB JD) from an earlier call: the
    real-orbit rung's price charges the orbit's integration only while it does not (ephem.theory.cost)."""
    return (body.name, body.naif_id, body.orbit, *_snap(start_jd_tdb, stop_jd_tdb)) in _PATHS


#: the paths kept, least recently used first (at most :data:`PATHS_KEPT`; a 150-year path holds ~6 MB)
_PATHS: OrderedDict = OrderedDict()
_PATHS_LOCK = threading.Lock()
PATHS_KEPT = 8


def _cached_path(name: str, naif_id, orbit, start: float, stop: float) -> SunPath:
    """:func:`_build_path`, kept per body and span (the last :data:`PATHS_KEPT`), asked by :func:`path_kept`."""
    key = (name, naif_id, orbit, start, stop)
    with _PATHS_LOCK:
        if key in _PATHS:
            _PATHS.move_to_end(key)
            return _PATHS[key]
    path = _build_path(name, naif_id, orbit, start, stop)     # outside the lock: two threads may both build it
    with _PATHS_LOCK:
        _PATHS[key] = path
        _PATHS.move_to_end(key)
        while len(_PATHS) > PATHS_KEPT:
            _PATHS.popitem(last=False)
    return path


_cached_path.cache_clear = _PATHS.clear


def _build_path(name: str, naif_id, orbit, start: float, stop: float) -> SunPath:
    if naif_id in DE421_BODIES:
        # Planet centres (Mars: 499, 0.2 m from the Mars barycentre 4). DE421
        # gives the Earth about the Earth-Moon barycentre in 4-day records, a
        # monthly wobble of 4700 km: 8-day pieces for it.
        return SunPath(name, lambda u: -heliocentric(naif_id, start, jd2=u), start, stop,
                       source=f"DE421 (Sun 10 minus {naif_id})",
                       interval=8.0 if naif_id == 399 else 16.0)
    r0, v0 = elements_to_state(orbit)
    states = integrate_heliocentric(r0, v0, orbit.epoch_jd_tdb, start, stop)
    return SunPath(name, lambda u: -states(start, u)[:, :3], start, stop,
                   source="orbit integrated from catalogue elements under the Sun and DE421 planets")
