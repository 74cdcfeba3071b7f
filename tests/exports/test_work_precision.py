"""The work-precision chart (ephem.exports.work_precision, drawn by ephem.answers.figures.models_chart): every
plotted model is one SVG group with a <title> naming it and giving the JSON's error and cost, exactly one is
marked chosen (the JSON's), the ineligible ones are dimmed, the unavailable ones are left out and listed; the bytes
are the same for the same answer; the drawing is charged before it is drawn.

The titles print 6 significant digits, so each number is compared with the JSON's within half a unit of the
sixth digit (5e-6 relative, and a hair more for the decimal rounding of the printed text).
"""
from __future__ import annotations

import io
import re
import xml.etree.ElementTree as ET

import pytest

from ephem import api, host
from ephem.answers import figures
from ephem.exports import work_precision as wp

SVG = "{http://www.w3.org/2000/svg}"
#: 6 significant digits printed: half a unit of the last
PRINTED = 5.1e-6
TITLE = re.compile(r"^(?P<name>\w+)(?:, e-order (?P<order>\d+))?(?P<adds>(?: \+[a-z ]+?)*): estimated error "
                   r"(?P<error>[-+0-9.e]+) mas, predicted cost (?P<cost>[-+0-9.e]+) ms")


@pytest.fixture(scope="module")
def vesta() -> dict:
    """Vesta over a year at 30 days, 100 mas: some models within the tolerance, some over, one unavailable."""
    return api.track_models("vesta", "2025-01-01", "2026-01-01", 30.0, tolerance_mas=100.0)


@pytest.fixture(scope="module")
def vesta_svg(vesta) -> ET.Element:
    return ET.fromstring(api.models_chart(vesta, fmt="svg"))


def _points(root: ET.Element) -> dict[int, ET.Element]:
    return {int(g.get("id").removeprefix("wp-point-")): g for g in root.iter(f"{SVG}g")
            if (g.get("id") or "").startswith("wp-point-")}


def _plotted(m: dict) -> bool:
    return bool(m["available"]) and m["estimated_error_mas"] is not None and m["estimated_cpu_ms"] is not None


def _opacity(group: ET.Element) -> float:
    """The fill opacity of a point's marker (1 when its style sets none)."""
    (use,) = group.iter(f"{SVG}use")
    found = re.search(r"fill-opacity: ([0-9.]+)", use.get("style", ""))
    return float(found.group(1)) if found else 1.0


def test_one_titled_point_per_model_with_the_jsons_numbers(vesta, vesta_svg):
    points = _points(vesta_svg)
    want = {i for i, m in enumerate(vesta["models"]) if _plotted(m)}
    assert set(points) == want and len(want) >= 30
    for i, g in points.items():
        m = vesta["models"][i]
        titles = g.findall(f"{SVG}title")
        assert len(titles) == 1, i
        got = TITLE.match(titles[0].text)
        assert got, titles[0].text
        assert got["name"] == m["name"]
        assert (got["order"] is None and m["order"] is None) or int(got["order"]) == m["order"]
        assert ("+rotation scale" in got["adds"]) == bool(m["rotation_scale"])
        assert float(got["error"]) == pytest.approx(m["estimated_error_mas"], rel=PRINTED)
        assert float(got["cost"]) == pytest.approx(m["estimated_cpu_ms"], rel=PRINTED)


def test_exactly_one_point_is_marked_chosen_and_it_is_the_jsons(vesta, vesta_svg):
    points = _points(vesta_svg)
    chosen = [i for i, g in points.items() if "chosen" in g.get("class", "").split()]
    assert chosen == [i for i, m in enumerate(vesta["models"]) if m["chosen"]]
    assert vesta["models"][chosen[0]]["name"] == vesta["chosen"]
    assert points[chosen[0]].find(f"{SVG}title").text.endswith("; chosen")
    assert len([e for e in vesta_svg.iter() if e.get("id") == "wp-chosen-ring"]) == 1


def test_the_ineligible_are_dimmed_and_the_eligible_not(vesta, vesta_svg):
    tol = vesta["tolerance_mas"]
    over = within = 0
    for i, g in _points(vesta_svg).items():
        m = vesta["models"][i]
        eligible = m["estimated_error_mas"] <= tol           # each is available: drawn
        assert ("ineligible" in g.get("class").split()) == (not eligible), i
        if eligible:
            within += 1
            assert _opacity(g) == 1.0, i
        else:
            over += 1
            assert _opacity(g) == pytest.approx(wp.DIM_ALPHA), i
    assert over and within                                    # the fixture holds both kinds
    assert len([e for e in vesta_svg.iter() if e.get("id") == "wp-tolerance"]) == 1


def test_the_unavailable_are_left_out_and_listed(vesta, vesta_svg):
    left = [m for m in vesta["models"] if not _plotted(m)]
    rigid = next(m for m in left if m["name"] == "nonrigid")  # Vesta is rigid in this project
    desc = vesta_svg.find(f"{SVG}desc").text
    assert "Not drawn: " in desc and f"nonrigid ({rigid['why_not'][:40]}" in desc
    assert all(f"{wp.label(m)} (" in desc.split("Not drawn: ", 1)[1] for m in left)
    assert vesta_svg.get("role") == "img" and vesta_svg.get("aria-labelledby") == "wp-title wp-desc"
    assert "Vesta" in vesta_svg.find(f"{SVG}title").text
    assert f"{len(vesta['models']) - len(left)} of the {len(vesta['models'])} models" in desc


