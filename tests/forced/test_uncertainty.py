"""Uncertainty propagation (ephem.forced.uncertainty): the replica of the model, linear vs Monte Carlo, and
limit cases. Petit et al.'s (2014) ±6.57″/yr for Itokawa: tests/forced/test_against_petit2014.py. See
docs/uncertainties.md."""
import dataclasses
import math

import numpy as np
import pytest

from ephem import api
from ephem.bodies.catalogue import get_body, load_catalogue, parse_catalogue
from ephem.base.errors import InvalidInputError, NotApplicableError
from ephem.forced.catalogue_sigmas import input_sigmas
from ephem.forced.uncertainty import SCALAR_KEYS, TERM_KEYS, _setup, monte_carlo, propagate

DATASETS = ("current", "petit2014")
APPLICABLE = [(ds, b.name) for ds in DATASETS for b in load_catalogue(ds).bodies if b.name != "Moon"]

# a σ on every input (made up), small enough for the model to be linear over ±1σ for a body whose pole
# is far from its orbit normal (Vesta, ε = 27°), with several inputs contributing to the outputs
SYNTHETIC = {"orbit.a": 1e-5, "orbit.e": 1e-4, "orbit.i": 0.01, "orbit.node": 0.1, "orbit.peri": 0.1,
             "orbit.mean_anomaly": 0.1, "pole.ra": 0.05, "pole.dec": 0.05, "rotation.period": 1e-5,
             "inertia.A": 1e-4, "inertia.B": 1e-4, "inertia.C": 1e-4}


def _public_numbers(body, dataset, order):
    # the replica is the single-perturber (Sun) theory's: the Earth's default answer is the lunisolar one
    # (ephem.earth.family), whose uncertainties are not propagated (tests/earth/test_earth.py)
    p = api.precession(body, dataset=dataset, order=order, perturbers="sun")
    nu = api.nutation(body, dataset=dataset, order=order, perturbers="sun")
    scalars = [p["obliquity_deg"], p["precession_rate_arcsec_per_year"], p["dynamical_ellipticity"],
               p["scaling_factor_arcsec_per_year"], nu["delta_psi_half_peak_to_peak_arcsec"],
               nu["delta_epsilon_half_peak_to_peak_arcsec"]]
    terms = np.array([[t[k] for k in TERM_KEYS[:5]] for t in nu["terms"]])
    return np.array(scalars), terms


def _perturbed(body, key, delta):
    """The body with one input moved by delta (model units), built as a user would."""
    o, p = body.orbit, body.pole
    field = {"orbit.a": "a_au", "orbit.e": "e", "orbit.i": "i_deg", "orbit.node": "node_deg",
             "orbit.peri": "peri_deg", "orbit.mean_anomaly": "mean_anomaly_deg"}
    if key in field:
        return dataclasses.replace(body, orbit=dataclasses.replace(o, **{field[key]: getattr(o, field[key]) + delta}))
    if key in ("pole.ra", "pole.dec"):
        name = "ra_deg" if key == "pole.ra" else "dec_deg"
        return dataclasses.replace(body, pole=dataclasses.replace(p, **{name: getattr(p, name) + delta}))
    if key == "rotation.period":
        return dataclasses.replace(body, rotation_period_hours=body.rotation_period_hours + delta)
    if key == "inertia.dynamical_ellipticity":
        return dataclasses.replace(body, dynamical_ellipticity=body.dynamical_ellipticity + delta)
    moments = list(body.moments)
    moments["ABC".index(key[-1])] += delta
    return dataclasses.replace(body, moments=tuple(moments))


# ----------------------------------------------------------------------------- the replica is the model

