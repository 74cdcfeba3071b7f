"""The Earth's rigid lunisolar precession-nutation (ephem.earth.lunisolar): the FFT grid of its forcing spectrum, the
H_d it takes, a numerical integration of the torque along DE421's Moon and Sun (the independent route: the rate,
the residuals, the precession-nutation coupling, the 9.3-yr second-order term), the Sun-only model of
ephem.forced.precession_nutation, its properties (in-phase terms, the Oppolzer conversion) and its evaluation (TermProducts).

Against outside references: ERFA (tests/earth/test_against_erfa.py), DE421's Moon and Sun (tests/orbit/test_against_de421.py),
IAU 2006/2000A (tests/earth/test_against_iau2006.py), Bourda & Capitaine 2004 (tests/earth/test_against_bourda_capitaine2004.py),
A&A 2017 Table A.4 (tests/earth/test_against_aa2017_aa30490.py). Numbers and their sources: docs/earth.md,
data/lunisolar.toml.
"""
import math

import numpy as np
import pytest

from ephem.earth import lunisolar as L
from ephem.earth.de421_integration import integrate_de421
from ephem.bodies.catalogue import get_body
from ephem.base.constants import ARCSEC, MAS
from ephem.base.errors import InvalidInputError
from ephem.forced.precession_nutation import build_model

J2000 = 2451545.0
CY = 36525.0


@pytest.fixture(scope="module")
def rigid_l():
    """Angular-momentum axis (what the torque equations move), IERS 2010 H_d."""
    return L.earth_lunisolar(hd="iers2010", axis="angular_momentum")


# ----------------------------------------------------------------------------- the forcing spectrum

def test_fft_grid_resolves_every_kept_term():
    hd, omega, eps = L.hd_iers2010(), L.earth_spin_rate(), L.obliquity_arcsec() * ARCSEC
    coarse = L.orbital_spectrum(L.PERTURBERS, 0.0)
    fine = L.orbital_spectrum(L.PERTURBERS, 0.0, (32, 16, 32, 32, 8))
    nu_c, nu_f = coarse.multipliers @ L.delaunay_rates(), fine.multipliers @ L.delaunay_rates()
    cc, pc = L._coefficients(coarse, hd, omega, eps, nu_c, "figure")
    cf, pf = L._coefficients(fine, hd, omega, eps, nu_f, "figure")
    fine_rows = {tuple(k): i for i, k in enumerate(fine.multipliers)}
    big = np.nonzero(np.abs(cc).max(axis=1) / MAS > 0.05)[0]
    assert big.size > 80
    diff = [np.abs(cc[i] - cf[fine_rows[tuple(coarse.multipliers[i])]]).max() / MAS for i in big]
    assert max(diff) < 1e-6
    assert pc == pytest.approx(pf, rel=1e-12)   # the constant term of two FFTs: round-off ~1e-15 of it


# ----------------------------------------------------------------------------- precession

def test_catalogue_hd_is_the_default_and_scales_the_rates():
    assert L.earth_lunisolar().hd == get_body("earth").hd == L.hd_iers2010()   # the catalogue now gives IERS's
    cat = L.earth_lunisolar(hd=get_body("earth").hd_from_moments)               # Lara's moments: 0.16% higher
    iers = L.earth_lunisolar(hd="iers2010")
    # the rate is linear in H_d: two rates and a ratio, a few ε; 1e-12
    assert cat.precession_rate / iers.precession_rate == pytest.approx(cat.hd / iers.hd, rel=1e-12)
    k = [0, 0, 0, 0, 1]
    assert cat.term(k)["obliquity_cos_mas"] / iers.term(k)["obliquity_cos_mas"] == \
        pytest.approx(cat.hd / iers.hd, rel=2e-6)                 # the figure-axis term is ~linear in H_d


# ----------------------------------------------------------------------------- DE421 numerical reference

