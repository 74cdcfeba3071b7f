"""The Earth under the Moon and the Sun, served (ephem.earth.family, issue 7): the catalogue's perturbers, the
lunisolar answers of ephem.api, the CLI and the service, and the Sun-only answer reproduced.

Against IAU 2006/2000A: as ERFA computes it (the rate, the track against the CIP within the estimate, the
estimate's ingredients), tests/earth/test_against_erfa.py; as published (ε_A, the leading terms),
tests/earth/test_against_iau2006.py.
"""
import csv
import dataclasses
import io
import json
import math

import numpy as np
import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from ephem import api
from ephem.bodies.catalogue import get_body, parse_catalogue, resolve_perturbers
from ephem.cli import app as cli
from ephem.base.errors import InvalidInputError, NotApplicableError
from ephem.earth.lunisolar import earth_lunisolar
from ephem.orbit.lunar import DELAUNAY_NAMES
from ephem.base.constants import ARCSEC
from ephem.forced.precession_nutation import cached_model
from ephem.orbit.geometry import unit_vector
from service.app import app as web
from tests.bodies.test_catalogue import GOOD


@pytest.fixture(scope="module")
def client():
    return TestClient(web)


def without_cost(d: dict) -> dict:
    d = json.loads(json.dumps(d, default=float))
    d["model"].pop("cost_ms")
    return d


# ----------------------------------------------------------------------------- perturbers

def test_catalogue_lists_the_perturbers():
    assert get_body("earth").perturbers == ("Moon", "Sun")
    assert get_body("earth", "petit2014").perturbers == ("Moon", "Sun")
    assert get_body("vesta").perturbers == ("Sun",)            # default: the orbit's centre
    assert get_body("moon").perturbers == ("Earth",)
    assert hash(get_body("earth")) == hash(get_body("earth"))    # still a cache key
    assert api.body_record("earth")["perturbers"] == ["Moon", "Sun"]
    assert TestClient(web).get("/v1/bodies/earth").json()["perturbers"] == ["Moon", "Sun"]


@pytest.mark.parametrize("given, expected", [
    ("sun", ("Sun",)), (["Sun"], ("Sun",)), ("moon,sun", ("Moon", "Sun")), ("Sun, MOON", ("Sun", "Moon")),
    (("moon",), ("Moon",)), (None, ("Moon", "Sun"))])
def test_perturbers_parse(given, expected):
    assert resolve_perturbers(given, get_body("earth")) == expected if given is not None else \
        get_body("earth").perturbers == expected


@pytest.mark.parametrize("given", ["jupiter", "sun,sun", "", ",", ["Sun", 3], 42, "moon;sun"])
def test_bad_perturbers_name_the_field(given):
    with pytest.raises(InvalidInputError) as info:
        api.precession("earth", perturbers=given)
    assert info.value.field == "perturbers"


@pytest.mark.parametrize("body, given, why", [("vesta", "moon,sun", "Earth only"), ("vesta", "earth", "centre"),
                                              ("mars", ["Moon"], "Earth only")])
def test_only_the_earth_has_the_moon(body, given, why):
    with pytest.raises(NotApplicableError, match=why):
        api.precession(body, perturbers=given)


def test_catalogue_records_are_validated():
    ok = parse_catalogue(GOOD + 'perturbers = ["sun"]\n', "t").get("Testa")
    assert ok.perturbers == ("Sun",)
    with pytest.raises(InvalidInputError, match="perturbers"):
        parse_catalogue(GOOD.replace('naif_id = 2999999', 'naif_id = 2999999\nperturbers = ["Jupiter"]'), "t")
    with pytest.raises(InvalidInputError, match="perturbers"):
        parse_catalogue(GOOD.replace('naif_id = 2999999', 'naif_id = 2999999\nperturbers = "Sun"'), "t")
    with pytest.raises(NotApplicableError, match="Earth only"):
        parse_catalogue(GOOD.replace('naif_id = 2999999', 'naif_id = 2999999\nperturbers = ["Moon", "Sun"]'), "t")


# ----------------------------------------------------------------------------- the Sun alone, as before

