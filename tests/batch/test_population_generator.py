"""tools/generate_population.py: the synthetic population for `ephem batch` (docs/batch_input.md).

The script is loaded from tools/ as a module. Every statistical check states its budget: a sample mean is held to
4 standard errors (σ/√n, σ of the chosen law computed here by quadrature), so a correct generator fails one
check with probability ~6e-5 for a random seed; the seeds are fixed, so the outcome is reproducible anyway.
"""
import csv
import importlib.util
import math
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("generate_population", ROOT / "tools" / "generate_population.py")
gen = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(gen)

N = 2000
SEED = 20240519
ARCSEC_DEG = 1.0 / 3600.0


def population(count=N, seed=SEED, **kw) -> dict:
    """All rows of one population in a single dict of columns (the chunks joined)."""
    chunks = list(gen.generate(count, seed=seed, **kw))
    return {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}


@pytest.fixture(scope="module")
def pop():
    return population()


def _filled(col):
    return ~np.isnan(col)


def _law_moments(density, f):
    """Mean and standard deviation of f(x) when x = cos ε has the density c0 + c1 x + c2 x² on [-1, 1]."""
    c0, c1, c2 = density
    p = lambda x: c0 + c1 * x + c2 * x * x
    assert quad(p, -1.0, 1.0)[0] == pytest.approx(1.0, abs=1e-12)          # a density: integrates to 1
    mean = quad(lambda x: f(x) * p(x), -1.0, 1.0)[0]
    var = quad(lambda x: (f(x) - mean) ** 2 * p(x), -1.0, 1.0)[0]
    return mean, math.sqrt(var)


# ---------------------------------------------------------------------------------------------- columns
def test_columns_present_and_typed(pop):
    assert set(gen.COLUMNS) <= set(pop)
    assert len(gen.COLUMNS) == len(set(gen.COLUMNS))
    assert pop["name"].dtype == object and len(pop["name"]) == N
    assert all(re.fullmatch(r"SYN\d{7}", s) for s in pop["name"])
    assert list(pop["name"][:2]) == ["SYN0000001", "SYN0000002"] and pop["name"][-1] == f"SYN{N:07d}"
    assert len(set(pop["name"])) == N
    for c in gen.COLUMNS[1:]:
        assert pop[c].dtype == np.float64 and pop[c].shape == (N,), c
    # the required columns are filled on every row; the optional ones on some rows (all three forms present)
    for c in ["a_au", "e", "i_deg", "node_deg", "peri_deg", "mean_anomaly_deg", "epoch_jd_tdb",
              "pole_ra_deg", "pole_dec_deg", "rotation_period_hours"]:
        assert np.isfinite(pop[c]).all(), c
    for c in ["pole_epoch_jd_tdb", "dynamical_ellipticity", "moment_a", "axis_a_km", "pole_ra_deg_sigma",
              "rotation_period_hours_sigma", "dynamical_ellipticity_sigma"]:
        assert 0 < _filled(pop[c]).sum() < N, c


def test_the_csv_carries_every_value(pop, tmp_path):
    path = tmp_path / "pop.csv"
    assert gen.write_csv(path, gen.generate(N, seed=SEED)) == N
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    assert rows[0] == gen.COLUMNS and len(rows) == N + 1
    for j, c in enumerate(gen.COLUMNS[1:], start=1):
        text = [r[j] for r in rows[1:]]
        back = np.array([float(t) if t else np.nan for t in text])
        # repr is Python's shortest round-trip text: the values come back bit for bit, and empty for NaN
        np.testing.assert_array_equal(back, pop[c], err_msg=c)
    assert [r[0] for r in rows[1:]] == list(pop["name"])


