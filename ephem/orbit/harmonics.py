"""Harmonic sums Σ_k S_k sin kx + C_k cos kx, k = 1..K, at many angles x: the engine the theories' series run on.

:func:`evaluate_harmonics` sums at any angles (:mod:`ephem.orbit.harmonic_grid`: on an even grid); it takes
one sin and one cos of x per epoch and builds the harmonics from Chebyshev polynomials of cos x (a power table and one
matrix product per cache-sized block, or the three-term recurrence for many harmonics), never a sin/cos
per harmonic, in blocks whose work table stays under :data:`BLOCK_BYTES` whatever the harmonics and the
epochs. :func:`cos_sin_into` gives cos x, sin x at any angles and :func:`shift_factors` moves them by a small
angle without a trigonometric call (the track kernel's); :func:`series_extrema` finds the half peak-to-peak
excursion of a sum over a period.

Angles in radians; the coefficients in any unit (the sums come out in it). Nothing here is one theory's:
Kinoshita's nutation series (:mod:`ephem.forced.kinoshita`) and the model's tracks (:mod:`ephem.forced.precession_nutation`) use it.
"""
from __future__ import annotations

import bisect
import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..base.budget import checkpoint

#: Epochs per block in the evaluators: small enough to stay in cache.
BLOCK = 8192
#: Largest work table of one block, bytes: with many harmonics (e -> 1: 10^4-10^5) a block holds fewer
#: epochs, so memory stays bounded whatever the harmonics and the epochs (a full 8192-epoch block of
#: 42 000 harmonics at e = 0.99 would be 5.5 GB). The cost model's harmonic_block_mb (data/cost_model.toml) is
#: this size (a test checks).
BLOCK_BYTES = 32 * 2**20
#: The power basis of cos x is used when it amplifies rounding by at most this factor over
#: the Chebyshev (harmonic) coefficients: its coefficients grow like 2^k for slowly decaying
#: series (random ones), not for nutation series, whose terms fall off like e^k.
_MAX_POWER_BASIS_GROWTH = 8.0
#: Beyond this many harmonics the power basis is not even tried (2^k overflows past ~1000 and
#: no series that long decays fast enough to pass the growth test).
MAX_POWER_BASIS_TERMS = 48


def _power_basis(multiple: np.ndarray, sin_coef: np.ndarray, cos_coef: np.ndarray) -> np.ndarray:
    """Coefficients of the sums in powers of c = cos x: Σ = P(c) + sin x · Q(c).

    cos kx = T_k(c) and sin kx = sin x · U_{k-1}(c) (Chebyshev polynomials of the
    first and second kinds). Returns an array (kmax+1, 2 ncol): P's columns, then Q's.
    """
    from numpy.polynomial import chebyshev

    kmax, ncol = sin_coef.shape
    out = np.zeros((kmax + 1, 2 * ncol))
    u_prev, u = np.zeros(kmax + 1), np.zeros(kmax + 1)
    u[0] = 1.0  # U_0
    u_list = [u.copy()]
    for _ in range(1, kmax):
        nxt = np.zeros(kmax + 1)
        nxt[1:] = 2.0 * u[:-1]
        nxt -= u_prev
        u_prev, u = u, nxt
        u_list.append(u.copy())
    for j in range(ncol):
        p = chebyshev.cheb2poly(np.concatenate([[0.0], cos_coef[:, j]]))   # trailing zeros trimmed
        out[:p.size, j] = p
        out[:, ncol + j] = sum(sin_coef[k, j] * u_list[k] for k in range(kmax))
    return out


