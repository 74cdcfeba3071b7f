"""The speed-against-accuracy charts (studies.accuracy), in their quick versions.

Runs every task once into a temporary directory (module-scoped: a few seconds in all), then
checks the files and properties of the plotted numbers that a wrong chart would break:
every estimate at least the true error, the truncated series converging geometrically at
the rate e / 0.6627 below the Laplace limit and not at all beyond it, the errors growing
with the span, the rotation-averaged pole failing against the rigid body below the product's
ω/n threshold and not above it.
"""
from __future__ import annotations

import math
from itertools import pairwise

import pytest

from ephem.orbit.hansen import LAPLACE_LIMIT
from ephem.forced.precession_nutation import MIN_SPIN_ORBIT_RATIO
from studies import accuracy as ab
from tests.conftest import run_quick_charts

CHARTS = ("work_precision", "error_vs_order", "error_vs_span", "averaging_vs_spin")


@pytest.fixture(scope="module")
def out_dir(tmp_path_factory):
    return run_quick_charts(ab.tasks, tmp_path_factory.mktemp("charts"), len(CHARTS))


def _rows(out_dir, name):
    return ab.read_csv(out_dir / f"{name}.csv")


def _f(value: str) -> float:
    return math.nan if value == "" else float(value)


@pytest.mark.parametrize("name", CHARTS)
def test_each_chart_is_written(out_dir, name):
    for ext in ("png", "svg", "csv"):
        path = out_dir / f"{name}.{ext}"
        assert path.is_file() and path.stat().st_size > 0, path
    assert (out_dir / f"{name}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"<svg" in (out_dir / f"{name}.svg").read_bytes()[:2000]


def test_work_precision_covers_every_body_and_rung(out_dir):
    rows = _rows(out_dir, "work_precision")
    assert {r["body"] for r in rows} == set(ab.CATALOGUE_BODIES)
    for body in ab.CATALOGUE_BODIES:
        sub = [r for r in rows if r["body"] == body]
        rungs = {r["rung"] for r in sub}
        assert {"secular", "series", "hansen", "second_order", "numerical"} <= rungs
        refs = [r for r in sub if r["is_reference"] == "True"]
        assert len(refs) == 1 and refs[0]["rung"] == refs[0]["reference"]
        assert refs[0]["reference"] in ("numerical", "real_orbit")
        assert all(_f(r["cost_ms"]) > 0.0 for r in sub)


def test_work_precision_estimates_bound_the_truth(out_dir):
    rows = [r for r in _rows(out_dir, "work_precision") if r["is_reference"] == "False"]
    below = [(r["body"], r["label"], r["true_error_mas"], r["estimate_vs_reference_mas"]) for r in rows
             if not _f(r["estimate_vs_reference_mas"]) >= _f(r["true_error_mas"])]
    assert not below, f"estimate below the true error: {below}"
    assert all(r["estimate_ge_true"] == "True" for r in rows)
    # the theory alone, against numerical (same fixed orbit), within the estimate without the physics terms
    fixed = [r for r in rows if r["true_error_vs_numerical_mas"] != ""]
    assert all(_f(r["theory_estimate_mas"]) >= _f(r["true_error_vs_numerical_mas"]) for r in fixed), fixed
    # the full estimate (what the ladder chooses by) adds the physics the reference shares
    assert all(_f(r["estimate_mas"]) >= _f(r["estimate_vs_reference_mas"]) for r in _rows(out_dir, "work_precision"))


def test_work_precision_ladder_climbs(out_dir):
    """Nutation with exact coefficients beats precession alone for every body; against the
    fixed-orbit reference, second order beats first order too (against the real orbit the
    orbit's motion may swamp that difference)."""
    rows = _rows(out_dir, "work_precision")
    for body in ab.CATALOGUE_BODIES:
        sub = [r for r in rows if r["body"] == body]
        err = {r["label"]: _f(r["true_error_mas"]) for r in sub}
        assert err["hansen"] < err["secular"], body
        if sub[0]["reference"] == "numerical":
            assert err["second_order"] < err["hansen"], body


def test_error_vs_order_converges_at_the_laplace_rate(out_dir):
    rows = _rows(out_dir, "error_vs_order")
    ratio = ab.geometric_ratio(rows, 0.1)
    assert ratio == pytest.approx(0.1 / LAPLACE_LIMIT, rel=0.15)
    # every second order at least (the coefficients come in steps of e^2 for some harmonics)
    err = [_f(r["nutation_error_mas"]) for r in rows if float(r["e"]) == 0.1]
    assert all(b < a for a, b in zip(err[:-2], err[2:]))


def test_error_vs_order_diverges_beyond_the_laplace_limit(out_dir):
    rows = [r for r in _rows(out_dir, "error_vs_order") if float(r["e"]) == 0.7]
    err = [_f(r["nutation_error_mas"]) for r in rows]
    assert min(err) > 1e3   # mas: never useful
    assert err[-1] > min(err) * 1.5          # turns round and grows again
    assert err[-1] > err[-3] > err[-5]
    assert all(r["beyond_laplace_limit"] == "True" and r["product_refuses"] == "True" for r in rows)
    assert "Laplace" in rows[0]["refusal"]
    below = [r for r in _rows(out_dir, "error_vs_order") if float(r["e"]) < LAPLACE_LIMIT]
    assert all(r["product_refuses"] == "False" for r in below)


def test_error_vs_order_estimates_bound_the_truth(out_dir):
    rows = _rows(out_dir, "error_vs_order")
    for r in rows:
        assert _f(r["estimate_mas"]) >= _f(r["nutation_error_mas"]), r
        # whole tracks: the same, plus the precession-rate difference over the orbit, above the
        # rounding of float64 pole vectors (~1e-15 rad)
        assert _f(r["track_estimate_one_orbit_mas"]) + ab.TRACK_ROUNDING_MAS >= _f(r["track_error_one_orbit_mas"]), r


def test_error_vs_span_estimates_bound_the_truth_and_grow(out_dir):
    rows = _rows(out_dir, "error_vs_span")
    checked = [r for r in rows if r["rung"] != "numerical"]
    assert checked
    below = [(r["body"], r["label"], r["span_years"], r["true_error_mas"], r["estimate_mas"]) for r in checked
             if not _f(r["estimate_mas"]) >= _f(r["true_error_mas"])]
    assert not below, f"estimate below the true error: {below}"
    for body in {r["body"] for r in rows}:
        for label in {r["label"] for r in rows}:
            sub = [r for r in rows if r["body"] == body and r["label"] == label]
            spans = [_f(r["span_years"]) for r in sub]
            assert spans == sorted(spans)
            est = [_f(r["estimate_mas"]) for r in sub]
            assert all(b >= a for a, b in pairwise(est)), (body, label)
            if label != "numerical":   # a running maximum over nested epoch sets
                true = [_f(r["true_error_mas"]) for r in sub]
                assert all(b >= a for a, b in pairwise(true)), (body, label)


def test_error_vs_span_crossings(out_dir):
    rows = _rows(out_dir, "error_vs_span")
    crossings = ab.read_csv(out_dir / "error_vs_span_crossings.csv")
    assert {float(c["threshold_mas"]) for c in crossings} == set(ab.THRESHOLDS_MAS)
    for c in crossings:
        if c["rung"] == "numerical":
            continue
        sub = [r for r in rows if r["body"] == c["body"] and r["label"] == c["label"]]
        thr, first, last = float(c["threshold_mas"]), _f(sub[0]["true_error_mas"]), _f(sub[-1]["true_error_mas"])
        x = _f(c["true_crossing_years"])
        if first >= thr:
            assert x == -math.inf
        elif last < thr:
            assert math.isnan(x)
        else:
            assert float(sub[0]["span_years"]) <= x <= float(sub[-1]["span_years"])


def test_crossing_interpolates_log_log():
    assert ab.crossing([1.0, 10.0], [1.0, 100.0], 10.0) == pytest.approx(math.sqrt(10.0))
    assert ab.crossing([1.0, 10.0], [20.0, 30.0], 10.0) == -math.inf
    assert math.isnan(ab.crossing([1.0, 10.0], [1.0, 2.0], 10.0))


def test_work_precision_falls_back_to_numerical(monkeypatch):
    """Where the real orbit is unavailable, the fixed-orbit integration is the reference, the
    estimates without the shared physics terms are held against it, and the chart says why."""
    import ephem.sun.rungs

    monkeypatch.setattr(ephem.sun.rungs, "real_orbit_unavailable", lambda body, t: "outside DE421 (test)")
    rows = ab.work_precision_rows("Vesta", ab.QUICK)
    assert {r["reference"] for r in rows} == {"numerical"}
    assert "real_orbit" not in {r["rung"] for r in rows}
    assert all("outside DE421 (test)" in r["note"] for r in rows)
    checked = [r for r in rows if not r["is_reference"]]
    assert checked and all(r["estimate_ge_true"] for r in checked)
    err = {r["label"]: r["true_error_mas"] for r in rows}
    assert err["second_order"] < err["hansen"] < err["secular"]


def test_averaging_vs_spin_fails_below_the_threshold_only(out_dir):
    """Rung 5 against rung 7 over one orbit (quick: triaxial Eros, the study's worst case, at
    ω/n = 3, 10, 30): both axes' relative errors fall as ω/n grows, the figure axis's is above 10%
    at the lowest ratio and below it from the product's threshold up, and the estimate bounds it
    wherever the study claims it."""
    for name in ("averaging_vs_spin_crossings", "averaging_vs_spin_bodies"):
        assert (out_dir / f"{name}.csv").stat().st_size > 0
    rows = _rows(out_dir, "averaging_vs_spin")
    assert [r["case"] for r in rows] and {r["body"] for r in rows} == {"Eros"}
    ratios = [_f(r["spin_orbit_ratio"]) for r in rows]
    assert ratios == sorted(ratios) and list(ratios) == list(ab.QUICK.avg_ratios)
    for key in ("relative_figure", "relative_momentum"):
        rel = [_f(r[key]) for r in rows]
        assert all(b < a for a, b in pairwise(rel)), (key, rel)
        # relative to the forced motion: the columns agree with the errors in mas
        for r in rows:
            err = _f(r["figure_error_mas" if key == "relative_figure" else "momentum_error_mas"])
            assert _f(r[key]) == pytest.approx(err / _f(r["displacement_mas"]), rel=1e-5)
    figure = [_f(r["relative_figure"]) for r in rows]
    assert figure[0] > ab.AVERAGING_LEVEL
    assert all(f < ab.AVERAGING_LEVEL for x, f in zip(ratios, figure) if x >= MIN_SPIN_ORBIT_RATIO)
    assert all((r["refused_by_product"] == "True") == (_f(r["spin_orbit_ratio"]) < MIN_SPIN_ORBIT_RATIO)
               for r in rows)
    (c,) = ab.read_csv(out_dir / "averaging_vs_spin_crossings.csv")
    x = _f(c["figure_crossing"])
    assert x == pytest.approx(ab.falls_below(ratios, figure, ab.AVERAGING_LEVEL), rel=1e-5)   # CSV: 6 digits
    assert ratios[0] < x < MIN_SPIN_ORBIT_RATIO and c["threshold_covers"] == "True"
    assert _f(c["momentum_crossing"]) < x   # L is the more robust axis


def test_averaging_vs_spin_marks_the_catalogue(out_dir):
    """Only the Moon (synchronous) is below the threshold; every other body is far above it."""
    bodies = ab.read_csv(out_dir / "averaging_vs_spin_bodies.csv")
    refused = {b["body"] for b in bodies if b["refused_by_product"] == "True"}
    assert refused == {"Moon"}
    assert _f(next(b for b in bodies if b["body"] == "Moon")["spin_orbit_ratio"]) == pytest.approx(1.0, abs=0.01)
    others = [_f(b["spin_orbit_ratio"]) for b in bodies if b["body"] != "Moon"]
    assert len(others) >= 6 and min(others) > 10 * MIN_SPIN_ORBIT_RATIO


def test_falls_below_interpolates_log_log():
    assert ab.falls_below([1.0, 100.0], [1.0, 0.01], 0.1) == pytest.approx(10.0)
    assert ab.falls_below([1.0, 10.0], [0.05, 0.01], 0.1) == -math.inf
    assert ab.falls_below([1.0, 10.0], [1.0, 0.5], 0.1) == math.inf
    # the last time it is above counts, not the first time it is below
    assert ab.falls_below([1.0, 2.0, 3.0, 4.0], [1.0, 0.05, 0.2, 0.01], 0.1) > 3.0
