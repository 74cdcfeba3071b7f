"""Property sweep over the valid domain: an answer is finite numbers or a clear error, never NaN."""
import json
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ephem import api
from ephem.catalogue import Body, Orbit, Pole
from ephem.errors import EphemError, NotApplicableError


@st.composite
def bodies(draw):
    orbit = Orbit(a_au=draw(st.floats(0.05, 200.0)), e=draw(st.floats(0.0, 0.95)), i_deg=draw(st.floats(0.0, 180.0)),
                  node_deg=draw(st.floats(0.0, 360.0)), peri_deg=draw(st.floats(0.0, 360.0)),
                  mean_anomaly_deg=draw(st.floats(0.0, 360.0)), epoch_jd_tdb=draw(st.floats(2.4e6, 2.5e6)))
    pole = Pole(draw(st.floats(0.0, 360.0)), draw(st.floats(-90.0, 90.0)))
    return Body("sweep", orbit, pole, rotation_period_hours=draw(st.floats(0.01, 5000.0)),
                dynamical_ellipticity=draw(st.floats(1e-8, 0.5)))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(bodies())
def test_answers_are_finite_or_clear_errors(body):
    try:
        p = api.precession(body)
        n = api.nutation(body)
        t = api.track(body, 2451545.0, 2451545.0 + 3650.0, 36.5)
    except EphemError as exc:
        assert str(exc)  # a message, never an empty error
        return
    for answer in (p, n, t):
        json.dumps(answer, allow_nan=False)  # raises on NaN or infinity
    assert all(math.isfinite(v) for k in ("pole_ra_deg", "pole_dec_deg", "psi_arcsec") for v in t[k])


def test_slow_rotator_is_refused_with_its_ratio():
    # a 400-day rotation on a 3.6-year orbit: ω/n = 3.3, not synchronous but too slow to average over
    b = Body("slow", Orbit(2.36, 0.09, 7.1, 103.7, 151.7, 0.0, 2451545.0), Pole(309.0, 42.2), 400 * 24.0,
             dynamical_ellipticity=0.1)
    with pytest.raises(NotApplicableError) as info:
        api.precession(b)
    assert info.value.ratio == pytest.approx(1325.4 / 400, rel=1e-3)
    assert "slow" in str(info.value)