def test_parquet_output(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    path = tmp_path / "pop.parquet"
    assert gen.main(["--count", "300", "--out", str(path), "--seed", "5"]) == 0
    table = pq.read_table(path)
    assert table.column_names == gen.COLUMNS and table.num_rows == 300
    ref = population(300, seed=5)
    for c in gen.COLUMNS[1:]:
        got = np.array([np.nan if v is None else v for v in table.column(c).to_pylist()], dtype=float)
        np.testing.assert_array_equal(got, ref[c], err_msg=c)          # empty fields are nulls


# ---------------------------------------------------------------------------------------------- validity
def test_every_row_is_a_valid_body(pop):
    a, e, i = pop["a_au"], pop["e"], pop["i_deg"]
    assert (a > 0).all() and ((e >= 0) & (e < 1)).all() and (a * (1 - e) > 0).all()
    assert ((i >= 0) & (i <= 180)).all()
    for c in ("node_deg", "peri_deg", "mean_anomaly_deg", "pole_ra_deg"):
        assert ((pop[c] >= 0) & (pop[c] < 360)).all(), c
    assert (np.abs(pop["pole_dec_deg"]) <= 90).all()
    assert (pop["epoch_jd_tdb"] == gen.EPOCH_JD).all()
    assert set(pop["pole_epoch_jd_tdb"][_filled(pop["pole_epoch_jd_tdb"])]) == {2451545.0}
    assert (pop["rotation_period_hours"] > 0).all()


def test_orbits_keep_to_their_class(pop):
    nea = pop["_is_nea"]
    a, e, i = pop["a_au"], pop["e"], pop["i_deg"]
    q, big_q = a * (1 - e), a * (1 + e)
    # NEAs: the NEO region q < 1.3 AU, Q >= 0.983 AU, and the generator's own bounds
    assert (q[nea] < 1.3).all() and (big_q[nea] >= 0.983).all() and (e[nea] <= 0.8).all() and (i[nea] < 60).all()
    assert ((a[nea] >= 0.8) & (a[nea] <= 3.0)).all()
    # the belt: within its edges, outside the three gaps, e < 0.3, i < 30°, q >= 1.3 AU
    belt = ~nea
    assert ((a[belt] >= 2.06) & (a[belt] <= 3.28)).all() and (e[belt] < 0.3).all() and (i[belt] < 30).all()
    assert (q[belt] >= 1.3).all()
    for gap in gen.KIRKWOOD_GAPS_AU:
        assert (np.abs(a[belt] - gap) >= gen.GAP_HALF_WIDTH_AU - 1e-12).all(), gap   # 1e-12 AU: rounding
    # the belt's means against the laws' (untruncated Rayleigh means 0.15 and 10°, truncated here): the
    # sample mean within 4 standard errors of the truncated law's mean, computed by quadrature
    for values, mean0, upper in ((i[belt], gen.BELT_I_MEAN_DEG, gen.BELT_I_MAX_DEG),):
        s = mean0 / math.sqrt(math.pi / 2)
        pdf = lambda x: x / s ** 2 * math.exp(-x * x / (2 * s * s))
        norm = quad(pdf, 0, upper)[0]
        mean = quad(lambda x: x * pdf(x), 0, upper)[0] / norm
        sd = math.sqrt(quad(lambda x: (x - mean) ** 2 * pdf(x), 0, upper)[0] / norm)
        assert abs(values.mean() - mean) < 4 * sd / math.sqrt(values.size), (values.mean(), mean)


def test_inertia_forms_are_valid_and_exclusive(pop):
    forms = np.stack([_filled(pop["dynamical_ellipticity"]), _filled(pop["moment_a"]), _filled(pop["axis_a_km"])])
    assert (forms.sum(axis=0) == 1).all()                    # each row exactly one of the three forms
    for group in (("moment_a", "moment_b", "moment_c"), ("axis_a_km", "axis_b_km", "axis_c_km")):
        filled = np.stack([_filled(pop[c]) for c in group])
        assert (filled.all(axis=0) == filled.any(axis=0)).all(), group      # a form's columns all or none
    hd = pop["dynamical_ellipticity"][forms[0]]
    assert ((hd > 0) & (hd <= 0.5)).all()
    m = np.stack([pop[c][forms[1]] for c in ("moment_a", "moment_b", "moment_c")])
    assert ((m[0] > 0) & (m[0] <= m[1]) & (m[1] <= m[2]) & (m[2] <= m[0] + m[1])).all()    # a rigid body's
    ax = np.stack([pop[c][forms[2]] for c in ("axis_a_km", "axis_b_km", "axis_c_km")])
    assert ((ax[0] >= ax[1]) & (ax[1] >= ax[2]) & (ax[2] > 0)).all()
    # the volume is the sphere's of the drawn diameter: a b c = (D/2)^3 to rounding (1e-12 relative)
    np.testing.assert_allclose(ax.prod(axis=0), (pop["_diameter_km"][forms[2]] / 2) ** 3, rtol=1e-12)
    # every form describes the same ellipsoid: H_d from the moments equals the drawn H_d (1e-14: rounding)
    np.testing.assert_allclose((m[2] - (m[0] + m[1]) / 2) / m[2], pop["_h_d"][forms[1]], rtol=1e-14)
    np.testing.assert_allclose(hd, pop["_h_d"][forms[0]], rtol=0)
    # the fractions of the three forms: binomial, each within 4σ = 4 sqrt(p(1-p)/N) (0.027 at p = 0.8)
    for row, p in zip(forms, (gen.FORM_FRACTIONS[k] for k in ("dynamical_ellipticity", "moments", "axes"))):
        assert abs(row.mean() - p) < 4 * math.sqrt(p * (1 - p) / N), (row.mean(), p)


def test_sigma_columns(pop):
    ra_s, dec_s, p_s, hd_s = (pop[c] for c in ("pole_ra_deg_sigma", "pole_dec_deg_sigma",
                                               "rotation_period_hours_sigma", "dynamical_ellipticity_sigma"))
    with_sigma = _filled(ra_s)
    assert (_filled(dec_s) == with_sigma).all() and (_filled(p_s) == with_sigma).all()
    assert ((ra_s[with_sigma] >= 2) & (ra_s[with_sigma] <= 10)).all()
    np.testing.assert_allclose(p_s[with_sigma], 1e-5 * pop["rotation_period_hours"][with_sigma], rtol=1e-15)
    assert (_filled(hd_s) == (with_sigma & _filled(pop["dynamical_ellipticity"]))).all()
    # binomial: the fraction within 4σ of 0.3 (4 sqrt(0.3 0.7 / 2000) = 0.041)
    assert abs(with_sigma.mean() - gen.SIGMA_FRACTION) < 4 * math.sqrt(0.3 * 0.7 / N)


def test_periods_respect_the_spin_barrier(pop):
    p, d = pop["rotation_period_hours"], pop["_diameter_km"]
    assert (p[d >= gen.SPIN_BARRIER_ABOVE_KM] >= gen.SPIN_BARRIER_H).all()
    # the bulk of the law: 55.5 % of a log-normal of median sqrt(40) h and σ 0.6 lies in 4-10 h, less the slow
    # rotators' 5 % of the bodies below 10 km (all of them but a few): expect 0.555 * 0.95 = 0.527, held to
    # 4 binomial σ (0.045) plus 0.01 for the part of the reflected tail (P < 2.2 h, 4 % of draws) landing in 4-10 h
    frac = ((p > 4) & (p < 10)).mean()
    assert abs(frac - 0.527) < 4 * math.sqrt(0.25 / N) + 0.01, frac


# ---------------------------------------------------------------------------------------------- poles
def test_poles_are_unit_vectors_at_the_drawn_obliquity(pop):
    vec = gen.pole_vectors_ecliptic(pop["i_deg"], pop["node_deg"], pop["_cos_obliquity"],
                                    np.linspace(0.0, 2 * math.pi, N))
    # unit vectors to rounding (a dozen operations of 1.1e-16 each)
    np.testing.assert_allclose(np.linalg.norm(vec, axis=1), 1.0, atol=1e-14)
    normal, _ = gen.orbit_frame(pop["i_deg"], pop["node_deg"])
    np.testing.assert_allclose(np.sum(vec * normal, axis=1), pop["_cos_obliquity"], atol=1e-14)


def test_the_written_pole_has_the_drawn_obliquity(pop):
    """RA/Dec back to the ecliptic by an independent rotation about x by ε0 = 84381.406″ (IAU 2006), then the
    angle to the orbit normal from i and Ω. Budget 2e-5° (0.072″): the generator's rotation (ERFA ecm06)
    also holds the ICRS frame bias, a rotation of 23 mas = 6.4e-6° (IERS Conventions 2010: ξ0 = -16.617,
    η0 = -6.819, dα0 = -14.6 mas), which this one leaves out; rounding adds ~1e-12°."""
    ra, dec = np.radians(pop["pole_ra_deg"]), np.radians(pop["pole_dec_deg"])
    icrf = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)
    eps0 = math.radians(84381.406 / 3600.0)
    to_ecliptic = np.array([[1, 0, 0], [0, math.cos(eps0), math.sin(eps0)], [0, -math.sin(eps0), math.cos(eps0)]])
    ecl = icrf @ to_ecliptic.T
    i, node = np.radians(pop["i_deg"]), np.radians(pop["node_deg"])
    normal = np.stack([np.sin(i) * np.sin(node), -np.sin(i) * np.cos(node), np.cos(i)], axis=-1)
    obliquity = np.degrees(np.arctan2(np.linalg.norm(np.cross(ecl, normal), axis=1), np.sum(ecl * normal, axis=1)))
    drawn = np.degrees(np.arccos(pop["_cos_obliquity"]))
    assert np.max(np.abs(obliquity - drawn)) < 2e-5