def _sum_block(c: np.ndarray, s: np.ndarray, kmax: int, power_coef: np.ndarray | None,
               sin_coef: np.ndarray, cos_coef: np.ndarray, out: np.ndarray, work: np.ndarray) -> None:
    """Harmonic sums for one block, given c = cos x and s = sin x; writes out (ncol, m).

    ``power_coef`` is :func:`_prepare`'s power basis, (2 ncol, kmax + 1): P's rows then Q's, or None for the
    three-term recurrence; ``work`` its table (the power table's row 0 already holds ones).
    """
    m = c.size
    ncol = sin_coef.shape[1]
    if power_coef is not None:
        pw = work[: kmax + 1, :m]  # rows: 1, c, c², … (contiguous for a full block)
        r = work[kmax + 1: kmax + 1 + 2 * ncol, :m]
        pw[1] = c
        for k in range(2, kmax + 1):
            np.multiply(pw[k - 1], c, out=pw[k])
        np.matmul(power_coef, pw, out=r)  # (2 ncol, m): P's rows then Q's
        q = r[ncol:]
        np.multiply(q, s, out=q)
        np.add(r[:ncol], q, out=out)
        return
    tab = work[: 2 * kmax, :m]  # rows: cos x .. cos kmax x, sin x .. sin kmax x
    cos_t, sin_t = tab[:kmax], tab[kmax:]
    cos_t[0] = c
    sin_t[0] = s
    two_c = 2.0 * c
    if kmax > 1:
        np.multiply(two_c, c, out=cos_t[1])
        cos_t[1] -= 1.0
        np.multiply(two_c, s, out=sin_t[1])
    for k in range(2, kmax):
        np.multiply(two_c, cos_t[k - 1], out=cos_t[k])
        cos_t[k] -= cos_t[k - 2]
        np.multiply(two_c, sin_t[k - 1], out=sin_t[k])
        sin_t[k] -= sin_t[k - 2]
    np.matmul(np.concatenate([cos_coef, sin_coef], axis=0).T, tab, out=out)


@functools.lru_cache(maxsize=64)
def _power_basis_cached(key: bytes, kmax: int, ncol: int) -> np.ndarray | None:
    """The power basis transposed, (2 ncol, kmax + 1), or None where it amplifies rounding beyond
    :data:`_MAX_POWER_BASIS_GROWTH`; kept per coefficients (``key``, their bytes): 0.5 ms a call on the same series."""
    coef = np.frombuffer(key, dtype=float).reshape(2, kmax, ncol)
    sin_coef, cos_coef = coef[0], coef[1]
    candidate = _power_basis(np.arange(1, kmax + 1), sin_coef, cos_coef)
    scale = np.abs(sin_coef).sum() + np.abs(cos_coef).sum()
    if np.abs(candidate).sum() <= _MAX_POWER_BASIS_GROWTH * scale:
        power = np.ascontiguousarray(candidate.T)
        power.flags.writeable = False
        return power
    return None


