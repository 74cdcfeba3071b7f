"""The body catalogue: orbits, spin poles, rotation periods and moments of inertia.

Each dataset is a TOML file in ``data/catalogue/`` (format: ``SCHEMA.md``
there); every value carries its unit, its uncertainty where the source gives
one, and a source key resolved in ``data/references.toml``. Units are
converted with astropy at load time; the records below hold plain floats in
the units their field names state.

Records validate themselves: a bad value raises
:class:`~ephem.base.errors.InvalidInputError` naming the body and the field, whether
it comes from a catalogue file or from a user's own body.

Here: the records (:class:`Orbit`, :class:`Pole`, :class:`Body`), a dataset's TOML read into them
(:func:`parse_catalogue`), and the lookups (:func:`load_catalogue`, :func:`get_body`, :func:`resolve_body`).
A value table of a record is read by :mod:`ephem.bodies.measured`; where the datasets live, shipped or
the user's, is :mod:`ephem.bodies.datasets`.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field, fields
from functools import lru_cache
from pathlib import Path

from ..base.centres import CENTER_HILL_AU, CENTER_RADIUS_AU, GM_CENTER, KNOWN_PERTURBERS, admissions
from ..base.constants import J2000_JD, JD_RANGE
from ..base.errors import InvalidInputError, NotApplicableError, UnknownBodyError
from .datasets import available_datasets, dataset_file
from .inertia import hd_of_moments
from .measured import (Measured, check_finite, convert, derived_moments, measured, rotation_period, section_reason,
                       stated_correlations)
from ..base.disk_cache import parse_toml, read_toml
from ..base.paths import data_dir
from ..orbit.geometry import ecliptic_to_icrf, lon_lat
from ..orbit.kepler import mean_motion_rad_per_day

DEFAULT_DATASET = "current"


def dynamical_ellipticity(A: float, B: float, C: float, body: str | None = None) -> float:
    """H_d = (C - (A+B)/2) / C (Petit et al. eq. 11), from principal moments A <= B <= C."""
    for name, value in (("A", A), ("B", B), ("C", C)):
        if not math.isfinite(value) or value <= 0.0:
            raise InvalidInputError(f"inertia.{name}", f"must be a positive finite number, got {value!r}", body)
    if not A <= B <= C:
        raise InvalidInputError("inertia", f"principal moments must satisfy A <= B <= C, got A={A}, B={B}, C={C}", body)
    if C > A + B:
        raise InvalidInputError("inertia", f"C={C} exceeds A+B={A + B}: no rigid body has these moments", body)
    return hd_of_moments(A, B, C)


def spin_rate_rad_per_day(rotation_period_hours: float) -> float:
    """Spin rate ω = 2π / P (rad/day) of a rotation period P in hours (sidereal: relative to the
    stars); the ω of K = 3 n² H_d / ω (Petit et al. 2014, eq. 10)."""
    return 2.0 * math.pi / (rotation_period_hours / 24.0)


#: Largest |angle| accepted for an angle taken modulo 360 deg (an orbit's node, argument of pericentre and mean
#: anomaly, a pole's right ascension or ecliptic longitude, a phase), deg: any number of turns up to 2778. Near
#: 1e6 the doubles are 2^-33 deg = 1.2e-10 deg (0.4 µas) apart, the rounding the answers carry already; each
#: decade beyond loses another digit of the remainder (1e308 keeps none), so a larger angle is refused rather
#: than silently rounded: reduce it modulo 360 first.
MAX_ANGLE_DEG = 1e6


def check_angle(body: str | None, name: str, value: float) -> None:
    """``value`` (deg) a finite number within ±:data:`MAX_ANGLE_DEG`, else :class:`InvalidInputError` naming
    ``name`` (its full path: ``pole.ra_deg``)."""
    check_finite(body, name, value)
    if abs(value) > MAX_ANGLE_DEG:
        raise InvalidInputError(name, f"an angle must lie within ±{MAX_ANGLE_DEG:g} deg: beyond it the doubles are "
                                f"more than {math.ulp(MAX_ANGLE_DEG):.2g} deg apart and its remainder modulo 360 deg "
                                f"loses the digits the answer needs; reduce it modulo 360, got {value!r}", body)


#: Shortest rotation period accepted, hours: ten times faster than the fastest known asteroid rotator
#: (2020 HS7, 2.99 s), and far from the floats where 2π/P overflows.
MIN_ROTATION_PERIOD_HOURS = 1e-4


def _check_epoch(body: str | None, name: str, jd: float) -> None:
    """The epochs the time parser accepts (:data:`ephem.base.constants.JD_RANGE`), for a record's epochs too."""
    lo, hi = JD_RANGE
    if not lo < jd < hi:
        raise InvalidInputError(name, f"Julian date {jd} is outside the supported range ({lo:g}, {hi:g})", body)


