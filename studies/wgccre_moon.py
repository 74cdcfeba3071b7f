"""The IAU WGCCRE model of the lunar pole and prime meridian, as NAIF's pck00011.tpc has it (the 2009 report's
series, Archinal et al. 2011, which the 2015 report dropped and NAIF kept): data/wgccre/moon_pck00011.toml.

A study's helper, not the library (see :mod:`studies`): :mod:`studies.moon` compares the Moon's pole with it and
tests/moon/test_against_wgccre_moon.py checks it against its printed values and CSPICE. With ``d`` days and ``T``
Julian centuries (36525 d) of TDB from J2000 (JD 2451545.0 TDB), degrees, ICRF:

    α0 = a0 + a1 T + a2 T² + Σ_i A_i sin E_i
    δ0 = b0 + b1 T + b2 T² + Σ_i B_i cos E_i
    W  = w0 + w1 d + w2 d² + Σ_i C_i sin E_i,        E_i = e0_i + e1_i T   (i = 1 … 13)

as SPICE evaluates a text PCK (the E rates per century, NAIF's scaling of the report's per-day rates). Every
function takes an array of JD TDB and is vectorised over it; angles come out in degrees (the API's unit),
vectors as unit vectors in the ICRF, and the E arguments (an internal quantity) in radians.
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

#: The data file (the project's data/ directory, next to this package's parent).
DATA = Path(__file__).resolve().parents[1] / "data" / "wgccre" / "moon_pck00011.toml"
J2000_JD = 2451545.0
DAYS_PER_CENTURY = 36525.0
#: The E arguments' names, in the file's order.
E_NAMES = tuple(f"E{i}" for i in range(1, 14))


@dataclass(frozen=True)
class MoonModel:
    """The file's numbers as arrays (degrees; the T rates per century, the d rates per day)."""

    pole_ra: np.ndarray          # (3,) deg, deg/cy, deg/cy²
    pole_dec: np.ndarray         # (3,)
    pm: np.ndarray               # (3,) deg, deg/d, deg/d²
    nut_prec_ra: np.ndarray      # (13,) deg, on sin E_i
    nut_prec_dec: np.ndarray     # (13,) deg, on cos E_i
    nut_prec_pm: np.ndarray      # (13,) deg, on sin E_i
    angles: np.ndarray           # (13, 2) deg, deg/cy
    source: dict


@lru_cache(maxsize=4)
def load(path: Path = DATA) -> MoonModel:
    with open(path, "rb") as fh:
        raw = tomllib.load(fh)
    m, em = raw["moon"], raw["earth_moon"]
    arr = lambda key, src=m: np.asarray(src[key], dtype=float)  # noqa: E731
    return MoonModel(arr("pole_ra"), arr("pole_dec"), arr("pm"), arr("nut_prec_ra"), arr("nut_prec_dec"),
                     arr("nut_prec_pm"), arr("nut_prec_angles", em), dict(raw["source"]))


def _days(jd_tdb) -> np.ndarray:
    return np.asarray(jd_tdb, dtype=float) - J2000_JD


def e_arguments(jd_tdb, model: MoonModel | None = None) -> np.ndarray:
    """E1 … E13 (radians), shape (13, *jd.shape): E_i = e0_i + e1_i T, T in Julian centuries of TDB."""
    model = model or load()
    t = _days(jd_tdb) / DAYS_PER_CENTURY
    deg = model.angles[:, :1].reshape((13,) + (1,) * t.ndim) \
        + model.angles[:, 1:].reshape((13,) + (1,) * t.ndim) * t
    return np.radians(np.mod(deg, 360.0))


def elements_deg(jd_tdb, model: MoonModel | None = None, terms=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(α0, δ0, W) in degrees at the epochs (W reduced to [0, 360)).

    ``terms``: the E terms to include, as 1-based indices (default all thirteen; ``()`` the polynomials alone),
    for the decomposition of :mod:`studies.moon`."""
    model = model or load()
    d = _days(jd_tdb)
    t = d / DAYS_PER_CENTURY
    e = e_arguments(jd_tdb, model)
    keep = np.zeros(13, dtype=bool)
    keep[[i - 1 for i in (range(1, 14) if terms is None else terms)]] = True
    k = keep.reshape((13,) + (1,) * d.ndim)
    s, c = np.where(k, np.sin(e), 0.0), np.where(k, np.cos(e), 0.0)
    cf = lambda v: v.reshape((13,) + (1,) * d.ndim)  # noqa: E731
    ra = model.pole_ra[0] + t * (model.pole_ra[1] + t * model.pole_ra[2]) + np.sum(cf(model.nut_prec_ra) * s, axis=0)
    dec = model.pole_dec[0] + t * (model.pole_dec[1] + t * model.pole_dec[2]) \
        + np.sum(cf(model.nut_prec_dec) * c, axis=0)
    # the day rate reduced before it is added (d up to 1e5 days: 1.3e6 deg, whose last bit is 2e-10 deg)
    w = model.pm[0] + np.mod(model.pm[1] * d, 360.0) + model.pm[2] * d * d \
        + np.sum(cf(model.nut_prec_pm) * s, axis=0)
    return ra, dec, np.mod(w, 360.0)


def unit_vectors(ra_deg, dec_deg) -> np.ndarray:
    """Unit vectors (…, 3) in the ICRF from right ascension and declination in degrees."""
    a, d = np.radians(np.asarray(ra_deg, dtype=float)), np.radians(np.asarray(dec_deg, dtype=float))
    return np.stack((np.cos(d) * np.cos(a), np.cos(d) * np.sin(a), np.sin(d)), axis=-1)


def pole_vectors(jd_tdb, model: MoonModel | None = None, terms=None) -> np.ndarray:
    """The IAU pole as ICRF unit vectors, shape (*jd.shape, 3)."""
    ra, dec, _ = elements_deg(jd_tdb, model, terms)
    return unit_vectors(ra, dec)


def body_matrix(jd_tdb, model: MoonModel | None = None) -> np.ndarray:
    """ICRF → IAU_MOON rotation matrices (…, 3, 3): R3(W) R1(90° − δ0) R3(90° + α0), as SPICE's TISBOD."""
    ra, dec, w = (np.radians(x) for x in elements_deg(jd_tdb, model))
    return _r3(w) @ _r1(np.pi / 2 - dec) @ _r3(np.pi / 2 + ra)


def _r1(a):
    c, s, o, z = np.cos(a), np.sin(a), np.ones_like(a), np.zeros_like(a)
    return np.stack((np.stack((o, z, z), -1), np.stack((z, c, s), -1), np.stack((z, -s, c), -1)), -2)


def _r3(a):
    c, s, o, z = np.cos(a), np.sin(a), np.ones_like(a), np.zeros_like(a)
    return np.stack((np.stack((c, s, z), -1), np.stack((-s, c, z), -1), np.stack((z, z, o), -1)), -2)
