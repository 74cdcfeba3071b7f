"""Nothing touches the network at run time, and times fail with messages a user can act on.

- UT1 takes UT1 - UTC from the IERS tables bundled with astropy (astropy-iers-data), never from
  astropy's auto-downloading IERS_Auto; inside their span it agrees with astropy's own conversion
  through the same tables (tests/orbit/test_against_astropy.py), outside it is refused naming the field and
  the span.
- A malformed date names the field, says what is wrong and lists the accepted forms, without
  astropy's or ERFA's text.
- A service process whose network is cut, and whose clock is moved past the bundled leap-second
  table's validity (when astropy would download a fresh one), answers every kind of request without
  one attempt to connect or download, and its imports leave astropy's configuration untouched.
"""
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from astropy.time import Time

from ephem.base.errors import InvalidInputError
from ephem.base.times import ACCEPTED, to_jd_tdb, ut1_span

ROOT = Path(__file__).resolve().parents[2]
#: internals that must never reach a user
INTERNALS = ("erfa", "dtf2d", "format class", "iers_auto", "offline", "auto_max_age", "astropy.utils",
             "traceback", "valueerror")


def test_ut1_differs_from_utc_by_the_tabulated_ut1_minus_utc():
    # 2020-01-01: UT1 - UTC = -0.1772 s (IERS Bulletin B); the UT1 clock reading is later in TDB by that much
    dt = (to_jd_tdb("2020-01-01T00:00 UT1") - to_jd_tdb("2020-01-01T00:00 UTC")) * 86400.0
    assert dt == pytest.approx(0.1772, abs=2e-3)
    t = Time("2020-01-01T00:00", scale="ut1")             # an astropy Time in UT1 takes the same route
    assert to_jd_tdb(t) == to_jd_tdb("2020-01-01T00:00 UT1")


def test_ut1_predictions_to_the_end_of_the_bundled_table_are_served():
    lo, hi = ut1_span()
    assert to_jd_tdb(f"{hi}T12:00 UT1") > to_jd_tdb(f"{lo} UT1")
    assert lo == "1962-01-01"


@pytest.mark.parametrize("text", ["2040-01-01T00:00 UT1", "1950-01-01 UT1", "1000-01-01T00:00 ut1"])
def test_ut1_outside_the_bundled_span_is_refused_naming_the_field_and_span(text):
    lo, hi = ut1_span()
    with pytest.raises(InvalidInputError) as e:
        to_jd_tdb(text, "start")
    assert e.value.field == "start"
    assert f"UT1 is supported from {lo} through {hi}" in e.value.reason
    assert not any(word in str(e.value).lower() for word in INTERNALS), str(e.value)
    with pytest.raises(InvalidInputError, match="UT1 is supported"):
        to_jd_tdb(Time(text.split()[0].replace(" ", "T"), scale="ut1"), "stop")


@pytest.mark.parametrize("text, what", [
    ("2020-13-45", "month 13 is not 1 to 12"),
    ("2020-02-30", "day 30 is not 1 to 29 (February 2020 has 29 days)"),
    ("2019-02-29T00:00", "day 29 is not 1 to 28"),
    ("2020-01-01T25:00", "hour 25 is not 0 to 23"),
    ("2020-01-01T12:61", "minute 61 is not 0 to 59"),
    ("2020-01-01 XYZ", "unknown time scale 'XYZ'"),
    ("2020-01-01 local", "unknown time scale 'local'"),
    ("2451545.0 TT", "a Julian date is always TDB"),
    ("1e6", "as digits with an optional decimal point"),
    ("yesterday", "cannot parse 'yesterday' as a time"),
    ("2020-01-01T12", "cannot parse"),
    ("", "empty time"),
])
def test_a_bad_date_names_the_field_says_what_is_wrong_and_lists_the_forms(text, what):
    with pytest.raises(InvalidInputError) as e:
        to_jd_tdb(text, "stop")
    assert e.value.field == "stop" and what in e.value.reason
    assert ACCEPTED in e.value.reason
    assert not any(word in str(e.value).lower() for word in INTERNALS), str(e.value)


def test_an_astropy_time_in_a_scale_without_tdb_is_refused_plainly():
    with pytest.raises(InvalidInputError, match="cannot convert this astropy Time") as e:
        to_jd_tdb(Time("2020-01-01", scale="local"), "start")
    assert not any(word in str(e.value).lower() for word in INTERNALS)


