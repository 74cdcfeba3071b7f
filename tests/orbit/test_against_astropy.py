"""astropy: the library's UT1 -> TDB (ephem.base.times) against astropy's own conversion through the same
bundled IERS tables, and the free wobble's phase (ephem.rotation.free_motion through ephem.api) against astropy's
position angle and separation."""
from functools import lru_cache

import pytest
from astropy.coordinates import SkyCoord
from astropy.time import Time
from astropy.utils import iers

from ephem import api
from ephem.base.times import to_jd_tdb

J2000 = 2451545.0


# ----------------------------------------------------------------------------- ephem.base.times

#: agreement with astropy's conversion through the same bundled table: 0.1 ms. Both round the JD to one
#: float64 (2.5e6 d carries ~40 µs), so this is the resolution, with margin; the conversions themselves
#: agree to nanoseconds (the same linear interpolation of UT1 - UTC and the same ERFA chain).
BUDGET_S = 1e-4
#: against the other bundled series: where IERS-B (EOP C04) covers the date we use it, and astropy's default
#: is the IERS-A file's Bulletin B column; the two differ by up to 4.1 ms in the 1970s, 0.25 ms since 1993
CROSS_SERIES_BUDGET_S = 5e-3


def _astropy_bundled_tdb(text: str, table) -> Time:
    """astropy's own UT1 -> TDB through a bundled table, told not to download: the independent route."""
    with iers.conf.set_temp("auto_download", False), iers.earth_orientation_table.set(table):
        return Time(text, scale="ut1").tdb


@lru_cache(maxsize=1)
def _bundled():
    return iers.IERS_B.open(iers.IERS_B_FILE), iers.IERS_A.open(iers.IERS_A_FILE)


def _seconds(jd: float, ref: Time) -> float:
    return ((jd - ref.jd1) - ref.jd2) * 86400.0


@pytest.mark.parametrize("text", ["1962-06-01T00:00:00", "1973-06-01T06:00:00", "1990-03-04T12:34:56",
                                  "2000-01-01T12:00:00", "2016-12-31T23:59:59", "2017-01-01T00:00:30",
                                  "2020-01-01T00:00:00", "2027-03-01T00:00:00"])
def test_ut1_inside_the_bundled_span_agrees_with_astropy(text):
    ours = to_jd_tdb(text + " UT1", "start")
    b, a = _bundled()
    same = b if Time(text, scale="utc").mjd <= b["MJD"][-1].value else a      # the series we use there
    assert abs(_seconds(ours, _astropy_bundled_tdb(text, same))) < BUDGET_S
    if Time(text, scale="utc").mjd >= a["MJD"][0].value:
        assert abs(_seconds(ours, _astropy_bundled_tdb(text, a))) < CROSS_SERIES_BUDGET_S


# ----------------------------------------------------------------------------- ephem.rotation.free_motion

def test_the_phase_is_the_position_angle_from_north_through_east():
    ans = api.track("eros", J2000, J2000 + 1.0, 1.0, model="hansen", free_wobble_phase_deg=250.0)
    momentum = api.track("eros", J2000, J2000 + 1.0, 1.0, model="hansen", axis="angular_momentum")
    L = SkyCoord(momentum["pole_ra_deg"][0], momentum["pole_dec_deg"][0], unit="deg")
    f = SkyCoord(ans["pole_ra_deg"][0], ans["pole_dec_deg"][0], unit="deg")
    assert L.position_angle(f).deg == pytest.approx(250.0, abs=1e-6)
    # 55" from RA/Dec served in degrees (ulp 5.7e-14°, 2e-10") and astropy's separation: rel 1e-9 = 5.5e-8"
    assert L.separation(f).arcsec == pytest.approx(55.0, rel=1e-9)
