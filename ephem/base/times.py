"""Times at the boundary: ISO 8601 (UTC unless a scale is named) or Julian dates (TDB).

Accepted forms (text exactly as :data:`TIME_PATTERN` states, which the service's OpenAPI document
publishes; ERFA takes ISO times in UTC, TAI, TT and TDB to TDB by the chain astropy's ``Time`` runs, to the same
bits, without loading astropy; astropy ``Time`` parses the other scales):
- a number, or digits ``"2451545.0"``, ``"JD2451545.0"``: a Julian date in TDB, in (0, 1e7);
- ``"2020-01-01"``, ``"2020-01-01T12:00:00"``, ``"2020-01-01 12:00"``, ``"2020-01-01T12:00Z"``: ISO 8601 in UTC;
- ``"2020-01-01T12:00:00 TDB"`` (or TT, TAI, TCB, TCG, UTC, UT1, any case): ISO 8601 in the named scale;
- an astropy ``Time`` (any scale: its TDB Julian date).

Nothing here touches the network. UT1 needs UT1 - UTC, which comes from the IERS tables that ship
with astropy (the ``astropy-iers-data`` package: IERS-B from 1962, IERS-A with its predictions to
about a year after the package's release), never from astropy's auto-downloading ``IERS_Auto``;
a UT1 time outside that span is refused, naming the span. The leap-second table is checked once,
against the bundled files only (astropy would otherwise download a fresh one once its bundled
copy nears expiry). Errors name the field, say what was wrong and list the accepted forms; they
never carry astropy's or ERFA's text.

Out, the other way: :func:`calendar_dates` writes Julian dates TDB as the ISO 8601 calendar dates people read, in
UTC, TT or TDB (:data:`CALENDAR_SCALES`), vectorised through ERFA (the answers' ``utc_iso`` columns).
"""
from __future__ import annotations

import calendar
import math
import re
import sys
import threading
import warnings
from functools import lru_cache
from typing import TYPE_CHECKING

from .constants import JD_RANGE  # (0, 1e7), exclusive: the grammar's Julian dates below are written for it
from .errors import InvalidInputError

if TYPE_CHECKING:       # numpy loads with the first vectorised call, not at the CLI's start-up
    from numpy.typing import ArrayLike

_SCALES = ("tdb", "tt", "tai", "utc", "tcb", "tcg", "ut1")

ACCEPTED = ("accepted: an ISO 8601 date or date-time (2020-01-01, 2020-01-01T12:00, 2020-01-01T12:00:00.5, "
            "2020-01-01T12:00Z), UTC unless followed by a space and a scale (TDB, TT, TAI, TCB, TCG, UTC, UT1), "
            "e.g. '2020-01-01T12:00 TDB'; or a Julian date in TDB, digits with an optional decimal point, "
            "in (0, 1e7) (2451545.0 or JD2451545.0)")


def _anycase(word: str) -> str:
    return "".join(f"[{c.upper()}{c.lower()}]" if c.isalpha() else c for c in word)


# The grammar of a time given as text, written once for both sides of the contract: the service's OpenAPI
# document states it as the `pattern` of every time field (ECMA 262 and Python read it alike: ASCII classes,
# literal spaces), and to_jd_tdb refuses any text outside it. Within it, what the pattern cannot say is
# checked and explained: a real calendar day (no 30 February), and UT1 inside the bundled IERS span.
_DATE = "[0-9]{4}-(?:0?[1-9]|1[0-2])-(?:0?[1-9]|[12][0-9]|3[01])"
_CLOCK = "(?:[01]?[0-9]|2[0-3]):[0-5]?[0-9](?::[0-5]?[0-9](?:[.][0-9]+)?)?"
_SCALE = "|".join(_anycase(s) for s in _SCALES)
_ISO_TEXT = f"(?P<iso>{_DATE}(?:[T ]{_CLOCK})?)(?:(?P<z>Z)| +(?P<scale>{_SCALE}))?"
_JD_TEXT = f"(?:{_anycase('jd')} *)?(?P<jd>0*(?:[1-9][0-9]{{0,6}}(?:[.][0-9]*)?|[.][0-9]*[1-9][0-9]*))"
TIME_PATTERN = f"^ *(?:{_JD_TEXT}|{_ISO_TEXT}) *$"
#: TIME_PATTERN without the group names, for JSON Schema (ECMA 262 has no (?P<name>...))
TIME_PATTERN_ECMA = re.sub(r"\(\?P<[a-z]+>", "(", TIME_PATTERN)
_TIME = re.compile(TIME_PATTERN)

