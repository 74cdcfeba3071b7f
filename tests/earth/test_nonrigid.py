"""The published non-rigid correction (ephem.earth.nonrigid): the IERS 1996 transfer function (data/nonrigid.toml)
itself, and applied to our rigid series, term by term and as a series.

That it explains our differences from IAU 2000A, as documented in docs/earth.md ("Why ours differs from
IAU 2000A"): tests/earth/test_against_iau2006.py and tests/earth/test_against_erfa.py; that it gives the IERS 1996 series
(KSV_1996_3): tests/earth/test_against_iers1996.py.
"""
import math

import numpy as np
import pytest

from ephem.earth import lunisolar as L
from ephem.earth import nonrigid as N
from ephem.base.errors import InvalidInputError


def _reference(name):
    return next(r for r in L.iau2000a_terms() if r["name"] == name)


# ----------------------------------------------------------------------------- the function itself

def test_transfer_function_leaves_the_precession_alone():
    # at zero frequency in space the non-rigid Earth precesses like the rigid one (R and the
    # RFCN term nearly cancel: 1.04902 - 0.04952 + 0.00058)
    t0 = complex(N.transfer_function(0.0))
    assert abs(t0 - 1.0) < 1e-4
    assert N.transfer_function(0.0).real == pytest.approx(1.0000676, abs=1e-7)


def test_the_fcn_resonance_is_retrograde_near_430_days():
    # |T| peaks on the retrograde side at the RFCN's frequency in space (-1/430 d), not prograde
    periods = np.linspace(300.0, 600.0, 3001)
    sig = np.array([N.sigma_cpsd(p) for p in periods])
    retro, pro = np.abs(N.transfer_function(-sig)), np.abs(N.transfer_function(sig))
    peak = periods[np.argmax(retro)]
    assert peak == pytest.approx(1.0 / (1.00231887299 - 1.0) / 1.00273781191135448, rel=0.01)   # 431 d
    assert retro.max() > 3.0 and pro.max() < 1.1          # damped: |T| peaks at 4.2


def test_circular_components_round_trip():
    se = math.sin(0.409)
    for coeffs in ((-17283.4, 0.0, 9228.0, 0.0), (1.2, -3.4, 5.6, 7.8)):
        plus, minus = N.circular_components(*coeffs, se)
        assert N.from_circular(plus, minus, se) == pytest.approx(coeffs, abs=1e-9)


def test_bad_input_is_refused():
    with pytest.raises(InvalidInputError, match="sigma_cpsd"):
        N.transfer_function([0.1, float("nan")])
    with pytest.raises(InvalidInputError, match="period_days"):
        N.non_rigid_term({"period_days": 0.0, "longitude_sin_mas": 1.0, "obliquity_cos_mas": 1.0}, 0.4)


# ----------------------------------------------------------------------------- applied to the rigid series

def test_the_fcn_term_is_the_retrograde_annual(rigid):
    ours = rigid.term([0, 1, 0, 0, 0])
    nr = N.non_rigid_term(ours, rigid.obliquity)
    assert nr["transfer_retrograde"] == pytest.approx(1.3285, abs=5e-4)
    assert nr["transfer_prograde"] == pytest.approx(1.0261, abs=5e-4)
    # the 7.4 mas annual obliquity term a rigid Earth lacks at first order comes from it
    assert abs(ours["obliquity_cos_mas"]) < 0.2
    assert nr["obliquity_cos_mas"] == pytest.approx(_reference("annual")["eps"][0], abs=0.05)


def test_non_rigid_series_keeps_the_series_shape(rigid):
    nr = N.non_rigid_series(rigid, coupling=False)
    assert nr.multipliers.shape == rigid.multipliers.shape and len(nr.terms) == len(rigid.terms)
    assert nr.term([0, 1, 0, 0, 0])["obliquity_cos_mas"] == pytest.approx(7.39, abs=0.01)
    assert rigid.term([0, 1, 0, 0, 0])["obliquity_cos_mas"] == pytest.approx(-0.14, abs=0.01)   # unchanged
