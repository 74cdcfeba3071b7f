"""Petit, Souchay & Lhotka (2014) in CI: Tables 3-10 reproduced, and every erratum asserted as recorded.

Also the paper's other printed numbers: the Hansen coefficients of Eqs. 16-18 and 23-25 (ephem.orbit.hansen),
Tables 9-10 in the amp-period layout of ephem.exports.tables, and Itokawa's ±6.57″/yr (ephem.forced.uncertainty).

The printed tables live verbatim in data/petit2014/; the errata in data/errata.toml. Tolerances
come from the printed precision: half a unit of the last printed digit (the paper rounds; only
Table 4's obliquity column is truncated, erratum eros-precession-rate), plus the effect of the
4-digit H_d of Table 4 (±0.00005, i.e. 3e-4 relative for Vesta, which the dataset takes from its
Table 3 moments) where K enters. Each tolerance states its budget where it is used.
"""
import csv
import functools
import importlib.util
import math
import sys
import tomllib
from dataclasses import replace
from fractions import Fraction as F
from pathlib import Path

import numpy as np
import pytest

from ephem import api
from ephem.base.paths import data_dir
from ephem.bodies.catalogue import dynamical_ellipticity, get_body, load_catalogue
from ephem.base.constants import ARCSEC, JULIAN_YEAR_DAYS, MAS
from ephem.orbit.geometry import icrf_to_ecliptic, spin_geometry
from ephem.orbit.hansen import hansen_series
from ephem.orbit.kepler import orbit_normal
from ephem.forced.kinoshita import nutation_series
from ephem.forced.precession_nutation import build_model
from ephem.exports.tables import render_nutation
from ephem.forced.uncertainty import monte_carlo, propagate
from tests.orbit.test_hansen import _poly
from tests.exports.test_tables import parse

TABLES = data_dir() / "petit2014"
ERRATA = tomllib.loads((data_dir() / "errata.toml").read_text())["erratum"]
ROOT = Path(__file__).resolve().parents[2]
HD_ROUNDING = 3e-4  # Table 4's 4-digit H_d, relative: ±0.00005 / 0.1692 (Vesta; measured 1.5e-4 in K)
#: Vesta and Ceres carry Table 4's printed obliquity, which is truncated (erratum eros-precession-rate):
#: the values behind it reach 27.46345 and 3.91466 deg, which scale sin ε by up to cot ε δε = 1.2e-4
#: and 1.2e-3 (cos ε by less): the relative budget of the nutation cells for it
OBLIQUITY_TRUNCATION = {"Vesta": 1.2e-4, "Ceres": 1.2e-3}
#: The two cells no fit meets (ODD_CELLS in tools/derive_petit2014.py), their extra budget (arcsec):
#: Vesta's Table 6 cos M, which its own row contradicts (measured 2.5e-4), Ceres' Table 7 6M Cos (9.1e-5)
ODD_CELL_BUDGET = {("Vesta", "obliquity", 1, "cos"): 2.5e-4, ("Ceres", "longitude", 6, "cos"): 5e-5}