@pytest.mark.parametrize("nea_fraction,group", [(1.0, "nea"), (0.0, "belt_small")])
def test_obliquities_follow_the_chosen_law(nea_fraction, group):
    """The sample mean of ε, of cos ε and of cos² ε within 4 standard errors of the law's (quadrature), on
    4000 bodies of one class (the D < 30 km ones: the law's domain)."""
    p = population(4000, seed=SEED + 1, nea_fraction=nea_fraction)
    small = p["_diameter_km"] < gen.ISOTROPIC_ABOVE_KM
    x = p["_cos_obliquity"][small]
    assert x.size > 3900                                     # nearly all: D >= 30 km needs H < 11.4 at best
    density = gen.OBLIQUITY_DENSITY[group]
    for f, sample in ((lambda t: math.degrees(math.acos(t)), np.degrees(np.arccos(x))),
                      (lambda t: t, x), (lambda t: t * t, x * x)):
        mean, sd = _law_moments(density, f)
        assert abs(sample.mean() - mean) < 4 * sd / math.sqrt(x.size), (group, sample.mean(), mean)
    # and the shapes differ from isotropy where they should: E[cos² ε] = 0.547, not 1/3; NEAs 2:1 retrograde
    assert _law_moments(density, lambda t: t * t)[0] == pytest.approx(0.1 * 2 / 3 + 1.2 * 2 / 5)
    if group == "nea":
        assert quad(lambda t: density[0] + density[1] * t + density[2] * t * t, -1, 0)[0] == pytest.approx(2 / 3)
        retro = (x < 0).mean()                               # binomial: 4 sqrt((2/9) / 4000) = 0.030
        assert abs(retro - 2 / 3) < 4 * math.sqrt(2 / 9 / x.size)