#: the planes and equinoxes an orbit's elements may be referred to (:class:`Orbit`)
ORBIT_FRAMES = ("ecliptic_j2000", "ecliptic_of_date")
#: the theories of a real orbit's periodic terms the library has: the Moon's (Meeus 1998 ch. 47, ELP-2000/82
#: truncated, in ephem.earth.lunisolar), which its physical librations and its rigid integration follow
ORBIT_THEORIES = ("meeus1998_moon",)


@dataclass(frozen=True)
class Orbit:
    """Osculating Keplerian elements, ecliptic and equinox J2000, at ``epoch_jd_tdb``.

    ``center`` is the attracting (and torquing) body: "Sun" for heliocentric
    orbits, "Earth" for the Moon.

    ``theory``: the name of a theory of the real orbit's periodic terms (:data:`ORBIT_THEORIES`), or None.

    ``node_rate_deg_per_year``: the node's mean motion on the reference plane (a satellite's orbit regressing
    on its Laplace plane), or None. ``frame``: the plane and equinox the elements are referred to:
    "ecliptic_j2000" (the default), or "ecliptic_of_date" (the mean ecliptic and equinox of date, as a
    lunar theory gives the Moon's node; the elements' i and node are then those of date).
    """

    a_au: float
    e: float
    i_deg: float
    node_deg: float
    peri_deg: float
    mean_anomaly_deg: float
    epoch_jd_tdb: float
    center: str = "Sun"
    node_rate_deg_per_year: float | None = None
    frame: str = "ecliptic_j2000"
    #: a theory of the real orbit's periodic terms the library has, or None (:data:`ORBIT_THEORIES`)
    theory: str | None = None
    body: str | None = field(default=None, compare=False)

    def __post_init__(self):
        b = self.body
        for name in ("a_au", "e", "i_deg", "node_deg", "peri_deg", "mean_anomaly_deg", "epoch_jd_tdb"):
            check_finite(b, f"orbit.{name}", getattr(self, name))
        for name in ("node_deg", "peri_deg", "mean_anomaly_deg"):
            check_angle(b, f"orbit.{name}", getattr(self, name))
        if self.node_rate_deg_per_year is not None:
            check_finite(b, "orbit.node_rate_deg_per_year", self.node_rate_deg_per_year)
        if self.theory is not None and self.theory not in ORBIT_THEORIES:
            raise InvalidInputError("orbit.theory", f"must be one of {', '.join(ORBIT_THEORIES)} or omitted, got "
                                    f"{self.theory!r}", b)
        if self.frame not in ORBIT_FRAMES:
            raise InvalidInputError("orbit.frame", f"must be one of {', '.join(ORBIT_FRAMES)}, got {self.frame!r}", b)
        _check_epoch(b, "orbit.epoch_jd_tdb", self.epoch_jd_tdb)
        if self.a_au <= 0:
            raise InvalidInputError("orbit.a_au", f"semi-major axis must be positive, got {self.a_au}", b)
        if not 0.0 <= self.e < 1.0:
            raise InvalidInputError("orbit.e", f"eccentricity must satisfy 0 <= e < 1 (bound orbit), got {self.e}", b)
        if not 0.0 <= self.i_deg <= 180.0:
            raise InvalidInputError("orbit.i_deg", f"inclination must lie in [0, 180] deg, got {self.i_deg}", b)
        if self.center not in GM_CENTER:
            raise InvalidInputError("orbit.center", f"unknown centre {self.center!r}; known: {sorted(GM_CENTER)}", b)
        radius, hill = CENTER_RADIUS_AU[self.center], CENTER_HILL_AU[self.center]
        if self.a_au * (1.0 - self.e) <= radius:
            raise InvalidInputError("orbit.a_au", f"the pericentre a(1 - e) = {self.a_au * (1.0 - self.e):.6g} AU lies "
                                    f"inside the {self.center} (radius {radius:.6g} AU): no orbit", b)
        if self.a_au > hill:
            raise InvalidInputError("orbit.a_au", f"a = {self.a_au:.6g} AU lies beyond the {self.center}'s Hill sphere "
                                    f"(~{hill:.3g} AU): no orbit bound to it", b)


