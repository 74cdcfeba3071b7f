"""ephem.answers.figures: the figures draw exactly the API's arrays, with units, titles and clear errors."""
from __future__ import annotations

import io
import re
import threading
import xml.etree.ElementTree as ET
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest

from ephem import api
from ephem.answers import requests as answers   # where the plots take their answers: patched there
from ephem.answers import figures as plots
from ephem.exports import plot_drawing
from ephem.base.errors import InvalidInputError, NotApplicableError, UnknownBodyError

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
UNIT = re.compile(r"\[(arcsec|mas|deg|yr|kyr|Myr)\]")
REPO = Path(__file__).resolve().parents[2]

START, STOP, STEP = "2020-01-01", "2030-01-01", 5.0   # a decade of Vesta, 5-day step: 731 epochs


def figure(*args, **options):
    """The figure of a plot request made from render_plot's arguments (plots.plot_request: its inputs checked)."""
    return plots.figure(plots.plot_request(*args, **options))


def plot_data(*args, **options):
    """The arrays drawn for a plot request made from render_plot's arguments."""
    return plots.data(plots.plot_request(*args, **options))


def julian_epoch(jd):
    return 2000.0 + (np.asarray(jd) - 2451545.0) / 365.25


@pytest.fixture(scope="module")
def vesta_track():
    return api.track_arrays("Vesta", START, STOP, STEP)


def labels(fig) -> list[str]:
    return [text for ax in fig.axes for text in (ax.get_xlabel(), ax.get_ylabel()) if text]


def close(a, b):
    """The plotted data are the API's arrays, at most rescaled (a few roundings: rel 1e-13 = 450 ε)."""
    np.testing.assert_allclose(np.asarray(a, dtype=float), np.asarray(b, dtype=float), rtol=1e-13, atol=0.0)


# --- the plotted data are the API's arrays --------------------------------------------------------

def test_precession_lines_are_the_track(vesta_track):
    fig = figure("precession", "Vesta", START, STOP, STEP)
    top, bottom = fig.axes
    psi, dpsi = vesta_track["psi_arcsec"], vesta_track["delta_psi_arcsec"]
    assert np.max(np.abs(psi)) < 36000.0 and "[arcsec]" in top.get_ylabel()   # below 10°: arcsec
    close(top.lines[0].get_xdata(), julian_epoch(vesta_track["jd_tdb"]))
    close(top.lines[0].get_ydata(), psi)
    close(top.lines[1].get_ydata(), psi - dpsi)                             # the precession alone
    close(bottom.lines[0].get_ydata(), dpsi)
    # the time axis is in years and starts at the requested date (2020 January 1, within a day)
    assert "[yr]" in bottom.get_xlabel()
    assert abs(top.lines[0].get_xdata()[0] - 2020.0) < 1.0 / 365.25


def test_precession_switches_to_degrees_when_psi_is_large():
    # Itokawa precesses by about -460"/yr (Petit et al. 2014): ψ is past 10° by 2100
    ans = api.track_arrays("Itokawa", "2100-01-01", "2102-01-01", 10.0)
    fig = figure("precession", "Itokawa", "2100-01-01", "2102-01-01", 10.0)
    assert np.min(ans["psi_arcsec"]) < -36000.0
    assert "[deg]" in fig.axes[0].get_ylabel()
    close(fig.axes[0].lines[0].get_ydata(), ans["psi_arcsec"] / 3600.0)
    assert "[arcsec]" in fig.axes[1].get_ylabel()                         # Δψ stays in arcsec


def test_short_span_time_axis_is_days_since_start():
    ans = api.track_arrays("Earth", "2020-01-01", "2020-03-01", 1.0)
    fig = figure("precession", "Earth", "2020-01-01", "2020-03-01", 1.0)
    x = fig.axes[1].lines[0].get_xdata()
    close(x, ans["jd_tdb"] - ans["jd_tdb"][0])
    assert x[0] == 0.0 and x[-1] == pytest.approx(60.0)
    assert fig.axes[1].get_xlabel().startswith("days since 2020-01-01")


