"""Hansen (Cayley) coefficients of the three functions that drive the nutation.

Petit, Souchay & Lhotka (2014, A&A 565, A79, Sect. 3.2, Eqs. 14-18; after
Hughes 1981) expand functions of the true anomaly ``nu`` of a Keplerian orbit
in Fourier series of the mean anomaly ``M``::

    (a/r)^3             = sum_{k>=0} c0_k(e) cos kM
    (a/r)^3 cos 2nu     = sum_{k>=0} c2_k(e) cos kM
    (a/r)^3 sin 2nu     = sum_{k>=1} s2_k(e) sin kM

With the Hansen coefficients ``X_n = X_n^{-3,2}(e)`` of
``(a/r)^3 exp(2i nu) = sum_n X_n exp(i n M)`` (all real) one has
``c2_k = X_k + X_{-k}`` and ``s2_k = X_k - X_{-k}`` for ``k >= 1``,
``c2_0 = X_0`` (which is exactly 0) and ``s2_0 = 0``.

Two independent ways to get them:

* :func:`hansen_exact` -- numerical, to machine precision, any ``0 <= e < 1``
  (FFT over ``M`` of the exact functions, Kepler's equation solved to
  round-off).
* :func:`hansen_series` -- the classical expansions in powers of ``e`` with
  exact rational coefficients, built here from the Bessel-function series of
  ``a/r``, ``cos nu`` and ``sin nu`` (Brouwer & Clemence 1961, Ch. II), not
  transcribed from tables.  As every power series in ``e`` of functions of
  ``M``, they converge only for ``e`` below the Laplace limit 0.6627434...

Everything here is plain floats / numpy arrays / ``fractions.Fraction``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from types import MappingProxyType
from typing import Mapping

import numpy as np

from ..base.budget import checkpoint
from ..base.errors import InvalidInputError
from .kepler import solve_kepler

__all__ = [
    "HansenCoefficients",
    "HansenSeries",
    "LAPLACE_LIMIT",
    "hansen_exact",
    "hansen_series",
]

#: Radius of convergence in ``e`` of the power series of Keplerian functions
#: of the mean anomaly (the Laplace limit, root of x exp(sqrt(1+x^2)) =
#: 1 + sqrt(1+x^2)).
LAPLACE_LIMIT = 0.6627434193491816

#: Relative size below which a coefficient is treated as zero (default kmax)
#: and below which the aliasing error of the FFT is kept.
_REL_TOL = 1e-16
#: Largest FFT length :func:`hansen_exact` accepts (2**23 samples: a few
#: seconds and ~0.5 GB of transient arrays; reached for e ~ 0.99898).
_MAX_SAMPLES = 2**23
#: Smallest default kmax.
_MIN_KMAX = 6


# ---------------------------------------------------------------------------
# Result containers
# ---------------------------------------------------------------------------

def _frozen_array(values, dtype=float) -> np.ndarray:
    array = np.array(values, dtype=dtype)
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class HansenCoefficients:
    """Fourier coefficients of ``(a/r)^3`` and ``(a/r)^3 exp(2i nu)`` in ``M``.

    ``k`` is ``0..kmax``; ``c0[k]``, ``c2[k]``, ``s2[k]`` are the coefficients
    of ``cos kM`` in ``(a/r)^3`` and in ``(a/r)^3 cos 2nu`` and of ``sin kM``
    in ``(a/r)^3 sin 2nu`` (``s2[0] == 0``).  Arrays are read-only.
    """

    e: float
    k: np.ndarray
    c0: np.ndarray
    c2: np.ndarray
    s2: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "k", _frozen_array(self.k, dtype=np.int64))
        for name in ("c0", "c2", "s2"):
            object.__setattr__(self, name, _frozen_array(getattr(self, name)))

    @property
    def kmax(self) -> int:
        """Highest harmonic held."""
        return int(self.k[-1])

    def synthesize(self, M) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Sum the three Fourier series at mean anomalies ``M`` (radians).

        Returns ``((a/r)^3, (a/r)^3 cos 2nu, (a/r)^3 sin 2nu)`` as arrays of
        the shape of ``M``; exact up to the harmonics dropped beyond ``kmax``.
        """
        M = np.asarray(M, dtype=float)
        # Reduce to [-pi, pi] first: the rounding of k*M then stays at the
        # problem's own conditioning (|M f'(M)| eps), small near pericentre.
        M = M - 2.0 * np.pi * np.round(M / (2.0 * np.pi))
        phase = np.multiply.outer(M, self.k)
        cos_kM, sin_kM = np.cos(phase), np.sin(phase)
        return cos_kM @ self.c0, cos_kM @ self.c2, sin_kM @ self.s2