@dataclass(frozen=True)
class Pole:
    """The instantaneous spin axis (positive pole, right-hand rule) in the ICRF at ``epoch_jd_tdb``."""

    ra_deg: float
    dec_deg: float
    epoch_jd_tdb: float = J2000_JD
    body: str | None = field(default=None, compare=False)

    def __post_init__(self):
        for name in ("ra_deg", "dec_deg", "epoch_jd_tdb"):
            check_finite(self.body, f"pole.{name}", getattr(self, name))
        check_angle(self.body, "pole.ra_deg", self.ra_deg)
        _check_epoch(self.body, "pole.epoch_jd_tdb", self.epoch_jd_tdb)
        if abs(self.dec_deg) > 90.0:
            raise InvalidInputError("pole.dec_deg", f"declination must lie in [-90, 90] deg, got {self.dec_deg}", self.body)

    @classmethod
    def from_ecliptic(cls, lon_deg: float, lat_deg: float, epoch_jd_tdb: float = J2000_JD,
                      body: str | None = None) -> Pole:
        """The pole at ecliptic (J2000) longitude and latitude ``lon_deg``, ``lat_deg``, in the ICRF (the
        obliquity of a pole on an orbit in the ecliptic is 90° - latitude)."""

        check_angle(body, "pole.lon", lon_deg)        # before the rotation turns it into another angle
        ra, dec = lon_lat(ecliptic_to_icrf(math.radians(lon_deg), math.radians(lat_deg)))
        return cls(math.degrees(float(ra)), math.degrees(float(dec)), epoch_jd_tdb, body=body)


