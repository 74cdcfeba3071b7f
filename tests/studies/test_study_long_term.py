"""The long-term study (studies.long_term) in its quick version (-30..+10 kyr, short Vondrák spans): every piece
runs and writes its files, and the numbers in them hold together; the measures (period, last maximum) on
series whose answers are known."""
import math

import numpy as np
import pytest

from studies import long_term
from conftest import run_quick_charts

FILES = ("long_term_earth_vs_vondrak", "long_term_vs_laskar2004", "long_term_obliquities")


def test_the_quick_study_writes_every_file_and_its_numbers_hold(tmp_path):
    # one test for the whole run (not a module fixture, which each xdist worker would run again)
    out = run_quick_charts(long_term.tasks, tmp_path, 4)
    check_files(out)
    check_vondrak(out)
    check_laskar(out)
    check_summary(out)


def check_files(out_dir):
    for name in FILES:
        assert (out_dir / f"{name}.png").stat().st_size > 0
        assert long_term.read_csv(out_dir / f"{name}.csv")
    assert long_term.read_csv(out_dir / "long_term_summary.csv")


def check_vondrak(out_dir):
    rows = [r for r in long_term.read_csv(out_dir / "long_term_earth_vs_vondrak.csv") if r["section"] == "summary"]
    assert [r["span"] for r in rows] == [f"±{h / 1000:g} kyr" for h, _ in long_term.QUICK_VONDRAK_SPANS]
    one = rows[0]
    assert float(one["largest_pole_angle_arcsec"]) < 2.0            # 0.4″ measured over ±1 kyr
    assert float(one["largest_obliquity_diff_arcsec"]) < 2.0
    assert one["pole_within_estimate"] == "True"
    assert float(rows[1]["largest_pole_angle_arcsec"]) > float(one["largest_pole_angle_arcsec"])


def check_laskar(out_dir):
    rows = [r for r in long_term.read_csv(out_dir / "long_term_vs_laskar2004.csv") if r["section"] == "series"]
    assert {r["body"] for r in rows} == {"earth", "mars"}
    for r in rows:
        assert abs(float(r["ours_minus_la2004_deg"])) < 0.05, r      # 0.001-0.003° over ±100 kyr
    assert all(r["la2003_deg"] for r in rows if r["body"] == "mars")


def check_summary(out_dir):
    rows = long_term.read_csv(out_dir / "long_term_summary.csv")
    bodies = {r["body"]: r for r in rows if r["section"] == "body"}
    assert set(bodies) == set(long_term.BODIES)
    assert "Itokawa" in bodies["itokawa"]["reason"] and not bodies["itokawa"]["present_deg"]
    assert float(bodies["earth"]["present_deg"]) == pytest.approx(23.439, abs=0.01)
    assert float(bodies["ceres"]["present_deg"]) == pytest.approx(4.0, abs=0.1)
    assert float(bodies["moon"]["past_max_deg"]) - float(bodies["moon"]["past_min_deg"]) < 1e-6
    inputs = [r for r in rows if r["section"] == "inputs"]
    assert {r["body"] for r in inputs} == {"ceres", "mars"}
    mars = [r for r in inputs if r["body"] == "mars"]
    assert float(mars[-1]["present_rate_arcsec_per_yr"]) == pytest.approx(long_term.MARS_LA2004_P_ARCSEC, abs=1e-6)
    (maximum,) = [r for r in rows if r["section"] == "ceres_last_maximum"]
    assert -30_000 < float(maximum["year"]) < 0.0


def test_the_published_ranges_are_read_from_the_references():
    (ceres, vaillant) = long_term.published_ranges("ceres")
    assert (ceres["min"], ceres["max"]) == (2.0, 20.0) and "Ermakov" in ceres["citation"]
    (vesta,) = long_term.published_ranges("vesta")
    assert (vesta["min"], vesta["max"]) == (21.0, 45.0)
    assert long_term.published_ranges("eros") == []


def test_the_period_and_maximum_measures_on_a_known_series():
    t = np.arange(-3.0e6, 1.0, 1000.0)
    y = 10.0 + 8.0 * np.cos(2.0 * math.pi * (t + 14_000.0) / 24_500.0)
    assert long_term.dominant_period(t, y) == pytest.approx(24_500.0, rel=0.005)
    assert long_term.crossing_period(t, y) == pytest.approx(24_500.0, rel=0.005)
    year, value = long_term.last_maximum(t, y)
    assert year == pytest.approx(-14_000.0, abs=100.0) and value == pytest.approx(18.0, abs=0.05)
    assert math.isnan(long_term.dominant_period(t, np.full(t.shape, 6.69)))
