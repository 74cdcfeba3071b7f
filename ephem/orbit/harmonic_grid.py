"""Harmonic sums on an even grid with no sin or cos per point: the tracks' and the grids' engine.

Σ_k S_k sin kx + C_k cos kx on the grid x_j = x_start + j x_step (:mod:`ephem.orbit.harmonics` sums at any angles).

:class:`GridHarmonics` fills the sums block by block: for few harmonics (up to
:data:`ephem.orbit.harmonics.MAX_POWER_BASIS_TERMS`, every nutation series of a catalogue body) by
:class:`UniformHarmonics`, one matrix product per block against a table shared by all blocks; for many, cos x
and sin x by angle addition (:func:`uniform_cos_sin`) and the Chebyshev sums of
:class:`ephem.orbit.harmonics.HarmonicSums`. :func:`evaluate_harmonics_uniform` is the whole grid at once.
Angles in radians; the coefficients in any unit (the sums come out in it).
"""
from __future__ import annotations

import math

import numpy as np

from ..base.budget import checkpoint
from .harmonics import BLOCK, BLOCK_BYTES, MAX_POWER_BASIS_TERMS, HarmonicSums

#: points per sub-block of :class:`UniformHarmonics` (its shared table, 2 kmax rows of them, stays in cache)
GRID_SUB = 2048


def angle_sum_into(cos_b, sin_b, cos_a, sin_a, c, s, tmp):
    """(c, s) = cos(a + b), sin(a + b) in place from cos b, sin b and cos a, sin a (arrays or numbers, broadcast);
    ``tmp``: a work array of the result's shape."""
    np.multiply(cos_b, cos_a, out=c)
    np.multiply(sin_b, sin_a, out=tmp)
    c -= tmp
    np.multiply(sin_b, cos_a, out=s)
    np.multiply(cos_b, sin_a, out=tmp)
    s += tmp
    return c, s


def uniform_cos_sin(x_start: float, x_step: float, count: int, block: int = BLOCK, work: np.ndarray | None = None):
    """Yield (start, cos x, sin x) by blocks for x_j = x_start + j x_step, j < count.

    One table of cos/sin(j x_step) within a block and one exact cos/sin per block
    start (angle addition): a few multiplications per epoch instead of two
    trigonometric calls, with rounding at the level of a direct evaluation.
    With ``work`` (at least 3 rows of ``block``), cos x and sin x are written into its rows 0 and 1 (valid until
    the next block) instead of new arrays.
    """
    if count <= 0:
        return
    offsets = x_step * np.arange(min(block, count))
    cos_off, sin_off = np.cos(offsets), np.sin(offsets)
    for start in range(0, count, block):
        m = min(block, count - start)
        a = x_start + x_step * start
        c, s, tmp = (np.empty(m), np.empty(m), np.empty(m)) if work is None else (work[0, :m], work[1, :m], work[2, :m])
        yield start, *angle_sum_into(cos_off[:m], sin_off[:m], math.cos(a), math.sin(a), c, s, tmp)