# What "the same number" means between machines: these answers pass through libm (sin, cos, atan2, ...)
# and numpy's SIMD and BLAS paths, each of which may round differently by an ulp or a few on another
# CPU or library version (the obliquity's last digit did: 23.43780785233491 against ...902). Their
# condition number is at most ~400: H_d = (C − (A+B)/2)/C = 0.0033 for the Earth cancels 2.5 digits,
# and nudging every catalogue input by 4 ulp moves each value below by ≤ 3.4e-13 (measured). So ~10
# such roundings give ≤ 10 × 400 × 2.2e-16 ≈ 1e-12 relative. Any real change (a term, a constant,
# the H_d of issue 7, 0.16 % away) moves them by more than 1e-6.
SAME = 1e-12


def same(reference, scale=None):
    """pytest.approx at the rounding budget SAME, relative to ``scale`` (the size of the sum a small
    coefficient comes out of) where it is given."""
    return pytest.approx(reference, rel=SAME, abs=SAME * (scale or 0.0))


def test_sun_only_reproduces_the_answers_before_the_moon():
    """Numbers served before issue 7 (Earth, Sun only, the H_d its moments imply), to rounding."""
    lara = dataclasses.replace(get_body("earth"), dynamical_ellipticity=None)   # the H_d of before
    for given in ("sun", ["sun"], ("Sun",)):
        p = api.precession(lara, perturbers=given)
        assert p["precession_rate_arcsec_per_year"] == same(15.973916758113933)
        assert p["obliquity_deg"] == same(23.437807852334902)
        assert p["scaling_factor_arcsec_per_year"] == same(34.80623162553889)
    n = api.nutation(lara, perturbers="sun")
    # the coefficients are sums over the Hansen harmonics: their rounding is relative to the whole
    # nutation (1.4" half peak-to-peak), not to a small term such as 0.008"
    half = 1.3788520955177874
    assert n["delta_psi_half_peak_to_peak_arcsec"] == same(half)
    assert [t["multiple"] for t in n["terms"][:2]] == [1, 2]
    assert [(t["longitude_sin_arcsec"], t["obliquity_cos_arcsec"]) for t in n["terms"][:2]] == \
        [(same(0.10833996482316119, half), same(0.008283012872339849, half)),
         (same(1.1441473772961002, half), same(-0.4953209952043133, half))]
    tr = api.track(lara, "2020-01-01", "2020-03-01", 10.0, perturbers="sun")
    # UTC -> TDB: a few additions on a JD of 2.46e6 days, whose ulp is 4.7e-10 d; 1e-9 d (86 µs) is two
    # ulp, far below the 1.7 ms of TDB − TT or a leap second
    assert tr["jd_tdb"][1] == pytest.approx(2458859.5008007395, abs=1e-9)
    # ψ moves 0.044"/day, so the JD's 1e-9 d adds 4e-11" (1e-13 relative): within SAME. Issue 32 added the
    # geodesic precession to every track: the torque's ψ of before less Ω_gp (t − t0) (ephem.orbit.relativity), and
    # the pole of before turned by that angle about the orbit normal
    model = cached_model(lara)
    turned = model.geodesic_rate * (tr["jd_tdb"][1] - model.pole_epoch)
    assert tr["psi_arcsec"][1] == same(320.73920856302135 - turned / ARCSEC)
    # the pole is 0.034° from the ICRF pole: its RA is 1/cos(dec) = 1700 times worse conditioned than the
    # direction, so compare the direction to SAME radians
    before = unit_vector(math.radians(357.2904923584953), math.radians(89.96611899848224))
    normal = model.icrf_from_orbit[:, 2]
    expected = before * math.cos(turned) + np.cross(normal, before) * math.sin(turned) + \
        normal * (normal @ before) * (1.0 - math.cos(turned))
    served = unit_vector(math.radians(tr["pole_ra_deg"][1]), math.radians(tr["pole_dec_deg"][1]))
    assert float(np.linalg.norm(served - expected)) < SAME
    # issue 15 moved two terms: rotation_averaging is ephem.forced.rotation_scale's (11.678 mas, the drift at its measured
    # factor; 11.871 from ephem.forced.rigid_body's older bound) and second_order the ladder's span-aware bound (2.244 mas over
    # these two months; 7.753 before). The estimate was 1069.9952992958686; issue 32 added the geodesic term
    geodesic = tr["model"]["error_terms_mas"]["geodesic"]
    assert tr["model"]["name"] == "hansen" and tr["model"]["estimated_error_mas"] == same(1064.2934460185702 + geodesic)
    assert tr["model"]["error_terms_mas"]["orbit_motion"] == same(50.371370081093275, 1069.8)
    # petit2014's Earth was not given an explicit H_d: its Sun-only answer is unchanged as it stands
    p = api.precession("earth", dataset="petit2014", perturbers="sun")
    assert p["precession_rate_arcsec_per_year"] == same(15.973722824565026)
    for ans in (p, n, tr):
        assert ans["perturbers"] == ["Sun"] and any("leaves out the Moon" in w for w in ans["model"]["warnings"])


