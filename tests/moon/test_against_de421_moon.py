"""The Moon against lunar laser ranging: JPL's DE421 lunar orientation (issue 40).

The kernels come with the install (the test extra's ``lunarsky`` ships ``moon_pa_de421_1900-2050.bpc`` and
``moon_080317.tf``; data/moon_orientation.toml [kernel]); CSPICE (spiceypy) reads them here, independently of the
library's own reader (jplephem). Times are TDB seconds past J2000, et = (JD − 2451545) × 86400: no leap seconds.

(a) The files: the installed ones are those data/moon_orientation.toml names (SHA-256); its PA→ME angles are the frame
    kernel's lines; the matrix the library builds from them is CSPICE's; its reading of the binary PCK is CSPICE's.
(b) Every model and axis the library serves against DE421's matching axis (``figure``: MOON_PA +Z; ``mean_rotation``:
    MOON_ME +Z) at every epoch, over the kernel's whole span at 5-day steps and over windows of 1 and 10 years: the
    model's estimate bounds the largest distance, and by no more than :data:`RATIO_MAX` (the table is printed; -s).
(c) The issue's goal: the default (``librations``) within 5″ of DE421 on both axes over 1900-2050.
(d) The ``de421`` model is DE421 itself, refused outside its span naming it, and unavailable (with why) without the
    package; the free wobble shipped is the one measured again here.
"""
from __future__ import annotations

import math
import re
import tomllib
from functools import lru_cache

import numpy as np
import pytest

from ephem import api
from ephem.base.errors import NotApplicableError
from ephem.base.paths import data_dir
from ephem.moon import lunar_kernel
from ephem.moon.orientation import me_to_pa

spice = pytest.importorskip("spiceypy")

ARCSEC = math.pi / 648_000.0
J2000 = 2451545.0
#: the kernel's span, 1900-01-01 to 2051-01-01 TDB, less half a day at each end
START, STOP = 2415021.0, 2470172.0
#: the issue's grid: the whole span at 5-day steps
STEP = 5.0
#: windows (years: first JD of each): the spans the estimates must hold at
WINDOWS = {1: (2415021.0, 2433283.0, 2451545.0, 2469807.0), 10: (2415021.0, 2440588.0, 2451545.0, 2466154.0)}
#: the integration's windows: it runs from the pole epoch (J2000) to each, so those after it (a 1900 window would
#: integrate a century again: the whole span has it)
INTEGRATION_WINDOWS = {1: (2451545.0, 2469807.0), 10: (2451545.0, 2466154.0)}
MODELS = ("cassini", "librations", "integration")
AXES = ("figure", "mean_rotation")
FRAMES = {"figure": "MOON_PA", "mean_rotation": "MOON_ME"}
#: an estimate bounds the distance by at most this: "about 3x" (the largest measured, 3.3, is the 1-year windows
#: about 2000, where the models come closest to DE421)
RATIO_MAX = 3.5
#: the issue's goal for the default model, arcsec
GOAL_ARCSEC = 5.0


@lru_cache(maxsize=1)
def _orientation() -> dict:
    with open(data_dir() / "moon_orientation.toml", "rb") as fh:
        return tomllib.load(fh)


@pytest.fixture(scope="module")
def kernels():
    pck, fk = lunar_kernel.kernel_paths()
    spice.kclear()
    spice.furnsh(str(fk))
    spice.furnsh(str(pck))
    yield pck, fk
    spice.kclear()


def _et(jd):
    return (np.asarray(jd, dtype=float) - J2000) * 86400.0


def _de421_pole(jd, axis: str) -> np.ndarray:
    """DE421's pole (ICRF unit vectors) by CSPICE: +Z of MOON_PA or MOON_ME in J2000 (the ICRF in SPICE)."""
    return np.array([spice.pxform(FRAMES[axis], "J2000", et)[:, 2] for et in _et(jd)])


def _vectors(tr) -> np.ndarray:
    ra, dec = np.radians(np.asarray(tr["pole_ra_deg"])), np.radians(np.asarray(tr["pole_dec_deg"]))
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


def _angle(a, b) -> np.ndarray:
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))