@pytest.fixture(scope="module")
def de421_run():
    return integrate_de421(J2000 - 7305.0, J2000 + 7305.0, "iers2010", step_days=0.5)   # 1980-2020


def _residual(num, series, extra=0.0):
    dpsi, deps = series.nutation_at(num.jd_tdb)
    t = (num.jd_tdb - J2000) / CY
    design = np.vstack([np.ones_like(t), t, t * t]).T
    out = []
    for y, d in ((num.psi, dpsi + extra), (num.epsilon, deps)):
        res = (y - d) / MAS
        coef, *_ = np.linalg.lstsq(design, res, rcond=None)
        out.append((coef, res - design @ coef))
    return out


def _coupling_at(jd, series):
    """Δψ (radians) of the precession-nutation coupling term at JD TDB."""
    coupling = L.precession_nutation_coupling(series)
    phases = L.delaunay_arguments(jd) @ series.multipliers.T.astype(float)
    return (np.sin(phases) @ coupling[:, 0] + np.cos(phases) @ coupling[:, 1]) * MAS


def test_series_against_de421_integration(de421_run, rigid_l):
    (cpsi, rpsi), (_ceps, reps) = _residual(de421_run, rigid_l)
    rate_num = cpsi[1] / 1000.0                                   # "/cy
    # second-order terms (P03 Table 3: -0.033 - 0.014 - 0.021 "/cy) are in the integration only
    assert rate_num - rigid_l.precession_rate_arcsec_per_century == pytest.approx(-0.068, abs=0.08)
    assert cpsi[2] / 1000.0 == pytest.approx(-1.079, abs=0.2)      # psi_A t^2 (ecliptic motion), IAU 2006
    assert np.sqrt(np.mean(rpsi**2)) < 5.0 and np.abs(rpsi).max() < 10.0      # mas
    assert np.sqrt(np.mean(reps**2)) < 1.0 and np.abs(reps).max() < 2.5


def test_de421_residual_is_the_precession_nutation_coupling(de421_run, rigid_l):
    # Second order: dpsi/dt of the precession depends on cos(eps), so the 18.6-yr Delta-eps
    # feeds -tan(eps) psi_dot Delta-eps into dpsi/dt (2.9 mas on the 18.6-yr term). Adding it
    # must halve the longitude residual: evidence that what is left is second order.
    corr = _coupling_at(de421_run.jd_tdb, rigid_l)
    assert np.abs(corr).max() / MAS == pytest.approx(2.9, abs=0.2)
    (_, before), _ = _residual(de421_run, rigid_l)
    (_, after), _ = _residual(de421_run, rigid_l, corr)
    assert np.sqrt(np.mean(after**2)) < 0.6 * np.sqrt(np.mean(before**2))
    assert np.sqrt(np.mean(after**2)) < 2.5


def test_de421_contains_the_9_3_year_difference_from_iau2000a(de421_run, rigid_l):
    # Ours x the IERS 1996 transfer function meets IAU 2000A on every leading term but 18.6 yr and
    # 9.3 yr (tests/earth/test_against_iau2006.py). The 9.3-yr remainder (IAU - ours x T: +1.37 mas in Δψ,
    # -0.32 in Δε) is rigid-Earth second order: the DE421 integration, which has every order of
    # the Newtonian torque, must show the same 2Ω term against our first-order series.
    from ephem.earth import nonrigid as N

    args = L.delaunay_arguments(de421_run.jd_tdb)
    corr = _coupling_at(de421_run.jd_tdb, rigid_l)
    dpsi, deps = rigid_l.nutation_at(de421_run.jd_tdb)
    t = (de421_run.jd_tdb - J2000) / CY
    om = args[:, 4]
    design = np.vstack([np.ones_like(t), t, t * t, np.sin(om), np.cos(om), np.sin(2 * om), np.cos(2 * om)]).T
    cpsi, *_ = np.linalg.lstsq(design, (de421_run.psi - dpsi - corr) / MAS, rcond=None)
    ceps, *_ = np.linalg.lstsq(design, (de421_run.epsilon - deps) / MAS, rcond=None)
    figure = L.earth_lunisolar(cut_mas=0.1, hd="iers2010")
    ref = next(r for r in L.iau2000a_terms() if r["name"] == "9.3 yr")
    nr = N.non_rigid_term(figure.term(ref["delaunay_multipliers"]), figure.obliquity)
    assert cpsi[5] == pytest.approx(ref["psi"][0] - nr["longitude_sin_mas"], abs=0.2)        # 1.33 vs 1.37
    assert ceps[6] == pytest.approx(ref["eps"][0] - nr["obliquity_cos_mas"], abs=0.2)        # -0.35 vs -0.32