# looser shapes, only to say what is wrong with a text outside the grammar
_WORD = re.compile(r"[A-Za-z][A-Za-z0-9]*")
_LOOSE_ISO = re.compile(r"(?P<Y>[0-9]{4})-(?P<m>[0-9]{1,2})-(?P<d>[0-9]{1,2})"
                        r"(?:[T ](?P<H>[0-9]{1,2}):(?P<M>[0-9]{1,2})(?::(?P<S>[0-9]{1,2}(?:[.][0-9]*)?))?)?Z?")


def to_jd_tdb(value, field: str = "time") -> float:
    """Julian date (TDB) of a boundary time; raises InvalidInputError naming ``field``."""
    if isinstance(value, bool):
        raise InvalidInputError(field, f"expected a time, got {value!r}; {ACCEPTED}")
    if _is_astropy_time(value):
        jd = _time_jd_tdb(value, field)
    elif isinstance(value, (int, float)):
        jd = float(value)
    else:
        jd = _parse_text(str(value), field)
    if not math.isfinite(jd):
        raise InvalidInputError(field, f"time must be finite, got {value!r}")
    if not JD_RANGE[0] < jd < JD_RANGE[1]:
        raise InvalidInputError(field, f"Julian date {jd} is outside the supported range "
                                       "(0, 1e7)")
    return jd


def _parse_text(text: str, field: str) -> float:
    m = _TIME.fullmatch(text)
    if m is None:
        raise InvalidInputError(field, _what_is_wrong(text))
    if m["jd"] is not None:
        return float(m["jd"])
    iso, scale = m["iso"], (m["scale"] or "utc").lower()
    _check_calendar(iso, field)
    return _iso_jd_tdb(iso + ("Z" if m["z"] else ""), scale, field)


def _what_is_wrong(text: str) -> str:
    """Why a text is not a time, for a text outside the grammar."""
    stripped = text.strip()
    if not stripped:
        return f"empty time; {ACCEPTED}"
    parts = stripped.rsplit(None, 1)
    body, word = (parts[0], parts[1]) if len(parts) == 2 and _WORD.fullmatch(parts[1]) else (stripped, None)
    if word is not None and word.lower() not in _SCALES:
        return (f"unknown time scale {word!r} in {text!r}: the scales are "
                f"{', '.join(s.upper() for s in _SCALES)}; {ACCEPTED}")
    number = body[2:].strip() if body.upper().startswith("JD") else body
    try:
        jd = float(number)
    except ValueError:
        pass
    else:
        if word is not None:
            return (f"a Julian date is always TDB: give {number} without a scale, or the time as ISO 8601 "
                    f"with its scale; {ACCEPTED}")
        if not math.isfinite(jd):
            return f"time must be finite, got {text!r}"
        if not JD_RANGE[0] < jd < JD_RANGE[1]:
            return f"Julian date {jd} is outside the supported range (0, 1e7)"
        return f"write the Julian date {text!r} as digits with an optional decimal point (no sign, exponent, " \
               f"separator or other spacing); {ACCEPTED}"
    loose = _LOOSE_ISO.fullmatch(body)
    if loose is not None:
        reason = _field_ranges(loose, body)
        if reason:
            return reason
    return f"cannot parse {text!r} as a time; {ACCEPTED}"


def _field_ranges(m: re.Match, text: str) -> str | None:
    """Which part of a date-shaped text is out of range (month 13, February 30, hour 25), or None."""
    year, month, day = int(m["Y"]), int(m["m"]), int(m["d"])
    if not 1 <= month <= 12:
        return f"{text!r}: month {month} is not 1 to 12; {ACCEPTED}"
    last = calendar.monthrange(year, month)[1]
    if not 1 <= day <= last:
        return (f"{text!r}: day {day} is not 1 to {last} ({calendar.month_name[month]} {year} has {last} days); "
                f"{ACCEPTED}")
    if m["H"] is not None:
        hour, minute = int(m["H"]), int(m["M"])
        if not 0 <= hour <= 23:
            return f"{text!r}: hour {hour} is not 0 to 23; {ACCEPTED}"
        if not 0 <= minute <= 59:
            return f"{text!r}: minute {minute} is not 0 to 59; {ACCEPTED}"
        if m["S"] is not None and not 0 <= float(m["S"]) < 60:
            return f"{text!r}: second {m['S']} is not 0 to 59.999...; {ACCEPTED}"
    return None


