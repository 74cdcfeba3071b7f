"""The population core's σ columns by forward-mode derivatives (issue 33: ephem.batch.tangents), and the core's
faster arithmetic, against the routes they replaced.

* The uncertainties against central differences (the route before issue 33, still in the module for the
  eccentricity: ``DIFFERENCED_INPUTS``), one input at a time, at two steps. A central difference D(h) = u + a h² +
  O(h⁴) + r(h) carries a truncation a h² that D(h) - D(2h) = -3 a h² measures, and a rounding r(h) ≈ δf σ/h =
  δf / STEP_FRACTION (δf the rounding of a value, h = STEP_FRACTION σ). Exact derivatives must then land within
  |D(h) - D(2h)|/2 (a h² with room for the h⁴ terms) plus 3 r(h) (D(h)'s own rounding and that of the truncation's
  estimate) of D(h): the budget of every comparison below. Forward mode has no complex arithmetic (no complex-step):
  a wrong or missing term of a tangent shows as a derivative off by much more than that, which the check that
  can fail demonstrates.
* Derivatives known in closed form: ∂H_d/∂H_d = 1, K ∝ H_d P, and ψ̇ ∝ H_d P but for the mean pole's shift.
* The rows whose steps leave the domain get NaN exactly where the central differences did.
* The leading terms and the estimate against the code they replaced (a stable argsort, np.hypot).
"""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

from ephem.base.constants import ARCSEC, JULIAN_YEAR_DAYS
from ephem.batch import population, tangents
from ephem.batch.population import SIGMA_INPUTS, UNCERTAIN, evaluate
from ephem.bodies.catalogue import MIN_ROTATION_PERIOD_HOURS
from ephem.forced.kinoshita import TERM_FLOOR, exact_series_floor
from ephem.orbit.geometry import icrf_to_ecliptic_matrix, spin_angles, unit_vector
from ephem.orbit.kepler import mean_motion_rad_per_day

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("generate_population", ROOT / "tools" / "generate_population.py")
gen = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(gen)

EPS = float(np.finfo(float).eps)
PER_YEAR = JULIAN_YEAR_DAYS / ARCSEC
#: a σ per input: the population's scale (poles of a few degrees) and more (orbits, shapes known to 1e-3-1e-4)
SIGMAS = {"a_au": 1e-4, "e": 1e-4, "i_deg": 0.5, "node_deg": 0.5, "peri_deg": 0.5, "mean_anomaly_deg": 0.5,
          "pole_ra_deg": 5.0, "pole_dec_deg": 5.0, "rotation_period_hours": 1e-3, "dynamical_ellipticity": 1e-3,
          "moment_a": 1e-4, "moment_b": 1e-4, "moment_c": 1e-4, "axis_a_km": 1e-2, "axis_b_km": 1e-2,
          "axis_c_km": 1e-2}


def generated(count: int = 600, seed: int = 33, **kw) -> dict:
    """The generator's rows (main belt and NEAs, the three inertia forms, H_d as ``_h_d``), without its own sigma
    columns."""
    chunks = list(gen.generate(count, seed=seed, **kw))
    cols = {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}
    return {k: v for k, v in cols.items() if not k.endswith("_sigma") and (k == "_h_d" or not k.startswith("_"))}


@pytest.fixture(scope="module")
def rows():
    return {k: v for k, v in generated().items() if not k.startswith("_")}


def by_differences(monkeypatch, cols: dict, step: float = population.STEP_FRACTION) -> dict:
    """``evaluate`` with every σ by central differences (the route before issue 33) at ``step`` σ."""
    with monkeypatch.context() as m:
        m.setattr(population, "DIFFERENCED_INPUTS", SIGMA_INPUTS)
        m.setattr(population, "STEP_FRACTION", step)
        return evaluate(cols)


