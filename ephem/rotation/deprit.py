"""Deprit's triangle: the Lie transform that normalises a Hamiltonian and carries functions through it.

Sources: A. Deprit (1969), Celest. Mech. 1, 12; M. Lara (2018), Appl. Math. Nonlinear Sci. 3(2), 537,
eq. 31 (the form used here).

For H = Σ εⁿ/n! H_{n,0} and a generating function W = Σ εⁿ/n! w_{n+1}, the triangle

    H_{i,j} = H_{i+1,j−1} + Σ_{m=0..i} C(i,m) {H_{i−m,j−1}; w_{m+1}}

gives the new Hamiltonian K_n = H_{0,n}; each order's w_n solves the homological equation
{h₀; w_n} = K_n − H̃_n, H̃_n the known terms of the row. :func:`deprit_normalize` runs it on
polynomials of :mod:`ephem.rotation.polynomials` for any h₀ ∝ uU (the kernel of its Lie operator is the
(uU)ʲ) with the caller's solver of the homological equation; :func:`deprit_transform` applies the
same triangle to a function f (H_{0,0} = f, H_{n,0} = 0), giving the old f in the new variables,
f = f' + Σ εⁿ/n! ξ_{0,n}. Nothing here is specific to one problem: Lara's free rotation
(:mod:`ephem.rotation.lie_series`) supplies h₀, h₁ and the solver.

Public API: :func:`deprit_normalize` (and its :class:`NormalForm`, with the CPU cost per order in
:class:`OrderCost`), :func:`deprit_transform`, the callable types :data:`Homological` and
:data:`FirstBracket`. Exact, dimensionless.
"""
from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from .polynomials import GaussianPoly


@dataclass
class OrderCost:
    """CPU seconds (time.process_time) spent at one order of the normalisation, split as in Lara (2018) Fig. 1.

    ``known`` fills the new row of the triangle with w_n = 0 (the known terms H̃_n: all
    the Poisson brackets); ``h_n`` selects the kernel terms K_n; ``s_n`` divides for w_n
    (the homological equation, Lara 2018 eq. 29); ``triangle`` adds the w_n contribution
    ({h₀; w_n} = K_n − H̃_n) to the row.
    """

    order: int
    known: float
    h_n: float
    s_n: float
    triangle: float
    row_terms: int      # terms in the new row of the triangle
    w_terms: int        # terms of w_n
    k_terms: int        # terms of K_n

    @property
    def total(self) -> float:
        return self.known + self.h_n + self.s_n + self.triangle


@dataclass
class NormalForm:
    """The output of :func:`deprit_normalize`: K[n] (K[0] = h₀) and w[n] (w[0] unused) as Deprit terms.

    The normal form is Σ εⁿ/n! K[n] and the generating function Σ εⁿ/n! w[n+1].
    """

    K: list[GaussianPoly]
    w: list[GaussianPoly | None]
    cost: list[OrderCost] = field(default_factory=list)

    @property
    def order(self) -> int:
        return len(self.K) - 1


Homological = Callable[[GaussianPoly], GaussianPoly]


def deprit_normalize(h_terms: Sequence[GaussianPoly], order: int, solve: Homological) -> NormalForm:
    """Deprit's triangle for H = Σ εⁿ/n! h_terms[n] (terms past the list are 0), to ``order``.

    The new Hamiltonian term K_n is the part of the known terms H̃_n in the kernel of the
    Lie operator, the monomials (uU)ʲ (as for any h₀ ∝ uU), and ``solve(image)`` returns the
    w_n with {h₀; w_n} = −image = K_n − H̃_n (the homological equation;
    :func:`ephem.rotation.lie_series.solve_sam_homological` for Lara's problem). Triangle (Lara 2018 eq. 31):
    H_{i,j} = H_{i+1,j−1} + Σ_{m=0..i} C(i,m){H_{i−m,j−1}; w_{m+1}}; the row i + j = n is
    first filled with w_n = 0, which gives H̃_n = H_{0,n}, and then {h₀; w_n}, which enters
    that row once through H_{n−1,1}, is added to every entry of the row.
    """
    zero = GaussianPoly()
    table: dict[tuple[int, int], GaussianPoly] = {(0, 0): h_terms[0]}
    for n in range(1, order + 1):
        table[(n, 0)] = h_terms[n] if n < len(h_terms) else zero
    w: list[GaussianPoly | None] = [None]
    K = [h_terms[0]]
    cost = []
    for n in range(1, order + 1):
        t0 = time.process_time()
        _fill_known_row(table, w, n)
        t1 = time.process_time()
        k_n, image = table[(0, n)].split_kernel()  # H̃_n = K_n + image
        t2 = time.process_time()
        w_n = solve(image)
        t3 = time.process_time()
        correction = -image  # {h₀; w_n} = K_n − H̃_n
        for j in range(1, n + 1):
            table[(n - j, j)] = table[(n - j, j)] + correction
        t4 = time.process_time()
        K.append(k_n)
        w.append(w_n)
        cost.append(OrderCost(n, t1 - t0, t2 - t1, t3 - t2, t4 - t3,
                              sum(len(table[(n - j, j)]) for j in range(1, n + 1)), len(w_n), len(k_n)))
    return NormalForm(K, w, cost)


def _fill_known_row(table, w, n: int) -> None:
    """Entries H_{n−j,j}, j = 1..n, of the triangle with w_n taken as 0 (it is not known yet)."""
    for j in range(1, n + 1):
        i = n - j
        acc = table[(i + 1, j - 1)]
        for m in range(min(i, n - 2) + 1):  # w_{m+1} with m + 1 ≤ n − 1
            acc = acc.add_multiple(table[(i - m, j - 1)].bracket(w[m + 1]), math.comb(i, m))
        table[(i, j)] = acc


FirstBracket = Callable[[int], GaussianPoly]


def deprit_transform(seed: GaussianPoly | FirstBracket, w: Sequence[GaussianPoly | None], order: int
                     ) -> list[GaussianPoly]:
    """[ξ_{0,1}, ..., ξ_{0,order}]: a function of the old variables in the new ones, f = f' + Σ εⁿ/n! ξ_{0,n}.

    ``seed`` is f itself when it is a polynomial, or, for a function that is not (an
    angle), the callable m ↦ {f; w_m}, which is all the triangle needs of it:
    ξ_{n,0} = 0 for n ≥ 1, so f enters only through ξ_{i,1} = {f; w_{i+1}}.
    """
    if order > len(w) - 1:
        raise ValueError(f"the generating function only reaches order {len(w) - 1}")
    first: FirstBracket = (lambda m: seed.bracket(w[m])) if isinstance(seed, GaussianPoly) else seed
    zero = GaussianPoly()
    table: dict[tuple[int, int], GaussianPoly] = {}
    for n in range(1, order + 1):
        for j in range(1, n + 1):
            i = n - j
            if j == 1:
                table[(i, 1)] = first(i + 1)
                continue
            acc = table.get((i + 1, j - 1), zero)
            for m in range(i + 1):
                acc = acc.add_multiple(table[(i - m, j - 1)].bracket(w[m + 1]), math.comb(i, m))
            table[(i, j)] = acc
    return [table[(0, n)] for n in range(1, order + 1)]