def measure(model: str, axis: str, start: float, stop: float, step: float) -> dict:
    """The model's track against DE421's matching axis: largest and rms distance (arcsec), its estimate (arcsec)."""
    tr = api.track_arrays("moon", start, stop, step, model=model, axis=axis)
    d = _angle(_vectors(tr), _de421_pole(tr["jd_tdb"], axis)) / ARCSEC
    est = tr["model"]["estimated_error_mas"] / 1000.0
    return {"model": model, "axis": axis, "years": round((stop - start) / 365.25), "start": start,
            "whole": start == START and stop == STOP,
            "max": float(d.max()), "rms": float(np.sqrt(np.mean(d * d))), "estimate": est,
            "ratio": est / float(d.max())}


# --- (a) the files ---------------------------------------------------------------------------------------------

def test_the_installed_kernels_are_the_ones_named(kernels):
    pck, fk = kernels
    k = _orientation()["kernel"]
    assert lunar_kernel.file_sha256(pck) == k["pck_sha256"] and pck.stat().st_size == k["pck_bytes"]
    assert lunar_kernel.file_sha256(fk) == k["frame_kernel_sha256"] and fk.stat().st_size == k["frame_kernel_bytes"]
    lo, hi = lunar_kernel.span()
    assert (lo, hi) == (2415020.5, 2470172.5)


def test_the_stored_angles_are_the_frame_kernels_lines(kernels):
    # the verbatim lines are the file's, at the lines named; the floats are what they print
    d = _orientation()["pa_to_me"]
    lines = kernels[1].read_text(encoding="ascii").splitlines()
    first, last = (int(x) for x in d["lines"].split("-"))
    assert lines[first - 1:last] == d["verbatim"]
    numbers = dict(re.findall(r"(TKFRAME_31007_\w+)\s*=\s*\(([^)]*)\)", "\n".join(d["verbatim"])))
    assert [float(x) for x in numbers["TKFRAME_31007_ANGLES"].split()] == d["angles_arcsec"]
    assert [int(x) for x in numbers["TKFRAME_31007_AXES"].replace(",", " ").split()] == d["axes"]


def test_the_pa_me_rotation_is_cspices(kernels):
    # MOON_ME -> MOON_PA coordinates: a constant (TK) frame, the same at any epoch; rounding only
    theirs = np.array(spice.pxform("MOON_ME", "MOON_PA", 0.0))
    assert np.abs(me_to_pa() - theirs).max() < 1e-15
    assert np.degrees(_angle(me_to_pa()[2], np.array([0.0, 0.0, 1.0]))) * 3600.0 == pytest.approx(78.5606, abs=1e-4)


def test_the_library_reads_the_pck_as_cspice_does(kernels):
    # jplephem's Chebyshev pieces against CSPICE's (the same coefficients): the Euler angles reach 4e3 rad over the
    # span (ulp 1e-12), the matrices agree to 1e-11
    jd = np.linspace(START, STOP, 301)
    ours = lunar_kernel.pa_axes_icrf(jd)
    theirs = np.array([spice.pxform("MOON_PA", "J2000", et) for et in _et(jd)])
    assert np.abs(ours - theirs).max() < 1e-11


# --- (b), (c) every model and axis against DE421 -----------------------------------------------------------------

@pytest.fixture(scope="module")
def table(kernels):
    """Every model and axis over the whole span (5-day steps) and the 1- and 10-year windows (daily)."""
    rows = []
    for axis in AXES:
        for model in MODELS:
            rows.append(measure(model, axis, START, STOP, STEP))
            for years, starts in (INTEGRATION_WINDOWS if model == "integration" else WINDOWS).items():
                for s in starts:
                    rows.append(measure(model, axis, s, min(s + years * 365.25, STOP), 1.0 if years == 1 else 2.0))
    print("\nmodel        axis           span start      max″     rms″  estimate″  ratio")
    for r in rows:
        print(f"{r['model']:12s} {r['axis']:14s} {r['years']:3d}y {r['start']:.0f} {r['max']:8.3f} {r['rms']:8.3f} "
              f"{r['estimate']:10.3f} {r['ratio']:6.2f}")
    return rows


@pytest.mark.parametrize("axis", AXES)
@pytest.mark.parametrize("model", MODELS)
def test_every_estimate_bounds_its_distance_from_de421_by_at_most_about_three(table, model, axis):
    rows = [r for r in table if r["model"] == model and r["axis"] == axis]
    assert len(rows) == 1 + sum(len(s) for s in (INTEGRATION_WINDOWS if model == "integration" else WINDOWS).values())
    for r in rows:
        assert 1.0 <= r["ratio"] <= RATIO_MAX, r


