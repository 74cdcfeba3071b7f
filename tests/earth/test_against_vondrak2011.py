"""The Earth's pole and obliquity over ±1, ±10 and ±200 kyr against the long-term precession of Vondrák, Capitaine
& Wallace (2011, A&A 534, A22), as ERFA implements it (erfa.ltpequ: the equator's pole; erfa.ltpecl: the
ecliptic's; both in the ICRS-aligned J2000 frame).

Their model is a fit to numerical solutions, "a few arcseconds" good over the historical period and "a few
tenths of a degree" at ±200 kyr (their abstract). Our budget per span is our own estimate at each epoch (the
answer's ``estimated_error_deg``, ``obliquity_error_deg``) plus theirs, which we measure where we can: their
obliquity against La2004's (tests/longterm/test_against_laskar2004.py's reference; 0.0001° over ±1 kyr, 0.011° over ±10 kyr,
0.37° over ±200 kyr)."""
import numpy as np
import pytest

import erfa
from ephem import api
from ephem.base.paths import data_dir
from ephem.orbit.geometry import icrf_to_ecliptic_matrix
from ephem.longterm.averaged_spin import outward_max

SPANS = {"±1 kyr": (1.0e3, 10.0), "±10 kyr": (1.0e4, 100.0), "±200 kyr": (2.0e5, 1000.0)}
ARCSEC_DEG = 1.0 / 3600.0


def vondrak(years: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The equator's pole (ICRF unit vectors) and the obliquity (deg) of Vondrák et al. at ``years``."""
    equ = np.array([erfa.ltpequ(2000.0 + t) for t in years])
    ecl = np.array([erfa.ltpecl(2000.0 + t) for t in years])
    obliquity = np.degrees(np.arctan2(np.linalg.norm(np.cross(equ, ecl), axis=-1), np.sum(equ * ecl, axis=-1)))
    return equ, obliquity


def unit(ra_deg, dec_deg) -> np.ndarray:
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


def their_obliquity_error(years: np.ndarray, obliquity: np.ndarray) -> np.ndarray:
    """Vondrák's obliquity against La2004's at the La2004 epochs (1 kyr), as an envelope from J2000 outward,
    interpolated to ``years``."""
    table = np.genfromtxt([line for line in (data_dir() / "laskar2004" / "earth_la2004.csv").read_text().splitlines()
                           if not line.startswith("#")], delimiter=",", names=True)
    m = np.abs(table["year"]) <= np.abs(years).max() + 1000.0
    la_years, la = table["year"][m], table["obliquity_deg"][m]
    _, v = vondrak(la_years)
    return np.interp(years, la_years, outward_max(la_years, 0.0, np.abs(v - la)))


@pytest.fixture(scope="module", params=list(SPANS))
def span(request):
    half, step = SPANS[request.param]
    ans = api.history("earth", -half, half, step)
    years = np.asarray(ans["year"])
    equ, obliquity = vondrak(years)
    pole = unit(ans["pole_ra_deg"], ans["pole_dec_deg"])
    angle = np.degrees(np.arctan2(np.linalg.norm(np.cross(pole, equ), axis=-1), np.sum(pole * equ, axis=-1)))
    return request.param, ans, years, angle, obliquity


def test_the_obliquity_is_vondraks_within_both_estimates(span):
    """Measured: 0.0001° over ±1 kyr, 0.011° over ±10 kyr, 0.37° over ±200 kyr: Vondrák's own departure from
    La2004 there (ours from La2004 is 0.001° over ±100 kyr)."""
    name, ans, years, _, obliquity = span
    diff = np.abs(np.asarray(ans["obliquity_deg"]) - obliquity)
    budget = np.asarray(ans["obliquity_error_deg"]) + their_obliquity_error(years, obliquity)
    assert np.all(diff <= budget), (name, diff.max())


def test_the_pole_is_vondraks_over_the_historical_and_the_ten_millennia_spans(span):
    """The pole's angle: 0.37″ over ±1 kyr, within their "few arcseconds" (3″); 77″ over ±10 kyr, within our
    estimate at each epoch (262″ at the ends: the precession constant's probe and the nutation). Over ±200 kyr the
    angle reaches 3.2°, mostly the precession angle's phase (0.3 % of the 2.8 turns); it is reported in
    docs/long_term.md, not asserted: neither model's precession phase there has a measured accuracy."""
    name, ans, years, angle, _ = span
    if name == "±1 kyr":
        assert angle.max() < 3.0 * ARCSEC_DEG
    elif name == "±10 kyr":
        assert np.all(angle <= np.asarray(ans["estimated_error_deg"]))
    else:
        assert angle.max() < 5.0      # the chart's number, kept from drifting unnoticed (measured 3.2°)


def test_the_precession_angle_is_vondraks_over_the_historical_span():
    """The equinox's turn on the J2000 ecliptic, ours against the same angle built from ltpequ × ltpecl: within
    2.5″ over ±1 kyr (measured 1.9″ of 50 400″), the rate at J2000 within 0.01 %."""
    years = np.linspace(-1.0e3, 1.0e3, 201)
    ans = api.history("earth", -1.0e3, 1.0e3, 10.0)
    equ, _ = vondrak(years)
    ecl = np.array([erfa.ltpecl(2000.0 + t) for t in years])
    m = icrf_to_ecliptic_matrix()
    g = np.cross(equ @ m.T, ecl @ m.T)
    lon = np.unwrap(np.arctan2(g[:, 1], g[:, 0]))
    theirs = -np.degrees(lon - lon[100]) * 3600.0
    ours = np.asarray(ans["precession_angle_deg"]) * 3600.0
    assert np.max(np.abs(ours - theirs)) < 2.5
    assert ours[-1] == pytest.approx(theirs[-1], rel=1e-4)
