"""The physics terms of the error estimates: the real orbit (rung 6) against the fixed one (rung 5)."""
import dataclasses
import math

import numpy as np
import pytest

from ephem import api
from ephem.bodies.catalogue import get_body
from ephem.base.constants import JULIAN_YEAR_DAYS, MAS
from ephem.forced.precession_nutation import cached_model
from ephem.sun.ladder import Ladder
from ephem.theory.tracks import pole_vectors
from ephem.forced.integration import angular_separation, integrate_spin_axis
from ephem.forced.physics_errors import _table, measure_orbit_motion, orbit_motion_for

J2000 = 2451545.0
YEAR = JULIAN_YEAR_DAYS


def rung_gap(ladder, t, low="numerical", high="real_orbit", scale=False):
    return float(np.max(angular_separation(pole_vectors(ladder.track(low, t, rotation_scale=scale)),
                                           pole_vectors(ladder.track(high, t, rotation_scale=scale)))))


# ----------------------------------------------------------------------------- the pole gap against the real orbit

#: The population of issue 15: per body, spans from a day to 150 years placed at random inside the measured
#: window (both sides of the pole epoch; every third reaches across it, the others mostly do not), each sampled
#: at up to 1200 epochs on a jittered grid, off the whole days the table was sampled on; and the 30 days at
#: each end of DE421 past the window, where the estimate is extrapolated. The real orbit over 150 years is
#: the cost: the two integrations take 1-4 s per body, the asteroids' paths 5-8 s more (about 60 s in all).
SPANS_PER_BODY = 30
#: The catalogue's heliocentric bodies (petit2014's tables are made by the same code; its Itokawa, with the
#: largest gap of all, is held against the real orbit in test_the_rotation_scale_variants_gap_is_within_the_estimate).
POPULATION = [("current", b) for b in ("Ceres", "Vesta", "Eros", "Steins", "Itokawa", "Earth", "Mars")]


def _spans(body, rng) -> list[np.ndarray]:
    from ephem.orbit.de421 import de421_span

    lo, hi = orbit_motion_for(body).window
    t0 = body.pole.epoch_jd_tdb
    spans = []
    for i in range(SPANS_PER_BODY):
        length = min(10.0 ** rng.uniform(0.0, math.log10(150.0 * YEAR)), hi - lo)
        start = rng.uniform(max(lo, t0 - length), min(t0, hi - length)) if i % 3 == 0 else rng.uniform(lo, hi - length)
        count = int(min(1200, math.ceil(length / 0.25) + 1))
        step = length / (count - 1)
        epochs = start + step * (np.arange(count) + rng.uniform(-0.49, 0.49, count))
        spans.append(np.clip(epochs, start, start + length))
    edge_lo, edge_hi = de421_span()
    beyond = [np.linspace(hi, edge_hi - 0.5, 60), np.linspace(edge_lo + 0.5, lo, 60)]
    return spans, beyond


@pytest.fixture(scope="module")
def population():
    """Per body: [(epochs, gap between numerical and real_orbit at them, the numerical rung's estimate,
    inside the window, across the pole epoch)] for the spans of _spans. Both rungs are computed once over
    the union of the epochs (a rung's pole at an epoch does not depend on the other epochs asked for, to
    its integration error)."""
    rng = np.random.default_rng(15)
    out = {}
    for ds, name in POPULATION:
        body = get_body(name, ds)
        ladder = Ladder(body, axis="angular_momentum")
        spans, beyond = _spans(body, rng)
        union = np.unique(np.concatenate(spans + beyond))
        gap = angular_separation(pole_vectors(ladder.track("numerical", union)),
                                 pole_vectors(ladder.track("real_orbit", union)))
        rows = []
        for epochs, inside in [(e, True) for e in spans] + [(e, False) for e in beyond]:
            est = next(e for e in ladder.estimates(epochs) if e.rung == "numerical" and e.rotation_scale is None)
            across = epochs[0] <= body.pole.epoch_jd_tdb <= epochs[-1]
            rows.append((epochs, float(gap[np.searchsorted(union, epochs)].max()), est, inside, across))
        out[(ds, name)] = rows
    return out


def test_orbit_motion_bounds_the_real_orbit_on_random_spans(population):
    for (ds, name), rows in population.items():
        for epochs, gap, est, inside, across in rows:
            # the table bounds the exact gap; each of the two tracks here is within the integration term of
            # its exact solution (the numerical rung's term; real_orbit's is the same integration_bound)
            allowance = 2.0 * est.terms["integration"]
            assert gap <= est.terms["orbit_motion"] + allowance, (ds, name, epochs[0], epochs[-1], gap / MAS)


