"""A family is a plug-in (issue 43): a toy family registered from outside the library is chosen by the registry and
answers through every surface, ephem.api, the CLI and the service, with the models it declares in every list.

The toy (:class:`ToyTheory`) is a whole :class:`~ephem.theory.interface.SpinAxisTheory`: Itokawa's pole turning
uniformly about its orbit's normal at a rate of its own, :data:`TOY_RATE_ARCSEC_PER_YEAR`, at the catalogue's mean
obliquity, with no nutation. Its numbers are known exactly, so each surface's answer is checked against them; what
it had to touch is what docs/architecture.md's "where a change goes" says a new family touches: its own module (here
this file), its entry (:func:`ephem.api.register_family`), and nothing of the library, the CLI or the service.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar
import json
import re
import time

import numpy as np
import pytest
from typer.testing import CliRunner

from ephem import api, families
from ephem.base.budget import Cost, Part, charge
from ephem.base.constants import ARCSEC, JULIAN_YEAR_DAYS
from ephem.base.errors import InvalidInputError
from ephem.bodies.catalogue import Body
from ephem.cli import app as cli_app
from ephem.forced.describe import model_info
from ephem.forced.precession_nutation import model_for
from ephem.theory.interface import SpinAxisTheory
from ephem.theory.results import (COVERS_NOTHING_TRUNCATED, Estimate, FamilySummary, PrecessionResult, quantity,
                                  selection)

#: the toy's own precession rate, arcsec per Julian year (no body has it: a number only the toy can give)
TOY_RATE_ARCSEC_PER_YEAR = 4321.0
#: the toy's one model, and the error it claims for it (mas)
TOY_MODEL = "toy_uniform"
TOY_ERROR_MAS = 7.0
#: the body the toy takes from the single-perturber ladder
TOY_BODY = "Itokawa"


@dataclass(frozen=True)
class ToySummary(FamilySummary):
    """What the toy derives beside the precession answer (its own object of the answer, rendered by its units)."""

    answer_key: ClassVar[str] = "toy"
    turn_rate: float = quantity("rad/day", period="turn_period_years")
    tilt: float = quantity("rad")


def serves_toy(body: Body, perturbers: tuple[str, ...]) -> bool:
    """The toy's test of a body: Itokawa under the Sun alone."""
    return body.name == TOY_BODY and tuple(perturbers) == ("Sun",)


class ToyTheory(SpinAxisTheory):
    """A uniform precession at :data:`TOY_RATE_ARCSEC_PER_YEAR` at the catalogue's mean obliquity, no nutation."""

    summary = "the toy family (a uniform precession, for the registry's test)"
    models = (TOY_MODEL,)
    descriptions = {TOY_MODEL: "a uniform precession at the toy's own rate, no nutation"}
    axes = ("figure",)

    @classmethod
    def serves(cls, body, perturbers):
        return serves_toy(body, perturbers)

    @classmethod
    def how_to_reach(cls, body):
        return "it serves Itokawa under the Sun alone"

    @property
    def rate(self) -> float:
        """ψ̇, rad/day."""
        return TOY_RATE_ARCSEC_PER_YEAR * ARCSEC / JULIAN_YEAR_DAYS

    @property
    def frame(self):
        """The catalogue pole's forced model: the orbit frame, the mean obliquity and the epochs the toy uses."""
        return model_for(self.body, self.body.dataset)

    def default_model(self, choice) -> str:
        return TOY_MODEL

    def check_request(self, choice) -> None:
        if choice.order is not None:
            raise InvalidInputError("order", "the toy family takes no e-order", self.body.name)

    def _cost(self, count: int) -> Cost:
        return Cost((Part("count", "the toy's uniform precession", 1e-8 * count, 56e-6 * count),))

    def choice_cost(self, start, stop, count):
        return self._cost(1)

    def track_cost(self, choice, start, stop, count):
        return self._cost(count)

    def answer_cost(self, order, nutation=False, tolerance=False):
        return self._cost(1)

    def estimates(self, jd_tdb):
        return [Estimate(TOY_MODEL, None, {"toy_theory": TOY_ERROR_MAS * ARCSEC / 1e3})]

    def named(self, jd_tdb, choice):
        return self.estimates(jd_tdb)[0]

    def track(self, choice, epochs):
        m, t = self.frame, epochs.jd_tdb
        psi = self.rate * (t - m.pole_epoch)
        zero = np.zeros_like(t)
        return m.track_from_angles(t, psi, zero, zero, np.full_like(t, m.obliquity))

    def describe(self, choice):
        info = model_info(self.frame, self.body, ["a uniform precession about the orbit's normal, no nutation"])
        info["theory"] = self.summary
        info["eccentricity_order"] = None
        info["perturbers"] = list(self.perturbers)
        return info

    def precession(self, order, tolerance, start):
        charge(self.answer_cost(order), self.body.name)
        m = self.frame
        uncertainty = {"method": "none: the toy propagates no 1-sigma", "complete": False, "dominant_input": {},
                       "unpropagated_inputs": [], "no_uncertainty_reasons": {}, "assumptions": []}
        return PrecessionResult(self.body, m.obliquity, m.hd, m.scaling_factor, self.rate, None, uncertainty,
                                self.describe(None), selection(self, TOY_MODEL, None, None,
                                                               1e3 * (time.perf_counter() - start), tolerance,
                                                               covers=COVERS_NOTHING_TRUNCATED),
                                ToySummary(self.rate, m.obliquity))

    def nutation(self, order, tolerance, cut_mas, start, nonrigid=False):
        raise api.NotApplicableError(self.body.name, "the toy family has no nutation")


