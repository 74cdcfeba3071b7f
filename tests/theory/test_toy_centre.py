"""A family's new centre and new perturber are data (issue 43, part 2): a toy binary asteroid's file of
data/centres.toml's form, registered from the test (:func:`ephem.api.register_centres`), lets a body orbit the toy
primary and lets Itokawa feel a toy secondary, through the library and the service, with no edit of either.

The toy family of tests/theory/test_toy_family.py, given a test of a body that takes the new centre and perturber
(:class:`ToyBinaryTheory`), serves the bodies the data admit; the single-perturber ladder computes a body about the
toy primary under it alone from the file's GM. What a binary-asteroid family touches is then its package, its
registry entry and its data: its centres and perturbers here, as the shipped ones are in data/centres.toml.
"""
from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from ephem import api, families
from tests.theory.test_toy_family import (SPAN, TOY_BODY, TOY_MODEL, TOY_RATE_ARCSEC_PER_YEAR, ToyTheory,
                                          expected_psi_arcsec, serves_toy)

TOY_CENTRE = "Toyprimary"
TOY_PERTURBER = "Toysecondary"
#: the toy primary's GM, m^3 s^-2 (Didymos' order: 5e11 kg), and its radius and Hill radius, km
TOY_GM_M3_S2, TOY_RADIUS_KM, TOY_HILL_KM = 35.0, 0.4, 100.0
#: the toy satellite's semi-major axis, km (its spin 2.26 h is then 130 times its orbital motion: Kinoshita's
#: averaged theory applies, ω/n >= 30)
TOY_A_KM = 10.0
KM_PER_AU = 149_597_870.7


def centres_file(summary: str) -> str:
    """The toy binary's data: the primary a centre; the Sun a perturber of the bodies about it; the secondary a
    perturber of Itokawa (as a binary's secondary torques its primary)."""
    return f"""
[[centre]]
name = "{TOY_CENTRE}"
gm = {{ value = {TOY_GM_M3_S2}, unit = "m3 / s2", source = "toy", no_uncertainty = "a toy" }}
radius = {{ value = {TOY_RADIUS_KM}, unit = "km", source = "toy", no_uncertainty = "a toy" }}
hill = {{ value = {TOY_HILL_KM}, unit = "km", source = "toy", no_uncertainty = "a toy" }}

[[perturber]]
name = "Sun"
theory = "{summary}"
torques = [{{ center = "{TOY_CENTRE}" }}]

[[perturber]]
name = "{TOY_PERTURBER}"
theory = "{summary}"
torques = [{{ body = "{TOY_BODY}", center = "Sun" }}]
"""


def serves_binary(body, perturbers) -> bool:
    """The toy's bodies with the data's perturbers: a body about the toy primary under it and the Sun, and Itokawa
    under the Sun and the toy secondary."""
    return tuple(perturbers) in ((TOY_CENTRE, "Sun"), ("Sun", TOY_PERTURBER)) and (
        body.orbit.center == TOY_CENTRE or body.name == TOY_BODY)


class ToyBinaryTheory(ToyTheory):
    """The toy family's uniform precession for the bodies the toy binary's data admit."""

    summary = "the toy binary family (a uniform precession, for the centres' test)"

    @classmethod
    def serves(cls, body, perturbers):
        return serves_binary(body, perturbers)

    @classmethod
    def how_to_reach(cls, body):
        return f"it serves a body about the {TOY_CENTRE} under it and the Sun, and {TOY_BODY} under the Sun and the " \
               f"{TOY_PERTURBER}"


ENTRY = api.Family(__name__, "ToyBinaryTheory", ToyBinaryTheory.models, serves_binary, ToyBinaryTheory.summary)


@pytest.fixture
def toy_data(tmp_path):
    """The toy binary's centres file registered, taken out after the test."""
    path = tmp_path / "toy_centres.toml"
    path.write_text(centres_file(ToyBinaryTheory.summary), encoding="utf-8")
    assert api.register_centres(path) == (TOY_CENTRE, "Sun", TOY_PERTURBER)
    try:
        yield path
    finally:
        api.unregister_centres(path)


