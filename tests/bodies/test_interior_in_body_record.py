"""The body answer shows each body's interior model (``interior``): the library's record, the HTTP route, the CLI
in each of its formats, and the body's web page. The expected Mars parameters are read from data/interiors.toml
here with tomllib, not through ephem.bodies.interior."""
from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from ephem import api
from ephem.cli import app as cli
from service.app import create_app
from service.settings import Settings

ROOT = Path(__file__).resolve().parents[2]
with open(ROOT / "data" / "interiors.toml", "rb") as _fh:
    FILE = tomllib.load(_fh)
MARS = FILE["Mars"]
PARAMETER_KEYS = {"value", "unit", "uncertainty", "no_uncertainty"}
INTERIOR_KEYS = {"model", "form", "parameters", "source", "reference", "why", "left_out", "parameters_file"}


def _check_mars(interior: dict) -> None:
    assert interior["model"] == "transfer_function" and interior["form"] == "fluid_core_resonance"
    p = interior["parameters"]
    assert set(p) == {"fcn_period_days", "fcn_amplitude_factor"}
    assert all(set(v) == PARAMETER_KEYS for v in p.values())
    assert (p["fcn_period_days"]["value"], p["fcn_period_days"]["uncertainty"]) == \
        (MARS["fcn_period_days"], MARS["fcn_period_days_uncertainty"]) == (-243.0, 3.3)
    assert (p["fcn_amplitude_factor"]["value"], p["fcn_amplitude_factor"]["uncertainty"]) == \
        (MARS["fcn_amplitude_factor"], MARS["fcn_amplitude_factor_uncertainty"]) == (0.0615, 0.007)
    assert p["fcn_period_days"]["unit"] == "d" and p["fcn_amplitude_factor"]["unit"] == ""
    assert interior["source"] == MARS["source"]
    assert interior["reference"] == FILE["references"][MARS["source"]]
    assert interior["left_out"] == MARS["left_out"] and interior["why"] is None
    alt = interior["alternatives"]["konopliv2016"]
    assert set(alt) == INTERIOR_KEYS                                # no nested alternatives
    assert alt["parameters"]["fcn_period_days"]["value"] == MARS["alternatives"]["konopliv2016"]["fcn_period_days"]
    assert alt["parameters"]["fcn_period_days"]["uncertainty"] is None
    assert alt["parameters"]["fcn_period_days"]["no_uncertainty"]
    assert alt["reference"] == FILE["references"]["konopliv2016_tudat"]


def test_the_record_carries_mars_fluid_core():
    interior = api.body_record("mars")["interior"]
    assert set(interior) == INTERIOR_KEYS | {"alternatives"}
    _check_mars(interior)


def test_ceres_is_rigid_with_a_reason_and_the_earth_has_the_iers_resonance():
    ceres = api.body_record("ceres")["interior"]
    assert ceres["model"] == "rigid" and ceres["why"] == FILE["Ceres"]["why"] and ceres["why"].strip()
    assert ceres["form"] is None and ceres["parameters"] == {} and ceres["reference"] is None
    earth = api.body_record("earth")["interior"]
    assert earth["model"] == "transfer_function" and earth["form"] == "iers1996_resonance"
    assert earth["parameters_file"] == FILE["Earth"]["parameters_file"]
    assert earth["reference"] == FILE["references"][FILE["Earth"]["source"]]


@pytest.mark.parametrize("dataset", ["current", "petit2014"])
def test_every_catalogue_body_has_one_in_its_record(dataset):
    for row in api.list_bodies(dataset=dataset):
        interior = api.body_record(row["name"], dataset=dataset)["interior"]
        assert interior["model"] in ("rigid", "transfer_function"), row["name"]
        assert interior["why"] if interior["model"] == "rigid" else interior["reference"], row["name"]


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def test_the_route_returns_it(client):
    r = client.get("/v1/bodies/mars")
    assert r.status_code == 200, r.text
    _check_mars(r.json()["interior"])
    r = client.get("/v1/bodies/ceres")
    assert r.json()["interior"]["model"] == "rigid" and r.json()["interior"]["why"] == FILE["Ceres"]["why"]


def test_the_page_shows_it(client):
    mars = client.get("/bodies/mars")
    assert mars.status_code == 200
    assert 'id="interior"' in mars.text and "fluid_core_resonance" in mars.text
    assert "-243 ± 3.3 d" in mars.text and "0.0615 ± 0.007" in mars.text
    assert "Le Maistre" in mars.text
    ceres = client.get("/bodies/ceres").text
    assert "rigid" in ceres and "Dawn gave the mean moment of inertia" in ceres


def test_the_cli_shows_it_in_every_format():
    runner = CliRunner()
    res = runner.invoke(cli, ["body", "mars"])
    assert res.exit_code == 0, res.output
    _check_mars(json.loads(res.stdout)["interior"])
    for fmt in ("csv", "table"):
        res = runner.invoke(cli, ["body", "mars", "--format", fmt])
        assert res.exit_code == 0, res.output
        line = res.stderr.splitlines()[-1]
        assert line.startswith("interior: transfer_function (fluid_core_resonance)"), res.stderr
        assert "fcn_period_days -243 ± 3.3 d" in line and "fcn_amplitude_factor 0.0615 ± 0.007" in line
        assert "source lemaistre2023" in line and "interior: " not in res.stdout
    res = runner.invoke(cli, ["body", "ceres", "--format", "table"])
    assert res.exit_code == 0 and f"interior: rigid; why: {FILE['Ceres']['why']}" in res.stderr