def test_nutation_loop_lines_are_the_track(vesta_track):
    fig = figure("nutation-loop", "Vesta", START, STOP, STEP)
    (ax,) = fig.axes
    x = vesta_track["delta_psi_arcsec"] * np.sin(np.radians(vesta_track["obliquity_deg"]))
    close(ax.lines[0].get_xdata(), x)
    close(ax.lines[0].get_ydata(), vesta_track["delta_epsilon_arcsec"])
    assert ax.get_xlabel() == "Δψ sin ε [arcsec]" and ax.get_ylabel() == "Δε [arcsec]"
    assert ax.get_aspect() == 1.0                                            # equal scales


def test_nutation_loop_in_mas_when_small():
    # Ceres: the loop is under 0.3" (Petit et al. 2014 Tables 7-8)
    ans = api.track_arrays("Ceres", START, STOP, STEP)
    fig = figure("nutation-loop", "Ceres", START, STOP, STEP)
    ax = fig.axes[0]
    assert "[mas]" in ax.get_xlabel() and "[mas]" in ax.get_ylabel()
    close(ax.lines[0].get_ydata(), ans["delta_epsilon_arcsec"] * 1000.0)


def test_nutation_loop_says_when_the_scales_differ():
    # Eros: Δε ~30" but Δψ sin ε < 1" (ε ≈ 89°): drawn to separate scales, and labelled so
    fig = figure("nutation-loop", "Eros", START, STOP, STEP)
    ax = fig.axes[0]
    assert ax.get_aspect() != 1.0
    assert "unequal scales" in ax.get_xlabel()
    assert "unequal scales" not in ax.get_ylabel()


def test_obliquity_offsets_from_the_labelled_mean(vesta_track):
    fig = figure("obliquity", "Vesta", START, STOP, STEP)
    ax = fig.axes[0]
    eps = vesta_track["obliquity_deg"]
    ref = round(float(np.mean(eps)), 6)
    assert f"{ref:.6f}°" in ax.get_ylabel() and "[arcsec]" in ax.get_ylabel()
    close(ax.lines[0].get_ydata(), (eps - ref) * 3600.0)
    # the offsets straddle zero (ε₀ is the mean) and are a few arcsec (Petit et al. 2014 Table 6: ~2")
    y = ax.lines[0].get_ydata()
    assert y.min() < 0.0 < y.max() and 0.5 < np.ptp(y) < 10.0


def test_obliquity_reference_only_for_small_ranges():
    assert plot_drawing.obliquity_reference_deg(np.array([10.0, 10.4])) == 10.2
    assert plot_drawing.obliquity_reference_deg(np.array([10.0, 10.6])) is None


def test_free_wobble_lines_are_the_free_motion():
    ans = api.free_motion_arrays("Earth", "2030-01-01", "2030-01-11", 0.05)
    fig = figure("free-wobble", "Earth", "2030-01-01", "2030-01-11", 0.05)
    space, body = fig.axes
    close(space.lines[0].get_xdata(), ans["figure_axis_offset_x_arcsec"])
    close(space.lines[0].get_ydata(), ans["figure_axis_offset_y_arcsec"])
    nu = np.radians(ans["andoyer_nu_deg"])
    close(body.lines[0].get_xdata(), ans["wobble_angle_J_arcsec"] * np.sin(nu))
    close(body.lines[0].get_ydata(), ans["wobble_angle_J_arcsec"] * np.cos(nu))
    for ax in (space, body):
        assert ax.get_aspect() == 1.0
        assert "[arcsec]" in ax.get_xlabel() and "[arcsec]" in ax.get_ylabel()


