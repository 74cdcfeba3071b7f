"""The free wobble served for catalogue bodies: exact, series and numerical solutions agree where they should."""
import math

import numpy as np
import pytest

from ephem.base.constants import ARCSEC
from ephem.bodies.catalogue import get_body
from ephem.base.errors import InvalidInputError, NotApplicableError
from ephem.rotation.free_motion import free_motion

J2000 = 2451545.0


def offsets(ans):
    """The figure axis's offsets from the angular momentum, arcsec."""
    return ans.figure_axis_offsets / ARCSEC


@pytest.mark.parametrize("name,J_arcsec,days", [("earth", None, 400.0), ("mars", None, 400.0), ("eros", None, 2.0),
                                                 ("eros", 20 * 3600.0, 2.0), ("vesta", 600.0, 2.0)])
def test_exact_and_numerical_solutions_agree(name, J_arcsec, days):
    t = J2000 + np.linspace(0.0, days, 41)
    exact = free_motion(get_body(name), t, J_arcsec, "exact")
    numeric = free_motion(get_body(name), t, J_arcsec, "numeric")
    gap = np.max(np.linalg.norm(offsets(exact) - offsets(numeric), axis=1))
    assert gap < 1e-8 * exact.J_arcsec + 1e-9, gap
    # at t0 the exact solution returns the J it was started with, through atan2 of rounded components: a few ε
    # relative to J (the components scale with sin J), so 1e-12 even for a 1" wobble
    assert exact.wobble_angle[0] / ARCSEC == pytest.approx(exact.J_arcsec, rel=1e-12)


@pytest.mark.parametrize("name,J_arcsec", [("eros", 55.0), ("eros", 4 * 3600.0), ("mars", 0.1), ("mars", 100.0),
                                            ("earth", 1.0), ("earth", 3600.0)])
def test_series_agrees_with_the_exact_solution(name, J_arcsec):
    t = J2000 + np.linspace(0.0, 50.0, 41)
    exact = free_motion(get_body(name), t, J_arcsec, "exact")
    series = free_motion(get_body(name), t, J_arcsec, "series")
    gap = np.max(np.linalg.norm(offsets(exact) - offsets(series), axis=1))
    assert gap < 1e-8 * J_arcsec, gap


def test_earth_rigid_euler_period_from_the_exact_solution():
    # Lara (2014) Table 1 inertia: the rigid-Earth Euler period is 2π/(ω κ), κ = √((C/A-1)(C/B-1)),
    # ≈ 303 days (sidereal days ≈ 304.5; the observed Chandler period, 433 d, includes elasticity)
    ans = free_motion(get_body("earth"), J2000 + np.array([0.0]), 1.0, "exact")
    a, b, c = get_body("earth").moments
    omega_days = 24.0 / get_body("earth").rotation_period_hours
    euler = 1.0 / (omega_days * math.sqrt((c / a - 1.0) * (c / b - 1.0)))
    assert ans.wobble_period_days == pytest.approx(euler, rel=1e-6)
    assert 300.0 < ans.wobble_period_days < 306.0


def test_auto_serves_the_exact_solution_and_the_series_only_where_it_converges():
    eros = get_body("eros")
    t = J2000 + np.linspace(0.0, 1.0, 5)
    assert free_motion(eros, t, 3600.0, "auto").method == "exact"       # cheapest and most accurate
    assert free_motion(eros, t, 3600.0, "series").method == "series"    # δ = 1.5e-4: served on request
    with pytest.raises(NotApplicableError, match="short-axis"):
        free_motion(eros, t, 60 * 3600.0, "series")                         # δ = 0.5: refused


@pytest.mark.parametrize("kwargs,field", [({"J_arcsec": -1.0}, "J_arcsec"), ({"J_arcsec": 700000.0}, "J_arcsec"),
                                          ({"J_arcsec": float("nan")}, "J_arcsec"), ({"method": "magic"}, "method")])
def test_bad_input_is_a_clear_error(kwargs, field):
    with pytest.raises(InvalidInputError) as info:
        free_motion(get_body("mars"), J2000 + np.array([0.0, 1.0]), **{"J_arcsec": 1.0, **kwargs})
    assert info.value.field == field


def test_bodies_without_moments_or_published_wobble_say_so():
    with pytest.raises(InvalidInputError, match="J"):
        free_motion(get_body("vesta"), J2000 + np.array([0.0]))   # no published J0 for Vesta


def test_route_and_cli_serve_the_free_motion():
    from fastapi.testclient import TestClient
    from typer.testing import CliRunner

    from ephem.cli import app as cli
    from service.app import app

    client = TestClient(app)
    r = client.get("/v1/bodies/earth/free-motion?start=2030-01-01&stop=2031-01-01&step_days=30")
    assert r.status_code == 200, r.text
    ans = r.json()
    assert ans["method"] == "exact" and ans["mode"] == "short-axis" and len(ans["jd_tdb"]) == 13
    assert 300.0 < ans["wobble_period_days"] < 306.0 and ans["J_arcsec"] == 1.0
    series = client.get("/v1/bodies/earth/free-motion?start=2030-01-01&stop=2031-01-01&step_days=30&method=series")
    assert series.json()["method"] == "series"
    assert np.allclose(series.json()["figure_axis_offset_x_arcsec"], ans["figure_axis_offset_x_arcsec"], atol=1e-8)
    bad = client.get("/v1/bodies/vesta/free-motion?start=2030-01-01&stop=2031-01-01&step_days=30")
    assert bad.status_code == 422 and bad.json()["errors"][0]["field"] == "J_arcsec"
    far = client.get("/v1/bodies/eros/free-motion?start=2030-01-01&stop=2030-01-02&step_days=1"
                     "&J_arcsec=300000&method=series")
    assert far.status_code == 422 and far.json()["title"] == "Not applicable"
    res = CliRunner().invoke(cli, ["free-motion", "mars", "--start", "2030-01-01", "--stop", "2030-01-05",
                                   "--step-days", "1", "--format", "csv"])
    assert res.exit_code == 0, res.output
    assert res.stdout.splitlines()[0].startswith("jd_tdb,utc_iso,figure_axis_offset_x_arcsec") and "wobble period" in res.stderr


def test_from_andoyer_keeps_an_arcsecond_wobble_exact():
    # sin J must not come from cos J = N/M: at J = 0.1" that loses 4e-4 of it to cancellation
    from ephem.rotation.euler_poinsot import FreeRotation
    J = 0.1 * math.pi / 648000.0
    rot = FreeRotation.from_andoyer((0.9942917, 0.9949813, 1.0), 6.1, J, 0.3, mu=0.2)
    f = rot.attitude(np.array([0.0]))[0][2]          # the C axis in inertial coordinates; L along +z
    # f[0], f[1] = sin J (sin μ, cos μ)-like products in which the other terms are exact zeros (the
    # invariable frame is the inertial one here), so J comes back to a few ε of itself: 1e-12 relative
    assert math.atan2(math.hypot(f[0], f[1]), f[2]) == pytest.approx(J, rel=1e-12)
