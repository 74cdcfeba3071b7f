"""The centres an orbit may name and the perturbers a body may name, read from data/centres.toml on first use.

A centre's gravitational parameter (m^3 s^-2: the mean motion, the geodesic precession), its radius and its Hill
radius (AU: the bounds of an orbit about it) are :data:`GM_CENTER`, :data:`CENTER_RADIUS_AU` and
:data:`CENTER_HILL_AU`; :data:`KNOWN_PERTURBERS` names the centres, then the other perturbers, and
:func:`admissions` says which bodies a perturber other than their orbit's centre may torque (read by
``ephem.bodies.catalogue.resolve_perturbers``). Each is a live view of one table: the shipped file is read when
one is first used, and :func:`register_centres` adds a file of the same form (a family's own, from outside the
library: a binary asteroid's primary and the Sun as its secondary's second perturber), so that a new centre or
perturber is data, not code.

Every value is a table ``{ value, unit, source }`` as in the catalogue (data/catalogue/SCHEMA.md), its source a key
of data/references.toml. The module imports nothing of the library: it sits under the orbit's Kepler, at the foot
of the longest import chains (tests/house/test_layers.py), so it finds the data directory as
``ephem.base.paths.data_dir`` does ($EPHEM_DATA_DIR, else the shipped copy; tests/base/test_centres.py holds the
two equal) and converts units by its own short table, which keeps the shipped values the very doubles the
constants were (695 700 km / 149 597 870.7 km per AU).
"""
from __future__ import annotations

import dataclasses
import os
import threading
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

#: kilometres per astronomical unit (IAU 2012 Resolution B2: 149 597 870 700 m)
AU_KM = 149_597_870.7
#: the units a centre's values may take: each unit's factor to the table's (m^3 s^-2 for ``gm``, AU for lengths),
#: or the divisor ``("per", x)`` where the value is divided (km -> AU: value / AU_KM, the constants' own division)
_UNITS = {"gm": {"m3 / s2": 1.0, "km3 / s2": 1e9},
          "length": {"AU": 1.0, "km": ("per", AU_KM), "m": ("per", AU_KM * 1000.0)}}
#: the file of the shipped centres, in the data directory
CENTRES_FILE = "centres.toml"


@dataclass(frozen=True)
class Centre:
    """A body an orbit may be centred on: its gravitational parameter ``gm_m3_s2`` (m^3 s^-2), its radius and its
    Hill radius (AU), the published values they came from (``values``: key -> {value, unit, source, ...}) and the
    file that gave it."""

    name: str
    gm_m3_s2: float
    radius_au: float
    hill_au: float
    values: dict
    origin: str


@dataclass(frozen=True)
class Admission:
    """A perturber other than a body's orbit's centre, admitted for the bodies on an orbit about ``center`` named
    ``body`` (any case) or numbered ``naif_id`` (neither: every body about ``center``); ``theory`` names what models
    its torque (the refusal of another body says it)."""

    perturber: str
    center: str
    body: str | None
    naif_id: int | None
    theory: str
    origin: str

    def admits(self, name: str, naif_id: int | None, center: str) -> bool:
        """Whether a body named ``name`` (NAIF id ``naif_id``) on an orbit about ``center`` may feel the perturber."""
        if center != self.center:
            return False
        if self.body is None and self.naif_id is None:
            return True
        return (self.naif_id is not None and naif_id == self.naif_id) or \
            (self.body is not None and name.strip().lower() == self.body.lower())


_LOCK = threading.Lock()
_CENTRES: dict[str, Centre] = {}
_ADMISSIONS: list[Admission] = []
_LOADED = False
#: every centre this process has known, by its name in lower case -> (GM, radius, Hill radius): the caches of per-body
#: work are keyed by the body, not by its centre's values, so a centre taken out may come back only as it was
_EVER: dict[str, tuple[float, float, float]] = {}


def data_file() -> Path:
    """The shipped centres' file: ``centres.toml`` in ``$EPHEM_DATA_DIR``, else in the installed wheel's
    ``ephem/_data`` or the repository's ``data/`` (where ``ephem.base.paths.data_dir`` looks)."""
    env = os.environ.get("EPHEM_DATA_DIR")
    if env:
        return Path(env) / CENTRES_FILE
    here = Path(__file__).resolve().parent.parent
    for candidate in (here / "_data", here.parent / "data"):
        if (candidate / "catalogue").is_dir():
            return candidate / CENTRES_FILE
    raise FileNotFoundError("ephem data directory not found (set EPHEM_DATA_DIR)")