def _check_calendar(iso: str, field: str) -> None:
    reason = _field_ranges(_LOOSE_ISO.fullmatch(iso), iso)
    if reason:
        raise InvalidInputError(field, reason)


def _is_astropy_time(value) -> bool:
    # not hasattr(value, "tdb"): that would convert (for UT1, through astropy's downloading IERS table)
    # while another thread is still importing astropy.time (a worker's first requests), the module is in sys.modules
    # without its Time yet: no value can be one of a class not yet made (module.Time raised AttributeError: a 500)
    time_class = getattr(sys.modules.get("astropy.time"), "Time", None)
    return time_class is not None and isinstance(value, time_class)


def _time_jd_tdb(value, field: str) -> float:
    if not value.isscalar:
        raise InvalidInputError(field, "expected one time, got an array of them")
    _leap_seconds_offline()
    from erfa import ErfaWarning

    if value.scale == "ut1" and getattr(value, "_delta_ut1_utc", None) is None:
        value = value.copy()      # UT1 - UTC from the bundled tables, never from IERS_Auto (the network)
        value.delta_ut1_utc = _ut1_minus_utc(value.jd1, value.jd2, field, value.isot + " UT1")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ErfaWarning)  # "dubious year": UTC beyond the leap-second table
            tdb = value.tdb
        return float(tdb.jd1 + tdb.jd2)
    except Exception:   # e.g. a scale astropy cannot take to TDB ('local')
        raise InvalidInputError(field, f"cannot convert this astropy Time (scale {value.scale!r}) to TDB; "
                                       f"give it in one of {', '.join(s.upper() for s in _SCALES)}") from None


#: the scales ERFA takes to TDB alone (UTC through its leap-second table): no astropy at run time for them
_ERFA_SCALES = ("utc", "tai", "tt", "tdb")


def _day_frac(a: float, b: float) -> tuple[float, float]:
    """(day, fraction) with day + fraction = a + b exactly (Knuth's two-sum), the day a whole number: the split
    astropy's ``Time`` keeps a date in, so that ERFA's two-part conversions see the same parts."""
    total = a + b
    bb = total - a
    err = (a - (total - bb)) + (b - bb)
    day = float(round(total))
    extra = total - day
    frac = extra + err
    day, frac = day + float(round(frac)), frac - float(round(frac))
    return day, frac


@lru_cache(maxsize=4096)     # a pure function of two strings: the same dates come again and again (~0.3 ms each)
def _erfa_jd_tdb(iso: str, scale: str) -> float:
    """JD TDB of a grammar-checked ISO date-time in UTC, TAI, TT or TDB by ERFA's conversions, the chain astropy's
    ``Time(...).tdb`` runs (dtf2d; utctai, taitt, tttdb with ERFA's dtdb at the geocentre), without importing
    astropy (0.2-0.45 s of a one-body answer's start-up). tests/base/test_times_erfa.py holds it to astropy's
    result over 1900-2100 and on leap-second days."""
    import erfa

    date, _, clock = iso.rstrip("Z").replace("T", " ").partition(" ")
    y, mo, d = (int(x) for x in date.split("-"))
    h, mi, sec = (clock.split(":") + ["0", "0"])[:3] if clock else ("0", "0", "0")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", erfa.ErfaWarning)  # "dubious year" for far dates, as on astropy's path
        jd1, jd2 = _day_frac(*erfa.dtf2d(scale.upper(), y, mo, d, int(h), int(mi), float(sec)))
        if scale == "tdb":
            return float(jd1 + jd2)
        if scale == "utc":
            jd1, jd2 = erfa.taitt(*erfa.utctai(jd1, jd2))
        elif scale == "tai":
            jd1, jd2 = erfa.taitt(jd1, jd2)
        jd1, jd2 = _day_frac(jd1, jd2)
        # TDB - TT at the geocentre (ERFA dtdb; the UT argument only moves its topocentric terms, zero here)
        u1, u2 = erfa.taiutc(*erfa.tttai(jd1, jd2))
        ut = _day_frac(u1 - 0.5, u2)[1]
        tdb1, tdb2 = _day_frac(*erfa.tttdb(jd1, jd2, erfa.dtdb(jd1, jd2, ut, 0.0, 0.0, 0.0)))
    return float(tdb1 + tdb2)