@pytest.mark.parametrize("order", [None, 4])
@pytest.mark.parametrize("dataset,name", APPLICABLE)
def test_replica_reproduces_the_public_answers(dataset, name, order):
    st = _setup(get_body(name, dataset), order, None, None)
    scalars, terms = _public_numbers(name, dataset, order)
    ours = st.y0[:len(SCALAR_KEYS)]
    # the replica recomputes the model's formulas (measured: within 4.4e-4 of this bound, i.e. 2 ε); 1e-12
    # covers ~10 roundings amplified by the outputs' condition number (≲ 400, as in tests/earth/test_earth.py)
    np.testing.assert_allclose(ours, scalars, rtol=1e-12, atol=0)
    ours_terms = st.y0[len(SCALAR_KEYS):].reshape(-1, len(TERM_KEYS))
    assert ours_terms.shape[0] == terms.shape[0]
    np.testing.assert_allclose(ours_terms[:, :5], terms, rtol=0, atol=1e-12 * np.abs(terms).max())


@pytest.mark.parametrize("dataset,name", [("current", "Itokawa"), ("current", "Vesta"), ("petit2014", "Steins"),
                                          ("current", "Earth")])
def test_replica_follows_the_model_for_perturbed_inputs(dataset, name):
    """Every input key moves the Body field it names: the replica at x0 + δ is build_model at the moved body."""
    body = load_catalogue(dataset).get(name)
    st = _setup(body, None, None, None)
    deltas = {"orbit.a": 0.01, "orbit.e": 0.01, "orbit.i": 0.3, "orbit.node": 2.0, "orbit.peri": 3.0,
              "orbit.mean_anomaly": 5.0, "pole.ra": 2.0, "pole.dec": -1.5, "rotation.period": 0.01,
              "inertia.dynamical_ellipticity": 0.002}
    if body.moments:   # moves that keep A <= B <= C <= A + B
        deltas.update({"inertia.A": -1e-3 * body.moments[0], "inertia.B": 1e-3 * body.moments[1],
                       "inertia.C": 1e-3 * body.moments[2]})
    for j, inp in enumerate(st.inputs):
        moved = _perturbed(body, inp.key, deltas[inp.key])
        x = st.x0.copy()
        x[j] += deltas[inp.key]
        ours = st.replica.outputs(x, None)
        scalars, terms = _public_numbers(moved, dataset, None)
        # the moved input reaches the two routes by different arithmetic (ε relative, times the outputs'
        # sensitivity: 1e-10), and the half peak-to-peak values come from the replica's own search for the
        # extrema: they differ by up to 3e-9 arcsec when e moves (measured; 1e-8 arcsec)
        np.testing.assert_allclose(ours[:len(SCALAR_KEYS)], scalars, rtol=1e-10, atol=1e-8, err_msg=inp.key)
        ours_terms = ours[len(SCALAR_KEYS):].reshape(-1, len(TERM_KEYS))[:, :5]
        common = min(len(ours_terms), len(terms))   # a moved e may add or drop a term below 1e-14 rad
        assert abs(len(ours_terms) - len(terms)) <= 1
        np.testing.assert_allclose(ours_terms[:common], terms[:common], rtol=0,
                                   atol=1e-10 * np.abs(terms).max(), err_msg=inp.key)


def _ecliptic_pole_body(lon, lat):
    rec = api.body_record("Itokawa")["values"]
    orbit = "\n".join(
        f'{k} = {{ value = {rec["orbit." + k]["value"]}, unit = "{rec["orbit." + k]["unit"]}", source = "x" }}'
        for k in ("epoch", "a", "e", "i", "node", "peri", "mean_anomaly"))
    toml = f"""
[dataset]
name = "t"
[[body]]
name = "EclipticItokawa"
[body.orbit]
{orbit}
[body.pole]
frame = "ecliptic_j2000"
lon = {{ value = {lon!r}, unit = "deg", uncertainty = 3.9, source = "x" }}
lat = {{ value = {lat!r}, unit = "deg", uncertainty = 0.05, source = "x" }}
[body.rotation]
period = {{ value = 12.132, unit = "h", source = "x" }}
[body.inertia]
dynamical_ellipticity = {{ value = 0.3828, unit = "", source = "x" }}
"""
    return parse_catalogue(toml, "t").get("EclipticItokawa")