@pytest.mark.parametrize("name", ["vesta", "ceres", "itokawa", "mars"])
def test_the_default_is_the_sun_alone_for_other_bodies(name):
    for fn in (api.precession, api.nutation):
        default = without_cost(fn(name))
        # the same computation on the same inputs in one process (the perturbers resolve to the same tuple):
        # bit-identical by construction, so the whole answer compares exactly
        assert default == without_cost(fn(name, perturbers="sun")) == without_cost(fn(name, perturbers=["Sun"]))
        assert default["perturbers"] == ["Sun"] and not any("Moon" in w for w in default["model"]["warnings"])


def test_the_explicit_hd_only_rescales_the_sun_only_earth():
    # the catalogue now carries IERS 2010's H_d; the Sun-only rate scales with it (ψ̇ ∝ K ∝ H_d)
    now = api.precession("earth", perturbers="sun")
    lara = api.precession(dataclasses.replace(get_body("earth"), dynamical_ellipticity=None), perturbers="sun")
    b = get_body("earth")
    # read from the catalogue and passed through with no arithmetic: equal to the parse's rounding (1 ulp)
    assert now["dynamical_ellipticity"] == pytest.approx(0.0032737949, rel=1e-15) and b.hd_from_moments == pytest.approx(0.0032789, abs=1e-7)
    assert now["precession_rate_arcsec_per_year"] / lara["precession_rate_arcsec_per_year"] == \
        pytest.approx(b.hd / b.hd_from_moments, rel=1e-6)


# ----------------------------------------------------------------------------- precession

@pytest.fixture(scope="module")
def prec():
    return api.precession("earth")


def test_the_moon_makes_two_thirds_of_it(prec):
    moon = api.precession("earth", perturbers="moon")["precession_rate_arcsec_per_year"]
    sun = earth_lunisolar(perturbers=("sun",)).precession_rate_arcsec_per_year
    # first order: linear, so the sum of the two one-perturber rates is the rate, up to the rounding of the
    # forcing spectra (three FFTs, ~1e-14 of the largest coefficient each) and of the sum (measured 1e-16): 1e-12
    assert moon + sun == pytest.approx(prec["precession_rate_arcsec_per_year"], rel=1e-12)
    assert moon / prec["precession_rate_arcsec_per_year"] == pytest.approx(0.684, abs=0.005)
    # the Sun alone, in the lunisolar theory and in the single-perturber one, agree (docs/earth.md: 6.5e-6)
    assert sun == pytest.approx(api.precession("earth", perturbers="sun")["precession_rate_arcsec_per_year"],
                                rel=2e-5)


def test_the_answer_says_which_hd_and_why(prec):
    info = prec["model"]
    assert prec["dynamical_ellipticity"] == pytest.approx(0.0032737949, rel=1e-15)   # the catalogue's, no arithmetic
    assert any("H_d = 0.0032737949 from the catalogue's explicit dynamical ellipticity (source iers2010_table1_1)" in a
               for a in info["assumptions"])
    assert any("given explicitly" in w and "0.0032789" in w and "Lara" in w for w in info["warnings"])
    assert any("ψ_A rate 50.384815" in a for a in info["assumptions"])


def test_uncertainties_follow_hd_as_a_perturbed_earth_confirms(prec):
    """Each value's 1σ is |∂value/∂H_d| × IERS 2010's σ(H_d) = 1e-9: the answer takes every value as
    proportional to H_d (the mean obliquity through the nutation at the pole epoch); an Earth with H_d 1e-4
    larger, through the whole lunisolar model, gives the derivatives independently (a difference quotient:
    its truncation, second order in 1e-4, and rounding stay below 1e-3 relative)."""
    earth = get_body("earth")
    step = 1e-4 * earth.hd
    bumped = api.precession(dataclasses.replace(earth, dynamical_ellipticity=earth.hd + step))
    for key in ("obliquity_deg", "scaling_factor_arcsec_per_year", "precession_rate_arcsec_per_year"):
        derivative = (bumped[key] - prec[key]) / step
        assert prec[f"{key}_uncertainty"] == pytest.approx(abs(derivative) * 1e-9, rel=1e-3), key
    assert prec["dynamical_ellipticity_uncertainty"] == pytest.approx(1e-9, rel=1e-12)
    u = prec["uncertainty"]
    assert "pole.ra" in u["unpropagated_inputs"] and "IAU 2006/2000A" in u["no_uncertainty_reasons"]["pole.ra"]
    assert "inertia.dynamical_ellipticity" not in u["unpropagated_inputs"]


