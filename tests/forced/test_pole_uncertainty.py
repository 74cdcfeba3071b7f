"""The pole's 1-σ along a track (ephem.forced.pole_uncertainty): the stepped models built once per body and evaluated
together at a request's epochs give the σ of the route they replace, the stepped models' own tracks (their kernel,
rebuilt for the question), and it is kept per body and order."""
import math

import numpy as np
import pytest

from ephem.bodies.catalogue import get_body
from ephem.forced import pole_uncertainty as pu
from ephem.forced.catalogue_sigmas import catalogue_inputs, correlation_matrix
from ephem.forced.precession_nutation import build_model
from ephem.forced.uncertainty import difference_step


def reference_sigma(b, t, order=None):
    """The independent route: every stepped body's model built and its track evaluated by the model's own kernel
    (PrecessionNutation.track), the central differences of the pole vectors, J Σ Jᵀ's trace."""
    inputs = catalogue_inputs(b, None)
    which = [j for j, i in enumerate(inputs) if i.sigma]
    x0 = np.array([i.value * i.factor for i in inputs])
    rho = correlation_matrix(inputs, None, b)

    def poles(x):
        tr = build_model(pu._perturbed_body(b, inputs, x), order).track(t)
        cd = np.cos(tr.pole_dec)
        return np.stack([cd * np.cos(tr.pole_ra), cd * np.sin(tr.pole_ra), np.sin(tr.pole_dec)], axis=-1)

    cols = []
    for j in which:
        h = difference_step(inputs[j], x0[j])
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        cols.append((poles(xp) - poles(xm)) / (2.0 * h))
    jac = np.stack(cols, axis=-1)
    s = np.array([inputs[j].sigma * inputs[j].factor for j in which])
    cov = s[:, None] * rho[np.ix_(which, which)] * s[None, :]
    return np.sqrt(np.einsum("eai,ij,eaj->e", jac, cov, jac))


@pytest.mark.parametrize("name, order", [("ceres", None), ("eros", None), ("eros", 3), ("vesta", None),
                                         ("mars", None), ("earth", 2)])
def test_the_stacked_evaluation_is_the_built_models_sigma(name, order):
    """Budget: the two routes evaluate the same tracks, the kernel within 2e-15 rad of the plain path the stacked one
    runs (tests/forced/test_track_kernel.py); a difference quotient turns that into 2e-15 / (2h) of the input's
    derivative and J Σ Jᵀ into <= 2e-15 * 50 * sqrt(inputs) rad of σ (h = σ/100): 1e-12 rad holds it with room, and
    is 1e-7 of the smallest σ compared here away from the pole epoch (Vesta's rate σ after a century: 7e-13 rad is
    not, so the test asks the absolute budget)."""
    b = get_body(name)
    t = b.pole.epoch_jd_tdb + np.linspace(-3.0 * 36525.0, 3.0 * 36525.0, 301)
    got = pu.pole_uncertainty(b, t, order=order)
    want = reference_sigma(b, t, order)
    assert got.shape == want.shape
    assert np.max(np.abs(got - want)) < 1e-12
    assert np.all(np.isfinite(got))


def test_blocks_join_and_the_body_is_kept():
    """More epochs than a block (1024) give the σ of each block alone; the stepped models are built once per body
    and order (a second question hits the cache) and a body without any σ has none."""
    b = get_body("eros")
    t = b.pole.epoch_jd_tdb + np.arange(9000) * 3.0
    whole = pu.pole_uncertainty(b, t)
    parts = np.concatenate([pu.pole_uncertainty(b, t[:5000]), pu.pole_uncertainty(b, t[5000:])])
    assert np.max(np.abs(whole - parts)) == pytest.approx(0.0, abs=1e-18)
    before = pu.cached_pole_sensitivity.cache_info().hits
    pu.pole_uncertainty(b, t[:10])
    assert pu.cached_pole_sensitivity.cache_info().hits == before + 1
    assert pu.pole_uncertainty(get_body("steins"), t[:10]) is None


def test_at_the_pole_epoch_it_is_the_poles_own_sigma():
    """At the pole epoch only the pole's own σ moves the pole: sqrt(σ_RA² cos²δ + σ_Dec²) (Ceres' pole has both), to
    the central differences' 1e-3."""
    b = get_body("ceres")
    sra, sdec = (b.values[k].uncertainty for k in ("pole.ra", "pole.dec"))
    cd = math.cos(math.radians(b.pole.dec_deg))
    own = math.radians(math.hypot(sra * cd, sdec))
    assert pu.pole_uncertainty(b, [b.pole.epoch_jd_tdb])[0] == pytest.approx(own, rel=1e-3)


def test_a_tracks_sigma_is_kept_per_epochs_and_handed_out_as_the_callers_own():
    """The σ of a track's epochs asked again is looked up (the kept entry's hits grow), equal to the stacked
    evaluation's to the bit (the same function of the same epochs), and each caller gets its own array: writing into
    one answer leaves the next unchanged. Other epochs of the same ends are another entry."""
    b = get_body("ceres")
    t = b.pole.epoch_jd_tdb + np.arange(37) * 10.0
    want = pu.cached_pole_sensitivity(b, None).sigma(t)
    first = pu.pole_uncertainty(b, t)
    hits = pu._cached_sigma.cache_info().hits
    first[:] = -1.0
    again = pu.pole_uncertainty(b, t)
    assert pu._cached_sigma.cache_info().hits == hits + 1
    assert np.array_equal(again, want)
    other = t.copy()
    other[1:-1] += 0.5
    assert not np.array_equal(pu.pole_uncertainty(b, other), want)
    assert np.array_equal(pu.pole_uncertainty(b, other), pu.cached_pole_sensitivity(b, None).sigma(other))


def test_bodies_that_differ_in_a_sigma_alone_do_not_share_the_kept_uncertainties():
    """A body's equality and hash leave its values (with their σ) out: the kept 1-σ key on the σ too
    (``Body.sigma_key``). Each body's kept answer equals the one given its σ explicitly (no cache)."""
    import dataclasses

    from ephem.forced.catalogue_sigmas import input_sigmas
    from ephem.forced.uncertainty import propagate, propagated

    vesta = get_body("vesta")
    values = dict(vesta.values)
    values["rotation.period"] = dataclasses.replace(values["rotation.period"],
                                                    uncertainty=10.0 * values["rotation.period"].uncertainty)
    wider = dataclasses.replace(vesta, values=values)
    assert wider == vesta and hash(wider) == hash(vesta)       # why the key needs the σ
    t = np.array([2451545.0, 2461000.5, 2470000.5])
    for b in (vesta, wider, vesta, wider):                     # each asked twice: the second from the caches
        sigmas = input_sigmas(b)
        kept = pu.pole_uncertainty(b, t)
        np.testing.assert_allclose(kept, pu.pole_uncertainty(b, t, uncertainties=sigmas), rtol=1e-12)
        rate = propagated(b, None)["precession_rate_arcsec_per_year_uncertainty"]
        explicit = propagate(b, uncertainties=sigmas, sensitivities=False)["precession_rate_arcsec_per_year_uncertainty"]
        assert rate == pytest.approx(explicit, rel=1e-12)
    # the period's σ moves the rate's σ in proportion (the only input of Vesta with one: 10x), but for the central
    # difference's step, σ/100, ten times longer: its O(step²) error measured 1.4e-4 of the derivative here
    ratio = propagated(wider, None)["precession_rate_arcsec_per_year_uncertainty"] / \
        propagated(vesta, None)["precession_rate_arcsec_per_year_uncertainty"]
    assert ratio == pytest.approx(10.0, rel=1e-3)