def test_orbit_motion_estimate_is_within_a_few_times_the_gap(population):
    ratio, length, across = [], [], []
    for rows in population.values():
        for epochs, gap, est, inside, through in rows:
            if inside:
                ratio.append(est.terms["orbit_motion"] / gap)
                length.append(epochs[-1] - epochs[0])
                across.append(through)
    ratio, length, across = np.array(ratio), np.array(length), np.array(across)
    assert across.any() and not across.all()
    # issue 15: the median within 3 (measured 1.005 over these 210 spans, 90% below 1.14: a span is charged
    # the largest gap of the bins it touches, a little more than its own largest gap) ...
    assert np.median(ratio) <= 3.0
    # ... and the worst within 10 for spans of 30 days or more (measured 1.37 here; over every daily start in
    # the window, at most 7.0 at 30 days, 9.9 at 15 days). The gap is the length of the difference of two
    # poles, which oscillates with the orbit's harmonics and passes close to zero now and then (Mars at
    # 1985.3: 0.013 mas, in a 90-day bin whose largest gap is 1.16 mas); a span of a few days in such a dip
    # is charged its bin's gap, so no table of bins bounds the ratio of the shortest spans: over every daily
    # start it exceeds 10 for 0.04-0.11% of the 1-day spans of Earth, Mars, Eros and petit2014's Itokawa
    # (worst 88, Mars) and for none of 30 days.
    assert ratio[length >= 30.0].max() <= 10.0
    short = ratio[length < 30.0]
    # so for the 59 shorter ones: few above 10 (measured here: none; the worst, 2.70, is a 0.9-day span of the
    # Earth's around t0 that reaches 0.4 day into the first bin, [0, 1] day, where the gap grows from zero)
    assert short.size >= 20 and np.mean(short > 10.0) <= 0.05


def test_the_rotation_scale_variants_gap_is_within_the_estimate():
    # the variants run both rungs from the mean pole: the Earth's Oppolzer start changes its gap most (0.56%
    # of the running maximum, measured), petit2014 Itokawa's semi-diurnal start moves furthest (29 mas)
    for body, phase, years in ((get_body("earth"), None, 10), (get_body("itokawa", "petit2014"), 0.7, 5)):
        ladder = Ladder(body, axis="angular_momentum", rotation_phase=phase)
        t = J2000 + np.linspace(-years * YEAR, years * YEAR, 1500)
        gap = rung_gap(ladder, t, scale=True)
        est = next(e for e in ladder.estimates(t) if e.rung == "numerical" and e.rotation_scale is not None)
        # each track is within the numerical rung's integration term of its exact solution
        assert gap <= est.terms["orbit_motion"] + 2.0 * est.terms["integration"]
        # a track sampled every 5 days (Earth), 2.4 days (Itokawa) against the table's daily bins: measured 0.988,
        # 0.997; a half would mean the variant's gap has left the table's
        assert gap >= 0.5 * est.terms["orbit_motion"]


def test_orbit_motion_beyond_the_window_grows_continuously_from_its_edge():
    from ephem.forced.physics_errors import gap_bound

    for name in ("Mars", "Earth", "Vesta", "Itokawa", "Eros"):
        body = get_body(name)
        om, model = orbit_motion_for(body), cached_model(body)
        for sign, ends, gaps in om.gap.sides():
            edge = model.pole_epoch + sign * ends[-1]
            past = [gap_bound(om, model, np.array([model.pole_epoch, edge + sign * d]))
                    for d in (0.0, 1e-4, 0.1, 1.0, 30.0, 10 * YEAR, 1000 * YEAR)]
            assert past[0] == pytest.approx(gaps.max(), rel=1e-12)     # the table's own value at the edge
            assert all(b >= a for a, b in zip(past, past[1:]))             # never below it, growing
            # continuous: 1e-4 day past the edge adds at most the two poles' speed times 1e-4 day
            # (K (a/q)³ ≤ 5e-5 rad/day for these bodies: 5e-9 rad)
            assert past[1] - past[0] <= 5e-9
            # the envelopes' growth, quadratic in time, takes over: 1000 years on, 170-3000 times the edge's
            assert past[-1] > 100.0 * past[0]


def test_the_fixed_orbit_error_is_real_and_large_for_asteroids():
    # Vesta's orbit plane turns ~4"/yr and Jupiter moves it along its orbit: over 1900-2050 the
    # fixed-orbit pole is off by more than an arcsecond (measured 1.5"), the theory error by < 0.1".
    ladder = Ladder(get_body("vesta"))
    t = J2000 + np.linspace(-100 * YEAR, 50 * YEAR, 1500)
    assert rung_gap(ladder, t) > 1000 * MAS
    assert rung_gap(ladder, t, "second_order", "numerical") < 1 * MAS


def test_orbit_motion_table_rederives_for_mars():
    body = get_body("mars")
    om = orbit_motion_for(body)
    fresh = measure_orbit_motion(body, cached_model(body), *om.window)
    for a, b in zip(om.normal + om.longitude + (om.torque_mismatch,),
                    fresh.normal + fresh.longitude + (fresh.torque_mismatch,)):
        # data/orbit_motion.toml prints ~6 significant digits (half a unit: <= 5e-5 relative for the
        # shortest); abs for the entries stored as 0
        assert a == pytest.approx(b, rel=1e-4, abs=1e-12)
    # printed rounded down to 1e-6 au
    assert fresh.real_perihelion_au - 1e-6 <= om.real_perihelion_au <= fresh.real_perihelion_au