def test_order_is_not_the_lunisolar_theorys():
    with pytest.raises(NotApplicableError, match="perturbers=sun"):
        api.precession("earth", order=4)
    assert api.precession("earth", order=4, perturbers="sun")["model"]["order"] == 4


# ----------------------------------------------------------------------------- nutation

@pytest.fixture(scope="module")
def nut():
    return api.nutation("earth")


def test_nutation_terms_carry_delaunay_multipliers(nut):
    series = earth_lunisolar(hd="iers2010")
    assert nut["argument"] == "Delaunay arguments l, l′, F, D, Ω (IERS 2010 eq. 5.43)"
    assert len(nut["terms"]) == len(series.terms) == 82 and nut["model"]["cut_mas"] == 0.1
    for t, s in zip(nut["terms"], series.terms):
        assert t["multiple"] is None and t["delaunay_multipliers"] == s["delaunay_multipliers"]
        assert len(t["delaunay_multipliers"]) == 5 and all(isinstance(k, int) for k in t["delaunay_multipliers"])
        # arcsec from mas: one division by 1e3 here and one multiplication there, ≤ 1 ulp; rel 1e-15 = 4.5 ε
        for comp in ("longitude", "obliquity"):
            for part in ("sin", "cos"):
                assert t[f"{comp}_{part}_arcsec"] * 1e3 == pytest.approx(s[f"{comp}_{part}_mas"], rel=1e-15)
                assert t[f"{comp}_{part}_rate_arcsec_per_century"] * 1e3 == \
                    pytest.approx(s[f"{comp}_{part}_rate_mas_per_century"], rel=1e-15)
        assert t["period_days"] == s["period_days"] and t["period_days_uncertainty"] is None
        amp = math.hypot(t["longitude_sin_arcsec"], t["longitude_cos_arcsec"]) * math.sin(math.radians(nut["obliquity_deg"]))
        assert t["longitude_amplitude_arcsec"] == pytest.approx(amp, rel=1e-12)   # hypot, sin, deg->rad: a few ε
        assert max(math.hypot(t[f"{c}_sin_arcsec"], t[f"{c}_cos_arcsec"]) for c in ("longitude", "obliquity")) \
            >= 0.1e-3 - 1e-15


def test_the_cut_and_the_tolerance(nut):
    coarse = api.nutation("earth", cut_mas=1.0)
    assert len(coarse["terms"]) == 34 and coarse["model"]["cut_mas"] == 1.0
    assert coarse["model"]["estimated_error_mas"] > nut["model"]["estimated_error_mas"] > 0.0
    for tol in (0.5, 50.0):
        ans = api.nutation("earth", tolerance_mas=tol)
        assert ans["model"]["estimated_error_mas"] <= tol and ans["model"]["tolerance_mas"] == tol
    # the estimate is the omitted terms' whole pole displacement: check it against the cut-free series
    full = earth_lunisolar(cut_mas=0.0, hd="iers2010")
    kept = {tuple(t["delaunay_multipliers"]) for t in coarse["terms"]}
    se = math.sin(math.radians(coarse["obliquity_deg"]))
    omitted = sum(se * math.hypot(t["longitude_sin_mas"], t["longitude_cos_mas"])
                  + math.hypot(t["obliquity_sin_mas"], t["obliquity_cos_mas"])
                  for t in full.terms if tuple(t["delaunay_multipliers"]) not in kept)
    # 17125 omitted terms summed in another order, and sin ε from the served (rounded) degrees: measured 1e-14
    # (N ε would be 4e-12 at worst): 1e-11
    assert coarse["model"]["estimated_error_mas"] == pytest.approx(omitted, rel=1e-11)


@pytest.mark.parametrize("kwargs, field", [({"cut_mas": 0.0}, "cut_mas"), ({"cut_mas": float("nan")}, "cut_mas"),
                                           ({"cut_mas": -1}, "cut_mas"), ({"cut_mas": 1, "tolerance_mas": 1}, "cut_mas"),
                                           ({"cut_mas": "big"}, "cut_mas")])
