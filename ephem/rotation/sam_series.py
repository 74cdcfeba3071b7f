"""Lara's short-axis-mode series evaluated for a body: the numerical side of :mod:`ephem.rotation.lie_series`.

- :class:`SamParameters`: Andoyer's α, β, ω and κ of a body's moments (L18 eqs. 3, 16, 24);
- the maps between the body's angular momentum and the Poincaré (complex) and action-angle variables;
- :class:`SamSeriesSolution`: the torque-free motion from the generated normal form and generating function
  (L18 eqs. 30-32), with the mean elements;
- :class:`Lara2014Series`: L14's eqs. 30-34 from a set of triaxiality polynomials (printed or generated): the
  second, independent route, and the way to test a printed table.

Sources and notation as :mod:`ephem.rotation.lie_series`'s (L18: Lara 2018; L14: Lara 2014).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .lie_series import Lara2014Tables, sam_normal_form
from .polynomials import BetaPoly, GaussianPoly


@dataclass(frozen=True)
class SamParameters:
    """Andoyer's α, β (L18 eq. 3), ω (eq. 16) and κ (eq. 24) of principal moments A ≤ B < C."""

    A: float
    B: float
    C: float

    def __post_init__(self):
        if not (0.0 < self.A <= self.B < self.C):
            raise ValueError(f"need 0 < A <= B < C for SAM rotation, got {(self.A, self.B, self.C)}")

    @property
    def alpha(self) -> float:
        return 0.5 * (self.C / self.A + self.C / self.B) - 1.0

    @property
    def beta(self) -> float:
        # α(1+β) − α(1−β) = C/A − C/B: written as differences of the moments to keep digits for A ≈ B
        return 0.5 * self.C * (self.B - self.A) / (self.A * self.B) / self.alpha

    @property
    def omega(self) -> float:
        return math.sqrt((1.0 + self.beta) / (1.0 - self.beta))

    @property
    def kappa(self) -> float:
        return math.sqrt((self.C / self.A - 1.0) * (self.C / self.B - 1.0))


def body_to_poincare(m, params: SamParameters) -> tuple[complex, complex, float]:
    """(u, U, G) from the body-frame angular momentum m = (m₁, m₂, m₃) (axes of A, B, C).

    Private minimal conversion (the Andoyer module of the package will own the general
    one): with Andoyer's m₁ = M sin J sin ν, m₂ = M sin J cos ν, N = m₃ = M cos J, L18
    eqs. 7-8 are x = −√2 m₁/√(M + N), X = √2 m₂/√(M + N) (no singularity at J = 0), and
    eqs. 20-21 with Ω = ω invert to u = (P + iQ)/2, U = (Q + iP)/2, P = √(2ω)x, Q = √(2/ω)X.
    """
    m1, m2, m3 = (float(c) for c in m)
    G = math.sqrt(m1 * m1 + m2 * m2 + m3 * m3)
    s = math.sqrt(2.0 / (G + m3))
    x, X = -m1 * s, m2 * s
    w = params.omega
    P, Q = math.sqrt(2.0 * w) * x, math.sqrt(2.0 / w) * X
    return complex(P, Q) / 2, complex(Q, P) / 2, G


def poincare_to_body(u, U, G: float, params: SamParameters) -> np.ndarray:
    """Body-frame angular momentum from (u, U, G): the inverse of :func:`body_to_poincare` (vectorised).

    P = u − iU, Q = U − iu (L18 eqs. 20-21), x = P/√(2ω), X = Q√(ω/2), M − N = (x² + X²)/2
    (eq. 12), m₁ = −x√((M + N)/2), m₂ = X√((M + N)/2). Imaginary parts (rounding, or a
    truncated series) are dropped.
    """
    u, U = np.asarray(u, dtype=complex), np.asarray(U, dtype=complex)
    w = params.omega
    x = ((u - 1j * U) / math.sqrt(2.0 * w)).real
    X = ((U - 1j * u) * math.sqrt(w / 2.0)).real
    m3 = G - 0.5 * (x * x + X * X)
    s = np.sqrt(0.5 * (G + m3))
    return np.stack([-x * s, X * s, m3], axis=-1)