def rounding(out: dict) -> dict:
    """δf per value, in its unit: 64 ε of its scale (the obliquity's angle, π rad; H_d's inertia, O(1), whose
    difference C - (A+B)/2 it is; K and ψ̇ with the relative rounding of H_d, 1/H_d)."""
    hd = out["dynamical_ellipticity"]
    scale = {"obliquity_deg": 180.0, "dynamical_ellipticity": 1.0,
             "scaling_factor_arcsec_per_year": np.abs(out["scaling_factor_arcsec_per_year"]) / hd,
             "precession_rate_arcsec_per_year": np.abs(out["scaling_factor_arcsec_per_year"]) / hd}
    return {k: 64.0 * EPS * np.asarray(scale[k]) for k in UNCERTAIN}


def within_differences(fast: dict, d1: dict, d2: dict, step: float = population.STEP_FRACTION) -> dict:
    """{value: the rows where the exact derivative is off D(h) by more than the module docstring's budget}."""
    out = {}
    for k, df in rounding(d1).items():
        f, a, b = (o[f"{k}_uncertainty"] for o in (fast, d1, d2))
        budget = 0.5 * np.abs(a - b) + 3.0 * df / step
        out[k] = np.nonzero(np.isfinite(a) & ~(np.abs(f - a) <= budget))[0]
    return out


@pytest.mark.parametrize("key", [k for k in SIGMA_INPUTS if k != "e"])
def test_forward_mode_matches_central_differences(rows, monkeypatch, key):
    cols = {**rows, f"{key}_sigma": np.full(rows["a_au"].size, SIGMAS[key])}
    fast = evaluate(cols)
    d1, d2 = by_differences(monkeypatch, cols), by_differences(monkeypatch, cols, 2 * population.STEP_FRACTION)
    for k in UNCERTAIN:      # the same rows known, the same rows unknown
        assert np.array_equal(np.isnan(fast[f"{k}_uncertainty"]), np.isnan(d1[f"{k}_uncertainty"])), k
    assert np.isfinite(fast["obliquity_deg_uncertainty"]).sum() > 0.9 * rows["a_au"].size
    assert {k: v.tolist() for k, v in within_differences(fast, d1, d2).items()} == {k: [] for k in UNCERTAIN}
    for k in ("obliquity_deg", "scaling_factor_arcsec_per_year", "precession_rate_arcsec_per_year"):
        # the values: one code path whatever the σ's route, so the same numbers (a few ε allowed, no more)
        np.testing.assert_allclose(fast[k], d1[k], rtol=4 * EPS, atol=0, equal_nan=True)


def test_the_comparison_can_fail(rows, monkeypatch):
    """The mean pole's passes dropped from the tangents (the period then moves no obliquity): caught."""
    cols = {**rows, "rotation_period_hours_sigma": np.full(rows["a_au"].size, SIGMAS["rotation_period_hours"])}
    d1, d2 = by_differences(monkeypatch, cols), by_differences(monkeypatch, cols, 2 * population.STEP_FRACTION)
    monkeypatch.setattr(tangents, "MEAN_POLE_PASSES", 0)
    bad = within_differences(evaluate(cols), d1, d2)
    assert bad["obliquity_deg"].size > 0.9 * rows["a_au"].size
    assert bad["scaling_factor_arcsec_per_year"].size == 0        # K holds no mean pole


def test_the_eccentricity_still_goes_by_differences(rows, monkeypatch):
    """e moves the Hansen coefficients: its σ is the central differences' own, to the bit."""
    cols = {**rows, "e_sigma": np.full(rows["a_au"].size, SIGMAS["e"])}
    fast, d1 = evaluate(cols), by_differences(monkeypatch, cols)
    for k in UNCERTAIN:     # the same differences: the same numbers (a few ε allowed, no more)
        np.testing.assert_allclose(fast[f"{k}_uncertainty"], d1[f"{k}_uncertainty"], rtol=4 * EPS, atol=0,
                                   equal_nan=True)


def test_no_hansen_coefficients_are_made_again_for_the_sigmas(rows, monkeypatch):
    """The population's σ columns (pole, period, H_d) cost no FFT: one pass over the rows' Hansen coefficients."""
    calls = []
    many = population.hansen_exact_many
    monkeypatch.setattr(population, "hansen_exact_many", lambda e: calls.append(np.size(e)) or many(e))
    n = rows["a_au"].size
    sig = {f"{k}_sigma": np.full(n, SIGMAS[k]) for k in ("pole_ra_deg", "pole_dec_deg", "rotation_period_hours",
                                                        "dynamical_ellipticity")}
    out = evaluate({**rows, **sig})
    assert calls == [np.count_nonzero(out["error"] == "")]       # once, the rows the theory takes