# ----------------------------------------------------------------------------- the Sun alone

def test_sun_only_reproduces_the_existing_model():
    model = build_model(get_body("earth"))
    sun = L.earth_lunisolar(cut_mas=0.0, perturbers=("sun",), axis="angular_momentum")
    # same H_d, omega and GM; the obliquities differ by 5.3" (model: catalogue CIP minus the
    # Sun-only nutation; here eps_A) and the orbits by Standish vs Simon elements
    assert sun.precession_rate / model.precession_rate == pytest.approx(1.0, abs=2e-5)
    # Fixed ellipse in the model: its M-series against ours with l' = M, L_sun = theta + M. The
    # residual is the tropical vs anomalistic frequency (4.8e-5 of the semi-annual term) and e.
    m = np.linspace(0.0, 2 * math.pi, 361)
    theta = model.equinox_to_pericentre
    args = np.stack([0 * m, m, theta + m, 0 * m, 0 * m], axis=-1)
    dpsi, deps = sun.nutation_from_arguments(args)
    mpsi, meps = model.nutation.evaluate(m)
    assert np.abs(mpsi).max() / MAS > 1300
    assert np.abs(dpsi - mpsi).max() / MAS < 0.15
    assert np.abs(deps - meps).max() / MAS < 0.05


# ----------------------------------------------------------------------------- properties

def test_rigid_first_order_terms_are_in_phase(rigid):
    assert np.abs(rigid.coefficients[:, [1, 2]]).max() < 1e-6        # no cos in Δψ, no sin in Δε


def test_oppolzer_terms_follow_the_formula(rigid, rigid_l):
    # figure axis = (I + gνJ)/(1 - (gν)^2) applied to the angular-momentum axis (module docstring)
    g = (1.0 - rigid.hd) / rigid.spin_rate
    se = math.sin(rigid.obliquity)
    for k in ([0, 0, 0, 0, 1], [0, 0, 2, 0, 2], [0, 0, 2, -2, 2]):
        f, a = rigid.term(k), rigid_l.term(k)
        nu = 2 * math.pi / f["period_days"]
        exact = 1.0 / (1.0 - (g * nu) ** 2)
        assert f["longitude_sin_mas"] == pytest.approx(
            exact * (a["longitude_sin_mas"] - g * nu * a["obliquity_cos_mas"] / se), abs=1e-9)
        assert f["obliquity_cos_mas"] == pytest.approx(
            exact * (a["obliquity_cos_mas"] - g * nu * se * a["longitude_sin_mas"]), abs=1e-9)
    # 18.6 yr: +3.4 mas in longitude (Kinoshita 1977's figure-minus-angular-momentum term)
    assert rigid.term([0, 0, 0, 0, 1])["longitude_sin_mas"] - rigid_l.term([0, 0, 0, 0, 1])["longitude_sin_mas"] == \
        pytest.approx(3.39, abs=0.02)