def test_large_bodies_are_isotropic():
    """The isotropic branch (D >= 30 km) is rare in a population, so it is checked directly: mean cos ε = 0 and
    mean cos² ε = 1/3, each within 4 standard errors (σ = 1/√3 and 2/√45) of 20000 draws."""
    x = gen.sample_cos_obliquity(np.random.default_rng(3), 20000, gen.OBLIQUITY_DENSITY["isotropic"])
    assert abs(x.mean()) < 4 / math.sqrt(3) / math.sqrt(x.size)
    assert abs((x * x).mean() - 1 / 3) < 4 * (2 / math.sqrt(45)) / math.sqrt(x.size)


def test_the_cdf_inversion_is_exact():
    """The Newton-refined inverse gives back u: the drawn x has CDF(x) = u to 1e-13 (rounding of the cubic)."""
    c0, c1, c2 = gen.OBLIQUITY_DENSITY["nea"]
    rng = np.random.default_rng(9)
    u = np.random.default_rng(9).uniform(0.0, 1.0, 1000)      # the same stream the sampler draws first
    x = gen.sample_cos_obliquity(rng, 1000, (c0, c1, c2))
    cdf = c0 * (x + 1) + 0.5 * c1 * (x * x - 1) + c2 * (x ** 3 + 1) / 3
    np.testing.assert_allclose(cdf, u, atol=1e-13)


