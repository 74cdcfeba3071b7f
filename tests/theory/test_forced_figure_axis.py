"""axis="forced_figure": the figure axis's forced motion (the analogue of the IAU's CIP), whose free wobble is polar
motion, not an error. The same track as the figure axis, an estimate without the free_wobble term, in every family
and on every surface (the Earth's against ERFA's CIP: tests/earth/test_against_erfa_nonrigid.py)."""
from __future__ import annotations

import json

import numpy as np
import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from ephem import api
from ephem.base.constants import AXES, MAS
from ephem.base.errors import InvalidInputError
from ephem.cli import app as cli
from ephem.rotation.free_motion import free_wobble_bound
from ephem.bodies.catalogue import get_body
from service.app import app

MARS = ("mars", "2000-01-01", "2010-01-01", 200.0)


def _pole(ans) -> np.ndarray:
    ra, dec = np.radians(ans["pole_ra_deg"]), np.radians(ans["pole_dec_deg"])
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


def test_it_is_one_of_the_axes():
    assert "forced_figure" in AXES


@pytest.mark.parametrize("model", ["hansen", "nonrigid"])
def test_mars_forced_figure_is_the_figure_track_without_the_wobble_term(model):
    """The same pole as the figure axis's (to rounding), and the estimate less exactly the free-wobble term (the
    published J, 0.1" for Mars)."""
    fig = api.track(*MARS, model=model, axis="figure")
    forced = api.track(*MARS, model=model, axis="forced_figure")
    assert np.max(np.abs(_pole(fig) - _pole(forced))) <= 1e-15 * 10
    f, g = fig["model"], forced["model"]
    assert "free_wobble" in f["error_terms_mas"] and "free_wobble" not in g["error_terms_mas"]
    wobble = free_wobble_bound(get_body("mars")) / MAS
    assert f["estimated_error_mas"] - g["estimated_error_mas"] == pytest.approx(wobble, rel=1e-9)
    assert g["axis"] == "forced_figure" and "polar motion" in g["assumptions"][0]


def test_a_tolerance_the_wobble_would_break_is_met():
    with pytest.raises(api.NotApplicableError, match="axis=forced_figure"):
        api.track(*MARS, tolerance_mas=80.0)
    assert api.track(*MARS, tolerance_mas=80.0, axis="forced_figure")["model"]["name"] == "nonrigid"


def test_a_wobble_phase_is_refused_naming_the_axis():
    with pytest.raises(InvalidInputError, match="axis=forced_figure") as exc:
        api.track(*MARS, axis="forced_figure", free_wobble_phase_deg=30.0)
    assert exc.value.field == "free_wobble_phase_deg"


def test_the_moon_serves_it_as_its_figure_axis_without_the_free_wobble():
    # the Moon's free wobble (8.22" x 3.30" in the body, measured in DE421: docs/moon.md) moves its figure axis, not
    # its forced motion; the bare Cassini state carries none, so there the two are one
    args = ("moon", "2024-01-01", "2024-03-01", 30.0)
    fig, forced = (api.track(*args, axis=a) for a in ("figure", "forced_figure"))
    a, b = _pole(fig), _pole(forced)
    gap = np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))) * 3600.0
    assert 3.2 < gap.min() and gap.max() < 8.3
    assert forced["model"]["axis"] == "forced_figure"
    assert "free_modes" not in forced["model"]["error_terms_mas"]
    fig, forced = (api.track(*args, axis=a, model="cassini") for a in ("figure", "forced_figure"))
    assert np.max(np.abs(_pole(fig) - _pole(forced))) <= 1e-14


def test_http_and_cli():
    with TestClient(app) as c:
        r = c.get("/v1/bodies/earth/track", params={"start": "2000-01-01", "stop": "2030-01-01", "step_days": 365,
                                                    "tolerance_mas": 10, "axis": "forced_figure"})
        assert r.status_code == 200, r.text
        assert r.json()["model"]["name"] == "nonrigid" and r.json()["model"]["axis"] == "forced_figure"
        r = c.get("/v1/bodies/earth/track", params={"start": "2000-01-01", "stop": "2030-01-01", "step_days": 365,
                                                    "tolerance_mas": 10})
        assert r.status_code == 422 and "forced_figure" in r.json()["detail"]
    res = CliRunner().invoke(cli, ["track", "earth", "--start", "2000-01-01", "--stop", "2030-01-01",
                                   "--step-days", "365", "--tolerance-mas", "10", "--axis", "forced_figure",
                                   "--format", "json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["model"]["name"] == "nonrigid"
