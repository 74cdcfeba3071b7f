"""The rotation-scale study (studies.rotation_scale) and the estimate-ratio chart (studies.estimate_ratios) in their
quick versions: the files they write and the numbers in them; the rung-choice report's comparison
(studies.rung_choice)."""
import math

import pytest

from studies import estimate_ratios, rotation_scale, rung_choice
from conftest import run_quick_charts


@pytest.fixture(scope="module")
def out_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("charts")
    run_quick_charts(rotation_scale.tasks, out, 1)
    run_quick_charts(estimate_ratios.tasks, out, 1)
    return out


def test_the_population_rows_hold_truth_estimate_and_pieces(out_dir):
    rows = rotation_scale.read_csv(out_dir / "rotation_scale_population.csv")
    assert len(rows) == 4 * len(rotation_scale.VARIANTS) * len(rotation_scale.AXES)
    for r in rows:
        pieces = sum(float(r[k]) for k in r if k.endswith("_mas") and k not in ("true_mas", "estimate_mas") and r[k])
        # the CSV prints the estimate and its pieces to 12 significant digits (repr of floats, summed anew)
        assert float(r["estimate_mas"]) == pytest.approx(pieces, rel=1e-9)
        assert float(r["true_mas"]) <= float(r["estimate_mas"]) + rotation_scale.FLOOR_MAS
    # re-estimating the stored rows with today's code gives the same estimates (the truths are kept)
    again = rotation_scale.re_estimate(rows)
    assert [float(a["estimate_mas"]) for a in again] == pytest.approx([float(r["estimate_mas"]) for r in rows],
                                                                       rel=1e-9)
    assert {(r["variant"], r["axis"]) for r in rotation_scale.ratio_rows(rows)} <= {
        (v, a) for v in rotation_scale.VARIANTS for a in rotation_scale.AXES}
    assert (out_dir / "rotation_scale_ratios.png").stat().st_size > 0


def test_the_estimate_ratio_chart_has_each_group(out_dir):
    rows = rotation_scale.read_csv(out_dir / "estimate_ratios.csv")
    assert {r["group"] for r in rows} == {"theory", "orbit_motion", "rotation_averaging"}
    summary = rotation_scale.read_csv(out_dir / "estimate_ratios_summary.csv")
    for s in summary:
        assert int(s["exceeded"]) == 0, s            # an estimate is a bound, in every group
        assert float(s["best"]) >= 1.0, s            # ... by itself, without the reference's own estimate
    assert (out_dir / "estimate_ratios.png").stat().st_size > 0


def test_the_rung_choice_comparison_pairs_the_same_scenes():
    before = [{"body": "Ceres", "span": "1 year", "axis": "figure", "tolerance_mas": "10.0", "served": "False",
               "model": "", "order": "", "rotation_scale": "", "estimated_error_mas": "465.3", "wall_ms": "2.0"}]
    after = [dict(before[0], served="True", model="series", order="4", rotation_scale="", estimated_error_mas="9.1",
                  wall_ms="1.0")]
    (row,) = rung_choice.compare_rows(before, after)
    assert row["before"] == "refused (465)" and row["after"] == "series N=4"
    assert math.isclose(row["before_ms"], 2.0) and math.isclose(row["after_ms"], 1.0)


def test_a_rung_choice_row_records_a_refusal_with_the_best_estimate():
    body = rung_choice.issue_bodies()["eros-like"]
    row = rung_choice.choice_row("eros-like", body, rung_choice.SPANS[0], "figure", 0.001)
    assert row["served"] is False and row["best_model"] and float(row["estimated_error_mas"]) > 0.001
    served = rung_choice.choice_row("eros-like", body, rung_choice.SPANS[0], "figure", 1e6)
    assert served["served"] is True and served["model"] == "secular"