@pytest.fixture
def binary(toy_data):
    """The toy binary family registered first, with its data, taken out after the test."""
    api.register_family(ENTRY)
    try:
        yield ENTRY
    finally:
        api.unregister_family(ENTRY.name)


def satellite(center: str = TOY_CENTRE, a_au: float = TOY_A_KM / KM_PER_AU, perturbers=None) -> api.Body:
    """A body on a near-circular orbit about ``center``, spinning in 2.26 h (Didymos' period)."""
    return api.Body("toy satellite", api.Orbit(a_au, 0.05, 3.0, 10.0, 20.0, 30.0, 2451545.0, center=center,
                                               body="toy satellite"),
                    api.Pole(10.0, 60.0), 2.26, dynamical_ellipticity=0.1, perturbers=perturbers)


def test_a_new_centre_is_known_while_its_data_are_registered(tmp_path):
    with pytest.raises(api.InvalidInputError, match=f"unknown centre '{TOY_CENTRE}'") as err:
        satellite()
    assert err.value.field == "orbit.center"
    path = tmp_path / "toy_centres.toml"
    path.write_text(centres_file(ToyBinaryTheory.summary), encoding="utf-8")
    api.register_centres(path)
    try:
        assert satellite().orbit.center == TOY_CENTRE
        assert api.GM_CENTER[TOY_CENTRE] == pytest.approx(TOY_GM_M3_S2, rel=1e-15)
        assert TOY_PERTURBER in api.KNOWN_PERTURBERS and TOY_CENTRE in api.KNOWN_PERTURBERS
        with pytest.raises(api.InvalidInputError, match="Hill sphere") as err:     # its data bound the orbit
            satellite(a_au=1.01 * TOY_HILL_KM / KM_PER_AU)
        assert err.value.field == "orbit.a_au"
        with pytest.raises(ValueError, match="registered already"):
            api.register_centres(path)
    finally:
        api.unregister_centres(path)
    assert TOY_CENTRE not in api.GM_CENTER and TOY_PERTURBER not in api.KNOWN_PERTURBERS
    with pytest.raises(api.InvalidInputError, match="unknown centre"):
        satellite()


def test_the_ladder_computes_about_the_new_centre_from_its_gm(toy_data):
    # K = 3 n^2 H_d / (2 ω) (1 - e^2)^(-3/2) with n^2 = GM / a^3: the same body about the Sun at 2 AU differs by
    # GM and a^3 alone; 1e-12: a few roundings of products of doubles
    toy, ref = api.precession(satellite()), api.precession(satellite("Sun", 2.0))
    assert toy["model"]["name"] == "hansen" and toy["perturbers"] == [TOY_CENTRE]
    expected = TOY_GM_M3_S2 / api.GM_CENTER["Sun"] * (2.0 * KM_PER_AU / TOY_A_KM) ** 3
    assert toy["scaling_factor_arcsec_per_year"] / ref["scaling_factor_arcsec_per_year"] == pytest.approx(
        expected, rel=1e-12)


def test_a_new_perturber_is_admitted_where_its_data_say(toy_data):
    itokawa = api.get_body(TOY_BODY)
    assert dataclasses.replace(itokawa, perturbers=("sun", TOY_PERTURBER.lower())).perturbers == ("Sun", TOY_PERTURBER)
    with pytest.raises(api.NotApplicableError, match=f"the {TOY_PERTURBER} as a perturber is modelled for "
                                                     f"{TOY_BODY} only"):
        dataclasses.replace(api.get_body("vesta"), perturbers=("Sun", TOY_PERTURBER))
    assert satellite(perturbers=(TOY_CENTRE, "Sun")).perturbers == (TOY_CENTRE, "Sun")
    with pytest.raises(api.NotApplicableError, match="Earth is not the orbit's centre"):
        dataclasses.replace(api.get_body("vesta"), perturbers=("Sun", "Earth"))
    # admitted, but no family serves it until one is registered
    with pytest.raises(api.NotApplicableError, match="no theory here models"):
        api.track(TOY_BODY, SPAN["start"], SPAN["stop"], SPAN["step_days"], perturbers=f"Sun,{TOY_PERTURBER}")


