"""Not-a-knot cubic splines on numpy alone: the orbit histories' interpolant, as scipy's ``CubicSpline`` builds it.

The long-term orbits (:mod:`ephem.longterm.nbody_orbit`'s shipped samples, the spin integration's resampled orbit in
:mod:`ephem.longterm.averaged_spin`) are read through not-a-knot cubic splines. ``scipy.interpolate.CubicSpline``
is that spline, but importing ``scipy.interpolate`` loads scipy.special, scipy.optimize, scipy.linalg and
scipy.sparse: 0.3-0.5 s of CPU in a fresh process, more than half of a 4-Myr history answered by the CLI, for a
tridiagonal solve of a few milliseconds. :class:`CubicSpline` is the same spline: the same linear system for the
slopes at the knots (the continuity of the second derivative inside, the third's at the second and the
second-to-last knots), the same polynomial coefficients from them, the same evaluation (scipy's ``PPoly`` sums
``c[3] + c[2] s + c[1] s² + c[0] s³`` in that order, ``s`` the distance from the interval's left knot, the last
interval taking the right end and beyond). The slopes' system is solved without pivoting (Gauss, as LAPACK's banded
solver does on it: its first pivot ties, every later row is diagonally dominant), its two sweeps as
linear recurrences evaluated by a doubling scan (numpy over all the knots at once, log2(n) passes): the slopes agree
with scipy's to a few units of the last place (tests/longterm/test_cubic_spline.py).
"""
from __future__ import annotations

import numpy as np


def _affine_scan(m: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The recurrence x[0] = d[0], x[i] = d[i] + m[i] x[i-1] (``m`` (n,), ``d`` (n, k)) by doubling: after the pass
    of width w each row holds the composition of the last 2w maps; log2(n) passes."""
    x = np.array(d, dtype=float)
    m = np.array(m, dtype=float)
    m[0] = 0.0
    w = 1
    while w < x.shape[0]:
        x[w:] = x[w:] + m[w:, None] * x[:-w]
        m[w:] = m[w:] * m[:-w]
        w *= 2
    return x


def not_a_knot_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The derivatives (n, k) at the knots ``x`` (n,) of the not-a-knot cubic spline through ``y`` (n, k), n >= 4:
    scipy's banded system (row 0 and n-1: the not-a-knot conditions; rows between: the second derivative's
    continuity), solved by Gauss without pivoting."""
    dx = np.diff(x)
    slope = np.diff(y, axis=0) / dx[:, None]
    n = x.size
    sub = np.zeros(n)                  # A[i, i-1]
    diag = np.empty(n)                 # A[i, i]
    sup = np.zeros(n)                  # A[i, i+1]
    rhs = np.empty(y.shape)
    diag[1:-1] = 2.0 * (dx[:-1] + dx[1:])
    sup[1:-1] = dx[:-1]
    sub[1:-1] = dx[1:]
    rhs[1:-1] = 3.0 * (dx[1:, None] * slope[:-1] + dx[:-1, None] * slope[1:])
    d = x[2] - x[0]
    diag[0], sup[0] = dx[1], d
    rhs[0] = ((dx[0] + 2.0 * d) * dx[1] * slope[0] + dx[0] ** 2 * slope[1]) / d
    d = x[-1] - x[-3]
    diag[-1], sub[-1] = dx[-2], d
    rhs[-1] = (dx[-1] ** 2 * slope[-2] + (2.0 * d + dx[-1]) * dx[-2] * slope[-1]) / d
    # the pivots: a recurrence in the knots alone (plain floats: numpy's per-call cost would be 30 times it)
    a, b, c = sub.tolist(), diag.tolist(), sup.tolist()
    pivot = [b[0]] * n
    factor = [0.0] * n
    for i in range(1, n):
        factor[i] = a[i] * (1.0 / pivot[i - 1])
        pivot[i] = b[i] - factor[i] * c[i - 1]
    pivot_arr = np.array(pivot)
    forward = _affine_scan(-np.array(factor), rhs)                       # L z = rhs
    ratio = -sup / pivot_arr
    back = _affine_scan(ratio[::-1], (forward / pivot_arr[:, None])[::-1])   # U s = z, from the last row
    return back[::-1]


class CubicSpline:
    """The not-a-knot cubic spline through ``y`` (n, ...) at the strictly ascending knots ``x`` (n,), n >= 4, along
    the first axis: ``spline(t)`` has shape ``t.shape + y.shape[1:]`` (extrapolated by the end pieces), ``c`` the
    coefficients (4, n-1, ...) of each interval in powers of the distance from its left knot, highest first
    (scipy's ``CubicSpline(x, y, axis=0)`` and its ``c``)."""

    def __init__(self, x, y):
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        if x.ndim != 1 or x.size < 4 or y.shape[:1] != x.shape or not np.all(np.diff(x) > 0.0):
            raise ValueError("a not-a-knot cubic spline takes at least 4 strictly ascending knots and one row of y "
                             "per knot")
        flat = y.reshape(x.size, -1)
        s = not_a_knot_slopes(x, flat)
        dx = np.diff(x)[:, None]
        slope = np.diff(flat, axis=0) / dx
        t = (s[:-1] + s[1:] - 2.0 * slope) / dx
        c = np.stack((t / dx, (slope - s[:-1]) / dx - t, s[:-1], flat[:-1]))
        self.x = x
        self.c = c.reshape((4, x.size - 1) + y.shape[1:])
        self._flat = c
        self._trailing = y.shape[1:]

    @classmethod
    def from_coefficients(cls, x, c) -> "CubicSpline":
        """The spline of the knots ``x`` (n,) and the coefficients ``c`` (4, n-1, ...) another one had (its ``c``:
        kept on disk between processes)."""
        self = cls.__new__(cls)
        self.x = np.asarray(x, dtype=float)
        self.c = np.asarray(c, dtype=float)
        if self.c.shape[:2] != (4, self.x.size - 1):
            raise ValueError(f"coefficients of shape {self.c.shape} for {self.x.size} knots")
        self._flat = self.c.reshape(4, self.x.size - 1, -1)
        self._trailing = self.c.shape[2:]
        return self

    def __call__(self, t, columns=None) -> np.ndarray:
        """The spline at ``t``; ``columns`` (an index or a slice of a 2-D ``y``'s columns): those alone."""
        t = np.asarray(t, dtype=float)
        flat = t.reshape(-1)
        i = np.clip(np.searchsorted(self.x, flat, side="right") - 1, 0, self.x.size - 2)
        s = (flat - self.x[i])[:, None]
        c = (self._flat if columns is None else self._flat[:, :, columns].reshape(4, self.x.size - 1, -1))[:, i]
        s2 = s * s
        out = c[3] + c[2] * s + c[1] * s2 + c[0] * (s2 * s)
        trailing = self._trailing if columns is None else () if isinstance(columns, (int, np.integer)) else out.shape[1:]
        return out.reshape(t.shape + trailing)
