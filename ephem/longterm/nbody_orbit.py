"""Long-term orbit-plane histories (millions of years) from an N-body integration with REBOUND (WHFast).

A spin axis integrated over Myr needs its orbit's plane over Myr. The catalogue's bodies have theirs shipped
in ``data/orbit_history/`` (one ``.npz`` per body and ``metadata.toml``), written by
``tools/derive_orbit_history.py``; :func:`shipped_orbit_history` reads them, :func:`nbody_orbit_history`
runs the same integration for a user's own orbit (:func:`nbody_cost_seconds` predicts its wall time first).
REBOUND is the ``nbody`` extra (``pip install 'ephem-asteroid-pn[nbody]'``): the shipped histories need none of it.

The integration (:func:`planet_simulation`, :func:`asteroid_state_j2000`, :func:`run_history`; one setup
shared by the tool and the library):

* the Sun and the barycentres of the eight planetary systems (the Earth–Moon barycentre, EMB, for the
  Earth) at J2000.0 TDB from DE421 (Folkner, Williams & Boggs 2009, IPN PR 42-178) through skyfield and
  skyfield-data (:func:`ephem.orbit.de421.barycentric`, offline), rotated to the mean ecliptic and equinox
  J2000 (:func:`ephem.orbit.geometry.icrf_to_ecliptic_matrix`); GMs DE421's (:data:`ephem.orbit.de421_header.GM_DE421`,
  :data:`~ephem.orbit.de421_header.GM_SUN_DE421`); units au, day, solar mass, G = GM_SUN_DE421 (au^3/day^2);
  moved to the centre of mass. No general relativity, no Moon as a separate body, no asteroid masses,
  no Pluto: see the module's horizon note.
* asteroids as massless test particles (``sim.N_active``). Their catalogue elements (osculating,
  heliocentric, ecliptic and equinox J2000, at their own epoch) are turned into a state at their epoch under
  GM_sun = k^2 (the value MPC/JPL elements are computed with), with the planets taken from DE421 at that
  same epoch, and carried to J2000.0 with IAS15 (Rein & Spiegel 2015, MNRAS 446, 1424; adaptive, so it
  resolves the near-Earth asteroids' encounters over those few decades); the J2000 heliocentric state is
  then added to the WHFast run.
* WHFast (Rein & Tamayo 2015, MNRAS 452, 376; Wisdom & Holman 1991), Jacobi coordinates, symplectic
  corrector of order 11, ``keep_unsynchronized`` (outputs do not perturb the trajectory), step
  :data:`DT_DAYS` ≈ Mercury's period / 16; forward and backward (negative step) from J2000.0.
* samples: the osculating heliocentric orbit normal (unit vector, ecliptic J2000), a (au) and e (with
  mu = G (M_sun + m)), for the EMB the EMB's, every :data:`SAMPLE_YEARS` Julian years.

The samples are osculating: they carry the short-period terms of the orbit normal (the planets' pulls over
synodic periods), aliased by the 500-year sampling into noise of that size: measured by dropping every other
sample and interpolating (tests/longterm/test_orbit_history.py): the EMB 1.1″, Mars 3.5″, Vesta 50″, Ceres 146″. A
spin-axis integration sees them averaged over its precession period; a mean (filtered) plane is not shipped.

Horizon: the times where a clone started 1 km away (a test particle) has its orbit normal 1 arcmin (1 deg)
away from the nominal one, past and future (measured by the tool, stored in the metadata). WHFast does not
resolve close planetary encounters, so the near-Earth asteroids' histories are meaningful only inside their
(short) horizons. Measured in the shipped run (data/orbit_history/metadata.toml): relative energy error
≤ 4.3e-12 over 3 Myr; dt vs dt/2 over ±20 kyr: EMB 8e-4″, Mars 1.5e-4″, Ceres 0.19″, Vesta 0.29″, Steins 0.56″,
Eros 16″, Itokawa unbounded; the planets' shadow run (EMB moved 1 km) stays within 0.65″ over -3..+1 Myr (the
inner solar system's Lyapunov time, ~5 Myr, Laskar 1989, Nature 338, 237, lies beyond the span); what is left
out (general relativity above all) bounds the planets' histories more than either. Units: Julian years of 365.25 days from J2000.0 TDB at the interface, radians inside.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..bodies.catalogue import Orbit
from ..base.paths import data_dir
from ..base.constants import J2000_JD, JULIAN_YEAR_DAYS
from ..base.errors import InvalidInputError, NotApplicableError
from ..base.extras import require
from ..orbit.de421 import barycentric
from ..orbit.de421_header import GM_DE421, GM_SUN_DE421
from ..base.disk_cache import cached_arrays, fingerprint, read_toml
from ..orbit.geometry import angle_between, icrf_to_ecliptic_matrix
from .cubic_spline import CubicSpline

#: the massive bodies of the run: (name, NAIF id of the DE421 barycentre, GM keys in GM_DE421 (none: the Sun))
MASSIVE = (("Sun", 10, ()), ("Mercury", 1, (1,)), ("Venus", 2, (2,)), ("Earth", 3, (399, 301)),
           ("Mars", 4, (4,)), ("Jupiter", 5, (5,)), ("Saturn", 6, (6,)), ("Uranus", 7, (7,)),
           ("Neptune", 8, (8,)))
#: output step of the shipped histories, Julian years
SAMPLE_YEARS = 500.0
#: WHFast steps per output step: dt = 500 yr / 33200 = 5.50075 d, Mercury's period (87.969 d) / 15.99
STEPS_PER_SAMPLE = 33200
DT_DAYS = SAMPLE_YEARS * JULIAN_YEAR_DAYS / STEPS_PER_SAMPLE
#: planets shipped (by the names of MASSIVE) and asteroids (catalogue names, test particles)
SHIPPED_PLANETS = ("Earth", "Mars")
SHIPPED_ASTEROIDS = ("Ceres", "Vesta", "Eros", "Steins", "Itokawa")
#: the bodies :func:`shipped_orbit_history` knows (the Moon gets the Earth's: its orbit plane about the Earth
#: precesses in 18.6 yr about the ecliptic, which is what this gives for it)
SHIPPED_BODIES = SHIPPED_PLANETS + SHIPPED_ASTEROIDS + ("Moon",)
#: wall time of :func:`nbody_orbit_history` per simulated Julian year (one test particle, 9 massive bodies,
#: WHFast at DT_DAYS), seconds: nbody_orbit_history timed over 20 kyr on the shared 2-core VM, idle, REBOUND
#: 5.2.2, 2026-11-27: 1.43e-4 s/yr (Ceres, 0 to +20 kyr, 2.9 s, the fixed cost included); 2.0e-4 leaves 40 % for
#: load (a second CPU-bound process on the other core was measured to cost ~+30 %; more processes than cores
#: cost more, which no constant covers). The fixed cost: DE421 states and the IAS15 leg to J2000 (0.2-0.6 s).
COST_SECONDS_PER_YEAR = 2.0e-4
COST_SECONDS_FIXED = 1.0

_DIR = "orbit_history"


# ----------------------------------------------------------------- the REBOUND setup (shared)

def _massive_states(jd_tdb: float):
    """(mass over the Sun's, ecliptic-J2000 barycentric position au, velocity au/day) of MASSIVE at ``jd_tdb``."""
    rot = icrf_to_ecliptic_matrix()
    out = []
    for _, naif, keys in MASSIVE:
        r, v = barycentric(naif, jd_tdb, velocity=True)
        mass = 1.0 if not keys else sum(GM_DE421[k] for k in keys) / GM_SUN_DE421
        out.append((mass, rot @ r[0], rot @ v[0]))
    return out


def _new_simulation(jd_tdb: float, integrator: str, dt_days: float):
    require("nbody", "an N-body orbit run")
    import rebound

    sim = rebound.Simulation()
    sim.G = GM_SUN_DE421           # au^3 / day^2 / M_sun: G M_sun = k^2
    for (name, _, _), (m, r, v) in zip(MASSIVE, _massive_states(jd_tdb)):
        sim.add(m=m, x=r[0], y=r[1], z=r[2], vx=v[0], vy=v[1], vz=v[2])
    sim.N_active = len(MASSIVE)
    sim.move_to_com()
    sim.integrator = integrator
    if integrator == "whfast":
        sim.dt = dt_days
        sim.integrator.safe_mode = 0
        sim.integrator.corrector = 11
        sim.integrator.keep_unsynchronized = 1
    return sim


def planet_simulation(dt_days: float = DT_DAYS):
    """A WHFast simulation of the Sun and the eight planetary systems at J2000.0 TDB (t = 0 days), ecliptic
    J2000, barycentric, au/day/M_sun. Negative ``dt_days`` integrates backwards."""
    return _new_simulation(J2000_JD, "whfast", dt_days)


def asteroid_state_j2000(orbit: Orbit) -> tuple[np.ndarray, np.ndarray]:
    """Heliocentric ecliptic-J2000 position (au) and velocity (au/day) at J2000.0 TDB of a body with osculating
    heliocentric elements ``orbit`` (ecliptic J2000, at ``orbit.epoch_jd_tdb``): placed at its epoch among the
    DE421 planets of that date (GM_sun = k^2) and carried to J2000.0 with IAS15 (test particle)."""
    if orbit.center != "Sun" or orbit.frame != "ecliptic_j2000":
        raise NotApplicableError(orbit.body or "orbit", "the N-body orbit history takes heliocentric elements "
                                 f"on the ecliptic J2000 (got centre {orbit.center!r}, frame {orbit.frame!r})")
    sim = _new_simulation(orbit.epoch_jd_tdb, "ias15", 0.0)
    sun = sim.particles[0]
    sim.add(primary=sun, m=0.0, a=orbit.a_au, e=orbit.e, inc=math.radians(orbit.i_deg),
            Omega=math.radians(orbit.node_deg), omega=math.radians(orbit.peri_deg),
            M=math.radians(orbit.mean_anomaly_deg))
    if abs(orbit.epoch_jd_tdb - J2000_JD) > 0.0:
        sim.integrate(J2000_JD - orbit.epoch_jd_tdb)   # t is days from the epoch
    p, s = sim.particles[-1], sim.particles[0]
    return (np.array([p.x - s.x, p.y - s.y, p.z - s.z]), np.array([p.vx - s.vx, p.vy - s.vy, p.vz - s.vz]))


def add_test_particle(sim, r_helio: np.ndarray, v_helio: np.ndarray, name: str) -> None:
    """Add a massless particle at a heliocentric state (ecliptic J2000, au, au/day) to ``sim``."""
    s = sim.particles[0]
    sim.add(m=0.0, x=s.x + r_helio[0], y=s.y + r_helio[1], z=s.z + r_helio[2],
            vx=s.vx + v_helio[0], vy=s.vy + v_helio[1], vz=s.vz + v_helio[2])


def _state_arrays(sim) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n = sim.N
    xyz = np.zeros((n, 3))
    vxyz = np.zeros((n, 3))
    m = np.zeros(n)
    sim.serialize_particle_data(xyz=xyz, vxvyvz=vxyz, m=m)
    return xyz, vxyz, m


def osculating(sim) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(unit orbit normal (N-1, 3), a au, e) of every particle but the Sun, heliocentric, mu = G (M_sun + m)."""
    xyz, vxyz, m = _state_arrays(sim)
    r = xyz[1:] - xyz[0]
    v = vxyz[1:] - vxyz[0]
    mu = sim.G * (m[0] + m[1:])
    h = np.cross(r, v)
    hn = np.linalg.norm(h, axis=1)
    rn = np.linalg.norm(r, axis=1)
    v2 = np.einsum("ij,ij->i", v, v)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = 1.0 / (2.0 / rn - v2 / mu)
        evec = (np.cross(v, h) / mu[:, None]) - r / rn[:, None]
        return h / hn[:, None], a, np.linalg.norm(evec, axis=1)


def energy(sim) -> float:
    """Total energy of the massive bodies (au^2/day^2 M_sun; test particles carry none, and a runaway one
    cannot turn it into NaN)."""
    xyz, vxyz, m = _state_arrays(sim)
    k = sim.N_active
    xyz, vxyz, m = xyz[:k], vxyz[:k], m[:k]
    kin = 0.5 * float(np.sum(m * np.einsum("ij,ij->i", vxyz, vxyz)))
    pot = 0.0
    for i in range(k):
        d = np.linalg.norm(xyz[i + 1:] - xyz[i], axis=1)
        pot -= sim.G * m[i] * float(np.sum(m[i + 1:] / d))
    return kin + pot


def run_history(sim, n_samples: int, steps_per_sample: int, on_sample=None, fine_every: int | None = None,
                on_fine=None, fine_until_steps: int = 0):
    """Step ``sim`` (WHFast, from t = 0) and sample it ``n_samples`` times after t = 0, every ``steps_per_sample``
    steps; returns (years (n+1,), normals (n+1, N-1, 3), a, e, max relative energy error), sample 0 at t = 0.

    ``on_fine(sim)`` is called every ``fine_every`` steps for the first ``fine_until_steps`` steps (the clones'
    divergence, resolved finer than the output step); ``on_sample(k, sim)`` after each sample (progress).
    """
    pole, a, e = osculating(sim)
    poles, aa, ee, years = [pole], [a], [e], [sim.t / JULIAN_YEAR_DAYS]
    e0 = energy(sim)
    worst = 0.0
    done = 0
    for k in range(1, n_samples + 1):
        target = k * steps_per_sample
        while done < target:
            if fine_every and done < fine_until_steps:
                n = min(fine_every, target - done)
                sim.steps(n)
                done += n
                if on_fine is not None:
                    sim.synchronize()
                    on_fine(sim)
            else:
                sim.steps(target - done)
                done = target
        sim.synchronize()
        pole, a, e = osculating(sim)
        poles.append(pole)
        aa.append(a)
        ee.append(e)
        years.append(sim.t / JULIAN_YEAR_DAYS)
        worst = max(worst, abs((energy(sim) - e0) / e0))
        if on_sample is not None:
            on_sample(k, sim)
    return np.array(years), np.array(poles), np.array(aa), np.array(ee), worst


# ----------------------------------------------------------------- the history object

def _check_years(name: str, value, body: str) -> np.ndarray:
    try:
        t = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(name, f"must be a number of Julian years from J2000.0, got {value!r}", body) from exc
    if not np.all(np.isfinite(t)):
        raise InvalidInputError(name, "must be finite", body)
    return t


@dataclass(frozen=True, eq=False)
class OrbitHistory:
    """A body's osculating heliocentric orbit plane, a and e, sampled over a long span.

    ``years``: Julian years (365.25 d) from J2000.0 TDB, ascending; ``pole``: (N, 3) unit orbit normals in the
    ecliptic and equinox J2000; ``a_au`` (au), ``e``; ``horizon_years``: (past, future) = how far back
    (negative) and forward the orbit normal is meaningful at the 1 arcmin level (clone divergence, see the
    module docstring); ``source``: what produced it.
    """

    body: str
    years: np.ndarray
    pole: np.ndarray
    a_au: np.ndarray
    e: np.ndarray
    horizon_years: tuple[float, float]
    source: str

    def __post_init__(self):
        t = np.asarray(self.years, dtype=float)
        if t.ndim != 1 or t.size < 4 or not np.all(np.diff(t) > 0.0):
            raise InvalidInputError("years", "must be at least 4 strictly ascending times", self.body)
        for name in ("pole", "a_au", "e"):
            arr = np.asarray(getattr(self, name), dtype=float)
            if arr.shape[0] != t.size or not np.all(np.isfinite(arr)):
                raise InvalidInputError(name, f"must have {t.size} finite rows", self.body)
        if abs(np.linalg.norm(self.pole, axis=1) - 1.0).max() > 1e-9:
            raise InvalidInputError("pole", "must hold unit vectors", self.body)

    @property
    def span_years(self) -> tuple[float, float]:
        return float(self.years[0]), float(self.years[-1])

    def _spline(self) -> CubicSpline:
        """The not-a-knot cubic spline of the pole's components, a and e (five columns), built once per object."""
        cached = self.__dict__.get("_spline_cache")
        if cached is None:
            cached = CubicSpline(self.years, np.column_stack([self.pole, self.a_au, self.e]))
            object.__setattr__(self, "_spline_cache", cached)   # a cache, not a field: frozen stays frozen
        return cached

    def _at(self, years, columns) -> np.ndarray:
        t = _check_years("years", years, self.body)
        lo, hi = self.span_years
        if np.any(t < lo - 1e-9) or np.any(t > hi + 1e-9):
            raise InvalidInputError("years", f"outside the history's span [{lo:g}, {hi:g}] Julian years from "
                                    f"J2000.0 ({self.source})", self.body)
        return self._spline()(t, columns)

    def pole_at(self, years) -> np.ndarray:
        """Unit orbit normal(s) (..., 3), ecliptic J2000, at Julian years from J2000.0: a not-a-knot cubic spline
        of each component, renormalised."""
        p = self._at(years, slice(0, 3))
        return p / np.linalg.norm(p, axis=-1, keepdims=True)

    def semi_major_axis_at(self, years) -> np.ndarray:
        """Osculating heliocentric a (au) at Julian years from J2000.0 (cubic spline)."""
        return self._at(years, 3)

    def eccentricity_at(self, years) -> np.ndarray:
        """Osculating heliocentric e at Julian years from J2000.0 (cubic spline)."""
        return self._at(years, 4)

    def covers(self, start_years: float, stop_years: float) -> bool:
        """Whether [start, stop] (Julian years from J2000.0) lies inside the data and inside the 1 arcmin
        horizon."""
        start = float(_check_years("start_years", start_years, self.body))
        stop = float(_check_years("stop_years", stop_years, self.body))
        if stop < start:
            raise InvalidInputError("stop_years", f"must not precede start_years ({stop} < {start})", self.body)
        lo = max(self.span_years[0], self.horizon_years[0])
        hi = min(self.span_years[1], self.horizon_years[1])
        return lo <= start and stop <= hi


# ----------------------------------------------------------------- shipped data

def history_dir() -> Path:
    """``data/orbit_history/`` (through :func:`ephem.base.paths.data_dir`)."""
    return data_dir() / _DIR


@lru_cache(maxsize=1)
def load_metadata() -> dict:
    """``data/orbit_history/metadata.toml``: the run, its sources, and each body's horizons (parsed once per machine,
    :func:`ephem.base.disk_cache.read_toml`)."""
    return read_toml(history_dir() / "metadata.toml")


def shipped_orbit_history(body_name: str) -> OrbitHistory:
    """The shipped history of a catalogue body (case-insensitive name; the Moon gets the Earth's).

    Raises :class:`~ephem.base.errors.NotApplicableError` for a body that has none (:data:`SHIPPED_BODIES`). Each file
    is read once (cached).
    """
    return _load_shipped(_shipped_name(body_name))


def _shipped_name(body_name: str) -> str:
    """The name of the shipped file's body for a body of :data:`SHIPPED_BODIES` (the Moon: the Earth)."""
    if not isinstance(body_name, str):
        raise InvalidInputError("body", f"must be a body name, got {body_name!r}")
    names = {b.lower(): b for b in SHIPPED_BODIES}
    name = names.get(body_name.strip().lower())
    if name is None:
        raise NotApplicableError(body_name, "no shipped orbit history; shipped: " + ", ".join(SHIPPED_BODIES)
                                 + " (use nbody_orbit_history for an orbit of your own)")
    return "Earth" if name == "Moon" else name


#: the shipped histories this process has loaded (:func:`shipped_loaded`: a price charges the read only once)
_LOADED: set[str] = set()


def shipped_loaded(body_name: str) -> bool:
    """Whether this process holds the shipped history of ``body_name`` already (False for a body without one)."""
    try:
        return _shipped_name(body_name) in _LOADED
    except (InvalidInputError, NotApplicableError):
        return False


@lru_cache(maxsize=None)
def shipped_span(body_name: str) -> tuple[float, float] | None:
    """The span (Julian years from J2000.0) the shipped N-body orbit of a catalogue body covers (the Moon: the
    Earth's), from the metadata, without loading the orbit; None for a body without one. A history within it follows
    that orbit by default (:func:`ephem.answers.requests.history`), one beyond it the secular orbit.

    Parameters
    ----------
    body_name : str
        The catalogue body's name (any case).

    Returns
    -------
    tuple of float, or None
        (first, last) Julian years from J2000.0 (negative: before it), or None.
    """
    try:
        name = _shipped_name(body_name)
    except (InvalidInputError, NotApplicableError):
        return None
    lo, hi = load_metadata()["body"][name]["data_span_years"]
    return float(lo), float(hi)


@lru_cache(maxsize=None)
def _load_shipped(name: str) -> OrbitHistory:
    _LOADED.add(name)
    meta = load_metadata()
    entry = meta["body"][name]
    z = _shipped_arrays(name)
    horizon = (float(entry["horizon_1arcmin_past_years"]), float(entry["horizon_1arcmin_future_years"]))
    source = (f"REBOUND {meta['run']['rebound_version']} WHFast dt={meta['run']['dt_days']:.5f} d N-body run "
              f"from DE421 at J2000 ({entry['initial_conditions']}); data/orbit_history/{entry['file']}")
    h = OrbitHistory(name, z["years"], z["pole"], z["a_au"], z["e"], horizon, source)
    object.__setattr__(h, "_spline_cache", CubicSpline.from_coefficients(z["years"], z["spline_c"]))
    return h


def shipped_sample_noise(name: str) -> float:
    """The shipped orbit normal's short-period noise (radians, :func:`_parse_shipped`) of a body of
    :data:`SHIPPED_BODIES` (the Moon: the Earth's)."""
    return float(_shipped_arrays(_shipped_name(name))["sample_noise"])


@lru_cache(maxsize=None)
def _shipped_arrays(name: str) -> dict:
    """The shipped file of ``name`` parsed, with its spline's coefficients and its sample noise: kept on disk between
    processes (:mod:`ephem.base.disk_cache`, keyed by the file and the code that builds them), so that a fresh
    process reads one table instead of solving two splines (12-15 ms of a CLI history)."""
    path = history_dir() / load_metadata()["body"][name]["file"]
    code = [Path(__file__), Path(__file__).with_name("cubic_spline.py")]
    return cached_arrays(f"orbit_history_{name.lower()}", fingerprint([path, *code]), lambda: _parse_shipped(path))


def _parse_shipped(path: Path) -> dict:
    """A shipped file's arrays, the coefficients (4, N-1, 5) of the not-a-knot spline of its pole's components, a
    and e (:meth:`OrbitHistory.pole_at`), and its normal's short-period noise (radians): half the largest miss of a
    spline through every other sample at the samples between (the osculating normal's terms of synodic periods,
    aliased by the 500-year sampling)."""
    with np.load(path) as z:
        years, pole, a, e = (np.array(z[k]) for k in ("years", "pole", "a_au", "e"))
    spline = CubicSpline(years, np.column_stack([pole, a, e]))
    even = CubicSpline(years[::2], pole[::2])(years[1:-1:2])
    noise = 0.5 * float(np.max(angle_between(even / np.linalg.norm(even, axis=-1, keepdims=True), pole[1:-1:2])))
    return {"years": years, "pole": pole, "a_au": a, "e": e, "spline_c": spline.c, "sample_noise": np.array(noise)}


# ----------------------------------------------------------------- custom bodies

def nbody_cost_seconds(start_years: float, stop_years: float) -> float:
    """Predicted wall time (s) of :func:`nbody_orbit_history` over [start, stop] Julian years from J2000.0:
    :data:`COST_SECONDS_PER_YEAR` x the simulated years (both directions from J2000.0) + a fixed cost."""
    start = float(_check_years("start_years", start_years, "orbit"))
    stop = float(_check_years("stop_years", stop_years, "orbit"))
    if stop <= start:
        raise InvalidInputError("stop_years", f"must follow start_years ({stop} <= {start})")
    simulated = max(0.0, stop) + max(0.0, -start)
    return COST_SECONDS_FIXED + COST_SECONDS_PER_YEAR * simulated


#: the factor by which the semi-major axis of an orbit run on demand may move from its J2000 value before the run is
#: refused as scattered: an osculating a near a planet swings by ten percent or more (a Hilda's near Jupiter at
#: aphelion: 4.13 to 3.58 AU), a close encounter scatters it by tens (a Jupiter-crossing orbit, e = 0.51 at 4.06 AU,
#: reached 7.1 AU within 1,000 years and 1,400 AU within 14,000)
MAX_A_FACTOR = 1.5


def nbody_orbit_history(orbit: Orbit, start_years: float, stop_years: float,
                        step_years: float = SAMPLE_YEARS) -> OrbitHistory:
    """The orbit history of a heliocentric ``orbit`` (catalogue elements, ecliptic J2000, at their epoch), by the
    shipped run's setup (module docstring) with this one test particle, sampled every ``step_years`` (rounded
    to a whole number of WHFast steps, :data:`DT_DAYS`) over [start, stop] Julian years from J2000.0, which
    must contain J2000.0 (the run starts there). No clone is run: the horizon given is the span itself; see
    the shipped metadata for how far such orbits hold. Cost: :func:`nbody_cost_seconds`.
    """
    body = orbit.body or "orbit"
    start = float(_check_years("start_years", start_years, body))
    stop = float(_check_years("stop_years", stop_years, body))
    step = float(_check_years("step_years", step_years, body))
    if step <= 0.0:
        raise InvalidInputError("step_years", f"must be positive, got {step}", body)
    if not start <= 0.0 <= stop or stop - start < 3.0 * step:
        raise InvalidInputError("start_years", f"the span [{start}, {stop}] must contain J2000.0 (0) and at least "
                                f"three steps of {step} years", body)
    steps = max(1, round(step * JULIAN_YEAR_DAYS / DT_DAYS))
    real_step = steps * DT_DAYS / JULIAN_YEAR_DAYS
    r, v = asteroid_state_j2000(orbit)
    parts = []
    for sign, end in ((-1.0, start), (1.0, stop)):
        # whole steps reaching the end (a step of whole WHFast steps rarely divides a short span: the run covered
        # [-0.77, 0.77] of [-1, 1] years, and the history's epochs at its ends were outside the orbit's span)
        n = int(math.ceil(abs(end) / real_step - 1e-9))
        if n == 0:
            continue
        sim = planet_simulation(sign * DT_DAYS)
        add_test_particle(sim, r, v, body)
        _, poles, a, e, _ = run_history(sim, n, steps)
        years = sign * np.arange(n + 1) * real_step        # the nominal grid (sim.t carries float sums)
        parts.append((sign, years, poles[:, -1], a[:, -1], e[:, -1]))
    ys, ps, aa, ee = [], [], [], []
    for sign, years, poles, a, e in parts:
        sl = slice(None, None, -1) if sign < 0 else slice(None)
        ys.append(years[sl])
        ps.append(poles[sl])
        aa.append(a[sl])
        ee.append(e[sl])
    years = np.concatenate(ys)
    keep = np.concatenate([[True], np.diff(years) > 0.0])     # J2000 appears in both directions
    years, pole, a, e = years[keep], np.concatenate(ps)[keep], np.concatenate(aa)[keep], np.concatenate(ee)[keep]
    ok = np.isfinite(pole).all(axis=1) & (e < 1.0)
    if not ok.all():
        raise NotApplicableError(body, "the orbit became unbound or singular within the span (a close "
                                 "encounter WHFast cannot follow); shorten the span")
    a0 = float(a[np.argmin(np.abs(years))])            # J2000, where the run starts
    scattered = np.abs(np.log(a / a0)) > math.log(MAX_A_FACTOR)
    if scattered.any():
        i = int(np.flatnonzero(scattered)[np.argmin(np.abs(years[scattered]))])      # the nearest J2000
        raise NotApplicableError(body, f"the orbit was scattered within the span: its semi-major axis went from "
                                 f"{a0:.4g} AU at J2000 to {a[i]:.4g} AU (e = {e[i]:.3g}) by year {years[i]:+.0f}, a "
                                 "close encounter with a planet, which the fixed-step N-body run does not resolve and "
                                 "the averaged spin does not follow; shorten the span to before it")
    return OrbitHistory(body, years, pole, a, e, (float(years[0]), float(years[-1])),
                        f"REBOUND WHFast dt={DT_DAYS:.5f} d N-body run from DE421 at J2000 (ephem.longterm.nbody_orbit)")
