"""Lara's perturbation series for short-axis-mode (SAM) free rotation, by a Lie-transform engine in exact arithmetic.

Sources
-------
* M. Lara (2018), "Complex variables approach to the short-axis-mode rotation of a
  rigid body", Appl. Math. Nonlinear Sci. 3(2), 537 ("L18" below): the Hamiltonian
  in complex variables (eqs. 25, 26), the Lie operator (eq. 28), the homological
  equation as a division (eq. 29), the normal form and its polynomials p_n
  (eq. 30), the generating function and its polynomials s_n (eq. 32), Deprit's
  triangle (eq. 31).
* M. Lara (2014), "Short-axis-mode rotation of a free rigid body by perturbation
  series", Celest. Mech. Dyn. Astron. 118, 221 ("L14" below): the same problem in
  the action-angle variables (ℓ, g, L, G) of the main problem (eqs. 17-25), and
  the series of Tables 2-5 (eqs. 30-34).
* A. Deprit (1969), Celest. Mech. 1, 12: the Lie-transform triangle.

The problem
-----------
A ≤ B ≤ C are the principal moments; Andoyer's α, β (L18 eq. 3, L14 eq. 2) are

    α(1 + β) = C/A − 1,   α(1 − β) = C/B − 1,   ω = √((1 + β)/(1 − β)),   κ = α√(1 − β²).

With (u, U) canonical (u a coordinate, U its momentum) and V = √κ G, G = |angular
momentum| (L18 eqs. 20-25), the free rigid body is H = M + εP with ε = 1 and

    M = V²/(2Cκ) − (V√κ/C) i u U,                            (L18 eq. 25)
    P = (α/4C) [2u²U² − iβ(u³U − uU³)].                       (L18 eq. 26)

V is a constant of the motion and nothing depends on its conjugate v, so within
the (u, U) transform V is a parameter. Dividing the Hamiltonian by the frequency
factor κG/C = V√κ/C and writing ρ = α/(√κ V) = 1/(G√(1 − β²)) gives the
scaled problem that the engine works on, free of every physical parameter but β:

    h = h₀ + ρ h₁,   h₀ = −i u U,   h₁ = ¼ [2u²U² − iβ(u³U − uU³)].

Every quantity of Deprit order n then carries ρⁿ: the physical generating function
is W_n = ρⁿ w_n and the physical normal form (κG/C) Σ ρⁿ K_n / n!. The polynomials
w_n, K_n have coefficients in Q(i)[β] and are computed exactly here.

Poisson bracket {f; g} = f_u g_U − f_U g_u (+ the (v, V) pair, idle here). The Lie
operator of h₀ is L(f) = {f; h₀}, with L(uʲUᵏ) = i(k − j) uʲUᵏ (L18 eq. 28 scaled):
its kernel is the monomials (uU)ʲ, and the homological equation of order n,
L(w_n) = H̃_n − K_n, is solved monomial by monomial (L18 eq. 29 scaled):

    K_n = the (uU)ʲ terms of H̃_n,   w_n = Σ_{j≠k} i q_jk/(j − k) uʲUᵏ.

Deprit's triangle (L18 eq. 31) is ξ_{n,q} = ξ_{n+1,q−1} + Σ_{m=0..n} C(n,m){ξ_{n−m,q−1}; w_{m+1}};
applied to the Hamiltonian it gives the normal form ξ_{0,n} = K_n, applied to a
function f (ξ_{0,0} = f, ξ_{n,0} = 0) it gives the old f in the new variables,
f = f' + Σ ρⁿ/n! ξ_{0,n}(u', U').

Link with L14
-------------
L18 eqs. 7-10, 17, 20-23 give u = i√L e^{−iℓ}, U = √L e^{iℓ} and g = √κ v, G = V/√κ,
with (ℓ, g, L, G) exactly L14's action-angle variables of the main problem (L14
eqs. 18-25: same tan ν = −√((1−β)/(1+β)) tan ℓ, same M − N, same g = μ + ν). So
uʲUᵏ = iʲ L^{(j+k)/2} e^{i(k−j)ℓ}, and with δ = ρ L' (L14 eq. 31) the series of
L14 eqs. 30-34 are read off the engine's polynomials (see :class:`SamNormalForm`).
The angles need their own first bracket: {ℓ; W} = (i/2)(u W_u + U W_U)/(uU) (from
e^{2iℓ} = iU/u) and {g; W_n} = ∂W_n/∂G = −(n/G) ρⁿ w_n.

Public API
----------
Exact: :func:`sam_hamiltonian_terms`, :func:`solve_sam_homological`, :class:`SamNormalForm` /
:func:`sam_normal_form` (K_n, w_n, p_n, s_n, the transformations of u, U, L, ℓ, g, and
:meth:`SamNormalForm.lara2014_tables`), :func:`cost_table`; the polynomials are those of
:mod:`ephem.rotation.polynomials` (Q(i)[u, U, β] with the Poisson bracket) and the triangle is the generic
one of :mod:`ephem.rotation.deprit`.
Numerical: :class:`SamParameters`, :class:`SamSeriesSolution` (the complex series),
:class:`Lara2014Series` (eqs. 30-34 from any table set), and the conversions
:func:`body_to_poincare`, :func:`poincare_to_body`, :func:`body_to_action_angle`,
:func:`action_angle_to_body` (minimal private versions; the package's Andoyer module owns
the general ones).

Cost (CPU, pure Python ints): order 20 in 0.5 s, 35 in 13 s, 50 in 134 s for the normal
form and generator; each transformation costs about as much again. The Poisson brackets
of the known terms dominate and grow like n^5.7 per order (L18 Fig. 1: ~quintic).

Errata of the printed series found with this engine (data/lara/errata.toml): L18's
p_0 = 2 (−2) and p_2 = β² (β²/2); L14 Table 4 ℓ_{1,1} = 1/4 (1/2) and Table 3
g_{6,3} = β²/128 (1/128). Everything else printed (p_1, p_3..p_9, s_1..s_8, and the
other 112 cells of L14 Tables 2-5) is reproduced term by term.

Units: the exact part is dimensionless. The numerical part (:class:`SamSeriesSolution`)
takes the moments and the body-frame angular momentum in any consistent units
(e.g. moments in kg m², angular momentum in kg m² s⁻¹), and time in the unit
they imply (s); angles in radians.
"""
from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