def test_dataset_reaches_the_data_and_the_title():
    cur = figure("nutation-loop", "Itokawa", START, STOP, 10.0)
    old = figure("nutation-loop", "Itokawa", START, STOP, 10.0, dataset="petit2014")
    ans = api.track_arrays("Itokawa", START, STOP, 10.0, dataset="petit2014")
    close(old.axes[0].lines[0].get_ydata(), ans["delta_epsilon_arcsec"])
    # the two catalogues differ (obliquity 178.7° against 157.3°): so must the loops
    assert not np.allclose(cur.axes[0].lines[0].get_ydata(), old.axes[0].lines[0].get_ydata())
    assert "Itokawa (petit2014 dataset)" in old.get_suptitle()
    assert "Itokawa (current dataset)" in cur.get_suptitle()


# --- titles and units -----------------------------------------------------------------------------

@pytest.mark.parametrize("kind", plots.KINDS)
def test_every_axis_label_has_a_unit_and_the_title_names_body_and_dataset(kind):
    body, stop, step = ("Earth", "2030-01-03", 0.02) if kind == "free-wobble" else ("Vesta", STOP, STEP)
    if kind == plots.HISTORY_KIND:      # start/stop in Julian years from J2000.0, the step in years
        body, stop = "Ceres", 1e5
        fig = figure(kind, body, -2e5, stop, step_years=1000.0)
    else:
        fig = figure(kind, body, START if kind != "free-wobble" else "2030-01-01", stop, step)
    assert all(ax.get_ylabel() for ax in fig.axes)                 # every panel: a y label
    assert any(ax.get_xlabel() for ax in fig.axes)                 # shared time axes: one x label
    for text in labels(fig):
        assert UNIT.search(text) or text.startswith("days since"), text
    title = fig.get_suptitle()
    assert f"{body} (current dataset)" in title
    if kind == plots.HISTORY_KIND:
        assert "model: averaged spin along the nbody orbit" in title and "estimated error" in title
    elif kind != "free-wobble":
        assert "model: hansen" in title and "estimated error" in title


def test_title_names_the_model_rung():
    fig = figure("precession", "Vesta", START, STOP, 30.0, model="series", order=4)
    assert "model: series N=4" in fig.get_suptitle()


# --- bytes ----------------------------------------------------------------------------------------

def test_png_bytes_decode_to_the_figure_size():
    png = plots.render("precession", "Vesta", START, STOP, STEP, fmt="png", dpi=50)
    assert png.startswith(PNG_SIGNATURE)
    image = matplotlib.image.imread(io.BytesIO(png), format="png")
    w, h = plot_drawing._FIGSIZE["precession"]
    assert image.shape[:2] == (round(h * 50), round(w * 50))
    assert image[..., :3].min() < 0.5                     # something dark was drawn on the white


def test_svg_parses_with_an_svg_root():
    svg = plots.render("nutation-loop", "Vesta", START, STOP, STEP, fmt="svg")
    root = ET.fromstring(svg)
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    assert plots.CONTENT_TYPES == {"png": "image/png", "svg": "image/svg+xml"}