def test_oppolzer_conversion_is_exact_in_frequency(rigid, rigid_l):
    """Independent route: the rigid body's own kinematics, L = Cω e3 + A e3 × de3/dt.

    For a figure axis moving on a small circle at frequency ν (either sense), build L numerically
    and measure the circle L̂ describes: its radius is |1 ∓ (A/Cω)ν| times the figure axis's, a
    rational relation with no (ν/ω)² remainder. The series' per-component figure/angular-momentum
    ratios must be exactly the inverses, 1/(1 ∓ gν), not the linear 1 ± gν (0.5% apart at 13.66 d).
    """
    from ephem.earth.nonrigid import circular_components

    hd, omega = rigid.hd, rigid.spin_rate
    k = (1.0 - hd) / omega                              # A/(Cω), days
    amplitude = 1e-5
    for period in (13.66, -13.66, 9.13, -27.55):
        nu = 2 * math.pi / period
        t = np.linspace(0.0, abs(period), 2001)
        x, y = amplitude * np.cos(nu * t), amplitude * np.sin(nu * t)
        e3 = np.stack([x, y, np.sqrt(1 - x * x - y * y)], axis=1)
        de3 = np.gradient(e3, t, axis=0, edge_order=2)
        lvec = e3 + k * np.cross(e3, de3)
        lhat = lvec / np.linalg.norm(lvec, axis=1)[:, None]
        radius = np.hypot(lhat[200:-200, 0], lhat[200:-200, 1]).mean()
        assert radius / amplitude == pytest.approx(1.0 - k * nu, rel=1e-6)     # L̂ leads e3
    se = math.sin(rigid.obliquity)
    for m in ([0, 0, 2, 0, 2], [1, 0, 2, 0, 2], [0, 0, 0, 0, 1]):
        f, a = rigid.term(m), rigid_l.term(m)
        nu = 2 * math.pi / f["period_days"]
        cf = circular_components(f["longitude_sin_mas"], 0.0, f["obliquity_cos_mas"], 0.0, se)
        ca = circular_components(a["longitude_sin_mas"], 0.0, a["obliquity_cos_mas"], 0.0, se)
        ratios = sorted(abs(p / q) for p, q in zip(cf, ca))
        assert ratios == pytest.approx(sorted([1 / (1 - k * nu), 1 / (1 + k * nu)]), rel=1e-9)


def test_series_api_shapes_and_cut(rigid):
    jd = J2000 + np.arange(12.0).reshape(3, 4) * 37.0
    dpsi, deps = rigid.nutation_at(jd)
    assert dpsi.shape == deps.shape == (3, 4)
    one = rigid.nutation_at(jd[1, 2])
    assert float(one[0]) == pytest.approx(dpsi[1, 2], abs=1e-15)
    amp = np.maximum(np.hypot(*rigid.coefficients[:, :2].T), np.hypot(*rigid.coefficients[:, 2:].T))
    assert amp.min() >= 0.1 and len(rigid.terms) == amp.size
    assert L.earth_lunisolar(hd="iers2010", cut_mas=1.0).coefficients.shape[0] < amp.size
    assert [t["delaunay_multipliers"] for t in rigid.long_period_terms] == [[0, -2, 2, -2, 2]]
    t = rigid.term([0, 0, -2, 2, -2])                       # the semi-annual term, argument negated
    assert t["longitude_sin_mas"] == pytest.approx(-rigid.term([0, 0, 2, -2, 2])["longitude_sin_mas"])


@pytest.mark.parametrize("kwargs, field", [({"perturbers": ("moon", "venus")}, "perturbers"),
                                           ({"perturbers": ()}, "perturbers"),
                                           ({"axis": "rotation"}, "axis"),
                                           ({"cut_mas": -1.0}, "cut_mas"),
                                           ({"hd": 2.0}, "hd"), ({"hd": "wgccre"}, "hd")])
def test_bad_inputs_name_the_field(kwargs, field):
    with pytest.raises(InvalidInputError) as info:
        L.earth_lunisolar(**kwargs)
    assert info.value.field == field