@dataclass(frozen=True, eq=False)
class HansenSeries:
    """The three families as polynomials in ``e`` truncated after ``e**order``.

    ``c0[k]``, ``c2[k]``, ``s2[k]`` (``k = 0..order+2``) are tuples of
    ``order + 1`` :class:`fractions.Fraction`, the coefficients of
    ``e**0 .. e**order``.  Harmonics ``k > order + 2`` vanish at this order.
    Valid (convergent as ``order`` grows) for ``e`` below
    :data:`LAPLACE_LIMIT`; the truncation error at ``e`` behaves like
    ``order * (e / LAPLACE_LIMIT)**order`` (see :func:`hansen_series`).
    """

    order: int
    c0: Mapping[int, tuple[Fraction, ...]]
    c2: Mapping[int, tuple[Fraction, ...]]
    s2: Mapping[int, tuple[Fraction, ...]]

    def truncated(self, order: int) -> HansenSeries:
        """The series to a lower ``order``: the coefficient of e^j does not depend on where a
        power series is cut, so this equals :func:`hansen_series` at that order."""
        if not 0 <= order <= self.order:
            raise ValueError(f"order must lie in [0, {self.order}], got {order}")

        def cut(family):
            return MappingProxyType({k: family[k][:order + 1] for k in range(order + 3)})
        return HansenSeries(order=order, c0=cut(self.c0), c2=cut(self.c2), s2=cut(self.s2))

    def evaluate(self, e: float) -> HansenCoefficients:
        """Evaluate every polynomial at ``e`` (floats, Horner's scheme)."""
        e = _check_eccentricity(e)
        ks = range(self.order + 3)
        return HansenCoefficients(
            e=e,
            k=np.arange(self.order + 3),
            c0=[_horner(self.c0[k], e) for k in ks],
            c2=[_horner(self.c2[k], e) for k in ks],
            s2=[_horner(self.s2[k], e) for k in ks],
        )


def _horner(coefficients: tuple[Fraction, ...], x: float) -> float:
    total = 0.0
    for c in reversed(coefficients):
        total = total * x + float(c)
    return total


def _check_eccentricity(e) -> float:
    """Return ``e`` as a float, or raise if it is not an elliptic eccentricity."""
    try:
        value = float(e)
    except (TypeError, ValueError):
        raise InvalidInputError("e", f"eccentricity must be a real number, got {e!r}") from None
    if math.isnan(value):
        raise InvalidInputError("e", "eccentricity is NaN; need 0 <= e < 1")
    if value < 0.0:
        raise InvalidInputError("e", f"eccentricity must be >= 0, got e={value!r}")
    if value >= 1.0:
        raise InvalidInputError(
            "e", f"eccentricity must be < 1 (elliptic orbit), got e={value!r}")
    return value


# ---------------------------------------------------------------------------
# Exact coefficients: FFT over the mean anomaly
# ---------------------------------------------------------------------------

def decay_rate(e: float) -> float:
    """``sigma`` in ``|X_k| ~ exp(-sigma k)`` for Fourier series in ``M``.

    The functions are analytic in ``M`` in the strip ``|Im M| < sigma`` bounded
    by the zeros of ``r``: ``cos E = 1/e``, i.e. ``E = i arccosh(1/e)`` and
    ``sigma = arccosh(1/e) - sqrt(1 - e^2)``.  (Note ``exp(-sigma) =
    rho exp(sqrt(1-e^2))`` with ``rho = e / (1 + sqrt(1-e^2))``: the decay in
    ``M`` is slower than ``rho**k``, which is the decay in ``E`` or ``nu``.)
    ``sigma -> (1-e^2)^(3/2)/3`` as ``e -> 1``.
    """
    if e == 0.0:
        return math.inf
    s = math.sqrt((1.0 - e) * (1.0 + e))
    return math.log((1.0 + s) / e) - s


