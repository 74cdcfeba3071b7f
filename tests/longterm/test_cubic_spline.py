"""The orbit histories' spline (ephem.longterm.cubic_spline) is scipy's not-a-knot CubicSpline, without importing
scipy.interpolate: checked against scipy itself on the shipped orbits and on random irregular knots, and the shipped
orbits' table kept on disk gives back what is built."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicSpline as ScipySpline

from ephem.longterm import nbody_orbit
from ephem.longterm.cubic_spline import CubicSpline
from ephem.orbit.geometry import angle_between

#: the slopes come from the same system solved in another order (a doubling scan, not LAPACK's sweeps): on random
#: knots spaced 0.05 to 3 apart they agree to at most 3e-14 of the values' scale (measured), to 4e-16 on the even
#: ones of the shipped orbits
RELATIVE = 1e-12


@pytest.mark.parametrize("n", [4, 5, 6, 9, 64, 1001])
def test_random_irregular_knots_give_scipys_spline(n):
    rng = np.random.default_rng(n)
    x = np.cumsum(rng.uniform(0.05, 3.0, n)) - 7.0
    y = rng.normal(size=(n, 3)) * [1.0, 1e-3, 1e4]
    ours, theirs = CubicSpline(x, y), ScipySpline(x, y, axis=0)
    t = np.concatenate([np.linspace(x[0] - 2.0, x[-1] + 2.0, 997), x])   # beyond both ends, and on every knot
    assert np.all(np.abs(ours(t) - theirs(t)) <= RELATIVE * np.abs(theirs(t)).max(axis=0))
    assert np.all(np.abs(ours.c - theirs.c) <= RELATIVE * np.abs(theirs.c).max(axis=(0, 1)))
    np.testing.assert_allclose(ours(x), y, rtol=0.0, atol=RELATIVE * np.abs(y).max())     # through the data


def test_shapes_follow_scipys():
    x = np.arange(6.0)
    one, three = CubicSpline(x, x ** 2), CubicSpline(x, np.column_stack([x, x ** 2, x ** 3]))
    assert one(2.5).shape == () and one([1.0, 2.0]).shape == (2,) and one(np.zeros((2, 3))).shape == (2, 3)
    assert three(2.5).shape == (3,) and three([1.0, 2.0]).shape == (2, 3)
    assert one.c.shape == (4, 5) and three.c.shape == (4, 5, 3)
    t = np.array([[0.5, 1.5], [2.5, 5.5]])
    assert three(t, 2).shape == (2, 2) and three(t, slice(0, 2)).shape == (2, 2, 2)
    np.testing.assert_array_equal(three(t, 2), three(t)[..., 2])          # a column alone: the same arithmetic
    np.testing.assert_array_equal(three(t, slice(1, 3)), three(t)[..., 1:3])
    # a cubic is its own not-a-knot spline, beyond the knots too
    assert np.allclose(three(np.array([-1.5, 0.3, 4.9, 7.0])),
                       np.column_stack([t := np.array([-1.5, 0.3, 4.9, 7.0]), t ** 2, t ** 3]), rtol=1e-13, atol=1e-13)
    assert np.isnan(one(np.nan))


def test_bad_knots_are_refused():
    with pytest.raises(ValueError):
        CubicSpline([0.0, 1.0, 2.0], [0.0, 1.0, 2.0])           # three knots: scipy's parabola, not taken here
    with pytest.raises(ValueError):
        CubicSpline([0.0, 2.0, 1.0, 3.0], [0.0, 1.0, 2.0, 3.0])
    with pytest.raises(ValueError):
        CubicSpline([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0])


@pytest.mark.parametrize("body", nbody_orbit.SHIPPED_PLANETS + nbody_orbit.SHIPPED_ASTEROIDS)
def test_the_shipped_orbits_read_as_scipys_splines_of_their_samples(body):
    h = nbody_orbit.shipped_orbit_history(body)
    lo, hi = h.span_years
    t = np.linspace(lo, hi, 7919)
    pole = ScipySpline(h.years, h.pole, axis=0)(t)
    assert np.max(np.abs(h.pole_at(t) - pole / np.linalg.norm(pole, axis=-1, keepdims=True))) < 1e-14
    assert np.max(np.abs(h.semi_major_axis_at(t) - ScipySpline(h.years, h.a_au)(t))) < 1e-13 * np.max(h.a_au)
    assert np.max(np.abs(h.eccentricity_at(t) - ScipySpline(h.years, h.e)(t))) < 1e-14


def test_the_table_kept_on_disk_is_the_table_built(tmp_path, monkeypatch):
    """The first process builds the spline and the noise and writes them; the next reads them back, the same."""
    monkeypatch.setenv("EPHEM_CACHE_DIR", str(tmp_path))
    nbody_orbit._shipped_arrays.cache_clear()
    try:
        built = nbody_orbit._shipped_arrays("Ceres")
        assert list(tmp_path.glob("orbit_history_ceres-*.npz"))
        nbody_orbit._shipped_arrays.cache_clear()
        read = nbody_orbit._shipped_arrays("Ceres")
    finally:
        nbody_orbit._shipped_arrays.cache_clear()
    assert set(built) == set(read)
    for k in built:
        np.testing.assert_array_equal(built[k], read[k])
    h = nbody_orbit.shipped_orbit_history("Ceres")
    even = ScipySpline(h.years[::2], h.pole[::2], axis=0)(h.years[1:-1:2])
    even /= np.linalg.norm(even, axis=-1, keepdims=True)
    noise = 0.5 * np.max(angle_between(even, h.pole[1:-1:2]))
    assert float(read["sample_noise"]) == pytest.approx(noise, rel=1e-9)