# ----------------------------------------------------------------------------- evaluation (TermProducts)
#
# nutation_at evaluates each term's e^{iφ} as a product of powers of e^{i a_j} (ephem.earth.lunisolar.TermProducts)
# instead of sin and cos of φ = k · a. Checked here against two independent routes written from the series'
# coefficients: the direct float64 sum (the evaluation used before, verbatim) and the same sum in long double
# (64-bit mantissa), within the rounding budget TermProducts states.

WINDOW = (2415020.5, 2488069.5)            # 1900-01-01 .. 2100-01-01 TDB: the served track's window
U = 2.0**-53


def _direct_sum(series, jd):
    """The direct route: sin and cos of every term's argument (ephem/earth/lunisolar.py before TermProducts)."""
    a, t = L.delaunay_arguments(jd), L.centuries(jd)
    phase = a @ series.multipliers.T.astype(float)
    s, c = np.sin(phase), np.cos(phase)
    k, r = series.coefficients, series.rates
    return ((s @ k[:, 0] + c @ k[:, 1] + t * (s @ r[:, 0] + c @ r[:, 1])) * MAS,
            (s @ k[:, 2] + c @ k[:, 3] + t * (s @ r[:, 2] + c @ r[:, 3])) * MAS)


def _long_double_sum(series, jd):
    """The same sum in long double from the same (float64) Delaunay arguments: error ~2^-64, not 2^-53."""
    ld = np.longdouble
    a, t = L.delaunay_arguments(jd).astype(ld), L.centuries(jd).astype(ld)
    phase = a @ series.multipliers.T.astype(ld)
    s, c = np.sin(phase), np.cos(phase)
    k, r = series.coefficients.astype(ld), series.rates.astype(ld)
    return ((s @ k[:, 0] + c @ k[:, 1] + t * (s @ r[:, 0] + c @ r[:, 1])) * ld(MAS),
            (s @ k[:, 2] + c @ k[:, 3] + t * (s @ r[:, 2] + c @ r[:, 3])) * ld(MAS))


def _budget(series, jd, per_norm, per_term_count, constant):
    """u Σ_n (|S_n + Ṡ_n T| + |C_n + Ċ_n T|) (per_norm |k_n|₁ + constant + per_term_count n), radians, for Δψ
    and Δε at each epoch: the form of the bound in TermProducts' docstring (4, 2, 12 there; the direct
    route's 36, 3, 17)."""
    t = L.centuries(jd)[:, None]
    k, r = series.coefficients, series.rates
    n = k.shape[0]
    factor = per_norm * np.abs(series.multipliers).sum(axis=1) + constant + per_term_count * n
    w_psi = np.abs(k[:, 0] + r[:, 0] * t) + np.abs(k[:, 1] + r[:, 1] * t)
    w_eps = np.abs(k[:, 2] + r[:, 2] * t) + np.abs(k[:, 3] + r[:, 3] * t)
    return U * MAS * (w_psi @ factor), U * MAS * (w_eps @ factor)


def _new_budget(series, jd):
    return _budget(series, jd, 4, 2, 12)


def _old_budget(series, jd):
    return _budget(series, jd, 36, 3, 17)


def _epochs(series, seed=2024):
    """Random epochs over 1900-2100, an even grid across several blocks (not a multiple of the block), the
    window's ends and J2000, and fine even grids (0.2 d) at both ends."""
    rng = np.random.default_rng(seed)
    block = series._plan.block
    return np.concatenate([
        rng.uniform(*WINDOW, 3000),
        np.linspace(*WINDOW, 3 * block + 17),
        np.array([WINDOW[0], WINDOW[1], J2000]),
        WINDOW[0] + 0.2 * np.arange(500),
        WINDOW[1] - 0.2 * np.arange(500),
    ])


@pytest.fixture(scope="module")
def fine():
    """A 0.001 mas cut: 400+ terms, multipliers up to 6, several blocks of the smaller block size."""
    return L.earth_lunisolar(hd="iers2010", cut_mas=0.001)