@dataclass(frozen=True)
class Body:
    """Everything the theory needs about one body.

    Either ``moments`` (A, B, C in any common normalisation) or
    ``dynamical_ellipticity`` must be given; if both are, the explicit H_d
    wins (``hd_from`` says which was used).
    """

    name: str
    orbit: Orbit
    pole: Pole
    rotation_period_hours: float
    moments: tuple[float, float, float] | None = None
    dynamical_ellipticity: float | None = None
    naif_id: int | None = None
    kind: str = "asteroid"
    dataset: str = "user"
    mean_radius_km: float | None = None
    values: dict = field(default_factory=dict, compare=False, repr=False)
    #: {(input key, input key): ρ}: the correlations of the values' errors, as the sources give them
    #: (``[[body.correlation]]``) or as a derivation implies them (moments from one polar moment, ephem.bodies.inertia)
    correlations: dict = field(default_factory=dict, compare=False, repr=False)
    #: The bodies whose torque moves the spin axis (canonical names, :data:`KNOWN_PERTURBERS`);
    #: None: the orbit's centre alone. Another perturber where data/centres.toml admits it (the Moon: the Earth's).
    perturbers: tuple[str, ...] | None = None

    def __hash__(self) -> int:
        # the dataclass's hash of the compared fields, computed once: every per-body cache (ephem.base.memo) hashes
        # the body on each look-up, and hashing the nested orbit and pole records took ~50 us a time
        h = self.__dict__.get("_hash")
        if h is None:
            h = hash(tuple(getattr(self, f.name) for f in fields(self) if f.compare))
            object.__setattr__(self, "_hash", h)
        return h

    @property
    def sigma_key(self) -> tuple:
        """The values' 1-σ (each with its value and unit) and their correlations, as one hashable tuple, made once.
        A body's equality and hash leave its ``values`` out (they describe, with sources and notes, what the compared
        fields hold), so a cache of what the σ decide (the propagated uncertainties, the pole's 1-σ) keys on this
        beside the body: two bodies that differ in a σ alone must not share an entry."""
        k = self.__dict__.get("_sigma_key")
        if k is None:
            k = (tuple(sorted((name, getattr(m, "value", None), getattr(m, "unit", None), getattr(m, "uncertainty", None))
                              for name, m in self.values.items())),
                 tuple(sorted(self.correlations.items())))
            object.__setattr__(self, "_sigma_key", k)
        return k

    def with_sigmas(self, *rest) -> tuple:
        """The key of a cache of what the body's σ decide: ``(body, sigma_key, *rest)``. The σ caches key by it and
        the predictors ask them by it (``ephem.theory.cost.kept``), so the two cannot drift apart."""
        return (self, self.sigma_key, *rest)

    def __getstate__(self) -> dict:
        # the kept hash is of this process's string hashing (PYTHONHASHSEED): a pickled body (a Dask task's)
        # computes its own
        state = dict(self.__dict__)
        state.pop("_hash", None)
        return state

    def __post_init__(self):
        
        n = self.name
        object.__setattr__(self, "perturbers", resolve_perturbers(self.perturbers, self))
        check_finite(n, "rotation_period_hours", self.rotation_period_hours)
        if self.rotation_period_hours < MIN_ROTATION_PERIOD_HOURS:
            raise InvalidInputError("rotation_period_hours",
                                    f"must be at least {MIN_ROTATION_PERIOD_HOURS:g} h (0.36 s; the fastest known "
                                    f"rotator, 2020 HS7, turns in 2.99 s), got {self.rotation_period_hours}", n)
        if self.mean_radius_km is not None:
            check_finite(n, "mean_radius_km", self.mean_radius_km)
            if self.mean_radius_km <= 0:
                raise InvalidInputError("mean_radius_km", f"must be positive, got {self.mean_radius_km}", n)
        if self.moments is None and self.dynamical_ellipticity is None:
            raise InvalidInputError("moments", "give the principal moments (A, B, C) or the dynamical ellipticity", n)
        hd_moments = None
        if self.moments is not None:
            if len(self.moments) != 3:
                raise InvalidInputError("moments", "expected three principal moments (A, B, C)", n)
            for label, v in zip("ABC", self.moments):
                check_finite(n, f"moments.{label}", v)
            hd_moments = dynamical_ellipticity(*self.moments, body=n)
        if self.dynamical_ellipticity is not None:
            check_finite(n, "dynamical_ellipticity", self.dynamical_ellipticity)
            if not 0.0 < self.dynamical_ellipticity <= 0.5:
                raise InvalidInputError(
                    "dynamical_ellipticity",
                    f"must lie in (0, 0.5] (oblate about the spin axis, C >= (A+B)/2 and C <= A+B), "
                    f"got {self.dynamical_ellipticity}", n)
        object.__setattr__(self, "_hd_moments", hd_moments)

    @property
    def hd(self) -> float:
        """The dynamical ellipticity H_d the theory uses."""
        return self.dynamical_ellipticity if self.dynamical_ellipticity is not None else self._hd_moments

    @property
    def spin_rate_rad_per_day(self) -> float:
        """ω = 2π / P (rad/day) of the rotation period (:func:`spin_rate_rad_per_day`)."""
        return spin_rate_rad_per_day(self.rotation_period_hours)

    @property
    def hd_from(self) -> str:
        return "dynamical_ellipticity" if self.dynamical_ellipticity is not None else "moments"

    @property
    def hd_from_moments(self) -> float | None:
        """H_d implied by the moments, whether or not an explicit value overrides it."""
        return self._hd_moments


def is_earth(body: Body) -> bool:
    """The Earth (by name or NAIF id 399): the body the lunisolar model is wired to (data/centres.toml admits the
    Moon as its perturber)."""
    return body.naif_id == 399 or body.name.strip().lower() == "earth"


#: A synchronous rotator: the spin rate within this fraction of the orbital mean motion.
SYNCHRONOUS_TOLERANCE = 0.01


