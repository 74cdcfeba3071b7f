"""Harmonic sums Σ_k S_k sin kx + C_k cos kx, k = 1..K, at many angles x: the engine the theories' series run on.

:func:`evaluate_harmonics` sums at any angles and :func:`evaluate_harmonics_uniform` on an even grid
(angle addition, :func:`uniform_cos_sin`: no trigonometric call per epoch); both take one sin and one
cos of x per epoch and build the harmonics from Chebyshev polynomials of cos x (a power table and one
matrix product per cache-sized block, or the three-term recurrence for many harmonics), never a sin/cos
per harmonic, in blocks whose work table stays under :data:`BLOCK_BYTES` whatever the harmonics and the
epochs. :func:`cos_sin_shifted` moves cos x, sin x by a small angle (below :data:`MAX_SHIFT`) without a
trigonometric call; :func:`series_extrema` finds the half peak-to-peak excursion of a sum over a period.

Angles in radians; the coefficients in any unit (the sums come out in it). Nothing here is one theory's:
Kinoshita's nutation series (:mod:`ephem.kinoshita`) and the model's tracks (:mod:`ephem.model`) use it.
"""
from __future__ import annotations

import math

import numpy as np

from .budget import checkpoint

#: Epochs per block in the evaluators: small enough to stay in cache.
_BLOCK = 8192
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
_MAX_POWER_BASIS_TERMS = 48


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
        out[:, j] = chebyshev.cheb2poly(np.concatenate([[0.0], cos_coef[:, j]]))
        out[:, ncol + j] = sum(sin_coef[k, j] * u_list[k] for k in range(kmax))
    return out


def _sum_block(c: np.ndarray, s: np.ndarray, kmax: int, power_coef: np.ndarray | None,
               sin_coef: np.ndarray, cos_coef: np.ndarray, out: np.ndarray, work: np.ndarray) -> None:
    """Harmonic sums for one block, given c = cos x and s = sin x; writes out (ncol, m)."""
    m = c.size
    ncol = sin_coef.shape[1]
    if power_coef is not None:
        pw = work[: kmax + 1, :m]  # rows: 1, c, c², … (contiguous)
        pw[0] = 1.0
        pw[1] = c
        for k in range(2, kmax + 1):
            np.multiply(pw[k - 1], c, out=pw[k])
        r = power_coef.T @ pw  # (2 ncol, m): P's rows then Q's
        np.multiply(r[ncol:], s, out=r[ncol:])
        np.add(r[:ncol], r[ncol:], out=out)
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


def _prepare(multiple, sin_coef, cos_coef, count: int = _BLOCK):
    """(kmax, the power basis or None, the work table, the epochs per block) for ``count`` epochs."""
    kmax = len(multiple)
    if kmax and not np.array_equal(multiple, np.arange(1, kmax + 1)):
        raise ValueError("multiple must be 1..kmax")
    power = None
    if 0 < kmax <= _MAX_POWER_BASIS_TERMS:
        candidate = _power_basis(multiple, sin_coef, cos_coef)
        scale = np.abs(sin_coef).sum() + np.abs(cos_coef).sum()
        if np.abs(candidate).sum() <= _MAX_POWER_BASIS_GROWTH * scale:
            power = candidate
    width = max(kmax + 1 if power is not None else 2 * kmax, 1)
    block = max(1, min(_BLOCK, count, BLOCK_BYTES // (8 * width)))
    return kmax, power, np.empty((width, block)), block


def evaluate_harmonics(angle, multiple: np.ndarray, sin_coef: np.ndarray, cos_coef: np.ndarray):
    """Σ_k S[k, j] sin(k x) + C[k, j] cos(k x) for each output column j, at any angles x.

    ``multiple`` must be 1, 2, …, kmax. One sin and one cos of x per epoch; the
    harmonics come from Chebyshev polynomials of cos x (a power table and one
    matrix product per cache-sized block, or the three-term recurrence for many
    harmonics) — never a sin/cos per harmonic. Returns arrays shaped like x.
    """
    x = np.asarray(angle, dtype=float)
    flat = x.ravel()
    ncol = sin_coef.shape[1]
    out = np.zeros((ncol, flat.size))
    kmax, power, work, block = _prepare(multiple, sin_coef, cos_coef, flat.size)
    if kmax:
        for start in range(0, flat.size, block):
            checkpoint()
            xb = flat[start:start + block]
            _sum_block(np.cos(xb), np.sin(xb), kmax, power, sin_coef, cos_coef, out[:, start:start + xb.size], work)
    return tuple(out[j].reshape(x.shape) for j in range(ncol))


def uniform_cos_sin(x_start: float, x_step: float, count: int, block: int = _BLOCK):
    """Yield (start, cos x, sin x) by blocks for x_j = x_start + j x_step, j < count.

    One table of cos/sin(j x_step) within a block and one exact cos/sin per block
    start (angle addition): a few multiplications per epoch instead of two
    trigonometric calls, with rounding at the level of a direct evaluation.
    """
    if count <= 0:
        return
    offsets = x_step * np.arange(min(block, count))
    cos_off, sin_off = np.cos(offsets), np.sin(offsets)
    for start in range(0, count, block):
        m = min(block, count - start)
        a = x_start + x_step * start
        ca, sa = math.cos(a), math.sin(a)
        cb, sb = cos_off[:m], sin_off[:m]
        yield start, cb * ca - sb * sa, sb * ca + cb * sa


def cos_sin_shifted(cos_x, sin_x, delta):
    """cos and sin of x + δ from cos x, sin x and a small δ (|δ| <= 0.01 rad).

    Taylor series of cos δ and sin δ to δ^6 and δ^5: truncation below 3e-18.
    """
    d2 = delta * delta
    sd = delta * (1.0 - d2 * (1.0 / 6.0 - d2 / 120.0))
    cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0 - d2 / 720.0))
    return cos_x * cd - sin_x * sd, sin_x * cd + cos_x * sd


#: Largest |δ| (radians) for :func:`cos_sin_shifted`.
MAX_SHIFT = 0.01


def evaluate_harmonics_uniform(x_start: float, x_step: float, count: int, multiple: np.ndarray,
                               sin_coef: np.ndarray, cos_coef: np.ndarray):
    """As :func:`evaluate_harmonics` on the grid x_j = x_start + j x_step, j < count.

    cos and sin of x come from :func:`uniform_cos_sin` (no trigonometric call per epoch).
    """
    ncol = sin_coef.shape[1]
    out = np.zeros((ncol, count))
    kmax, power, work, block = _prepare(multiple, sin_coef, cos_coef, count)
    if kmax:
        for start, c, s in uniform_cos_sin(x_start, x_step, count, block):
            checkpoint()
            _sum_block(c, s, kmax, power, sin_coef, cos_coef, out[:, start:start + c.size], work)
    return tuple(out[j] for j in range(ncol))


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
