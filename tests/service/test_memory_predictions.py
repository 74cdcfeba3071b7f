"""Requests charged for the memory they take (issue 42: a worker's RSS under its bound through any sequence of
requests). benchmarks/bench_request_memory.py measures each request's resident high-water rise beside its charged peak;
what it found taking more than its charge is charged here, and these tests hold the charge to the measurement
(benchmarks/RESULTS_request_memory.md): never below what was measured, never so far above that honest work is refused.
"""
from __future__ import annotations

import logging

import pytest
from fastapi.testclient import TestClient

from ephem import api
from ephem.answers import figures
from ephem.base.budget import budget
from service.app import create_app
from service.settings import Settings

#: the Earth's free wobble over 9.2 years: 100,000 epochs at the default step, ~3,400 turns of the figure axis about L
EARTH_LONG = ("earth", 2448425.8381, 2451799.6069)
#: ... and over 300 days: 19,316 epochs (64 a turn), ~300 turns
EARTH_SHORT = ("earth", 2448425.8381, 2448725.8381)
#: the whole request's resident high-water rise measured for them as PNG, MB, by dpi (RESULTS_request_memory.md):
#: the Agg rasterizer's cells along the overlapping loops, ~610 bytes a turn a dpi
MEASURED_PNG_MB = {EARTH_LONG: {30: 68.1, 46: 100.4, 80: 170.4, 110: 232.1},
                   EARTH_SHORT: {30: 10.2, 46: 10.8, 80: 17.8, 110: 24.6}}


@pytest.mark.parametrize("case", list(MEASURED_PNG_MB))
def test_free_wobble_png_is_charged_for_its_loops(case):
    """A PNG free-wobble figure is charged at least its measured peak and at most 1.5x it (the old charge, the
    figure's base and pixels, stood at 4.4-9.4 MB against 68-232 MB for the long span)."""
    request = figures.plot_request("free-wobble", *case, None)
    for dpi, measured in MEASURED_PNG_MB[case].items():
        predicted = figures.wobble_drawing_cost(request, "png", dpi).memory_mb
        assert measured <= predicted <= 1.5 * measured, (dpi, measured, predicted)


def test_free_wobble_svg_charges_the_drawing_alone():
    """SVG writes the loops as text (12 MB at 100,000 epochs, within the data's own charge): no raster term."""
    request = figures.plot_request("free-wobble", *EARTH_LONG, None)
    assert figures.wobble_drawing_cost(request, "svg", 70).memory_mb == pytest.approx(
        figures.drawing_cost("svg", 70).memory_mb, rel=1e-12)


def test_free_wobble_png_charge_reaches_the_budget_before_its_data():
    """The loops' charge is made by the figure's answer, before the data (the budget's peak holds it, so the service
    admits the request with it at the data's checkpoint)."""
    request = figures.plot_request("free-wobble", *EARTH_SHORT, None)
    expected = figures.wobble_drawing_cost(request, "png", 46).memory_mb
    with budget(60.0, 1000.0) as b:
        png = api.render_plot("free-wobble", *EARTH_SHORT, fmt="png", dpi=46)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert b.peak_memory_mb >= expected * (1.0 - 1e-9)
    assert b.peak_memory_mb >= MEASURED_PNG_MB[EARTH_SHORT][46]


def test_service_refuses_a_free_wobble_png_over_the_memory_budget_naming_dpi():
    """The Earth's 9.2-year wobble as a 110-dpi PNG took 232 MB: over a worker's 80-MB allowance, it is now a 422
    naming ``dpi`` with its estimate, before any work (it was answered at a charge of 69 MB and took the worker to
    ~500 MB); the same as SVG still fits."""
    body, start, stop = EARTH_LONG
    with TestClient(create_app(Settings(warm_up=False))) as client:
        r = client.get(f"/v1/bodies/{body}/track.png?start={start}&stop={stop}&kind=free-wobble&dpi=110")
        assert r.status_code == 422, r.text
        p = r.json()
        assert p["type"].endswith("/over-budget")
        assert p["errors"][0]["field"] == "dpi"
        assert p["estimated_memory_mb"] >= MEASURED_PNG_MB[EARTH_LONG][110]
        assert "free wobble" in p["detail"] and "as svg" in p["detail"]     # the way out that keeps the span
        r = client.get(f"/v1/bodies/{body}/track.svg?start={start}&stop={stop}&kind=free-wobble")
        assert r.status_code == 200, r.text


def test_service_records_each_requests_charged_and_admitted_memory(caplog):
    """The DEBUG record the measurement reads (ephem.service.memory): a request's charged peak and what the worker's
    allowance counted of it, the second never above the first; nothing is recorded at the default level."""
    url = "/v1/bodies/ceres/track?start=2451545&stop=2451845&step_days=10"
    with TestClient(create_app(Settings(warm_up=False))) as client:
        with caplog.at_level(logging.INFO, logger="ephem.service.memory"):
            assert client.get(url).status_code == 200
        assert not [r for r in caplog.records if r.name == "ephem.service.memory"]
        with caplog.at_level(logging.DEBUG, logger="ephem.service.memory"):
            assert client.get(url + "&format=csv").status_code == 200
    records = [r for r in caplog.records if r.name == "ephem.service.memory"]
    assert len(records) == 1
    r = records[0]
    assert r.peak_memory_mb > 0.0
    assert 0.0 <= r.admitted_memory_mb <= r.peak_memory_mb
    assert "/v1/bodies/ceres/track" in r.getMessage()