import numpy as np

from .deprit import FirstBracket, OrderCost, deprit_normalize, deprit_transform
from .polynomials import BetaPoly, GaussianPoly, beta_poly, beta_poly_shift_down

# =========================================================================== Lara's SAM problem

def sam_hamiltonian_terms() -> list[GaussianPoly]:
    """[h₀, h₁] of the scaled problem: h₀ = −i uU, h₁ = ¼[2u²U² − iβ(u³U − uU³)] (L18 eqs. 25, 26 / (κG/C))."""
    h0 = GaussianPoly.monomial(1, 1, 0, (0, -1))
    h1 = GaussianPoly({(2, 2, 0): Fraction(1, 2), (3, 1, 1): (0, Fraction(-1, 4)), (1, 3, 1): (0, Fraction(1, 4))})
    return [h0, h1]


def solve_sam_homological(image: GaussianPoly) -> GaussianPoly:
    """w_n from the non-kernel part of H̃_n by L18 eq. 29 (scaled): w_n = Σ_{j≠k} i q_jk/(j − k) uʲUᵏ.

    {h₀; uʲUᵏ} = i(j − k) uʲUᵏ with h₀ = −iuU, so {h₀; w_n} = −image; w_n has no kernel
    term (the usual choice, which is also L14's zero-average generating function). With
    {uʲUᵏ; uU} = (j − k) uʲUᵏ, w_n is i times the inverse of the Lie operator of uU on the image.
    """
    return image.invert_bracket_with_uU().scale((0, 1))


@dataclass(frozen=True)
class Lara2014Tables:
    """L14's triaxiality polynomials, from the engine: q[i] (Table 2), g[i, m] (Table 3), ell[i, m] (Table 4),
    L[i, m] (Table 5; m = 0 is L_{i,0}), each a BetaPoly, indexed as printed."""

    q: dict[int, BetaPoly]
    g: dict[tuple[int, int], BetaPoly]
    ell: dict[tuple[int, int], BetaPoly]
    L: dict[tuple[int, int], BetaPoly]


