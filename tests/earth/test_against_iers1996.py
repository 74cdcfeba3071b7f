"""The IERS 1996 nutation series (KSV_1996_3, data/nonrigid.toml): our rigid series (ephem.earth.lunisolar) times the
IERS 1996 transfer function (ephem.earth.nonrigid) gives its coefficients."""
import math

import pytest

from ephem import api
from ephem.earth import nonrigid as N
from ephem.earth.nonrigid import nonrigid_data


def test_rigid_times_transfer_function_is_the_iers_1996_series(rigid):
    # KSV_1996_3 = (Souchay & Kinoshita's rigid series) x T. Ours x T must give its coefficients
    # to 0.2 mas (measured: 0.17 annual, 0.11 semi-annual, <= 0.02 the rest) where both rigid
    # series are first-order complete; 18.6 yr and 9.3 yr carry second-order terms (2.8, 1.3 mas)
    for ref in N.iers1996_terms():
        k = ref["delaunay_multipliers"]
        nr = N.non_rigid_term(rigid.term(k), rigid.obliquity)
        psi, eps, psi_out, eps_out = ref["mas"]
        long_period = abs(rigid.term(k)["period_days"]) > 3000
        tol = 3.0 if long_period else 0.2
        assert nr["longitude_sin_mas"] == pytest.approx(psi, abs=tol), k
        assert nr["obliquity_cos_mas"] == pytest.approx(eps, abs=tol), k


def test_earth_nonrigid_terms_meet_the_iers_1996_series_within_the_stated_residual():
    """KSV_1996_3's own leading coefficients (data/nonrigid.toml, from the routine's data statements): each
    served non-rigid term's difference moves the pole by less than the answer's nutation_residual (4.2 mas, the
    envelope measured against IAU 2000A); the rigid answer's 18.6-year term misses by more (it can fail)."""
    ans = api.nutation("earth", nonrigid=True, cut_mas=0.01)
    rigid = api.nutation("earth", cut_mas=0.01)
    residual = ans["model"]["error_terms_mas"]["nutation_residual"]
    se = math.sin(math.radians(23.4393))

    def miss(t, uas):
        lon = math.hypot(t["longitude_sin_arcsec"] * 1e6 - uas[0], t["longitude_cos_arcsec"] * 1e6 - uas[2])
        obl = math.hypot(t["obliquity_cos_arcsec"] * 1e6 - uas[1], t["obliquity_sin_arcsec"] * 1e6 - uas[3])
        return (se * lon + obl) / 1e3

    served = {tuple(t["delaunay_multipliers"]): t for t in ans["terms"]}
    rigid_terms = {tuple(t["delaunay_multipliers"]): t for t in rigid["terms"]}
    for rec in nonrigid_data()["iers1996_term"]:
        k = tuple(rec["delaunay_multipliers"])
        assert miss(served[k], rec["uas"]) <= residual, k
    assert miss(rigid_terms[(0, 0, 0, 0, 1)], nonrigid_data()["iers1996_term"][0]["uas"]) > residual
    assert ans["model"]["name"] == "nonrigid"
