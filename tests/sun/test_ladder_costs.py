"""The sun ladder's predicted costs (ephem.sun.ladder.Ladder.cost): they grow with what drives them (epochs, span,
eccentricity), the estimates' tables are charged until built, and the real orbit is charged from its elements'
epoch. Moved from tests/service/test_bounded_work.py (issue 43: the tests mirror the packages)."""
from __future__ import annotations

import pytest

from ephem import api
from ephem.bodies.catalogue import Body, Orbit, Pole
from ephem.theory import cost


def test_the_predicted_cost_grows_with_what_drives_it():
    from ephem.sun.ladder import Ladder

    from ephem.sun.bounds import cached_tables

    ladder = Ladder(Body("x", Orbit(2.36, 0.3, 7.0, 0.0, 0.0, 0.0, 2451545.0), Pole(10.0, 20.0), 5.0,
                             dynamical_ellipticity=0.1))
    t0 = 2451545.0
    # the estimates' tables are the first request's, once per body: charged until built, then not
    first = ladder.cost(None, t0, t0 + 3650, 100)
    assert any("tables" in p.what for p in first.parts)
    cached_tables(ladder.body)
    later = ladder.cost(None, t0, t0 + 3650, 100)
    assert not any("tables" in p.what for p in later.parts) and later.cpu_s < first.cpu_s
    small = ladder.cost("hansen", t0, t0 + 3650, 100)
    many = ladder.cost("hansen", t0, t0 + 3650, 100_000)
    assert many.cpu_s > 10 * small.cpu_s and many.memory_mb > 10 * small.memory_mb
    short = ladder.cost("numerical", t0, t0 + 365, 100)
    long = ladder.cost("numerical", t0, t0 + 36500, 100)
    assert long.cpu_s > 10 * short.cpu_s and long.largest().parameter == "stop"
    assert cost.harmonics(0.9, None)[1] > cost.harmonics(0.5, None)[1] > cost.harmonics(0.1, None)[1]


def test_the_real_orbit_is_charged_from_the_elements_epoch():
    """The orbit is integrated from its elements' epoch (ephem.orbit.de421): elements of 1900 for a track in
    2040 cost 140 years of integration, not the 40 from the pole epoch (J2000)."""
    import dataclasses

    from ephem.sun.ladder import Ladder

    vesta = api.resolve_body("vesta")
    t0, t1 = 2466154.5, 2466519.5                      # 2040-2041

    def path_years(body) -> float:
        part = next(p for p in Ladder(body).cost("real_orbit", t0, t1, 10).parts if p.what.startswith("the real orbit"))
        return float(part.what.split()[-2])

    # Vesta's elements are of 2025 and its pole of J2000: from J2000 to 2041 (the description prints 4 digits)
    assert path_years(vesta) == pytest.approx((t1 - 2451545.0) / 365.25, rel=1e-3)
    old_elements = dataclasses.replace(vesta, orbit=dataclasses.replace(vesta.orbit, epoch_jd_tdb=2415020.5))
    assert path_years(old_elements) == pytest.approx((t1 - 2415020.5) / 365.25, rel=1e-3)
