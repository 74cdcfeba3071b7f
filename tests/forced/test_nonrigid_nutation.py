"""The nutation answer with the body's interior applied (``nonrigid``): Mars' liquid core, the Earth's IERS 1996
transfer function; every surface (library, HTTP, CLI) and the refusal for a rigid body."""
from __future__ import annotations

import json
import math

import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from ephem import api
from ephem.base.errors import NotApplicableError
from ephem.bodies.interior import interior_of
from ephem.cli import app as cli
from service.app import app


def _by_multiple(ans):
    return {t["multiple"]: t for t in ans["terms"]}


def test_mars_terms_are_the_rigid_ones_times_the_transfer_function_of_each_circular_component():
    """The semi-annual term (2M) with the core, rebuilt by hand from the rigid answer's four coefficients: the
    prograde and retrograde components c± of Δψ sin ε + iΔε, each times 1 + Fσ/(σ − σ_FCN) at σ = ±2n."""
    rigid, core = (_by_multiple(api.nutation("mars", nonrigid=flag)) for flag in (False, True))
    ans = api.nutation("mars")
    eps = math.radians(ans["obliquity_deg"]) if "obliquity_deg" in ans else None
    assert eps is not None
    r = rigid[2]
    se = math.sin(eps)
    z_sin = complex(se * r["longitude_sin_arcsec"], r["obliquity_sin_arcsec"])   # the sin φ and cos φ phasors
    z_cos = complex(se * r["longitude_cos_arcsec"], r["obliquity_cos_arcsec"])
    # a sin φ + b cos φ = c₊ e^{iφ} + c₋ e^{−iφ}: c₊ = (b − i a)/2, c₋ = (b + i a)/2 (per complex component)
    plus, minus = (z_cos - 1j * z_sin) / 2, (z_cos + 1j * z_sin) / 2
    p = interior_of("Mars").parameters
    F, P = p["fcn_amplitude_factor"].value, p["fcn_period_days"].value
    n = 2.0 * math.pi / (2.0 * r["period_days"])                  # the mean motion, from the 2M term's period
    t_plus, t_minus = (1.0 + F * s / (s - 2.0 * math.pi / P) for s in (2 * n, -2 * n))
    new_cos, new_sin = t_plus * plus + t_minus * minus, 1j * (t_plus * plus - t_minus * minus)
    c = core[2]
    budget = 1e-9   # arcsec: rounding of a few operations on 1-arcsec coefficients
    assert c["longitude_cos_arcsec"] == pytest.approx(new_cos.real / se, abs=budget)
    assert c["obliquity_cos_arcsec"] == pytest.approx(new_cos.imag, abs=budget)
    assert c["longitude_sin_arcsec"] == pytest.approx(new_sin.real / se, abs=budget)
    assert c["obliquity_sin_arcsec"] == pytest.approx(new_sin.imag, abs=budget)
    # the core's change is tens of mas (docs/interiors.md), its 1σ carries the parameters'
    assert abs(c["longitude_amplitude_arcsec"] - r["longitude_amplitude_arcsec"]) > 0.01
    assert c["longitude_amplitude_arcsec_uncertainty"] > 3 * r["longitude_amplitude_arcsec_uncertainty"]


def test_mars_nonrigid_selection_names_its_terms():
    m = api.nutation("mars", nonrigid=True)["model"]
    assert m["name"] == "nonrigid"
    assert set(m["error_terms_mas"]) == {"truncation", "interior_parameters", "interior_mantle"}
    assert m["estimated_error_mas"] == pytest.approx(sum(m["error_terms_mas"].values()), rel=1e-12)
    assert any("T(sigma)" in a or "transfer function" in a for a in m["assumptions"])


@pytest.mark.parametrize("body,kw", [("vesta", {}), ("moon", {}), ("earth", {"perturbers": "sun"})])
def test_a_rigid_answer_says_why(body, kw):
    with pytest.raises(NotApplicableError, match="non-rigid terms do not apply"):
        api.nutation(body, nonrigid=True, **kw)


def test_http_and_cli():
    with TestClient(app) as c:
        r = c.get("/v1/bodies/mars/nutation", params={"nonrigid": "true"})
        assert r.status_code == 200 and r.json()["model"]["name"] == "nonrigid"
        r = c.get("/v1/bodies/mars/nutation", params={"nonrigid": "true", "format": "csv"})
        assert r.status_code == 200 and r.text.startswith("component,")
        r = c.get("/v1/bodies/vesta/nutation", params={"nonrigid": "true"})
        assert r.status_code == 422 and "rigid" in r.json()["detail"]
        r = c.get("/v1/bodies/mars/nutation", params={"nonrigid": "perhaps"})
        assert r.status_code == 422
    runner = CliRunner()
    res = runner.invoke(cli, ["nutation", "mars", "--nonrigid", "--format", "json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["model"]["name"] == "nonrigid"
    res = runner.invoke(cli, ["nutation", "ceres", "--nonrigid"])
    assert res.exit_code == 3 and "rigid" in res.stderr