def exact_unavailable(e: float) -> str | None:
    """Why the exact coefficients cannot be had at ``e`` (None: they can). As e -> 1 the significant
    harmonics grow like (1-e²)^(-3/2): past e ~ 0.999 they would need more than ``_MAX_SAMPLES``."""
    try:
        fft_length(e, None)
    except InvalidInputError as exc:
        return (f"e = {e:.6g} is too close to 1 for the Fourier series of the solar torque in the mean anomaly: "
                f"{exc.reason}; the pericentre passage is too brief for an averaged theory")
    return None


def fft_length(e: float, kmax: int | None) -> int:
    """Power-of-two sample count making aliasing negligible (< 1e-16 relative).

    With ``|X_n| <~ n^(3/2) exp(-sigma n)`` (``(a/r)^3 ~ (M - M_s)^(-3/2)`` at
    the singularity), the harmonics above 1e-18 of the largest are
    ``|n| <= K`` with ``sigma K - 1.5 ln K = ln(1e18)``.  Taking ``N >= 4 K``
    puts their aliases beyond ``3 K`` and leaves the top half of the returned
    harmonics (``K <= n < N/2``) pure round-off, which :func:`hansen_exact`
    uses to measure its noise floor.  Checked: doubling ``N`` changes the
    coefficients by < 4e-16 of the largest for e = 0.1 ... 0.99.
    """
    N = _sample_count(float(e)) if kmax is None else \
        max(_sample_count(float(e)), 1 << max(5, math.ceil(math.log2(4.0 * kmax + 4.0))))
    if N > _MAX_SAMPLES:
        raise InvalidInputError(
            "e", f"eccentricity e={e!r} is too close to 1 for kmax={kmax!r}: "
            f"machine-precision coefficients would need {N} FFT samples "
            f"(limit {_MAX_SAMPLES})")
    return N


@lru_cache(maxsize=1024)    # every request prices its Hansen coefficients by it: ~50 us a call, the same e each time
def _sample_count(e: float) -> int:
    return int(_sample_counts(np.array([e]))[0])


def _sample_counts(e: np.ndarray) -> np.ndarray:
    """:func:`fft_length`'s N (without a requested kmax) for each eccentricity of ``e`` (vectorised): the K with
    sigma K - 1.5 ln K >= ln(1e18), grown by 5 % steps from ln(1e18)/sigma, then N >= 4K + 4 (a power of two,
    at least 32)."""
    e = np.asarray(e, dtype=float)
    s = np.sqrt((1.0 - e) * (1.0 + e))
    # log(1 + s) - log(e): no overflow for a subnormal e, where (1 + s)/e would be
    sigma = np.where(e > 0.0, np.log1p(s) - np.log(np.where(e > 0.0, e, 1.0)) - s, np.inf)
    target = math.log(1e18)
    finite = np.isfinite(sigma)
    K = np.where(finite, target / np.where(finite, sigma, 1.0), float(_MIN_KMAX))
    short = finite & (sigma * K - 1.5 * np.log(K) < target)
    while short.any():
        K = np.where(short, K * 1.05, K)
        short = finite & (sigma * K - 1.5 * np.log(K) < target)
    K = np.maximum(K, _MIN_KMAX)
    return 1 << np.maximum(5, np.ceil(np.log2(4.0 * K + 4.0)).astype(int))


