#!/usr/bin/env python3
"""Generate a synthetic population of asteroids in the batch input format (docs/batch_input.md).

    python tools/generate_population.py --count N --out FILE [--seed S] [--nea-fraction F] [--corrupt K]

One body a row, the columns of docs/batch_input.md, written as CSV (or Parquet when the output ends in
``.parquet`` and pyarrow is importable; without pyarrow a ``.parquet`` output is refused). The rows are made in
chunks of ``CHUNK_ROWS`` and written as they come, so memory stays bounded whatever N (10^6 rows take a few
seconds). Chunk k draws from ``numpy.random.default_rng([seed, k])``: the same seed gives the same file.

The population is realistic in the large, not a model of the real belt: each distribution below says where its
numbers come from, and where the choice is ours ("our choice") it says so.

Orbits (heliocentric osculating elements, ecliptic and equinox J2000, epoch ``EPOCH_JD`` = 2461000.5 TDB)
--------------------------------------------------------------------------------------------------------
* Main belt (a fraction 1 - F of the rows, F = --nea-fraction, each row an independent draw).
  - a: uniform over 2.06-3.28 AU with the three main Kirkwood gaps cut out (±``GAP_HALF_WIDTH_AU``, our choice):
    3:1 at 2.50, 5:2 at 2.82, 2:1 at 3.28 AU (the belt's edges and the gaps as given by the Oxford Dictionary
    of Astronomy, http://oxfordindex.oup.com/view/10.1093/oi/authority.20110803100038928 , and Britannica,
    http://www.britannica.com/print/topic/358582 : "semimajor axes between 2.06 and 3.28 AU"). The flat density
    between the gaps is our simplification of JPL's histogram (https://ssd.jpl.nasa.gov/diagrams/mb_hist.html).
  - e: Rayleigh with mean 0.15, i: Rayleigh with mean 10° ("The average inclination is about 10° and the
    average eccentricity is 0.15", Collins Dictionary of Astronomy,
    http://encyclopedia2.thefreedictionary.com/Main-belt+Asteroid ; Kirkwood (1888) already found a mean e of
    0.157 and a mean i of about 8°, https://bitlit.ru/page/en/daniel-kirkwood/the-asteroids-or-minor-planets-between-mars-and-jupiter/12 ).
    The Rayleigh shape is our choice. Draws are kept to e < 0.3 and i < 30° (the belt's usual bounds, "with
    eccentricities below about 0.3, and inclinations smaller than 30°",
    https://liquisearch.com/list_of_minor-planet_groups/the_asteroid_belt ) and to q = a(1 - e) >= 1.3 AU
    (else the orbit would be a near-Earth one); a draw outside is drawn again, which lowers the means a little
    (the truncated mean e is 0.142, i 9.9°).
* Near-Earth asteroids (a fraction F, default 0.05: our choice): the NEO region q < 1.3 AU and Q >= 0.983 AU
  (Bottke et al. 2002, Icarus 156, 399, https://freebook.uk/debiased-orbital-and-absolute-magnitude-distribution-of-the-near-earth-objects-n2i742 ;
  CNEOS' q < 1.3 au, https://near.earth/ ). a uniform in 0.8-3.0 AU, e uniform between the smallest value that
  gives q < 1.3 AU and Q >= 0.983 AU and 0.8, i Rayleigh with mean 13° kept below 60°: all our choice, a coarse
  stand-in for the debiased NEO model of Granvik et al. 2018 (https://ar5iv.labs.arxiv.org/html/1804.10265 ),
  whose numbers we did not take.
* The node, the argument of perihelion and the mean anomaly are uniform in [0°, 360°).

Sizes
-----
* Absolute magnitude H: cumulative N(<H) ∝ 10^(αH). Main belt: H in [11, 18], α = 0.51 for H < 15 and
  α = 0.30 for H >= 15 (Gladman et al. 2009, Icarus 202, 104, "On the asteroid belt's orbital and size
  distribution": α = 0.51 for H = 11-15 and the debiased α = 0.30 ± 0.02 for H_R = 15-18,
  https://fliphtml5.com/qcfn/beso/On_the_asteroid_belt%26%2339%3Bs_orbital_and_size_distribution/11/ ).
  NEAs: H in [17, 25] (the range of Granvik et al. 2018's model) with α = 0.30 (our choice: the small
  main-belt slope, not an NEA measurement).
* Geometric albedo p_V log-uniform in [0.05, 0.25] ("Most main-belt minor planets will have albedos in the
  range 0.05 to 0.25", MPC, http://web.archive.org/web/20101027093630/http:/www.minorplanetcenter.org/iau/lists/Sizes.html ;
  log-uniform is our choice), and D = 1329 km / sqrt(p_V) 10^(-H/5) (Pravec & Harris 2007, Icarus 190, 250,
  appendix A, as quoted at https://kiwix.lukehooper.xyz/content/astronomy.stackexchange.com_en_all_2024-10/questions/26017/good-source-for-the-relationship-between-absolute-magnitude-diameter-and-albed ).

Shapes and inertia
------------------
* Triaxial ellipsoid a >= b >= c with b/a uniform in [0.5, 0.95] and c/b uniform in [0.6, 0.95]: our choice,
  not a fitted statistic (Cibulková et al. 2016, A&A 596, A57, https://www.aanda.org/articles/aa/full_html/2016/12/aa29192-16/aa29192-16.html ,
  derive b/a distributions from survey photometry; we did not take their numbers). The volume is that of the
  sphere of diameter D: a b c = (D/2)^3.
* The inertia is written in one of the three forms of docs/batch_input.md, each row drawn independently:
  ``axis_a_km, axis_b_km, axis_c_km`` (fraction ``FORM_FRACTIONS['axes']`` = 0.8), ``dynamical_ellipticity``
  (0.1) or ``moment_a, moment_b, moment_c`` (0.1, normalised to C = 1). All three come from the same ellipsoid
  of uniform density (A = (b² + c²) m/5, ...), so H_d = (a² + b² - 2c²) / (2 (a² + b²)) whichever form a row
  carries; the columns of the other forms are left empty.

Spin
----
* Obliquity ε (angle between the spin pole and the orbit normal), drawn as x = cos ε from a quadratic density
  p(x) = c0 + c1 x + c2 x² on [-1, 1] (``OBLIQUITY_DENSITY``):
  - D >= 30 km: isotropic (c0 = 1/2). Large main-belt asteroids have a nearly isotropic pole distribution and
    small ones poles clustered toward the ecliptic poles, attributed to YORP (Hanuš et al. 2011, A&A 530, A134,
    https://doi.org/10.1051/0004-6361/201116738 , as summarised by Cibulková et al. 2016 above; Ďurech & Hanuš
    2023, A&A 675, A24, https://ar5iv.labs.arxiv.org/html/2305.10798 : "small asteroids have poles clustered
    toward ecliptic poles"). The 30 km boundary is our reading of Hanuš et al. 2011, not checked against the paper.
  - Main belt, D < 30 km: c0 = 0.1, c1 = 0, c2 = 1.2, thirteen times denser at the poles than in the orbit plane
    (the coefficients are our choice; mean ε = 90°).
  - NEAs: c0 = 0.1, c1 = -1/3, c2 = 1.2: the same excess of extreme obliquities with two retrograde rotators
    for one prograde, the shape Tardioli et al. 2017 (A&A 608, A61,
    https://www.aanda.org/component/article?access=doi&doi=10.1051/0004-6361/201731338 ) found best for NEAs
    ("a quadratic function ... favors extreme obliquities ... a 2:1 ratio between retrograde and direct
    rotators"); their coefficients were not taken, ours give the 2:1 ratio exactly (mean cos ε = -2/9).
  The azimuth of the pole about the orbit normal (from the ascending node) is uniform. The pole vector
  s = cos ε n + sin ε (cos φ u + sin φ (n × u)), with n the orbit normal and u the ascending node (both ecliptic
  J2000), is turned to the ICRF by ``ephem.orbit.geometry.icrf_to_ecliptic_matrix`` (ERFA's ecm06 at J2000: the IAU
  2006 obliquity ε0 = 84381.406″ with the ICRS frame bias, ~0.02″), the rotation the library uses to compute
  the obliquity back, so a row's obliquity is what ``ephem`` will find. ``pole_epoch_jd_tdb`` is 2451545.0 in
  half the rows and left empty (its default) in the others.
* Sidereal rotation period: log-normal with median 6.32 h (the geometric middle of 4-10 h) and σ(ln P) = 0.6,
  so 56 % of the periods fall in 4-10 h ("Most minor planets have rotation periods that are greater than about
  2.2 hours with the majority being between 4 and 10 hours", MPC, http://www.minorplanetcenter.net/light_curve ;
  Warner et al. 2009, Icarus 202, 134). "There is an excess of slow rotators among smaller minor planets"
  (same page): a fraction 0.05 of the bodies with D < 10 km instead get a period log-uniform in 30-500 h
  (numbers our choice). "Objects spinning faster than about 2.2 hours must be strength-bound" (same page):
  for D >= 0.2 km a period below 2.2 h is reflected to 2.2² / P (above the barrier); below 0.2 km (the size
  under which fast rotators are found: our recollection of Pravec & Harris 2000, not checked) it is kept.

Uncertainties
-------------
A fraction 0.3 of the rows (our choice) carry 1-sigma columns: ``pole_ra_deg_sigma`` and
``pole_dec_deg_sigma`` uniform in 2-10°, ``rotation_period_hours_sigma`` = 1e-5 P and, on rows with the
ellipticity form, ``dynamical_ellipticity_sigma`` = 0.1 H_d. The other rows leave them empty.

Names: ``SYN0000001``, ``SYN0000002``, ... (row number from 1, seven digits or more).

Corrupt rows (``--corrupt K``)
------------------------------
K rows get one bad value each, for tests of the batch reader's error handling. The rows are
``corrupt_rows(count, K)``: the row numbers round(j (N - 1) / (K - 1)) for j = 0 .. K-1 (0-based; K = 1 gives
row 0), and the j-th takes the j-th fault of ``CORRUPTIONS`` in turn:
  0. ``e`` = 1.5 (not a bound orbit)
  1. ``rotation_period_hours`` = -5.0 (negative period)
  2. ``pole_dec_deg`` = 120.0 (declination beyond 90°)
  3. ``a_au`` = -2.5 (negative semi-major axis)
Every other value of such a row is left as drawn.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Iterator

import numpy as np

from ephem.orbit.geometry import icrf_to_ecliptic_matrix

EPOCH_JD = 2461000.5                       # JD TDB of every row's osculating elements
J2000_JD = 2451545.0
CHUNK_ROWS = 100_000

# Main belt: edges and Kirkwood gaps (AU), see the module docstring
BELT_EDGES_AU = (2.06, 3.28)
KIRKWOOD_GAPS_AU = (2.50, 2.82, 3.28)
GAP_HALF_WIDTH_AU = 0.02
BELT_E_MEAN, BELT_E_MAX = 0.15, 0.30
BELT_I_MEAN_DEG, BELT_I_MAX_DEG = 10.0, 30.0
NEO_Q_MAX_AU, NEO_BIG_Q_MIN_AU = 1.3, 0.983
NEA_A_RANGE_AU = (0.8, 3.0)
NEA_E_MAX = 0.8
NEA_I_MEAN_DEG, NEA_I_MAX_DEG = 13.0, 60.0

# H distributions: (H_min, H_break, H_max, alpha below the break, alpha above)
BELT_H = (11.0, 15.0, 18.0, 0.51, 0.30)
NEA_H = (17.0, 25.0, 25.0, 0.30, 0.30)
ALBEDO_RANGE = (0.05, 0.25)
DIAMETER_CONSTANT_KM = 1329.0

B_OVER_A = (0.5, 0.95)
C_OVER_B = (0.6, 0.95)
FORM_FRACTIONS = {"axes": 0.8, "dynamical_ellipticity": 0.1, "moments": 0.1}

# p(cos ε) = c0 + c1 x + c2 x² on [-1, 1]; each integrates to 1
OBLIQUITY_DENSITY = {
    "isotropic": (0.5, 0.0, 0.0),
    "belt_small": (0.1, 0.0, 1.2),
    "nea": (0.1, -1.0 / 3.0, 1.2),
}
ISOTROPIC_ABOVE_KM = 30.0

PERIOD_MEDIAN_H, PERIOD_SIGMA_LN = math.sqrt(4.0 * 10.0), 0.6
SLOW_FRACTION, SLOW_BELOW_KM, SLOW_RANGE_H = 0.05, 10.0, (30.0, 500.0)
SPIN_BARRIER_H, SPIN_BARRIER_ABOVE_KM = 2.2, 0.2

SIGMA_FRACTION = 0.3
POLE_SIGMA_DEG = (2.0, 10.0)
PERIOD_SIGMA_RELATIVE = 1e-5
ELLIPTICITY_SIGMA_RELATIVE = 0.1

CORRUPTIONS = (("e", 1.5), ("rotation_period_hours", -5.0), ("pole_dec_deg", 120.0), ("a_au", -2.5))

ORBIT_COLUMNS = ["a_au", "e", "i_deg", "node_deg", "peri_deg", "mean_anomaly_deg", "epoch_jd_tdb"]
COLUMNS = (["name", *ORBIT_COLUMNS, "pole_ra_deg", "pole_dec_deg", "pole_epoch_jd_tdb", "rotation_period_hours",
            "dynamical_ellipticity", "moment_a", "moment_b", "moment_c", "axis_a_km", "axis_b_km", "axis_c_km",
            "pole_ra_deg_sigma", "pole_dec_deg_sigma", "rotation_period_hours_sigma",
            "dynamical_ellipticity_sigma"])


# ---------------------------------------------------------------------------------------------- orbits
def _rayleigh_truncated(rng: np.random.Generator, n: int, mean: float, upper: float) -> np.ndarray:
    """n draws of a Rayleigh law of the given (untruncated) mean, redrawn until below ``upper``."""
    scale = mean / math.sqrt(math.pi / 2.0)            # the Rayleigh mean is σ sqrt(π/2)
    out = rng.rayleigh(scale, n)
    bad = out >= upper
    while bad.any():
        out[bad] = rng.rayleigh(scale, int(bad.sum()))
        bad = out >= upper
    return out


def _belt_semi_major_axes(rng: np.random.Generator, n: int) -> np.ndarray:
    """a (AU) uniform over the belt with the Kirkwood gaps cut out: one uniform draw over the total allowed
    length, mapped onto the allowed intervals."""
    lo, hi = BELT_EDGES_AU
    cuts = [lo]
    for gap in KIRKWOOD_GAPS_AU:
        cuts += [gap - GAP_HALF_WIDTH_AU, gap + GAP_HALF_WIDTH_AU]
    cuts.append(hi)
    intervals = [(a, b) for a, b in zip(cuts[::2], cuts[1::2]) if b > a]   # (lo, 2.48), (2.52, 2.80), ...
    lengths = np.array([b - a for a, b in intervals])
    u = rng.uniform(0.0, lengths.sum(), n)
    ends = np.cumsum(lengths)
    k = np.searchsorted(ends, u, side="right").clip(max=len(intervals) - 1)
    starts = np.array([a for a, _ in intervals])
    return starts[k] + (u - (ends[k] - lengths[k]))


def main_belt_orbits(rng: np.random.Generator, n: int) -> dict[str, np.ndarray]:
    """a (AU), e, i (deg) of n main-belt orbits: Rayleigh e and i, truncated, with q >= 1.3 AU."""
    a = _belt_semi_major_axes(rng, n)
    e = _rayleigh_truncated(rng, n, BELT_E_MEAN, BELT_E_MAX)
    bad = a * (1.0 - e) < NEO_Q_MAX_AU                 # would be a near-Earth orbit: draw e again
    while bad.any():
        e[bad] = _rayleigh_truncated(rng, int(bad.sum()), BELT_E_MEAN, BELT_E_MAX)
        bad = a * (1.0 - e) < NEO_Q_MAX_AU
    i = _rayleigh_truncated(rng, n, BELT_I_MEAN_DEG, BELT_I_MAX_DEG)
    return {"a_au": a, "e": e, "i_deg": i}


def nea_orbits(rng: np.random.Generator, n: int) -> dict[str, np.ndarray]:
    """a (AU), e, i (deg) of n near-Earth orbits: q < 1.3 AU, Q >= 0.983 AU, e <= 0.8."""
    a = rng.uniform(*NEA_A_RANGE_AU, n)
    # q < 1.3 needs e > 1 - 1.3/a; Q >= 0.983 needs e >= 0.983/a - 1 (binding for a < 0.983 AU)
    e_min = np.maximum.reduce([np.zeros(n), 1.0 - NEO_Q_MAX_AU / a, NEO_BIG_Q_MIN_AU / a - 1.0])
    e = rng.uniform(e_min, NEA_E_MAX)
    i = _rayleigh_truncated(rng, n, NEA_I_MEAN_DEG, NEA_I_MAX_DEG)
    return {"a_au": a, "e": e, "i_deg": i}


# ---------------------------------------------------------------------------------------------- sizes
def absolute_magnitudes(rng: np.random.Generator, n: int, law: tuple) -> np.ndarray:
    """H from a broken power law N(<H) ∝ 10^(αH) (``law`` = H_min, H_break, H_max, α1, α2), by inverting
    the cumulative number in closed form on each side of the break."""
    h0, hb, h1, a1, a2 = law
    n1 = 10.0 ** (a1 * (hb - h0)) - 1.0                      # relative numbers below and above the break
    n2 = 10.0 ** (a1 * (hb - h0)) * (10.0 ** (a2 * (h1 - hb)) - 1.0) if h1 > hb else 0.0
    u = rng.uniform(0.0, n1 + n2, n)
    below = u < n1
    h = np.empty(n)
    h[below] = h0 + np.log10(1.0 + u[below]) / a1
    h[~below] = hb + np.log10(1.0 + (u[~below] - n1) / 10.0 ** (a1 * (hb - h0))) / a2
    return h


def diameters_km(rng: np.random.Generator, h: np.ndarray) -> np.ndarray:
    """D (km) = 1329 / sqrt(p_V) 10^(-H/5), p_V log-uniform in ``ALBEDO_RANGE``."""
    p = np.exp(rng.uniform(*np.log(ALBEDO_RANGE), h.size))
    return DIAMETER_CONSTANT_KM / np.sqrt(p) * 10.0 ** (-h / 5.0)


def ellipsoid_axes_km(rng: np.random.Generator, d_km: np.ndarray) -> np.ndarray:
    """Semi-axes a >= b >= c (km, shape (n, 3)) of the ellipsoid of the sphere's volume (a b c = (D/2)^3)."""
    q1 = rng.uniform(*B_OVER_A, d_km.size)
    q2 = rng.uniform(*C_OVER_B, d_km.size)
    a = 0.5 * d_km / np.cbrt(q1 * q1 * q2)
    return np.stack([a, q1 * a, q1 * q2 * a], axis=-1)