def is_synchronous(body: Body, perturbers: tuple[str, ...]) -> bool:
    """A synchronous rotator (ω/n within :data:`SYNCHRONOUS_TOLERANCE` of 1) torqued by its orbit's centre, among
    others: what the Moon's Cassini-state theory serves (the Sun's torque on a satellite is in that theory)."""
    o = body.orbit
    ratio = body.spin_rate_rad_per_day / mean_motion_rad_per_day(o.a_au, o.center)
    return abs(ratio - 1.0) <= SYNCHRONOUS_TOLERANCE and o.center in perturbers


def is_lunisolar(body: Body, perturbers: tuple[str, ...]) -> bool:
    """The Moon among the perturbers (only the Earth may name it): what the Earth's lunisolar theory serves."""
    return "Moon" in perturbers


def is_centre_alone(body: Body, perturbers: tuple[str, ...]) -> bool:
    """The centre of the body's orbit the one perturber: what the single-perturber ladder serves."""
    return tuple(perturbers) == (body.orbit.center,)


def resolve_perturbers(value, body: Body) -> tuple[str, ...]:
    """Validated perturbers of ``body``: None (the orbit's centre), a name, a comma-separated string
    ("moon,sun") or a list of names, any case. Canonical names, in the order given.

    Unknown or repeated names raise :class:`InvalidInputError` (field ``perturbers``); a known body
    the theory cannot take as a perturber of this one raises :class:`NotApplicableError`: the
    single-perturber theory is torqued by the orbit's centre, and another perturber acts on the bodies
    data/centres.toml admits it for (:func:`ephem.base.centres.admissions`: the Moon on the Earth,
    :mod:`ephem.earth.lunisolar`).
    """
    centre = body.orbit.center
    if value is None:
        return (centre,)
    if isinstance(value, str):
        names = [v.strip() for v in value.split(",")]
    elif isinstance(value, (list, tuple)):
        names = list(value)
    else:
        raise InvalidInputError("perturbers", f"expected a name, a comma-separated list or a list of names, "
                                f"got {value!r}", body.name)
    canonical = {p.lower(): p for p in KNOWN_PERTURBERS}
    out = []
    for name in names:
        if not isinstance(name, str) or name.strip().lower() not in canonical:
            raise InvalidInputError("perturbers", f"unknown perturber {name!r}; known: {', '.join(KNOWN_PERTURBERS)}",
                                    body.name)
        p = canonical[name.strip().lower()]
        if p in out:
            raise InvalidInputError("perturbers", f"{p} is listed twice", body.name)
        out.append(p)
    if not out:
        raise InvalidInputError("perturbers", "give at least one perturber", body.name)
    rules = admissions()
    for p in out:
        if p == centre:
            continue
        own = [a for a in rules if a.perturber == p]
        if any(a.admits(body.name, body.naif_id, centre) for a in own):
            continue
        if own:
            where = " and ".join(dict.fromkeys(_admitted(a) for a in own))
            raise NotApplicableError(body.name, f"the {p} as a perturber is modelled for {where} only "
                                     f"({'; '.join(dict.fromkeys(a.theory for a in own))}); the single-perturber "
                                     f"theory takes its torque from the orbit's centre, the {centre}")
        others = "; ".join(dict.fromkeys(f"{_named(a.perturber)} on {_admitted(a)}" for a in rules))
        raise NotApplicableError(body.name, f"{p} is not the orbit's centre ({centre}): the single-perturber "
                                 "theory takes its torque from the orbit's centre, and a second perturber acts only "
                                 f"where data/centres.toml admits it: {others or 'nowhere'}")
    return tuple(out)


def _named(name: str) -> str:
    """A centre's or a perturber's name with its article ("the Earth"), a body's without ("Itokawa")."""
    return f"the {name}" if name in KNOWN_PERTURBERS else name


def _admitted(admission) -> str:
    """The bodies an admission of a perturber names ("the Earth", "the bodies about the Sun"), for a refusal."""
    return _named(admission.body) if admission.body else f"the bodies about {_named(admission.center)}"


# --------------------------------------------------------------------------- loading

