"""The Moon's free librations about its Cassini state: the periods of the linearised system's free modes.

The free modes are the Floquet exponents of the F-chain operator that :mod:`ephem.moon.libration_chains` solves
with (eq. (3) of :mod:`ephem.moon.physical_librations`'s docstring, "Solution": they sit where the chain matrix is
singular), about the Cassini state of the series :func:`ephem.moon.physical_librations.moon_physical_librations`
solves: the libration in longitude, the free libration in latitude and the free wobble. Days.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..orbit.lunar import delaunay_rates
from .libration_chains import chain_operator
from .libration_forcing import torus_fields
from .physical_librations import DEFAULT_GRID, moments_over_c, moon_physical_librations


@dataclass(frozen=True)
class FreeModes:
    """The free librations of the linearised system about the Cassini state (periods in days): the Floquet
    exponents of the F-chain operator, folded into (−Ḟ/2, Ḟ/2]."""

    longitude_days: float       # the libration in longitude (τ)
    latitude_days: float        # the free libration in latitude: the pole about the Cassini pole, in the node's frame
    wobble_days: float          # the free wobble, in the body (R) frame


def _free_modes(grid: tuple, sun: bool, I: float, mom: np.ndarray) -> FreeModes:
    """θ = e^{iλt} Σ_m c_m e^{imF}: det[T0 + i T1 diag(λ + mḞ) − diag((λ + mḞ)²) ⊗ diag(A, B, C)] = 0, a quadratic
    eigenvalue problem in λ, linearised to twice its size. Each mode appears once per shift λ + jḞ the truncated
    chain holds; the one kept is that whose eigenvector has most weight at m = 0 (the longitude mode and the
    wobble) or m = ±1 (the latitude mode: the pole circling the Cassini pole at nearly Ḟ in the body)."""
    nf = grid[2]
    f, m0, m1 = torus_fields(grid, sun, I, mom)
    ms, T0, T1 = chain_operator(m0.mean(axis=(2, 3, 5, 6)), m1, mom, nf)
    fdot = delaunay_rates(0.0)[2]
    d = np.repeat(ms * fdot, 3)
    idiag = np.tile(mom, ms.size)
    size = d.size
    # Q(λ) = −I λ² + (i T1 − 2 I D) λ + (T0 + i T1 D − I D²); z = (c, λc): λ z = [[0, 1], [−Q2⁻¹Q0, −Q2⁻¹Q1]] z
    q2 = -idiag
    q1 = 1j * T1 - np.diag(2.0 * idiag * d)
    q0 = T0 + 1j * T1 * d[None, :] - np.diag(idiag * d * d)
    comp = np.zeros((2 * size, 2 * size), dtype=complex)
    comp[:size, size:] = np.eye(size)
    comp[size:, :size] = -q0 / q2[:, None]
    comp[size:, size:] = -q1 / q2[:, None]
    lam, vec = np.linalg.eig(comp)
    vec = vec[:size]
    weight = np.abs(vec.reshape(ms.size, 3, -1)) ** 2
    weight = weight / weight.sum(axis=(0, 1), keepdims=True)
    centre = ms.size // 2
    ok = (np.abs(lam.imag) < 1e-9 * fdot) & (lam.real > 0) & (lam.real <= 0.5 * fdot)
    at0 = weight[centre].sum(axis=0)
    at1 = weight[centre - 1].sum(axis=0) + weight[centre + 1].sum(axis=0)
    tau_share = weight[:, 2].sum(axis=0)
    cand = np.nonzero(ok)[0]
    lon = cand[np.argmax(tau_share[cand] * at0[cand])]
    pole = cand[tau_share[cand] < 0.5]
    wob = pole[np.argmax(at0[pole])]
    lat = pole[np.argmax(at1[pole])]
    period = lambda i: 2.0 * math.pi / float(lam[i].real)  # noqa: E731
    return FreeModes(period(lon), period(lat), period(wob))


def free_modes(moments=None, *, sun: bool = True, grid: tuple = DEFAULT_GRID) -> FreeModes:
    """The free libration periods about the series' own Cassini state (:class:`FreeModes`)."""
    series = moon_physical_librations(moments, sun=sun, grid=grid, model="constant")
    return _free_modes(series.grid, series.sun, series.equator_inclination, moments_over_c(series.moments))