def _derive_module():
    spec = importlib.util.spec_from_file_location("derive_petit2014", ROOT / "tools" / "derive_petit2014.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("derive_petit2014", mod)
    spec.loader.exec_module(mod)
    return mod


@functools.cache
def _obliquity_evidence():
    # the intervals of erratum eros-precession-rate (tools/derive_petit2014.py; ~3 s, computed once)
    return _derive_module().obliquity_evidence()


def _csv(name):
    with open(TABLES / name) as fh:
        return list(csv.DictReader(fh))


TABLE4 = {r["body"]: {k: float(v) for k, v in r.items() if k != "body"} for r in _csv("table4_rotation.csv")}
NUTATION = _csv("table5_8_nutation.csv")
RAMBAUX = _csv("table9_10_rambaux.csv")
TYPOS = {("Ceres", "longitude", 6, "sin"), ("Ceres", "obliquity", 5, "cos")}


def _series(body):
    return build_model(load_catalogue("petit2014").get(body), order=4)


# ----------------------------------------------------------------------------- Table 4

@pytest.mark.parametrize("body", ["Vesta", "Ceres"])
def test_scaling_factor_from_the_printed_orbital_period(body):
    # K = 3 n² H_d / ω with n from the period the paper prints (Tables 5-10); independent of Table 4's K.
    # Budget: Table 4's 4-digit H_d (Vesta's dataset H_d is Table 3's 0.169167; K implies 0.169191)
    p = api.precession(body, dataset="petit2014", order=4)
    assert p["scaling_factor_arcsec_per_year"] == pytest.approx(TABLE4[body]["scaling_factor_arcsec_per_year"],
                                                                rel=HD_ROUNDING)


@pytest.mark.parametrize("body", ["Eros", "Steins", "Itokawa"])
def test_scaling_factor_table4_where_it_fixes_a(body):
    # a is derived from Table 4's K with the dataset's H_d: K comes back to half a unit of its 4th decimal
    p = api.precession(body, dataset="petit2014", order=4)
    assert p["scaling_factor_arcsec_per_year"] == pytest.approx(TABLE4[body]["scaling_factor_arcsec_per_year"],
                                                                abs=5e-5)


@pytest.mark.parametrize("body", ["Eros", "Steins", "Itokawa"])
def test_semi_major_axis_implied_by_k_is_a_real_orbit(body):
    # for these the dataset's a is derived from Table 4's K (the paper's epoch is unknown):
    # it must lie within 1e-3 of today's osculating a, or the K/H_d/period triple is not physical
    # (budget: a plausibility bound, not a printing one; measured 7e-5 Eros, 5.8e-4 Steins, 5.6e-4 Itokawa)
    eff = load_catalogue("petit2014").get(body).orbit.a_au
    cur = load_catalogue("current").get(body).orbit.a_au
    assert abs(eff / cur - 1) < 1e-3


@pytest.mark.parametrize("body", ["Eros", "Steins", "Itokawa", "Vesta", "Ceres"])
def test_precession_rate_table4(body):
    # eq. 25 at order 4. Budgets:
    # - Eros: half a unit of the printed 4th decimal (ψ̇ is rounded; the dataset's obliquity is the one
    #   that gives it, which Table 4 prints truncated: erratum eros-precession-rate); measured 7e-7
    # - Vesta, Ceres: the 4-digit H_d (HD_ROUNDING); measured 1.1e-4 and 2e-6 relative
    # - Steins, Itokawa: 1e-3 relative for the orbit's e: the dataset's elements (2015, 2020) have
    #   e = 0.145433 and 0.280117 where Table 4 implies 0.1470 and 0.2805 (obliquity_evidence), i.e.
    #   7e-4 and 3.4e-4 in ψ̇ (measured)
    p = api.precession(body, dataset="petit2014", order=4)
    printed = TABLE4[body]["precession_rate_arcsec_per_year"]
    if body == "Eros":
        assert p["precession_rate_arcsec_per_year"] == pytest.approx(printed, abs=5e-5)
    else:
        tol = HD_ROUNDING if body in ("Vesta", "Ceres") else 1e-3
        assert p["precession_rate_arcsec_per_year"] == pytest.approx(printed, rel=tol)


def test_vesta_precession_rate_is_13_67():
    # the default (exact-e) model, 13.6713, against Table 4's 13.6728 at 2 decimals: budget half a unit, ±0.005
    p = api.precession("vesta", dataset="petit2014")
    assert round(p["precession_rate_arcsec_per_year"], 2) == 13.67


@pytest.mark.parametrize("body", ["Eros", "Vesta"])
def test_dynamical_ellipticity_from_table3_where_consistent(body):
    row = next(r for r in _csv("table3_physical.csv") if r["body"] == body)
    hd = dynamical_ellipticity(*(float(row[f"moment_{x}"]) for x in "ABC"))
    assert hd == pytest.approx(TABLE4[body]["dynamical_ellipticity"], abs=5e-5)  # half a unit of the 4th decimal


def test_dynamical_ellipticity_of_vesta_table3_is_table4():
    # Petit et al. (2014): Table 3 moments 0.3433, 0.3546, 0.42 -> Table 4 H_d = 0.1692
    assert dynamical_ellipticity(0.3433, 0.3546, 0.42) == pytest.approx(0.1692, abs=5e-5)


@pytest.mark.parametrize("body", ["Vesta", "Ceres"])
def test_nutation_semi_amplitudes_table4(body):
    # budget: half a unit of the 4th decimal, the 4-digit H_d and the truncated obliquity the dataset
    # carries (measured: Vesta 1.1e-4 and 2.4e-4 relative, Ceres 2e-5)
    n = api.nutation(body, dataset="petit2014", order=4)
    expected = {"Vesta": (5.1460, 2.2122), "Ceres": (3.1834, None)}[body]
    rel = HD_ROUNDING + OBLIQUITY_TRUNCATION[body]
    assert n["delta_psi_half_peak_to_peak_arcsec"] == pytest.approx(expected[0], rel=rel, abs=5e-5)
    if expected[1] is not None:  # Ceres' Δε: erratum ceres-table4-delta-epsilon
        assert n["delta_epsilon_half_peak_to_peak_arcsec"] == pytest.approx(expected[1], rel=rel, abs=5e-5)


# ----------------------------------------------------------------------------- Tables 5-10

@pytest.mark.parametrize("row", NUTATION, ids=lambda r: f"T{r['table']}-{r['body']}-{r['component']}-{r['multiple']}M")
def test_nutation_coefficients_tables_5_to_8(row):
    body, comp, k = row["body"], row["component"], int(row["multiple"])
    s = _series(body).nutation
    if comp == "longitude":
        ours = (s.lon_sin[k - 1], s.lon_cos[k - 1])
    else:  # the paper's sign of Δε is flipped (erratum delta-epsilon-sign)
        ours = (-s.obl_sin[k - 1], -s.obl_cos[k - 1])
    for part, value in zip(("sin", "cos"), ours):
        if (body, comp, k, part) in TYPOS:
            continue
        printed = float(row[f"{part}_arcsec"])
        # budget: half a unit (5e-5"), ODD_CELL_BUDGET for the two cells no fit meets, and in proportion
        # the 4-digit H_d and the truncated obliquity the dataset carries (measured at most 4.3e-4", Vesta 2M)
        odd = ODD_CELL_BUDGET.get((body, comp, k, part), 0.0)
        rel = HD_ROUNDING + OBLIQUITY_TRUNCATION[body]
        assert value / ARCSEC == pytest.approx(printed, abs=5e-5 + odd + rel * abs(printed)), part
    # budget: half a unit of the printed period, plus our period's own share (Ceres': the printed 4.6010 yr, /k)
    assert s.period_days[k - 1] / JULIAN_YEAR_DAYS == pytest.approx(float(row["period_years"]), abs=5e-5 + 5e-5 / k)


@pytest.mark.parametrize("row", NUTATION, ids=lambda r: f"T{r['table']}-{r['body']}-{r['component']}-{r['multiple']}M")
def test_amp_columns_tables_5_to_8(row):
    body, comp, k = row["body"], row["component"], int(row["multiple"])
    m = _series(body)
    s = m.nutation
    if comp == "longitude":
        amp = math.hypot(s.lon_sin[k - 1], s.lon_cos[k - 1]) * math.sin(m.obliquity)  # erratum table5-amp-column
    else:
        amp = math.hypot(s.obl_sin[k - 1], s.obl_cos[k - 1])
    printed = float(row["amp_arcsec"])
    # budget: half a unit, plus in proportion the 4-digit H_d and the truncated obliquity the dataset
    # carries (measured at most 4.8e-4", Vesta 2M Δε; Ceres' 1.5e-4" are the obliquity's 1e-3)
    rel = HD_ROUNDING + OBLIQUITY_TRUNCATION[body]
    assert amp / ARCSEC == pytest.approx(printed, abs=5e-5 + rel * printed)


@pytest.mark.parametrize("row", RAMBAUX, ids=lambda r: f"T{r['table']}-{r['multiple']}M")
def test_tables_9_10_our_model_and_rambaux(row):
    m = _series("Vesta")
    s = m.nutation
    k = int(row["multiple"])
    if row["component"].startswith("longitude"):
        amp = math.hypot(s.lon_sin[k - 1], s.lon_cos[k - 1]) * math.sin(m.obliquity) / MAS
    else:
        amp = math.hypot(s.obl_sin[k - 1], s.obl_cos[k - 1]) / MAS
    # budget: half a unit of Tables 5-6 (0.05 mas; Tables 9-10 print 0.01 mas of the same series), plus
    # in proportion the 4-digit H_d and the truncated obliquity (measured at most 0.52 mas, 2M Δε)
    rel = HD_ROUNDING + OBLIQUITY_TRUNCATION["Vesta"]
    assert amp == pytest.approx(float(row["petit_amp_mas"]), abs=0.05 + rel * amp)
    # budget: half a unit of the printed 4th decimal, plus as much for ours from the printed 1325.3803 d
    assert s.period_days[k - 1] == pytest.approx(float(row["petit_period_days"]), abs=1e-4)
    # Rambaux (2013), an Eulerian model with other inputs: within 1.5% for the leading terms
    # (measured 0.05-1.4%), 5% for the small 5M term (measured 4.6%); periods: his orbit's, 3e-4
    # (measured 2.1e-4 to 2.8e-4)
    assert amp == pytest.approx(float(row["rambaux_amp_mas"]), rel=0.015 if k < 5 else 0.05)
    assert s.period_days[k - 1] == pytest.approx(float(row["rambaux_period_days"]), rel=3e-4)


@pytest.fixture(scope="module")
def vesta():
    return api.nutation("vesta", dataset="petit2014", order=4)


def test_amp_period_layout_reproduces_petit_tables_9_and_10(vesta):
    got = parse(render_nutation(vesta, "csv", layout="amp-period"), "csv", "amp-period")
    for row in RAMBAUX:
        comp = "longitude" if row["component"].startswith("longitude") else "obliquity"
        cell = got[(comp, int(row["multiple"]))]
        # the tolerance of test_tables_9_10_our_model_and_rambaux (above)
        assert cell["amp_mas"] == pytest.approx(float(row["petit_amp_mas"]), abs=0.05 + HD_ROUNDING * cell["amp_mas"])
        assert cell["period_days"] == pytest.approx(float(row["petit_period_days"]), abs=1e-4)


def test_effective_inputs_are_reproduced_by_the_derivation_tool():
    # no hand-tuned number in the petit2014 dataset: tools/derive_petit2014.py re-derives them.
    # Budget: half a unit of the digits the toml carries (a 8-9 decimals, e 7, angles 6), with margin
    # for the fits' convergence: rel 1e-8 (a), 1e-7 (e), 1e-6 deg (angles; measured below 4e-7)
    derived = _derive_module().derive()
    cat = load_catalogue("petit2014")
    for name, vals in derived.items():
        b = cat.get(name)
        assert b.orbit.a_au == pytest.approx(vals["a_au"], rel=1e-8)
        if "e" in vals:
            assert b.orbit.e == pytest.approx(vals["e"], abs=1e-7)
            assert b.orbit.peri_deg == pytest.approx(vals["peri_deg"], abs=1e-6)
        assert b.pole.ra_deg == pytest.approx(vals["pole_ra_deg"], abs=1e-6)
        assert b.pole.dec_deg == pytest.approx(vals["pole_dec_deg"], abs=1e-6)


# ----------------------------------------------------------------------------- Eqs. 16-18, 23-25

# Petit et al. (2014), Eqs. 16-18 and 23-25 (as given in the brief).  Every
# value below agrees exactly with the engine.  Typos found in the (extracted)
# Eqs. 23-24 of the paper, none of which affects the coefficient values:
#   * Eq. 23 contains a spurious extra pair "- C' 62/48 e^3 sin5M/5n
#     - C' 533/16 e^4 sin6M/6n" (no coefficient 62/48 exists; the correct
#     k = 5 term is 845/48 e^3, which is also printed);
#   * Eq. 23 prints "S' (7/2 e - 115/6 e^4) cos4M/4n": the k = 4 coefficient
#     is S2_4 = 17/2 e^2 - 115/6 e^4 (7/2 e belongs to k = 3);
#   * Eq. 23 divides the k = 2 terms by n instead of 2n (Eq. 24 has 2n);
#   * Eq. 24 repeats the (17/2 e^2 - 115/6 e^4) term three times with the
#     arguments 3M and 5M; it belongs once, with 4M / 4n; "S sin 3M" lacks
#     the prime of S'.
PUBLISHED = {
    "c0": {
        0: {0: F(1), 2: F(3, 2), 4: F(15, 8)},
        1: {1: F(3), 3: F(27, 8)},
        2: {2: F(9, 2), 4: F(7, 2)},
        3: {3: F(53, 8)},
        4: {4: F(77, 8)},
        5: {},
        6: {},
    },
    "c2": {
        0: {},
        1: {1: F(-1, 2), 3: F(1, 12)},
        2: {0: F(1), 2: F(-5, 2), 4: F(41, 48)},
        3: {1: F(7, 2), 3: F(-123, 16)},
        4: {2: F(17, 2), 4: F(-115, 6)},
        5: {3: F(845, 48)},
        6: {4: F(533, 16)},
    },
    "s2": {
        0: {},
        1: {1: F(-1, 2), 3: F(1, 24)},
        2: {0: F(1), 2: F(-5, 2), 4: F(37, 48)},
        3: {1: F(7, 2), 3: F(-123, 16)},   # no e^4 term (parity)
        4: {2: F(17, 2), 4: F(-115, 6)},
        5: {3: F(845, 48)},
        6: {4: F(533, 16)},
    },
}


@pytest.mark.parametrize("family", ["c0", "c2", "s2"])
def test_order4_series_equals_published(family):
    series = hansen_series(4)
    got = getattr(series, family)
    assert sorted(got) == list(range(7))            # k = 0 .. order + 2
    for k, terms in PUBLISHED[family].items():
        assert got[k] == _poly(4, terms), (family, k, got[k])


# ----------------------------------------------------------------------------- errata, one test each

def _table(component, body):
    rows = [r for r in NUTATION if r["body"] == body and r["component"] == component]
    return [(float(r["sin_arcsec"]), float(r["cos_arcsec"])) for r in rows]


def _half_ptp(rows):
    m = np.linspace(0, 2 * np.pi, 200000, endpoint=False)
    v = sum(s * np.sin(k * m) + c * np.cos(k * m) for k, (s, c) in enumerate(rows, start=1))
    return (v.max() - v.min()) / 2


def test_erratum_eq26_orbit_normal():
    i, node = math.radians(7.14), math.radians(103.7)
    nodes = np.array([math.cos(node), math.sin(node), 0.0])
    printed = np.array([math.sin(i) * math.sin(node), math.cos(node) * math.sin(i), math.cos(i)])
    # budget: floating point (an identity)
    assert abs(printed @ nodes) == pytest.approx(abs(math.sin(i) * math.sin(2 * node)), rel=1e-12)
    assert abs(orbit_normal(i, node) @ nodes) < 1e-15


def test_paper_eq26_sign_slip():
    """Erratum: Petit et al. eq. 26 prints z = (sin i sin Ω, cos Ω sin i, cos i).

    The orbit normal must be orthogonal to the line of nodes (cos Ω, sin Ω, 0);
    the printed vector is not (unless sin 2Ω = 0), ours is.
    """
    i, node = math.radians(7.14), math.radians(103.7)
    nodes = np.array([math.cos(node), math.sin(node), 0.0])
    printed = np.array([math.sin(i) * math.sin(node), math.cos(node) * math.sin(i), math.cos(i)])
    assert abs(np.dot(printed, nodes)) > 0.02
    assert abs(np.dot(orbit_normal(i, node), nodes)) < 1e-15   # a 3-term dot product of unit vectors: ≲ 3 ε


def test_erratum_eq27_pole_vector():
    b = load_catalogue("current").get("Vesta")
    i, node = math.radians(b.orbit.i_deg), math.radians(b.orbit.node_deg)
    s = icrf_to_ecliptic(math.radians(309.031), math.radians(42.2264))
    mirrored = s * np.array([1, -1, 1])
    z = orbit_normal(i, node)
    z26 = z * np.array([1, -1, 1])
    # budget: half a unit of the erratum's 2 decimals
    assert math.degrees(math.acos(z @ s)) == pytest.approx(27.44, abs=5e-3)
    assert math.degrees(math.acos(z @ mirrored)) == pytest.approx(25.46, abs=5e-3)  # one slip alone
    assert math.degrees(math.acos(z26 @ mirrored)) == pytest.approx(27.44, abs=5e-3)  # both: they cancel


def test_erratum_eq29_unsigned_angle():
    # Ceres (current): the equinox-to-perihelion angle is negative mod 360 in one branch; arccos folds it
    b = load_catalogue("current").get("Vesta")
    o = b.orbit
    geo = spin_geometry(icrf_to_ecliptic(math.radians(b.pole.ra_deg), math.radians(b.pole.dec_deg)),
                        *(math.radians(x) for x in (o.i_deg, o.node_deg, o.peri_deg)))
    theta = geo.equinox_to_pericentre
    assert math.acos(math.cos(theta)) == pytest.approx(abs(theta))  # budget: floating point (default rel 1e-6)
    # θ and -θ give different nutation phases: 2θ enters through C' = cos 2θ, S' = sin 2θ
    s1 = nutation_series(1e-4, 0.017, 0.5, 0.09, theta)
    s2 = nutation_series(1e-4, 0.017, 0.5, 0.09, -theta)
    # budget: floating point for the antisymmetry; 1e-6 rad sets the term well apart from zero
    # (sin is odd and cos even to the bit in libm, so the sum is 0; an ulp of asymmetry would be 1e-22)
    assert abs(s1.lon_cos[1] + s2.lon_cos[1]) < 1e-18 and abs(s1.lon_cos[1]) > 1e-6


def test_erratum_eq23_k2_divisor():
    # Table 5's 2M terms follow /(2n): the coefficients test passes with it; with /n they would double
    # budget: half a unit, plus in proportion the 4-digit H_d and the truncated obliquity (measured 3e-4);
    # the /n reading misses by 2.6", far beyond 0.5
    s = _series("Vesta").nutation
    rel = HD_ROUNDING + OBLIQUITY_TRUNCATION["Vesta"]
    assert s.lon_cos[1] / ARCSEC == pytest.approx(-2.6481, abs=5e-5 + rel * 2.6481)
    assert 2 * s.lon_cos[1] / ARCSEC != pytest.approx(-2.6481, abs=0.5)


def test_erratum_eq23_k4_coefficient():
    from fractions import Fraction as F
    s2_4 = hansen_series(4).s2[4]
    assert s2_4 == (0, 0, F(17, 2), 0, F(-115, 6))


def test_erratum_eq23_spurious_terms():
    from fractions import Fraction as F
    h = hansen_series(4)
    assert h.c2[5][3] == F(845, 48) and h.c2[6][4] == F(533, 16)
    assert F(62, 48) not in h.c2[5] and F(62, 48) not in h.s2[5]


def test_erratum_eq24_missing_k1_term():
    s = _series("Vesta").nutation
    # Table 6's sin M coefficient (paper's sign): only the S' C2_1 term produces it
    # (budget: half a unit, plus in proportion the 4-digit H_d and the truncated obliquity; measured 4.7e-5)
    rel = HD_ROUNDING + OBLIQUITY_TRUNCATION["Vesta"]
    assert -s.obl_sin[0] / ARCSEC == pytest.approx(-0.1263, abs=5e-5 + rel * 0.1263)


def test_erratum_eq24_repeated_terms():
    s = _series("Vesta").nutation
    # budget: half a unit, plus in proportion the 4-digit H_d and the truncated obliquity; measured 1.6e-5
    rel = HD_ROUNDING + OBLIQUITY_TRUNCATION["Vesta"]
    assert (-s.obl_sin[3] / ARCSEC, -s.obl_cos[3] / ARCSEC) == pytest.approx((0.0475, -0.0494), abs=5e-5 + rel * 0.05)


def test_erratum_delta_epsilon_sign():
    fit = _derive_module()
    t4 = TABLE4["Vesta"]
    K = t4["scaling_factor_arcsec_per_year"] * ARCSEC / JULIAN_YEAR_DAYS
    n = 2 * math.pi / 1325.3803
    eps = math.radians(t4["obliquity_deg"])
    from scipy.optimize import least_squares
    target = np.array(_table("longitude", "Vesta") + _table("obliquity", "Vesta"))

    def resid(p, sign):
        s = nutation_series(K, n, eps, p[0], p[1], order=4)
        ours = np.concatenate([np.stack([s.lon_sin[:6], s.lon_cos[:6]], 1),
                               sign * np.stack([s.obl_sin[:6], s.obl_cos[:6]], 1)]) / ARCSEC
        return (ours - target).ravel()

    def best(sign):
        return min((least_squares(resid, [0.09, th], args=(sign,)) for th in np.linspace(0, math.pi, 12)),
                   key=lambda r: r.cost)
    # budget 3e-4: half a unit elsewhere, 2.3e-4 at Table 6's cos M, which its own row contradicts
    # (ODD_CELLS in tools/derive_petit2014.py); the unflipped sign misses by arcseconds
    assert np.abs(best(-1).fun).max() < 3e-4    # the paper's tables = our theory with Δε flipped
    assert np.abs(best(+1).fun).max() > 2.0     # as printed, no phase and e fit
    assert fit.fit_nutation_table("Vesta", 1325.3803)["max_residual_arcsec"] < 3e-4


def test_erratum_table4_nutation_columns():
    # budget: half a unit of Table 4's 4th decimal (measured 3.4e-5 and 2.6e-5); the alternatives miss by > 0.1
    assert _half_ptp(_table("longitude", "Vesta")) == pytest.approx(5.1460, abs=5e-5)
    assert _half_ptp(_table("obliquity", "Vesta")) == pytest.approx(2.2122, abs=5e-5)
    amps = [math.hypot(*sc) for sc in _table("longitude", "Vesta")]
    assert sum(amps) != pytest.approx(5.1460, abs=0.1) and max(amps) != pytest.approx(5.1460, abs=0.1)


def test_erratum_table5_amp_column():
    # with the obliquity behind Table 4's truncated 27.46 (27.4633, erratum eros-precession-rate; with
    # 27.46 itself: 1.10260). Budget: half a unit, plus the printed Sin and Cos's share (2.5e-5)
    s, c = _table("longitude", "Vesta")[0]
    assert math.hypot(s, c) * math.sin(math.radians(27.4633)) == pytest.approx(1.1027, abs=7.5e-5)


def test_erratum_ceres_table7_6M():
    # budget: half a unit of the 4th decimal (measured 2e-6, 3.4e-5, 4.6e-5)
    rows = _table("longitude", "Ceres")
    assert _half_ptp(rows) == pytest.approx(3.1841, abs=5e-5)              # as printed
    fixed = rows[:5] + [(-0.0008, rows[5][1])]
    assert _half_ptp(fixed) == pytest.approx(3.1834, abs=5e-5)             # = Table 4
    assert _series("Ceres").nutation.lon_sin[5] / ARCSEC == pytest.approx(-0.0008, abs=5e-5)


def test_erratum_ceres_table8_5M():
    assert -_series("Ceres").nutation.obl_cos[4] / ARCSEC == pytest.approx(-0.0005, abs=5e-5)  # half a unit


def test_erratum_ceres_table4_delta_epsilon():
    rows = _table("obliquity", "Ceres")
    fixed = rows[:4] + [(rows[4][0], -0.0005)] + rows[5:]
    # budget: half a unit of the erratum's 4 decimals; the printed 0.1813 is 32 half-units away
    assert _half_ptp(fixed) == pytest.approx(0.1830, abs=5e-5)
    ours = api.nutation("ceres", dataset="petit2014", order=4)["delta_epsilon_half_peak_to_peak_arcsec"]
    assert ours == pytest.approx(0.1829, abs=5e-5)
    assert abs(ours - 0.1813) > 1e-3


def _hd_from_table3(body):
    row = next(r for r in _csv("table3_physical.csv") if r["body"] == body)
    return dynamical_ellipticity(*(float(row[f"moment_{x}"]) for x in "ABC"))


def test_erratum_table4_hd_steins():
    assert _hd_from_table3("Steins") == pytest.approx(0.2532, abs=5e-5)  # half a unit of the erratum's digits
    assert load_catalogue("petit2014").get("Steins").hd == 0.2717


def test_erratum_table4_hd_itokawa():
    # budget: half a unit of the erratum's digits
    assert _hd_from_table3("Itokawa") == pytest.approx(0.4211, abs=5e-5)
    assert dynamical_ellipticity(0.298**2 + 0.244**2, 0.535**2 + 0.244**2, 0.535**2 + 0.298**2) == \
        pytest.approx(0.34125, abs=5e-6)
    assert dynamical_ellipticity(0.294**2 + 0.209**2, 0.535**2 + 0.209**2, 0.535**2 + 0.294**2) == \
        pytest.approx(0.3828, abs=5e-5)


def test_erratum_table4_hd_ceres():
    assert _hd_from_table3("Ceres") == pytest.approx(0.0632, abs=5e-5)  # half a unit of the erratum's digits
    # the dataset carries the paper's printed H_d unchanged (no arithmetic): equal to the parse's rounding
    assert load_catalogue("petit2014").get("Ceres").hd == pytest.approx(0.071652, rel=1e-15)


def _geometric_obliquity(name, ra, dec, ecliptic=False):
    o = load_catalogue("current").get(name).orbit
    from ephem.orbit.geometry import unit_vector
    s = unit_vector(math.radians(ra), math.radians(dec)) if ecliptic else \
        icrf_to_ecliptic(math.radians(ra), math.radians(dec))
    return math.degrees(spin_geometry(s, *(math.radians(x) for x in (o.i_deg, o.node_deg, o.peri_deg))).obliquity)


def test_erratum_itokawa_pole_frame():
    # budget: half a unit of the erratum's 1 decimal; 156.22 is erratum table4-obliquity's mean obliquity
    # (2 decimals), which the geometric one here differs from by Δε at J2000 (0.004°): 0.01
    assert _geometric_obliquity("Itokawa", 128.5, -89.66, ecliptic=True) == pytest.approx(178.7, abs=0.05)
    assert _geometric_obliquity("Itokawa", 128.5, -89.66) == pytest.approx(156.22, abs=0.01)


@pytest.mark.parametrize("body, ra, dec, ours", [("Eros", 11.3692, 17.2273, 89.02), ("Steins", 99, -59, 176.13),
                                                  ("Itokawa", 128.5, -89.66, 156.22), ("Vesta", 309.031, 42.2264, 27.44),
                                                  ("Ceres", 288, 66, 3.94)])
def test_erratum_table4_obliquity(body, ra, dec, ours):
    # the mean obliquity at J2000 (the pole's epoch) of Table 3's pole on the current orbit, as the
    # erratum records it (budget: half a unit of its 2 decimals); the geometric one differs by Δε (Eros 0.0065°)
    b = load_catalogue("current").get(body)
    table3 = replace(b, pole=replace(b.pole, ra_deg=ra, dec_deg=dec))
    got = math.degrees(build_model(table3, order=4).obliquity)
    assert got == pytest.approx(ours, abs=5e-3)
    # outside what the printed obliquity stands for, rounded or truncated: [x - 0.005, x + 0.01)
    printed = TABLE4[body]["obliquity_deg"]
    assert not printed - 0.005 <= got < printed + 0.01


#: The intervals of the obliquity behind Table 4's column that erratum eros-precession-rate records (deg):
#: every printed value that depends on it met to its printed digits, read as rounded
OBLIQUITY_INTERVALS = {"Eros": (89.00613, 89.00624), "Steins": (161.83479, 161.84100),
                       "Itokawa": (157.29769, 157.30442), "Vesta": (27.46321, 27.46345), "Ceres": (3.91318, 3.91466)}


def test_erratum_eros_precession_rate():
    ev = _obliquity_evidence()["Eros"]
    # ψ̇ alone (eq. 25), ψ̇ and K read as rounded, e = 0.222836 ± 0.001: 89.00555-89.00697, inside the
    # truncated cell of the printed 89.00 and clear of the rounded one (budget: the erratum's 5 decimals)
    lo, hi = ev["rate_rounded"]
    assert (lo, hi) == pytest.approx((89.00555, 89.00697), abs=5e-6)
    assert 89.0 <= lo and hi < 89.01 and lo > 89.005
    # the dataset carries the obliquity that gives the printed ψ̇ (half a unit of its 4th decimal,
    # ψ̇ being rounded) with the printed K (half a unit); Table 4's 89.00 would give 2.8635
    p = api.precession("eros", dataset="petit2014", order=4)
    assert p["precession_rate_arcsec_per_year"] == pytest.approx(2.8456, abs=5e-5)
    assert p["scaling_factor_arcsec_per_year"] == pytest.approx(304.0953, abs=5e-5)
    assert p["obliquity_deg"] == pytest.approx(89.006257, abs=5e-7)  # the toml's 6 decimals
    derive = _derive_module()
    e = load_catalogue("petit2014").get("Eros").orbit.e
    at_printed = 0.5 * 304.0953 * math.cos(math.radians(89.0)) * (1 + 1.5 * e**2 + 15 / 8 * e**4)
    assert at_printed == pytest.approx(2.8635, abs=5e-5)  # the erratum's 4 decimals
    assert derive.obliquity_from_rate(2.8456, 304.0953, e) == pytest.approx(89.006257, abs=5e-7)


@pytest.mark.parametrize("body", OBLIQUITY_INTERVALS)
def test_table4_obliquity_column_is_truncated(body):
    # erratum eros-precession-rate: the interval of ε that the other printed values allow meets the
    # truncated reading of the printed obliquity for every body; only Eros' misses the rounded one
    ev = _obliquity_evidence()[body]
    joint = ev["joint_rounded"]
    assert joint["minimax"] <= 1.0  # one point meets every printed value to its printed digits
    assert joint["miss_at_ends"] <= 1.0 + 1e-6  # and so do the ends (budget: the search's linearisation)
    lo, hi = joint["interval"]
    assert (lo, hi) == pytest.approx(OBLIQUITY_INTERVALS[body], abs=5e-6)  # the erratum's 5 decimals
    t_lo, t_hi = ev["cells"]["truncated"]
    r_lo, r_hi = ev["cells"]["rounded"]
    assert lo < t_hi and hi >= t_lo
    assert (lo < r_hi and hi >= r_lo) == (body != "Eros")
    # read as truncated, the other printed values move the intervals by 0.0033 deg at most, or admit none
    other = ev["joint_truncated"]["interval"]
    if other is not None:
        assert abs(other[0] - lo) < 0.0034 and abs(other[1] - hi) < 0.0034
        assert (other[0] < r_hi and other[1] >= r_lo) == (body != "Eros") and other[0] < t_hi and other[1] >= t_lo


def test_table4_other_columns_are_rounded():
    # erratum eros-precession-rate: Tables 5-8 are met cell by cell when read as rounded, not as truncated
    # (in half-units of the last digit; budget: the erratum's 2 decimals)
    ev = _obliquity_evidence()
    for body, rounded, truncated in (("Vesta", 0.98, 1.97), ("Ceres", 0.93, 1.84)):
        assert ev[body]["joint_rounded"]["minimax"] == pytest.approx(rounded, abs=0.005)
        assert ev[body]["joint_truncated"]["interval"] is None
        assert ev[body]["joint_truncated"]["minimax"] == pytest.approx(truncated, abs=0.005)
    # Vesta's K with the printed periods: H_d 0.1691895-0.1691933, which prints 0.1692 only if rounded
    derive = _derive_module()
    assert derive.vesta_hd_interval("rounded") == pytest.approx((0.1691895, 0.1691933), abs=5e-8)
    lo, hi = derive.vesta_hd_interval("truncated")
    assert 0.16915 <= lo and hi < 0.16925 and hi < 0.1692


def test_erratum_nutation_phase_ceres():
    fit = _derive_module().fit_nutation_table("Ceres", 4.6010 * JULIAN_YEAR_DAYS)
    assert fit["theta_deg"] == pytest.approx(162.14, abs=5e-3)  # half a unit of the erratum's 2 decimals
    # budget: half a unit, plus the fit's fixed, truncated obliquity (3.91 for 3.914: 1.2e-3 of the
    # largest Δε cell, 0.1361", i.e. 1.6e-4); measured 1.6e-4
    assert fit["max_residual_arcsec"] < 5e-5 + OBLIQUITY_TRUNCATION["Ceres"] * 0.1361
    # Ceres' osculating orbit of 2013 Nov 4.0 TT (MPCORB, MPO286777): i, Ω, ω
    geo = spin_geometry(icrf_to_ecliptic(math.radians(288), math.radians(66)),
                        *(math.radians(x) for x in (10.59398, 80.32762, 72.29213)))
    assert math.degrees(geo.equinox_to_pericentre) % 180 == pytest.approx(97.72, abs=5e-3)  # 2 decimals


def test_every_erratum_has_its_test():
    names = set(globals())
    missing = [e["id"] for e in ERRATA if "test_erratum_" + e["id"].replace("-", "_") not in names]
    assert not missing


def test_erratum_itokawa_precession_uncertainty():
    from ephem.forced.uncertainty import propagate

    r = propagate(get_body("Itokawa", "petit2014"), order=4)
    ours = r["precession_rate_arcsec_per_year_uncertainty"]
    assert ours == pytest.approx(13.0, abs=0.05)          # the pole's 3.9° as 1σ; half a unit of 1 decimal
    slope = abs(-461.5208 * math.tan(math.radians(157.30)))  # Table 4: |ψ̇ tan ε|, arcsec/yr per radian
    assert round(slope * math.radians(3.9 / 2), 2) == 6.57   # the printed σ: half the margin
    # twice, but for σ_ε = 3.86° (not 3.9°): 2 × 3.86/3.9 = 1.98; budget: half a unit of the 2 decimals
    # plus 6.57's own rounding (0.0015)
    assert ours / 6.57 == pytest.approx(1.98, abs=0.0065)


# ----------------------------------------------------------------------------- Itokawa's σ

#: Petit et al. (2014), abstract, Sect. 6.1 and conclusion: ψ̇ = −(461.52 ± 6.57)″/yr for Itokawa.
PETIT_ITOKAWA_SIGMA = 6.57
#: Demura et al. (2006): the Itokawa pole "with a 3.9° margin of error" (Petit Sect. 5.1: "±3.9° margin").
DEMURA_MARGIN_DEG = 3.9


def test_itokawa_petit2014_precession_rate_uncertainty():
    """Petit et al. give ψ̇ = −461.52 ± 6.57″/yr for Itokawa; they say the uncertainty comes from H_d and ε
    (Sect. 3.3) and quote the pole's ±3.9° margin (Sect. 5.1), with no H_d uncertainty.

    With their inputs (petit2014: pole ±3.9° in RA and Dec, nothing else uncertain) ψ̇ depends on the pole
    through ε only, so σ_ψ̇ = |∂ψ̇/∂ε| σ_ε = |ψ̇ tan ε| σ_ε. Ours: σ_ε = 3.86°, σ_ψ̇ = 13.0″/yr, twice
    theirs.
    Their 6.57 is |ψ̇ tan ε| × 1.95°, half the 3.9° margin, to the last printed digit.
    """
    r = propagate(get_body("Itokawa", "petit2014"), order=4)
    assert set(r["inputs"]) == {"pole.ra", "pole.dec"}
    psidot = r["values"]["precession_rate_arcsec_per_year"]
    eps = math.radians(r["values"]["obliquity_deg"])
    assert psidot == pytest.approx(-461.52, abs=0.2) and math.degrees(eps) == pytest.approx(157.30, abs=0.005)
    sig_eps = math.radians(r["obliquity_deg_uncertainty"])
    sig_psi = r["precession_rate_arcsec_per_year_uncertainty"]
    slope = sig_psi / sig_eps
    assert slope == pytest.approx(abs(psidot * math.tan(eps)), rel=1e-3)
    # ours, from the inputs the paper states
    assert r["obliquity_deg_uncertainty"] == pytest.approx(DEMURA_MARGIN_DEG, rel=0.02)
    assert sig_psi == pytest.approx(13.0, abs=0.1)
    assert sig_psi / PETIT_ITOKAWA_SIGMA == pytest.approx(2.0, abs=0.04)
    # the Monte Carlo agrees with our linear value (the model is nearly linear over ±3.9° here)
    mc = monte_carlo(get_body("Itokawa", "petit2014"), 1000, 0, order=4)
    assert mc["precession_rate_arcsec_per_year_uncertainty"] == pytest.approx(sig_psi, rel=0.10)
    # theirs: the same slope times half the margin, 6.57 to the printed digit (with 3.9° itself: 13.1)
    assert round(slope * math.radians(DEMURA_MARGIN_DEG / 2), 2) == PETIT_ITOKAWA_SIGMA
    assert round(abs(-461.5208 * math.tan(math.radians(157.30))) * math.radians(DEMURA_MARGIN_DEG / 2), 2) \
        == PETIT_ITOKAWA_SIGMA
    assert slope * math.radians(DEMURA_MARGIN_DEG) == pytest.approx(13.1, abs=0.05)


def test_itokawa_shape_uncertainty_is_not_in_petits_number():
    """Their H_d comes from the shape (±1 m on each axis). For the uniform ellipsoid 535 × 294 × 209 m
    that gives Table 4's H_d, H_d = 1/2 − c²/(a² + b²) (semi-axes); ±1 m on each full axis adds
    1.4″/yr to ψ̇ in quadrature: with it, ε alone would have to be 1.88°, no round fraction of 3.9°."""
    a, b, c = 267.5, 147.0, 104.5                      # semi-axes, m
    hd = 0.5 - c * c / (a * a + b * b)
    assert hd == pytest.approx(0.3828, abs=5e-5)
    s = a * a + b * b
    grad = np.array([2 * a * c * c / s**2, 2 * b * c * c / s**2, -2 * c / s])
    sig_hd = 0.5 * float(np.linalg.norm(grad))           # ±1 m on a full axis = ±0.5 m on a semi-axis
    r = propagate(get_body("Itokawa", "petit2014"), order=4, uncertainties={"inertia.dynamical_ellipticity": sig_hd})
    shape_part = abs(r["contributions"]["precession_rate_arcsec_per_year"]["inertia.dynamical_ellipticity"])
    assert shape_part == pytest.approx(abs(r["values"]["precession_rate_arcsec_per_year"]) * sig_hd / 0.3828,
                                       rel=1e-3)
    assert shape_part == pytest.approx(1.44, abs=0.02)
    pole_only = math.sqrt(PETIT_ITOKAWA_SIGMA**2 - shape_part**2)
    slope = abs(r["values"]["precession_rate_arcsec_per_year"] * math.tan(math.radians(157.30)))
    assert math.degrees(pole_only / slope) == pytest.approx(1.90, abs=0.02)