ENTRY = api.Family(__name__, "ToyTheory", ToyTheory.models, serves_toy, ToyTheory.summary)
SPAN = dict(start="2000-01-01T12:00:00 TDB", stop="2002-01-01T12:00:00 TDB", step_days=365.25)


@pytest.fixture
def toy():
    """The toy family registered first (before the families it takes Itokawa from), taken out after the test."""
    api.register_family(ENTRY)
    try:
        yield ENTRY
    finally:
        api.unregister_family(ENTRY.name)


def expected_psi_arcsec(jd_tdb, pole_epoch: float) -> np.ndarray:
    return TOY_RATE_ARCSEC_PER_YEAR * (np.asarray(jd_tdb) - pole_epoch) / JULIAN_YEAR_DAYS


def test_the_registry_chooses_the_toy_for_its_body_alone_and_lists_its_model(toy):
    itokawa, vesta = api.get_body("itokawa"), api.get_body("vesta")
    assert type(families.theory_for(itokawa, ("Sun",)).inner) is ToyTheory
    assert type(families.theory_for(vesta, ("Sun",)).inner).__name__ == "SunLadder"
    assert TOY_MODEL in api.MODELS and api.MODELS[-1] == "long_term"
    assert (ToyTheory.summary, (TOY_MODEL,)) in api.model_families()


def test_unregistering_gives_the_body_back():
    api.register_family(ENTRY)
    api.unregister_family(ENTRY.name)
    assert TOY_MODEL not in api.MODELS
    assert type(families.theory_for(api.get_body("itokawa"), ("Sun",)).inner).__name__ == "SunLadder"


def test_a_family_registered_twice_or_before_no_family_is_refused(toy):
    with pytest.raises(ValueError, match="registered already"):
        api.register_family(ENTRY)
    with pytest.raises(ValueError, match="no family 'Nowhere'"):
        api.register_family(dataclasses.replace(ENTRY, name="OtherToy"), before="Nowhere")
    assert [f.name for f in families.FAMILIES].count("OtherToy") == 0


def test_a_family_goes_before_the_one_named():
    api.register_family(ENTRY, before="SunLadder")
    try:
        names = [f.name for f in families.FAMILIES]
        assert names.index("ToyTheory") == names.index("SunLadder") - 1
        assert type(families.theory_for(api.get_body(TOY_BODY), ("Sun",)).inner) is ToyTheory
    finally:
        api.unregister_family(ENTRY.name)


def test_the_api_answers_with_the_toy(toy):
    ans = api.track(TOY_BODY, SPAN["start"], SPAN["stop"], SPAN["step_days"], model=TOY_MODEL)
    assert ans["model"]["name"] == TOY_MODEL and ans["model"]["theory"] == ToyTheory.summary
    assert ans["model"]["estimated_error_mas"] == pytest.approx(TOY_ERROR_MAS, rel=1e-12)
    epoch = model_for(api.get_body(TOY_BODY)).pole_epoch
    # 1e-9 arcsec: float64 rounding of a few thousand arcsec
    np.testing.assert_allclose(ans["psi_arcsec"], expected_psi_arcsec(ans["jd_tdb"], epoch), rtol=0, atol=1e-9)
    assert np.all(np.asarray(ans["delta_psi_arcsec"]) == 0.0)
    default = api.track(TOY_BODY, SPAN["start"], SPAN["stop"], SPAN["step_days"])      # the toy's default
    assert default["model"]["name"] == TOY_MODEL
    chosen = api.track(TOY_BODY, SPAN["start"], SPAN["stop"], SPAN["step_days"], tolerance_mas=10.0)
    assert chosen["model"]["name"] == TOY_MODEL
    precession = api.precession(TOY_BODY)
    assert precession["precession_rate_arcsec_per_year"] == pytest.approx(TOY_RATE_ARCSEC_PER_YEAR, rel=1e-12)
    # the toy's own summary, rendered by the units its fields declare (render.py knows no toy)
    assert precession["toy"]["turn_rate_deg_per_year"] == pytest.approx(TOY_RATE_ARCSEC_PER_YEAR / 3600.0, rel=1e-12)
    assert precession["toy"]["turn_period_years"] == pytest.approx(1296000.0 / TOY_RATE_ARCSEC_PER_YEAR, rel=1e-12)
    assert precession["toy"]["tilt_deg"] == pytest.approx(precession["obliquity_deg"], rel=1e-12)