@pytest.mark.parametrize("which", ["rigid", "rigid_l", "fine", "served"])
def test_term_products_equal_the_direct_sum(which, request):
    series = L.earth_lunisolar() if which == "served" else request.getfixturevalue(which)
    jd = _epochs(series)
    new, old = series.nutation_at(jd), _direct_sum(series, jd)
    for got, ref, b_new, b_old in zip(new, old, _new_budget(series, jd), _old_budget(series, jd)):
        assert np.all(np.abs(got - ref) <= b_new + b_old)
        # what the budget means in practice: ~1e-17 rad (2e-12 mas) for the served series
        assert np.abs(got - ref).max() < 1e-16
    if which == "served":
        # the budget of the docstring, and what is measured: ~1e-19 rad
        assert max(b.max() for b in _new_budget(series, jd)) < 5e-18


@pytest.mark.skipif(np.finfo(np.longdouble).eps > 1e-18, reason="long double is no wider than double here")
@pytest.mark.parametrize("which", ["rigid", "rigid_l", "fine"])
def test_term_products_within_their_budget_of_a_long_double_sum(which, request):
    series = request.getfixturevalue(which)
    jd = _epochs(series, seed=7)
    ref = _long_double_sum(series, jd)
    # the reference's own rounding: the direct route's budget at long double's unit roundoff
    ref_err = [b * (np.finfo(np.longdouble).eps / 2 / U) for b in _old_budget(series, jd)]
    for got, exact, budget, slack in zip(series.nutation_at(jd), ref, _new_budget(series, jd), ref_err):
        err = np.abs(got.astype(np.longdouble) - exact)
        assert np.all(err <= budget + slack)
        assert float(err.max()) < 1e-18                 # measured ~1e-19 rad: the budget is ~20x above
    for got, exact, budget, slack in zip(_direct_sum(series, jd), ref, _old_budget(series, jd), ref_err):
        assert np.all(np.abs(got.astype(np.longdouble) - exact) <= budget + slack)   # the old route's own bound


def test_term_products_carry_the_poisson_terms(rigid):
    # at the window's ends |T| = 1: the rate terms move Δψ by up to ~17 mas there, and are evaluated as exactly
    # as the rest. A series of its rates alone checks them apart from the constant coefficients.
    from dataclasses import replace

    jd = np.concatenate([np.linspace(WINDOW[0], WINDOW[0] + 30.0, 301), np.linspace(WINDOW[1] - 30.0, WINDOW[1], 301)])
    static = replace(rigid, rates=np.zeros_like(rigid.rates))
    rates_only = replace(rigid, coefficients=np.zeros_like(rigid.coefficients))
    assert np.abs(rigid.nutation_at(jd)[0] - static.nutation_at(jd)[0]).max() / MAS > 5.0
    for series in (rates_only, static):
        new, old = series.nutation_at(jd), _direct_sum(series, jd)
        for got, ref, b_new, b_old in zip(new, old, _new_budget(series, jd), _old_budget(series, jd)):
            assert np.all(np.abs(got - ref) <= b_new + b_old)
    total = rigid.nutation_at(jd)
    for whole, part_a, part_b in zip(total, static.nutation_at(jd), rates_only.nutation_at(jd)):
        assert np.abs(whole - (part_a + part_b)).max() < 1e-16