@pytest.mark.parametrize("axis", AXES)
def test_the_default_is_within_five_arcsec_of_de421(table, axis):
    whole = next(r for r in table if r["model"] == "librations" and r["axis"] == axis and r["whole"])
    assert whole["max"] < GOAL_ARCSEC
    # and its estimate is under the goal too: a tolerance of 5″ is met without the kernel
    assert whole["estimate"] < GOAL_ARCSEC


def test_the_axes_are_distinct_where_de421s_are(table):
    # the two axes are 78.56″ apart in DE421; each model's pole is near its own axis, far from the other's
    tr = api.track_arrays("moon", 2451545.0, 2451575.0, 1.0, model="librations", axis="figure")
    other = _de421_pole(tr["jd_tdb"], "mean_rotation")
    assert (_angle(_vectors(tr), other) / ARCSEC).min() > 70.0


# --- (d) the de421 model ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("axis", AXES)
def test_the_de421_model_is_de421(kernels, axis):
    # the library's reader and CSPICE's on the same file: 1e-11 rad in the matrices, 2e-12 rad (4e-7″) in the pole
    tr = api.track_arrays("moon", START, STOP, 97.0, model="de421", axis=axis)
    assert (_angle(_vectors(tr), _de421_pole(tr["jd_tdb"], axis)) / ARCSEC).max() < 1e-5
    k = _orientation()["kernel"]
    expected = k["pa_accuracy_microrad"] if axis == "figure" else k["me_accuracy_microrad"]
    assert tr["model"]["error_terms_mas"]["ephemeris"] == pytest.approx(expected * 1e-6 / ARCSEC * 1e3, rel=1e-12)


def test_a_tolerance_within_de421s_accuracy_picks_it():
    tr = api.track_arrays("moon", "2020-01-01", "2021-01-01", 10.0, tolerance_mas=1000.0)
    assert tr["model"]["name"] == "de421"


def test_the_de421_model_is_refused_outside_its_span_naming_it():
    with pytest.raises(NotApplicableError, match=r"spans JD 2415020\.5 to 2470172\.5 TDB \(1900-01-01 to 2051-01-01\)"):
        api.track_arrays("moon", "2051-06-01", "2052-01-01", 10.0, model="de421")
    with pytest.raises(NotApplicableError, match="no model meets the tolerance"):
        api.track_arrays("moon", "1890-01-01", "1891-01-01", 10.0, tolerance_mas=1000.0)


def test_without_the_package_the_kernel_is_not_applicable_with_why(monkeypatch):
    from ephem.moon import kernel_rung

    monkeypatch.setattr(lunar_kernel, "unavailable", lambda: "DE421's lunar orientation ships in the package "
                        "'lunarsky' (the test extra), which is not installed")
    with pytest.raises(NotApplicableError, match="'lunarsky'"):
        api.track_arrays("moon", "2020-01-01", "2021-01-01", 10.0, model="de421")
    est = kernel_rung.kernel_estimate(np.array([2451545.0]), True)
    assert not est.available and "not installed" in est.why_not
    # the others answer as before
    assert api.track_arrays("moon", "2020-01-01", "2021-01-01", 10.0, tolerance_mas=5000.0)["model"]["name"] == \
        "librations"


def test_the_shipped_free_wobble_is_measured_again():
    # tools/derive_moon_free_wobble.py's fit over 1970-2010, redone: the printed 0.001″ digits
    from tools.derive_moon_free_wobble import measure as fit

    d = _orientation()["free_wobble"]
    again = fit()
    for key in ("x_cos_arcsec", "x_sin_arcsec", "y_cos_arcsec", "y_sin_arcsec"):
        assert again[key] == pytest.approx(d[key], abs=6e-4)
    # against a published measurement in a later ephemeris fitted to more ranges (Yang et al. 2017, DE430: 8.19″ x
    # 3.31″): the same mode, 90° apart on the two axes
    assert math.hypot(d["x_cos_arcsec"], d["x_sin_arcsec"]) == pytest.approx(8.19, abs=0.05)
    assert math.hypot(d["y_cos_arcsec"], d["y_sin_arcsec"]) == pytest.approx(3.31, abs=0.05)
    phase = math.atan2(d["x_sin_arcsec"], d["x_cos_arcsec"]) - math.atan2(d["y_sin_arcsec"], d["y_cos_arcsec"])
    assert abs(math.remainder(phase, math.pi)) == pytest.approx(0.5 * math.pi, abs=0.01)