def test_the_api_refuses_what_the_toy_has_not(toy):
    with pytest.raises(api.NotApplicableError, match="toy family"):
        api.track(TOY_BODY, SPAN["start"], SPAN["stop"], SPAN["step_days"], model="hansen")
    with pytest.raises(api.InvalidInputError, match="toy family takes no e-order"):
        api.track(TOY_BODY, SPAN["start"], SPAN["stop"], SPAN["step_days"], model=TOY_MODEL, order=2)
    with pytest.raises(api.NotApplicableError, match="the '" + TOY_MODEL + "' model belongs to the toy family"):
        api.track("vesta", SPAN["start"], SPAN["stop"], SPAN["step_days"], model=TOY_MODEL)


def test_the_cli_lists_and_answers_with_the_toy(toy):
    runner = CliRunner()
    helped = runner.invoke(cli_app, ["track", "--help"], env={"COLUMNS": "200"})
    words = " ".join(re.sub("[│╭╮╰╯─]", " ", helped.stdout).split())      # the help's text, its box and wrapping aside
    assert helped.exit_code == 0 and f"{TOY_MODEL} ({ToyTheory.summary})" in words, words
    res = runner.invoke(cli_app, ["track", "itokawa", "--start", SPAN["start"], "--stop", SPAN["stop"],
                                  "--step-days", str(SPAN["step_days"]), "--model", TOY_MODEL])
    assert res.exit_code == 0, res.output
    ans = json.loads(res.stdout)
    epoch = model_for(api.get_body(TOY_BODY)).pole_epoch
    np.testing.assert_allclose(ans["psi_arcsec"], expected_psi_arcsec(ans["jd_tdb"], epoch), rtol=0, atol=1e-9)
    res = runner.invoke(cli_app, ["precession", "itokawa"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["precession_rate_arcsec_per_year"] == pytest.approx(TOY_RATE_ARCSEC_PER_YEAR,
                                                                                      rel=1e-12)


def test_the_service_documents_and_answers_with_the_toy(toy, monkeypatch):
    from fastapi.testclient import TestClient
    from service import app as service_app
    from service.settings import Settings

    monkeypatch.setattr(service_app, "Rung", service_app.Rung)     # the module's enum as it was, after this app's
    settings = dataclasses.replace(Settings.from_env(), warm_up=False)
    client = TestClient(service_app.create_app(settings))     # an app made after the toy's registration
    schema = client.get("/openapi.json").json()
    assert TOY_MODEL in schema["components"]["schemas"]["Rung"]["enum"]
    assert TOY_MODEL in schema["components"]["schemas"]["ModelInfo"]["properties"]["name"]["enum"]
    r = client.get("/v1/bodies/itokawa/track", params={**SPAN, "model": TOY_MODEL})
    assert r.status_code == 200, r.text
    ans = r.json()
    assert ans["model"]["name"] == TOY_MODEL
    epoch = model_for(api.get_body(TOY_BODY)).pole_epoch
    np.testing.assert_allclose(ans["psi_arcsec"], expected_psi_arcsec(ans["jd_tdb"], epoch), rtol=0, atol=1e-9)
    r = client.get("/v1/bodies/itokawa/precession")
    assert r.status_code == 200, r.text
    assert r.json()["precession_rate_arcsec_per_year"] == pytest.approx(TOY_RATE_ARCSEC_PER_YEAR, rel=1e-12)
    r = client.get("/v1/bodies/vesta/track", params={**SPAN, "model": TOY_MODEL})
    assert r.status_code == 422 and "toy family" in r.text
    # the pages: the track page answers with the toy, and both forms offer its model
    r = client.get("/bodies/itokawa/track", params={**SPAN, "model": TOY_MODEL})
    assert r.status_code == 200, r.text
    assert f'<option value="{TOY_MODEL}" selected' in r.text and f"<strong>{TOY_MODEL}</strong>" in r.text
    assert f'<option value="{TOY_MODEL}"' in client.get("/my-body").text