def test_bad_cut_names_the_field(kwargs, field):
    with pytest.raises(InvalidInputError) as info:
        api.nutation("earth", **kwargs)
    assert info.value.field == field


def test_a_cut_is_for_the_lunisolar_series_only():
    with pytest.raises(InvalidInputError, match="cut_mas"):
        api.nutation("vesta", cut_mas=0.1)
    with pytest.raises(NotApplicableError, match="smallest served"):
        api.nutation("earth", tolerance_mas=1e-6)


# ----------------------------------------------------------------------------- the track

def test_free_wobble_for_the_lunisolar_earth():
    near = dict(free_wobble_phase_deg=30.0, free_wobble_epoch="2020-01-15")
    wob = api.track_arrays("earth", "2020-01-01", "2020-02-01", 1.0, tolerance_mas=500, **near)
    # over 32 epochs the rigid and the non-rigid tracks cost alike (data/cost_model.toml): a tie the more accurate
    # may win (ephem.theory.choice); the wobble is the same on either
    assert wob["model"]["name"] in ("lunisolar", "nonrigid") and wob["model"]["free_wobble"]["J_arcsec"] == 1.0
    plain = api.track_arrays("earth", "2020-01-01", "2020-02-01", 1.0, model=wob["model"]["name"])
    assert wob["model"]["estimated_error_mas"] <= 500 and "free_wobble_model" in wob["model"]["error_terms_mas"]
    shift = np.hypot((wob["pole_ra_deg"] - plain["pole_ra_deg"]) * np.cos(np.radians(plain["pole_dec_deg"])),
                     wob["pole_dec_deg"] - plain["pole_dec_deg"]) * 3600.0
    assert shift == pytest.approx(np.ones_like(shift), abs=0.01)        # the figure axis 1" from L
    assert api.track_arrays("earth", "2020-01-01", "2020-02-01", 1.0, tolerance_mas=1500, **near)["model"][
        "free_wobble"] is None                                          # not needed: not added
    with pytest.raises(InvalidInputError, match="free_wobble_phase_deg"):
        api.track("earth", "2020-01-01", "2020-02-01", 1.0, axis="angular_momentum", free_wobble_phase_deg=0.0)
    with pytest.raises(NotApplicableError, match="free_wobble_phase_deg"):
        api.track("earth", "2020-01-01", "2020-02-01", 1.0, tolerance_mas=500)


def test_outside_the_measured_window_is_not_applicable():
    with pytest.raises(NotApplicableError, match="1900-01-01 to 2100-01-01"):
        api.track("earth", "2099-01-01", "2101-01-01", 30.0)
    with pytest.raises(NotApplicableError, match="Moon and the Sun"):
        api.track("earth", "2000-01-01", "2001-01-01", 30.0, perturbers="moon")
    assert api.track("earth", "2099-01-01", "2101-01-01", 30.0, perturbers="sun")["model"]["name"] == "hansen"


@pytest.mark.parametrize("kwargs, error, match", [
    ({"model": "hansen"}, NotApplicableError, "perturbers=sun"),
    ({"order": 4}, NotApplicableError, "cut by amplitude"),
    ({"model": "nonsense"}, InvalidInputError, "lunisolar"),
    ({"model": "lunisolar", "perturbers": "sun"}, NotApplicableError, "single-perturber"),
])
def test_models_and_perturbers_must_agree(kwargs, error, match):
    with pytest.raises(error, match=match):
        api.track("earth", "2000-01-01", "2001-01-01", 30.0, **kwargs)


def test_named_lunisolar_model_is_the_default():
    a = api.track_arrays("earth", "2000-01-01", "2001-01-01", 30.0)
    b = api.track_arrays("earth", "2000-01-01", "2001-01-01", 30.0, model="lunisolar")
    # the default is that model: the same computation in one process, bit-identical by construction
    assert np.array_equal(a["pole_ra_deg"], b["pole_ra_deg"]) and b["obliquity_deg_uncertainty"] is None


# ----------------------------------------------------------------------------- the Moon

@pytest.mark.parametrize("perturbers", [None, "earth"])
def test_the_moon_is_served_by_its_cassini_state(perturbers):
    ans = api.precession("moon", perturbers=perturbers)
    assert ans["model"]["name"] in ("cassini", "librations") and ans["perturbers"] == ["Earth"]