def test_ecliptic_pole_inputs():
    """A pole given as ecliptic lon/lat (Demura's Itokawa pole) is propagated in those coordinates."""
    body = _ecliptic_pole_body(128.5, -89.66)
    st = _setup(body, None, None, None)
    keys = [i.key for i in st.inputs]
    assert keys[6:8] == ["pole.lon", "pole.lat"]
    np.testing.assert_allclose(st.y0[:len(SCALAR_KEYS)], _public_numbers(body, "t", None)[0], rtol=1e-12)
    for key, lon, lat in (("pole.lon", 130.5, -89.66), ("pole.lat", 128.5, -89.61)):
        x = st.x0.copy()
        x[keys.index(key)] += 2.0 if key == "pole.lon" else 0.05
        np.testing.assert_allclose(st.replica.outputs(x, None)[:len(SCALAR_KEYS)],
                                   _public_numbers(_ecliptic_pole_body(lon, lat), "t", None)[0], rtol=1e-9)
    r = propagate(body)
    assert set(r["inputs"]) == {"pole.lon", "pole.lat"}


# ----------------------------------------------------------------------------- keys, limits

@pytest.mark.parametrize("dataset,name", APPLICABLE)
def test_keys_for_every_applicable_body(dataset, name):
    r = propagate(get_body(name, dataset))
    for key in SCALAR_KEYS:
        assert r[f"{key}_uncertainty"] >= 0.0
        assert key in r["contributions"] and key in r["dominant_input"] and key in r["sensitivities"]
    nu = api.nutation(name, dataset=dataset, perturbers="sun")      # propagate() is the Sun-only theory's
    assert [t["multiple"] for t in r["terms"]] == [t["multiple"] for t in nu["terms"]]
    for t in r["terms"]:
        for key in TERM_KEYS:
            assert t[f"{key}_uncertainty"] >= 0.0
    inputs = set(r["inputs"]) | set(r["unpropagated_inputs"])
    assert {"orbit.a", "orbit.e", "pole.ra", "pole.dec", "rotation.period"} <= inputs
    body = load_catalogue(dataset).get(name)
    for key in r["unpropagated_inputs"]:
        assert body.values[key].uncertainty is None            # never a σ invented
    for key, d in r["inputs"].items():
        assert d["uncertainty"] == body.values[key].uncertainty and d["source"] == body.values[key].source


@pytest.mark.parametrize("dataset", DATASETS)
def test_moon_is_not_applicable(dataset):
    with pytest.raises(NotApplicableError):
        propagate(get_body("Moon", dataset))
    with pytest.raises(NotApplicableError):
        monte_carlo(get_body("Moon", dataset), 10, 0)


def test_catalogue_gaps_are_listed():
    """Vesta's period has Park et al. 2025's σ; its polar moment has none (so neither have the moments derived
    from it), nor its pole or orbit: each gap is listed with the record's reason."""
    vesta = propagate("Vesta")
    assert set(vesta["inputs"]) == {"rotation.period"} and len(vesta["unpropagated_inputs"]) == 11
    reasons = vesta["no_uncertainty_reasons"]
    assert set(reasons) == set(vesta["unpropagated_inputs"])
    assert "Park et al. (2025)" in reasons["inertia.C"] and "WGCCRE" in reasons["pole.ra"]
    eros = propagate("Eros")
    assert set(eros["inputs"]) == {"pole.ra", "pole.dec"}
    assert "rotation.period" in eros["unpropagated_inputs"]
    # an explicit H_d replaces the moments: they are not inputs then
    ito = propagate(get_body("Itokawa", "petit2014"))
    assert "inertia.dynamical_ellipticity" in ito["unpropagated_inputs"]
    assert not any(k in ito["unpropagated_inputs"] for k in ("inertia.A", "inertia.B", "inertia.C"))


def test_zero_input_sigma_gives_zero_output_sigma():
    body = load_catalogue("current").get("Vesta")
    r = propagate(body, uncertainties={k: 0.0 for k in SYNTHETIC})
    assert r["unpropagated_inputs"] == []
    assert all(r[f"{k}_uncertainty"] == 0.0 for k in SCALAR_KEYS)
    assert all(t[f"{k}_uncertainty"] == 0.0 for t in r["terms"] for k in TERM_KEYS)
    assert all(v is None for v in r["dominant_input"].values())