def _iso_jd_tdb(text: str, scale: str, field: str) -> float:
    if scale in _ERFA_SCALES:
        try:
            return _erfa_jd_tdb(text, scale)
        except Exception:      # ERFA's messages name its internals, not the user's input
            raise InvalidInputError(field, f"cannot parse {text} {scale.upper()!r} as a time; {ACCEPTED}") from None
    from astropy.time import Time
    from erfa import ErfaWarning

    _leap_seconds_offline()
    shown = f"{text} {scale.upper()}"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ErfaWarning)  # "dubious year" for far dates
            t = Time(text, format="isot" if "T" in text else "iso", scale=scale)
            if scale == "ut1":
                t.delta_ut1_utc = _ut1_minus_utc(t.jd1, t.jd2, field, shown)
            tdb = t.tdb
            return float(tdb.jd1 + tdb.jd2)
    except InvalidInputError:
        raise
    except Exception:      # astropy's and ERFA's messages name their internals, not the user's input
        raise InvalidInputError(field, f"cannot parse {shown!r} as a time; {ACCEPTED}") from None


# ---------------------------------------------------------------------------------------------- calendar dates

#: the scales a calendar column is written in (``time_scale``): UTC (civil time, with its leap seconds), TT, TDB
CALENDAR_SCALES = ("utc", "tt", "tdb")
#: decimals of the second in a calendar date: milliseconds (a float64 Julian date near J2000 resolves 40 us)
CALENDAR_DECIMALS = 3
#: how far the calendar dates may stand from ERFA's full TDB - TT series, seconds (1600-2200; the USNO's
#: estimate of its own series, which tests/base/test_times_calendar.py checks against ERFA's dtdb)
TDB_TT_ERROR_S = 1e-5


def check_calendar_scale(scale, field: str = "time_scale") -> str:
    """``scale`` in lower case if it is one of :data:`CALENDAR_SCALES`; InvalidInputError naming ``field`` else."""
    if isinstance(scale, str) and scale.lower() in CALENDAR_SCALES:
        return scale.lower()
    raise InvalidInputError(field, f"must be one of {', '.join(CALENDAR_SCALES)} (the scale of the calendar dates), "
                                   f"got {scale!r}")


def calendar_dates(jd_tdb: ArrayLike, scale: str = "utc") -> list[str]:
    """ISO 8601 calendar dates (``2040-01-01T00:00:00.000``, to the millisecond) of Julian dates TDB, in ``scale``
    (:data:`CALENDAR_SCALES`): the column a person reads beside ``jd_tdb``.

    Vectorised through ERFA, the chain :func:`to_jd_tdb` runs the other way: TDB to TT, TT to TAI, TAI to UTC (ERFA's
    leap-second table; a leap second reads ``23:59:60.xxx``; before 1960 UTC is taken as TAI, as ERFA does), then
    ERFA's ``d2dtf`` rounds to the millisecond. TDB - TT (1.7 ms at most) is the USNO Circular 179 series (eq. 2.6,
    skyfield's ``tdb_minus_tt`` to the bit, its terms taken in one array: :func:`_tdb_minus_tt`; within
    :data:`TDB_TT_ERROR_S` of ERFA's full ``dtdb`` over 1600-2200), which costs ~0.07 us an epoch where ``dtdb`` costs 8 us: the whole column costs 0.2-0.3 us an epoch, a 10^5-epoch track's
    dates ~30 ms of CPU (benchmarks/RESULTS_calendar.md). Years outside 0000-9999 are written with their sign
    (``-4712``, ``+10000``), as ISO 8601's expanded years.

    Parameters
    ----------
    jd_tdb : float or array_like of float
        Julian dates in TDB (days).
    scale : str
        The time scale the dates are written in: one of :data:`CALENDAR_SCALES` ("utc", "tt", "tdb").

    Returns
    -------
    list of str
        One ISO 8601 date and time to the millisecond per epoch, in order.
    """
    import erfa
    import numpy as np

    scale = check_calendar_scale(scale)
    jd = np.asarray(jd_tdb, dtype=float).ravel()
    day = np.floor(jd)
    frac = jd - day                     # exact: the split ERFA's two-part dates take
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", erfa.ErfaWarning)   # "dubious year": UTC before 1960 or far in the future
        if scale != "tdb":
            frac = frac - _tdb_minus_tt(jd) / 86400.0        # TT (the series takes TT or TDB alike, 1.7 ms apart)
        fields = _utc_fields(*erfa.tttai(day, frac)) if scale == "utc" else \
            erfa.d2dtf(scale.upper(), CALENDAR_DECIMALS, day, frac)
    return _iso_texts(*fields)