def _prepare(multiple, sin_coef, cos_coef, count: int = BLOCK, cap: int = BLOCK):
    """(kmax, the power basis (2 ncol, kmax + 1) or None, the work table, the epochs per block, at most ``cap``)
    for ``count`` epochs."""
    kmax = len(multiple)
    if kmax and not np.array_equal(multiple, np.arange(1, kmax + 1)):
        raise ValueError("multiple must be 1..kmax")
    ncol = sin_coef.shape[1]
    power = None
    if 0 < kmax <= MAX_POWER_BASIS_TERMS:
        key = np.ascontiguousarray(np.stack([sin_coef, cos_coef]), dtype=float).tobytes()
        power = _power_basis_cached(key, kmax, ncol)
    width = max(kmax + 1 + 2 * ncol if power is not None else 2 * kmax, 1)
    block = max(1, min(cap, count, BLOCK_BYTES // (8 * width)))
    work = np.empty((width, block))
    if power is not None:
        work[0] = 1.0   # the power table's c⁰ row, the same for every block
    return kmax, power, work, block


class HarmonicSums:
    """Σ_k S[k, j] sin(k x) + C[k, j] cos(k x), k = 1..kmax, block by block from cos x and sin x: the set-up of
    :func:`evaluate_harmonics` (the power basis or the recurrence, the work table, :attr:`block` epochs per block)
    for a caller that makes its own cos x and sin x (a track's kernel, :mod:`ephem.forced.precession_nutation`)."""

    def __init__(self, multiple: np.ndarray, sin_coef: np.ndarray, cos_coef: np.ndarray, count: int = BLOCK,
                 cap: int = BLOCK):
        self.sin_coef, self.cos_coef = np.asarray(sin_coef, dtype=float), np.asarray(cos_coef, dtype=float)
        self.kmax, self.power, self.work, self.block = _prepare(multiple, self.sin_coef, self.cos_coef, count, cap)

    def into(self, c: np.ndarray, s: np.ndarray, out: np.ndarray) -> None:
        """The sums at the block's angles (c = cos x, s = sin x, at most :attr:`block` of them) into ``out``
        (ncol, m)."""
        if self.kmax:
            _sum_block(c, s, self.kmax, self.power, self.sin_coef, self.cos_coef, out, self.work)
        else:
            out[...] = 0.0


def evaluate_harmonics(angle, multiple: np.ndarray, sin_coef: np.ndarray, cos_coef: np.ndarray):
    """Σ_k S[k, j] sin(k x) + C[k, j] cos(k x) for each output column j, at any angles x.

    ``multiple`` must be 1, 2, …, kmax. One numpy sin and cos of x per epoch (the plain path); the harmonics
    come from Chebyshev polynomials of cos x (a power table and one matrix product per cache-sized block, or the
    three-term recurrence for many harmonics) — never a sin/cos per harmonic. Returns arrays shaped like x.
    """
    x = np.asarray(angle, dtype=float)
    flat = x.ravel()
    ncol = sin_coef.shape[1]
    out = np.zeros((ncol, flat.size))
    sums = HarmonicSums(multiple, sin_coef, cos_coef, flat.size)
    if sums.kmax:
        for start in range(0, flat.size, sums.block):
            checkpoint()
            xb = flat[start:start + sums.block]
            sums.into(np.cos(xb), np.sin(xb), out[:, start:start + xb.size])
    return tuple(out[j].reshape(x.shape) for j in range(ncol))


#: The largest spread of a block of angles about a reference that the track kernel moves cos and sin across by the
#: Taylor series (:func:`shift_factors`; beyond, :func:`cos_sin_into`'s table), radians
MAX_SHIFT = 0.01
#: The Taylor series stop where the first omitted term is below this (alternating series with falling terms: it
#: bounds what is left out), 1/32 of an ulp of 1
SHIFT_TRUNCATION = 2.0**-57
#: :func:`cos_sin_into`'s table: cos and sin of j 2π/L, L = 2^12 (|δ| <= π/L = 7.7e-4 is left to the series). 2π/L
#: in two parts (Cody and Waite): the first with 26 significant bits, so j times it is exact for |j| < 2^27, the
#: second the rest of 2π/L to 53 bits (2π = 6.283185307179586 + 2.4492935982947064e-16)
_TABLE_SIZE = 1 << 12
_STEP = 2.0 * math.pi / _TABLE_SIZE                                     # exact: L is a power of 2
_STEP_HI = math.ldexp(math.floor(math.ldexp(math.frexp(_STEP)[0], 26)), math.frexp(_STEP)[1] - 26)
_STEP_LO = (_STEP - _STEP_HI) + 2.4492935982947064e-16 / _TABLE_SIZE    # _STEP - _STEP_HI is exact
#: angles up to this size are reduced by the table (|j| < 2^26: j times :data:`_STEP_HI` exact, with room); beyond
#: (10^5 rad: 16 000 years of the Earth's mean anomaly), numpy's cos and sin
REDUCE_LIMIT = 2.0**26 * _STEP
#: 1.5 2^52: x/step + this rounds x/step to the nearest integer j, whose low bits are then the mantissa's
_ROUND = 1.5 * 2.0**52


def _cos_sin_table(extended: bool | None = None) -> tuple[np.ndarray, np.ndarray]:
    """cos and sin of j 2π/L, j < L: the nearest doubles (but for the long double angle's 3e-19) where numpy's
    long double has the x87's 64-bit mantissa (``extended`` None: wherever it has); else within an ulp: libm's at
    the rounded angle a = fl(j 2π/L), corrected by its rounding e = j 2π/L - a (exact from the split step):
    cos a - e sin a, sin a + e cos a (|e| <= 4.4e-16, e² negligible)."""
    j = np.arange(_TABLE_SIZE, dtype=float)
    if extended if extended is not None else np.finfo(np.longdouble).nmant >= 63:
        a = np.longdouble("6.283185307179586476925286766559005768") * j.astype(np.longdouble) / _TABLE_SIZE
        cos_t, sin_t = np.cos(a).astype(float), np.sin(a).astype(float)
    else:                                          # platforms whose long double is a double (tested on any)
        hi, lo = j * _STEP_HI, j * _STEP_LO       # j * hi exact
        a = hi + lo
        e = (hi - a) + lo
        cos_t, sin_t = np.cos(a) - e * np.sin(a), np.sin(a) + e * np.cos(a)
    cos_t.flags.writeable = sin_t.flags.writeable = False
    return cos_t, sin_t


_TABLE_COS, _TABLE_SIN = _cos_sin_table()
#: for n = 1, 2, …: the largest |δ| at which n terms of sin δ's (cos δ's) series leave out less than
#: :data:`SHIFT_TRUNCATION` (the first omitted term, δ^(2n+1)/(2n+1)! (δ^2n/(2n)!), bounds the rest)
_SIN_LIMITS = tuple((SHIFT_TRUNCATION * math.factorial(2 * n + 1)) ** (1.0 / (2 * n + 1)) for n in range(1, 12))
_COS_LIMITS = tuple((SHIFT_TRUNCATION * math.factorial(2 * n)) ** (1.0 / (2 * n)) for n in range(1, 12))
#: Horner coefficients: sin δ = δ Σ_i SIN_COEF[i] δ^2i, cos δ = Σ_i COS_COEF[i] δ^2i
_SIN_COEF = tuple((-1.0) ** i / math.factorial(2 * i + 1) for i in range(12))
_COS_COEF = tuple((-1.0) ** i / math.factorial(2 * i) for i in range(12))


def _series_terms(beta: float) -> tuple[int, int]:
    """The terms (n_sin, n_cos) of sin δ = δ Σ_{i<n_sin} (-δ²)^i/(2i+1)! and cos δ = Σ_{i<n_cos} (-δ²)^i/(2i)!
    that leave out less than :data:`SHIFT_TRUNCATION` for |δ| <= beta (beta < 1)."""
    return bisect.bisect_left(_SIN_LIMITS, beta) + 1, bisect.bisect_left(_COS_LIMITS, beta) + 1


def shift_factors(delta: np.ndarray, beta: float, cd: np.ndarray, sd: np.ndarray, d2: np.ndarray) -> np.ndarray:
    """cos δ into cd and sin δ into sd for |δ| <= beta < 1, no trigonometric call: their Taylor series with the
    terms :func:`_series_terms` keeps (Horner in δ²), so cos(x + δ) = cos x cd - sin x sd and sin(x + δ) =
    sin x cd + cos x sd. d2: a work array the size of δ; none of the arrays is δ. Returns sin δ's array: sd, or δ
    itself when sin δ = δ to the truncation (then sd is untouched)."""
    n_sin, n_cos = _series_terms(beta)
    np.multiply(delta, delta, out=d2)
    for n, coef, out in ((n_sin, _SIN_COEF, sd), (n_cos, _COS_COEF, cd)):
        if n == 1:
            continue
        np.multiply(d2, coef[n - 1], out=out)
        for i in range(n - 2, 0, -1):
            out += coef[i]
            out *= d2
        out += 1.0
    if n_sin > 1:
        sd *= delta
    if n_cos == 1:
        cd.fill(1.0)
    return sd if n_sin > 1 else delta


def cos_sin_into(x: np.ndarray, cos_out: np.ndarray, sin_out: np.ndarray, work: np.ndarray) -> None:
    """cos x and sin x at any angles x (a block, in any order), into cos_out and sin_out, with no trigonometric
    call per angle: x = j 2π/L + δ (L = 2^12, |δ| <= π/L), cos and sin of j 2π/L from a table (each within half an
    ulp), of δ by :func:`shift_factors` (truncation below 2^-57). j 2π/L is subtracted in two parts (exact to 1e-18
    for |x| <= :data:`REDUCE_LIMIT`): within 3 ulp of numpy's at the same x. A block reaching beyond
    :data:`REDUCE_LIMIT` (or not finite) gets numpy's cos and sin. ``work``: 4 rows of at least x.size, none of them
    x or the outputs."""
    m = x.size
    if m and not (max(-float(x.min()), float(x.max())) <= REDUCE_LIMIT):
        np.cos(x, out=cos_out)
        np.sin(x, out=sin_out)
        return
    y, j, delta, tmp = work[0, :m], work[1, :m], work[2, :m], work[3, :m]
    np.multiply(x, _TABLE_SIZE / (2.0 * math.pi), out=y)
    y += _ROUND                                   # j in the low bits, rounded to nearest
    np.subtract(y, _ROUND, out=j)                 # j (exact)
    index = y.view(np.int64)
    np.bitwise_and(index, _TABLE_SIZE - 1, out=index)   # j mod L (two's complement: also for j < 0)
    _TABLE_COS.take(index, out=cos_out, mode="clip")
    _TABLE_SIN.take(index, out=sin_out, mode="clip")
    np.multiply(j, _STEP_HI, out=delta)
    np.subtract(x, delta, out=delta)
    j *= _STEP_LO
    delta -= j
    # |δ| <= π/L, plus the rounding of x/step to an integer (an ulp of it) and of δ
    sd = shift_factors(delta, math.pi / _TABLE_SIZE * (1.0 + 2.0**-20), tmp, y, j)
    np.multiply(sin_out, sd, out=j)               # sin x_j sin δ
    sd *= cos_out                                 # cos x_j sin δ
    cos_out *= tmp
    cos_out -= j
    sin_out *= tmp
    sin_out += sd


def evaluate_harmonics_periodic(x_start: float, count: int, sin_coef: np.ndarray, cos_coef: np.ndarray) -> np.ndarray:
    """Σ_k S[k, j] sin(k x) + C[k, j] cos(k x), k = 1..K, on the grid x_i = x_start + 2πi/count covering one
    period: an array (count, ncol), by one inverse FFT (O(count log count), not O(count K)); exact (to rounding)
    when count > 2K, as the harmonics then do not alias.

    Shifted to the grid's start, harmonic k is S' sin kθ + C' cos kθ with S' = S cos kx0 - C sin kx0,
    C' = S sin kx0 + C cos kx0 (θ = x - x_start), the real part of (C' - i S') e^{ikθ}.
    """
    sin_coef, cos_coef = np.asarray(sin_coef, dtype=float), np.asarray(cos_coef, dtype=float)
    kmax = sin_coef.shape[0]
    if count <= 2 * kmax:
        raise ValueError(f"{count} samples alias {kmax} harmonics: at least {2 * kmax + 1} needed")
    k = np.arange(1.0, kmax + 1.0)[:, None]
    c, s = np.cos(k * x_start), np.sin(k * x_start)
    spec = np.zeros((count // 2 + 1, sin_coef.shape[1]), dtype=complex)
    spec[1:kmax + 1] = 0.5 * count * ((sin_coef * s + cos_coef * c) - 1j * (sin_coef * c - cos_coef * s))
    return np.fft.irfft(spec, n=count, axis=0)


def series_extrema(sin_coef: np.ndarray, cos_coef: np.ndarray) -> tuple[float, float, float]:
    """(max - min)/2 of Σ_k S_k sin kM + C_k cos kM (k = 1, 2, …, K) over one period of M (one orbit for a
    series in the mean anomaly), and the M of the max and of the min.

    A grid of 64 points per harmonic brackets each extremum; Newton's method on the derivative
    series then polishes it to rounding. The grid is summed by :func:`evaluate_harmonics` in
    blocks: memory stays O(K) whatever K (a dense 64K x K table would take 4.7 GB at e = 0.95).
    """
    sin_coef, cos_coef = np.asarray(sin_coef, dtype=float), np.asarray(cos_coef, dtype=float)
    if sin_coef.size == 0:
        return 0.0, 0.0, 0.0
    k = np.arange(1.0, sin_coef.size + 1.0)
    count = max(256, 64 * sin_coef.size)
    h = 2.0 * math.pi / count
    grid = h * np.arange(count)
    (values,) = evaluate_harmonics(grid, k, sin_coef[:, None], cos_coef[:, None])
    found = []
    for idx, better in ((int(np.argmax(values)), max), (int(np.argmin(values)), min)):
        x0 = x = grid[idx]
        for _ in range(20):
            sk, ck = np.sin(k * x), np.cos(k * x)
            d1 = float(np.sum(k * (sin_coef * ck - cos_coef * sk)))
            d2 = -float(np.sum(k * k * (sin_coef * sk + cos_coef * ck)))
            if d2 == 0.0:
                break
            x = min(max(x - d1 / d2, x0 - h), x0 + h)
            if abs(d1 / d2) < 1e-15:
                break
        polished = float(np.sum(sin_coef * np.sin(k * x) + cos_coef * np.cos(k * x)))
        found.append((x, polished) if better(polished, float(values[idx])) == polished else (x0, float(values[idx])))
    (x_max, v_max), (x_min, v_min) = found
    return 0.5 * (v_max - v_min), x_max, x_min


#: Relative sampling error a :class:`PeriodicTable` built from harmonics aims at: its step h keeps the
#: interpolation error h²/8 Σ k² |c_k| within this fraction of Σ |c_k| (the most the sum can reach).
TABLE_RESOLUTION = 3e-3
#: Bounds on the samples of a :class:`PeriodicTable` over one period (memory and the one-off cost of the table).
TABLE_MIN_SAMPLES, TABLE_MAX_SAMPLES = 64, 16384
#: An interval spanning at most this many table steps is sampled afresh (this many steps, exact values):
#: the table's own samples would cover it too coarsely.
FRESH_STEPS = 16
#: When the interpolation bound of an interval shorter than a period exceeds this fraction of the largest sample,
#: the interval is sampled afresh, finely enough to bring it to that fraction, with at most :data:`MAX_FRESH`
#: points (the exact values cost a sum over the harmonics per point).
REFINE, MAX_FRESH = 0.02, 512


def harmonic_norms(sin_coef: np.ndarray, cos_coef: np.ndarray) -> np.ndarray:
    """|c_k| = sqrt(Σ_d S_kd² + C_kd²) for arrays (K, g, d): per harmonic and group, the most the vector
    S_k sin kx + C_k cos kx can reach (Cauchy-Schwarz), shape (K, g)."""
    return np.sqrt(np.sum(np.square(sin_coef) + np.square(cos_coef), axis=-1))


@dataclass(frozen=True)
class PeriodicTable:
    """A vector function F(x) of period 2π, tabulated on the even grid x_j = x0 + j h (j = 0..N-1, N h = 2π),
    for upper bounds on its largest excursion over an interval of x.

    ``values`` (N, g, d): g groups of d-vectors (e.g. the pole displacement's two components, for several
    series at once); ``curvature`` (g,): a bound on |F''| (Euclidean norm over d) per group; ``at`` evaluates
    F at any x (an array (m,) -> (m, g, d)) to within ``tail`` (the harmonics it leaves out, if any).

    :meth:`interval_max` bounds max over x in [x_lo, x_hi] of |F(x) - ref|. Between two samples a, b (b - a
    <= h) F differs from its linear interpolant L by at most h²/8 sup|F''| (the interpolation error in
    integral form, F - L = -∫ G(x, s) F''(s) ds with G >= 0 and ∫ G ds = (x - a)(b - x)/2), and |L(x) - ref| is
    convex in x, so at most its larger value at a or b: the largest sample plus h²/8 ``curvature`` bounds the
    interval. The interval's ends are evaluated exactly; an interval of at most :data:`FRESH_STEPS` steps is
    sampled afresh at :data:`FRESH_STEPS` + 1 points (or more, :data:`REFINE`), so a short interval is bounded by
    its own values, not by the table's coarser neighbours.
    """

    x0: float
    values: np.ndarray
    curvature: np.ndarray
    at: Callable[[np.ndarray], np.ndarray]
    tail: float = 0.0
    #: |F''| on the grid (N, g) and h²/8 sup|F''''| (g,): for an interval shorter than a period, sup |F''| there is
    #: at most the largest of the grid values around it plus the margin (the interpolation bound applied to F'')
    local: np.ndarray | None = None
    local_margin: np.ndarray | float = 0.0

    @property
    def step(self) -> float:
        return 2.0 * math.pi / self.values.shape[0]

    @classmethod
    def of_harmonics(cls, sin_coef: np.ndarray, cos_coef: np.ndarray, x0: float) -> PeriodicTable:
        """The table of F(x) = Σ_k S_k sin kx + C_k cos kx, k = 1..K, from coefficient arrays (K, g, d).

        The step keeps h²/8 Σ k² |c_k| within :data:`TABLE_RESOLUTION` Σ |c_k| for every group (|c_k| from
        :func:`harmonic_norms`); the curvature is Σ k² |c_k|, which bounds |F''|.
        """
        sin_coef, cos_coef = np.asarray(sin_coef, dtype=float), np.asarray(cos_coef, dtype=float)
        kmax, g, d = sin_coef.shape
        k = np.arange(1.0, kmax + 1.0)
        norms = harmonic_norms(sin_coef, cos_coef)
        reach, curvature = norms.sum(axis=0), (k[:, None] ** 2 * norms).sum(axis=0)
        live = curvature > 0.0
        if live.any():
            h = float(np.min(np.sqrt(8.0 * TABLE_RESOLUTION * reach[live] / curvature[live])))
            count = int(min(TABLE_MAX_SAMPLES, max(TABLE_MIN_SAMPLES, math.ceil(2.0 * math.pi / h))))
        else:
            count = TABLE_MIN_SAMPLES
        count = max(count, 2 * kmax + 2)          # the inverse FFT needs more samples than twice the harmonics
        flat_sin, flat_cos = sin_coef.reshape(kmax, g * d), cos_coef.reshape(kmax, g * d)
        k2 = (k * k)[:, None]
        both = evaluate_harmonics_periodic(x0, count, np.concatenate([flat_sin, -k2 * flat_sin], axis=1),
                                           np.concatenate([flat_cos, -k2 * flat_cos], axis=1))
        values = both[:, :g * d].reshape(count, g, d)
        second = _norm(both[:, g * d:].reshape(count, g, d))
        h = 2.0 * math.pi / count
        margin = h * h / 8.0 * (k[:, None] ** 4 * norms).sum(axis=0)
        return cls(float(x0), values, curvature, harmonic_sum(flat_sin, flat_cos, (g, d)), 0.0, second, margin)

    def curvature_over(self, x_lo: float, x_hi: float) -> np.ndarray:
        """A bound (g,) on |F''| over [x_lo, x_hi]: ``curvature``, or within a period the local one if smaller."""
        n, h = self.values.shape[0], self.step
        if self.local is None or x_hi - x_lo >= 2.0 * math.pi:
            return self.curvature
        j = np.arange(math.floor((x_lo - self.x0) / h), math.ceil((x_hi - self.x0) / h) + 1) % n
        return np.minimum(self.curvature, np.max(self.local[j], axis=0) + self.local_margin)

    def samples(self, x_lo: float, x_hi: float, fresh: int = FRESH_STEPS,
                unwrapped: bool = False) -> tuple[np.ndarray, np.ndarray, float]:
        """Points x, F there (m, g, d) and the largest gap between neighbours, covering [x_lo, x_hi]: the table's
        samples inside and the exact ends, or ``fresh`` + 1 exact points on a short interval (at most
        :data:`FRESH_STEPS` table steps, or any shorter than a period when ``fresh`` exceeds :data:`FRESH_STEPS`).
        An interval longer than a period gives one period of the table or, ``unwrapped``, the first and the last
        period of the interval (where each phase first and last occurs: x_lo to x_lo + 2π and x_hi - 2π to x_hi,
        those four points exact). Tables on the same grid give the same points."""
        n = self.values.shape[0]
        h = self.step
        width = max(0.0, x_hi - x_lo)
        if width >= 2.0 * math.pi:
            if not unwrapped:
                return self.x0 + h * np.arange(n), self.values, h
            first, last = math.ceil((x_lo - self.x0) / h), math.floor((x_hi - self.x0) / h)
            j = np.concatenate([np.arange(first, first + n), np.arange(last - n + 1, last + 1)])
            ends = np.array([x_lo, x_lo + 2.0 * math.pi, x_hi - 2.0 * math.pi, x_hi])
        elif width <= FRESH_STEPS * h or fresh > FRESH_STEPS:
            x = np.linspace(x_lo, x_hi, fresh + 1)
            return x, self.at(x), width / fresh
        else:
            j = np.arange(math.ceil((x_lo - self.x0) / h), math.floor((x_hi - self.x0) / h) + 1)
            ends = np.array([x_lo, x_hi])
        x = self.x0 + h * j
        keep = (x >= x_lo) & (x <= x_hi)
        return np.concatenate([x[keep], ends]), np.concatenate([self.values[j[keep] % n], self.at(ends)]), h

    def interval_max(self, x_lo: float, x_hi: float, ref=None, slope=None) -> np.ndarray:
        """Upper bound (g,) on max over x in [x_lo, x_hi] of |F(x) - ref + slope (x - x0)| (``ref``, ``slope``
        (g, d) or None for 0). A linear term leaves F'' and the interpolation bound unchanged. Over more than a
        period, |F(x) - ref + slope (x - x0)| at one phase is convex in the count of periods, so its largest value
        is where the phase first or last occurs in the interval (:meth:`samples` ``unwrapped``)."""
        ref = 0.0 if ref is None else ref
        curvature = self.curvature_over(x_lo, x_hi)

        def bound(fresh):
            x, samples, spacing = self.samples(x_lo, x_hi, fresh=fresh, unwrapped=slope is not None)
            samples = samples - ref
            if slope is not None:
                samples = samples + (x - self.x0)[:, None, None] * slope
            return np.max(_norm(samples), axis=0), spacing * spacing / 8.0 * curvature

        peak, interpolation = bound(FRESH_STEPS)
        finer = refined_count(x_hi - x_lo, curvature, peak, interpolation)
        if finer:
            peak, interpolation = bound(finer)
        return peak + interpolation + self.tail


def _norm(v: np.ndarray) -> np.ndarray:
    """Euclidean norm over the last axis."""
    return np.hypot(v[..., 0], v[..., 1]) if v.shape[-1] == 2 else np.sqrt(np.sum(v * v, axis=-1))


def refined_count(width: float, curvature, peak, interpolation) -> int | None:
    """Points for sampling an interval (shorter than a period) afresh when its interpolation bound exceeds
    :data:`REFINE` times its largest sample (arrays over groups): spacing sqrt(8 REFINE peak / curvature), at
    most :data:`MAX_FRESH`; None when no group needs it."""
    if width >= 2.0 * math.pi:
        return None
    peak, curvature, interpolation = (np.atleast_1d(np.asarray(x, dtype=float)) for x in (peak, curvature, interpolation))
    need = (interpolation > REFINE * peak) & (peak > 0.0) & (curvature > 0.0)
    if not need.any():
        return None
    h = float(np.min(np.sqrt(8.0 * REFINE * peak[need] / curvature[need])))
    return int(min(MAX_FRESH, max(FRESH_STEPS + 1, math.ceil(width / h))))


def harmonic_sum(sin_coef: np.ndarray, cos_coef: np.ndarray, shape: tuple[int, ...], x0: float = 0.0):
    """x (m,) -> Σ_k S_k sin k(x - x0) + C_k cos k(x - x0), shaped (m, *shape): a direct sum for the few points
    (an interval's ends) a :class:`PeriodicTable` evaluates exactly, where :func:`evaluate_harmonics`' set-up per
    call would cost more than the sum."""
    k = np.arange(1.0, sin_coef.shape[0] + 1.0)

    def at(x):
        arg = np.outer(np.atleast_1d(np.asarray(x, dtype=float)) - x0, k)
        return (np.sin(arg) @ sin_coef + np.cos(arg) @ cos_coef).reshape(arg.shape[0], *shape)

    return at


# ----------------------------------------------------------------------------- integer multiplier rows

def row_codes(k: np.ndarray) -> np.ndarray:
    """One int64 per row of the integer matrix ``k``, ordered as the rows are lexicographically (the first column
    most significant: each column shifted to start at 0 is a digit of a mixed radix). np.unique of these is
    np.unique(k, axis=0)'s order at a fraction of its cost (it sorts rows as opaque bytes)."""
    k = np.asarray(k, dtype=np.int64)
    if k.ndim != 2 or k.shape[1] == 0:
        return np.zeros(k.shape[0] if k.ndim else 0, dtype=np.int64)
    low = k.min(axis=0)
    radix = k.max(axis=0) - low + 1
    if float(np.prod(radix.astype(float))) >= 2.0**62:     # pragma: no cover - multipliers of a few tens
        raise ValueError("multipliers too large to code as one integer")
    codes = np.zeros(k.shape[0], dtype=np.int64)
    for j in range(k.shape[1]):
        codes = codes * radix[j] + (k[:, j] - low[j])
    return codes


def unique_rows(k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """np.unique(k, axis=0, return_inverse=True), the same arrays in the same order, by :func:`row_codes`."""
    _, first, inverse = np.unique(row_codes(k), return_index=True, return_inverse=True)
    return np.asarray(k)[first], inverse.ravel()


def matching_rows(k: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Per row of the integer matrix ``k``, its index in ``table`` (the last if repeated; -1: none), by row codes."""
    k = np.asarray(k, dtype=np.int64).reshape(-1, np.shape(table)[-1] if np.ndim(table) == 2 else 0)
    table = np.asarray(table, dtype=np.int64).reshape(-1, k.shape[1])
    if table.shape[0] == 0 or k.shape[0] == 0:
        return np.full(k.shape[0], -1, dtype=np.intp)
    codes = row_codes(np.concatenate([k, table]))
    want, have = codes[:k.shape[0]], codes[k.shape[0]:]
    by_code = np.argsort(have, kind="stable")
    sorted_codes = have[by_code]
    at = np.searchsorted(sorted_codes, want, side="right") - 1       # the last of equal codes: the latest row
    hit = (at >= 0) & (sorted_codes[np.maximum(at, 0)] == want)
    return np.where(hit, by_code[np.maximum(at, 0)], -1).astype(np.intp)