def test_the_moon_under_other_perturbers_says_why():
    with pytest.raises(NotApplicableError, match="the Moon as a perturber is modelled for the Earth only"):
        api.precession("moon", perturbers="moon,sun")
    # the Sun alone leaves out the Earth, whose torque the Cassini state balances
    with pytest.raises(NotApplicableError, match="Sun is not the orbit's centre"):
        api.precession("moon", perturbers="sun")


# ----------------------------------------------------------------------------- CLI and service

def test_cli():
    r = CliRunner().invoke(cli, ["precession", "earth", "--perturbers", "sun", "--format", "csv"])
    assert r.exit_code == 0 and float(list(csv.DictReader(io.StringIO(r.stdout)))[0][
        "precession_rate_arcsec_per_year"]) == pytest.approx(15.949, abs=1e-3)
    r = CliRunner().invoke(cli, ["precession", "earth"])
    assert r.exit_code == 0 and json.loads(r.stdout)["precession_rate_arcsec_per_year"] == pytest.approx(50.4043, abs=1e-4)
    r = CliRunner().invoke(cli, ["nutation", "earth", "--format", "csv", "--cut-mas", "1"])
    rows = list(csv.DictReader(io.StringIO(r.stdout)))
    assert r.exit_code == 0 and len(rows) == 34 and [rows[0][c] for c in DELAUNAY_NAMES] == ["0", "0", "0", "0", "1"]
    r = CliRunner().invoke(cli, ["track", "earth", "--start", "2020-01-01", "--stop", "2020-03-01", "--step-days",
                                 "30", "--perturbers", "moon,sun", "--format", "csv"])
    assert r.exit_code == 0 and "model: lunisolar" in r.stderr
    r = CliRunner().invoke(cli, ["precession", "earth", "--perturbers", "pluto"])
    assert r.exit_code == 2 and "perturbers" in r.stderr


def test_routes(client):
    p = client.get("/v1/bodies/earth/precession").json()
    assert p["perturbers"] == ["Moon", "Sun"] and p["model"]["name"] == "lunisolar"
    assert p["precession_rate_arcsec_per_year"] == pytest.approx(50.4043, abs=1e-4)
    sun = client.get("/v1/bodies/earth/precession?perturbers=sun").json()
    lib = without_cost(api.precession("earth", perturbers="sun"))
    sun["model"].pop("cost_ms")
    assert sun == lib     # the route calls the library in this process and JSON round-trips floats exactly
    n = client.get("/v1/bodies/earth/nutation?cut_mas=1").json()
    assert len(n["terms"]) == 34 and n["terms"][0]["delaunay_multipliers"] == [0, 0, 0, 0, 1]
    assert n["terms"][0]["multiple"] is None
    assert "delaunay_multipliers" not in client.get("/v1/bodies/earth/nutation?perturbers=sun").json()["terms"][0]
    csv_text = client.get("/v1/bodies/earth/nutation?format=csv&layout=amp-period").text
    assert csv_text.startswith("component,arg,l,l',F,D,Omega,amp_mas")
    tr = client.get("/v1/bodies/earth/track?start=2020-01-01&stop=2020-03-01&step_days=10").json()
    assert tr["model"]["name"] == "lunisolar" and tr["perturbers"] == ["Moon", "Sun"]
    assert client.get("/v1/bodies/earth/track?start=2020-01-01&stop=2020-03-01&step_days=10&perturbers=sun"
                      ).json()["model"]["name"] == "hansen"


@pytest.mark.parametrize("url, status, field", [
    ("/v1/bodies/earth/precession?perturbers=pluto", 422, "perturbers"),
    ("/v1/bodies/earth/nutation?perturbers=sun,sun", 422, "perturbers"),
    ("/v1/bodies/earth/track?start=2020-01-01&stop=2020-02-01&step_days=1&perturbers=venus", 422, "perturbers"),
    ("/v1/bodies/earth/nutation?cut_mas=0", 422, "cut_mas"),
])
def test_bad_perturbers_are_422_naming_the_field(client, url, status, field):
    r = client.get(url)
    assert r.status_code == status and r.headers["content-type"].startswith("application/problem+json")
    assert field in {e["field"] for e in r.json()["errors"]}


def test_moon_route_under_the_moon_is_422(client):
    r = client.get("/v1/bodies/moon/precession?perturbers=moon,sun")
    assert r.status_code == 422 and "modelled for the Earth only" in r.json()["reason"]