#: USNO Circular 179's TDB - TT (eq. 2.6), as skyfield's ``tdb_minus_tt`` writes it: seconds = sum of
#: amplitude * sin(rate * T + phase), T in Julian centuries TDB from J2000, the last term's amplitude times T
_TDB_TT_AMPLITUDE = (0.001657, 0.000022, 0.000014, 0.000005, 0.000005, 0.000002, 0.000010)
_TDB_TT_RATE = (628.3076, 575.3385, 1256.6152, 606.9777, 52.9691, 21.3299, 628.3076)
_TDB_TT_PHASE = (6.2401, 4.2970, 6.1969, 4.0212, 0.4444, 5.5431, 4.2490)


def _tdb_minus_tt(jd):
    """TDB - TT (s) at the Julian dates TDB ``jd`` (1-D): skyfield's ``tdb_minus_tt`` to the bit, its seven terms'
    arguments and sines taken in one (7, epochs) array instead of 38 small numpy calls (~40 us for a few dozen
    epochs, 10 here): each element the same IEEE operations on the same operands, and the terms summed in the same
    order, first to last (tests/base/test_times_calendar.py compares them, and the dates they give)."""
    import numpy as np

    rate, phase, amplitude = _tdb_tt_arrays()
    t = (jd - 2451545.0 + 0.0) / 36525.0
    sines = np.sin(rate * t + phase)
    terms = amplitude * sines[:6]
    total = terms[0] + terms[1]
    for k in range(2, 6):
        total += terms[k]
    total += _TDB_TT_AMPLITUDE[6] * t * sines[6]
    return total


@lru_cache(maxsize=1)
def _tdb_tt_arrays():
    """The series' rates and phases as (7, 1) columns and its first six amplitudes as a (6, 1) column (numpy loads
    with the first call, not with the module)."""
    import numpy as np

    column = lambda values: np.array(values, dtype=float)[:, None]      # noqa: E731
    return column(_TDB_TT_RATE), column(_TDB_TT_PHASE), column(_TDB_TT_AMPLITUDE[:6])


