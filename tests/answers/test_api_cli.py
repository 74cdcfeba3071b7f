"""The contract: JSON keys of the library answers and the CLI, errors and exit codes."""
import csv
import io
import json
import math

import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.theory.choice import SAME_ESTIMATE, TIE
from ephem.bodies.catalogue import Body, Orbit, Pole
from ephem.cli import app
from ephem.base.errors import InvalidInputError, NotApplicableError

runner = CliRunner()
TERM_KEYS = {"multiple", "period_days", "period_years", "longitude_sin_arcsec", "longitude_cos_arcsec",
             "obliquity_sin_arcsec", "obliquity_cos_arcsec", "longitude_amplitude_arcsec", "obliquity_amplitude_arcsec",
             "period_days_uncertainty", "longitude_amplitude_arcsec_uncertainty", "obliquity_amplitude_arcsec_uncertainty"}
TERM_KEYS |= {f"{c}_{p}_arcsec_uncertainty" for c in ("longitude", "obliquity") for p in ("sin", "cos")}
TRACK_KEYS = ["jd_tdb", "psi_arcsec", "delta_psi_arcsec", "delta_epsilon_arcsec", "obliquity_deg",
              "pole_ra_deg", "pole_dec_deg"]


def _json(args):
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


def test_cli_precession_vesta_petit2014():
    ans = _json(["precession", "vesta", "--dataset", "petit2014"])
    assert round(ans["precession_rate_arcsec_per_year"], 2) == 13.67
    assert {"obliquity_deg", "dynamical_ellipticity", "scaling_factor_arcsec_per_year",
            "precession_rate_arcsec_per_year", "model"} <= set(ans)
    assert ans["model"]["eccentricity_order"] == "exact"


def test_cli_nutation_terms_and_order():
    ans = _json(["nutation", "2000004", "--order", "4"])
    assert ans["terms"] and all(set(t) == TERM_KEYS for t in ans["terms"])
    assert [t["multiple"] for t in ans["terms"]] == list(range(1, 7))  # order 4: k up to order + 2
    assert ans["model"]["eccentricity_order"] == 4


def test_cli_track_json_and_csv():
    ans = _json(["track", "Itokawa", "--start", "2020-01-01", "--stop", "2020-02-01", "--step-days", "10"])
    assert all(len(ans[k]) == 4 for k in TRACK_KEYS)
    assert ans["jd_tdb"][0] == pytest.approx(2458849.5 + 69.184 / 86400, abs=1e-6)  # UTC -> TDB
    res = runner.invoke(app, ["track", "vesta", "--start", "2451545.0", "--stop", "2451565", "--step-days", "5",
                              "--format", "csv"])
    rows = list(csv.DictReader(io.StringIO(res.stdout)))
    assert list(rows[0]) == [TRACK_KEYS[0], "utc_iso", *TRACK_KEYS[1:]] and len(rows) == 5    # the dates after jd_tdb
    assert rows[0]["utc_iso"] == "2000-01-01T11:58:55.816"                 # J2000.0 (TDB) in UTC


def test_cli_bodies_table_and_csv():
    res = runner.invoke(app, ["bodies", "--format", "table"])
    assert res.exit_code == 0 and "Itokawa" in res.stdout
    res = runner.invoke(app, ["bodies", "--format", "csv"])
    assert len(list(csv.DictReader(io.StringIO(res.stdout)))) == 8


@pytest.mark.parametrize("args, code, text", [
    (["precession", "pallas"], 2, "known bodies: Ceres, Vesta"),
    (["precession", "moon", "--perturbers", "sun"], 3, "not applicable to Moon"),
    (["nutation", "vesta", "--order", "-1"], 2, "order"),
    (["track", "vesta", "--start", "2020-01-01", "--stop", "2019-01-01", "--step-days", "1"], 2, "stop"),
    (["track", "vesta", "--start", "yesterday", "--stop", "2019-01-01", "--step-days", "1"], 2, "start"),
    (["track", "vesta", "--start", "2020-01-01", "--stop", "2021-01-01", "--step-days", "0"], 2, "step_days"),
    (["track", "vesta", "--start", "2020-01-01", "--stop", "2021-01-01", "--step-days", "nan"], 2, "step_days"),
    (["precession", "vesta", "--dataset", "old"], 2, "dataset"),
])
def test_cli_errors_are_clear(args, code, text):
    res = runner.invoke(app, args)
    assert res.exit_code == code
    assert text in res.output


def test_not_applicable_reports_the_ratio():
    slow = Body("slow", Orbit(1.0, 0.0167, 0.0, 0.0, 0.0, 0.0, 2451545.0), Pole(10.0, 60.0),
                365.25 * 24.0 / 5.0, moments=(0.9, 0.95, 1.0))      # ω/n = 5: too slow to average over
    with pytest.raises(NotApplicableError) as info:
        api.precession(slow)
    assert info.value.ratio == pytest.approx(5.0, rel=1e-3)     # a year of 365.25 d against the Sun's n: 1e-4
    assert "ω/n" in str(info.value)


