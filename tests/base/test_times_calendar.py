"""The calendar dates beside ``jd_tdb`` (ephem.base.times.calendar_dates, issue 41): ISO 8601 in UTC, TT or TDB, to
the millisecond, against astropy's ``Time``, which runs ERFA's full chain (its TDB - TT is ERFA's ``dtdb``, ours the
USNO Circular 179 series: :data:`ephem.base.times.TDB_TT_ERROR_S`).

The error budget of a date: half its last digit (0.5 ms, the rounding), the TDB - TT series' 10 us and a float64
Julian date's own resolution (2^-52 of 2.5e6 days: 40 us, half of it in the input). A date further than that from
astropy's is a wrong date; within it, the two texts agree but where astropy's instant sits within the series' 10 us
of a rounding boundary."""
from __future__ import annotations

import warnings

import erfa
import numpy as np
import pytest

from ephem.base import times
from ephem.base.errors import InvalidInputError

astropy_time = pytest.importorskip("astropy.time")

#: the budget above, in seconds
BUDGET_S = 0.5e-3 + times.TDB_TT_ERROR_S + 20e-6


def astropy_dates(jd: np.ndarray, scale: str) -> np.ndarray:
    times._leap_seconds_offline()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = getattr(astropy_time.Time(jd, format="jd", scale="tdb"), scale)
        return t, t.isot


@pytest.mark.parametrize("scale", times.CALENDAR_SCALES)
def test_the_dates_are_astropys_within_their_last_digit(scale):
    rng = np.random.default_rng(41)
    jd = rng.uniform(2437300.5, 2488070.0, 4000)         # 1961 to 2100: UTC defined by the leap-second table
    ours = times.calendar_dates(jd, scale)
    exact, exact_text = astropy_dates(jd, scale)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        read = astropy_time.Time(ours, format="isot", scale=scale)
        apart_s = np.abs((read - exact).to_value("s"))
    assert apart_s.max() < BUDGET_S, apart_s.max()
    same = np.mean(np.array(ours) == exact_text)
    assert same > 0.99, same                              # the rest: a rounding boundary within the series' 10 us


def test_a_leap_second_reads_sixty():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = astropy_time.Time(["2016-12-31T23:59:59.500", "2016-12-31T23:59:60.500", "2017-01-01T00:00:00.500"],
                              scale="utc").tdb
    assert times.calendar_dates(t.jd1 + t.jd2, "utc") == ["2016-12-31T23:59:59.500", "2016-12-31T23:59:60.500",
                                                          "2017-01-01T00:00:00.500"]


@pytest.mark.parametrize("text, scale", [("2040-01-01", "utc"), ("2040-01-01T12:34:56.789", "utc"),
                                         ("2025-06-30T23:59:59.999 TT", "tt"), ("1999-12-31T00:00:00.001 TDB", "tdb")])
def test_a_date_given_reads_back_as_given(text, scale):
    iso = text.split(" ")[0]
    expected = iso if "T" in iso else iso + "T00:00:00.000"
    assert times.calendar_dates([times.to_jd_tdb(text)], scale) == [expected]


def test_the_fast_utc_path_is_erfas_own_chain():
    """Away from leap seconds and after 1972 UTC is TAI less a whole number of seconds (times._utc_fields); its dates
    must be those of ERFA's taiutc then d2dtf("UTC"), on every day, leap-second days and the drifting 1960s too."""
    rng = np.random.default_rng(7)
    table = erfa.leap_seconds.get()
    day0, day1 = erfa.cal2jd(table["year"], table["month"], 1)
    near = np.concatenate([c + np.linspace(-3.0, 3.0, 2001) for c in day0 + day1])
    jd = np.concatenate([rng.uniform(2415020.5, 2488070.0, 20000), near])
    day = np.floor(jd)
    frac = jd - day
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tai = erfa.tttai(day, frac)
        reference = times._iso_texts(*erfa.d2dtf("UTC", times.CALENDAR_DECIMALS, *erfa.taiutc(*tai)))
        assert times._iso_texts(*times._utc_fields(*tai)) == reference


