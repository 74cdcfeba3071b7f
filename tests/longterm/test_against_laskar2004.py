"""The Earth's and Mars' obliquity over millions of years against Laskar et al. (2004): La2004 for the Earth (A&A
428, 261) and La2004 and La2003 for Mars (Icarus 170, 343), IMCCE's published solutions (data/laskar2004/, from
tools/derive_laskar2004.py).

Their solutions integrate the full orbital and spin equations with tides and core-mantle friction; ours is the
averaged spin equation along the shipped N-body orbit (no tides, no general relativity in the orbit). The budget of
each comparison is our own estimate (the envelope of the neighbouring solutions and the orbit's error, the answer's
``obliquity_error_deg``) plus, for Mars, the solutions' own precision, which their authors give as the difference
La2004 − La2003 (two solutions from initial precession rates 0.3 % apart, -7.597 and -7.576″/yr): Mars' obliquity is
chaotic. So Mars is compared from La2004's own starting rate: the catalogue's (Baland et al. 2020's H_D, from the
2016 measured rate) is 0.3 % above it, and over 3 Myr that input difference alone parts the solutions by more
than La2004 from La2003. La2004's rate in our model's terms (its definition of the precession constant is not
ours) is fitted on ±100 kyr, before chaos spreads anything (one parameter for 201 epochs: the fit's residual is
itself a test of the model); the tests then hold the fitted model to La2004 over millions of years."""
import numpy as np
import pytest

from ephem import api
from ephem.base.paths import data_dir
from ephem.longterm.averaged_spin import outward_max

SPANS = {"±100 kyr": (-1.0e5, 1.0e5), "past 1 Myr": (-1.0e6, 0.0), "past 3 Myr": (-3.0e6, 0.0),
         "next 1 Myr": (0.0, 1.0e6)}


def solution(name: str) -> tuple[np.ndarray, np.ndarray]:
    table = np.genfromtxt([line for line in (data_dir() / "laskar2004" / f"{name}.csv").read_text().splitlines()
                           if not line.startswith("#")], delimiter=",", names=True)
    return table["year"], table["obliquity_deg"]


#: the span La2004's Mars rate is fitted on (Julian years from J2000), before the solutions' chaos matters:
#: La2004 and La2003 (0.3 % apart in rate) part there by 0.05°
FIT_SPAN = (-1.0e5, 1.0e5)


def mars_at_la2004s_rate():
    """The catalogue's Mars with the H_D whose history fits La2004 best over :data:`FIT_SPAN` (the least
    largest difference, scanned in steps of 2e-5 of H_D and refined by a parabola through the best three)."""
    import dataclasses

    from ephem.bodies.catalogue import get_body

    years, la = solution("mars_la2004")
    m = (years >= FIT_SPAN[0]) & (years <= FIT_SPAN[1])
    mars = get_body("mars")

    def misfit(scale):
        b = dataclasses.replace(mars, dynamical_ellipticity=mars.hd * scale)
        ans = api.history(b, FIT_SPAN[0], FIT_SPAN[1], 1000.0)
        return float(np.sqrt(np.mean((np.asarray(ans["obliquity_deg"]) - la[m]) ** 2)))

    scales = 1.0 + np.arange(-0.006, 0.0021, 0.0004)
    costs = np.array([misfit(x) for x in scales])
    k = int(np.clip(np.argmin(costs), 1, len(scales) - 2))
    c2, c1, _ = np.polyfit(scales[k - 1:k + 2], costs[k - 1:k + 2], 2)
    best = -c1 / (2.0 * c2)
    return dataclasses.replace(mars, dynamical_ellipticity=mars.hd * best), best


@pytest.fixture(scope="module")
def fitted_mars():
    return mars_at_la2004s_rate()


@pytest.fixture(scope="module")
def histories(fitted_mars):
    return {"earth": api.history("earth", -3.0e6, 1.0e6, 1000.0),
            "mars": api.history(fitted_mars[0], -3.0e6, 1.0e6, 1000.0)}


def test_la2004s_mars_rate_is_below_the_measured_one(fitted_mars):
    """La2004 started from -7.597″/yr, before Konopliv et al. 2016 measured -7608.3 ± 2.1 mas/yr (the
    catalogue's H_D, Baland et al. 2020's, carries that): the fitted H_D must lie below the catalogue's, by more
    than the two rates' 0.15 % and less than 0.5 % (measured: 0.31 %; the definitions' difference, the geodesic
    term, is 0.09 %)."""
    _, scale = fitted_mars
    assert 0.995 < scale < 0.9985


@pytest.mark.parametrize("span", list(SPANS))
def test_the_earths_obliquity_is_la2004s_within_our_estimate(histories, span):
    """Measured: 0.0015° over ±100 kyr, 0.095° over the past Myr, 0.67° over 3 Myr, 0.09° over the next Myr; the
    estimate at each epoch covers the difference there (the envelope from J2000 outward; it counts the tides'
    change of α, which La2004 integrates, and a 1e-3 probe of the constant's unbounded change)."""
    years, la = solution("earth_la2004")
    ans = histories["earth"]
    assert np.allclose(ans["year"], years)
    lo, hi = SPANS[span]
    m = (years >= lo) & (years <= hi)
    diff = np.abs(np.asarray(ans["obliquity_deg"]) - la)
    assert np.all(diff[m] <= np.asarray(ans["obliquity_error_deg"])[m])


def test_the_earths_obliquity_range_over_the_last_million_years():
    """Laskar et al. 2004's 22.08-24.46° over the last Myr (data/long_term_references.toml), to the 0.1° our
    estimate gives there (measured: 22.077-24.457°)."""
    years, la = solution("earth_la2004")
    m = (years >= -1.0e6) & (years <= 0.0)
    ans = api.history("earth", -1.0e6, 0.0, 1000.0)
    ours = np.asarray(ans["obliquity_deg"])
    assert ours.min() == pytest.approx(la[m].min(), abs=0.1)
    assert ours.max() == pytest.approx(la[m].max(), abs=0.1)


@pytest.mark.parametrize("span", list(SPANS))
def test_mars_obliquity_is_la2004s_within_our_estimate_and_their_precision(histories, span):
    """Largest difference over the span against our estimate's largest plus La2004 − La2003's largest (both
    envelopes from J2000 outward), from La2004's rate. Measured: 0.0023° over ±100 kyr (estimate 0.03°), 0.85°
    over the past Myr (0.33° + 0.75°), 3.39° over 3 Myr (0.98° + 2.63°), 0.64° over the next Myr (0.32° + 0.76°)."""
    years, la04 = solution("mars_la2004")
    _, la03 = solution("mars_la2003")
    ans = histories["mars"]
    lo, hi = SPANS[span]
    m = (years >= lo) & (years <= hi)
    diff = np.abs(np.asarray(ans["obliquity_deg"]) - la04)
    precision = outward_max(years, 0.0, np.abs(la04 - la03))
    assert diff[m].max() <= np.asarray(ans["obliquity_error_deg"])[m].max() + precision[m].max()


def test_mars_obliquity_follows_la2004_closely_over_the_last_hundred_thousand_years(histories):
    """Before chaos spreads the solutions, one fitted constant reproduces La2004's 201 epochs over ±100 kyr to
    0.01°, a fifth of La2004 − La2003 there (0.05°), through the present 25.19° and the cycle's 19.7-29.4°."""
    years, la04 = solution("mars_la2004")
    ans = histories["mars"]
    m = np.abs(years) <= 1.0e5
    assert np.max(np.abs(np.asarray(ans["obliquity_deg"])[m] - la04[m])) < 0.01