def test_the_service_refuses_ut1_out_of_span_as_a_problem_naming_the_field():
    from fastapi.testclient import TestClient

    from service.app import create_app
    from service.settings import Settings

    with TestClient(create_app(Settings(warm_up=False))) as c:
        r = c.get("/v1/bodies/ceres/track", params={"start": "2040-01-01T00:00 UT1", "stop": "2041-01-01",
                                                    "step_days": 120})
        assert r.status_code == 422 and r.headers["content-type"] == "application/problem+json"
        problem = r.json()
        assert problem["errors"][0]["field"] == "start" and "UT1 is supported from" in problem["detail"]
        assert not any(word in r.text.lower() for word in INTERNALS), r.text
        ok = c.get("/v1/bodies/ceres/track", params={"start": "2020-01-01T00:00 UT1", "stop": "2020-06-01",
                                                     "step_days": 30})
        assert ok.status_code == 200, ok.text
        assert ok.json()["jd_tdb"][0] == to_jd_tdb("2020-01-01T00:00 UT1")


# A service process with its network cut and its clock in 2035 (astropy would then fetch a leap-second
# table: the bundled one expires in 2027). It records every attempt to resolve, connect or download.
_NO_NETWORK = textwrap.dedent(r"""
    import json, socket, sys, warnings
    attempts = []

    def refuse(*args, **kwargs):
        attempts.append(repr(args[:2])[:200])
        raise OSError("network cut by tests/base/test_offline.py")

    socket.socket.connect = lambda self, address: refuse("connect", address)
    socket.socket.connect_ex = lambda self, address: refuse("connect_ex", address)
    socket.getaddrinfo = lambda *a, **k: refuse("getaddrinfo", *a)
    socket.create_connection = lambda *a, **k: refuse("create_connection", *a)
    import astropy.utils.data as data
    data.download_file = lambda url, *a, **k: refuse("download_file", url)
    from astropy.time import Time
    from astropy.utils import iers
    iers.LeapSeconds._today = staticmethod(lambda: Time("2035-01-01", scale="tai", format="iso"))
    conf_before = {k: getattr(iers.conf, k) for k in ("auto_download", "auto_max_age", "iers_degraded_accuracy")}

    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient
    import service.app
    from service.app import create_app
    from service.settings import Settings
    conf_after_import = {k: getattr(iers.conf, k) for k in conf_before}

    user = {"orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                      "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
            "pole": {"ra_deg": 309.03, "dec_deg": 42.23}, "rotation_period_hours": 5.342,
            "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42},
            "track": {"start": "2020-01-01T00:00 UT1", "stop": "2020-03-01 TT", "step_days": 30}}
    statuses = {}
    with TestClient(create_app(Settings(warm_up=True))) as c:       # the start-up's work included
        for name, method, url, kwargs in [
            ("healthz", "GET", "/healthz", {}),
            ("utc", "GET", "/v1/bodies/vesta/track?start=2040-01-01&stop=2041-01-01&step_days=60", {}),
            ("ut1", "GET", "/v1/bodies/ceres/track?start=2020-01-01T00:00%20UT1&stop=2020-06-01&step_days=30", {}),
            ("ut1_out", "GET", "/v1/bodies/ceres/track?start=2040-01-01T00:00%20UT1&stop=2041-01-01&step_days=30", {}),
            ("real_orbit", "GET", "/v1/bodies/vesta/track?start=2020-01-01&stop=2020-02-01&step_days=10"
                                  "&model=real_orbit", {}),
            ("earth", "GET", "/v1/bodies/earth/track?start=2020-01-01T00:00:00Z&stop=2020-02-01&step_days=10", {}),
            ("free_motion", "GET", "/v1/bodies/mars/free-motion?start=2030-01-01&stop=2030-01-03&step_days=1", {}),
            ("post", "POST", "/v1/precession-nutation", {"json": user}),
            ("docs", "GET", "/docs", {}), ("redoc", "GET", "/redoc", {}), ("openapi", "GET", "/openapi.json", {}),
        ]:
            statuses[name] = c.request(method, url, **kwargs).status_code
    conf_after = {k: getattr(iers.conf, k) for k in conf_before}
    print(json.dumps({"attempts": attempts, "statuses": statuses, "conf_before": conf_before,
                      "conf_after_import": conf_after_import, "conf_after": conf_after}))
""")


def test_a_service_with_its_network_cut_never_tries_to_reach_it():
    env = dict(os.environ, PYTHONPATH=str(ROOT), EPHEM_WARM_UP="0")
    env.pop("SSL_CERT_FILE", None)
    done = subprocess.run([sys.executable, "-c", _NO_NETWORK], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    out = json.loads(done.stdout.strip().splitlines()[-1])
    assert out["attempts"] == [], out["attempts"]
    assert out["statuses"] == {"healthz": 200, "utc": 200, "ut1": 200, "ut1_out": 422, "real_orbit": 200,
                               "earth": 200, "free_motion": 200, "post": 200, "docs": 200, "redoc": 200,
                               "openapi": 200}, out["statuses"]
    # importing ephem and the service configures nothing in astropy (neither to download nor not to)
    assert out["conf_after_import"] == out["conf_before"] == out["conf_after"]