@pytest.mark.parametrize("name", ["Ceres", "Itokawa", "Mars"])
def test_period_alone_scales_the_rate(name):
    """ψ̇ ∝ K ∝ 1/ω ∝ P: the relative σ of ψ̇ and of K is that of the period."""
    body = load_catalogue("current").get(name)
    rel_p = 1e-4
    alone = {key: None for key in input_sigmas(body)} | {"rotation.period": rel_p * body.rotation_period_hours}
    r = propagate(body, uncertainties=alone)
    v = r["values"]
    assert r["scaling_factor_arcsec_per_year_uncertainty"] / v["scaling_factor_arcsec_per_year"] \
        == pytest.approx(rel_p, rel=1e-8)
    # ψ̇ also moves through the mean obliquity (the nutation at the pole epoch scales with K): 1e-3 at most
    assert r["precession_rate_arcsec_per_year_uncertainty"] / abs(v["precession_rate_arcsec_per_year"]) \
        == pytest.approx(rel_p, rel=1e-3)
    assert r["dynamical_ellipticity_uncertainty"] == 0.0
    for t in r["terms"][:3]:   # every coefficient is proportional to K
        assert t["amplitude_obliquity_arcsec_uncertainty"] / t["amplitude_obliquity_arcsec"] \
            == pytest.approx(rel_p, rel=1e-2)
    assert r["dominant_input"]["precession_rate_arcsec_per_year"] == "rotation.period"


def test_catalogue_period_sigma_of_ceres():
    """Ceres' period derives from Dawn's W' = 952.1532635 ± 0.000002 °/d: σ_P/P = σ_W/W' = 2.1e-9, whose share
    of the rate's σ is the same fraction of the rate."""
    body = load_catalogue("current").get("Ceres")
    rel = 0.000002 / 952.1532635
    assert body.values["rotation.period"].uncertainty / body.rotation_period_hours == pytest.approx(rel, rel=1e-9)
    r = propagate("Ceres")
    share = r["contributions"]["precession_rate_arcsec_per_year"]["rotation.period"]
    assert abs(share) / abs(r["values"]["precession_rate_arcsec_per_year"]) == pytest.approx(rel, rel=1e-3)


def test_contributions_add_in_quadrature_and_name_the_dominant_input():
    body = load_catalogue("current").get("Vesta")
    r = propagate(body, uncertainties=SYNTHETIC)
    for key in SCALAR_KEYS:
        c = r["contributions"][key]
        # the same sum of squares in another order: a few ε (12 inputs); 1e-12
        assert math.sqrt(sum(v * v for v in c.values())) == pytest.approx(r[f"{key}_uncertainty"], rel=1e-12)
        assert r["dominant_input"][key] == max(c, key=lambda k: abs(c[k]))
    # sensitivities are per catalogue unit: contribution = sensitivity × σ
    for key, sig in SYNTHETIC.items():
        assert r["contributions"]["precession_rate_arcsec_per_year"][key] == pytest.approx(
            r["sensitivities"]["precession_rate_arcsec_per_year"][key] * sig, rel=1e-6, abs=1e-12)


def test_step_size_does_not_matter():
    """Central differences at σ/100 and σ/50 give the same contributions (truncation error negligible)."""
    import ephem.forced.uncertainty as unc

    body = load_catalogue("current").get("Vesta")
    st = _setup(body, None, SYNTHETIC, None)
    which = list(range(len(st.inputs)))
    sig = np.array([i.sigma * i.factor for i in st.inputs])
    c1, c2 = unc._jacobian(st, which) * sig, unc._jacobian(st, which, step_scale=2.0) * sig
    s1 = np.sqrt((c1**2).sum(axis=1))
    # against each output's σ. Every contribution also carries the FFT round-off of the Hansen coefficients
    # divided by the step (σ/100): measured 4-5e-15 arcsec, the amount varying by 30% with the CPU's SIMD
    # path, so that outputs with σ ~ 7e-9 arcsec (the last harmonics) reached 0.6-0.75 of the 1e-6 below.
    # Keep the outputs whose σ exceeds 1e-7 arcsec, 2e7 times that noise (66 of Vesta's 90; measured 1e-8).
    big = s1 > 1e-7
    assert big.sum() > 40
    assert np.max(np.abs(c1 - c2)[big] / s1[big, None]) < 1e-6


