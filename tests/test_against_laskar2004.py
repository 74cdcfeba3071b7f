"""The Earth's and Mars' obliquity over millions of years against Laskar et al. (2004): La2004 for the Earth (A&A
428, 261) and La2004 and La2003 for Mars (Icarus 170, 343), IMCCE's published solutions (data/laskar2004/, from
tools/derive_laskar2004.py).

Their solutions integrate the full orbital and spin equations with tides and core-mantle friction; ours is the
averaged spin equation along the shipped N-body orbit (no tides, no general relativity in the orbit). The budget of
each comparison is our own estimate (the envelope of the neighbouring solutions and the orbit's error, the answer's
``obliquity_error_deg``) plus, for Mars, the solutions' own precision, which their authors give as the difference
La2004 − La2003 (two solutions from initial precession rates 0.3 % apart, -7.597 and -7.576″/yr): Mars' obliquity is
chaotic, and ours starts from a rate (the catalogue's moments) 0.2 % from La2004's."""
import numpy as np
import pytest

from ephem import api
from ephem.catalogue import data_dir
from ephem.spin_history import outward_max

SPANS = {"±100 kyr": (-1.0e5, 1.0e5), "past 1 Myr": (-1.0e6, 0.0), "past 3 Myr": (-3.0e6, 0.0),
         "next 1 Myr": (0.0, 1.0e6)}


def solution(name: str) -> tuple[np.ndarray, np.ndarray]:
    table = np.genfromtxt([line for line in (data_dir() / "laskar2004" / f"{name}.csv").read_text().splitlines()
                           if not line.startswith("#")], delimiter=",", names=True)
    return table["year"], table["obliquity_deg"]


@pytest.fixture(scope="module")
def histories():
    return {body: api.history(body, -3.0e6, 1.0e6, 1000.0) for body in ("earth", "mars")}


@pytest.mark.parametrize("span", list(SPANS))
def test_the_earths_obliquity_is_la2004s_within_our_estimate(histories, span):
    """Measured: 0.001° over ±100 kyr, 0.10° over the past Myr, 0.67° over 3 Myr, 0.09° over the next Myr; the
    estimate at each epoch covers the difference there (the envelope from J2000 outward)."""
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
    envelopes from J2000 outward). Measured: 0.003° over ±100 kyr (estimate 0.03°), 0.84° over the past Myr
    (0.32° + 0.75°), 3.4° over 3 Myr (0.95° + 2.6°), 0.64° over the next Myr (0.31° + 0.76°)."""
    years, la04 = solution("mars_la2004")
    _, la03 = solution("mars_la2003")
    ans = histories["mars"]
    lo, hi = SPANS[span]
    m = (years >= lo) & (years <= hi)
    diff = np.abs(np.asarray(ans["obliquity_deg"]) - la04)
    precision = outward_max(years, 0.0, np.abs(la04 - la03))
    assert diff[m].max() <= np.asarray(ans["obliquity_error_deg"])[m].max() + precision[m].max()


def test_mars_obliquity_follows_la2004_closely_over_the_last_hundred_thousand_years(histories):
    """Before chaos spreads the solutions: within 0.01° of La2004 over ±100 kyr (measured 0.003°; La2004 −
    La2003 there: 0.05°), through the present 25.19° and the cycle's 19.7-29.4° range."""
    years, la04 = solution("mars_la2004")
    ans = histories["mars"]
    m = np.abs(years) <= 1.0e5
    assert np.max(np.abs(np.asarray(ans["obliquity_deg"])[m] - la04[m])) < 0.01