def ellipsoid_moments(axes: np.ndarray) -> np.ndarray:
    """Principal moments A <= B <= C of uniform ellipsoids, normalised to C = 1: A ∝ b² + c², B ∝ a² + c²,
    C ∝ a² + b² (the mass and the 1/5 cancel)."""
    sq = axes * axes
    m = np.stack([sq[:, 1] + sq[:, 2], sq[:, 0] + sq[:, 2], sq[:, 0] + sq[:, 1]], axis=-1)
    return m / m[:, 2:3]


def dynamical_ellipticity(moments: np.ndarray) -> np.ndarray:
    """H_d = (C - (A + B)/2) / C."""
    return (moments[:, 2] - 0.5 * (moments[:, 0] + moments[:, 1])) / moments[:, 2]


# ---------------------------------------------------------------------------------------------- spin
def sample_cos_obliquity(rng: np.random.Generator, n: int, density: tuple[float, float, float]) -> np.ndarray:
    """x = cos ε from p(x) = c0 + c1 x + c2 x² on [-1, 1], by inverting the cubic CDF: a start from a tabulated
    inverse, then Newton steps (p > 0, so the CDF is strictly increasing and Newton converges)."""
    c0, c1, c2 = density
    cdf = lambda x: c0 * (x + 1.0) + 0.5 * c1 * (x * x - 1.0) + c2 * (x ** 3 + 1.0) / 3.0
    pdf = lambda x: c0 + c1 * x + c2 * x * x
    grid = np.linspace(-1.0, 1.0, 2049)
    u = rng.uniform(0.0, 1.0, n)
    x = np.interp(u, cdf(grid), grid)
    for _ in range(3):
        x = np.clip(x - (cdf(x) - u) / pdf(x), -1.0, 1.0)
    return x