def _body_from_record(rec: dict, dataset: str) -> Body:
    name = rec.get("name")
    if not name:
        raise InvalidInputError("name", "every body record needs a name", None)
    values: dict[str, Measured] = {}

    def get(section: str, key: str, target: str, required: bool = True) -> float | None:
        sec = rec.get(section, {}) if section else rec
        if key not in sec:
            if required:
                raise InvalidInputError(f"{section}.{key}" if section else key, "missing", name)
            return None
        where = f"{section}.{key}" if section else key
        # a section's reason is for its measured values: an epoch is a definition
        reason = section_reason(sec, section, name) if section and key != "epoch" else None
        m = measured(sec[key], where, name, reason)
        values[where] = m
        return convert(m, target, where, name)

    orbit_rec = rec.get("orbit", {})
    orbit = Orbit(
        a_au=get("orbit", "a", "AU"), e=get("orbit", "e", ""), i_deg=get("orbit", "i", "deg"),
        node_deg=get("orbit", "node", "deg"), peri_deg=get("orbit", "peri", "deg"),
        mean_anomaly_deg=get("orbit", "mean_anomaly", "deg"), epoch_jd_tdb=get("orbit", "epoch", "d"),
        center=orbit_rec.get("center", "Sun"), node_rate_deg_per_year=get("orbit", "node_rate", "deg/yr", required=False),
        frame=orbit_rec.get("frame", "ecliptic_j2000"), theory=orbit_rec.get("theory"), body=name)

    pole_rec = rec.get("pole", {})
    frame = pole_rec.get("frame", "icrf")
    epoch = get("pole", "epoch", "d", required=False) or J2000_JD
    if frame == "icrf":
        pole = Pole(get("pole", "ra", "deg"), get("pole", "dec", "deg"), epoch, body=name)
    elif frame == "ecliptic_j2000":
        lon, lat = get("pole", "lon", "deg"), get("pole", "lat", "deg")
        if abs(lat) > 90:
            raise InvalidInputError("pole.lat", f"latitude must lie in [-90, 90] deg, got {lat}", name)
        pole = Pole.from_ecliptic(lon, lat, epoch, body=name)
    else:
        raise InvalidInputError("pole.frame", f"must be 'icrf' or 'ecliptic_j2000', got {frame!r}", name)

    period_h = rotation_period(rec.get("rotation", {}), values, name, get)
    inertia = rec.get("inertia", {})
    moments = None
    correlations: dict[tuple[str, str], float] = {}
    if "derived_from" in inertia:
        if any(k in inertia for k in "ABC"):
            raise InvalidInputError("inertia", "give the moments A, B, C or inertia.derived_from, not both", name)
        moments = derived_moments(inertia["derived_from"], values, correlations, name)
    elif all(k in inertia for k in "ABC"):
        units = {inertia[k].get("unit", "") for k in "ABC" if isinstance(inertia[k], dict)}
        if len(units) != 1:
            raise InvalidInputError("inertia", f"A, B and C must share one unit, got {sorted(units)}", name)
        unit = units.pop()
        moments = tuple(get("inertia", k, unit) for k in "ABC")
    elif any(k in inertia for k in "ABC"):
        raise InvalidInputError("inertia", "give all three of A, B, C or none", name)
    hd = get("inertia", "dynamical_ellipticity", "", required=False)
    radius = get("", "mean_radius", "km", required=False)
    naif = rec.get("naif_id")
    perturbers = rec.get("perturbers")
    if perturbers is not None and not isinstance(perturbers, list):
        raise InvalidInputError("perturbers", f"expected a list of names, got {perturbers!r}", name)
    correlations.update(stated_correlations(rec.get("correlation", []), values, name))
    return Body(name=name, orbit=orbit, pole=pole, rotation_period_hours=period_h, moments=moments,
                dynamical_ellipticity=hd, naif_id=None if naif is None else int(naif),
                kind=rec.get("kind", "asteroid"), dataset=dataset, mean_radius_km=radius, values=values,
                correlations=correlations, perturbers=None if perturbers is None else tuple(perturbers))