class _NumericPoly:
    """Σ_n ρⁿ/n! ξ_n(u, U) collapsed to complex floats at one β, for fast vectorised evaluation."""

    def __init__(self, polys: Sequence[GaussianPoly], beta: float):
        self.orders = []
        self.top = 0
        for n, p in enumerate(polys, 1):
            coll = p.collapse(beta)
            j = np.array([jk[0] for jk in coll], dtype=int)
            k = np.array([jk[1] for jk in coll], dtype=int)
            c = np.array(list(coll.values()), dtype=complex) / math.factorial(n)
            self.orders.append((j, k, c))
            self.top = max(self.top, int(j.max(initial=0)), int(k.max(initial=0)))

    @staticmethod
    def _powers(z: np.ndarray, top: int) -> np.ndarray:
        # repeated products, not np.power: exact at z = 0 and no complex log/exp rounding
        out = np.empty(z.shape + (top + 1,), dtype=complex)
        out[..., 0] = 1.0
        for p in range(1, top + 1):
            out[..., p] = out[..., p - 1] * z
        return out

    def __call__(self, u, U, rho: float, upto: int):
        u, U = np.broadcast_arrays(np.asarray(u, dtype=complex), np.asarray(U, dtype=complex))
        pu, pU = self._powers(u, self.top), self._powers(U, self.top)
        total = np.zeros(u.shape, dtype=complex)
        for n, (j, k, c) in enumerate(self.orders[:upto], 1):
            total = total + rho**n * (c * pu[..., j] * pU[..., k]).sum(axis=-1)
        return total


@dataclass(frozen=True)
class MeanElements:
    """The series' new (prime) variables of one state: L' (action), ℓ' (angle) and G."""

    L: float
    ell: float
    G: float