class SamNormalForm:
    """Lara's SAM series to a given order, exact: normal form, generating function and transformations.

    Notation as in the module docstring: K[n], w[n] are the scaled Deprit terms; with ε = 1
    the physical normal form is G²/(2C) + (κG/C) Σ_{n≥0} ρⁿ K[n](u'U')/n! and the physical
    generating function Σ_{n≥0} ρⁿ⁺¹ w[n+1]/n! (L18's S_{n+1} = ρⁿ⁺¹ w[n+1], eq. 32).
    """

    def __init__(self, order: int):
        if order < 1:
            raise ValueError("order must be at least 1")
        t0 = time.process_time()
        self.normal_form = deprit_normalize(sam_hamiltonian_terms(), order, solve_sam_homological)
        self.normalization_seconds = time.process_time() - t0
        self.order = order
        self._transforms: dict[str, list[GaussianPoly]] = {}

    @property
    def K(self) -> list[GaussianPoly]:
        return self.normal_form.K

    @property
    def w(self) -> list[GaussianPoly | None]:
        return self.normal_form.w

    @property
    def cost(self) -> list[OrderCost]:
        return self.normal_form.cost

    # ------------------------------------------------------------------ L18's polynomials
    def kernel_coefficient(self, n: int) -> list[tuple[Fraction, Fraction]]:
        """K[n] = c(β)(uU)^{n+1}: the β-coefficients of c, checking that K[n] is of that form."""
        mons = self.K[n].monomials_uU()
        if mons - {(n + 1, n + 1)}:
            raise AssertionError(f"K_{n} has monomials {sorted(mons)} besides (uU)^{n + 1}")
        return self.K[n].beta_coefficients(n + 1, n + 1)

    def p(self, n: int) -> BetaPoly:
        """L18's p_n (eq. 30): the n-th term of the normal form is (√κ/2C) V² (−α)ⁿ κ^{−n/2} p_n (i u'U'/V)^{n+1}.

        Matching with (κG/C) ρⁿ K[n]/n! gives p_n = 2 (−1)ⁿ c_n / (n! i^{n+1}), c_n the
        coefficient of (uU)^{n+1} in K[n]. (With K[0] = −iuU this makes p_0 = −2.)
        """
        phase = [(1, 0), (0, 1), (-1, 0), (0, -1)][(n + 1) % 4]  # i^{n+1}
        scale = Fraction(2 * (-1) ** n, math.factorial(n))
        out = []
        for re, im in self.kernel_coefficient(n):
            # (re + i im) / (pr + i pi) with |p| = 1: multiply by the conjugate
            q_re, q_im = re * phase[0] + im * phase[1], im * phase[0] - re * phase[1]
            if q_im:
                raise AssertionError(f"p_{n} is not real")
            out.append(q_re * scale)
        return beta_poly(out)

    def s(self, n: int) -> GaussianPoly:
        """L18's s_n (eq. 32): w[n] = β(u² + U²) s_n (ValueError if w[n] has not that factor)."""
        return self.w[n].divide_by_beta_u2_plus_U2()

    # ------------------------------------------------------------------ transformations
    def transformation(self, name: str) -> list[GaussianPoly]:
        """[ξ_{0,1}, ..., ξ_{0,N}] for name in {"u", "U", "L", "ell", "g"} (scaled; cached).

        u, U, L = −iuU: old = new + Σ ρⁿ/n! ξ_{0,n}(u', U').
        ell (the angle ℓ): ℓ = ℓ' + Σ ρⁿ/n! ξ_{0,n}, seeded by {ℓ; w_m} = (i/2)(u∂_u + U∂_U)w_m/(uU).
        g: g = g' + (1/G) Σ ρⁿ/n! ξ_{0,n}, seeded by {g; w_m} = −m w_m (from ∂ρᵐ/∂G = −m ρᵐ/G).
        """
        if name not in self._transforms:
            w, n = self.w, self.order
            seeds: dict[str, GaussianPoly | FirstBracket] = {
                "u": GaussianPoly.monomial(1, 0),
                "U": GaussianPoly.monomial(0, 1),
                "L": GaussianPoly.monomial(1, 1, 0, (0, -1)),
                "ell": lambda m: w[m].euler_operator_over_uU().scale((0, Fraction(1, 2))),
                "g": lambda m: w[m].scale(-m),
            }
            if name not in seeds:
                raise ValueError(f"unknown variable {name!r}; expected one of {sorted(seeds)}")
            self._transforms[name] = deprit_transform(seeds[name], w, n)
        return self._transforms[name]

    # ------------------------------------------------------------------ L14's tables
    def lara2014_tables(self) -> Lara2014Tables:
        """L14 Tables 2-5 regenerated (orders up to self.order, resp. self.order − 1 for Table 2).

        With uʲUᵏ = iʲ L^{(j+k)/2} e^{i(k−j)ℓ}, δ = ρL' and ε = 1:
        Table 2 (eq. 30): K[i+1]/(i+1)! = k(β) L'^{i+2} and q_i = −2k/β².
        Table 5 (eq. 34): ξ^L_{0,i}/i! = L'^{i+1}(a₀ + Σ a_m cos 2mℓ'), L_{i,0} = a₀/β², L_{i,m} = −a_m/(−β)ᵐ.
        Table 4 (eq. 33): ξ^ℓ_{0,i}/i! = L'^i Σ b_m sin 2mℓ', ℓ_{i,m} = b_m/(−β)ᵐ.
        Table 3 (eq. 32): ξ^g_{0,i}/i! = L'^{i+1} Σ b_m sin 2mℓ', g_{i,m} = −b_m/(−β)ᵐ.
        Any other Fourier term (a cosine in ℓ or g, a sine in L) must vanish: checked.
        """
        q = {}
        for i in range(1, self.order):
            const, _ = _fourier(self.K[i + 1], i + 2, math.factorial(i + 1))
            q[i] = tuple(-2 * c for c in beta_poly_shift_down(const[0], 2))
        tables: dict[str, dict[tuple[int, int], BetaPoly]] = {"g": {}, "ell": {}, "L": {}}
        for i in range(1, self.order + 1):
            fact = math.factorial(i)
            cos_l, sin_l = _fourier(self.transformation("L")[i - 1], i + 1, fact)
            cos_a, sin_a = _fourier(self.transformation("ell")[i - 1], i, fact)
            cos_g, sin_g = _fourier(self.transformation("g")[i - 1], i + 1, fact)
            _require_zero(sin_l, f"sines in the transformation of L at order {i}")
            _require_zero(cos_a, f"cosines in the transformation of ℓ at order {i}")
            _require_zero(cos_g, f"cosines in the transformation of g at order {i}")
            tables["L"][(i, 0)] = beta_poly_shift_down(cos_l.get(0, ()), 2)
            for m in sorted(set(cos_l) | set(sin_a) | set(sin_g)):
                if m == 0:
                    continue
                sign = (-1) ** m
                if m in cos_l:
                    tables["L"][(i, m)] = tuple(-sign * c for c in beta_poly_shift_down(cos_l[m], m))
                if m in sin_a:
                    tables["ell"][(i, m)] = tuple(sign * c for c in beta_poly_shift_down(sin_a[m], m))
                if m in sin_g:
                    tables["g"][(i, m)] = tuple(-sign * c for c in beta_poly_shift_down(sin_g[m], m))
        return Lara2014Tables(q, tables["g"], tables["ell"], tables["L"])