def test_correlated_moments():
    """Ceres's A, B, C all derive from one C/MR²: moved together, H_d = J2/C̄ and σ_H/H = σ_C̄/C̄."""
    body = load_catalogue("current").get("Ceres")
    sig = 0.005
    keys = ("inertia.A", "inertia.B", "inertia.C")
    together = propagate(body, uncertainties={k: sig for k in keys},
                         correlations={("inertia.A", "inertia.B"): 1.0, ("inertia.A", "inertia.C"): 1.0,
                                       ("inertia.B", "inertia.C"): 1.0})
    hd, c_bar = body.hd, body.moments[2]
    assert together["dynamical_ellipticity_uncertainty"] == pytest.approx(hd * sig / c_bar, rel=1e-6)
    apart = propagate(body, uncertainties={k: sig for k in keys})
    # treated as independent the same σ gives a σ_H twenty times too large: the assumption matters
    assert apart["dynamical_ellipticity_uncertainty"] > 15 * together["dynamical_ellipticity_uncertainty"]
    mc = monte_carlo(body, 400, 3, uncertainties={k: sig for k in keys},
                     correlations={("inertia.A", "inertia.B"): 1.0, ("inertia.A", "inertia.C"): 1.0,
                                   ("inertia.B", "inertia.C"): 1.0})
    assert mc["comparison"]["dynamical_ellipticity"]["ratio"] == pytest.approx(1.0, abs=0.1)


def test_edge_of_the_domain():
    """A circular orbit (e = 0) cannot be varied downwards: one-sided differences; the Monte Carlo drops
    the draws with e < 0 and says how many."""
    vesta = load_catalogue("current").get("Vesta")
    body = dataclasses.replace(vesta, orbit=dataclasses.replace(vesta.orbit, e=0.0), values={})
    r = propagate(body, uncertainties={"orbit.e": 1e-3, "pole.ra": 0.01})
    assert math.isfinite(r["precession_rate_arcsec_per_year_uncertainty"])
    # ψ̇ ∝ (1 - e²)^(-3/2) is flat at e = 0
    assert abs(r["sensitivities"]["precession_rate_arcsec_per_year"]["orbit.e"]) < 1e-3
    mc = monte_carlo(body, 200, 0, uncertainties={"orbit.e": 1e-3})
    assert mc["rejected"] + mc["valid"] == 200 and 60 < mc["rejected"] < 140


def test_bad_requests():
    with pytest.raises(InvalidInputError):
        propagate("Vesta", uncertainties={"pole.lat": 1.0})   # an ICRF pole has no lat
    with pytest.raises(InvalidInputError):
        propagate("Vesta", uncertainties={"pole.ra": -1.0})
    with pytest.raises(InvalidInputError):
        propagate("Vesta", correlations={("pole.ra", "pole.dec"): 1.5})
    with pytest.raises(InvalidInputError):
        monte_carlo("Vesta", 1)


def test_the_cost_is_two_model_evaluations_per_input(monkeypatch):
    """Central differences: the nominal model once and two evaluations per input (one-sided at a domain
    edge: still two), 1 + 2 n for the body's n inputs (10 to 12). A count, not a time: benchmarks/bench_cost.py measures
    the seconds (uncertainty.propagated)."""
    from ephem.forced.uncertainty import _Replica
    calls = []
    original = _Replica.outputs

    def counted(self, x, extrema):
        calls.append(1)
        return original(self, x, extrema)
    monkeypatch.setattr(_Replica, "outputs", counted)
    for ds, name in APPLICABLE:
        body = load_catalogue(ds).get(name)
        calls.clear()
        out = propagate(body)
        n_inputs = len(out["sensitivities"]["obliquity_deg"])
        assert 10 <= n_inputs <= 12, (ds, name, n_inputs)
        assert len(calls) == 1 + 2 * n_inputs, (ds, name, len(calls))