def _utc_fields(day, frac):
    """ERFA's ``d2dtf`` fields of the UTC dates of TAI two-part Julian dates: as ``taiutc`` then ``d2dtf("UTC")``
    give them, at a third of their cost. From 1972 TAI - UTC is a whole number of seconds between leap seconds, so
    away from them (two days) UTC is TAI less the table's offset, on an ordinary day; ERFA's own functions take the
    rest (a leap second's day, and before 1972, when UTC drifted)."""
    import erfa
    import numpy as np

    changes, offsets = _leap_changes(erfa.leap_seconds.get())
    tai = day + frac
    if tai.size:        # the usual column: every date since 1972 between the same two changes, two days from both
        lo, hi = float(tai.min()), float(tai.max())
        i = int(np.searchsorted(changes, lo, side="right"))
        # as the test below finds it date by date: each date's distance to either change is least at an end
        if 0 < i == int(np.searchsorted(changes, hi, side="right")) and lo - changes[i - 1] >= 2.0 \
                and abs(changes[min(i, changes.size - 1)] - hi) >= 2.0:
            return erfa.d2dtf("TAI", CALENDAR_DECIMALS, day, frac - offsets[i - 1])
    after = np.searchsorted(changes, tai, side="right")          # offsets in force: changes[after - 1] <= tai
    nearest = np.minimum(np.abs(tai - changes[np.maximum(after - 1, 0)]),
                         np.abs(changes[np.minimum(after, changes.size - 1)] - tai))
    slow = (after == 0) | (nearest < 2.0)
    if not slow.any():                  # every date on an ordinary day since 1972 (across a change), in one call
        return erfa.d2dtf("TAI", CALENDAR_DECIMALS, day, frac - offsets[after - 1])
    fast = ~slow
    year, month, mday = (np.empty(tai.size, dtype=np.int32) for _ in range(3))
    clock = None
    for mask, fields in ((fast, lambda: erfa.d2dtf("TAI", CALENDAR_DECIMALS, day[fast],
                                                   frac[fast] - offsets[after[fast] - 1])),
                         (slow, lambda: erfa.d2dtf("UTC", CALENDAR_DECIMALS, *erfa.taiutc(day[slow], frac[slow])))):
        if not mask.any():
            continue
        y, m, d, c = fields()
        if clock is None:
            clock = np.empty(tai.size, dtype=c.dtype)
        year[mask], month[mask], mday[mask], clock[mask] = y, m, d, c
    if clock is None:                   # no dates
        return erfa.d2dtf("UTC", CALENDAR_DECIMALS, day, frac)
    return year, month, mday, clock


_LEAP_CHANGES: dict = {}


def _leap_changes(table) -> tuple:
    """(each whole-second TAI - UTC offset's first instant as a TAI Julian date, the offsets in days) from ERFA's
    leap-second table (year, month, TAI - UTC s), from 1972; kept per table's contents (ERFA's table changes only
    when a leap second is added), since a small track's dates would spend a third of their cost on it."""
    key = table.tobytes()
    kept = _LEAP_CHANGES.get(key)
    if kept is None:
        import erfa
        import numpy as np

        table = table[table["year"] >= 1972]
        djm0, djm = erfa.cal2jd(table["year"], table["month"], 1)
        offsets = np.asarray(table["tai_utc"], dtype=float) / 86400.0
        kept = (djm0 + djm + offsets, offsets)
        _LEAP_CHANGES.clear()           # one table at a time
        _LEAP_CHANGES[key] = kept
    return kept


#: up to this many dates are written by one f-string each, their fields' digits looked up (~0.4 us a date); beyond,
#: numpy places the digits of every date at once (a fixed ~50 us, then ~0.5 us a date): 37 dates 72 -> 31 -> ~15 us
FEW_DATES = 64
#: the digits of a date's two-digit fields (00-99: a leap second's 60 among them) and of its milliseconds (000-999)
_DIGITS_2 = tuple(f"{i:02d}" for i in range(100))
_DIGITS_3 = tuple(f"{i:03d}" for i in range(10 ** CALENDAR_DECIMALS))


def _iso_texts(year, month, mday, clock) -> list[str]:
    """``YYYY-MM-DDThh:mm:ss.sss`` of ERFA's ``d2dtf`` fields, the digits placed by numpy (a Python format per date
    would cost ~0.6 us each); the rare year outside 0000-9999 formatted alone, with its sign."""
    import numpy as np

    n = year.size
    if n <= FEW_DATES:      # the fields' digits looked up (d2dtf's fields are never negative), the year formatted
        two, three = _DIGITS_2, _DIGITS_3
        return [f"{y:04d}-{two[mo]}-{two[d]}T{two[h]}:{two[mi]}:{two[s]}.{three[ms]}" if 0 <= y <= 9999 else
                f"{y:+05d}-{two[mo]}-{two[d]}T{two[h]}:{two[mi]}:{two[s]}.{three[ms]}"
                for y, mo, d, h, mi, s, ms in zip(year.tolist(), month.tolist(), mday.tolist(), clock["h"].tolist(),
                                                  clock["m"].tolist(), clock["s"].tolist(), clock["f"].tolist())]
    text = np.empty((n, 21 + CALENDAR_DECIMALS), dtype=np.uint8)      # each date and a newline
    for column, char in ((4, "-"), (7, "-"), (10, "T"), (13, ":"), (16, ":"), (19, "."), (-1, "\n")):
        text[:, column] = ord(char)
    for column, width, values in ((0, 4, year), (5, 2, month), (8, 2, mday), (11, 2, clock["h"]),
                                  (14, 2, clock["m"]), (17, 2, clock["s"]), (20, CALENDAR_DECIMALS, clock["f"])):
        v = np.abs(values.astype(np.int64))
        for k in range(width - 1, -1, -1):
            text[:, column + k] = 48 + v % 10
            v //= 10
    out = text.tobytes().decode("ascii").split()     # one text, split at the newlines: the cheapest way to n strs
    for j in np.flatnonzero((year < 0) | (year > 9999)).tolist():
        out[j] = f"{int(year[j]):+05d}" + out[j][4:]
    return out


