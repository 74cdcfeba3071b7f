"""The Moon through the one model interface (ephem.moon.family): every route, the CLI, the tables, the SPICE kernel
and a user's own synchronous satellite, with "not applicable" and its reason where the inputs do not allow the
theory."""
import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.answers import kernels as pck
from ephem.exports import tables
from ephem.bodies.catalogue import Body, Orbit, Pole, get_body
from ephem.cli import app as cli
from ephem.base.constants import JULIAN_YEAR_DAYS
from ephem.base.errors import NotApplicableError
from ephem.families import theory_for
from ephem.moon.family import SynchronousTheory

MOON = get_body("moon")
runner = CliRunner()


@pytest.fixture(scope="module")
def client():
    from fastapi.testclient import TestClient

    from service.app import create_app

    with TestClient(create_app()) as c:
        yield c


def _satellite(**orbit):
    """A Moon-like synchronous satellite of the user's own (the catalogue Moon's values)."""
    o = dict(a_au=MOON.orbit.a_au, e=0.0549, i_deg=5.145, node_deg=125.04, peri_deg=318.3, mean_anomaly_deg=134.96,
             epoch_jd_tdb=2451545.0, center="Earth", node_rate_deg_per_year=-19.3414)
    o.update(orbit)
    return Body("locked", Orbit(**o), Pole(266.86, 65.64), MOON.rotation_period_hours, moments=MOON.moments)


def test_the_registry_gives_the_moon_its_own_theory():
    assert isinstance(theory_for(MOON, MOON.perturbers).inner, SynchronousTheory)
    assert not isinstance(theory_for(get_body("vesta"), ("Sun",)).inner, SynchronousTheory)


def test_the_precession_answer_is_the_node_and_the_cassini_state():
    p = api.precession("moon")
    # the node's inertial regression: Meeus' 1934.1362891 deg/cy on the ecliptic of date plus the equinox's
    # precession 5028.796195″/cy (IAU 2006): both published constants, so 1e-9 relative (rounding)
    rate = (1934.1362891 * 3600.0 + 5028.796195) / 100.0
    assert p["precession_rate_arcsec_per_year"] == pytest.approx(rate, rel=1e-9)
    c = p["cassini"]
    assert c["node_period_years"] == pytest.approx(360.0 * 3600.0 / rate, rel=1e-9)
    # obliquity to the orbit = i + I (Cassini state 2), the served I the catalogue pole's
    assert p["obliquity_deg"] == pytest.approx(5.145 + c["equator_inclination_deg"], abs=1e-9)
    assert c["derived_obliquity_deg"] == pytest.approx(5.145 + c["derived_equator_inclination_deg"], abs=1e-9)
    assert p["model"]["name"] in SynchronousTheory.models
    # the node's rate and the catalogue pole have no published σ: unknown, with the record's reasons
    assert p["precession_rate_arcsec_per_year_uncertainty"] is None and p["obliquity_deg_uncertainty"] is None
    assert {"orbit.node_rate", "pole.ra"} <= set(p["uncertainty"]["no_uncertainty_reasons"])


def test_the_moons_moment_uncertainties_come_from_lunar_laser_ranging():
    """H_d's and K's 1σ from β, γ's (Williams et al. 2014) with the correlation their derivation gives A and B,
    against 4000 samples of β and γ through the moments and the model's own K formula: the sampled σ's
    relative standard error 1/sqrt(2(N-1)) = 1.1 %, four of them 4.5 %."""
    from ephem.bodies.inertia import moments_from_libration

    p = api.precession("moon")
    rng = np.random.default_rng(11)
    hd, k = [], []
    for beta, gamma in zip(631.0213e-6 + 0.0031e-6 * rng.standard_normal(4000),
                           227.7317e-6 + 0.0042e-6 * rng.standard_normal(4000)):
        A, B, C = moments_from_libration(beta, gamma)
        hd.append((C - 0.5 * (A + B)) / C)
        k.append((C - A) / C)
    assert p["dynamical_ellipticity_uncertainty"] == pytest.approx(np.std(hd, ddof=1), rel=0.045)
    rel_k = np.std(k, ddof=1) / np.mean(k)
    assert p["scaling_factor_arcsec_per_year_uncertainty"] / p["scaling_factor_arcsec_per_year"] == \
        pytest.approx(rel_k, rel=0.045)


