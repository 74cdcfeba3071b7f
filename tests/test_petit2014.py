"""Petit, Souchay & Lhotka (2014) in CI: Tables 3-10 reproduced, and every erratum asserted as recorded.

The printed tables live verbatim in data/petit2014/; the errata in data/errata.toml. Tolerances
come from the printed precision: half a unit of the last printed digit, plus the effect of the
4-digit H_d of Table 4 (±0.00005, i.e. 3e-4 relative for Vesta, which the dataset takes from its
Table 3 moments) where K enters.
"""
import csv
import importlib.util
import math
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ephem import api
from ephem.catalogue import data_dir, load_catalogue
from ephem.constants import ARCSEC, JULIAN_YEAR_DAYS, MAS
from ephem.geometry import icrf_to_ecliptic, spin_geometry
from ephem.hansen import hansen_series
from ephem.kepler import orbit_normal
from ephem.kinoshita import dynamical_ellipticity, nutation_series
from ephem.model import build_model

TABLES = data_dir() / "petit2014"
ERRATA = tomllib.loads((data_dir() / "errata.toml").read_text())["erratum"]
ROOT = Path(__file__).resolve().parent.parent
HD_ROUNDING = 3e-4  # Table 4's 4-digit H_d, relative


def _derive_module():
    spec = importlib.util.spec_from_file_location("derive_petit2014", ROOT / "tools" / "derive_petit2014.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("derive_petit2014", mod)
    spec.loader.exec_module(mod)
    return mod


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
    # K = 3 n² H_d / ω with n from the period the paper prints (Tables 5-10); independent of Table 4's K
    p = api.precession(body, "petit2014", order=4)
    assert p["scaling_factor_arcsec_per_year"] == pytest.approx(TABLE4[body]["scaling_factor_arcsec_per_year"],
                                                                rel=HD_ROUNDING)


@pytest.mark.parametrize("body", ["Eros", "Steins", "Itokawa"])
def test_semi_major_axis_implied_by_k_is_a_real_orbit(body):
    # for these the dataset's a is derived from Table 4's K (the paper's epoch is unknown):
    # it must lie within 1e-3 of today's osculating a, or the K/H_d/period triple is not physical
    eff = load_catalogue("petit2014").get(body).orbit.a_au
    cur = load_catalogue("current").get(body).orbit.a_au
    assert abs(eff / cur - 1) < 1e-3


@pytest.mark.parametrize("body", ["Steins", "Itokawa", "Vesta", "Ceres"])
def test_precession_rate_table4(body):
    # eq. 25 at order 4; tolerance: 4-digit H_d (Vesta, Ceres) or 1e-3 for the unknown orbit epoch's e
    # (Eros: see erratum eros-precession-rate)
    tol = HD_ROUNDING if body in ("Vesta", "Ceres") else 1e-3
    p = api.precession(body, "petit2014", order=4)
    assert p["precession_rate_arcsec_per_year"] == pytest.approx(TABLE4[body]["precession_rate_arcsec_per_year"],
                                                                 rel=tol)


def test_vesta_precession_rate_is_13_67():
    p = api.precession("vesta", "petit2014")
    assert round(p["precession_rate_arcsec_per_year"], 2) == 13.67


@pytest.mark.parametrize("body", ["Eros", "Vesta"])
def test_dynamical_ellipticity_from_table3_where_consistent(body):
    row = next(r for r in _csv("table3_physical.csv") if r["body"] == body)
    hd = dynamical_ellipticity(*(float(row[f"moment_{x}"]) for x in "ABC"))
    assert hd == pytest.approx(TABLE4[body]["dynamical_ellipticity"], abs=5e-5)


@pytest.mark.parametrize("body", ["Vesta", "Ceres"])
def test_nutation_semi_amplitudes_table4(body):
    n = api.nutation(body, "petit2014", order=4)
    expected = {"Vesta": (5.1460, 2.2122), "Ceres": (3.1834, None)}[body]
    assert n["delta_psi_half_peak_to_peak_arcsec"] == pytest.approx(expected[0], rel=HD_ROUNDING, abs=5e-5)
    if expected[1] is not None:  # Ceres' Δε: erratum ceres-table4-delta-epsilon
        assert n["delta_epsilon_half_peak_to_peak_arcsec"] == pytest.approx(expected[1], rel=HD_ROUNDING, abs=5e-5)


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
        # the order-4 theory with the fitted (e, θ) meets every printed cell to 0.00023" (measured;
        # printing precision 0.00005"), plus the 4-digit H_d's share
        assert value / ARCSEC == pytest.approx(printed, abs=3e-4 + HD_ROUNDING * abs(printed)), part
    assert s.period_days[k - 1] / JULIAN_YEAR_DAYS == pytest.approx(float(row["period_years"]), abs=5e-5 * k)


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
    assert amp / ARCSEC == pytest.approx(printed, abs=1.5e-4 + HD_ROUNDING * printed)


@pytest.mark.parametrize("row", RAMBAUX, ids=lambda r: f"T{r['table']}-{r['multiple']}M")
def test_tables_9_10_our_model_and_rambaux(row):
    m = _series("Vesta")
    s = m.nutation
    k = int(row["multiple"])
    if row["component"].startswith("longitude"):
        amp = math.hypot(s.lon_sin[k - 1], s.lon_cos[k - 1]) * math.sin(m.obliquity) / MAS
    else:
        amp = math.hypot(s.obl_sin[k - 1], s.obl_cos[k - 1]) / MAS
    assert amp == pytest.approx(float(row["petit_amp_mas"]), abs=0.05 + HD_ROUNDING * amp)
    assert s.period_days[k - 1] == pytest.approx(float(row["petit_period_days"]), abs=1e-4)
    # Rambaux (2013), an Eulerian model with other inputs: within 1.5% for the leading terms
    # (measured 0.05-1.4%), 5% for the small 5M term (measured 4.6%)
    assert amp == pytest.approx(float(row["rambaux_amp_mas"]), rel=0.015 if k < 5 else 0.05)
    assert s.period_days[k - 1] == pytest.approx(float(row["rambaux_period_days"]), rel=3e-4)


def test_effective_inputs_are_reproduced_by_the_derivation_tool():
    # no hand-tuned number in the petit2014 dataset: tools/derive_petit2014.py re-derives them
    derived = _derive_module().derive()
    cat = load_catalogue("petit2014")
    for name, vals in derived.items():
        b = cat.get(name)
        assert b.orbit.a_au == pytest.approx(vals["a_au"], rel=1e-8)
        if "e" in vals:
            assert b.orbit.e == pytest.approx(vals["e"], abs=1e-7)
            assert b.orbit.peri_deg == pytest.approx(vals["peri_deg"], abs=1e-5)
        assert b.pole.ra_deg == pytest.approx(vals["pole_ra_deg"], abs=1e-5)
        assert b.pole.dec_deg == pytest.approx(vals["pole_dec_deg"], abs=1e-5)


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
    assert abs(printed @ nodes) == pytest.approx(abs(math.sin(i) * math.sin(2 * node)), rel=1e-12)
    assert abs(orbit_normal(i, node) @ nodes) < 1e-15


def test_erratum_eq27_pole_vector():
    b = load_catalogue("current").get("Vesta")
    i, node = math.radians(b.orbit.i_deg), math.radians(b.orbit.node_deg)
    s = icrf_to_ecliptic(math.radians(309.031), math.radians(42.2264))
    mirrored = s * np.array([1, -1, 1])
    z = orbit_normal(i, node)
    z26 = z * np.array([1, -1, 1])
    assert math.degrees(math.acos(z @ s)) == pytest.approx(27.44, abs=0.01)
    assert math.degrees(math.acos(z @ mirrored)) == pytest.approx(25.46, abs=0.01)  # one slip alone
    assert math.degrees(math.acos(z26 @ mirrored)) == pytest.approx(27.44, abs=0.01)  # both: they cancel


def test_erratum_eq29_unsigned_angle():
    # Ceres (current): the equinox-to-perihelion angle is negative mod 360 in one branch; arccos folds it
    b = load_catalogue("current").get("Vesta")
    o = b.orbit
    geo = spin_geometry(icrf_to_ecliptic(math.radians(b.pole.ra_deg), math.radians(b.pole.dec_deg)),
                        *(math.radians(x) for x in (o.i_deg, o.node_deg, o.peri_deg)))
    theta = geo.equinox_to_pericentre
    assert math.acos(math.cos(theta)) == pytest.approx(abs(theta))
    # θ and -θ give different nutation phases: 2θ enters through C' = cos 2θ, S' = sin 2θ
    s1 = nutation_series(1e-4, 0.017, 0.5, 0.09, theta)
    s2 = nutation_series(1e-4, 0.017, 0.5, 0.09, -theta)
    assert abs(s1.lon_cos[1] + s2.lon_cos[1]) < 1e-18 and abs(s1.lon_cos[1]) > 1e-6


def test_erratum_eq23_k2_divisor():
    # Table 5's 2M terms follow /(2n): the coefficients test passes with it; with /n they would double
    s = _series("Vesta").nutation
    assert s.lon_cos[1] / ARCSEC == pytest.approx(-2.6481, abs=2e-3)
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
    assert -s.obl_sin[0] / ARCSEC == pytest.approx(-0.1263, abs=2e-4)


def test_erratum_eq24_repeated_terms():
    s = _series("Vesta").nutation
    assert (-s.obl_sin[3] / ARCSEC, -s.obl_cos[3] / ARCSEC) == pytest.approx((0.0475, -0.0494), abs=1.5e-4)


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
    assert np.abs(best(-1).fun).max() < 3e-4    # the paper's tables = our theory with Δε flipped
    assert np.abs(best(+1).fun).max() > 2.0     # as printed, no phase and e fit
    assert fit.fit_nutation_table("Vesta", 1325.3803)["max_residual_arcsec"] < 3e-4


def test_erratum_table4_nutation_columns():
    assert _half_ptp(_table("longitude", "Vesta")) == pytest.approx(5.1460, abs=1e-4)
    assert _half_ptp(_table("obliquity", "Vesta")) == pytest.approx(2.2122, abs=1e-4)
    amps = [math.hypot(*sc) for sc in _table("longitude", "Vesta")]
    assert sum(amps) != pytest.approx(5.1460, abs=0.1) and max(amps) != pytest.approx(5.1460, abs=0.1)


def test_erratum_table5_amp_column():
    s, c = _table("longitude", "Vesta")[0]
    assert math.hypot(s, c) * math.sin(math.radians(27.46)) == pytest.approx(1.1027, abs=1e-4)


def test_erratum_ceres_table7_6M():
    rows = _table("longitude", "Ceres")
    assert _half_ptp(rows) == pytest.approx(3.1841, abs=1e-4)              # as printed
    fixed = rows[:5] + [(-0.0008, rows[5][1])]
    assert _half_ptp(fixed) == pytest.approx(3.1834, abs=1e-4)             # = Table 4
    assert _series("Ceres").nutation.lon_sin[5] / ARCSEC == pytest.approx(-0.0008, abs=1e-4)


def test_erratum_ceres_table8_5M():
    assert -_series("Ceres").nutation.obl_cos[4] / ARCSEC == pytest.approx(-0.0005, abs=1e-4)


def test_erratum_ceres_table4_delta_epsilon():
    rows = _table("obliquity", "Ceres")
    fixed = rows[:4] + [(rows[4][0], -0.0005)] + rows[5:]
    assert _half_ptp(fixed) == pytest.approx(0.1830, abs=1e-4)
    ours = api.nutation("ceres", "petit2014", order=4)["delta_epsilon_half_peak_to_peak_arcsec"]
    assert ours == pytest.approx(0.1829, abs=2e-4)
    assert abs(ours - 0.1813) > 1e-3




def _hd_from_table3(body):
    row = next(r for r in _csv("table3_physical.csv") if r["body"] == body)
    return dynamical_ellipticity(*(float(row[f"moment_{x}"]) for x in "ABC"))


def test_erratum_table4_hd_steins():
    assert _hd_from_table3("Steins") == pytest.approx(0.2532, abs=1e-4)
    assert load_catalogue("petit2014").get("Steins").hd == 0.2717


def test_erratum_table4_hd_itokawa():
    assert _hd_from_table3("Itokawa") == pytest.approx(0.4211, abs=1e-4)
    assert dynamical_ellipticity(0.298**2 + 0.244**2, 0.535**2 + 0.244**2, 0.535**2 + 0.298**2) == \
        pytest.approx(0.3413, abs=1e-4)
    assert dynamical_ellipticity(0.294**2 + 0.209**2, 0.535**2 + 0.209**2, 0.535**2 + 0.294**2) == \
        pytest.approx(0.3828, abs=5e-5)


def test_erratum_table4_hd_ceres():
    assert _hd_from_table3("Ceres") == pytest.approx(0.0632, abs=1e-4)
    assert load_catalogue("petit2014").get("Ceres").hd == 0.071652


def _geometric_obliquity(name, ra, dec, ecliptic=False):
    o = load_catalogue("current").get(name).orbit
    from ephem.geometry import unit_vector
    s = unit_vector(math.radians(ra), math.radians(dec)) if ecliptic else \
        icrf_to_ecliptic(math.radians(ra), math.radians(dec))
    return math.degrees(spin_geometry(s, *(math.radians(x) for x in (o.i_deg, o.node_deg, o.peri_deg))).obliquity)


def test_erratum_itokawa_pole_frame():
    assert _geometric_obliquity("Itokawa", 128.5, -89.66, ecliptic=True) == pytest.approx(178.7, abs=0.05)
    assert _geometric_obliquity("Itokawa", 128.5, -89.66) == pytest.approx(156.22, abs=0.05)


@pytest.mark.parametrize("body, ra, dec, ours", [("Eros", 11.3692, 17.2273, 89.02), ("Steins", 99, -59, 176.13),
                                                  ("Itokawa", 128.5, -89.66, 156.22), ("Vesta", 309.031, 42.2264, 27.44),
                                                  ("Ceres", 288, 66, 3.94)])
def test_erratum_table4_obliquity(body, ra, dec, ours):
    got = _geometric_obliquity(body, ra, dec)
    assert got == pytest.approx(ours, abs=0.006)
    assert abs(got - TABLE4[body]["obliquity_deg"]) > 0.01


def test_erratum_eros_precession_rate():
    t4 = TABLE4["Eros"]
    e = load_catalogue("petit2014").get("Eros").orbit.e
    f4 = 1 + 1.5 * e**2 + 15 / 8 * e**4
    implied = math.degrees(math.acos(t4["precession_rate_arcsec_per_year"] / (t4["scaling_factor_arcsec_per_year"] / 2 * f4)))
    assert implied == pytest.approx(89.006, abs=1e-3)
    ours = api.precession("eros", "petit2014", order=4)["precession_rate_arcsec_per_year"]
    assert ours == pytest.approx(2.864, abs=2e-3)


def test_erratum_nutation_phase_ceres():
    fit = _derive_module().fit_nutation_table("Ceres", 4.6010 * JULIAN_YEAR_DAYS)
    assert fit["theta_deg"] == pytest.approx(162.14, abs=0.01)
    assert fit["max_residual_arcsec"] < 2e-4
    # Ceres' osculating orbit of 2013 Nov 4.0 TT (MPCORB, MPO286777): i, Ω, ω
    geo = spin_geometry(icrf_to_ecliptic(math.radians(288), math.radians(66)),
                        *(math.radians(x) for x in (10.59398, 80.32762, 72.29213)))
    assert math.degrees(geo.equinox_to_pericentre) % 180 == pytest.approx(97.72, abs=0.01)


def test_every_erratum_has_its_test():
    names = set(globals())
    missing = [e["id"] for e in ERRATA if "test_erratum_" + e["id"].replace("-", "_") not in names]
    assert not missing


def test_erratum_itokawa_precession_uncertainty():
    from ephem.uncertainty import propagate

    r = propagate("Itokawa", "petit2014", order=4)
    ours = r["precession_rate_arcsec_per_year_uncertainty"]
    assert ours == pytest.approx(13.0, abs=0.1)           # the pole's 3.9° as 1σ
    slope = abs(-461.5208 * math.tan(math.radians(157.30)))  # Table 4: |ψ̇ tan ε|, arcsec/yr per radian
    assert round(slope * math.radians(3.9 / 2), 2) == 6.57   # the printed σ: half the margin
    assert ours / 6.57 == pytest.approx(2.0, abs=0.04)