def test_the_series_is_within_its_stated_error_of_erfas_dtdb():
    from skyfield.timelib import tdb_minus_tt

    jd = np.arange(2305447.5, 2524593.5, 3.7)            # 1600-2200
    full = erfa.dtdb(jd, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert np.abs(tdb_minus_tt(jd) - full).max() < times.TDB_TT_ERROR_S


def test_years_beyond_four_digits_carry_their_sign():
    year_zero = sum(erfa.cal2jd(0, 6, 1))              # astronomical year 0 (1 BC), proleptic Gregorian
    dates = times.calendar_dates([100.0, year_zero, 9e6], "tdb")
    assert dates == ["-4712-03-03T12:00:00.000", "0000-06-01T00:00:00.000", "+19929-01-23T12:00:00.000"]
    assert times.calendar_dates([], "utc") == []


@pytest.mark.parametrize("scale", ["UTC", "Tt", "tdb"])
def test_the_scale_is_named_in_any_case(scale):
    assert times.check_calendar_scale(scale) == scale.lower()


@pytest.mark.parametrize("scale", ["ut1", "tai", "", None, 3])
def test_another_scale_is_refused_naming_the_field(scale):
    with pytest.raises(InvalidInputError) as err:
        times.check_calendar_scale(scale)
    assert err.value.field == "time_scale" and "utc, tt, tdb" in err.value.reason


def test_a_time_is_told_apart_while_astropy_time_is_still_being_imported(monkeypatch):
    """A worker's first requests can run while another thread imports astropy.time: the module is in sys.modules
    without its Time yet (the memory soak of issue 42 met a 500 AttributeError there). A date is then read as given."""
    import sys
    import types
    from ephem.base import times
    monkeypatch.setitem(sys.modules, "astropy.time", types.ModuleType("astropy.time"))      # half imported: no Time
    assert times._is_astropy_time("2040-01-01") is False
    assert times.to_jd_tdb("JD2451545") == 2451545.0


def test_few_dates_are_written_as_many_are(monkeypatch):
    """A short column is written date by date (an f-string each), a long one by numpy all at once (ephem.base.times.FEW_DATES): the
    same text either way, signed years, leap seconds and every scale included."""
    import numpy as np
    from ephem.base import times
    leap = 2457754.5 + 69.184 / 86400 - np.arange(-3, 3, 0.25) / 86400        # about 2016-12-31T23:59:60 UTC
    jd = np.concatenate([leap, [1e5, 5.3e6, 2451545.0], 2441317.5 + 997.3 * np.arange(20)])
    for scale in ("utc", "tt", "tdb"):
        few = times.calendar_dates(jd, scale)
        monkeypatch.setattr(times, "FEW_DATES", 0)
        assert times.calendar_dates(jd, scale) == few
        monkeypatch.setattr(times, "FEW_DATES", 64)
    assert "2016-12-31T23:59:60.000" in times.calendar_dates(leap) and few[len(leap)].startswith("-4439-")


def test_the_series_taken_at_once_is_skyfields_term_by_term():
    """times._tdb_minus_tt takes skyfield's seven terms in one array: the same IEEE operations on the same operands,
    summed in the same order. Budget: one unit in the last place (~2e-19 s at 1.7 ms), the most a sine's vector
    kernel could move it by; the dates then read the same text, which the column built through skyfield's own
    function shows, grids over leap seconds and a drifting 1960s included."""
    from skyfield.timelib import tdb_minus_tt

    rng = np.random.default_rng(39)
    for size in (1, 7, 37, 64, 65, 1000):
        jd = np.sort(rng.uniform(2305447.5, 2524593.5, size))
        np.testing.assert_array_max_ulp(times._tdb_minus_tt(jd), tdb_minus_tt(jd), maxulp=1)
    table = erfa.leap_seconds.get()
    day0, day1 = erfa.cal2jd(table["year"], table["month"], 1)
    grids = [c - 0.5 + np.arange(37) * step for c in day0 + day1 for step in (1.0 / 86400, 0.01, 10.0)]
    grids.append(2465424.5 + np.arange(37) * 10.0)                  # the 37-epoch track of 2040
    for jd in grids:
        day = np.floor(jd)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tai = erfa.tttai(day, jd - day - tdb_minus_tt(jd) / 86400.0)
            reference = times._iso_texts(*erfa.d2dtf("UTC", times.CALENDAR_DECIMALS, *erfa.taiutc(*tai)))
        assert times.calendar_dates(jd, "utc") == reference


def test_a_column_away_from_leap_seconds_takes_one_call():
    """A column of ordinary days since 1972 (no leap second within two days of any date) is written by one d2dtf
    (times._utc_fields' short way, decided from the column's ends): the dates of ERFA's own chain, taiutc then
    d2dtf("UTC"); so are columns whose end stands just within or just beyond two days of a change, or across one."""
    changes, _ = times._leap_changes(erfa.leap_seconds.get())
    columns = [2465424.5 + np.arange(37) * 10.0]
    for c in changes:
        for end in (c - 2.0 - 1e-6, c - 2.0 + 1e-6, c + 2.0 - 1e-6, c + 2.0 + 1e-6):
            columns += [end - np.arange(8)[::-1] * 0.5, end + np.arange(8) * 0.5, end + np.array([-10.0, 0.0, 10.0])]
    for tai_jd in columns:
        day = np.floor(tai_jd)
        tai = (day, tai_jd - day)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            reference = times._iso_texts(*erfa.d2dtf("UTC", times.CALENDAR_DECIMALS, *erfa.taiutc(*tai)))
            assert times._iso_texts(*times._utc_fields(*tai)) == reference
