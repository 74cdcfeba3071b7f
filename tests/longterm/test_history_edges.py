"""A body of the user's own on an N-body orbit run on request, over short spans (issue 42's edges).

The run's samples are whole WHFast steps (5.5 d): they covered [-0.77, 0.77] of a [-1, 1]-year history, and the
epochs at its ends were 'outside the history's span' (a 422 naming an internal field, ``years``); a span within days
of J2000 (0 to 0.001 years, or -5e-324 to 4.2e-90) gave a run of no step at all (a 500: nothing to concatenate) or a
refusal naming ``start_years``, which the request does not have. The run now reaches past the span's ends, and is at
least eight steps long."""
from __future__ import annotations

import numpy as np
import pytest

from ephem import api
from ephem.bodies.catalogue import Body, Orbit, Pole
from ephem.longterm.history import MIN_NBODY_RUN_YEARS
from ephem.longterm.nbody_orbit import DT_DAYS, nbody_orbit_history

pytest.importorskip("rebound")

USER = Body("edge-user", Orbit(2.36, 0.089, 7.14, 103.7, 151.7, 169.2, 2460200.5), Pole(309.03, 42.23), 5.342,
            moments=(0.3433, 0.3546, 0.42))


@pytest.mark.parametrize("start, stop, step", [(-1.0, 1.0, 0.5), (-2.0, 2.0, 1.0), (-0.11, 0.005, 0.01),
                                               (0.0, 0.001, 0.0005), (-5e-324, 4.2e-90, 500.0),
                                               (0.0, 1e-322, 5e-324)])
def test_a_short_history_on_a_run_n_body_orbit_is_answered(start, stop, step):
    ans = api.history(USER, start, stop, step, orbit_model="nbody")
    assert ans["model"]["name"] == "nbody"
    assert ans["year"][0] == start and ans["year"][-1] <= stop
    for key in ("obliquity_deg", "pole_ra_deg", "pole_dec_deg", "estimated_error_deg"):
        assert np.all(np.isfinite(ans[key])), key


def test_the_run_covers_its_span_and_the_shortest_run_has_eight_steps():
    h = nbody_orbit_history(USER.orbit, -1.0, 1.0, 0.25)
    assert h.years[0] <= -1.0 and h.years[-1] >= 1.0           # whole steps reaching past the ends
    assert MIN_NBODY_RUN_YEARS == pytest.approx(8 * DT_DAYS / 365.25, rel=1e-12)
    short = nbody_orbit_history(USER.orbit, 0.0, MIN_NBODY_RUN_YEARS, MIN_NBODY_RUN_YEARS / 8.0)
    assert short.years.size >= 8