def test_order_beyond_the_laplace_limit_is_refused():
    b = Body("eccentric", Orbit(2.0, 0.7, 5, 10, 20, 30, 2451545.0), Pole(10, 40), 6.0, dynamical_ellipticity=0.1)
    with pytest.raises(InvalidInputError, match="Laplace"):
        api.nutation(b, order=8)
    assert api.nutation(b)["terms"]  # exact Hansen coefficients are fine


def test_track_sample_cap():
    with pytest.raises(InvalidInputError, match="cap"):
        api.track("vesta", 2451545.0, 2451545.0 + 1e6, 0.5)


def test_user_body_answers_have_finite_numbers():
    b = Body("my-asteroid", Orbit(2.36, 0.089, 7.14, 103.7, 151.7, 169.2, 2460200.5), Pole(309.03, 42.23), 5.342,
             moments=(0.3433, 0.3546, 0.42))
    ans = api.track(b, "2020-01-01", "2030-01-01", 10)
    json.dumps(ans, allow_nan=False)
    assert all(math.isfinite(x) for k in TRACK_KEYS for x in ans[k])


def test_demo_runs():
    res = runner.invoke(app, ["demo"])
    assert res.exit_code == 0 and "not applicable" not in res.stdout and "Vesta" in res.stdout
    moon = next(line for line in res.stdout.splitlines() if line.strip().startswith("Moon"))
    # the Moon's precession is its node's regression, 1934.14 deg per century plus the equinox's 1.397 deg
    # (Meeus 1998 eq. 47.7, IAU 2006 p_A): 69679.2″/yr, printed to 4 decimals
    assert float(moon.split()[-1]) == pytest.approx((1934.1362891 + 5028.796195 / 3600) * 36 / 1.0, rel=1e-9)


def test_cli_track_with_tolerance_reports_the_model_on_stderr():
    res = runner.invoke(app, ["track", "mars", "--start", "2000-01-01", "--stop", "2001-01-01", "--step-days", "30",
                              "--tolerance-mas", "1000", "--format", "csv"])
    assert res.exit_code == 0, res.output
    assert "model: " in res.stderr and "estimated error" in res.stderr
    res = runner.invoke(app, ["track", "vesta", "--start", "2000-01-01", "--stop", "2300-01-01", "--step-days", "365",
                              "--tolerance-mas", "1"])
    assert res.exit_code == 3 and "tolerance" in res.stderr


@pytest.mark.parametrize("body, tolerance", [("vesta", 100.0), ("earth", None), ("moon", 10000.0)])
def test_track_models_are_the_tracks_own_estimates(body, tolerance):
    """Speed against accuracy (api.track_models): the model a tolerance picks is the one the track takes, with
    the same estimate; a named model's listed estimate is its track's; every available model is priced."""
    args = ("2020-01-01", "2025-01-01", 10.0)
    table = api.track_models(body, *args, tolerance_mas=tolerance)
    assert table["epochs"] == len(api.track(body, *args)["jd_tdb"])
    available = [m for m in table["models"] if m["available"]]
    assert available and all(m["estimated_cpu_ms"] > 0 and m["estimated_error_mas"] > 0 for m in available)
    if tolerance is not None:
        (chosen,) = [m for m in table["models"] if m["chosen"]]
        got = api.track(body, *args, tolerance_mas=tolerance)["model"]
        assert (chosen["name"], chosen["order"]) == (got["name"], got["order"]) == (table["chosen"], got["order"])
        assert chosen["estimated_error_mas"] == pytest.approx(got["estimated_error_mas"], rel=1e-12)
        assert chosen["estimated_error_mas"] <= tolerance
        # the choice by cost (issue 39): no eligible model is predicted cheaper beyond the tie band, and within it
        # none is more accurate
        eligible = [m for m in available if m["eligible"]]
        assert all(m["estimated_error_mas"] <= tolerance for m in eligible) and chosen in eligible
        assert all(m["estimated_cpu_ms"] >= chosen["estimated_cpu_ms"] / (1.0 + TIE) for m in eligible)
        assert all(m["estimated_error_mas"] * (1.0 + SAME_ESTIMATE) >= chosen["estimated_error_mas"] for m in eligible
                   if m["estimated_cpu_ms"] <= chosen["estimated_cpu_ms"])
    plain = next(m for m in available if not m["free_wobble"] and not m["rotation_scale"] and m["order"] is None)
    named = api.track(body, *args, model=plain["name"])["model"]
    assert plain["estimated_error_mas"] == pytest.approx(named["estimated_error_mas"], rel=1e-12)
