"""Even grids of epochs that float64 can hold (ephem.base.grids, issue 42): a step below the spacing of doubles at the
span's dates is refused naming the step and the smallest step the dates resolve; every grid accepted is strictly
increasing; the tracks and histories at the numeric edges answer finite numbers."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from ephem import api
from ephem.answers.requests import epoch_grid
from ephem.base.errors import InvalidInputError
from ephem.base.grids import SAFE_SPACINGS, check_step, resolution
from ephem.longterm.history import history_grid

J2000 = 2451545.0
#: IEEE 754 double: a number in [2^21, 2^22) (2097152 to 4194304, which holds JD 2451545) has 52 fraction bits
#: below 2^21, so its neighbours are 2^(21 - 52) = 2^-31 days apart
ULP_AT_J2000 = 2.0 ** -31


def test_the_resolution_is_the_spacing_of_doubles_at_the_largest_date():
    assert resolution(J2000, J2000 + 1.0) == ULP_AT_J2000
    assert resolution(J2000, 4194304.0) == 2.0 ** -30          # the next binade
    assert resolution(-5e-324, 4.2e-90) == math.ulp(4.2e-90)
    assert resolution(0.0, -0.0) == 5e-324                     # the smallest subnormal


def test_the_issue_s_track_step_is_refused_naming_the_smallest_step():
    """GET /v1/bodies/ceres/track?start=JD2451545&stop=JD2451545.000000001&step_days=1e-12 was a 500 (NaN)."""
    for step in (1e-12, 1e-11, 1e-10, 3e-10, 0.99 * ULP_AT_J2000):
        with pytest.raises(InvalidInputError) as err:
            epoch_grid("JD2451545", "JD2451545.000000001", step)
        assert err.value.field == "step_days"
        assert "the smallest step these dates resolve is 4.657e-10 d (40.2 µs)" in err.value.reason


def test_a_step_of_one_spacing_is_exact_and_accepted():
    t0, step, count = epoch_grid(J2000, J2000 + 10 * ULP_AT_J2000, ULP_AT_J2000)
    assert count == 11
    t = t0 + step * np.arange(count)
    assert np.all(np.diff(t) == ULP_AT_J2000)


@settings(max_examples=300)
@given(start=st.floats(1e-300, 9.9e6), spacings=st.floats(0.0, 8.0), count=st.integers(2, 50))
def test_every_grid_accepted_is_strictly_increasing(start, spacings, count):
    step = spacings * resolution(start)
    stop = start + step * (count - 1)
    if not step > 0.0 or not math.isfinite(stop):
        return
    try:
        check_step("step_days", start, stop, step, count)
    except InvalidInputError as exc:
        assert exc.field == "step_days" and "smallest step" in exc.reason
        return
    assert np.all(np.diff(start + step * np.arange(count)) > 0.0)
    if spacings >= SAFE_SPACINGS:
        return
    assert step >= resolution(start, stop)


def test_a_history_step_below_the_years_resolution_is_refused():
    with pytest.raises(InvalidInputError) as err:
        history_grid(1000.0, 1000.0 + 1e-11, 1e-14)
    assert err.value.field == "step_years" and f"{math.ulp(1000.0):.4g} years" in err.value.reason


def test_the_issue_s_near_zero_history_is_its_one_epoch_at_j2000():
    """GET /v1/bodies/vesta/history?start_year=-5e-324&stop_year=4.2e-90&step_years=500 was a 500 (the orbit's
    spline had knots float64 could not tell apart): a span shorter than the step is its first epoch, here J2000.0,
    where the pole is the catalogue's (RA 309.03, Dec 42.23 deg, within the estimate)."""
    ans = api.history("vesta", -5e-324, 4.2e-90, 500)
    assert list(ans["year"]) == [-5e-324]
    assert ans["pole_ra_deg"][0] == pytest.approx(309.03, abs=0.01)
    assert ans["pole_dec_deg"][0] == pytest.approx(42.23, abs=0.01)
    for key in ("obliquity_deg", "estimated_error_deg", "orbit_inclination_deg"):
        assert np.all(np.isfinite(ans[key])), key