def test_the_family_serves_what_its_data_admit(binary):
    assert not serves_toy(api.get_body(TOY_BODY), ("Sun", TOY_PERTURBER))       # the first toy serves it not
    assert type(families.theory_for(satellite(), (TOY_CENTRE, "Sun")).inner) is ToyBinaryTheory
    assert type(families.theory_for(satellite(), (TOY_CENTRE,)).inner).__name__ == "SunLadder"
    ans = api.track(TOY_BODY, SPAN["start"], SPAN["stop"], SPAN["step_days"], perturbers=f"sun,{TOY_PERTURBER}")
    assert ans["model"]["name"] == TOY_MODEL and ans["perturbers"] == ["Sun", TOY_PERTURBER]
    epoch = api.model_for(api.get_body(TOY_BODY)).pole_epoch
    # 1e-9 arcsec: float64 rounding of a few thousand arcsec
    np.testing.assert_allclose(ans["psi_arcsec"], expected_psi_arcsec(ans["jd_tdb"], epoch), rtol=0, atol=1e-9)
    mine = api.precession(satellite(perturbers=(TOY_CENTRE, "Sun")))
    assert mine["precession_rate_arcsec_per_year"] == pytest.approx(TOY_RATE_ARCSEC_PER_YEAR, rel=1e-12)


def test_the_service_takes_the_new_centre_and_perturber(binary, monkeypatch):
    from fastapi.testclient import TestClient
    from service import app as service_app
    from service.settings import Settings

    monkeypatch.setattr(service_app, "Rung", service_app.Rung)     # the module's enum as it was, after this app's
    settings = dataclasses.replace(Settings.from_env(), warm_up=False)
    client = TestClient(service_app.create_app(settings))     # an app made after the data's registration
    schema = client.get("/openapi.json").json()
    assert TOY_CENTRE in schema["components"]["schemas"]["OrbitIn"]["properties"]["center"]["enum"]
    (pattern,) = [branch["pattern"] for p in schema["paths"]["/v1/bodies/{body}/track"]["get"]["parameters"]
                  if p["name"] == "perturbers" for branch in p["schema"]["anyOf"] if "pattern" in branch]
    assert re.fullmatch(pattern, f"sun, {TOY_PERTURBER.upper()}") and not re.fullmatch(pattern, "sun,nowhere")
    # a posted body about the toy primary: the ladder, from the file's GM
    orbit = {"a_au": TOY_A_KM / KM_PER_AU, "e": 0.05, "i_deg": 3.0, "node_deg": 10.0, "peri_deg": 20.0,
             "mean_anomaly_deg": 30.0, "epoch_jd_tdb": 2451545.0, "center": TOY_CENTRE}
    posted = {"name": "toy satellite", "orbit": orbit, "pole": {"ra_deg": 10.0, "dec_deg": 60.0},
              "rotation_period_hours": 2.26, "dynamical_ellipticity": 0.1}
    r = client.post("/v1/precession-nutation", json=posted)
    assert r.status_code == 200, r.text
    expected = api.precession(satellite())["scaling_factor_arcsec_per_year"]
    assert r.json()["precession"]["scaling_factor_arcsec_per_year"] == pytest.approx(expected, rel=1e-12)
    r = client.post("/v1/precession-nutation", json={**posted, "orbit": {**orbit, "center": "Nowhere"}})
    assert r.status_code == 422 and "center" in r.text and TOY_CENTRE in r.text, r.text
    # Itokawa under the toy secondary: the toy family's answer
    r = client.get(f"/v1/bodies/{TOY_BODY.lower()}/track", params={**SPAN, "perturbers": f"sun,{TOY_PERTURBER}"})
    assert r.status_code == 200, r.text
    ans = r.json()
    epoch = api.model_for(api.get_body(TOY_BODY)).pole_epoch
    np.testing.assert_allclose(ans["psi_arcsec"], expected_psi_arcsec(ans["jd_tdb"], epoch), rtol=0, atol=1e-9)
