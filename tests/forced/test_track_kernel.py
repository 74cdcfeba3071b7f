"""The track kernel (PrecessionNutation.track, track_grid, angles_grid) against the plain path.

The plain path is ``m.track_from_angles(t, *m.angles(t))``: numpy's cos and sin of M, ψ and ε and its arctan2 at
every epoch. The kernel computes the same quantities without a sin or cos per epoch (a table and Taylor series, ψ's
rotation folded into the frame matrix, atan's series for RA), choosing between paths from floats (a block's spread,
|v_z|, the size of M).

Budget: BUDGET = 1e-12 rad (0.2 µas) on every angle, the pole compared on the sky (their separation, and Dec): RA
alone is ill-conditioned near the celestial poles (1/cos Dec) in both paths alike. 1e-12 rad is below anything the
library reports (answers and tolerances in mas, the ladder's smallest error terms in µas) and about 500 times what
the kernel's rounding gives (measured: <= 2e-15 rad), so it allows another order of operations but no wrong
term, frame or branch (each would move the pole by far more). A Taylor term too few at the largest spread could hide
below it (δ⁵/120 at δ = 0.01 is 8e-13): tests/orbit/test_harmonics.py holds the series themselves to a few ulp.
On a grid the kernel's mean anomaly is exact in time while the plain path's comes from the rounded JDs: add the
nutation's fastest rate times 4 ulp of t (as tests/forced/test_kinoshita.py's grid test).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from ephem.api import model_for
from ephem.orbit.harmonic_grid import UniformHarmonics
from ephem.forced import precession_nutation as pn
from ephem.orbit import harmonics

BUDGET = 1e-12
BODIES = ["vesta", "ceres", "eros", "mars", "earth", "itokawa"]
TWO_PI = 2.0 * math.pi


def plain(m, t):
    t = np.asarray(t, dtype=float)
    return m.track_from_angles(t, *m.angles(t))


def vec(ra, dec):
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


def separation(a, b):
    """Angle between the two tracks' poles, well conditioned at any size."""
    return 2.0 * np.arcsin(0.5 * np.linalg.norm(vec(a.pole_ra, a.pole_dec) - vec(b.pole_ra, b.pole_dec), axis=-1))


def nutation_rate(m) -> float:
    """A bound on |dΔψ/dt| + |dΔε/dt| (rad/day)."""
    s = m.nutation
    k = s.multiple.astype(float)
    return m.mean_motion * float(np.sum(k * (np.hypot(s.lon_sin, s.lon_cos) + np.hypot(s.obl_sin, s.obl_cos))))


def assert_close(fast, ref, extra=0.0):
    assert np.shape(fast.pole_ra) == np.shape(ref.pole_ra)
    budget = BUDGET + extra
    for name in ("psi", "delta_psi", "delta_epsilon", "obliquity", "pole_dec"):
        a, b = np.asarray(getattr(fast, name)), np.asarray(getattr(ref, name))
        assert a.shape == b.shape, name
        if a.size:
            assert np.max(np.abs(a - b)) <= budget, (name, np.max(np.abs(a - b)))
    if np.size(fast.pole_ra):
        assert np.max(separation(fast, ref)) <= budget
        ra = np.asarray(fast.pole_ra)
        assert np.all((ra >= 0.0) & (ra < TWO_PI))


def grid_extra(m, t) -> float:
    return nutation_rate(m) * 4 * np.spacing(np.max(np.abs(t))) if np.size(t) else 0.0


def check_everywhere(m, t0, step, count, seed=0):
    """track_grid and angles_grid on the grid, track at its epochs sorted, shuffled and as a 2-D array."""
    grid = m.track_grid(t0, step, count)
    t = grid.jd_tdb
    ref = plain(m, t)
    extra = grid_extra(m, t)
    assert_close(grid, ref, extra)
    t_a, psi, dpsi, deps, eps = m.angles_grid(t0, step, count)
    assert np.array_equal(t_a, t) and np.array_equal(t, t0 + step * np.arange(count))   # the grid np.arange makes
    for got, want in zip((psi, dpsi, deps, eps), (ref.psi, ref.delta_psi, ref.delta_epsilon, ref.obliquity)):
        assert np.max(np.abs(got - want), initial=0.0) <= BUDGET + extra
    assert_close(m.track(t), ref)
    perm = np.random.default_rng(seed).permutation(count)
    shuffled = m.track(t[perm])
    assert_close(shuffled, plain(m, t[perm]))
    if count % 4 == 0 and count:
        assert_close(m.track(t.reshape(4, -1)), plain(m, t.reshape(4, -1)))