@pytest.mark.parametrize("key", ["dynamical_ellipticity", "rotation_period_hours"])
def test_derivatives_in_closed_form(key):
    """K = 3 n² H_d / ω ∝ H_d P, so σ_K = K σ/x exactly; ψ̇ = (K/2) cos ε̄ (1 - e²)^(-3/2) ∝ H_d P too, but for the
    mean pole ε̄ = ε - Δε(t0), whose Δε ∝ K moves with it: dψ̇/dx = (ψ̇ + (K/2) sin ε̄ Δε (1 - e²)^(-3/2))/x, to
    O(c²) with c = K/(2n) the nutation's scale (the passes' dependence on ε̄, θ̄). H_d's own σ is σ."""
    every = generated(300, seed=34, nea_fraction=0.3)
    cols = {k: v for k, v in every.items() if k not in population.INERTIA_INPUTS and not k.startswith("_")}
    cols["dynamical_ellipticity"] = every["_h_d"]     # every row in H_d's form
    x = cols[key]
    sigma = 1e-3 * x
    out = evaluate({**cols, f"{key}_sigma": sigma})
    good = out["error"] == ""                       # (the generator makes a few slow rotators)
    assert good.sum() > 0.9 * x.size
    cols, x, sigma = {k: v[good] for k, v in cols.items()}, x[good], sigma[good]
    out = {k: v[good] for k, v in out.items()}
    K, rate, obl = out["scaling_factor_arcsec_per_year"], out["precession_rate_arcsec_per_year"], out["obliquity_deg"]
    # K: one product and one quotient of each side, a few ε
    np.testing.assert_allclose(out["scaling_factor_arcsec_per_year_uncertainty"], K * sigma / x, rtol=16 * EPS)
    if key == "dynamical_ellipticity":
        np.testing.assert_allclose(out["dynamical_ellipticity_uncertainty"], sigma, rtol=4 * EPS)
    s = unit_vector(np.radians(cols["pole_ra_deg"]), np.radians(cols["pole_dec_deg"])) @ icrf_to_ecliptic_matrix().T
    eps_catalogue = spin_angles(s, *(np.radians(cols[k]) for k in ("i_deg", "node_deg", "peri_deg")))[0]
    eps_mean = np.radians(obl)
    fe = (1.0 - cols["e"] ** 2) ** -1.5
    half_k = 0.5 * K * fe                           # arcsec per year: the rate's scale
    expected = np.abs(rate + half_k * np.sin(eps_mean) * (eps_catalogue - eps_mean)) * sigma / x
    c = K / PER_YEAR / (2.0 * mean_motion_rad_per_day(cols["a_au"]))
    # O(c²) of the rate's scale (the sums of the nutation at t0 are O(1) in c's unit for e < 0.8: 100 covers
    # them), and the rate's rounding (1e-13 of its scale)
    budget = half_k * sigma / x * (100.0 * c * c + 1e-13)
    assert np.all(np.abs(out["precession_rate_arcsec_per_year_uncertainty"] - expected) <= budget)
    # the mean pole's share is resolved: without it, the rows whose nutation at t0 is large would fail
    shift = half_k * np.abs(np.sin(eps_mean) * (eps_catalogue - eps_mean)) * sigma / x
    assert np.any(shift > 100 * budget)


