"""The free-motion charts (studies.free_motion), in their quick versions.

Runs both tasks once into a temporary directory (module-scoped, a few seconds), then checks the
files and properties of the plotted numbers that a wrong chart would break: the series error
falling with the order at small J, growing with J toward the separatrix, the exact solution agreeing
with a tight integration, the numeric error falling with rtol.
"""
from __future__ import annotations

import math
from itertools import pairwise

import pytest

from ephem.rotation.free_motion import SERIES_MAX_DELTA
from studies import free_motion as fb
from tests.conftest import run_quick_charts

CHARTS = ("free_motion_work_precision", "free_motion_series_failure")


@pytest.fixture(scope="module")
def out_dir(tmp_path_factory):
    return run_quick_charts(fb.tasks, tmp_path_factory.mktemp("charts"), len(CHARTS))


def _f(value: str) -> float:
    return math.nan if value == "" else float(value)


def _rows(out_dir, name):
    return fb.read_csv(out_dir / f"{name}.csv")


def test_files_written(out_dir):
    for name in CHARTS:
        for ext in ("png", "svg", "csv"):
            path = out_dir / f"{name}.{ext}"
            assert path.is_file() and path.stat().st_size > 0, path
        assert _rows(out_dir, name)
    assert (out_dir / "free_motion_work_precision.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_work_precision_methods_and_costs(out_dir):
    rows = _rows(out_dir, "free_motion_work_precision")
    s = fb.QUICK
    assert {r["method"] for r in rows} == {"exact", "series", "numeric"}
    assert len(rows) == len(s.bodies) * len(s.j_arcsec) * (1 + len(s.orders) + len(s.rtols))
    assert all(_f(r["cpu_ms"]) >= 0.0 for r in rows)


def test_exact_agrees_with_tight_integration(out_dir):
    # the reference itself: within the rtol 1e-13 integration's own error at every J
    for r in _rows(out_dir, "free_motion_work_precision"):
        assert _f(r["reference_check_rad"]) < 1e-12, r


def test_series_error_falls_with_order_at_small_j(out_dir):
    rows = [r for r in _rows(out_dir, "free_motion_work_precision") if r["method"] == "series"]
    j_values = sorted({_f(r["J_arcsec"]) for r in rows})
    for body in {r["body"] for r in rows}:
        for j in j_values:
            sel = sorted((int(r["parameter"]), _f(r["error_rad"])) for r in rows
                         if r["body"] == body and _f(r["J_arcsec"]) == j)
            errs = [e for _, e in sel]
            assert all(math.isfinite(e) for e in errs)
            # never worse with the order (beyond rounding), and at J = 10°: order 1 to 4 gains > 1e4
            assert all(b <= a * 1.01 + 1e-15 for a, b in pairwise(errs)), (body, j, sel)
            if j == 36000.0:
                assert errs[0] > 1e-5 and dict(sel)[4] < 1e-4 * errs[0], sel


def test_numeric_error_falls_with_rtol(out_dir):
    rows = [r for r in _rows(out_dir, "free_motion_work_precision") if r["method"] == "numeric"]
    for key in {(r["body"], r["J_arcsec"]) for r in rows}:
        sel = sorted(((_f(r["parameter"]), _f(r["error_rad"])) for r in rows
                      if (r["body"], r["J_arcsec"]) == key), reverse=True)
        assert sel[0][1] > sel[-1][1], sel
        assert all(e < 1e3 * rtol for rtol, e in sel), sel


def test_series_error_grows_toward_separatrix(out_dir):
    rows = [r for r in _rows(out_dir, "free_motion_series_failure") if r["sweep"] == "J"]
    assert {r["mode"] for r in rows} == {"short-axis"}
    for key in {(r["moments"], r["order"]) for r in rows}:
        sel = sorted((_f(r["J_deg"]), _f(r["error_rad"])) for r in rows if (r["moments"], r["order"]) == key)
        err = [math.inf if math.isnan(e) else e for _, e in sel]
        below = [e for (j, _), e in zip(sel, err) if j <= fb.SWITCH_J_DEG and j <= 10.0]
        # at the product's switch and below: the order-8 series is good to 1e-12 rad
        assert max(below) < 1e-12, sel
        # beyond 60°: orders of magnitude worse than anywhere below the switch, and failing near 90°
        far = [e for (j, _), e in zip(sel, err) if j >= 60.0]
        assert min(far) > 1e4 * max(below), sel
        assert err[-1] > 1e-2, sel
        # monotone (within rounding) from 10° on
        tail = [e for (j, _), e in zip(sel, err) if j >= 10.0]
        assert all(b >= a * 0.5 for a, b in pairwise(tail)), sel


def test_switch_line_matches_product():
    assert math.isclose(2.0 * math.sin(math.radians(fb.SWITCH_J_DEG) / 2) ** 2, SERIES_MAX_DELTA)


def test_beta_sweep_axisymmetric_is_exact(out_dir):
    rows = [r for r in _rows(out_dir, "free_motion_series_failure") if r["sweep"] == "beta"]
    assert rows
    zero = [r for r in rows if _f(r["beta"]) == 0.0]
    # β = 0 (A = B): the main problem is the whole motion, the series is exact at any order
    assert zero and all(_f(r["error_rad"]) < 1e-13 for r in zero)
    # the triaxial cases below the switch stay well converged at order 8
    assert all(_f(r["error_rad"]) < 1e-8 for r in rows), rows