@pytest.mark.parametrize("body", BODIES)
def test_dense_twenty_years_as_the_benchmark(body):
    # 20 years at 0.02 d, several kernel blocks (Earth: the pole at Dec 89.97-89.999 deg, RA by arctan2 there)
    m = model_for(body)
    check_everywhere(m, m.pole_epoch, 20 * 365.25 / 365_000, 365_000)


@pytest.mark.parametrize("body", BODIES)
def test_sparse_and_long_spans(body):
    # 8000 years at 73 d: blocks whose ψ spreads beyond MAX_SHIFT (Itokawa's 6.6e-6 rad/day; the table path)
    m = model_for(body)
    check_everywhere(m, m.pole_epoch - 4000 * 365.25, 73.05, 40_000, seed=1)


@pytest.mark.parametrize("body", ["earth", "vesta"])
def test_mean_anomalies_beyond_the_table_reduction(body):
    # +-30 000 years: the Earth's M reaches 1.9e5 rad, beyond harmonics.REDUCE_LIMIT (1e5): numpy's cos and sin
    m = model_for(body)
    t = m.pole_epoch + np.linspace(-30_000, 30_000, 20_001) * 365.25
    assert body != "earth" or np.max(np.abs(m.mean_anomaly(t))) > harmonics.REDUCE_LIMIT
    assert_close(m.track(t), plain(m, t))
    check_everywhere(m, t[0], t[1] - t[0], t.size)


@pytest.mark.parametrize("count", [0, 1, 2, 3])
@pytest.mark.parametrize("body", ["vesta", "itokawa"])
def test_few_epochs(body, count):
    m = model_for(body)
    check_everywhere(m, m.pole_epoch + 0.25, 17.5, count)
    t = m.pole_epoch + 17.5 * np.arange(count)
    assert_close(m.track(list(t)), plain(m, t))


def test_a_single_epoch_as_a_scalar_keeps_its_shape():
    m = model_for("vesta")
    tr = m.track(2461000.5)
    assert np.shape(tr.pole_ra) == () and np.shape(tr.psi) == ()
    assert_close(tr, plain(m, 2461000.5))


@pytest.mark.parametrize("step", [1_000.0, 30_000.0])
@pytest.mark.parametrize("body", ["vesta", "itokawa", "earth"])
def test_large_steps(body, step):
    # consecutive epochs far apart: no Taylor shift holds across a block (the table path for ψ and ε, arctan2 for RA)
    m = model_for(body)
    check_everywhere(m, m.pole_epoch - 500 * step, step, 1000, seed=2)


def scaled_nutation(m, factor):
    s = m.nutation
    return dataclasses.replace(m, nutation=dataclasses.replace(
        s, lon_sin=s.lon_sin * factor, lon_cos=s.lon_cos * factor, obl_sin=s.obl_sin * factor,
        obl_cos=s.obl_cos * factor))


@pytest.mark.parametrize("step", [0.0005, 0.002, 0.01])
def test_a_nutation_beyond_max_shift(step):
    # Vesta's nutation x 3000: |Δψ| 0.08 rad (the old kernel's MAX_SHIFT gave up above 0.01 rad). Blocks of 16384
    # epochs spread below MAX_SHIFT at the smallest step, beyond it at the largest, and both ways by the orbit's
    # phase at 0.002 d: the Taylor shift and the table meet
    m = scaled_nutation(model_for("vesta"), 3000.0)
    assert np.max(np.abs(m.angles(m.pole_epoch + np.linspace(0, 1400, 2000))[1])) > 5 * harmonics.MAX_SHIFT
    check_everywhere(m, m.pole_epoch, step, 200_000, seed=3)


def aimed(m, t, ra, dec):
    """The model with its frame turned so that the pole at epoch t points to (ra, dec)."""
    ref = plain(m, np.array([t]))
    v, w = vec(ref.pole_ra[0], ref.pole_dec[0]), vec(ra, dec)
    axis = np.cross(v, w)
    s, c = np.linalg.norm(axis), float(np.dot(v, w))
    k = axis / s
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    q = np.eye(3) + s * kx + (1 - c) * kx @ kx          # Rodrigues: turns v onto w
    return dataclasses.replace(m, icrf_from_orbit=q @ m.icrf_from_orbit)