def test_nutation_from_arguments_any_arguments_and_shapes(rigid):
    # unreduced and negative arguments, T broadcast against them: the same as the direct formula
    rng = np.random.default_rng(3)
    args = rng.uniform(-30.0, 30.0, (3, 4, 5))
    t = rng.uniform(-1.0, 1.0, (3, 4))
    dpsi, deps = rigid.nutation_from_arguments(args, t)
    assert dpsi.shape == deps.shape == (3, 4)
    phase = args @ rigid.multipliers.T.astype(float)
    s, c = np.sin(phase), np.cos(phase)
    k, r = rigid.coefficients, rigid.rates
    ref_psi = (s @ k[:, 0] + c @ k[:, 1] + t * (s @ r[:, 0] + c @ r[:, 1])) * MAS
    ref_eps = (s @ k[:, 2] + c @ k[:, 3] + t * (s @ r[:, 2] + c @ r[:, 3])) * MAS
    # the direct route's phase rounds by ~|k·a| u (|a| up to 30 rad here): still ~1e-16 relative
    assert np.abs(dpsi - ref_psi).max() < 1e-15 and np.abs(deps - ref_eps).max() < 1e-15
    one = rigid.nutation_from_arguments(args[1, 2], t[1, 2])
    assert np.shape(one[0]) == () and float(one[0]) == pytest.approx(dpsi[1, 2], abs=1e-18)
    at_t = rigid.nutation_from_arguments(args[0], 0.5)          # a scalar T
    assert at_t[0].shape == (4,)


def test_term_products_plan_and_edge_cases(rigid):
    plan = rigid._plan
    # the served tree: fewer products than one per term and argument; every term a row of the last level
    assert sum(level[1].size for level in plan.levels) < 2 * len(rigid.multipliers)
    assert plan.weights.shape == (8, len(rigid.multipliers))
    assert 64 <= plan.block <= 2048
    # the Sun alone uses only some arguments (no l, and F, D, Ω through F - D + Ω): a shorter tree
    sun = L.earth_lunisolar(perturbers=("sun",), cut_mas=0.0)
    jd = np.linspace(*WINDOW, 1001)
    for got, ref in zip(sun.nutation_at(jd), _direct_sum(sun, jd)):
        assert np.abs(got - ref).max() < 1e-16
    # one argument only (the tree is the power table), and a multiplier vector given twice (its terms add up)
    from dataclasses import replace

    one_arg = replace(rigid, multipliers=np.array([[0, 0, 0, 0, 1], [0, 0, 0, 0, -2], [0, 0, 0, 0, 1]]),
                      coefficients=rigid.coefficients[:3], rates=rigid.rates[:3])
    for got, ref in zip(one_arg.nutation_at(jd), _direct_sum(one_arg, jd)):
        assert np.abs(got - ref).max() < 1e-16
    # no terms at all: zeros of the epochs' shape
    empty = L.earth_lunisolar(cut_mas=1e9)
    assert empty.multipliers.shape[0] == 0
    z = empty.nutation_at(np.full((2, 3), J2000))
    assert z[0].shape == (2, 3) and not np.any(z[0]) and not np.any(z[1])
    assert empty.nutation_at(np.array([]))[0].shape == (0,)


def test_nutation_at_checkpoints_every_block(rigid, monkeypatch):
    calls = []
    monkeypatch.setattr(L, "checkpoint", lambda: calls.append(1))
    block = rigid._plan.block
    rigid.nutation_at(np.linspace(*WINDOW, 2 * block + 1))
    assert len(calls) == 3


def test_the_integer_row_codes_sort_as_numpy_unique_rows():
    """ephem.orbit.harmonics.unique_rows (one int64 per row) against np.unique(axis=0): the same rows, order and
    inverse, on random multiplier matrices and on the served series' own multipliers."""
    from ephem.orbit.harmonics import unique_rows

    rng = np.random.default_rng(7)
    cases = [rng.integers(-9, 10, size=(int(rng.integers(1, 500)), int(rng.integers(1, 6)))) for _ in range(40)]
    cases.append(np.asarray(L.earth_lunisolar(cut_mas=0.01).multipliers))
    for k in cases:
        want, want_inverse = np.unique(k, axis=0, return_inverse=True)
        got, got_inverse = unique_rows(k)
        np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(got_inverse, np.asarray(want_inverse).ravel())