def _sample_functions(e, N: int) -> tuple[np.ndarray, np.ndarray]:
    """``(a/r)^3`` and ``(a/r)^3 exp(2i nu)`` at ``M_j = 2 pi j / N``.

    Samples ``j >= N/2`` are taken at the equivalent ``2 pi (j - N) / N`` so
    that ``M`` near pericentre (where the functions are steepest) carries no
    ``2 pi``-sized rounding error; as the first is even in ``M`` and the second
    its conjugate at ``-M`` (E and nu odd), they are those of ``j' = N - j``
    mirrored, computed once: half the Kepler solves, the same numbers to the
    bit. ``e`` may be a column (B, 1) of eccentricities: rows of samples, one
    orbit each.
    """
    half_n = N // 2
    M = 2.0 * np.pi * np.arange(half_n + 1) / N          # 0 .. pi
    E = solve_kepler(M, e)
    half = np.sin(0.5 * E)
    r_over_a = (1.0 - e) + 2.0 * e * half**2           # 1 - e cos E
    x = (1.0 - e) - 2.0 * half**2                       # cos E - e  (= r/a cos nu)
    y = np.sqrt((1.0 - e) * (1.0 + e)) * np.sin(E)      # r/a sin nu
    inv3 = r_over_a ** -3
    f = (x + 1j * y) ** 2 * inv3 / r_over_a**2
    mirror = slice(half_n, 0, -1)                       # j = N/2 .. N-1 take j' = N - j = N/2 .. 1
    return (np.concatenate((inv3[..., :half_n], inv3[..., mirror]), axis=-1),
            np.concatenate((f[..., :half_n], np.conj(f[..., mirror])), axis=-1))


@lru_cache(maxsize=32)      # immutable results; a model's build asks three times (its mean-pole iteration)
def hansen_exact(e: float, kmax: int | None = None) -> HansenCoefficients:
    """Coefficients ``c0, c2, s2`` to machine precision for any ``0 <= e < 1``.

    Method: the two functions are sampled on ``N`` (a power of two) uniformly
    spaced mean anomalies, Kepler's equation being solved to round-off
    (:func:`solve_kepler`), and Fourier-analysed by FFT.  ``N`` is chosen from
    the analyticity strip of the functions in ``M`` (:func:`decay_rate`) so
    that aliasing is below 1e-16 relative; what remains is round-off, a few
    1e-16 of the largest coefficient (measured: doubling ``N`` moves no
    coefficient by more than 4e-16 of the largest, e = 0.1 ... 0.99).

    Validity and cost: any ``0 <= e < 1`` in principle; the number of
    significant harmonics grows like ``(1-e^2)^(-3/2)``: ``N = 512`` (kmax
    ~ 95) at ``e = 0.5``, 8192 (kmax ~ 1360) at 0.9, 2.6e5 (kmax ~ 45000) at
    0.99.  ``e`` needing more than 2**23 samples (``e > 0.99898``) is
    refused with :class:`ValueError` rather than run for minutes.

    ``kmax`` defaults to the last ``k`` at which some coefficient exceeds
    both 1e-16 times the largest one in magnitude and the FFT round-off
    noise (measured on harmonics known to be negligible), and is at least 6.
    A larger ``kmax`` may be requested (the FFT is lengthened accordingly);
    coefficients past the default are round-off noise.

    Raises :class:`ValueError` (:class:`ephem.base.errors.InvalidInputError` naming
    ``e``) for NaN, negative or ``e >= 1``, and for a negative ``kmax``.
    """
    e = _check_eccentricity(e)
    if kmax is not None and (int(kmax) != kmax or kmax < 0):
        raise InvalidInputError("kmax", f"must be a non-negative integer, got {kmax!r}")
    N = fft_length(e, None if kmax is None else int(kmax))
    checkpoint()        # the service's: the FFT is the large step of an eccentric orbit's answer

    c0, c2, s2 = _fourier_coefficients(*_sample_functions(e, N))
    if kmax is None:
        kmax = int(_significant_kmax(c0, c2, s2))
    kmax = int(kmax)
    return HansenCoefficients(e=e, k=np.arange(kmax + 1),
                              c0=c0[:kmax + 1], c2=c2[:kmax + 1], s2=s2[:kmax + 1])