def test_concurrent_renders_equal_sequential_ones():
    jobs = [("precession", "Vesta"), ("obliquity", "Ceres"), ("nutation-loop", "Earth")]
    expected = [plots.render(k, b, START, STOP, 20.0, dpi=40) for k, b in jobs]
    got = [None] * len(jobs)

    def run(i, k, b):
        got[i] = plots.render(k, b, START, STOP, 20.0, dpi=40)

    threads = [threading.Thread(target=run, args=(i, k, b)) for i, (k, b) in enumerate(jobs)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert got == expected


# --- defaults -------------------------------------------------------------------------------------

def test_default_track_step_resolves_every_orbit_and_respects_the_cap():
    period = plots._orbital_period_days(api.resolve_body("Itokawa"))
    step = plots.default_step_days("precession", "Itokawa", START, STOP)
    assert period / step >= 100.0
    assert api.epoch_grid(START, STOP, step)[2] <= plots.MAX_PLOT_POINTS
    # three millennia of the Earth: 100 steps per orbit would be 300 000 epochs; the cap wins
    long = plots.default_step_days("precession", "Earth", "1000-01-01", "4000-01-01")
    assert api.epoch_grid("1000-01-01", "4000-01-01", long)[2] <= plots.MAX_PLOT_POINTS
    fig = figure("precession", "Itokawa", START, STOP)        # no step given
    assert 2 < len(fig.axes[0].lines[0].get_xdata()) <= plots.MAX_PLOT_POINTS


def test_default_wobble_step_never_aliases_the_cone():
    # the Earth's figure axis circles L every 23.86 h: a daily step would alias it
    step = plots.default_step_days("free-wobble", "Earth", "2030-01-01", "2031-01-01")
    prec = api.free_motion_arrays("Earth", "2030-01-01", "2030-01-02", 1.0)["precession_period_days"]
    assert step <= prec / 8.0


# --- errors ---------------------------------------------------------------------------------------

def field_of(excinfo) -> str:
    return excinfo.value.field


@pytest.mark.parametrize("call, field", [
    (lambda: figure("histogram", "Vesta", START, STOP, STEP), "kind"),
    (lambda: plots.render("precession", "Vesta", START, STOP, STEP, fmt="jpeg"), "fmt"),
    (lambda: plots.render("precession", "Vesta", START, STOP, STEP, dpi=5000), "dpi"),
    (lambda: figure("precession", "Vesta", START, STOP, 0.001), "step_days"),      # 3.65 M points
    (lambda: figure("precession", "Vesta", START, STOP, -1.0), "step_days"),
    (lambda: figure("precession", "Vesta", STOP, START, STEP), "stop"),
    (lambda: figure("precession", "Vesta", START, START, STEP), "stop"),
    (lambda: figure("precession", "Vesta", "2020-01-01", "2020-01-05", 10.0), "step_days"),
    (lambda: figure("precession", "Vesta", "not a date", STOP, STEP), "start"),
    (lambda: figure("obliquity", "Vesta", START, STOP, STEP, J_arcsec=1.0), "J_arcsec"),
    (lambda: figure("free-wobble", "Earth", START, STOP, None, tolerance_mas=1.0), "tolerance_mas"),
    (lambda: figure("free-wobble", "Earth", "2030-01-01", "2031-01-01", 1.0), "step_days"),   # aliasing
    (lambda: figure("free-wobble", "Earth", "2000-01-01", "2100-01-01"), "stop"),           # too long
    (lambda: figure("free-wobble", "Vesta", "2030-01-01", "2030-01-02"), "J_arcsec"),
])
def test_bad_input_names_the_field(call, field):
    with pytest.raises(InvalidInputError) as excinfo:
        call()
    assert field_of(excinfo) == field


def test_unknown_body():
    with pytest.raises(UnknownBodyError, match="Pluto"):
        figure("precession", "Pluto", START, STOP, STEP)


def test_free_wobble_without_published_J_needs_one():
    with pytest.raises(InvalidInputError, match="give the wobble amplitude J"):
        figure("free-wobble", "Vesta", "2030-01-01", "2030-01-02")
    fig = figure("free-wobble", "Vesta", "2030-01-01", "2030-01-02", J_arcsec=10.0)
    assert "J₀ = 10″" in fig.get_suptitle()
    assert np.max(np.hypot(fig.axes[0].lines[0].get_xdata(), fig.axes[0].lines[0].get_ydata())) == \
        pytest.approx(10.0, rel=1e-6)


def test_synchronous_rotator_track_is_drawn():
    fig = figure("precession", "Moon", START, STOP, STEP)
    assert "Moon" in fig.get_suptitle()


# --- the documentation figures --------------------------------------------------------------------

def test_regenerate_doc_figures_writes_png_and_svg(tmp_path, monkeypatch):
    monkeypatch.setattr(plots, "DOC_FIGURES", (("loop", "nutation-loop", "Ceres", "current", START, None),))
    paths = plots.regenerate_doc_figures(tmp_path, dpi=40)
    assert sorted(p.name for p in paths) == ["loop.png", "loop.svg"]
    assert (tmp_path / "loop.png").read_bytes().startswith(PNG_SIGNATURE)
    ET.parse(tmp_path / "loop.svg")
    # stop=None is one orbit: the loop closes on itself
    y = figure("nutation-loop", "Ceres", START,
                     api.epoch_grid(START, START, 1.0)[0] + plots._orbital_period_days(api.resolve_body("Ceres")),
                     ).axes[0].lines[0].get_ydata()
    assert abs(y[-1] - y[0]) < 0.01 * np.ptp(y)


def test_doc_embeds_figures_that_exist():
    doc = (REPO / "docs" / "plots.md").read_text()
    embedded = re.findall(r"\]\((figures/[^)]+)\)", doc)
    assert embedded
    for rel in embedded:
        assert (REPO / "docs" / rel).is_file(), rel
    for stem, *_ in plots.DOC_FIGURES:
        assert f"figures/{stem}.png" in doc
        assert (REPO / "docs" / "figures" / f"{stem}.svg").is_file()


def test_route_and_cli_serve_the_figures(tmp_path):
    from fastapi.testclient import TestClient
    from typer.testing import CliRunner

    from ephem.cli import app as cli
    from service.app import app as web

    c = TestClient(web)
    q = "start=2020-01-01&stop=2024-01-01&dataset=petit2014"
    png = c.get(f"/v1/bodies/vesta/track.png?{q}&kind=nutation-loop&dpi=60")
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    assert png.content == plots.render("nutation-loop", "vesta", "2020-01-01", "2024-01-01", fmt="png",
                                 dataset="petit2014", dpi=60)
    svg = c.get(f"/v1/bodies/vesta/track.svg?{q}&kind=obliquity")
    assert svg.status_code == 200 and svg.headers["content-type"].startswith("image/svg+xml")
    assert ET.fromstring(svg.content).tag.endswith("svg")
    assert c.get(f"/v1/bodies/vesta/track.png?{q}&kind=pie").status_code == 422
    assert c.get("/v1/bodies/moon/track.png?start=2020-01-01&stop=2021-01-01").status_code == 200
    out = tmp_path / "loop.png"
    res = CliRunner().invoke(cli, ["plot", "vesta", "--kind", "nutation-loop", "--start", "2020-01-01", "--stop",
                                   "2024-01-01", "--dataset", "petit2014", "--dpi", "60", "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert out.read_bytes() == png.content
    bad = CliRunner().invoke(cli, ["plot", "vesta", "--start", "2020-01-01", "--stop", "2021-01-01",
                                   "--out", str(tmp_path / "x.pdf")])
    assert bad.exit_code == 2 and "out" in bad.stderr


# --- obliquity-history: the obliquity over millennia (ephem.api.history) ------------------------------

HISTORY = plots.HISTORY_KIND
Y0, Y1, YSTEP = -2e5, 1e5, 1000.0        # 301 epochs of Ceres, ~0.3 s


@pytest.fixture(scope="module")
def ceres_history():
    return api.history("Ceres", Y0, Y1, YSTEP)


@pytest.fixture(scope="module")
def ceres_history_figure():
    return figure(HISTORY, "Ceres", Y0, Y1, step_years=YSTEP)


def test_history_figure_draws_the_history_answer(ceres_history, ceres_history_figure):
    top, middle, bottom = ceres_history_figure.axes
    close(top.lines[0].get_xdata(), ceres_history["year"] / 1e3)                 # kyr over a 300-kyr span
    close(top.lines[0].get_ydata(), ceres_history["obliquity_deg"])
    close(middle.lines[0].get_ydata(), ceres_history["precession_angle_deg"])
    assert middle.get_ylabel() == "precession angle ψ\n[deg]"
    close(bottom.lines[0].get_ydata(), ceres_history["orbit_inclination_deg"])
    assert bottom.get_xlabel() == "years from J2000.0 (TDB) [kyr]"
    assert top.get_ylabel() == "obliquity ε [deg]"
    assert "inclination" in bottom.get_ylabel() and "J2000 ecliptic [deg]" in bottom.get_ylabel()
    # the band is ε ± obliquity_error_deg: its vertices span exactly that range
    (band,) = top.collections
    verts = np.concatenate([path.vertices for path in band.get_paths()])
    eps, err = ceres_history["obliquity_deg"], ceres_history["obliquity_error_deg"]
    assert verts[:, 1].min() == pytest.approx(float(np.min(eps - err)), rel=1e-12)
    assert verts[:, 1].max() == pytest.approx(float(np.max(eps + err)), rel=1e-12)
    legend = [t.get_text() for t in top.get_legend().get_texts()]
    assert any("obliquity_error_deg" in t for t in legend)
    assert not any("not meaningful" in t for t in legend)        # Ceres: meaningful over the whole span
    title = ceres_history_figure.get_suptitle()
    assert "Ceres (current dataset): obliquity history, -200 to 100 kyr from J2000.0" in title
    assert "nbody orbit" in title and "estimated error" in title and "(obliquity)" in title


def test_history_time_unit_follows_the_span():
    assert plot_drawing.history_time_axis([-3e6, 1e6]) == (1e6, "years from J2000.0 (TDB) [Myr]")
    assert plot_drawing.history_time_axis([-2e5, 1e5]) == (1e3, "years from J2000.0 (TDB) [kyr]")
    assert plot_drawing.history_time_axis([0.0, 1000.0]) == (1.0, "years from J2000.0 (TDB) [yr]")


def test_history_hatches_where_it_stops_meaning_anything(monkeypatch):
    years = np.arange(-10_000.0, 5_001.0, 500.0)
    fake = {"body": "Mars", "dataset": "current", "perturbers": ["Sun"], "year": years,
            "obliquity_deg": 25.0 + np.sin(years / 1e3), "obliquity_error_deg": np.full(years.size, 0.1),
            "orbit_inclination_deg": 1.8 + 0.1 * np.cos(years / 3e3), "precession_angle_deg": -0.002 * years,
            "meaningful_from_year": -4000.0, "meaningful_to_year": 2000.0,
            "model": {"name": "secular", "estimated_error_mas": 4.0e6, "warnings": ["..."]}}
    monkeypatch.setattr(answers, "history", lambda *a, **k: fake)
    assert plot_drawing.meaningless_spans(fake) == [pytest.approx((-10_000.0, -4000.0), abs=1e-9),
                                             pytest.approx((2000.0, 5000.0), abs=1e-9)]
    fig = figure(HISTORY, "Mars", -10_000, 5_000, step_years=500)
    top, middle, bottom = fig.axes
    for ax in (top, middle, bottom):                              # both hatched spans on every panel
        spans = sorted(tuple(np.round(p.get_extents().transformed(ax.transData.inverted()).intervalx, 6))
                       for p in ax.patches if p.get_hatch())
        assert spans == [(-10.0, -4.0), (2.0, 5.0)]
    legend = [t.get_text() for t in top.get_legend().get_texts()]
    assert sum("history not meaningful" in t for t in legend) == 1      # one legend entry for both spans
    assert "4e+06" not in fig.get_suptitle() and "1.11°" in fig.get_suptitle()   # 4e6 mas: in degrees
    # None: not limited on that side
    fake.update(meaningful_from_year=None, meaningful_to_year=2000.0)
    assert plot_drawing.meaningless_spans(fake) == [pytest.approx((2000.0, 5000.0), abs=1e-9)]


def test_history_default_step_is_a_nice_number():
    """Nice numbers (1, 2, 2.5 or 5 times a power of ten), to rounding (1e-12 relative)."""
    for args, step in ((( -3e6, 1e6), 5000.0),          # 4000 rounds to 5000
                       ((-2e5, 1e5), 250.0),            # 300 rounds to 250
                       ((0, 1e4), 100.0),               # never below 100 years
                       ((0, 50), 50.0),                 # a span under 100 years: its two ends
                       (("-1.2e5", "0"), 100.0)):       # numeric strings
        assert plots.default_step_years(*args) == pytest.approx(step, rel=1e-12)


def test_history_takes_numeric_strings_and_a_default_step(ceres_history):
    ans = plot_data(HISTORY, "Ceres", "-2e5", " 1e5 ", step_years="1000")
    np.testing.assert_array_equal(ans["year"], ceres_history["year"])
    fig = figure(HISTORY, "Ceres", -1e4, 0)                 # default step: 100 years
    assert np.diff(fig.axes[0].lines[0].get_xdata())[0] == pytest.approx(100.0 / 1e3)


def test_history_png_and_svg(ceres_history_figure):
    png = plots.render(HISTORY, "Ceres", Y0, Y1, fmt="png", dpi=40, step_years=YSTEP)
    assert png.startswith(PNG_SIGNATURE)
    image = matplotlib.image.imread(io.BytesIO(png), format="png")
    w, h = plot_drawing._FIGSIZE[HISTORY]
    assert image.shape[:2] == (round(h * 40), round(w * 40))
    svg = plots.render(HISTORY, "Ceres", Y0, Y1, fmt="svg", step_years=YSTEP)
    assert ET.fromstring(svg).tag == "{http://www.w3.org/2000/svg}svg"


@pytest.mark.parametrize("call, field", [
    (lambda: figure(HISTORY, "Ceres", "three million years ago", 0), "start"),
    (lambda: figure(HISTORY, "Ceres", "2020-01-01", 0), "start"),          # a date: not for this kind
    (lambda: figure(HISTORY, "Ceres", -1e5, "soon"), "stop"),
    (lambda: figure(HISTORY, "Ceres", float("nan"), 0), "start"),
    (lambda: figure(HISTORY, "Ceres", 1e5, -1e5), "stop"),                  # stop before start
    (lambda: figure(HISTORY, "Ceres", 1e5, 1e5), "stop"),                   # no span
    (lambda: figure(HISTORY, "Ceres", -2e7, 1e6), "stop"),                  # beyond 20 Myr
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, step_years=0), "step_years"),
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, step_years=-5), "step_years"),
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, step_years=0.5), "step_years"),     # 200 001 epochs
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, step_years=2e5), "step_years"),     # a single epoch
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, step_years="x"), "step_years"),
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, 10.0), "step_days"),
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, model="hansen"), "model"),
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, J_arcsec=1.0), "J_arcsec"),
    (lambda: figure(HISTORY, "Ceres", -1e5, 0, orbit_model="kepler"), "orbit_model"),
    (lambda: figure("precession", "Vesta", START, STOP, STEP, step_years=10.0), "step_years"),
    (lambda: figure("obliquity", "Vesta", START, STOP, STEP, orbit_model="nbody"), "orbit_model"),
    (lambda: plots.default_step_days(HISTORY, "Ceres", -1e5, 0), "kind"),
])
def test_history_bad_input_names_the_field(call, field):
    with pytest.raises(InvalidInputError) as excinfo:
        call()
    assert field_of(excinfo) == field