# ----------------------------------------------------------------------------- linear vs Monte Carlo

def test_linear_agrees_with_monte_carlo():
    """Twelve uncertain inputs, small enough for the model to be linear over ±1σ: the sample std of
    1000 draws matches the linear σ within 10% (the std's sampling error is 1/sqrt(2·999) = 2.2%)."""
    body = load_catalogue("current").get("Vesta")
    mc = monte_carlo(body, 1000, 0, uncertainties=SYNTHETIC)
    assert mc["valid"] == 1000 and mc["rejected"] == 0
    assert mc["relative_standard_error"] == pytest.approx(0.0224, abs=1e-4)
    for key in SCALAR_KEYS:
        c = mc["comparison"][key]
        assert c["ratio"] == pytest.approx(1.0, abs=0.10), (key, c)
        assert abs(c["bias_sigma"]) < 0.2, (key, c)   # no nonlinear shift of the mean either
    lin = mc["linear"]
    for t_lin, t_mc in list(zip(lin["terms"], mc["terms"]))[:6]:
        for key in TERM_KEYS:
            assert t_mc[f"{key}_uncertainty"] == pytest.approx(t_lin[f"{key}_uncertainty"], rel=0.10), \
                (t_lin["multiple"], key)


def test_linear_agrees_with_monte_carlo_for_catalogue_sigmas():
    """The Eros pole (WGCCRE ±0.02°) is the catalogue's one non-trivial σ set: linear holds."""
    mc = monte_carlo("Eros", 1000, 0)
    for key in ("obliquity_deg", "precession_rate_arcsec_per_year", "delta_psi_half_peak_to_peak_arcsec"):
        assert mc["comparison"][key]["ratio"] == pytest.approx(1.0, abs=0.10)


def test_linear_fails_for_a_5_degree_pole_near_the_orbit_normal():
    """petit2014 Ceres: pole ±5° per coordinate, obliquity 3.9°. ε cannot go below 0 and the equinox
    (hence the Sin/Cos split of every term) turns with the pole: linear propagation is wrong here."""
    mc = monte_carlo(get_body("Ceres", "petit2014"), 1000, 0, order=4)
    c = mc["comparison"]
    assert c["precession_rate_arcsec_per_year"]["ratio"] > 1.3   # ψ̇ ∝ cos ε: curvature, not slope
    assert c["obliquity_deg"]["ratio"] < 0.9
    assert c["obliquity_deg"]["bias_sigma"] > 0.4                 # mean pushed up: ε is folded at 0
    k2_lin, k2_mc = mc["linear"]["terms"][1], mc["terms"][1]
    assert k2_mc["longitude_cos_arcsec_uncertainty"] < 0.6 * k2_lin["longitude_cos_arcsec_uncertainty"]


def test_the_poles_uncertainty_along_a_track_is_the_monte_carlo_one():
    """The pole's 1-σ at each epoch (ephem.forced.pole_uncertainty.pole_uncertainty, linear, the RMS angle) against a Monte
    Carlo of 400 catalogue Eros (pole RA and Dec σ 0.02°, here correlated at ρ = 0.5 to use the covariance): the
    RMS angle of the sampled poles from the nominal one, over a century. Budget: the RMS of N normal samples is
    known to 1/sqrt(2N) = 3.5 % (1σ); 4σ, 14 %. At the pole epoch it is the pole's own σ, sqrt(σ_ra² cos²δ +
    σ_dec²): the trace of the offset's covariance, which the correlation does not change (it tilts the error
    ellipse); to the central differences' 1e-3."""
    import dataclasses
    import math

    from ephem.forced.precession_nutation import build_model
    from ephem.forced.pole_uncertainty import pole_uncertainty

    b = get_body("eros")
    t = 2451545.0 + np.array([0.0, 18262.5, 36525.0])
    rho = {("pole.ra", "pole.dec"): 0.5}
    linear = pole_uncertainty(b, t, correlations=rho)
    sra = sdec = 0.02
    cov = np.array([[sra**2, 0.5 * sra * sdec], [0.5 * sra * sdec, sdec**2]])
    rng = np.random.default_rng(7)
    draws = rng.multivariate_normal([b.pole.ra_deg, b.pole.dec_deg], cov, size=400)

    def poles(body):
        tr = build_model(body).track(t)
        cd = np.cos(tr.pole_dec)
        return np.stack([cd * np.cos(tr.pole_ra), cd * np.sin(tr.pole_ra), np.sin(tr.pole_dec)], axis=-1)

    nominal = poles(b)
    angles = np.array([np.arccos(np.clip(np.sum(poles(dataclasses.replace(
        b, pole=dataclasses.replace(b.pole, ra_deg=ra, dec_deg=dec), values={})) * nominal, axis=-1), -1, 1))
        for ra, dec in draws])
    mc = np.sqrt(np.mean(angles**2, axis=0))
    assert linear == pytest.approx(mc, rel=0.14)
    cd = math.cos(math.radians(b.pole.dec_deg))
    own = math.radians(math.sqrt((sra * cd) ** 2 + sdec**2))
    assert linear[0] == pytest.approx(own, rel=1e-3)