def _fourier(poly: GaussianPoly, power: int, divisor: int
             ) -> tuple[dict[int, BetaPoly], dict[int, BetaPoly]]:
    """poly/divisor = L^power Σ_m (a_m cos 2mℓ + b_m sin 2mℓ) with u = i√L e^{−iℓ}, U = √L e^{iℓ}.

    Returns ({m: a_m}, {m: b_m}) as real BetaPolys (zero ones omitted); raises if poly is not
    homogeneous of degree 2·power, has odd harmonics or complex a_m, b_m.
    From c_f = Σ_{k−j=f} iʲ q_jk: a_0 = c_0, a_m = c_{2m} + c_{−2m}, b_m = i(c_{2m} − c_{−2m}).
    """
    harm: dict[int, dict[int, tuple[Fraction, Fraction]]] = {}
    for (j, k, b), (re, im) in poly.terms().items():
        if j + k != 2 * power or (k - j) % 2:
            raise AssertionError(f"u^{j} U^{k} is not a term of L^{power} e^(2imℓ)")
        ph = [(1, 0), (0, 1), (-1, 0), (0, -1)][j % 4]  # iʲ
        c = (re * ph[0] - im * ph[1], re * ph[1] + im * ph[0])
        slot = harm.setdefault(k - j, {})
        old = slot.get(b, (Fraction(0), Fraction(0)))
        slot[b] = (old[0] + c[0], old[1] + c[1])
    cos_part: dict[int, BetaPoly] = {}
    sin_part: dict[int, BetaPoly] = {}
    top = max((b for slot in harm.values() for b in slot), default=0)
    for m in sorted({abs(f) // 2 for f in harm}):
        plus, minus = harm.get(2 * m, {}), harm.get(-2 * m, {})
        a, s = [], []
        for b in range(top + 1):
            cp = plus.get(b, (Fraction(0), Fraction(0)))
            cm = minus.get(b, (Fraction(0), Fraction(0))) if m else (Fraction(0), Fraction(0))
            ar, ai = cp[0] + cm[0], cp[1] + cm[1]
            br_, bi = -(cp[1] - cm[1]), cp[0] - cm[0]  # i (cp − cm)
            if ai or (m and bi):
                raise AssertionError(f"harmonic {2 * m} has a complex coefficient")
            a.append(ar / divisor)
            s.append(br_ / divisor if m else Fraction(0))
        if beta_poly(a):
            cos_part[m] = beta_poly(a)
        if beta_poly(s):
            sin_part[m] = beta_poly(s)
    return cos_part, sin_part


def _require_zero(part: dict[int, BetaPoly], what: str) -> None:
    if part:
        raise AssertionError(f"unexpected {what}: {part}")


@lru_cache(maxsize=4)
def sam_normal_form(order: int) -> SamNormalForm:
    """A cached :class:`SamNormalForm` (the tests and the numerical solution share it)."""
    return SamNormalForm(order)


# =========================================================================== numerics

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


# =========================================================================== cost study

def cost_table(order: int) -> list[OrderCost]:
    """CPU cost per order of a fresh normalisation to ``order`` (uncached), as in L18 Fig. 1."""
    return SamNormalForm(order).cost