def test_history_not_applicable_and_unknown_body():
    with pytest.raises(NotApplicableError, match="Itokawa"):
        figure(HISTORY, "Itokawa", Y0, Y1, step_years=YSTEP)
    with pytest.raises(UnknownBodyError):
        figure(HISTORY, "Pluto", Y0, Y1, step_years=YSTEP)


def test_history_cli_takes_negative_years(tmp_path):
    from typer.testing import CliRunner

    from ephem.cli import app as cli

    out = tmp_path / "sub" / "ceres.png"
    res = CliRunner().invoke(cli, ["plot", "ceres", "--kind", HISTORY, "--start", "-2e5", "--stop", "1e5",
                                   "--step-years", "1000", "--dpi", "40", "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert out.read_bytes() == plots.render(HISTORY, "ceres", -2e5, 1e5, fmt="png", dpi=40, step_years=1000)
    svg = tmp_path / "ceres.svg"
    res = CliRunner().invoke(cli, ["plot", "ceres", "--kind", HISTORY, "--start=-1e4", "--stop", "0",
                                   "--out", str(svg)])
    assert res.exit_code == 0, res.output
    ET.parse(svg)
    bad = CliRunner().invoke(cli, ["plot", "ceres", "--kind", HISTORY, "--start", "-1e4", "--stop", "-2e4",
                                   "--out", str(tmp_path / "x.png")])
    assert bad.exit_code == 2 and "stop" in bad.stderr
    helped = " ".join(CliRunner().invoke(cli, ["plot", "--help"]).output.replace("│", " ").split())
    assert "obliquity-history, Julian years from J2000.0 TDB" in helped and "--step-years" in helped


@pytest.fixture(scope="module")
def web():
    from fastapi.testclient import TestClient

    from service.app import create_app
    from service.settings import Settings

    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def test_history_route_serves_png_and_svg(web):
    q = f"start_year={Y0:g}&stop_year={Y1:g}&step_years={YSTEP:g}"
    png = web.get(f"/v1/bodies/ceres/history.png?{q}&dpi=40")
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    assert png.content == plots.render(HISTORY, "ceres", Y0, Y1, fmt="png", dpi=40, step_years=YSTEP)
    svg = web.get(f"/v1/bodies/ceres/history.svg?{q}&orbit_model=nbody")
    assert svg.status_code == 200 and svg.headers["content-type"].startswith("image/svg+xml")
    assert ET.fromstring(svg.content).tag.endswith("svg")


@pytest.mark.parametrize("query, status, kind, field", [
    ("start_year=1e5&stop_year=-2e5", 422, "invalid-input", "stop_year"),          # the client's name for stop
    ("start_year=soon&stop_year=1e5", 422, "invalid-input", "start_year"),
    ("start_year=-1e5&stop_year=0&step_years=0.5", 422, "invalid-input", "step_years"),
    ("start_year=-1e5&stop_year=0&step_years=0", 422, "invalid-input", "step_years"),
    ("start_year=-1e5&stop_year=0&orbit_model=kepler", 422, "invalid-input", "orbit_model"),
    ("start_year=-1e5&stop_year=0&dpi=5000", 422, "invalid-input", "dpi"),
])
def test_history_route_refuses_bad_input_as_a_problem(web, query, status, kind, field):
    r = web.get(f"/v1/bodies/ceres/history.png?{query}")
    assert r.status_code == status and r.headers["content-type"] == "application/problem+json", r.text
    problem = r.json()
    assert problem["type"].endswith(kind)
    assert [e["field"] for e in problem["errors"]] == [field]


def test_history_route_not_applicable_and_unknown(web):
    r = web.get("/v1/bodies/itokawa/history.png?start_year=-1e5&stop_year=0&step_years=1000")
    assert r.status_code == 422 and r.json()["type"].endswith("not-applicable")
    assert web.get("/v1/bodies/pluto/history.png?start_year=-1e5&stop_year=0").status_code == 404


def test_a_plot_request_is_checked_once_and_prints_on_one_line():
    """api.plot_request makes the request render_plot draws: the track kinds carry their TrackRequest (the track's
    checks), the history its canonical perturbers; its repr is one short line, not the Body's every value."""
    req = api.plot_request("precession", "Vesta", START, STOP, STEP, dataset="petit2014", model="series", order=4)
    assert isinstance(req, api.PlotRequest) and isinstance(req.track, api.TrackRequest)
    assert req.body.dataset == "petit2014" and req.track.epochs.count == 731 and req.track.choice.order == 4
    assert req.step == STEP and req.start == req.track.epochs.start
    text = repr(req)
    assert text.startswith("PlotRequest(precession of Vesta (petit2014), JD ") and "731 epochs" in text
    assert len(text) < 300 and "values" not in text
    history = api.plot_request(HISTORY, "Earth", -1e4, 0, perturbers="sun")
    assert history.perturbers == ("Sun",) and history.track is None and history.step == 100.0
    assert repr(history) == "PlotRequest(obliquity-history of Earth (current), -10000 to 0 by 100 yr, under Sun)"
    with pytest.raises(InvalidInputError) as err:      # refused when made, before any work
        api.plot_request("precession", "Vesta", START, STOP, STEP, model="hansen", order=3)
    assert err.value.field == "order"