# ----------------------------------------------------------------------------- moments from one polar moment

def _vesta_with_a_polar_moment_sigma(sigma_c: float):
    """Vesta as the catalogue has it, with a σ on Park et al. (2025)'s polar moment (none is published), its
    moments and their covariance derived as the loader derives them (ephem.bodies.inertia)."""
    from ephem.bodies.measured import Measured
    from ephem.bodies.inertia import derive

    vesta = get_body("vesta")
    keys = ("polar_moment", "J2", "C22", "S22")
    given = {k: vesta.values[f"inertia.derived_from.{k}"] for k in keys}
    d = derive("gravity_and_polar_moment", {k: m.value for k, m in given.items()},
               {k: (sigma_c if k == "polar_moment" else m.uncertainty) for k, m in given.items()})
    values = dict(vesta.values)
    for label, value, s in zip("ABC", d.moments, d.sigma):
        values[f"inertia.{label}"] = Measured(value, "", "park2025_vesta", s)
    return dataclasses.replace(vesta, values=values, correlations=d.correlations)


def test_moments_from_one_polar_moment_carry_its_error_once():
    """A, B and C from one C-bar (σ 0.003, hypothetical) and the gravity: their correlations (~1) make H_d's σ
    that of J2/C-bar, H_d σ_C/C (to the gravity's 1e-7 share), where independent moments of the same σ would
    give a σ five times larger; the precession rate's σ, linear, against 600 draws of C-bar and the gravity
    through the answers themselves (sampling error of a σ: 1/sqrt(2·599) = 2.9 %, 3 of them: 9 %)."""
    from ephem.bodies.inertia import moments_from_gravity

    sigma_c = 0.003
    body = _vesta_with_a_polar_moment_sigma(sigma_c)
    lin = propagate(body)
    hd = body.hd
    assert lin["dynamical_ellipticity_uncertainty"] == pytest.approx(hd * sigma_c / 0.4208, rel=1e-4)
    independent = propagate(body, correlations={pair: 0.0 for pair in body.correlations})
    assert independent["dynamical_ellipticity_uncertainty"] > 5.0 * lin["dynamical_ellipticity_uncertainty"]

    vesta = get_body("vesta")
    g = {k: vesta.values[f"inertia.derived_from.{k}"] for k in ("J2", "C22", "S22")}
    rng = np.random.default_rng(3)
    rates = []
    for _ in range(600):
        moments = moments_from_gravity(0.4208 + sigma_c * rng.standard_normal(),
                                       *(m.value + m.uncertainty * rng.standard_normal() for m in g.values()))
        sample = dataclasses.replace(vesta, moments=moments, values={}, correlations={})
        rates.append(api.precession(sample)["precession_rate_arcsec_per_year"])
    assert lin["precession_rate_arcsec_per_year_uncertainty"] == pytest.approx(np.std(rates, ddof=1), rel=0.09)