@pytest.mark.parametrize("start, stop, step", [(-5e-324, 5e-324, 5e-324), (0.0, 1e-300, 1e-301),
                                               (-1e-6, 1e-6, 1e-7), (-4.99e-210, 2.34e-145, 1e-146)])
def test_histories_within_a_breath_of_j2000_are_finite_and_as_at_j2000(start, stop, step):
    ans = api.history("eros", start, stop, step)
    at_j2000 = api.history("eros", 0.0, 1.0, 2.0)
    assert np.all(np.diff(ans["year"]) > 0.0)
    for key in ("obliquity_deg", "pole_ra_deg", "pole_dec_deg", "estimated_error_deg"):
        assert np.all(np.isfinite(ans[key])), key
    # the pole moves ~1e-5 deg a year: within a microsecond of a year of J2000 it is J2000's to 1e-9 deg
    assert np.max(np.abs(ans["obliquity_deg"] - at_j2000["obliquity_deg"][0])) < 1e-9


@pytest.mark.parametrize("body", ["ceres", "vesta", "eros", "itokawa", "mars", "earth", "moon"])
def test_a_track_at_the_pole_epoch_and_a_few_spacings_after_it_is_finite(body):
    """The rotation-averaging estimate sampled [t0, t0 + span] from the pole's epoch: a span of zero or a few
    float64 spacings gave 65 equal epochs and a rate 0/0 (the issue's 'nan mas')."""
    for stop, step in ((J2000, 1.0), (J2000 + 4 * ULP_AT_J2000, ULP_AT_J2000)):
        ans = api.track(body, J2000, stop, step)
        assert np.all(np.isfinite(np.asarray(ans["psi_arcsec"], float)))
        assert math.isfinite(ans["model"]["estimated_error_mas"])


def test_a_kernel_over_a_span_its_fit_cannot_resolve_is_refused_naming_stop():
    """The kernel's fit steps through the span at 4 x 1499 steps at least: a span of a few spacings was refused
    naming step_days, which the kernel does not take."""
    with pytest.raises(InvalidInputError) as err:
        api.write_pck("ceres", J2000, J2000 + 1000 * ULP_AT_J2000)
    assert err.value.field == "stop" and "at least 1.117e-05 d" in err.value.reason


def test_a_plot_over_a_few_spacings_draws_them_and_a_shorter_one_is_refused_naming_stop():
    """The default step of a plot is never finer than the dates resolve; its time axis is in µs, not 0.0000000005 d."""
    from ephem.answers.figures import data, plot_request
    from ephem.exports.plot_drawing import time_axis

    ans = data(plot_request("precession", "ceres", J2000, J2000 + 10 * ULP_AT_J2000))
    assert ans["jd_tdb"].size >= 2 and np.all(np.diff(ans["jd_tdb"]) > 0.0)
    x, label = time_axis(ans["jd_tdb"])
    assert label.startswith("µs since") and ans["jd_tdb"][-1] - J2000 <= 10 * ULP_AT_J2000
    assert x[-1] == pytest.approx((ans["jd_tdb"][-1] - J2000) * 86400e6, rel=1e-9) and x[-1] > 100.0
    with pytest.raises(InvalidInputError) as err:
        plot_request("precession", "ceres", J2000, J2000 + 2 * ULP_AT_J2000)
    assert err.value.field == "stop"


def test_the_history_plot_of_a_breath_of_time_labels_years_since_its_start():
    from ephem.exports.plot_drawing import history_time_axis

    factor, label = history_time_axis([-4.99e-210, 2.34e-145])
    assert factor == pytest.approx(1e-145, rel=1e-12) and label.startswith("years since -4.99e-210")
    png = api.render_plot(api.HISTORY_PLOT_KIND, "Eros", -4.99e-210, 2.34e-145, None, fmt="png", dpi=60)
    assert png.startswith(b"\x89PNG")
