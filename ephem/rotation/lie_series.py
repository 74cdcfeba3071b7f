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
:func:`sam_normal_form` (K_n, w_n, p_n, s_n, the transformations of u, U, L, ℓ, g,
:meth:`SamNormalForm.lara2014_tables`, and ``cost``: each order's CPU and sizes, as L18 Fig. 1); the polynomials
are those of :mod:`ephem.rotation.polynomials` (Q(i)[u, U, β] with the Poisson bracket) and the triangle is the generic
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
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

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