@dataclass(frozen=True)
class Catalogue:
    """One dataset of bodies, looked up by case-insensitive name or NAIF id."""

    name: str
    description: str
    bodies: tuple[Body, ...]

    @property
    def names(self) -> list[str]:
        return [b.name for b in self.bodies]

    def get(self, query: str | int) -> Body:
        q = str(query).strip()
        for b in self.bodies:
            if b.name.lower() == q.lower() or (b.naif_id is not None and q == str(b.naif_id)):
                return b
        raise UnknownBodyError(str(query), self.names)


def parse_catalogue(text: str, dataset: str) -> Catalogue:
    """Parse and validate a catalogue TOML document."""
    doc = parse_toml(text, f"catalogue_{dataset}")
    meta = doc.get("dataset", {})
    bodies = tuple(_body_from_record(rec, dataset) for rec in doc.get("body", []))
    names = [b.name.lower() for b in bodies]
    if len(set(names)) != len(names):
        raise InvalidInputError("name", f"duplicate body names in dataset {dataset!r}", None)
    return Catalogue(dataset, meta.get("description", ""), bodies)


@lru_cache(maxsize=None)
def _load_catalogue_file(path: str, dataset: str, mtime_ns: int, size: int) -> Catalogue:
    """Parse a dataset file once per version of it (the key holds its modification time and size)."""
    try:
        text = Path(path).read_text(encoding="utf-8")
        return parse_catalogue(text, dataset)
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InvalidInputError("dataset", f"cannot read dataset {dataset!r} ({path}): {exc}") from None


def load_catalogue(dataset: str = DEFAULT_DATASET) -> Catalogue:
    """Load (once per version of its file) and validate a dataset: a shipped one, "current" (default) or
    "petit2014", or one the user imported (``ephem catalogue import``, in
    :func:`ephem.bodies.datasets.user_catalogue_dir`).

    The parsed catalogue is cached under the file's path, modification time and size, so a dataset imported
    or replaced after the first call is seen by the next one; ``load_catalogue.cache_clear()`` empties the cache.

    Parameters
    ----------
    dataset : str
        The dataset's name: a shipped one (:func:`ephem.bodies.datasets.available_datasets`) or an imported one.

    Returns
    -------
    Catalogue
        The dataset's name, description and bodies (:class:`Body` records, looked up by name or NAIF id).
    """
    path = dataset_file(dataset)
    try:
        st = path.stat() if path is not None else None
    except OSError:
        st = None
    if st is None:
        known = available_datasets()
        raise InvalidInputError("dataset", f"unknown dataset {dataset!r}; known: {', '.join(known)}")
    return _load_catalogue_file(str(path), dataset, st.st_mtime_ns, st.st_size)


load_catalogue.cache_clear = _load_catalogue_file.cache_clear


@lru_cache(maxsize=1)
def load_references() -> dict:
    """The references file: source key -> {authors, year, title, journal, where, …}."""
    return read_toml(data_dir() / "references.toml")


def get_body(query: str | int, dataset: str = DEFAULT_DATASET) -> Body:
    """A catalogue body by case-insensitive name or NAIF id (2000004 = Vesta).

    Parameters
    ----------
    query : str or int
        The body's name (any case) or NAIF id.
    dataset : str
        The dataset to look in: "current" (default), "petit2014" or one the user imported.

    Returns
    -------
    Body
        The body's record: orbit (a in au, angles in degrees), pole (RA and Dec in degrees, ICRF), rotation period
        (hours) and moments, each value with its unit, 1-sigma and source. :class:`UnknownBodyError` names the known
        ones when there is none.
    """
    return load_catalogue(dataset).get(query)


def resolve_body(body: "str | int | Body", dataset: str = DEFAULT_DATASET) -> Body:
    """``body`` itself if it is a :class:`Body` (a user's own), else the catalogue's by name or NAIF id.

    Parameters
    ----------
    body : str, int or Body
        A body's name (any case) or NAIF id, or a :class:`Body` (returned as it is).
    dataset : str
        The dataset a name or id is looked up in.

    Returns
    -------
    Body
        The body's record (see :func:`get_body`).
    """
    return body if isinstance(body, Body) else get_body(body, dataset)
