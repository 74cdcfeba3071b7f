"""The Moon's physical librations solved linearly, chain by chain: the harmonic balance on the torus of the arguments.

The linearised equations Λ θ̈ + M1 θ̇ + M0 θ = f (eq. (3) of :mod:`ephem.moon.physical_librations`'s docstring,
and its "Solution"), with M0 averaged over (l, l', D, Ω), couple a harmonic k = (b, m) of θ only to those of the
same base b = (l, l', D, Ω): one small linear solve per chain of F multipliers m, resonances included. Here are
that operator (:func:`chain_operator`), its solve for a forcing spectrum (:func:`solve_chains`), the spectrum the
chains give on the FFT grid (:func:`scatter`), the constant θ a constant torque gives (:func:`dc_response`) and the
frequencies of the grid's harmonics (:func:`grid_frequencies`). The fixed point that uses them, and the public
entry, are :mod:`ephem.moon.physical_librations`'s. Radians and days.
"""
from __future__ import annotations

import numpy as np

from ..orbit.lunar import delaunay_rates


def grid_frequencies(grid: tuple) -> np.ndarray:
    """ν_k = k · (dl/dt, dl'/dt, dF/dt, dD/dt, dΩ/dt) (rad/day) at every index of the grid's spectrum (0 at the
    Nyquist indices, whose harmonics the grid cannot resolve)."""
    rates = delaunay_rates(0.0)
    nu = 0.0
    for i, n in enumerate(grid):
        k = np.fft.fftfreq(n, 1.0 / n)
        k[np.abs(k) * 2 >= n] = 0.0
        nu = nu + (k * rates[i]).reshape([-1 if i == j else 1 for j in range(5)])
    return nu


def chain_operator(m0_f: np.ndarray, m1_f: np.ndarray, moments: np.ndarray, nf: int):
    """The F-chain blocks: for a chain of multipliers k_m = (b, m) (m = −J..J, J = NF/2 − 1), the harmonic-balance
    matrix is T0 + i T1 diag(ν_m) − diag(ν_m²) ⊗ diag(A, B, C), with T0[m, m'] = M0_{m−m'} and T1[m, m'] =
    M1_{m−m'} the F-harmonics of the F-dependent part of the coefficients (those with |m − m'| > J dropped:
    beyond the grid's resolution). Returns (ms, T0, T1) with T0, T1 of shape (3 nm, 3 nm)."""
    J = nf // 2 - 1
    ms = np.arange(-J, J + 1)
    M0 = np.fft.fft(m0_f, axis=2) / nf
    M1 = np.fft.fft(m1_f, axis=2) / nf
    jd = ms[:, None] - ms[None, :]
    keep = np.abs(jd) <= J
    nm = ms.size

    def blocks(M):
        t = M[:, :, jd % nf] * keep                  # (3, 3, nm, nm)
        return t.transpose(2, 0, 3, 1).reshape(3 * nm, 3 * nm)

    return ms, blocks(M0), blocks(M1)


def solve_chains(spec: np.ndarray, grid: tuple, ms: np.ndarray, T0: np.ndarray, T1: np.ndarray,
                  moments: np.ndarray, floor: float):
    """Harmonic balance, chain by chain: every forcing harmonic k = (l, l', F, D, Ω) above ``floor`` of the
    spectrum ``spec`` (3, grid; coefficients of e^{ik·φ}) belongs to the chain of its base b = (l, l', D, Ω); one
    chain per ±b pair is solved (the other is its conjugate: the forcing is real). Returns (bases (nb, 4),
    coefficients (nb, nm, 3) of θ at k = (b, ms))."""
    rates = delaunay_rates(0.0)
    nm = ms.size
    mag = np.abs(spec).max(axis=0)
    idx = np.argwhere(mag > floor * mag.max())
    half = np.array(grid) // 2
    signed = np.where(idx > half, idx - np.array(grid), idx)
    signed = signed[np.all(2 * np.abs(signed) < np.array(grid), axis=1)]   # no Nyquist rows
    b = signed[:, [0, 1, 3, 4]]
    # one chain per ±b: first non-zero of (Ω, D, l, l') positive
    sign = np.zeros(b.shape[0], dtype=int)
    for i in (3, 2, 0, 1):
        undecided = sign == 0
        sign[undecided] = np.sign(b[undecided, i])
    sign[sign == 0] = 1
    bases = np.unique(b * sign[:, None], axis=0)
    brates = rates[[0, 1, 3, 4]]
    out = np.zeros((bases.shape[0], nm, 3), dtype=complex)
    diag_i = np.tile(moments, nm)
    chunk = 256
    for start in range(0, bases.shape[0], chunk):
        bb = bases[start:start + chunk]
        nu = (bb @ brates)[:, None] + ms[None, :] * rates[2]                  # (nb, nm)
        nu3 = np.repeat(nu, 3, axis=1)                                        # (nb, 3 nm)
        mat = T0[None] + 1j * T1[None] * nu3[:, None, :]
        mat[:, np.arange(3 * nm), np.arange(3 * nm)] -= nu3**2 * diag_i
        k = np.empty((bb.shape[0], nm, 5), dtype=int)
        k[:, :, [0, 1, 3, 4]] = bb[:, None, :]
        k[:, :, 2] = ms[None, :]
        ok = np.all(2 * np.abs(k) < np.array(grid), axis=2)
        kk = np.where(k < 0, k + np.array(grid), k)
        rhs = spec[:, kk[..., 0], kk[..., 1], kk[..., 2], kk[..., 3], kk[..., 4]]   # (3, nb, nm)
        rhs = np.where(ok[None], rhs, 0.0).transpose(1, 2, 0).reshape(bb.shape[0], 3 * nm)
        out[start:start + chunk] = np.linalg.solve(mat, rhs[..., None])[..., 0].reshape(bb.shape[0], nm, 3)
    return bases, out


def scatter(bases: np.ndarray, theta: np.ndarray, ms: np.ndarray, grid: tuple) -> np.ndarray:
    """The spectrum (3, grid) of chains (bases (nb, 4), coefficients (nb, nm, 3)) and their conjugates (the b = 0
    chain holds both signs of m itself)."""
    gsize = np.array(grid)
    full = np.zeros((3,) + grid, dtype=complex)
    for sgn in (1, -1):
        sel = np.ones(bases.shape[0], dtype=bool) if sgn == 1 else np.any(bases, axis=1)
        k = np.empty((int(sel.sum()), ms.size, 5), dtype=int)
        k[:, :, [0, 1, 3, 4]] = sgn * bases[sel, None, :]
        k[:, :, 2] = sgn * ms[None, :]
        idx = tuple(np.moveaxis(k % gsize, -1, 0))
        vals = theta[sel] if sgn == 1 else np.conj(theta[sel])
        np.add.at(full, (slice(None),) + idx, np.moveaxis(vals, -1, 0))
    return full


def dc_response(ms: np.ndarray, T0: np.ndarray, T1: np.ndarray, mom: np.ndarray) -> np.ndarray:
    """G (3, 3): the constant θ a unit constant torque about each principal axis gives (the b = 0 chain, rad per
    rad/day² with C = 1)."""
    nu = np.repeat(ms * delaunay_rates(0.0)[2], 3)
    mat = T0 + 1j * T1 * nu[None, :]
    mat[np.arange(nu.size), np.arange(nu.size)] -= nu**2 * np.tile(mom, ms.size)
    centre = 3 * (ms.size // 2)
    rhs = np.zeros((nu.size, 3), dtype=complex)
    rhs[centre:centre + 3] = np.eye(3)
    return np.linalg.solve(mat, rhs)[centre:centre + 3].real
