"""The non-rigid Earth rung (ephem.earth.model.NonRigidEarth) against ERFA's IAU 2006/2000A: its pole against the CIP
over 1900–2100, its measured residual envelope re-measured, and its choice by tolerance."""
import dataclasses
import math

import erfa
import numpy as np
import pytest

from ephem import api
from ephem.base.constants import MAS
from ephem.base.errors import NotApplicableError
from ephem.bodies.catalogue import get_body
from ephem.earth.lunisolar import earth_lunisolar
from ephem.earth.nonrigid import non_rigid_series
from ephem.earth.estimates import nonrigid_earth
from ephem.earth.model import residual_envelope
from ephem.forced.integration import angular_separation

#: ERFA's CIP is the figure axis's forced motion: the free wobble (polar motion) is not part of it, so the estimate
#: it is held to is the answer's less its free_wobble term
NOT_IN_THE_CIP = ("free_wobble",)


def cip(jd_tdb: np.ndarray) -> np.ndarray:
    """IAU 2006/2000A's CIP in the GCRS (erfa.xy06: the series form; TT for TDB, < 2 ms apart)."""
    x, y = erfa.xy06(jd_tdb, 0.0)
    return np.stack([x, y, np.sqrt(1.0 - x * x - y * y)], axis=-1)


def served_pole(ans: dict) -> np.ndarray:
    ra, dec = np.radians(ans["pole_ra_deg"]), np.radians(ans["pole_dec_deg"])
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


@pytest.mark.parametrize("start,stop,step", [("2000-01-01", "2030-01-01", 3.0), ("1900-01-02", "2099-12-30", 10.0)])
def test_the_pole_lies_within_its_estimate_of_erfas(start, stop, step):
    ans = api.track_arrays("earth", start, stop, step, model="nonrigid")
    assert ans["model"]["name"] == "nonrigid"
    bound = sum(v for k, v in ans["model"]["error_terms_mas"].items() if k not in NOT_IN_THE_CIP)
    err = angular_separation(served_pole(ans), cip(np.asarray(ans["jd_tdb"]))) / MAS
    # a bound, and not a loose one: its largest term, the nutation's residual envelope (4.2 mas), is within a factor
    # 2 of the error (measured 2.8 mas over 2000-2030 and 1900-2100; the sum is 5.3 and 7.2, iau_reference growing
    # as T² away from J2000)
    assert err.max() <= bound and err.max() > 0.5 * ans["model"]["error_terms_mas"]["nutation_residual"], \
        (err.max(), bound)
    # against the rigid rung, which the non-rigid one is for: 30x closer
    rigid = api.track_arrays("earth", start, stop, step, model="lunisolar")
    rigid_err = angular_separation(served_pole(rigid), cip(np.asarray(rigid["jd_tdb"]))) / MAS
    assert rigid_err.max() > 10.0 * err.max()


def test_the_earth_at_10_mas_over_2000_2030_is_served_on_the_forced_figure_axis():
    """The issue's request: a 10 mas tolerance over 2000-2030. The figure axis counts its 1" free wobble as an error
    and the angular momentum its 82 mas from the CIP (axis_relation), so both are refused; the forced figure axis
    (the CIP's definition: the free wobble is polar motion) is served by the non-rigid rung, and its pole lies within
    its whole estimate of ERFA's CIP (no term left aside)."""
    epochs = ("earth", "2000-01-01", "2030-01-01", 3.0)
    for axis in ("figure", "angular_momentum"):
        with pytest.raises(NotApplicableError, match="free_wobble|axis_relation"):
            api.track(*epochs, tolerance_mas=10.0, axis=axis)
    ans = api.track_arrays(*epochs, tolerance_mas=10.0, axis="forced_figure")
    m = ans["model"]
    assert m["name"] == "nonrigid" and m["axis"] == "forced_figure" and m["estimated_error_mas"] <= 10.0
    assert "free_wobble" not in m["error_terms_mas"] and "axis_relation" not in m["error_terms_mas"]
    err = angular_separation(served_pole(ans), cip(np.asarray(ans["jd_tdb"]))) / MAS
    assert err.max() <= m["estimated_error_mas"], (err.max(), m["estimated_error_mas"])
    # the same track as the figure axis's (the axis only changes what the estimate counts)
    fig = api.track_arrays(*epochs, model="nonrigid", axis="figure")
    assert np.max(angular_separation(served_pole(ans), served_pole(fig))) <= 1e-12