def test_the_track_turns_with_the_node():
    """Over one node period (18.6 yr) the mean rotation axis circles the ecliptic pole of date once: its ecliptic
    longitude of date advances by −360° and stays 90° ahead of the node (Cassini's third law) at the observed
    inclination, up to its lag behind the moving ecliptic (ephem.moon.orientation: 7.3″ on the sky)."""
    import erfa

    tr = api.track_arrays("moon", 2451545.0, 2451545.0 + 6798.38, 50.0, model="cassini", axis="mean_rotation")
    ra, dec = np.radians(tr["pole_ra_deg"]), np.radians(tr["pole_dec_deg"])
    v = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)
    ecl = np.einsum("nij,nj->ni", erfa.ecm06(tr["jd_tdb"], 0.0 * tr["jd_tdb"]), v)
    lon = np.unwrap(np.arctan2(ecl[:, 1], ecl[:, 0]))
    T = (tr["jd_tdb"] - 2451545.0) / 36525.0
    node = np.radians(125.0445479 - 1934.1362891 * T)
    offset = np.degrees(np.remainder(lon - node - math.pi / 2 + math.pi, 2 * math.pi) - math.pi)
    incl = np.degrees(np.arccos(ecl[:, 2]))
    lag = 7.5 / 3600.0          # the lag's 7.33″ and the Delaunay node's T² terms against this linear node
    assert np.abs(offset * np.sin(np.radians(incl))).max() < lag
    assert np.abs(incl - 1.54242).max() < lag


def test_the_figure_axis_circles_the_mean_rotation_axis_monthly():
    """The principal axis of largest inertia is the mean rotation frame turned by DE421's constant PA–ME rotation:
    78.56″ from the mean rotation axis at every epoch (the frame kernel's 78.56″ about Y and 0.30″ about X), toward
    the mean Earth, so it circles it once a month in space."""
    fig = api.track_arrays("moon", "2024-01-01", "2024-03-01", 0.5, model="librations", axis="figure")
    mean = api.track_arrays("moon", "2024-01-01", "2024-03-01", 0.5, model="librations", axis="mean_rotation")

    def vec(tr):
        ra, dec = np.radians(tr["pole_ra_deg"]), np.radians(tr["pole_dec_deg"])
        return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)

    a, b = vec(fig), vec(mean)
    angle = np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))) * 3600.0
    assert np.abs(angle - math.hypot(78.56, 0.30)).max() < 0.01        # the small-rotation pole: 1e-9 rad
    # a monthly circle: the direction from the mean pole turns through 360° in a sidereal month (27.32 d)
    d = a - b
    d -= np.sum(d * b, axis=-1, keepdims=True) * b
    east = np.cross([0.0, 0.0, 1.0], b)
    east /= np.linalg.norm(east, axis=-1, keepdims=True)
    turn = np.unwrap(np.arctan2(np.sum(d * east, axis=-1), np.sum(d * np.cross(b, east), axis=-1)))
    period = 2.0 * math.pi / abs(np.polyfit(fig["jd_tdb"], turn, 1)[0])
    assert period == pytest.approx(27.32, abs=0.2)


@pytest.mark.parametrize("route", ["precession", "nutation", "track?start=2020-01-01&stop=2021-01-01&step_days=10",
                                   "track.png?start=2020-01-01&stop=2021-01-01"])
def test_every_route_answers(client, route):
    r = client.get(f"/v1/bodies/moon/{route}")
    assert r.status_code == 200, r.text


@pytest.mark.parametrize("args", [["precession", "moon"], ["nutation", "moon"],
                                  ["track", "moon", "--start", "2020-01-01", "--stop", "2020-02-01",
                                   "--step-days", "10"]])
def test_every_command_answers(args):
    res = runner.invoke(cli, args)
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["body"] == "Moon"


def test_tables_and_kernel_answer(tmp_path):
    out = runner.invoke(cli, ["tables", "moon", "--out", str(tmp_path)])
    assert out.exit_code == 0 and "wrote" in out.stdout and (tmp_path / "moon_current_sin-cos.csv").exists()
    # one row per term and component (longitude, obliquity)
    assert len(tables.table_rows(api.nutation("moon"))) == 2 * len(api.nutation("moon")["terms"])
    res = pck.write_pck(["Moon"], "2020-01-01", "2030-01-01")
    fit = res.bodies[0]
    assert "BODY301_POLE_RA" in res.text and fit.model["name"] in SynchronousTheory.models