def _value(rec: dict, key: str, kind: str, where: str) -> float:
    """``rec[key]``, a ``{value, unit, source}`` table, in the table's unit (:data:`_UNITS`); ValueError naming it."""
    v = rec.get(key)
    if not isinstance(v, dict) or not {"value", "unit", "source"} <= v.keys():
        raise ValueError(f"{where}.{key}: expected a table {{ value, unit, source }}, got {v!r}")
    value, unit = v["value"], v["unit"]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.0 < float(value) < float("inf"):
        raise ValueError(f"{where}.{key}: the value must be a positive finite number, got {value!r}")
    factor = _UNITS[kind].get(unit)
    if factor is None:
        raise ValueError(f"{where}.{key}: unit {unit!r} is not one of {', '.join(map(repr, _UNITS[kind]))}")
    return float(value) / factor[1] if isinstance(factor, tuple) else float(value) * factor


def parse_centres(text: str, origin: str) -> tuple[list[Centre], list[Admission]]:
    """The centres and the perturbers' admissions of a TOML document of data/centres.toml's form; ValueError
    naming the file and the entry's field when one is wrong."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{origin}: {exc}") from None
    unknown = set(doc) - {"centre", "perturber"}
    if unknown:
        raise ValueError(f"{origin}: unknown tables {sorted(unknown)}; expected [[centre]] and [[perturber]]")
    centres = []
    for k, rec in enumerate(doc.get("centre", [])):
        name = rec.get("name")
        where = f"{origin}: centre {name or k!r}"
        if not isinstance(name, str) or not name.strip():
            raise ValueError(f"{where}: every centre needs a name")
        radius, hill = _value(rec, "radius", "length", where), _value(rec, "hill", "length", where)
        if hill <= radius:
            raise ValueError(f"{where}: the Hill radius ({hill:.6g} AU) must exceed the radius ({radius:.6g} AU)")
        centres.append(Centre(name, _value(rec, "gm", "gm", where), radius, hill,
                              {key: dict(rec[key]) for key in ("gm", "radius", "hill")}, origin))
    admissions = []
    for k, rec in enumerate(doc.get("perturber", [])):
        name = rec.get("name")
        where = f"{origin}: perturber {name or k!r}"
        if not isinstance(name, str) or not name.strip():
            raise ValueError(f"{where}: every perturber needs a name")
        theory, torques = rec.get("theory"), rec.get("torques")
        if not isinstance(theory, str) or not theory.strip():
            raise ValueError(f"{where}: say which theory models its torque (theory = \"...\")")
        if not isinstance(torques, list) or not torques:
            raise ValueError(f"{where}: list the bodies it torques (torques = [{{ body, naif_id, center }}, ...])")
        for t in torques:
            if not isinstance(t, dict) or not isinstance(t.get("center"), str) or set(t) - {"body", "naif_id",
                                                                                           "center"}:
                raise ValueError(f"{where}.torques: each is {{ center = \"...\" }} with an optional body and "
                                 f"naif_id, got {t!r}")
            naif = t.get("naif_id")
            if naif is not None and (isinstance(naif, bool) or not isinstance(naif, int)):
                raise ValueError(f"{where}.torques: naif_id must be an integer, got {naif!r}")
            admissions.append(Admission(name, t["center"], t.get("body"), naif, theory, origin))
    return centres, admissions


def _add(centres: list[Centre], admissions: list[Admission]) -> tuple[str, ...]:
    """Add to the tables (under the lock), refusing a centre known already and a torque about no known centre; the
    names added (the centres, then the perturbers, as the tables spell them)."""
    known = {c.lower() for c in _CENTRES}
    for c in centres:
        if c.name.lower() in known:
            raise ValueError(f"{c.origin}: centre {c.name!r} is known already ({_CENTRES.get(c.name, c).origin})")
        before = _EVER.get(c.name.lower())
        if before is not None and before != (c.gm_m3_s2, c.radius_au, c.hill_au):
            raise ValueError(f"{c.origin}: centre {c.name!r} was known to this process with other values (GM, "
                             "radius or Hill radius); answers computed with those may be cached: give it another "
                             "name, or start a new process")
        known.add(c.name.lower())
    names = {c.lower(): c for c in [*_CENTRES, *(c.name for c in centres)]}
    for a in admissions:
        if a.center.lower() not in names:
            raise ValueError(f"{a.origin}: perturber {a.perturber!r} torques bodies about {a.center!r}, which is "
                             f"no known centre ({', '.join(names.values())})")
    # a name written in another case is the known one (the orbit's centre and the perturbers are matched as spelt)
    perturbers = {**names, **{p.lower(): p for p in dict.fromkeys(a.perturber for a in _ADMISSIONS)}}
    admissions = [dataclasses.replace(a, center=names[a.center.lower()],
                                      perturber=perturbers.setdefault(a.perturber.lower(), a.perturber))
                  for a in admissions]
    _CENTRES.update({c.name: c for c in centres})
    _EVER.update({c.name.lower(): (c.gm_m3_s2, c.radius_au, c.hill_au) for c in centres})
    _ADMISSIONS.extend(admissions)
    return tuple(dict.fromkeys([*(c.name for c in centres), *(a.perturber for a in admissions)]))


def _load() -> None:
    """Read the shipped file once (the first use of any table)."""
    global _LOADED
    with _LOCK:
        if not _LOADED:
            path = data_file()
            _add(*parse_centres(path.read_text(encoding="utf-8"), str(path)))
            _LOADED = True


def centres() -> dict[str, Centre]:
    """The known centres, name -> :class:`Centre` (the shipped ones first, in their file's order)."""
    if not _LOADED:
        _load()
    return _CENTRES


def admissions() -> tuple[Admission, ...]:
    """The perturbers other than an orbit's centre and the bodies each may torque (:class:`Admission`)."""
    if not _LOADED:
        _load()
    return tuple(_ADMISSIONS)


def register_centres(path: str | os.PathLike) -> tuple[str, ...]:
    """Add the centres and the perturbers of a TOML file of data/centres.toml's form (a family's own data, from
    outside the library): a body may then orbit its centres, and feel its perturbers where it admits them.

    Parameters
    ----------
    path : str or path-like
        The file: ``[[centre]]`` entries (name; gm, radius, hill as ``{ value, unit, source }``) and
        ``[[perturber]]`` entries (name, theory, torques), data/catalogue/SCHEMA.md.

    Returns
    -------
    tuple of str
        The names of the centres and perturbers it added (:func:`unregister_centres` takes the file out again). A
        centre known already (or known earlier in this process with other values: its answers may be cached),
        a torque about no known centre or a malformed value raises ValueError naming the
        file and the field, and adds nothing.
    """
    path = Path(path)
    if str(path) in {c.origin for c in centres().values()} | {a.origin for a in admissions()}:
        raise ValueError(f"{path} is registered already")
    found = parse_centres(path.read_text(encoding="utf-8"), str(path))
    with _LOCK:
        return _add(*found)


def unregister_centres(path: str | os.PathLike) -> None:
    """Take out what :func:`register_centres` added from the file ``path``: its centres and its perturbers'
    admissions (the shipped file's stay: ValueError).

    Parameters
    ----------
    path : str or path-like
        The file :func:`register_centres` was given.

    Returns
    -------
    None
        The tables no longer hold that file's centres and perturbers (a file never registered changes nothing).
    """
    origin = str(Path(path))
    if origin == str(data_file()):
        raise ValueError(f"{origin} holds the shipped centres: they cannot be taken out")
    with _LOCK:
        for name in [name for name, c in _CENTRES.items() if c.origin == origin]:
            del _CENTRES[name]
        _ADMISSIONS[:] = [a for a in _ADMISSIONS if a.origin != origin]


class _Column(Mapping):
    """One value of every known centre, by the centre's name (a live, read-only view of :func:`centres`)."""

    def __init__(self, attribute: str, doc: str):
        self._attribute = attribute
        self.__doc__ = doc

    def __getitem__(self, name: str) -> float:
        return getattr((_CENTRES if _LOADED else centres())[name], self._attribute)

    def __iter__(self):
        return iter(list(centres()))

    def __len__(self) -> int:
        return len(centres())

    def __repr__(self) -> str:
        return repr(dict(self))


class _Perturbers(Sequence):
    """The names a body's ``perturbers`` may take: the centres, then the other perturbers (a live view)."""

    def _names(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys([*centres(), *(a.perturber for a in admissions())]))

    def __getitem__(self, index):
        return self._names()[index]

    def __len__(self) -> int:
        return len(self._names())

    def __iter__(self):
        return iter(self._names())

    def __contains__(self, name) -> bool:
        return name in self._names()

    def __eq__(self, other) -> bool:
        return isinstance(other, Sequence) and tuple(self) == tuple(other)

    __hash__ = None

    def __repr__(self) -> str:
        return repr(self._names())


#: Gravitational parameter of each orbit centre the catalogue may name, m^3 s^-2 (data/centres.toml: the Sun's
#: and the Earth's IAU 2015 Resolution B3 nominal values).
GM_CENTER = _Column("gm_m3_s2", "GM of each centre, m^3 s^-2")
#: Radius of each orbit centre, AU: a pericentre inside it is no orbit (the Sun: IAU 2015 Resolution B3's nominal
#: radius, 695 700 km; the Earth: its equatorial radius, 6378.1366 km, IERS Conventions 2010).
CENTER_RADIUS_AU = _Column("radius_au", "radius of each centre, AU")
#: Largest semi-major axis of a bound orbit about each centre, AU: the centre's Hill sphere, beyond which another
#: body's pull dominates (the Sun in the Galactic tide: ~2.3e5 AU; the Earth under the Sun: 0.0100 AU).
CENTER_HILL_AU = _Column("hill_au", "Hill radius of each centre, AU")
#: Bodies that may torque a body (the ``perturbers`` of a record): an orbit's centre, or a perturber admitted for
#: it (the Moon, for the Earth only: :mod:`ephem.earth.lunisolar`).
KNOWN_PERTURBERS = _Perturbers()
