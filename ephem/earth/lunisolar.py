"""The Earth's forced precession and nutation under the Moon and the Sun (rigid Earth, first order).

Kinoshita's first-order theory (Kinoshita 1977, Celest. Mech. 15, 277) for two perturbers on
moving orbits, in the Delaunay arguments l, l', F, D, Ω of IERS Conventions (2010) eq. 5.43.
The Sun-only, fixed-ellipse case is :mod:`ephem.forced.kinoshita`; this module reproduces it with
``perturbers=("sun",)`` (tests/earth/test_lunisolar.py).

Torque and equations (rotation-averaged, degree-2 potential, the numerical.py convention)
-----------------------------------------------------------------------------------------
With s the angular-momentum axis and r̂ = (x, y, z) the perturber's direction in the frame of
the mean ecliptic and equinox of date (x to the equinox), the averaged torque gives

    ds/dt = Σ_j (3 GM_j H_d / (ω r_j³)) (s·r̂_j)(r̂_j × s).

With s = (sin ε sin ψ, sin ε cos ψ, cos ε) (ψ > 0 retrograde, as kinoshita.py) this is

    dψ/dt =  (3 H_d/ω) Σ_j [cos ε G1_j + (cos 2ε / sin ε) G2_j]
    dε/dt = -(3 H_d/ω) Σ_j [sin ε G3_j + cos ε G4_j]

with the ε-free orbital functions G1 = GM (y² - z²)/r³, G2 = GM yz/r³, G3 = GM xy/r³,
G4 = GM xz/r³. For the Sun on the ecliptic (z = 0) they reduce to kinoshita.py's
(K/2) cos ε (a/r)³ (1 - cos 2λ) and -(K/2) sin ε (a/r)³ sin 2λ. These are Kinoshita's
first-order equations dψ/dt = -(1/(Cω sin ε)) ∂U/∂ε, dε/dt = (1/(Cω sin ε)) ∂U/∂ψ for the
rotation-averaged potential U; the signs are fixed by the vector equation above (the same
one ephem/forced/integration.py integrates) and checked against IAU 2000A and DE421 in the tests.

Harmonic analysis
-----------------
The Moon's longitude, latitude and distance are Meeus's (1998, ch. 47) truncation of
ELP-2000/82, whose arguments are Delaunay combinations (the Moon's mean longitude is F + Ω);
the Sun moves on the Earth-Moon barycentre's Kepler ellipse (Simon et al. 1994) with mean
anomaly l' and mean longitude F - D + Ω. Both are therefore exact functions on the 5-torus of
(l, l', F, D, Ω); the G's are sampled on a regular grid of that torus and their Fourier
coefficients taken by FFT. This is harmonic analysis without least-squares leakage: the grid
is finer than any harmonic above the cut (aliasing checked by doubling it, in the tests). A
forcing term A cos φ + B sin φ (φ = k·(l, l', F, D, Ω), φ̇ = ν at J2000) integrates to
(A/ν) sin φ - (B/ν) cos φ; the constant term of dψ/dt is the precession rate.

Axes
----
The equations move the angular-momentum axis. IAU 2000A and REN-2000 tabulate the figure
axis; the two differ by Oppolzer terms (Kinoshita 1977): with e3 the figure axis,
L̂ = e3 + (A/(Cω)) e3 × de3/dt, so per term ψ_f = ψ_L - (A/Cω) ν ε_L / sin ε and
ε_f = ε_L - (A/Cω) ν sin ε ψ_L (sin/cos pairs as in the code). ``axis="figure"`` (default)
applies them.

Poisson terms
-------------
The coefficients drift with the mean obliquity of date ε_A (IAU 2006 rate -46.836769"/cy) and
with the solar eccentricity (Simon et al. 1994; Meeus's factor E on the Moon's solar terms).
They are rebuilt at T = 1 century and the difference kept as the rate per century, as the
IAU 2000A tables do. Nothing else in the theory moves.

Evaluation: :class:`TermProducts` sums the series without a sine per term (products of e^{i m a_j} on a
prefix tree, then one matrix product), to within the rounding budget its docstring states.

Units: radians and days internally; terms in mas (rates mas per Julian century); JD TDB.
Not here: second-order (crossed-nutation) terms, J3/J4, direct planetary torques, the
Moon's planetary terms (Meeus's A1-A3), tides and any non-rigid response.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from pathlib import Path

import numpy as np

from ..base.budget import checkpoint
from ..base.disk_cache import cached_arrays, fingerprint
from ..orbit.harmonics import matching_rows, row_codes, unique_rows
from ..base.paths import data_dir
from ..bodies.catalogue import get_body
from ..base.constants import ARCSEC, AU_M, AXES, JULIAN_YEAR_DAYS, MAS
from ..base.errors import InvalidInputError
from ..orbit import lunar
from ..orbit.lunar import (DAYS_PER_CENTURY, centuries, delaunay_arguments, delaunay_rates, gm_km3_day2, lunisolar_data,
                           moon_position, obliquity_arcsec, sun_position)

PERTURBERS = ("moon", "sun")
#: Default FFT grid on the torus (l, l', F, D, Ω). Against (32, 16, 32, 32, 8) and
#: (64, 16, 64, 64, 8) no term above 0.05 mas moves by more than 1e-6 mas (tests/earth/test_lunisolar.py);
#: 8 points in l' are not enough (0.06 mas of aliasing from the solar ellipse).
DEFAULT_GRID = (24, 12, 16, 24, 6)
#: Terms of longer period than this (the 10 500-year 2(L_sun - l') term, twice the solar perigee)
#: are constant over any span the series is used for: they belong to the precession and
#: obliquity, as in IAU 2000A, and are kept apart in ``long_period_terms``.
MAX_PERIOD_DAYS = 100.0 * JULIAN_YEAR_DAYS


def hd_iers2010() -> float:
    """H_d of IERS Conventions (2010) Table 1.1 (0.0032737949), as stored in data/lunisolar.toml."""
    return float(lunisolar_data()["earth"]["hd_iers2010"])


# ----------------------------------------------------------------------------- the perturbers


def orbital_functions(name: str, args: tuple, t_centuries: float = 0.0) -> np.ndarray:
    """G1..G4 = GM (y²-z², yz, xy, xz)/r³ (rad²/day²) of perturber ``name`` at Delaunay ``args``."""
    lam, beta, r = (moon_position if name == "moon" else sun_position)(args, t_centuries)
    gm_r3 = gm_km3_day2(name) / r**3
    cb = np.cos(beta)
    x, y, z = cb * np.cos(lam), cb * np.sin(lam), np.sin(beta)
    z = z + 0.0 * x  # broadcast the Sun's z = 0 to the grid
    return np.stack(np.broadcast_arrays(gm_r3 * (y * y - z * z), gm_r3 * y * z,
                                        gm_r3 * x * y, gm_r3 * x * z))


# ----------------------------------------------------------------------------- harmonic analysis

@dataclass(frozen=True)
class OrbitalSpectrum:
    """Fourier coefficients of G1..G4 summed over the perturbers, half-space of multipliers.

    G_i = const_i + Σ_k cos_[k, i] cos(k·θ) + sin_[k, i] sin(k·θ) over the rows k of ``multipliers``.
    """

    multipliers: np.ndarray   # (n, 5) int
    cos_: np.ndarray          # (n, 4)
    sin_: np.ndarray          # (n, 4)
    const: np.ndarray         # (4,)


def _canonical(k: np.ndarray) -> np.ndarray:
    """Sign convention for a multiplier: first non-zero of (Ω, D, F, l, l') positive."""
    for i in (4, 3, 2, 0, 1):
        if k[i]:
            return k if k[i] > 0 else -k
    return k


@lru_cache(maxsize=16)
def orbital_spectrum(perturbers: tuple, t_centuries: float = 0.0, grid: tuple = DEFAULT_GRID,
                     floor: float = 1e-14) -> OrbitalSpectrum:
    """FFT of the orbital functions on the torus (l, l', F, D, Ω); coefficients below
    ``floor`` × the largest are dropped (they are far below any nutation cut).

    A pure function of data/lunisolar.toml and this code: built once (1.6 s for the Moon and the Sun) and then read
    from the disk cache (:mod:`ephem.base.disk_cache`), whose key hashes the data as read (not the file: data
    changed in memory makes another key), the code that builds it and the arguments."""
    here = Path(__file__).resolve()
    # the data through the module that reads it (what the orbital functions see, patched or not)
    key = fingerprint([here, here.parent.parent / "orbit" / "lunar.py"], repr(lunar.lunisolar_data()),
                      tuple(perturbers), float(t_centuries), tuple(grid), float(floor))
    name = f"orbital_spectrum_{'_'.join(perturbers)}_t{float(t_centuries):g}_{'x'.join(map(str, grid))}"
    arrays = cached_arrays(name, key, lambda: _spectrum_arrays(perturbers, t_centuries, grid, floor))
    return OrbitalSpectrum(arrays["multipliers"].astype(int), arrays["cos_"], arrays["sin_"], arrays["const"])


def _spectrum_arrays(perturbers: tuple, t_centuries: float, grid: tuple, floor: float) -> dict:
    s = _build_spectrum(perturbers, t_centuries, grid, floor)
    return {"multipliers": s.multipliers, "cos_": s.cos_, "sin_": s.sin_, "const": s.const}


def _build_spectrum(perturbers: tuple, t_centuries: float, grid: tuple, floor: float) -> OrbitalSpectrum:
    axes = [2 * math.pi * np.arange(n) / n for n in grid]
    shaped = tuple(a.reshape([-1 if i == j else 1 for j in range(5)]) for i, a in enumerate(axes))
    total = 0.0
    for name in perturbers:
        total = total + orbital_functions(name, shaped, t_centuries)
    g = np.broadcast_to(total, (4,) + tuple(grid))
    spec = np.fft.fftn(g, axes=(1, 2, 3, 4, 5)) / np.prod(grid)
    const = spec[(slice(None),) + (0,) * 5].real.copy()
    # keep one of each ±k pair: G = c0 + Σ_half 2 Re(c_k) cos kθ - 2 Im(c_k) sin kθ
    mag = np.max(np.abs(spec), axis=0)
    big = np.argwhere(mag > floor * np.abs(spec).max())
    seen, ks, cos_, sin_ = set(), [], [], []
    for idx in big:
        k = np.array([i if i <= n // 2 else i - n for i, n in zip(idx, grid)])
        if not k.any():
            continue
        if any(2 * abs(int(k[i])) >= grid[i] for i in range(5)):
            continue  # Nyquist row: a harmonic the grid cannot resolve (negligible by construction)
        kc = _canonical(k)
        key = tuple(int(v) for v in kc)
        if key in seen:
            continue
        seen.add(key)
        c = spec[(slice(None),) + tuple(idx)]
        if not np.array_equal(kc, k):
            c = np.conj(c)
        ks.append(kc)
        cos_.append(2.0 * c.real)
        sin_.append(-2.0 * c.imag)
    return OrbitalSpectrum(np.array(ks, dtype=int).reshape(-1, 5), np.array(cos_).reshape(-1, 4),
                           np.array(sin_).reshape(-1, 4), const)


# ----------------------------------------------------------------------------- evaluating the series

#: Complex values per work array of :class:`TermProducts` (8 MB): sets the epochs per block, 2048 for the served
#: 82 terms and for 192 (0.01 mas cut), 1024 for the 414 of a 0.001 mas cut. Measured over 256-4096 epochs per
#: block (3.6 x 10^5 epochs, one BLAS thread), each within 3% of the fastest; 4096 took 1.5x as long with 414
#: terms (cache), 256 1.2-1.6x (the Python work per block).
BLOCK_VALUES = 1 << 19
MIN_BLOCK, MAX_BLOCK = 64, 2048


@dataclass(frozen=True)
class TermProducts:
    """Σ (S + Ṡ T) sin φ + (C + Ċ T) cos φ over a series' terms, φ = k · a, without a sine per term.

    Why: the direct route (``sin(a @ k)``, ``cos(a @ k)``) costs two trigonometric calls per term and
    epoch, nearly all of an Earth track's time (0.70 s of 0.71 s at 3.6 x 10^5 epochs). Here, per block of
    epochs, each of the five arguments a_j gets e^{i a_j} = cos a_j + i sin a_j (ten calls per epoch, whatever
    the number of terms), then its powers e^{i m a_j} for every multiplier m the terms use, by repeated
    complex multiplication (negative m by conjugation, exact). Each term's e^{iφ} = Π_j e^{i k_j a_j} is then
    built on a prefix tree: the terms sharing the multipliers of the first arguments share the partial
    product, so level l holds one row per distinct prefix of l + 1 multipliers (the order of the arguments is
    the one with the fewest rows over all levels: 8 + 18 + 36 + 82 products for the served 82 terms, against
    4 × 82 for a product per term), each row a copy of its parent row times one row of the power table (rows
    grouped by multiplier, so that row is broadcast; none for multiplier 0). The sums are one matrix product
    (BLAS) of the weights (S, C and the Poisson rates Ṡ, Ċ: eight rows) with the (term, epoch) array of
    e^{iφ} (its float view holds cos φ, sin φ interleaved). Memory: a few (rows, block) complex arrays of at
    most 8 MB each (:data:`BLOCK_VALUES`) and the power tables. Time: 0.3 µs per epoch for the served 82
    terms against 1.9 µs, 0.9 µs for 414 terms against 11 µs (one BLAS thread;
    benchmarks/RESULTS_earth_track.md). An even grid would gain little more: the per-term work (one complex
    multiplication and the matrix product's share) is what an angle-addition recurrence costs too, and the
    ten calls per epoch are a quarter of the time.

    Accuracy (u = 2^-53; both routes start from the same arguments a_j of :func:`delaunay_arguments`, in
    [0, 2π)): cos a_j and sin a_j are within 1 ulp (≤ u, |value| ≤ 1), so e^{ia_j} errs by ≤ √2 u; a complex
    product of unit numbers adds ≤ √5 u (Brent, Percival & Zimmermann 2007); e^{ima_j} after m - 1 products
    errs by ≤ (√2 m + √5 (m - 1)) u, and a term's product of at most five factors by ≤ (3.7 |k|₁ + 9) u,
    |k|₁ = Σ_j |k_j|. The matrix product's dot products over n terms (≤ n u each, of Σ |weight|), the sum of the
    cos and sin parts, the Poisson combination g + T ġ and the conversion to radians add ≤ (n + 4) u. Rounded
    up, with w_n = |S_n + Ṡ_n T| + |C_n + Ċ_n T| (mas) for Δψ, likewise for Δε, at each epoch

        |error| ≤ u Σ_n w_n (4 |k_n|₁ + 12 + 2 n)   (mas; × MAS for radians),

    at most 1.9e-18 rad in Δψ and 1.0e-18 rad in Δε over 1900-2100 for the served 82-term series (Σ w_n ≈
    19 400 and 10 100 mas), 8.9e-18 and 4.6e-18 for the 414 terms of a 0.001 mas cut. Measured against the
    same sum in long double: 1.5e-19 and 8e-20 rad (tests/earth/test_lunisolar.py checks the bound at random epochs,
    on even grids and at the window's ends, for both axes and the Poisson terms apart). The direct route's
    bound is larger (its phase a @ k rounds by up to 5 u Σ_j |k_j a_j| ≤ 10π |k|₁ u rad: u Σ_n w_n
    (36 |k_n|₁ + 17 + 3 n)), its measured error alike (1.1e-19 rad); the two routes differ by at most
    1.6e-19 rad (2.6e-19 with 414 terms; 1900-2100 every 0.2 d), inside the sum of the two bounds the tests
    hold them to.
    """

    order: tuple[int, ...]        # the arguments in the tree's order (those some term uses)
    low: np.ndarray               # (5,) the smallest multiplier of each argument (≤ 0)
    high: np.ndarray              # (5,) the largest (≥ 0)
    levels: tuple                 # per level after the first: (argument, parent rows, (table row, start, stop)...)
    weights: np.ndarray           # (8, last level's rows): C_ψ, Ċ_ψ, C_ε, Ċ_ε on cos; S_ψ, Ṡ_ψ, S_ε, Ṡ_ε on sin
    block: int                    # epochs per block

    @classmethod
    def build(cls, multipliers, coefficients, rates) -> "TermProducts":
        k = np.asarray(multipliers, dtype=int).reshape(-1, 5)
        c = np.asarray(coefficients, dtype=float).reshape(-1, 4)
        r = np.asarray(rates, dtype=float).reshape(-1, 4)
        low = np.minimum(k.min(axis=0, initial=0), 0)
        high = np.maximum(k.max(axis=0, initial=0), 0)
        order = _tree_order(k)
        levels, rows, widest = [], None, 1
        if order:
            rows = k[:, order[0]] - low[order[0]]           # the first level is the power table itself
            keys = np.arange(high[order[0]] - low[order[0]] + 1)[:, None] + low[order[0]]
            widest = keys.shape[0]
        for depth in range(2, len(order) + 1):
            prefixes, rows = unique_rows(k[:, order[:depth]])
            # rows sorted by the new multiplier: each multiplier's rows are one slice, multiplied by one row of
            # the power table (broadcast, no gather), and those of multiplier 0 are left alone
            by_m = np.argsort(prefixes[:, -1], kind="stable")
            new_row = np.empty_like(by_m)
            new_row[by_m] = np.arange(by_m.size)
            prefixes, rows = prefixes[by_m], new_row[np.asarray(rows).ravel()]
            above = {tuple(p): i for i, p in enumerate(keys.tolist())}
            parents = np.array([above[tuple(p)] for p in prefixes[:, :-1].tolist()], dtype=np.intp)
            arg = order[depth - 1]
            values, starts = np.unique(prefixes[:, -1], return_index=True)
            stops = np.append(starts[1:], prefixes.shape[0])
            slices = tuple((int(m - low[arg]), int(i0), int(i1)) for m, i0, i1 in zip(values, starts, stops) if m)
            levels.append((arg, parents, slices))
            keys = prefixes
            widest = max(widest, keys.shape[0])
        width = keys.shape[0] if order else 1
        rows = np.zeros(k.shape[0], dtype=np.intp) if rows is None else np.asarray(rows, dtype=np.intp).ravel()
        weights = np.zeros((8, width))
        for i, (col, src) in enumerate(((c, 1), (r, 1), (c, 3), (r, 3), (c, 0), (r, 0), (c, 2), (r, 2))):
            np.add.at(weights[i], rows, col[:, src])       # add.at: a repeated multiplier vector sums
        block = int(min(MAX_BLOCK, max(MIN_BLOCK, 1 << int(math.log2(max(BLOCK_VALUES // widest, 1))))))
        return cls(tuple(order), low, high, tuple(levels), weights, block)

    def products(self, args: np.ndarray) -> np.ndarray:
        """e^{iφ} on the last level's rows, (rows, epochs) complex, at ``args`` (epochs, 5)."""
        a = np.asarray(args, dtype=float).reshape(-1, 5)
        if not self.order:
            return np.ones((1, a.shape[0]), dtype=complex)
        first = np.empty((5, a.shape[0]), dtype=complex)          # e^{i a_j}: ten calls per epoch, in two
        np.cos(a.T, out=first.real)
        np.sin(a.T, out=first.imag)
        tables = {j: self._powers(first[j], int(self.low[j]), int(self.high[j])) for j in self.order}
        cur = tables[self.order[0]]
        for arg, parents, slices in self.levels:
            nxt = cur.take(parents, axis=0)
            table = tables[arg]
            for row, start, stop in slices:
                nxt[start:stop] *= table[row]
            cur = nxt
        return cur

    def evaluate(self, args: np.ndarray, t_centuries: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Δψ, Δε (radians) at ``args`` (epochs, 5) and T (epochs,): one block (no splitting here)."""
        t = np.asarray(t_centuries, dtype=float).ravel()
        z = self.products(args)
        g = self.weights @ z.view(float)               # (8, 2 epochs): columns Re, Im interleaved
        g = g[:4, 0::2] + g[4:, 1::2]                  # Σ C cos φ + S sin φ, the four (value, rate) pairs
        return (g[0] + t * g[1]) * MAS, (g[2] + t * g[3]) * MAS

    @staticmethod
    def _powers(first: np.ndarray, low: int, high: int) -> np.ndarray:
        """e^{i m a} for m = low..high (rows) from ``first`` = e^{ia}, by repeated multiplication;
        e^{-ima} = conj(e^{ima}) exactly."""
        table = np.empty((high - low + 1, first.size), dtype=complex)
        table[-low] = 1.0
        power = first
        for m in range(1, max(high, -low) + 1):
            if m > 1:
                power = power * first
            if m <= high:
                table[m - low] = power
            if -m >= low:
                np.conjugate(power, out=table[-m - low])
        return table


def _tree_order(k: np.ndarray) -> list[int]:
    """The order of the arguments some term uses that makes the fewest partial products: the number of
    rows at a level is that of the distinct multiplier vectors on the set of arguments taken so far, so the
    best chain of sets is found over the (at most 31) subsets (dynamic programming)."""
    used = [j for j in range(5) if k.shape[0] and np.any(k[:, j])]
    if not used:
        return []
    count = {}
    for mask in range(1, 1 << len(used)):
        cols = [used[i] for i in range(len(used)) if mask >> i & 1]
        count[mask] = 1 + int(np.count_nonzero(np.diff(np.sort(row_codes(k[:, cols])))))  # distinct rows; np.unique loads numpy.ma
    best = {}   # mask -> (products, order)
    for mask in sorted(count, key=lambda m: bin(m).count("1")):
        members = [i for i in range(len(used)) if mask >> i & 1]
        if len(members) == 1:
            best[mask] = (0, [used[members[0]]])     # a power table: no products
            continue
        options = [best[mask & ~(1 << i)] for i in members]
        products, order = min(((o[0] + count[mask], o[1] + [used[i]]) for i, o in zip(members, options)),
                              key=lambda o: o[0])
        best[mask] = (products, order)
    return best[(1 << len(used)) - 1][1]


# ----------------------------------------------------------------------------- the series

@dataclass(frozen=True)
class LunisolarSeries:
    """Rigid-Earth precession rate and nutation series in the Delaunay arguments.

    Δψ = Σ (S + Ṡ T) sin φ + (C + Ċ T) cos φ, likewise Δε, φ = multipliers · (l, l', F, D, Ω)
    from :func:`delaunay_arguments`, T Julian centuries TDB from J2000; coefficients in mas,
    rates in mas per century (``terms``).
    """

    perturbers: tuple
    axis: str
    hd: float
    spin_rate: float                      # ω, rad/day
    obliquity: float                      # ε_A at J2000, rad
    cut_mas: float
    precession_rate: float                # rad/day at J2000 (ψ̇ on the ecliptic of date)
    precession_rate_t: float              # its change per century (rad/day/cy)
    multipliers: np.ndarray               # (n, 5)
    coefficients: np.ndarray              # (n, 4) mas: ψ sin, ψ cos, ε sin, ε cos
    rates: np.ndarray                     # (n, 4) mas per century
    frequencies: np.ndarray               # (n,) rad/day at J2000
    long_period_terms: list = field(default_factory=list, compare=False)

    @cached_property
    def terms(self) -> list:
        """The terms as dicts (:func:`term_dicts`), on first use (a cut-free series is read for its arrays)."""
        return term_dicts(self.multipliers, self.frequencies, self.coefficients, self.rates)

    @property
    def precession_rate_arcsec_per_year(self) -> float:
        return self.precession_rate * JULIAN_YEAR_DAYS / ARCSEC

    @property
    def precession_rate_arcsec_per_century(self) -> float:
        return self.precession_rate * DAYS_PER_CENTURY / ARCSEC

    @property
    def period_days(self) -> np.ndarray:
        return 2.0 * math.pi / self.frequencies

    def term(self, multipliers) -> dict | None:
        """The term with these multipliers (or their negatives, signs folded in), else None."""
        k = np.asarray(multipliers, dtype=int)
        for sign in (1, -1):
            hit = np.nonzero(np.all(self.multipliers == sign * k, axis=1))[0]
            if hit.size:
                t = dict(self.terms[int(hit[0])])
                if sign < 0:
                    for key in ("longitude_sin_mas", "obliquity_sin_mas", "longitude_sin_rate_mas_per_century",
                                "obliquity_sin_rate_mas_per_century"):
                        t[key] = -t[key]
                    t["delaunay_multipliers"] = [int(v) for v in k]
                    t["period_days"] = -t["period_days"]
                return t
        return None

    def nutation_from_arguments(self, args, t_centuries=0.0) -> tuple[np.ndarray, np.ndarray]:
        """Δψ, Δε (radians) at Delaunay arguments ``args`` (shape (..., 5), any real values) and time T
        (centuries, broadcast against ``args[..., 0]``)."""
        a = np.asarray(args, dtype=float)
        t = np.asarray(t_centuries, dtype=float)
        shape = np.broadcast_shapes(a.shape[:-1], t.shape)
        flat_a = np.broadcast_to(a, shape + (5,)).reshape(-1, 5)
        flat_t = np.broadcast_to(t, shape).ravel()
        dpsi = np.empty(flat_t.size)
        deps = np.empty(flat_t.size)
        block = self._plan.block
        for start in range(0, flat_t.size, block):   # bounded memory: (block, terms)
            sl = slice(start, start + block)
            dpsi[sl], deps[sl] = self._plan.evaluate(flat_a[sl], flat_t[sl])
        return dpsi.reshape(shape), deps.reshape(shape)

    def nutation_at(self, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """Δψ, Δε (radians) at JD TDB (any array shape), with the Poisson (T) terms."""
        jd = np.asarray(jd_tdb, dtype=float)
        flat = jd.ravel()
        dpsi = np.empty(flat.size)
        deps = np.empty(flat.size)
        plan = self._plan
        for start in range(0, flat.size, plan.block):   # bounded memory: (block, terms)
            checkpoint()    # the service's backstop
            sl = slice(start, start + plan.block)
            dpsi[sl], deps[sl] = plan.evaluate(delaunay_arguments(flat[sl]), centuries(flat[sl]))
        return dpsi.reshape(jd.shape), deps.reshape(jd.shape)

    @cached_property
    def _plan(self) -> "TermProducts":
        return TermProducts.build(self.multipliers, self.coefficients, self.rates)


def term_amplitudes(coefficients) -> np.ndarray:
    """Per term of (N, 4) coefficients (ψ sin, ψ cos, ε sin, ε cos), the larger of its two amplitudes: what the
    amplitude cut compares (a term is kept when either component reaches the cut)."""
    c = np.asarray(coefficients, dtype=float).reshape(-1, 4)
    return np.maximum(np.hypot(c[:, 0], c[:, 1]), np.hypot(c[:, 2], c[:, 3]))


def _coefficients(spec: OrbitalSpectrum, hd: float, omega: float, eps: float, nu: np.ndarray, axis: str):
    """Nutation coefficients (rad) ψ sin, ψ cos, ε sin, ε cos for each row of ``spec``."""
    f = 3.0 * hd / omega
    se, ce, c2e = math.sin(eps), math.cos(eps), math.cos(2.0 * eps)
    # rates: dψ/dt = f (cε G1 + c2ε/sε G2), dε/dt = -f (sε G3 + cε G4); per harmonic cos/sin parts
    psi_cos = f * (ce * spec.cos_[:, 0] + c2e / se * spec.cos_[:, 1])
    psi_sin = f * (ce * spec.sin_[:, 0] + c2e / se * spec.sin_[:, 1])
    eps_cos = -f * (se * spec.cos_[:, 2] + ce * spec.cos_[:, 3])
    eps_sin = -f * (se * spec.sin_[:, 2] + ce * spec.sin_[:, 3])
    # ∫ (A cos φ + B sin φ) dt = (A/ν) sin φ - (B/ν) cos φ
    coef = np.stack([psi_cos / nu, -psi_sin / nu, eps_cos / nu, -eps_sin / nu], axis=1)
    if axis == "figure":
        # ψ_f = ψ_L + (A/Cω) ε̇_L / sin ε, ε_f = ε_L - (A/Cω) sin ε ψ̇_L   (module docstring)
        g = (1.0 - hd) / omega
        ps, pc, es, ec = coef.T
        # ε̇ = ν (es cos φ - ec sin φ), ψ̇ = ν (ps cos φ - pc sin φ)
        # The map is I + gνJ with J² = I; L̂ = e3 + (A/Cω) e3 × ė3 holds to every order in ν/ω, so
        # the exact inverse is (I + gνJ)/(1 - (gν)²): +0.53% on the fortnightly term, 1.2% at 9.13 d.
        exact = 1.0 / (1.0 - (g * nu) ** 2)
        coef = np.stack([ps - g * nu * ec / se, pc + g * nu * es / se,
                         es + g * se * nu * pc, ec - g * se * nu * ps], axis=1) * exact[:, None]
    precession = f * (ce * spec.const[0] + c2e / se * spec.const[1])
    return coef, precession


def resolve_hd(hd) -> float:
    if hd is None:
        return float(get_body("earth").hd)
    if isinstance(hd, str):
        if hd.lower() in ("iers", "iers2010"):
            return hd_iers2010()
        if hd.lower() == "catalogue":
            return float(get_body("earth").hd)
        raise InvalidInputError("hd", f"unknown H_d name {hd!r} (use a number, 'catalogue' or 'iers2010')")
    value = float(hd)
    if not math.isfinite(value) or not 0.0 < value < 1.0:
        raise InvalidInputError("hd", f"must be in (0, 1), got {hd!r}")
    return value


def earth_spin_rate() -> float:
    """ω (rad/day): the catalogue's stellar day (rotation relative to the ICRF)."""
    return get_body("earth").spin_rate_rad_per_day


def earth_lunisolar(cut_mas: float = 0.1, perturbers=PERTURBERS, hd=None, axis: str = "figure",
                    grid: tuple = DEFAULT_GRID, spin_rate: float | None = None) -> LunisolarSeries:
    """The Earth's rigid-body lunisolar precession rate and nutation series.

    ``hd``: None or "catalogue" for the catalogue's H_d (the current catalogue gives IERS 2010
    Table 1.1's 0.0032737949 explicitly; its Lara 2014 moments imply 0.0032789), "iers2010" for
    IERS 2010 Table 1.1 (0.0032737949), or a number. ``axis``: "figure" (comparable with
    IAU 2000A and REN-2000) or "angular_momentum" (what the torque equations move, and what
    ephem.forced.kinoshita / ephem.forced.precession_nutation give). Terms whose Δψ or Δε amplitude reaches ``cut_mas`` are
    kept. ``spin_rate`` ω (rad/day): default the catalogue Earth's (:func:`earth_spin_rate`).
    """
    perturbers = tuple(perturbers) if not isinstance(perturbers, str) else (perturbers,)
    if not perturbers or any(p not in PERTURBERS for p in perturbers) or len(set(perturbers)) != len(perturbers):
        raise InvalidInputError("perturbers", f"must be distinct names among {PERTURBERS}, got {perturbers!r}")
    if axis not in AXES:
        raise InvalidInputError("axis", f"must be one of {AXES}, got {axis!r}")
    cut = float(cut_mas)
    if not math.isfinite(cut) or cut < 0.0:
        raise InvalidInputError("cut_mas", f"must be a finite non-negative number, got {cut_mas!r}")
    if spin_rate is None:
        spin_rate = earth_spin_rate()
    elif not (isinstance(spin_rate, (int, float)) and math.isfinite(spin_rate) and spin_rate > 0.0):
        raise InvalidInputError("spin_rate", f"must be a positive finite number (rad/day), got {spin_rate!r}")
    return _build(cut, tuple(sorted(perturbers, key=PERTURBERS.index)), resolve_hd(hd), axis, tuple(grid),
                  float(spin_rate))


@lru_cache(maxsize=16)
def _build(cut: float, perturbers: tuple, hd: float, axis: str, grid: tuple, omega: float) -> LunisolarSeries:
    eps0 = obliquity_arcsec(0.0) * ARCSEC
    spec0 = orbital_spectrum(perturbers, 0.0, grid)
    nu0 = spec0.multipliers @ delaunay_rates(0.0)
    coef0, prec0 = _coefficients(spec0, hd, omega, eps0, nu0, axis)
    # the same harmonics one century on: ε_A, the solar eccentricity and the frequencies drift
    spec1 = orbital_spectrum(perturbers, 1.0, grid)
    rows = matching_rows(spec0.multipliers, spec1.multipliers)    # -1: the harmonic is not there a century on
    found = rows >= 0
    cos1 = np.zeros((rows.size, 4))
    sin1 = np.zeros((rows.size, 4))
    cos1[found] = np.asarray(spec1.cos_).reshape(-1, 4)[rows[found]]
    sin1[found] = np.asarray(spec1.sin_).reshape(-1, 4)[rows[found]]
    spec1 = OrbitalSpectrum(spec0.multipliers, cos1, sin1, spec1.const)
    nu1 = spec0.multipliers @ delaunay_rates(1.0)
    coef1, prec1 = _coefficients(spec1, hd, omega, obliquity_arcsec(1.0) * ARCSEC, nu1, axis)

    mas0, mas_rate = coef0 / MAS, (coef1 - coef0) / MAS
    amp = term_amplitudes(mas0)
    periodic = 2.0 * math.pi / np.abs(nu0) <= MAX_PERIOD_DAYS
    keep = np.nonzero((amp >= cut) & periodic)[0]
    keep = keep[np.argsort(-amp[keep], kind="stable")]
    slow = np.nonzero((amp >= cut) & ~periodic)[0]
    long_terms = term_dicts(spec0.multipliers[slow], nu0[slow], mas0[slow], mas_rate[slow])
    ks, c, r, nu = spec0.multipliers[keep], mas0[keep], mas_rate[keep], nu0[keep]
    return LunisolarSeries(perturbers, axis, hd, omega, eps0, cut, prec0, prec1 - prec0, ks, c, r, nu, long_terms)


def term_dicts(ks, nu, c, r) -> list:
    """The series' terms as dicts (the ``LunisolarSeries.terms`` entries): Delaunay multipliers ``ks``, angular
    frequencies ``nu`` (rad/day; the period is 2π/ν), coefficients ``c`` (mas: Δψ sin, Δψ cos, Δε sin, Δε cos)
    and their rates ``r`` (mas per century), one row per term (``tolist``: float() per element, 5x faster)."""
    period = (2.0 * math.pi / np.asarray(nu, dtype=float)).tolist()
    return [{
        "delaunay_multipliers": k,
        "period_days": p,
        "longitude_sin_mas": ci[0], "longitude_cos_mas": ci[1],
        "obliquity_sin_mas": ci[2], "obliquity_cos_mas": ci[3],
        "longitude_sin_rate_mas_per_century": ri[0], "longitude_cos_rate_mas_per_century": ri[1],
        "obliquity_sin_rate_mas_per_century": ri[2], "obliquity_cos_rate_mas_per_century": ri[3],
    } for k, p, ci, ri in zip(np.asarray(ks, dtype=int).reshape(-1, 5).tolist(), period,
                              np.asarray(c, dtype=float).reshape(-1, 4).tolist(),
                              np.asarray(r, dtype=float).reshape(-1, 4).tolist())]


# ----------------------------------------------------------------------------- comparison with IAU 2000A

def precession_nutation_coupling(series: LunisolarSeries) -> np.ndarray:
    """The leading second-order term, left out of the series: (n, 2) Δψ sin, cos coefficients, mas.

    The precession rate goes as cos ε, so the nutation in obliquity Δε feeds
    -tan ε ψ̇ Δε into dψ/dt; integrated per term it adds (-tan ε ψ̇/ν)(E sin φ - F cos φ) to Δψ
    for Δε = E cos φ + F sin φ: +2.9 mas on the 18.6-yr term, under 0.02 mas elsewhere. The
    DE421 integration contains it (tests/earth/test_lunisolar.py).
    """
    k = -math.tan(series.obliquity) * series.precession_rate
    c = series.coefficients
    return np.stack([k * c[:, 3] / series.frequencies, -k * c[:, 2] / series.frequencies], axis=1)


def iau2000a_terms() -> list:
    """The IAU 2000A leading terms stored in data/lunisolar.toml (mas; ERFA nut00a.c)."""
    return list(lunisolar_data()["iau2000a_term"])


def residual_vs_iau2000a(series: LunisolarSeries, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
    """Δψ, Δε of ``series`` minus ERFA's IAU 2000A (``erfa.nut00a``), radians, at JD TDB (as TT)."""
    import erfa

    jd = np.asarray(jd_tdb, dtype=float)
    dpsi, deps = series.nutation_at(jd)
    ref_psi, ref_eps = erfa.nut00a(jd, 0.0)
    return dpsi - ref_psi, deps - ref_eps