def _fourier_coefficients(g: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """c0, c2, s2 for k = 0 .. N/2 - 1 from the samples of :func:`_sample_functions` (the last axis: N samples)."""
    N = g.shape[-1]
    G = np.fft.rfft(g, axis=-1) / N      # G[n]: coefficient of exp(i n M) in (a/r)^3
    F = np.fft.fft(f, axis=-1) / N       # F[n], F[N - n]: X_n, X_{-n}
    half = N // 2
    X_pos = F[..., :half].real                              # X_0 .. X_{N/2-1}
    X_neg = np.concatenate((np.zeros(F.shape[:-1] + (1,)), F[..., :-half:-1].real), axis=-1)  # 0, X_-1 ..
    c0 = 2.0 * G[..., :half].real
    c0[..., 0] = G[..., 0].real
    c2 = X_pos + X_neg
    c2[..., 0] = X_pos[..., 0]
    s2 = X_pos - X_neg
    s2[..., 0] = 0.0
    return c0, c2, s2


def fft_lengths(e) -> np.ndarray:
    """:func:`fft_length`'s N (no kmax, no limit) for each eccentricity of ``e`` (vectorised), as
    :func:`hansen_exact_many` groups a population by it: what a population's cost counts before the work."""
    return _sample_counts(np.asarray(e, dtype=float))


def exact_available(e) -> np.ndarray:
    """Whether the exact coefficients can be had at each eccentricity of ``e`` (the vectorised
    :func:`exact_unavailable`: no more than 2**23 FFT samples)."""
    return _sample_counts(np.asarray(e, dtype=float)) <= _MAX_SAMPLES


def hansen_exact_many(e) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """:func:`hansen_exact` for a population: ``e`` an array; returns one group per FFT length, each
    (indices into ``e``, k, c0, c2, s2) with the coefficients as rows (len(indices), kmax + 1) and kmax the
    group's largest significant one (a row's coefficients past its own are round-off, ~1e-16 of its largest).
    Vectorised over the bodies of a group: one Kepler solve and one FFT per group, not per body. Validity as
    :func:`hansen_exact`: ``e`` needing more than 2**23 samples is the caller's to refuse
    (:func:`exact_unavailable`)."""
    e = np.asarray(e, dtype=float)
    counts = _sample_counts(e)
    groups = []
    for N in np.unique(counts):
        rows = np.nonzero(counts == N)[0]
        # rows in chunks of about 2**15 samples: arrays that stay in the cache run several times faster
        step = max(1, (1 << 15) // int(N))
        parts = []
        for start in range(0, rows.size, step):
            checkpoint()
            parts.append(_fourier_coefficients(*_sample_functions(e[rows[start:start + step], None], int(N))))
        c0, c2, s2 = (np.concatenate([p[i] for p in parts]) for i in range(3))
        kmax = int(_significant_kmax(c0, c2, s2).max())
        groups.append((rows, np.arange(kmax + 1), c0[:, :kmax + 1], c2[:, :kmax + 1], s2[:, :kmax + 1]))
    return groups


def _significant_kmax(*families: np.ndarray):
    """Last ``k`` where some family exceeds both 1e-16 of the largest value
    and the round-off noise, taken as the largest magnitude over the top half
    of the harmonics (negligible by the choice of ``N``, see
    :func:`fft_length`); at least 6. Families of rows (B, K) give one per row."""
    magnitude = np.abs(families[0])
    for family in families[1:]:
        magnitude = np.maximum(magnitude, np.abs(family))
    half = magnitude.shape[-1] // 2
    noise = magnitude[..., half:].max(axis=-1)
    threshold = np.maximum(_REL_TOL * magnitude.max(axis=-1), noise)
    above = magnitude > threshold[..., None]
    last = np.where(above.any(axis=-1), magnitude.shape[-1] - 1 - np.argmax(above[..., ::-1], axis=-1), 0)
    return np.maximum(last, _MIN_KMAX)


# ---------------------------------------------------------------------------
# Series in powers of e with exact rational coefficients
# ---------------------------------------------------------------------------
#
# A truncated "Poisson series" is a dict {(n, j): Fraction}: the coefficient of
# e**j * exp(i n M).  All coefficients involved are real.  A univariate power
# series in e is a list of Fractions (index = power of e).

def _bessel_kx(k: int, order: int) -> list[Fraction]:
    """``J_k(k e)`` as a power series in ``e`` up to ``e**order``."""
    out = [Fraction(0)] * (order + 1)
    half_k = Fraction(k, 2)
    s = 0
    while k + 2 * s <= order:
        out[k + 2 * s] = ((-1) ** s * half_k ** (k + 2 * s)
                          / (math.factorial(s) * math.factorial(k + s)))
        s += 1
    return out


def _bessel_kx_prime(k: int, order: int) -> list[Fraction]:
    """``J_k'(x)`` at ``x = k e`` as a power series in ``e`` up to ``e**order``.

    ``J_k(x) = sum_s (-1)^s (x/2)^(k+2s) / (s! (k+s)!)``, differentiated term by
    term: ``d/dx (x/2)^m = (m/2) (x/2)^(m-1)``.
    """
    out = [Fraction(0)] * (order + 1)
    half_k = Fraction(k, 2)
    s = 0
    while k + 2 * s - 1 <= order:
        m = k + 2 * s
        out[m - 1] = ((-1) ** s * Fraction(m, 2) * half_k ** (m - 1)
                      / (math.factorial(s) * math.factorial(k + s)))
        s += 1
    return out


def _sqrt_one_minus_e2(order: int) -> list[Fraction]:
    """``sqrt(1 - e^2) = sum_s binom(1/2, s) (-e^2)^s`` up to ``e**order``."""
    out = [Fraction(0)] * (order + 1)
    binom = Fraction(1)
    for s in range(order // 2 + 1):
        out[2 * s] = binom * (-1) ** s
        binom = binom * (Fraction(1, 2) - s) / (s + 1)
    return out


def _mul_univariate(a: list[Fraction], b: list[Fraction]) -> list[Fraction]:
    order = len(a) - 1
    out = [Fraction(0)] * (order + 1)
    for i, ai in enumerate(a):
        if ai:
            for j in range(order + 1 - i):
                if b[j]:
                    out[i + j] += ai * b[j]
    return out


def _add_term(series: dict, n: int, coefficients: list[Fraction]) -> None:
    for j, c in enumerate(coefficients):
        if c:
            series[(n, j)] = series.get((n, j), Fraction(0)) + c


def _mul_poisson(a: dict, b: dict, order: int) -> dict:
    """Product of two Poisson series, dropping powers of e above ``order``."""
    out: dict = {}
    for (na, ja), ca in a.items():
        for (nb, jb), cb in b.items():
            if ja + jb <= order:
                key = (na + nb, ja + jb)
                out[key] = out.get(key, Fraction(0)) + ca * cb
    return {key: c for key, c in out.items() if c}


def _a_over_r(order: int) -> dict:
    """``a/r = 1 + 2 sum_k J_k(ke) cos kM`` (Brouwer & Clemence, Ch. II)."""
    series: dict = {(0, 0): Fraction(1)}
    for k in range(1, order + 1):
        bessel = _bessel_kx(k, order)
        _add_term(series, k, bessel)
        _add_term(series, -k, bessel)
    return series


def _exp_i_nu(order: int) -> dict:
    """``exp(i nu) = cos nu + i sin nu`` from the Bessel series

    ``cos nu = -e + 2 (1-e^2)/e sum_k J_k(ke) cos kM`` and
    ``sin nu = 2 sqrt(1-e^2) sum_k J_k'(ke) sin kM`` (Brouwer & Clemence,
    Ch. II), so the coefficient of ``exp(+-ikM)`` is
    ``(1-e^2)/e J_k(ke) +- sqrt(1-e^2) J_k'(ke)``.
    The coefficient of ``exp(i n M)`` is ``O(e^|n-1|)``, hence ``k <= order+1``.
    """
    one_minus_e2 = [Fraction(0)] * (order + 1)
    one_minus_e2[0] = Fraction(1)
    if order >= 2:
        one_minus_e2[2] = Fraction(-1)
    root = _sqrt_one_minus_e2(order)
    series: dict = {}
    _add_term(series, 0, [Fraction(0), Fraction(-1)][: order + 1])
    for k in range(1, order + 2):
        bessel_over_e = _bessel_kx(k, order + 1)[1:]     # J_k(ke)/e, k >= 1
        cos_part = _mul_univariate(one_minus_e2, bessel_over_e)
        sin_part = _mul_univariate(root, _bessel_kx_prime(k, order))
        _add_term(series, k, [c + s for c, s in zip(cos_part, sin_part)])
        _add_term(series, -k, [c - s for c, s in zip(cos_part, sin_part)])
    return {key: c for key, c in series.items() if c}


def _coefficients_in_e(series: dict, n: int, order: int) -> list[Fraction]:
    return [series.get((n, j), Fraction(0)) for j in range(order + 1)]


#: Orders up to this are cut from one series built to it (0.15 s once) rather than built one by one:
#: the fidelity ladder asks for every order from 0 up.
_SHARED_ORDER = 20


@lru_cache(maxsize=None)
def hansen_series(order: int) -> HansenSeries:
    """Expansions of ``c0_k, c2_k, s2_k`` in powers of ``e`` up to ``e**order``.

    Exact rational coefficients (``fractions.Fraction``) for ``k = 0..order+2``,
    computed by truncated power-series arithmetic: ``(a/r)^3`` is the cube of
    the Bessel series of ``a/r`` and ``(a/r)^3 exp(2i nu)`` its product with
    the square of the Bessel series of ``exp(i nu)`` (see :func:`_exp_i_nu`).
    Order 4 gives Petit et al. (2014) Eqs. 16-18 and 23-25.

    Validity: the series converge only for ``e < LAPLACE_LIMIT`` (0.6627...).
    The largest error over all harmonics of the order-``N`` truncation stays
    below ``N (e / 0.6627)**N`` (measured for e <= 0.5, N <= 30; the
    geometric rate is the radius of convergence, the factor N empirical):
    at N = 20 it is 4e-7 at e = 0.28 (the highest harmonics, k ~ 19-22, carry
    only one or two powers of e; harmonics k <= 10 are good to 2e-11) and
    0.06 at e = 0.5.  Use :func:`hansen_exact` when that is not enough.
    Cost: ~0.15 s for order 20, ~0.7 s for order 30; the result is cached.
    Raises :class:`ValueError` for a negative or non-integer ``order``.
    """
    if int(order) != order or order < 0:
        raise InvalidInputError("order", f"must be a non-negative integer, got {order!r}")
    order = int(order)
    if order < _SHARED_ORDER:
        return hansen_series(_SHARED_ORDER).truncated(order)
    a_over_r = _a_over_r(order)
    cube = _mul_poisson(_mul_poisson(a_over_r, a_over_r, order), a_over_r, order)
    w = _exp_i_nu(order)
    f = _mul_poisson(cube, _mul_poisson(w, w, order), order)

    zero = tuple([Fraction(0)] * (order + 1))
    c0: dict[int, tuple[Fraction, ...]] = {}
    c2: dict[int, tuple[Fraction, ...]] = {}
    s2: dict[int, tuple[Fraction, ...]] = {}
    for k in range(order + 3):
        y = _coefficients_in_e(cube, k, order)
        x_plus = _coefficients_in_e(f, k, order)
        x_minus = _coefficients_in_e(f, -k, order)
        if k == 0:
            c0[k] = tuple(y)
            c2[k] = tuple(x_plus)
            s2[k] = zero
        else:
            c0[k] = tuple(2 * c for c in y)
            c2[k] = tuple(p + m for p, m in zip(x_plus, x_minus))
            s2[k] = tuple(p - m for p, m in zip(x_plus, x_minus))
    return HansenSeries(order=order, c0=MappingProxyType(c0),
                        c2=MappingProxyType(c2), s2=MappingProxyType(s2))
