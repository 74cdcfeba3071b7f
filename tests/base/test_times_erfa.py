"""ISO times in UTC, TAI, TT and TDB go to TDB through ERFA alone (ephem.base.times._erfa_jd_tdb, issue 33: no
astropy at a one-body answer's start-up). Astropy's ``Time(...).tdb`` runs the same ERFA chain and is the
reference: the two must give the same double (the chain and the two-part splits are the same, so any difference
is a slip in the reimplementation, not rounding), over 1850-2200, on leap-second days and in every form of the
grammar."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from ephem.base import times

astropy_time = pytest.importorskip("astropy.time")


def astropy_jd_tdb(iso: str, scale: str) -> float:
    times._leap_seconds_offline()           # astropy's leap-second table, from the bundled files only
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # "dubious year" far from the leap-second table's span
        t = astropy_time.Time(iso.rstrip("Z"), format="isot" if "T" in iso else "iso", scale=scale).tdb
    return float(t.jd1 + t.jd2)


def random_texts(count: int, seed: int):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        y, mo, d = int(rng.integers(1850, 2201)), int(rng.integers(1, 13)), int(rng.integers(1, 29))
        h, mi = int(rng.integers(0, 24)), int(rng.integers(0, 60))
        sec = min(float(np.round(rng.uniform(0.0, 60.0), int(rng.integers(0, 7)))), 59.999999)
        yield f"{y:04d}-{mo:02d}-{d:02d}T{h:02d}:{mi:02d}:{sec:09.6f}"


@pytest.mark.parametrize("scale", ["utc", "tai", "tt", "tdb"])
def test_erfa_alone_gives_astropys_tdb_to_the_last_bit(scale):
    for iso in random_texts(400, seed=hash(scale) % 2**32):
        assert times._erfa_jd_tdb(iso, scale) == astropy_jd_tdb(iso, scale), (iso, scale)


@pytest.mark.parametrize("iso", [
    "2016-12-31T23:59:59.5", "2017-01-01T00:00:00", "2016-12-31", "2015-06-30T23:59:59.999",  # leap-second days
    "1972-01-01T00:00:00", "1960-01-01", "1959-12-31T23:00", "2000-01-01T12:00", "2100-02-28T23:59:59"])
@pytest.mark.parametrize("scale", ["utc", "tt"])
def test_leap_second_days_and_the_short_forms(iso, scale):
    assert times._erfa_jd_tdb(iso, scale) == astropy_jd_tdb(iso, scale)


def test_the_boundary_parses_every_form_through_erfa_as_through_astropy():
    for text, iso, scale in [("2020-01-01", "2020-01-01", "utc"), ("2020-01-01T12:00Z", "2020-01-01T12:00", "utc"),
                             ("2020-01-01 12:00", "2020-01-01 12:00", "utc"),
                             ("2020-01-01T12:00:00 TDB", "2020-01-01T12:00:00", "tdb"),
                             ("2020-01-01T12:00:00.25 tai", "2020-01-01T12:00:00.25", "tai")]:
        assert times.to_jd_tdb(text) == astropy_jd_tdb(iso, scale), text
    # J2000.0 is 2000-01-01T12:00 TT, and TDB - TT there is -99.3 µs (ERFA dtdb at the geocentre): the JD must be
    # that far below 2451545.0, to the double's resolution there (40 µs); a TT taken as TDB would be 0
    resolution_s = np.spacing(2451545.0) * 86400.0
    tdb_minus_tt_s = (times.to_jd_tdb("2000-01-01T12:00:00 TT") - 2451545.0) * 86400.0
    assert abs(tdb_minus_tt_s - (-99.3e-6)) <= resolution_s


def test_a_one_body_answer_from_an_iso_date_does_not_import_astropy():
    import subprocess
    import sys
    code = ("import sys; from ephem.base.times import to_jd_tdb; to_jd_tdb('2020-01-01T12:00'); "
            "print(any(m == 'astropy' or m.startswith('astropy.') for m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