def orbit_frame(i_deg: np.ndarray, node_deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Ecliptic-J2000 unit vectors (n, 3) of the orbit normal and the ascending node."""
    i, node = np.radians(i_deg), np.radians(node_deg)
    normal = np.stack([np.sin(i) * np.sin(node), -np.sin(i) * np.cos(node), np.cos(i)], axis=-1)
    ascending = np.stack([np.cos(node), np.sin(node), np.zeros_like(node)], axis=-1)
    return normal, ascending


def pole_vectors_ecliptic(i_deg, node_deg, cos_obliquity, azimuth_rad) -> np.ndarray:
    """Spin poles (ecliptic J2000 unit vectors) at obliquity arccos(cos_obliquity) from the orbit normal and at
    ``azimuth_rad`` about it, counted from the ascending node."""
    normal, u = orbit_frame(i_deg, node_deg)
    v = np.cross(normal, u)
    sin_obl = np.sqrt(np.clip(1.0 - cos_obliquity ** 2, 0.0, None))
    return (cos_obliquity[:, None] * normal
            + (sin_obl * np.cos(azimuth_rad))[:, None] * u + (sin_obl * np.sin(azimuth_rad))[:, None] * v)


def ecliptic_to_radec_deg(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ICRF right ascension in [0, 360) and declination (deg) of ecliptic-J2000 unit vectors (n, 3)."""
    icrf = vectors @ icrf_to_ecliptic_matrix()            # row vectors: v_icrf = M^T v_ecl
    ra = np.degrees(np.arctan2(icrf[:, 1], icrf[:, 0])) % 360.0
    dec = np.degrees(np.arctan2(icrf[:, 2], np.hypot(icrf[:, 0], icrf[:, 1])))
    return ra, dec


def rotation_periods_h(rng: np.random.Generator, d_km: np.ndarray) -> np.ndarray:
    """Sidereal periods (h): log-normal, a slow-rotator tail for D < 10 km, reflected above the 2.2 h barrier
    for D >= 0.2 km."""
    n = d_km.size
    p = PERIOD_MEDIAN_H * np.exp(PERIOD_SIGMA_LN * rng.standard_normal(n))
    slow = (d_km < SLOW_BELOW_KM) & (rng.uniform(size=n) < SLOW_FRACTION)
    p[slow] = np.exp(rng.uniform(*np.log(SLOW_RANGE_H), int(slow.sum())))
    fast = (d_km >= SPIN_BARRIER_ABOVE_KM) & (p < SPIN_BARRIER_H)
    p[fast] = SPIN_BARRIER_H ** 2 / p[fast]
    return p


# ---------------------------------------------------------------------------------------------- rows
def _names(start: int, n: int) -> np.ndarray:
    return np.array([f"SYN{k:07d}" for k in range(start + 1, start + n + 1)], dtype=object)


def generate_chunk(seed: int, chunk_index: int, start: int, n: int, nea_fraction: float) -> dict[str, np.ndarray]:
    """Rows ``start`` .. ``start + n - 1`` as columns (numpy arrays; NaN where a row leaves a column empty).

    Besides ``COLUMNS`` the dict holds the draws behind them, for checks: ``_is_nea``, ``_diameter_km``,
    ``_cos_obliquity``, ``_inertia_form`` (0 axes, 1 dynamical_ellipticity, 2 moments), ``_h_d``.
    """
    rng = np.random.default_rng([seed, chunk_index])
    is_nea = rng.uniform(size=n) < nea_fraction
    cols: dict[str, np.ndarray] = {"name": _names(start, n)}
    orbit = {k: np.empty(n) for k in ("a_au", "e", "i_deg")}
    for mask, draw in ((~is_nea, main_belt_orbits), (is_nea, nea_orbits)):
        part = draw(rng, int(mask.sum()))
        for k in orbit:
            orbit[k][mask] = part[k]
    cols.update(orbit)
    for k in ("node_deg", "peri_deg", "mean_anomaly_deg"):
        cols[k] = rng.uniform(0.0, 360.0, n)
    cols["epoch_jd_tdb"] = np.full(n, EPOCH_JD)

    h = np.empty(n)
    h[~is_nea] = absolute_magnitudes(rng, int((~is_nea).sum()), BELT_H)
    h[is_nea] = absolute_magnitudes(rng, int(is_nea.sum()), NEA_H)
    d = diameters_km(rng, h)

    x = np.empty(n)
    groups = {"isotropic": d >= ISOTROPIC_ABOVE_KM}
    groups["nea"] = is_nea & ~groups["isotropic"]
    groups["belt_small"] = ~is_nea & ~groups["isotropic"]
    for key, mask in groups.items():
        x[mask] = sample_cos_obliquity(rng, int(mask.sum()), OBLIQUITY_DENSITY[key])
    azimuth = rng.uniform(0.0, 2.0 * math.pi, n)
    ra, dec = ecliptic_to_radec_deg(pole_vectors_ecliptic(cols["i_deg"], cols["node_deg"], x, azimuth))
    cols["pole_ra_deg"], cols["pole_dec_deg"] = ra, dec
    cols["pole_epoch_jd_tdb"] = np.where(rng.uniform(size=n) < 0.5, J2000_JD, np.nan)
    cols["rotation_period_hours"] = rotation_periods_h(rng, d)

    axes = ellipsoid_axes_km(rng, d)
    moments = ellipsoid_moments(axes)
    h_d = dynamical_ellipticity(moments)
    form = rng.choice(3, size=n, p=[FORM_FRACTIONS[k] for k in ("axes", "dynamical_ellipticity", "moments")])
    nan = np.full(n, np.nan)
    cols["dynamical_ellipticity"] = np.where(form == 1, h_d, nan)
    for j, k in enumerate(("moment_a", "moment_b", "moment_c")):
        cols[k] = np.where(form == 2, moments[:, j], nan)
    for j, k in enumerate(("axis_a_km", "axis_b_km", "axis_c_km")):
        cols[k] = np.where(form == 0, axes[:, j], nan)

    with_sigma = rng.uniform(size=n) < SIGMA_FRACTION
    cols["pole_ra_deg_sigma"] = np.where(with_sigma, rng.uniform(*POLE_SIGMA_DEG, n), nan)
    cols["pole_dec_deg_sigma"] = np.where(with_sigma, rng.uniform(*POLE_SIGMA_DEG, n), nan)
    cols["rotation_period_hours_sigma"] = np.where(with_sigma, PERIOD_SIGMA_RELATIVE * cols["rotation_period_hours"], nan)
    cols["dynamical_ellipticity_sigma"] = np.where(with_sigma & (form == 1), ELLIPTICITY_SIGMA_RELATIVE * h_d, nan)

    cols.update(_is_nea=is_nea, _diameter_km=d, _cos_obliquity=x, _inertia_form=form, _h_d=h_d)
    return cols


def corrupt_rows(count: int, k: int) -> list[tuple[int, str, float]]:
    """(row, column, bad value) of the K corrupt rows of a population of ``count`` rows (0-based rows)."""
    if not 0 <= k <= count:
        raise ValueError(f"--corrupt must be between 0 and --count ({count}), got {k}")
    if k == 0:
        return []
    rows = [0] if k == 1 else [round(j * (count - 1) / (k - 1)) for j in range(k)]
    if len(set(rows)) != k:                               # only when K is close to N: fall back to the first K
        rows = list(range(k))
    return [(row, *CORRUPTIONS[j % len(CORRUPTIONS)]) for j, row in enumerate(rows)]


def generate(count: int, seed: int = 1, nea_fraction: float = 0.05, corrupt: int = 0,
             chunk_rows: int = CHUNK_ROWS) -> Iterator[dict[str, np.ndarray]]:
    """The population, chunk by chunk (see ``generate_chunk``), with the corrupt rows applied. The arguments
    are checked here, before the first chunk (and before an output file is opened): ValueError."""
    if count < 0:
        raise ValueError(f"--count must be >= 0, got {count}")
    if not 0.0 <= nea_fraction <= 1.0:
        raise ValueError(f"--nea-fraction must be in [0, 1], got {nea_fraction}")
    faults = corrupt_rows(count, corrupt)
    return _chunks(count, seed, nea_fraction, faults, chunk_rows)


def _chunks(count, seed, nea_fraction, faults, chunk_rows) -> Iterator[dict[str, np.ndarray]]:
    for index, start in enumerate(range(0, count, chunk_rows)):
        n = min(chunk_rows, count - start)
        cols = generate_chunk(seed, index, start, n, nea_fraction)
        for row, column, value in faults:
            if start <= row < start + n:
                cols[column][row - start] = value
        yield cols


# ---------------------------------------------------------------------------------------------- output
def _formatted(values: np.ndarray) -> list[str]:
    """Numbers as Python's shortest round-trip repr (a value read back is the value drawn), NaN as an empty
    field. Only the filled entries are formatted: the optional columns are mostly empty, and formatting is
    most of the run at 10^6 rows."""
    if values.dtype == object:
        return list(values)
    filled = np.flatnonzero(~np.isnan(values))
    if filled.size == values.size:
        return list(map(repr, values.tolist()))
    out = [""] * values.size
    for k, text in zip(filled.tolist(), map(repr, values[filled].tolist())):
        out[k] = text
    return out


def write_csv(path: Path, chunks) -> int:
    """Write the chunks as one CSV file with a header; returns the number of rows. No field needs quoting
    (the names are SYN + digits, the rest numbers), so rows are joined directly: 3 times faster than csv."""
    rows = 0
    with open(path, "w", encoding="utf-8") as f:
        f.write(",".join(COLUMNS) + "\n")
        for cols in chunks:
            f.writelines(line + "\n" for line in map(",".join, zip(*(_formatted(cols[c]) for c in COLUMNS))))
            rows += len(cols["name"])
    return rows


def write_parquet(path: Path, chunks) -> int:
    """Write the chunks as one Parquet file (pyarrow), empty fields as nulls; returns the number of rows."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    schema = pa.schema([(c, pa.string() if c == "name" else pa.float64()) for c in COLUMNS])
    rows = 0
    with pq.ParquetWriter(path, schema) as writer:
        for cols in chunks:
            arrays = [pa.array(cols[c].tolist() if c == "name" else cols[c], from_pandas=True) for c in COLUMNS]
            writer.write_table(pa.Table.from_arrays(arrays, schema=schema))
            rows += len(cols["name"])
    return rows


def _pyarrow_available() -> bool:
    try:
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, required=True, help="number of bodies (rows)")
    parser.add_argument("--out", type=Path, required=True, help="output file: .csv, or .parquet (needs pyarrow)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    parser.add_argument("--nea-fraction", type=float, default=0.05, help="probability that a row is an NEA (0.05)")
    parser.add_argument("--corrupt", type=int, default=0, help="rows given one bad value each (see the docstring)")
    args = parser.parse_args(argv)
    try:
        chunks = generate(args.count, args.seed, args.nea_fraction, args.corrupt)
        if args.out.suffix.lower() == ".parquet":
            if not _pyarrow_available():
                print("error: --out: a .parquet output needs pyarrow, which is not installed; write .csv",
                      file=sys.stderr)
                return 2
            rows = write_parquet(args.out, chunks)
        else:
            rows = write_csv(args.out, chunks)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"{rows} rows written to {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