# ---------------------------------------------------------------------------------------------- fraction, seed
def test_nea_fraction_within_the_binomial_budget(pop):
    # each row an NEA with probability 0.05: the count is binomial, σ = sqrt(p(1-p)/N) = 0.0049 of the
    # fraction at N = 2000; held to 4σ
    p = 0.05
    assert abs(pop["_is_nea"].mean() - p) < 4 * math.sqrt(p * (1 - p) / N)
    half = population(N, seed=SEED + 2, nea_fraction=0.5)["_is_nea"].mean()
    assert abs(half - 0.5) < 4 * math.sqrt(0.25 / N)
    assert not population(200, nea_fraction=0.0)["_is_nea"].any()
    assert population(200, nea_fraction=1.0)["_is_nea"].all()


def test_reproducible_with_the_seed(pop, tmp_path):
    again = population()
    for c in gen.COLUMNS:
        np.testing.assert_array_equal(again[c], pop[c], err_msg=c)
    other = population(seed=SEED + 1)
    assert not np.array_equal(other["a_au"], pop["a_au"])
    # the file too, byte for byte, written through the command line
    paths = [tmp_path / "a.csv", tmp_path / "b.csv"]
    for path in paths:
        assert gen.main(["--count", "500", "--out", str(path), "--seed", "7"]) == 0
    assert paths[0].read_bytes() == paths[1].read_bytes()


def test_chunks_continue_the_rows():
    chunks = list(gen.generate(250, seed=1, chunk_rows=100))
    assert [len(c["name"]) for c in chunks] == [100, 100, 50]
    names = np.concatenate([c["name"] for c in chunks])
    assert list(names) == [f"SYN{k:07d}" for k in range(1, 251)]


# ---------------------------------------------------------------------------------------------- corrupt rows
def test_corrupt_rows_where_stated(pop):
    faults = gen.corrupt_rows(N, 4)
    assert faults == [(0, "e", 1.5), (666, "rotation_period_hours", -5.0), (1333, "pole_dec_deg", 120.0),
                      (1999, "a_au", -2.5)]
    bad = population(corrupt=4)
    for c in gen.COLUMNS[1:]:
        changed = set(np.flatnonzero(~((bad[c] == pop[c]) | (np.isnan(bad[c]) & np.isnan(pop[c])))))
        assert changed == {row for row, column, _ in faults if column == c}, c   # only the stated cells
    for row, column, value in faults:
        assert bad[column][row] == value
    assert gen.corrupt_rows(10, 1) == [(0, "e", 1.5)]
    assert [r for r, _, _ in gen.corrupt_rows(5, 5)] == [0, 1, 2, 3, 4]
    assert gen.corrupt_rows(N, 0) == []


def test_bad_arguments_are_refused(tmp_path, capsys):
    out = str(tmp_path / "x.csv")
    assert gen.main(["--count", "3", "--out", out, "--corrupt", "4"]) == 2
    assert "--corrupt" in capsys.readouterr().err
    assert gen.main(["--count", "3", "--out", out, "--nea-fraction", "1.5"]) == 2
    assert gen.main(["--count", "-1", "--out", out]) == 2
