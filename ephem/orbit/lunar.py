"""The analytic Moon and Sun seen from the Earth, in the Delaunay arguments: shared by the Earth and the Moon.

The Delaunay arguments l, l', F, D, Ω (IERS Conventions 2010 eq. 5.43) and their rates; the Moon's longitude,
latitude and distance (Meeus 1998 ch. 47, a truncation of ELP-2000/82) and the Sun's Kepler ellipse; DE421's GM
of the Sun, the Moon and the Earth; the mean obliquity of date; and the amplitude cut of a series in these
arguments (``cut_mas``). The data are data/lunisolar.toml.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..base.constants import ARCSEC, AU_M, J2000_JD
from ..base.errors import InvalidInputError
from ..base.paths import data_dir
from .de421_header import GM_DE421, GM_SUN_DE421
from .kepler import solve_kepler
from ..base.disk_cache import read_toml

DAYS_PER_CENTURY = 36525.0

TURN_ARCSEC = 1_296_000.0

#: Order of the Delaunay arguments in every multiplier vector.
DELAUNAY_NAMES = ("l", "l'", "F", "D", "Omega")


@lru_cache(maxsize=1)
def lunisolar_data() -> dict:
    """Parsed data/lunisolar.toml (the Moon, the Sun, Delaunay polynomials, reference values)."""
    return read_toml(data_dir() / "lunisolar.toml")


def _delaunay_poly() -> np.ndarray:
    d = lunisolar_data()["delaunay"]
    return np.array([d["l"], d["lp"], d["F"], d["D"], d["Omega"]], dtype=float)  # (5, 5) arcsec


def centuries(jd_tdb) -> np.ndarray:
    """Julian centuries of TDB from J2000.0."""
    return (np.asarray(jd_tdb, dtype=float) - J2000_JD) / DAYS_PER_CENTURY


def delaunay_arguments(jd_tdb) -> np.ndarray:
    """l, l', F, D, Ω (radians, in [0, 2π)) at JD TDB: IERS Conventions (2010) eq. 5.43.

    Returns an array shaped ``jd_tdb.shape + (5,)``.
    """
    t = centuries(jd_tdb)[..., None]
    p = _delaunay_poly()
    # constant term reduced first so that the large rate term keeps its precision
    arcsec = np.fmod(p[:, 0], TURN_ARCSEC) + t * (p[:, 1] + t * (p[:, 2] + t * (p[:, 3] + t * p[:, 4])))
    return np.remainder(arcsec, TURN_ARCSEC) * ARCSEC


def delaunay_rates(t_centuries: float = 0.0) -> np.ndarray:
    """Rates of l, l', F, D, Ω in rad/day at ``t_centuries`` from J2000 (derivative of eq. 5.43)."""
    p = _delaunay_poly()
    t = float(t_centuries)
    per_cy = p[:, 1] + t * (2 * p[:, 2] + t * (3 * p[:, 3] + t * 4 * p[:, 4]))
    return per_cy * ARCSEC / DAYS_PER_CENTURY


def obliquity_arcsec(t_centuries: float = 0.0) -> float:
    """Mean obliquity of date ε_A, linear part of IAU 2006 (arcsec): the value the series use."""
    e = lunisolar_data()["earth"]
    return e["obliquity_j2000_arcsec"] + e["obliquity_rate_arcsec_per_century"] * t_centuries


def gm_km3_day2(name: str) -> float:
    """DE421's GM (km³/day²) of "sun", "moon" or "earth"."""
    gm_au = {"sun": GM_SUN_DE421, "moon": GM_DE421[301], "earth": GM_DE421[399]}[name]
    return gm_au * (AU_M / 1e3) ** 3


def _series_sum(rows: np.ndarray, col: int, args: tuple, efac: float, func) -> np.ndarray:
    """Σ rows[:, col] E^|m'| func(k·args) on the broadcast grid of ``args`` (5 arrays)."""
    out = 0.0
    for row in rows:
        k = row[:5].astype(int)
        if row[col] == 0.0:
            continue
        amp = row[col] * efac ** abs(k[1])
        phase = sum(int(k[i]) * args[i] for i in range(5) if k[i])
        out = out + amp * func(phase)
    return out


def moon_position(args: tuple, t_centuries: float = 0.0):
    """The Moon's ecliptic longitude λ, latitude β (radians, mean ecliptic and equinox of date)
    and distance r (km) from Delaunay arguments (a tuple of 5 broadcastable arrays).

    Meeus (1998) Tables 47.A/47.B and the Delaunay-argument additive terms (data/lunisolar.toml).
    """
    m = lunisolar_data()["moon"]
    e1, e2 = m["eccentricity_factor"][1:]
    efac = 1.0 + t_centuries * (e1 + t_centuries * e2)
    lr = np.array(m["longitude_distance"], dtype=float)
    lat = np.array(m["latitude"], dtype=float)
    deg6 = math.radians(1e-6)
    lon = _series_sum(lr, 5, args, efac, np.sin) + _series_sum(np.array(m["additive_longitude"], float), 5, args, 1.0, np.sin)
    dist = _series_sum(lr, 6, args, efac, np.cos)
    b = _series_sum(lat, 5, args, efac, np.sin) + _series_sum(np.array(m["additive_latitude"], float), 5, args, 1.0, np.sin)
    lam = args[2] + args[4] + deg6 * lon
    return lam, deg6 * b, m["distance_constant_km"] + 1e-3 * dist


def sun_position(args: tuple, t_centuries: float = 0.0):
    """The Sun's ecliptic longitude λ, latitude (0) and distance r (km) seen from the Earth:
    the Earth-Moon barycentre's Kepler ellipse, mean anomaly l', mean longitude F - D + Ω."""
    s = lunisolar_data()["sun"]
    e = s["eccentricity"][0] + s["eccentricity"][1] * t_centuries
    mean_anomaly = np.asarray(args[1], dtype=float)
    big_e = solve_kepler(np.remainder(mean_anomaly, 2 * math.pi), e)
    beta = e / (1.0 + math.sqrt(1.0 - e * e))
    nu = big_e + 2.0 * np.arctan2(beta * np.sin(big_e), 1.0 - beta * np.cos(big_e))
    r = s["semi_major_axis_au"] * (AU_M / 1e3) * (1.0 - e * np.cos(big_e))
    lam = args[2] - args[3] + args[4] + (nu - mean_anomaly)
    return lam, 0.0, r


#: Smallest cut the nutation answer accepts (mas): far below the first-order theory's own error (the
#: second-order terms are of order 1 mas), and the answer stays a few thousand terms long.
MIN_CUT_MAS = 0.001


def check_cut(cut_mas) -> float:
    if isinstance(cut_mas, bool) or not isinstance(cut_mas, (int, float)) or not math.isfinite(cut_mas) \
            or cut_mas < MIN_CUT_MAS:
        raise InvalidInputError("cut_mas", f"must be a finite number of milliarcseconds >= {MIN_CUT_MAS:g}, "
                                f"got {cut_mas!r}")
    return float(cut_mas)