def test_steps_out_of_the_domain_give_nan_as_the_differences_did(monkeypatch):
    """Rows at the domain's edges, each with the σ whose step leaves it, and the generator's corrupted rows with
    every σ: the same NaN and the same errors as the central differences."""
    cols = {k: v for k, v in generated(400, seed=35, corrupt=40).items() if not k.startswith("_")}
    n = cols["a_au"].size
    sig = {f"{k}_sigma": np.full(n, SIGMAS[k]) for k in SIGMA_INPUTS}
    edges = {0: ("pole_dec_deg", 90.0 - 0.004, 1.0), 1: ("i_deg", 0.004, 1.0),
             2: ("rotation_period_hours", MIN_ROTATION_PERIOD_HOURS + 1e-4, 0.1), 3: ("e", 1e-5, 0.01),
             4: ("a_au", 2.5, 5e-324)}     # σ/100 underflows to 0: 0/0
    for j, (key, value, s) in edges.items():
        cols[key][j], sig[f"{key}_sigma"][j] = value, s
    fast, d1 = evaluate({**cols, **sig}), by_differences(monkeypatch, {**cols, **sig})
    assert list(fast["error"]) == list(d1["error"])
    for k in UNCERTAIN:
        assert np.array_equal(np.isnan(fast[f"{k}_uncertainty"]), np.isnan(d1[f"{k}_uncertainty"])), k
    assert np.all(np.isnan(fast["obliquity_deg_uncertainty"][list(edges)]))
    assert np.isfinite(fast["obliquity_deg_uncertainty"]).sum() > 0.5 * n


def _reference_terms(k, n, eps, lon_s, lon_c, obl_s, obl_c):
    """The leading terms and the estimate as the core made them before issue 33 (a stable argsort, np.hypot)."""
    sin_eps = np.abs(np.sin(eps))[:, None]
    lon, obl = np.hypot(lon_s, lon_c) * sin_eps, np.hypot(obl_s, obl_c)
    order = np.argsort(-(lon + obl), axis=1, kind="stable")[:, :population.LEADING_TERMS]
    pick = np.arange(order.shape[0])
    terms = {}
    for j in range(population.LEADING_TERMS):
        col = order[:, j]
        terms[f"nutation_{j + 1}_multiple"] = k[col]
        terms[f"nutation_{j + 1}_longitude_amplitude_arcsec"] = lon[pick, col] / ARCSEC
        terms[f"nutation_{j + 1}_obliquity_amplitude_arcsec"] = obl[pick, col] / ARCSEC
    disp = lon + obl
    big = np.max(np.abs(np.stack([lon_s, lon_c, obl_s, obl_c])), axis=0) >= TERM_FLOOR
    last = np.where(big.any(axis=1), big.shape[1] - np.argmax(big[:, ::-1], axis=1), 0)
    tail = np.where(np.arange(big.shape[1])[None, :] >= last[:, None], disp, 0.0).sum(axis=1)
    return terms, exact_series_floor(tail, disp.sum(axis=1) - tail)


def test_leading_terms_and_estimate_as_before():
    """Random series with ties (repeated and zero terms), subnormal and NaN rows: the same terms chosen (ties to
    the lowest k, NaN last) and the same numbers to an ulp of np.hypot."""
    rng = np.random.default_rng(7)
    rows_, width = 400, 40
    c = [rng.normal(size=(rows_, width)) * np.exp(-rng.uniform(0, 1, (rows_, 1)) * np.arange(width)) * 1e-6
         for _ in range(4)]
    c[0][:50, 5:9] = c[0][:50, 4:5]                 # ties: equal terms
    for a in c:
        a[50:60] = 0.0                              # all zero: every term tied
        a[60:70] *= 1e-300                          # squares below the normal range
        a[70:75, 3] = np.nan
    k = np.arange(1.0, width + 1)
    n, eps = rng.uniform(1e-3, 1e-2, rows_), rng.uniform(0.1, 3.0, rows_)
    terms = {key: np.full(rows_, np.nan) for key in population._term_columns()}
    estimate = population._terms_and_floor(terms, np.arange(rows_), k, n, eps, *c)
    ref, ref_estimate = _reference_terms(k, n, eps, *c)
    for key, value in ref.items():
        if key.endswith("multiple"):
            assert np.array_equal(terms[key], value), key
        else:       # np.hypot and (x² + y²)^½: within an ulp of each other, a few ε after the products
            np.testing.assert_allclose(terms[key], value, rtol=4 * EPS, atol=0, equal_nan=True, err_msg=key)
    np.testing.assert_allclose(estimate, ref_estimate, rtol=8 * EPS, equal_nan=True)