def test_the_same_answer_gives_the_same_bytes(vesta):
    assert api.models_chart(vesta, fmt="svg") == api.models_chart(vesta, fmt="svg")
    png = api.models_chart(vesta, fmt="png", dpi=50)
    assert png == api.models_chart(vesta, fmt="png", dpi=50)
    from PIL import Image

    with Image.open(io.BytesIO(png)) as im:
        assert im.size == (round(wp.FIGSIZE[0] * 50), round(wp.FIGSIZE[1] * 50))


def _synthetic(tolerance, **extra) -> dict:
    """An answer without the eligible key (as before the choice by predicted cost): eligibility by the fallback."""
    def model(name, error, cost, available=True, **more):
        return {"name": name, "order": None, "description": "", "available": available,
                "why_not": None if available else "cannot serve these epochs", "estimated_error_mas": error,
                "error_terms_mas": None, "free_wobble": False, "rotation_scale": None, "estimated_cpu_ms": cost,
                "estimated_memory_mb": 1.0, "chosen": False, **more}
    models = [model("secular", 500.0, 2.0), model("hansen", 50.0, 3.0, chosen=tolerance is not None),
              model("numerical", 5.0, 80.0, free_wobble=True, rotation_scale="oppolzer"),
              model("nonrigid", None, None, available=False)]
    return {"body": "Testbody", "dataset": "current", "perturbers": ["Sun"], "theory": "a test family",
            "start_jd_tdb": 2460000.5, "stop_jd_tdb": 2460100.5, "epochs": 11, "tolerance_mas": tolerance,
            "chosen": "hansen" if tolerance is not None else None, "models": models, **extra}


def test_without_the_eligible_key_eligibility_is_available_and_within_the_tolerance():
    ans = _synthetic(100.0)
    root = ET.fromstring(figures.models_chart(ans, fmt="svg"))
    points = _points(root)
    assert set(points) == {0, 1, 2}
    assert [("ineligible" in points[i].get("class")) for i in (0, 1, 2)] == [True, False, False]
    assert "+wobble +rotation scale" in points[2].find(f"{SVG}title").text
    rows = wp.model_rows(ans)
    assert [r["eligible"] for r in rows] == [False, True, True, False]
    assert [r["variant"] for r in rows] == ["", "", "+wobble +rotation scale", ""]
    # no tolerance: every available model is eligible, none chosen, no line
    free = _synthetic(None)
    root = ET.fromstring(figures.models_chart(free, fmt="svg"))
    assert not [g for g in _points(root).values() if "ineligible" in g.get("class") or "chosen" in g.get("class")]
    assert not [e for e in root.iter() if e.get("id") == "wp-tolerance"]
    assert [r["eligible"] for r in wp.model_rows(free)] == [True, True, True, False]


def test_the_answers_eligible_key_wins_over_the_fallback():
    ans = _synthetic(100.0)
    ans["models"][1]["eligible"] = False          # as a rule beyond the tolerance might say
    assert [r["eligible"] for r in wp.model_rows(ans)][:2] == [False, False]
    assert "ineligible" in _points(ET.fromstring(figures.models_chart(ans, fmt="svg")))[1].get("class")


def test_a_tolerance_far_from_every_estimate_is_noted_not_drawn():
    ans = _synthetic(1e-9)
    ans["models"][1]["chosen"] = False
    fig = wp.figure(ans)
    ymin, ymax = fig.axes[0].get_ylim()
    assert ymin > 1.0 and ymax < 1e4                           # the estimates' range, not down to 1e-9 mas
    texts = " ".join(t.get_text() for t in fig.texts)
    assert "tolerance 1e-09 mas: off the chart, below every model's estimate" in texts


def test_the_drawing_is_charged_before_it_is_drawn(vesta, monkeypatch):
    drawn = []
    monkeypatch.setattr(wp, "figure", lambda answer: drawn.append(answer))
    cost = figures.chart_cost(len(vesta["models"]), "svg")
    with host.budget(cost.cpu_s * 0.5, 1000.0):
        with pytest.raises(api.OverBudgetError) as refused:
            figures.models_chart(vesta, fmt="svg")
    assert refused.value.field == "format" and not drawn
    png = figures.chart_cost(len(vesta["models"]), "png", 300)
    assert png.cpu_s > 1.5 * cost.cpu_s                  # the PNG's pixels, at 300 dpi
    with host.budget(0.5 * (cost.cpu_s + png.cpu_s), 1000.0):
        with pytest.raises(api.OverBudgetError) as refused:
            figures.models_chart(vesta, fmt="png", dpi=300)
    assert refused.value.field == "dpi" and not drawn


def test_bad_format_or_dpi_names_the_field(vesta):
    with pytest.raises(api.InvalidInputError) as bad:
        figures.models_chart(vesta, fmt="pdf")
    assert bad.value.field == "fmt"
    with pytest.raises(api.InvalidInputError) as bad:
        api.track_models_chart("vesta", "2025-01-01", "2026-01-01", 30.0, fmt="png", dpi=1000)
    assert bad.value.field == "dpi"