class UniformHarmonics:
    """Σ_k S[k, j] sin(k x) + C[k, j] cos(k x), k = 1..kmax, on the even grid x_i = x_start + i x_step, i < count,
    by sub-blocks of :attr:`sub` points with no sin or cos per point and no table per block.

    On a sub-block x = x_s + θ_j (θ_j = j x_step, j < sub), harmonic k is cos kθ_j (S sin kx_s + C cos kx_s) +
    sin kθ_j (S cos kx_s - C sin kx_s): the sums of all the sub-blocks are one matrix product of their rotated
    coefficients (one cos and sin of k x_s per harmonic and sub-block) with one table cos kθ_j, sin kθ_j shared by
    every sub-block (kθ by angle addition in k, from one cos and sin of θ_j). For few harmonics (up to
    :data:`ephem.orbit.harmonics.MAX_POWER_BASIS_TERMS`): the coefficients cost 2 kmax sin/cos per sub-block.
    """

    def __init__(self, x_start: float, x_step: float, sin_coef: np.ndarray, cos_coef: np.ndarray, count: int):
        self.x_start, self.x_step = float(x_start), float(x_step)
        self.sin_coef, self.cos_coef = np.asarray(sin_coef, dtype=float), np.asarray(cos_coef, dtype=float)
        kmax = self.sin_coef.shape[0]
        self.k = np.arange(1.0, kmax + 1.0)
        self.sub = max(1, min(GRID_SUB, count, BLOCK_BYTES // (16 * max(kmax, 1))))
        theta = self.x_step * np.arange(self.sub)
        c1, s1 = np.cos(theta), np.sin(theta)
        table = np.empty((2 * kmax, self.sub))       # rows: cos kθ, k = 1..kmax, then sin kθ
        if kmax:
            table[0], table[kmax] = c1, s1
        tmp = np.empty(self.sub)
        for k in range(1, kmax):
            angle_sum_into(table[k - 1], table[kmax + k - 1], c1, s1, table[k], table[kmax + k], tmp)
        self.table = table

    def into(self, start: int, m: int, out: np.ndarray) -> None:
        """The sums at grid points start .. start + m - 1 (``start`` a multiple of :attr:`sub`) into ``out``
        (ncol, m), whose rows are contiguous."""
        sub, ncol = self.sub, self.sin_coef.shape[1]
        if m <= 0:
            return
        if self.k.size == 0:
            out[...] = 0.0
            return
        full, rest = divmod(m, sub)
        x_s = self.x_start + self.x_step * (start + sub * np.arange(full + (rest > 0), dtype=float))
        phase = np.multiply.outer(x_s, self.k)                     # (sub-blocks, kmax)
        ca, sa = np.cos(phase)[:, :, None], np.sin(phase)[:, :, None]
        coef = np.empty((ncol, x_s.size, 2 * self.k.size))
        coef[:, :, :self.k.size] = (ca * self.cos_coef + sa * self.sin_coef).transpose(2, 0, 1)
        coef[:, :, self.k.size:] = (ca * self.sin_coef - sa * self.cos_coef).transpose(2, 0, 1)
        for j in range(ncol):
            row = out[j]
            if full:
                np.matmul(coef[j, :full], self.table, out=row[:full * sub].reshape(full, sub))
            if rest:
                np.matmul(coef[j, full], self.table[:, :rest], out=row[full * sub:])


class GridHarmonics:
    """The sums on the grid x_j = x_start + j x_step, j < count, block by block: :meth:`into` fills the blocks in
    order, each :attr:`block` points (the last fewer). ``multiple`` must be 1..kmax; ``cap``: at most that many
    points per block (rounded down to :class:`UniformHarmonics`' sub-blocks where it serves)."""

    def __init__(self, x_start: float, x_step: float, count: int, multiple: np.ndarray, sin_coef: np.ndarray,
                 cos_coef: np.ndarray, cap: int = BLOCK):
        if len(multiple) <= MAX_POWER_BASIS_TERMS:
            if len(multiple) and not np.array_equal(multiple, np.arange(1, len(multiple) + 1)):
                raise ValueError("multiple must be 1..kmax")
            self.uniform = UniformHarmonics(x_start, x_step, sin_coef, cos_coef, count)
            self.block = self.uniform.sub * max(1, cap // self.uniform.sub)
        else:
            self.uniform = None
            self.sums = HarmonicSums(multiple, sin_coef, cos_coef, count, cap=cap)
            self.block = self.sums.block
            self.angles = uniform_cos_sin(x_start, x_step, count, self.block, np.empty((3, self.block)))

    def into(self, start: int, m: int, out: np.ndarray) -> None:
        """The sums at points start .. start + m - 1, the next block in order, into ``out`` (ncol, m)."""
        if self.uniform is not None:
            self.uniform.into(start, m, out)
        else:
            _, c, s = next(self.angles)
            self.sums.into(c, s, out)


def evaluate_harmonics_uniform(x_start: float, x_step: float, count: int, multiple: np.ndarray,
                               sin_coef: np.ndarray, cos_coef: np.ndarray):
    """As :func:`ephem.orbit.harmonics.evaluate_harmonics` on the grid x_j = x_start + j x_step, j < count (no
    trigonometric call per point: :class:`GridHarmonics`)."""
    sin_coef = np.asarray(sin_coef, dtype=float)
    out = np.zeros((sin_coef.shape[1], count))
    grid = GridHarmonics(x_start, x_step, count, multiple, sin_coef, cos_coef)
    for start in range(0, count, grid.block):
        checkpoint()
        m = min(grid.block, count - start)
        grid.into(start, m, out[:, start:start + m])
    return tuple(out)