class SamSeriesSolution:
    """The series solution of torque-free SAM rotation to order ≤ N, in floating point.

    Given the principal moments and a body-frame angular momentum, it finds the mean
    (prime) elements by inverting the truncated transformation (fixed-point iteration:
    the correction is O(δ)), advances them (ℓ' = ℓ'₀ + n_ℓ t, g' = g'₀ + n_g t, L', G
    constant) and maps back. ``order`` may be lowered per call (``upto``) to study
    convergence. Valid for rotation about the axis of maximum inertia (N > 0) with
    δ = L'/(G√(1 − β²)) inside the series' convergence region.
    """

    def __init__(self, moments: Sequence[float], order: int):
        self.params = SamParameters(*(float(x) for x in moments))
        self.order = order
        exact = sam_normal_form(order)
        beta = self.params.beta
        self._u = _NumericPoly(exact.transformation("u"), beta)
        self._U = _NumericPoly(exact.transformation("U"), beta)
        self._g = _NumericPoly(exact.transformation("g"), beta)
        # K[n]/n! = k_n (uU)^{n+1} = k_n (iL)^{n+1}: the normal form's coefficients of L^{n+1}, real
        self._k = []
        for n in range(order + 1):
            c = sum(complex(re, im) * beta**b for b, (re, im) in enumerate(exact.kernel_coefficient(n)))
            self._k.append((c * 1j ** (n + 1) / math.factorial(n)).real)

    def _upto(self, upto: int | None) -> int:
        n = self.order if upto is None else upto
        if not 0 <= n <= self.order:
            raise ValueError(f"upto must lie in [0, {self.order}]")
        return n

    def rho(self, G: float) -> float:
        return 1.0 / (G * math.sqrt(1.0 - self.params.beta ** 2))

    def energy(self, L: float, G: float, upto: int | None = None) -> float:
        """The normal form H = G²/(2C) + (κG/C) Σ_{n≤N} k_n ρⁿ L^{n+1} (L14 eq. 30, L18 eq. 30)."""
        return G * G / (2 * self.params.C) + self.excess_energy(L, G, upto)

    def excess_energy(self, L: float, G: float, upto: int | None = None) -> float:
        """H − G²/(2C), the energy above rotation about the C axis, without the cancellation of
        :meth:`energy` (it is ~J² G²/C, far below G²/2C for small J)."""
        p, rho = self.params, self.rho(G)
        s = sum(self._k[n] * rho**n * L ** (n + 1) for n in range(self._upto(upto) + 1))
        return p.kappa * G / p.C * s

    def frequencies(self, L: float, G: float, upto: int | None = None) -> tuple[float, float]:
        """(n_ℓ, n_g) = (∂H/∂L', ∂H/∂G) of the normal form, rad per time unit.

        With ρ ∝ 1/G: ∂/∂G of (κG/C) k_n ρⁿ L^{n+1} is (κ/C)(1 − n) k_n ρⁿ L^{n+1}.
        """
        p, rho = self.params, self.rho(G)
        n_top = self._upto(upto)
        n_l = p.kappa * G / p.C * sum((n + 1) * self._k[n] * rho**n * L**n for n in range(n_top + 1))
        n_g = G / p.C + p.kappa / p.C * sum((1 - n) * self._k[n] * rho**n * L ** (n + 1) for n in range(n_top + 1))
        return n_l, n_g

    def mean_elements(self, m, upto: int | None = None, tol: float = 1e-15, max_iter: int = 200) -> MeanElements:
        """The prime variables of body-frame angular momentum m, inverting u = u' + Σ ρⁿ/n! uₙ(u', U')."""
        n_top = self._upto(upto)
        u0, U0, G = body_to_poincare(m, self.params)
        rho = self.rho(G)
        up, Up = u0, U0
        scale = abs(u0) + abs(U0) + 1e-300
        change = math.inf
        for _ in range(max_iter):
            nu = u0 - complex(self._u(up, Up, rho, n_top))
            nU = U0 - complex(self._U(up, Up, rho, n_top))
            change = abs(nu - up) + abs(nU - Up)
            up, Up = nu, nU
            if change <= tol * scale:
                break
        # rounding can keep the last change a few ulps above tol; a real failure stays large
        if change > 1e-10 * scale:
            raise RuntimeError("the inverse transformation did not converge: outside the series' region?")
        L = (-1j * up * Up).real
        return MeanElements(L, math.atan2(Up.imag, Up.real), G)

    def propagate(self, m0, t, upto: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(m(t), g(t) − g(0)): body-frame angular momentum (shape (len(t), 3)) and the Andoyer angle
        g = μ + ν advanced from m0 at t = 0 (times in the unit implied by the moments and m0)."""
        n_top = self._upto(upto)
        t = np.asarray(t, dtype=float)
        mean = self.mean_elements(m0, upto=n_top)
        n_l, n_g = self.frequencies(mean.L, mean.G, upto=n_top)
        ell = mean.ell + n_l * t
        sq = math.sqrt(mean.L)
        up, Up = 1j * sq * np.exp(-1j * ell), sq * np.exp(1j * ell)
        rho = self.rho(mean.G)
        u = up + self._u(up, Up, rho, n_top)
        U = Up + self._U(up, Up, rho, n_top)
        m = poincare_to_body(u, U, mean.G, self.params)
        periodic = self._g(up, Up, rho, n_top).real / mean.G
        up0, Up0 = 1j * sq * np.exp(-1j * mean.ell), sq * np.exp(1j * mean.ell)
        periodic0 = complex(self._g(up0, Up0, rho, n_top)).real / mean.G
        return m, n_g * t + periodic - periodic0


def body_to_action_angle(m, params: SamParameters) -> tuple[float, float, float]:
    """(ℓ, L, G): L14's action-angle variables of the main problem from body-frame angular momentum.

    L18 eq. 17 inverted, x = √(2L/ω) sin ℓ, X = √(2ωL) cos ℓ, with x, X as in
    :func:`body_to_poincare`; this is L14 eqs. 22 and 25 without their singularity at J = 0.
    """
    m1, m2, m3 = (float(c) for c in m)
    G = math.sqrt(m1 * m1 + m2 * m2 + m3 * m3)
    s = math.sqrt(2.0 / (G + m3))
    x, X = -m1 * s, m2 * s
    w = params.omega
    return math.atan2(math.sqrt(w) * x, X / math.sqrt(w)), 0.5 * (w * x * x + X * X / w), G


def action_angle_to_body(ell, L, G: float, params: SamParameters) -> np.ndarray:
    """Body-frame angular momentum from (ℓ, L, G), vectorised (L14 eqs. 18-21 via L18 eqs. 7-17)."""
    ell, L = np.asarray(ell, dtype=float), np.asarray(L, dtype=float)
    w = params.omega
    x, X = np.sqrt(2.0 * L / w) * np.sin(ell), np.sqrt(2.0 * w * L) * np.cos(ell)
    m3 = G - 0.5 * (x * x + X * X)
    s = np.sqrt(0.5 * (G + m3))
    return np.stack([-x * s, X * s, m3], axis=-1)


class Lara2014Series:
    """L14 eqs. 30-34 evaluated from a set of triaxiality polynomials (printed or generated).

    In the action-angle variables of the main problem, with δ = L'/(G√(1 − β²)):

        ℓ = ℓ' + Σ_i δⁱ Σ_m (−β)ᵐ ℓ_{i,m} sin 2mℓ'                         (eq. 33)
        L = L' + L' Σ_i δⁱ (β² L_{i,0} − Σ_m (−β)ᵐ L_{i,m} cos 2mℓ')        (eq. 34)
        g = g' − (L'/G) Σ_i δⁱ Σ_m (−β)ᵐ g_{i,m} sin 2mℓ'                   (eq. 32)
        T = G²/2C [1 + 2α(L'/G)√(1 − β²) − α(L'/G)²(1 + β² Σ_i q_i δⁱ)]     (eq. 30)

    A second, independent evaluation route to :class:`SamSeriesSolution` (real Fourier
    series instead of complex polynomials), and the way to test a printed table against
    the torque-free motion. ``upto`` = N keeps i ≤ N in eqs. 32-34 and, in eq. 30, the
    α(L'/G)² term when N ≥ 1 and q_i for i ≤ N − 1 (the terms of Deprit order ≤ N).
    """

    def __init__(self, moments: Sequence[float], tables: Lara2014Tables, order: int):
        self.params = SamParameters(*(float(x) for x in moments))
        self.order = order
        beta = self.params.beta

        def val(p: BetaPoly) -> float:
            return sum(float(c) * beta**e for e, c in enumerate(p))

        self._q = {i: val(p) for i, p in tables.q.items()}
        self._ell = {k: (-beta) ** k[1] * val(p) for k, p in tables.ell.items()}
        self._g = {k: (-beta) ** k[1] * val(p) for k, p in tables.g.items()}
        self._L = {k: (beta**2 if k[1] == 0 else -(-beta) ** k[1]) * val(p) for k, p in tables.L.items()}

    def _delta(self, L: float, G: float) -> float:
        return L / (G * math.sqrt(1.0 - self.params.beta ** 2))

    def periodic(self, ellp, Lp: float, G: float, upto: int):
        """(ℓ − ℓ', L/L' − 1, (g − g')G/L') at the prime variables (vectorised in ℓ')."""
        ellp = np.asarray(ellp, dtype=float)
        d = self._delta(Lp, G)
        dl, dL, dg = (np.zeros_like(ellp) for _ in range(3))
        for (i, m), c in self._ell.items():
            if i <= upto:
                dl = dl + d**i * c * np.sin(2 * m * ellp)
        for (i, m), c in self._L.items():
            if i <= upto:
                dL = dL + d**i * c * np.cos(2 * m * ellp)
        for (i, m), c in self._g.items():
            if i <= upto:
                dg = dg - d**i * c * np.sin(2 * m * ellp)
        return dl, dL, dg

    def frequencies(self, Lp: float, G: float, upto: int) -> tuple[float, float]:
        """(n_ℓ, n_g) = (∂T/∂L', ∂T/∂G) of eq. 30 truncated at Deprit order ``upto``."""
        p = self.params
        d, b2 = self._delta(Lp, G), p.beta ** 2
        n_l = p.kappa * G / p.C
        n_g = G / p.C + p.kappa * Lp / p.C
        if upto >= 1:
            qs = [(i, q) for i, q in self._q.items() if i <= upto - 1]
            n_l -= p.alpha * Lp / p.C * (1.0 + b2 * sum((1 + 0.5 * i) * q * d**i for i, q in qs))
            n_g += 0.5 * p.alpha / p.C * Lp * Lp / G * b2 * sum(i * q * d**i for i, q in qs)
        return n_l, n_g

    def mean_elements(self, m, upto: int, tol: float = 1e-15, max_iter: int = 200) -> MeanElements:
        """Prime (ℓ', L') of a body-frame angular momentum, by fixed-point inversion of eqs. 33-34."""
        ell, L, G = body_to_action_angle(m, self.params)
        ellp, Lp = ell, L
        change = math.inf
        for _ in range(max_iter):
            dl, dL, _ = self.periodic(ellp, Lp, G, upto)
            n_ell, n_L = ell - float(dl), L / (1.0 + float(dL))
            change = abs(n_ell - ellp) + abs(n_L - Lp) / L
            ellp, Lp = n_ell, n_L
            if change <= tol:
                break
        if change > 1e-10:
            raise RuntimeError("the inverse transformation did not converge: outside the series' region?")
        return MeanElements(Lp, ellp, G)

    def propagate(self, m0, t, upto: int) -> tuple[np.ndarray, np.ndarray]:
        """(m(t), g(t) − g(0)) as :meth:`SamSeriesSolution.propagate`, from eqs. 30-34."""
        t = np.asarray(t, dtype=float)
        mean = self.mean_elements(m0, upto)
        n_l, n_g = self.frequencies(mean.L, mean.G, upto)
        ellp = mean.ell + n_l * t
        dl, dL, dg = self.periodic(ellp, mean.L, mean.G, upto)
        m = action_angle_to_body(ellp + dl, mean.L * (1.0 + dL), mean.G, self.params)
        _, _, dg0 = self.periodic(mean.ell, mean.L, mean.G, upto)
        return m, n_g * t + mean.L / mean.G * (dg - float(dg0))