def test_the_residual_envelope_is_remeasured_against_erfa():
    """The stored envelope (data/lunisolar.toml [nonrigid_track]) against a fresh daily comparison with erfa.nut00a
    over 1900-2100: the daily maximum stays under it, and within 0.2 mas of it (the stored value is the 0.25-day
    maximum, 4.1025, rounded up to 4.2; a daily grid can miss the peak by (π/2 × 1 d / 13.7 d)² of a 10 mas term,
    0.1 mas)."""
    model = nonrigid_earth(get_body("earth"))
    jd = np.arange(2415020.5, 2488069.5, 1.0)
    dpsi, deps = model.series.nutation_at(jd)
    ref_psi, ref_eps = erfa.nut00a(jd, 0.0)
    fresh = float(np.max(math.sin(model.obliquity) * np.abs(dpsi - ref_psi) + np.abs(deps - ref_eps))) / MAS
    assert residual_envelope() - 0.2 <= fresh <= residual_envelope()


def test_the_transfer_function_is_what_closes_the_gap():
    """Independent of the rung's wiring: the same series with and without T(σ) against erfa.nut00a (rms over
    1900-2100): 63 -> 1.8 mas in Δψ, 22 -> 1.7 mas in Δε (docs/earth.md)."""
    rigid = earth_lunisolar(cut_mas=0.1, hd="iers2010", axis="figure")
    jd = np.arange(2415020.5, 2488069.5, 5.0)
    ref_psi, ref_eps = erfa.nut00a(jd, 0.0)
    for series, psi_rms, eps_rms in ((rigid, (55.0, 70.0), (18.0, 26.0)), (non_rigid_series(rigid), (1.5, 2.1),
                                                                          (1.4, 2.0))):
        dpsi, deps = series.nutation_at(jd)
        assert psi_rms[0] < np.sqrt(np.mean((dpsi - ref_psi) ** 2)) / MAS < psi_rms[1]
        assert eps_rms[0] < np.sqrt(np.mean((deps - ref_eps) ** 2)) / MAS < eps_rms[1]


def test_a_tolerance_chooses_the_rung():
    epochs = ("earth", "2000-01-01", "2030-01-01", 30.0)
    candidates = {m["name"]: m["estimated_error_mas"] for m in api.track_models(*epochs, axis="angular_momentum")["models"]}
    rigid, nonrigid = candidates["lunisolar"], candidates["nonrigid"]
    assert nonrigid < 0.5 * rigid
    between = 0.5 * (rigid + nonrigid)
    assert api.track(*epochs, tolerance_mas=between, axis="angular_momentum")["model"]["name"] == "nonrigid"
    assert api.track(*epochs, tolerance_mas=1.01 * rigid, axis="angular_momentum")["model"]["name"] == "lunisolar"
    with pytest.raises(NotApplicableError, match="nonrigid"):
        api.track(*epochs, tolerance_mas=0.5 * nonrigid, axis="angular_momentum")


def test_another_pole_is_not_the_earths_and_keeps_the_rigid_rung():
    b = get_body("earth")
    moved = dataclasses.replace(b, pole=dataclasses.replace(b.pole, dec_deg=b.pole.dec_deg - 0.01))
    with pytest.raises(NotApplicableError, match="IAU 2006's pole"):
        api.track(moved, "2000-01-01", "2001-01-01", 30.0, model="nonrigid")
    assert api.track(moved, "2000-01-01", "2001-01-01", 30.0, model="lunisolar")["model"]["name"] == "lunisolar"


def test_outside_the_measured_window_it_is_refused():
    with pytest.raises(NotApplicableError, match="1900"):
        api.track("earth", "2150-01-01", "2151-01-01", 30.0, model="nonrigid")


def test_the_answer_says_what_the_rung_is():
    ans = api.track("earth", "2020-01-01", "2021-01-01", 30.0, model="nonrigid")
    text = " ".join(ans["model"]["assumptions"])
    assert "IERS 1996 transfer function" in text and "IAU 2006" in text and "planetary nutation" in text
    assert not any(a.startswith("rigid Earth") for a in ans["model"]["assumptions"])
    assert ans["model"]["theory"].startswith("IAU 2006 precession")
