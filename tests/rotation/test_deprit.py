"""Deprit's triangle (ephem/rotation/deprit.py), exact: on Lara's SAM problem (ephem/rotation/lie_series.py) the normal form
equals the Hamiltonian composed with the transformation, the transformation is canonical and commutes with
products to the truncation order, and an angle's seed (a first bracket) stands in for the function.
"""
import math
from fractions import Fraction

from ephem.rotation.deprit import deprit_transform
from ephem.rotation.lie_series import sam_normal_form
from ephem.rotation.polynomials import GaussianPoly, parse_polynomial
from tests.rotation.test_lie_series import ORDER  # the normal form (sam_normal_form's cache) the suites share



def _series_mul(a, b, order):
    return [sum((a[i] * b[n - i] for i in range(n + 1)), GaussianPoly()) for n in range(order + 1)]


def _plain_series(seed: GaussianPoly, xi, order):
    """[seed, ξ₁/1!, ξ₂/2!, ...]: the transformation as a plain power series in ε."""
    return [seed] + [xi[n - 1].scale(Fraction(1, math.factorial(n))) for n in range(1, order + 1)]


def test_normal_form_by_composition():
    # h₀(u, U) + ε h₁(u, U) with u, U the transformation series = Σ εⁿ/n! K_n + O(ε^{N+1})
    order = 6
    nf = sam_normal_form(ORDER)
    u = _plain_series(GaussianPoly.monomial(1, 0), nf.transformation("u"), order)
    U = _plain_series(GaussianPoly.monomial(0, 1), nf.transformation("U"), order)
    uU = _series_mul(u, U, order)
    u2U2 = _series_mul(uU, uU, order)
    u3U = _series_mul(uU, _series_mul(u, u, order), order)
    uU3 = _series_mul(uU, _series_mul(U, U, order), order)
    for n in range(order + 1):
        value = uU[n].scale((0, -1))
        if n >= 1:
            value = value + u2U2[n - 1].scale(Fraction(1, 2)) + (u3U[n - 1] - uU3[n - 1]) * parse_polynomial("-i*b/4")
        assert value == nf.K[n].scale(Fraction(1, math.factorial(n))), n


def test_transformation_is_canonical_to_the_truncation_order(nf):
    # {u, U} in the new variables = 1 + O(ε^{N+1})
    order = 8
    u = _plain_series(GaussianPoly.monomial(1, 0), nf.transformation("u"), order)
    U = _plain_series(GaussianPoly.monomial(0, 1), nf.transformation("U"), order)
    for n in range(order + 1):
        total = sum((u[i].bracket(U[n - i]) for i in range(n + 1)), GaussianPoly())
        assert total == (GaussianPoly.constant(1) if n == 0 else GaussianPoly()), n


def test_triangle_on_functions_commutes_with_products(nf):
    # the Lie transform of L = −iuU is −i (transform of u)(transform of U)
    order = 8
    u = _plain_series(GaussianPoly.monomial(1, 0), nf.transformation("u"), order)
    U = _plain_series(GaussianPoly.monomial(0, 1), nf.transformation("U"), order)
    L = _plain_series(GaussianPoly.monomial(1, 1, 0, (0, -1)), nf.transformation("L"), order)
    assert [x.scale((0, -1)) for x in _series_mul(u, U, order)] == L


def test_angle_seed_matches_the_bracket_of_ell():
    # {ℓ; w} from e^{2iℓ} = iU/u: for w = u^j U^k it is −(j + k)/(2i) u^{j−1}U^{k−1}, worked by hand
    # here for one w; the ℓ-series as a whole is checked against the integrated motion below
    w = parse_polynomial("3*u**3*U - 2*i*b*u*U**5")
    nf = sam_normal_form(ORDER)
    seeded = deprit_transform(lambda m: w.euler_operator_over_uU().scale((0, Fraction(1, 2))), [None, w], 1)[0]
    assert seeded == parse_polynomial("(i/2)*(12*u**2 - 12*i*b*U**4)")
    assert nf.transformation("ell")[0] == nf.w[1].euler_operator_over_uU().scale((0, Fraction(1, 2)))
