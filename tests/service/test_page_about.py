"""The About page (issue 41, what a scientist expects): the version, how to cite it (BibTeX), the theories each
answer rests on as the answers state them, the data sets with their descriptions, every source of the catalogue's
values with the values it gives, and the licence: each read from the answers, the catalogue and the package's
metadata, so that the page cannot drift from them.
"""
from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import create_app
from service.settings import Settings

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def about():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        r = c.get("/about")
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
        yield c, " ".join(re.sub(r"<[^>]+>", " ", r.text).replace("&#39;", "'").replace("&amp;", "&").split())


def test_the_version_licence_and_citation(about):
    client, text = about
    version = client.get("/healthz").json()["version"]
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert f"ephem {version}:" in text and f"Licence: {project['license']}." in text
    assert f"version = {{{version}}}" in text and "@software{" in text
    assert '<a href="/about">' in client.get("/").text                  # in every page's menu


def test_the_theories_are_the_answers_own(about):
    client, text = about
    for body in ("vesta", "earth", "moon"):
        theory = client.get(f"/v1/bodies/{body}/precession").json()["model"]["theory"]
        assert " ".join(theory.split()) in text, body
    history = client.get("/v1/bodies/ceres/history", params={"start_year": -1000, "stop_year": 0,
                                                               "step_years": 500}).json()["model"]
    assert history["spin"] in text


def test_every_dataset_and_every_source_of_its_values(about):
    client, text = about
    for dataset in api.available_datasets():
        assert " ".join(api.load_catalogue(dataset).description.split()) in text, dataset
        for entry in client.get("/v1/bodies", params={"dataset": dataset}).json():
            record = client.get(f"/v1/bodies/{entry['name']}", params={"dataset": dataset}).json()
            for key, value in record["values"].items():
                ref = value.get("reference")
                if ref:
                    assert str(ref["title"]).rstrip(".") in text, (dataset, entry["name"], key)
                    assert f"{dataset}: {record['name']} {key}" in text, (dataset, entry["name"], key)
                    if ref.get("doi"):
                        assert f"doi:{ref['doi']}" in text