@pytest.mark.parametrize("body", ["vesta", "itokawa"])
def test_tracks_that_straddle_ra_zero(body):
    # the pole aimed at RA = 0 mid-span: the nutation (Vesta) or the precession (Itokawa) takes it to both sides
    base = model_for(body)
    t_mid = base.pole_epoch + 300.0
    m = aimed(base, t_mid, 0.0, math.radians(20.0))
    t0, step, count = t_mid - 700.0, 1400.0 / 200_000, 200_000
    check_everywhere(m, t0, step, count, seed=4)
    ra = m.track_grid(t0, step, count).pole_ra
    assert np.any(ra < 1e-3) and np.any(ra > TWO_PI - 1e-3)


@pytest.mark.parametrize("dec_deg", [90 - 1e-6, 90 - 1e-3, 89.0, 64.0, 64.2, -64.2, -89.0, -90 + 1e-3, -90 + 1e-6])
@pytest.mark.parametrize("body", ["vesta", "itokawa"])
def test_poles_near_the_celestial_poles(body, dec_deg):
    # Dec near +-90 deg: RA by arctan2 (its series' bound fails), Dec by atan2(z, hypot(x, y)); 64 deg brackets the
    # arcsin branch's |v_z| <= 0.9 (sin 64.16 deg)
    base = model_for(body)
    t_mid = base.pole_epoch + 100.0
    m = aimed(base, t_mid, 1.0, math.radians(dec_deg))
    check_everywhere(m, t_mid - 500.0, 1000.0 / 100_000, 100_000, seed=5)


def test_ra_a_hair_below_two_pi_is_zero():
    # atan2 gives -1.6e-16; + 2π rounds to 2π exactly: both paths return 0 (RA in [0, 2π))
    m = dataclasses.replace(model_for("vesta"), icrf_from_orbit=np.eye(3))
    psi = np.nextafter(math.pi / 2, 4.0) + np.zeros(5)   # RA = π/2 - ψ with the frame the identity
    eps = np.full(5, 0.4)
    ref = m.track_from_angles(np.zeros(5), psi, np.zeros(5), np.zeros(5), eps)
    assert np.all(ref.pole_ra == 0.0)
    ra, dec = np.empty(5), np.empty(5)
    m._pole_block(psi, eps, ra, dec, np.empty((pn._KERNEL_ROWS, 5)))
    assert np.all((ra >= 0.0) & (ra < TWO_PI)) and np.all(np.minimum(ra, TWO_PI - ra) <= 1e-15)


