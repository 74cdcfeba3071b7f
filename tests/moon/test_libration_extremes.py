"""The nutation answer's half peak-to-peak σ and ρ of the Moon's librations (ephem.moon.family): kept per body and
cut once computed, and charged to the request's budget while they are not kept (0.06 s for the 57 terms of the
default cut, 0.8 s for the 795 terms of a 0.001-mas cut: once a process, not every answer)."""
import numpy as np
import pytest

from ephem import api
from ephem.base import budget
from ephem.base.budget import OverBudgetError
from ephem.base.constants import ARCSEC, J2000_JD, MAS
from ephem.bodies.catalogue import get_body
from ephem.moon import costs
from ephem.moon.family import EXTREMES_EPOCHS, HALF_PEAK_BLOCK, _extremes
from ephem.moon.model import LIBRATION_CUT, synchronous_model


def _all_at_once(series) -> tuple[float, float]:
    """An independent route: the series at every epoch in one evaluation, not in blocks."""
    rho, sigma, _ = series.angles(J2000_JD + np.arange(0.0, 6800.0, 0.25))
    return 0.5 * float(sigma.max() - sigma.min()), 0.5 * float(rho.max() - rho.min())


@pytest.mark.parametrize("cut_mas", [None, 10.0, 0.5])
def test_the_kept_extremes_are_the_series_over_a_node_period(cut_mas):
    moon = get_body("moon")
    cut = LIBRATION_CUT if cut_mas is None else cut_mas * MAS
    series = synchronous_model(moon).series.truncated(cut)
    expected = _all_at_once(series)
    _extremes.cache_clear()
    first = _extremes(moon, cut)
    again = _extremes(moon, cut)
    assert _extremes.cache_info().hits == 1
    # the blocks and the single evaluation take each epoch's sum alike but for BLAS's order: 1e-12 of the amplitude
    np.testing.assert_allclose(first, expected, rtol=1e-12)
    assert again == first
    if cut_mas is None:
        ans = api.nutation("moon")
        np.testing.assert_allclose([ans["delta_psi_half_peak_to_peak_arcsec"],
                                    ans["delta_epsilon_half_peak_to_peak_arcsec"]],
                                   np.array(expected) / ARCSEC, rtol=1e-12)


def test_the_extremes_are_charged_until_kept():
    moon = get_body("moon")
    terms = len(synchronous_model(moon).series.truncated(LIBRATION_CUT))
    part = costs.libration_extremes(terms, EXTREMES_EPOCHS, HALF_PEAK_BLOCK)
    assert part.cpu_s > 0.02          # 57 terms at 27,200 epochs, ~40 ns each
    _extremes.cache_clear()
    with budget.budget(cpu_s=0.5 * part.cpu_s, memory_mb=1e6):
        with pytest.raises(OverBudgetError):
            api.nutation("moon")
    assert not _extremes.cached(moon, LIBRATION_CUT)          # refused before the work
    api.nutation("moon")
    with budget.budget(cpu_s=0.5 * part.cpu_s, memory_mb=1e6) as b:
        api.nutation("moon")                                   # kept: the same budget holds
    assert b.spent_cpu_s < 0.5 * part.cpu_s


def test_each_cut_keeps_its_own_extremes():
    moon = get_body("moon")
    full = synchronous_model(moon).series
    _extremes.cache_clear()
    wide, narrow = _extremes(moon, 100 * MAS), _extremes(moon, LIBRATION_CUT)
    assert _extremes(moon, 100 * MAS) == wide and _extremes(moon, LIBRATION_CUT) == narrow
    assert wide != narrow                 # 27 terms against 57: the extremes of different sums
    np.testing.assert_allclose(wide, _all_at_once(full.truncated(100 * MAS)), rtol=1e-12)