# ---------------------------------------------------------------------------------------------- offline

_LEAP_LOCK = threading.Lock()
_leap_done = False


def _leap_seconds_offline() -> None:
    """Run astropy's once-per-process leap-second check with downloads off.

    astropy checks the leap-second table on the first UTC conversion and, when no bundled file is
    valid well into the future, downloads one (``iers.conf.auto_download``). We run that check
    first, offline: it then picks the freshest bundled table (ERFA's, astropy-iers-data's, the
    system's) and never runs again. The configuration is changed only for that one conversion.
    """
    global _leap_done
    if _leap_done:
        return
    with _LEAP_LOCK:
        if _leap_done:
            return
        from astropy.time import Time
        from astropy.utils import iers

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")     # "leap-second file is expired": then the dates are dubious anyway
            with iers.conf.set_temp("auto_download", False):
                Time(51544.0, format="mjd", scale="utc").tai     # triggers (and completes) astropy's check
        _leap_done = True


@lru_cache(maxsize=1)
def _iers_tables():
    """The bundled IERS-B (definitive, from 1962) and IERS-A (to about a year past the package's release,
    predictions included) tables, read from astropy-iers-data's files: no download, no cache."""
    from astropy.utils import iers

    b = iers.IERS_B.read(iers.IERS_B_FILE)
    a = iers.IERS_A.read(iers.IERS_A_FILE)
    return b, a


def ut1_span() -> tuple[str, str]:
    """First and last UTC dates (ISO) on which a UT1 time is accepted (all day): the bundled IERS tables' span.

    Returns
    -------
    tuple of str
        (first, last): ISO 8601 dates (``YYYY-MM-DD``, UTC), both accepted.
    """
    from astropy.time import Time

    b, a = _iers_tables()
    first, last = float(b["MJD"][0].value), float(a["MJD"][-1].value) - 1.0
    return (Time(first, format="mjd", scale="utc").isot[:10], Time(last, format="mjd", scale="utc").isot[:10])


def _ut1_minus_utc(jd1: float, jd2: float, field: str, shown: str) -> float:
    """UT1 - UTC in seconds at the UT1 time jd1 + jd2, from the bundled tables; InvalidInputError outside them."""
    import erfa

    b, a = _iers_tables()
    b_last, a_first = float(b["MJD"][-1].value), float(a["MJD"][0].value)
    first, last = float(b["MJD"][0].value), float(a["MJD"][-1].value)
    mjd = (jd1 - 2400000.5) + jd2
    if not first <= mjd < last:
        lo, hi = ut1_span()
        raise InvalidInputError(field, f"{shown!r}: UT1 is supported from {lo} through {hi}, the span of the IERS "
                                       "tables bundled with astropy (UT1 - UTC is measured, then predicted about "
                                       "a year ahead; beyond, it is unknown); give the time in UTC or TDB instead")
    table = b if mjd <= b_last or mjd < a_first else a
    dut, _ = table.ut1_utc(jd1, jd2, return_status=True)     # statuses: the span is checked above
    # the table is indexed by UTC: one refinement at the UTC time this gives (as astropy does)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", erfa.ErfaWarning)
        u1, u2 = erfa.ut1utc(jd1, jd2, float(dut.to_value("s")))
    dut, _ = table.ut1_utc(u1, u2, return_status=True)
    return float(dut.to_value("s"))
