"""Mars' liquid-core chart (studies.mars_core_chart, docs/charts/mars_nonrigid.png), on a short span.

The physics it draws is tested in tests/forced/test_against_mars_nutation_models.py (the served 'nonrigid' track
meets WGCCRE 2015's periodic terms, the rigid one misses the semi-annual); here the study runs over two years,
weekly, into a temporary directory, writes its two files, and its numbers keep the properties a wrong chart would
break: the core moves the pole by more than nothing and by less than the rigid rungs' ``interior_rigid`` estimate
term, the WGCCRE pole it compares with is the test module's, and with the trend removed the non-rigid pole is the
closer to WGCCRE's.
"""
import csv

import numpy as np
import pytest

from ephem.base.constants import MAS
from ephem.bodies.catalogue import get_body
from ephem.sun.ladder import Ladder
from studies import mars_core_chart as mcc
from tests.forced.test_against_mars_nutation_models import wgccre_pole


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    prefix = tmp_path_factory.mktemp("mars") / "mars_nonrigid"
    summary = mcc.main(["--prefix", str(prefix), "--years", "2", "--step", "7", "--n", "1000", "--repeat", "2"])
    with open(prefix.with_suffix(".csv"), newline="") as fh:
        rows = list(csv.DictReader(fh))
    return prefix, summary, rows


def _col(rows, name):
    return np.array([float(r[name]) for r in rows])


def test_the_study_writes_the_png_and_the_csv(run):
    prefix, _, rows = run
    for ext in ("png", "csv"):
        assert prefix.with_suffix(f".{ext}").stat().st_size > 0
    assert prefix.with_suffix(".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    year = _col(rows, "year")
    assert year[0] == pytest.approx(2000.0, abs=0.01) and 2001.9 < year[-1] <= 2002.0
    assert np.all(np.diff(_col(rows, "jd_tdb")) == pytest.approx(7.0))


def test_the_core_moves_the_pole_by_less_than_the_rigid_rungs_say(run):
    _, summary, rows = run
    core = _col(rows, "nonrigid_vs_rigid_mas")
    jd = _col(rows, "jd_tdb")
    est = {e.rung: e for e in Ladder(get_body("mars"), axis="angular_momentum").estimates(jd)
           if e.rotation_scale is None and e.order is None}
    interior_rigid = est["second_order"].terms["interior_rigid"] / MAS
    assert 0.0 < core.max() < interior_rigid
    assert _col(rows, "interior_rigid_estimate_mas")[0] == pytest.approx(interior_rigid, abs=1e-4)
    assert summary["nonrigid_vs_rigid_max_mas"] == pytest.approx(core.max(), abs=1e-4)


def test_the_wgccre_pole_is_the_test_modules(run):
    jd = _col(run[2], "jd_tdb")
    ra, dec = wgccre_pole(jd)
    mine = mcc.wgccre_vectors(jd)
    theirs = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)
    assert mcc.angle_mas(mine, theirs).max() < 1e-3


def test_without_the_trend_the_nonrigid_pole_is_the_closer_to_wgccre(run):
    _, summary, rows = run
    rigid, core = _col(rows, "rigid_vs_wgccre_detrended_mas"), _col(rows, "nonrigid_vs_wgccre_detrended_mas")
    assert np.sqrt(np.mean(core**2)) < 0.5 * np.sqrt(np.mean(rigid**2))
    # the cost is measured (a ratio to numpy.sin, not compared between the rungs here: timings are noisy)
    assert summary["nonrigid_ratio_to_sin"] > 1.0 and summary["second_order_ratio_to_sin"] > 1.0
