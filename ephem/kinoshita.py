"""Kinoshita's theory of the forced precession and nutation, one perturber on a fixed Keplerian orbit.

References: Kinoshita (1977), Celest. Mech. 15, 277; Petit, Souchay & Lhotka
(2014), A&A 565, A79, eqs. 9-25.

Pure numerics: radians, days, rad/day. Conventions are the paper's: ψ is the
precession in longitude (ψ = -h), ε the obliquity (ε = -I); ψ̇ > 0 is a
retrograde precession (as the Earth's), ψ̇ < 0 a prograde one.

First order in the torque, rotation-averaged, the figure, rotation and
angular-momentum axes taken as one (J = 0), the triaxial P_2^2 term of the
potential dropped (it averages out over a rotation). With λ the Sun's
longitude from the body's equinox, K = 3 n² H_d / ω and (a/r)^3 from the orbit:

    dψ/dt = (K/2) cos ε (a/r)^3 (1 - cos 2λ)
    dε/dt = -(K/2) sin ε (a/r)^3 sin 2λ

Writing λ = θ + ν (θ: equinox to pericentre) and expanding with the Hansen
coefficients of :mod:`ephem.hansen` (C' = cos 2θ, S' = sin 2θ):

    Δψ = (K/2) cos ε Σ_k [(C0_k - C' C2_k) sin kM - S' S2_k cos kM] / (k n)
    Δε = -(K/2) sin ε Σ_k [S' C2_k sin kM - C' S2_k cos kM] / (k n)

which is the paper's eqs. 20 and 22 with sin I read as sin ε. The paper's
Tables 6 and 8 carry the opposite sign of Δε (see data/errata.toml); the
sign here is the one the numerical integration of the torque confirms.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import InvalidInputError
from .hansen import hansen_exact, hansen_series


def dynamical_ellipticity(A: float, B: float, C: float, body: str | None = None) -> float:
    """H_d = (C - (A+B)/2) / C (Petit et al. eq. 11), from principal moments A <= B <= C."""
    for name, value in (("A", A), ("B", B), ("C", C)):
        if not math.isfinite(value) or value <= 0.0:
            raise InvalidInputError(f"inertia.{name}", f"must be a positive finite number, got {value!r}", body)
    if not A <= B <= C:
        raise InvalidInputError("inertia", f"principal moments must satisfy A <= B <= C, got A={A}, B={B}, C={C}", body)
    if C > A + B:
        raise InvalidInputError("inertia", f"C={C} exceeds A+B={A + B}: no rigid body has these moments", body)
    return (C - 0.5 * (A + B)) / C


def scaling_factor(n: float, omega: float, hd: float) -> float:
    """K = 3 n² H_d / ω (Petit et al. eq. 10), in the unit of n and ω (rad per time)."""
    return 3.0 * n * n * hd / omega


def eccentricity_factor(e: float, order: int | None = None) -> float:
    """The mean of (a/r)^3 over the orbit, (1 - e²)^(-3/2), or its e-power series to e^order.

    order=4 gives the paper's 1 + 3/2 e² + 15/8 e⁴ (eq. 25).
    """
    if order is None:
        return (1.0 - e * e) ** -1.5
    total, coeff = 0.0, 1.0
    for j in range(order // 2 + 1):
        total += coeff * e ** (2 * j)
        coeff *= (2 * j + 3) / (2 * j + 2)  # binomial series of (1 - x)^(-3/2)
    return total


def precession_rate(K: float, obliquity: float, e: float, order: int | None = None) -> float:
    """Secular rate ψ̇ = (K/2) cos ε (1 - e²)^(-3/2) (Petit et al. eq. 25, exact in e by default)."""
    return 0.5 * K * math.cos(obliquity) * eccentricity_factor(e, order)


@dataclass(frozen=True)
class NutationSeries:
    """Nutation in longitude and obliquity as harmonics of the mean anomaly M.

        Δψ(M) = Σ_k lon_sin[k] sin kM + lon_cos[k] cos kM
        Δε(M) = Σ_k obl_sin[k] sin kM + obl_cos[k] cos kM

    Coefficients in radians; ``multiple`` the k's; ``mean_motion`` n in rad/day.
    """

    multiple: np.ndarray
    lon_sin: np.ndarray
    lon_cos: np.ndarray
    obl_sin: np.ndarray
    obl_cos: np.ndarray
    mean_motion: float
    order: int | None

    @property
    def period_days(self) -> np.ndarray:
        return 2.0 * math.pi / (self.multiple * self.mean_motion)

    def evaluate(self, mean_anomaly) -> tuple[np.ndarray, np.ndarray]:
        """Δψ and Δε (radians) at mean anomalies M (any array shape)."""
        return evaluate_harmonics(
            mean_anomaly, self.multiple,
            np.stack([self.lon_sin, self.obl_sin], axis=1),
            np.stack([self.lon_cos, self.obl_cos], axis=1))

    def semi_peak_to_peak(self, samples: int = 20000) -> tuple[float, float]:
        """Half the peak-to-peak excursion of Δψ and of Δε over one orbit (radians).

        This is what Petit et al. Table 4 lists as "Δψ" and "Δε".
        """
        m = np.linspace(0.0, 2.0 * math.pi, samples * max(1, int(self.multiple.max())), endpoint=False)
        dpsi, deps = self.evaluate(m)
        return 0.5 * float(np.ptp(dpsi)), 0.5 * float(np.ptp(deps))


def nutation_series(K: float, n: float, obliquity: float, e: float, equinox_to_pericentre: float,
                    order: int | None = None, min_amplitude: float = 1e-14) -> NutationSeries:
    """Nutation coefficients (Petit et al. eqs. 20, 22; radians).

    K and n in rad/day; ``order`` None for exact Hansen coefficients, else the
    e-power truncation order (the paper's eqs. 23-24 are order 4). Harmonics
    whose four coefficients are all below ``min_amplitude`` (radians; the
    default is 2 nano-arcseconds) are dropped.
    """
    if order is None:
        h = hansen_exact(e)
    else:
        h = hansen_series(order).evaluate(e)
    k = np.asarray(h.k[1:], dtype=float)
    c0, c2, s2 = h.c0[1:], h.c2[1:], h.s2[1:]
    cp, sp = math.cos(2.0 * equinox_to_pericentre), math.sin(2.0 * equinox_to_pericentre)
    f_psi = 0.5 * K * math.cos(obliquity) / (k * n)
    f_eps = -0.5 * K * math.sin(obliquity) / (k * n)
    lon_sin = f_psi * (c0 - cp * c2)
    lon_cos = -f_psi * sp * s2
    obl_sin = f_eps * sp * c2
    obl_cos = -f_eps * cp * s2
    big = np.max(np.abs(np.stack([lon_sin, lon_cos, obl_sin, obl_cos])), axis=0) >= min_amplitude
    keep = np.nonzero(big)[0]
    last = keep[-1] + 1 if keep.size else 0
    sl = slice(0, last)
    return NutationSeries(h.k[1:][sl].astype(int), lon_sin[sl], lon_cos[sl], obl_sin[sl],
                          obl_cos[sl], n, order)


#: Epochs per block in :func:`evaluate_harmonics`: small enough to stay in cache.
_BLOCK = 16384


def evaluate_harmonics(angle, multiple: np.ndarray, sin_coef: np.ndarray, cos_coef: np.ndarray):
    """Σ_k S[k, j] sin(k x) + C[k, j] cos(k x) for each output column j.

    ``multiple`` must be 1, 2, …, kmax (consecutive). One sin and one cos of x
    per epoch; the higher harmonics come from the Chebyshev recurrence
    cos((k+1)x) = 2 cos x cos kx - cos((k-1)x) (likewise for sin), and the sums
    are one matrix product per block. Returns a tuple of arrays shaped like x.
    """
    x = np.asarray(angle, dtype=float)
    shape = x.shape
    flat = x.ravel()
    kmax = len(multiple)
    ncol = sin_coef.shape[1]
    if kmax == 0:
        return tuple(np.zeros(shape) for _ in range(ncol))
    if not np.array_equal(multiple, np.arange(1, kmax + 1)):
        raise ValueError("multiple must be 1..kmax")
    coef = np.concatenate([cos_coef, sin_coef], axis=0)  # (2 kmax, ncol)
    out = np.empty((flat.size, ncol))
    block = min(_BLOCK, max(flat.size, 1))
    table = np.empty((2 * kmax, block))  # rows: cos x .. cos kmax x, sin x .. sin kmax x
    two_c = np.empty(block)
    for start in range(0, flat.size, block):
        stop = min(start + block, flat.size)
        m = stop - start
        t = table[:, :m]
        cos_rows, sin_rows = t[:kmax], t[kmax:]
        np.cos(flat[start:stop], out=cos_rows[0])
        np.sin(flat[start:stop], out=sin_rows[0])
        if kmax > 1:
            tc = two_c[:m]
            np.multiply(cos_rows[0], 2.0, out=tc)
            np.multiply(tc, cos_rows[0], out=cos_rows[1])
            cos_rows[1] -= 1.0
            np.multiply(tc, sin_rows[0], out=sin_rows[1])
            for j in range(2, kmax):
                np.multiply(tc, cos_rows[j - 1], out=cos_rows[j])
                cos_rows[j] -= cos_rows[j - 2]
                np.multiply(tc, sin_rows[j - 1], out=sin_rows[j])
                sin_rows[j] -= sin_rows[j - 2]
        np.matmul(t.T, coef, out=out[start:stop])
    return tuple(out[:, j].reshape(shape) for j in range(ncol))