@pytest.mark.parametrize("dx", [0.0, 1e-17, -1e-17, 3e-16, -3e-16, 1e-9, -1e-9])
def test_the_ra_series_and_arctan2_agree_around_zero(dx):
    # _ra_into on the same vectors by atan's series (a small stray) and by arctan2 (stray unknown and large): a flip
    # between them changes RA by a few ulp of 2π; both in [0, 2π)
    y = dx + np.array([-2e-12, -1e-15, 0.0, -0.0, 1e-15, 2e-12])
    vx, vy = -np.ones(y.size), -y                         # the kernel hands _ra_into -x, -y
    series, direct = np.empty(y.size), np.empty(y.size)
    work = [np.empty(y.size) for _ in range(3)]
    pn._ra_into(vx, vy, y.size // 2, 1e-9, series, *work)
    pn._ra_into(vx, vy, y.size // 2, 1.0, direct, *work)
    for ra in (series, direct):
        assert np.all((ra >= 0.0) & (ra < TWO_PI))
        wrapped = np.mod(ra - np.arctan2(y, 1.0) + math.pi, TWO_PI) - math.pi
        assert np.max(np.abs(wrapped)) <= 4 * np.spacing(TWO_PI)


def test_the_dec_branches_agree_where_they_switch():
    # arcsin v_z and atan2(v_z, hypot(v_x, v_y)) at |v_z| = 0.9 +- 1e-12, the kernel's switch: a flip changes Dec by
    # a few ulp
    for z0 in (0.9, -0.9):
        z = z0 + np.linspace(-1e-12, 1e-12, 101)
        ra = np.linspace(0.0, TWO_PI, 101, endpoint=False)
        v = np.stack([np.sqrt(1 - z * z) * np.cos(ra), np.sqrt(1 - z * z) * np.sin(ra), z])
        a, b = np.arcsin(v[2]), np.arctan2(v[2], np.hypot(v[0], v[1]))
        assert np.max(np.abs(a - b)) <= 1e-15


def test_the_grid_kernel_and_the_any_epoch_kernel_take_different_paths():
    # the grid's harmonics come from UniformHarmonics (no cos M at all), the any-epoch ones from cos_sin_into's table:
    # the two kernels agree with each other as with the plain path, and the grid's beyond 48 harmonics (the old
    # grid path: uniform_cos_sin and HarmonicSums) as well
    m = model_for("vesta")
    s = m.nutation
    k = harmonics.MAX_POWER_BASIS_TERMS + 4
    pad = np.zeros(k - s.multiple.size)
    many = dataclasses.replace(m, nutation=dataclasses.replace(
        s, multiple=np.arange(1, k + 1), lon_sin=np.concatenate([s.lon_sin, pad]),
        lon_cos=np.concatenate([s.lon_cos, pad]), obl_sin=np.concatenate([s.obl_sin, pad]),
        obl_cos=np.concatenate([s.obl_cos, pad])))
    for model in (m, many):
        check_everywhere(model, m.pole_epoch, 0.05, 50_000, seed=6)
    a, b = m.track_grid(m.pole_epoch, 0.05, 50_000), many.track_grid(m.pole_epoch, 0.05, 50_000)
    assert np.max(separation(a, b)) <= BUDGET


def test_a_series_with_no_harmonics():
    # every term below the amplitude cut (NutationSeries with no harmonics): Δψ = Δε = 0 on both kernels
    m = model_for("vesta")
    empty = np.zeros(0)
    m = dataclasses.replace(m, nutation=dataclasses.replace(m.nutation, multiple=np.zeros(0, dtype=int),
                                                            lon_sin=empty, lon_cos=empty, obl_sin=empty, obl_cos=empty))
    check_everywhere(m, m.pole_epoch, 3.0, 20_000, seed=7)
    assert np.all(m.track_grid(m.pole_epoch, 3.0, 100).delta_psi == 0.0)


def test_ra_of_a_block_with_opposite_vectors():
    # unsorted epochs (no spread known: |u| measured) whose poles sit on both sides of the celestial pole, RA and
    # RA + π: u = tan(RA - RA_r) is small for both, so the series needs every dot product positive, or arctan2
    rng = np.random.default_rng(8)
    ra_true = np.where(rng.random(101) < 0.5, 1.0, 1.0 + math.pi) + rng.uniform(-1e-4, 1e-4, 101)
    vx, vy = -np.cos(ra_true), -np.sin(ra_true)           # negated, as the kernel hands them
    ra = np.empty(101)
    pn._ra_into(vx, vy, 50, None, ra, *[np.empty(101) for _ in range(3)])
    wrapped = np.mod(ra - ra_true + math.pi, TWO_PI) - math.pi
    assert np.max(np.abs(wrapped)) <= 4 * np.spacing(TWO_PI)


@pytest.mark.parametrize("kmax, count, span", [(1, 5000, 4096), (12, 2048, 16384), (12, 2049, 2048),
                                               (48, 9000, 4096), (0, 7, 2048)])
def test_the_grid_product_matches_direct_sums(kmax, count, span):
    # UniformHarmonics: rotated coefficients per sub-block of 2048 points times one shared table, filled span by
    # span as the kernel does (sub-blocks whole and cut): the direct sums in long double to the recurrence's
    # rounding plus the grid's phase rounding (as tests/orbit/test_harmonics.py's grid test)
    from tests.orbit.test_harmonics import direct_sums, rounding_bound
    rng = np.random.default_rng(kmax + count)
    sin_c, cos_c = rng.normal(size=(kmax, 2)), rng.normal(size=(kmax, 2))
    x0, dx = -1.234567, 0.0123
    grid = UniformHarmonics(x0, dx, sin_c, cos_c, count)
    out = np.full((2, count), np.nan)
    for start in range(0, count, span):
        grid.into(start, min(span, count - start), out[:, start:start + span])
    if kmax == 0:
        assert np.array_equal(out, np.zeros((2, count)))
        return
    x = np.longdouble(x0) + np.longdouble(dx) * np.arange(count, dtype=np.longdouble)
    direct = direct_sums(x, sin_c, cos_c)
    k = np.arange(1, kmax + 1)[:, None]
    phase = 4 * np.spacing(abs(x0) + dx * count) * (k * (np.abs(sin_c) + np.abs(cos_c))).sum(axis=0)
    for j in range(2):
        assert np.max(np.abs(out[j] - direct[:, j])) < rounding_bound(sin_c, cos_c) + phase[j]