def test_pole_gap_table_rederives_for_mars():
    from ephem.forced.physics_errors import GAP_DIGITS
    from tools.derive_orbit_motion import pole_gap       # as the tool measures it

    body = get_body("mars")
    om = orbit_motion_for(body)
    fresh, check = pole_gap(body, *om.window)
    assert check <= 1.0           # the allowance covers the peaks between daily samples (measured 0.23)
    for (sign, ends, shipped), (_, fresh_ends, gaps) in zip(om.gap.sides(), fresh.sides()):
        assert np.array_equal(ends, fresh_ends)        # whole days
        # printed in mas rounded up to GAP_DIGITS significant digits: up by less than one unit of the last,
        # < 10^(1 - GAP_DIGITS) of the value; 1e-12 for reading mas back into radians
        assert np.all(shipped >= gaps * (1.0 - 1e-12))
        assert np.all(shipped <= gaps * (1.0 + 10.0 ** (1 - GAP_DIGITS)))


def test_orbit_motion_table_covers_every_heliocentric_catalogue_body():
    from ephem.bodies.catalogue import load_catalogue
    from ephem.bodies.datasets import available_datasets
    for ds in available_datasets():
        for body in load_catalogue(ds).bodies:
            if body.orbit.center == "Sun":
                om = orbit_motion_for(body)
                assert om is not None and om.gap is not None, (ds, body.name)
                # measured for the catalogue's pole and K as they are now
                assert om.gap.describes(body, cached_model(body)), (ds, body.name)
    assert len(_table()) >= 14


def test_a_catalogue_body_given_another_h_d_falls_back_to_the_envelopes():
    from ephem.forced.physics_errors import envelope_bound, orbit_motion_bound

    body = dataclasses.replace(get_body("mars"), dynamical_ellipticity=0.0059)   # its moments give 0.00536
    model = cached_model(body)
    t = J2000 + np.linspace(0.0, 20 * YEAR, 200)
    assert not orbit_motion_for(body).gap.describes(body, model)   # the gap was measured for another K
    assert orbit_motion_bound(body, model, t) == pytest.approx(envelope_bound(orbit_motion_for(body), model, t),
                                                                 rel=1e-12)   # the same function's value


def test_real_orbit_code_path_reproduces_the_keplerian_rung_on_a_keplerian_sun():
    # feed the real-orbit integrator the model's own ellipse: it must give rung 5 back
    m = cached_model(get_body("vesta"))
    from ephem.forced.physics_errors import keplerian_sun_orbit_frame
    a = get_body("vesta").orbit.a_au

    def sun(t):
        lam, r = keplerian_sun_orbit_frame(m, np.array([t]))
        v = -a * r[0] * np.array([math.cos(lam[0]), math.sin(lam[0]), 0.0])  # Sun seen from the body
        x, y, z = m.icrf_from_orbit @ v
        return x, y, z

    t = m.pole_epoch + np.linspace(0.0, 8 * YEAR, 50)
    gap = angular_separation(integrate_spin_axis(m, t), integrate_spin_axis(m, t, sun=sun))
    assert np.max(gap) < 1e-4 * MAS


def test_real_orbit_outside_de421_is_unavailable_and_the_ladder_says_why():
    ladder = Ladder(get_body("vesta"))
    t = J2000 + np.linspace(0.0, 200 * YEAR, 10)
    real = next(e for e in ladder.estimates(t) if e.rung == "real_orbit")
    assert not real.available and "DE421" in real.why_not and "2053" in real.why_not
    inside = J2000 + np.linspace(0.0, 20 * YEAR, 10)
    assert next(e for e in ladder.estimates(inside) if e.rung == "real_orbit").available


def test_tight_tolerance_inside_de421_climbs_to_the_real_orbit():
    # Vesta 2000-2010: the fixed orbit's orbit_motion term (the measured gap to the real orbit) keeps every
    # fixed-orbit rung above 100 mas, so 100 mas climbs to the real orbit (0.13 mas); 1000 mas is met by a series.
    # (Mars, the earlier example here, now carries its liquid core's interior_rigid term in every rigid rung:
    # tests/sun/test_nonrigid_rung.py.)
    ans = api.track("vesta", "2000-01-01", "2010-01-01", 100.0, tolerance_mas=100.0, axis="angular_momentum")
    assert ans["model"]["name"] == "real_orbit"
    assert ans["model"]["estimated_error_mas"] < 1.0
    assert ans["model"]["error_terms_mas"]["integration"] < 0.01
    loose = api.track("vesta", "2000-01-01", "2010-01-01", 100.0, tolerance_mas=1000.0)
    assert loose["model"]["name"] in ("secular", "series", "hansen")


def test_a_users_body_reports_that_orbit_motion_was_not_estimated():
    body = dataclasses.replace(get_body("vesta"), name="my asteroid", dataset="user")
    ans = api.track(body, "2000-01-01", "2010-01-01", 50.0, tolerance_mas=100.0)
    assert "orbit_motion" not in ans["model"]["error_terms_mas"]
    assert any("never measured" in w for w in ans["model"]["warnings"])