def test_a_users_synchronous_satellite_gets_the_same_theory(client):
    b = _satellite()
    p = api.precession(b)
    assert p["model"]["name"] in SynchronousTheory.models
    assert p["precession_rate_arcsec_per_year"] == pytest.approx(19.3414 * 3600.0, rel=1e-12)   # J2000 frame
    body = {"name": "locked", "orbit": {"a_au": MOON.orbit.a_au, "e": 0.0549, "i_deg": 5.145, "node_deg": 125.04,
                                        "peri_deg": 318.3, "mean_anomaly_deg": 134.96, "epoch_jd_tdb": 2451545.0,
                                        "center": "Earth", "node_rate_deg_per_year": -19.3414},
            "pole": {"ra_deg": 266.86, "dec_deg": 65.64}, "rotation_period_hours": MOON.rotation_period_hours,
            "moments": {"A": MOON.moments[0], "B": MOON.moments[1], "C": MOON.moments[2]},
            "track": {"start": "2020-01-01", "stop": "2020-03-01", "step_days": 10}}
    r = client.post("/v1/precession-nutation", json=body)
    assert r.status_code == 200, r.text
    assert r.json()["precession"]["cassini"]["derived_equator_inclination_deg"] == \
        pytest.approx(p["cassini"]["derived_equator_inclination_deg"], rel=1e-12)


@pytest.mark.parametrize("change, reason", [
    (dict(node_rate_deg_per_year=None), "node's rate"),
    (dict(node_rate_deg_per_year=+19.3), "regress"),
    (dict(i_deg=0.0), "i = 0"),
])
def test_a_satellite_outside_the_theory_is_not_applicable_with_the_reason(change, reason):
    with pytest.raises(NotApplicableError, match=reason):
        api.precession(_satellite(**change))


def test_a_satellite_without_moments_is_not_applicable():
    b = _satellite()
    b = Body(b.name, b.orbit, b.pole, b.rotation_period_hours, dynamical_ellipticity=5e-4)
    with pytest.raises(NotApplicableError, match="three principal moments"):
        api.track(b, "2020-01-01", "2020-02-01", 10.0)


def test_the_nutation_answer_is_the_libration_series():
    n = api.nutation("moon")
    assert n["model"]["name"] == "librations" and n["terms"][0]["delaunay_multipliers"] == [1, 0, 0, 0, 0]
    # Eckhardt (1981) via Meeus (1998 ch. 53): ρ = −0.02752° cos l, σ = −0.02816° sin l; our rigid series with the
    # catalogue's moments is within 2″ of them (tests/moon/test_physical_librations.py holds the per-term budgets)
    l_term = n["terms"][0]
    assert l_term["obliquity_cos_arcsec"] == pytest.approx(-0.02752 * 3600.0, abs=2.0)
    assert l_term["longitude_sin_arcsec"] == pytest.approx(-0.02816 * 3600.0, abs=2.0)
    # a tolerance picks the largest cut whose omitted terms stay within it
    cut = api.nutation("moon", tolerance_mas=1000.0)
    assert cut["model"]["estimated_error_mas"] <= 1000.0 and len(cut["terms"]) < len(n["terms"])


def test_the_ladder_orders_its_estimates():
    tr = {m: api.track_arrays("moon", "2020-01-01", "2022-01-01", 30.0, model=m)["model"]
          for m in SynchronousTheory.models}
    est = {m: tr[m]["estimated_error_mas"] for m in tr}
    assert est["de421"] < est["librations"] < est["integration"] < est["cassini"]
    # within the librations' estimate: the cheaper of it and DE421's kernel (read here: kept, so cheap)
    tol = est["librations"] * 1.01
    costs = {r["name"]: r["estimated_cpu_ms"] for r in
             api.track_models("moon", "2020-01-01", "2022-01-01", 30.0, tolerance_mas=tol)["models"]}
    assert api.track_arrays("moon", "2020-01-01", "2022-01-01", 30.0, tolerance_mas=tol)["model"]["name"] == \
        min(("librations", "de421"), key=costs.get)
    with pytest.raises(NotApplicableError, match="no model meets the tolerance"):
        api.track_arrays("moon", "2020-01-01", "2022-01-01", 30.0, tolerance_mas=1.0)


def test_a_users_satellite_has_the_bare_cassini_state_only():
    b = _satellite()
    tr = api.track(b, "2020-01-01", "2020-03-01", 10.0)
    assert tr["model"]["name"] == "cassini" and any("librations" in w for w in tr["model"]["warnings"])
    with pytest.raises(NotApplicableError, match="Moon only"):
        api.track(b, "2020-01-01", "2020-03-01", 10.0, model="librations")


def test_an_e_order_is_refused_with_the_reason():
    with pytest.raises(NotApplicableError, match="e-order"):
        api.precession("moon", order=4)


def test_the_moons_precession_rate_is_its_node_in_the_track():
    tr = api.track_arrays("moon", 2451545.0, 2451545.0 + 3652.5, 365.25)
    rate = np.diff(tr["psi_arcsec"]) / 365.25 * JULIAN_YEAR_DAYS
    p = api.precession("moon")
    # ψ is the inertial angle the rate describes: equal to rounding (ψ ~ 1e6″ held to 1e-16 relative)
    np.testing.assert_allclose(rate, p["precession_rate_arcsec_per_year"], rtol=1e-10)
