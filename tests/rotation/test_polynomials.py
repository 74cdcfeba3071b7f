"""The exact polynomial ring (ephem/rotation/polynomials.py): the Poisson bracket's algebra, the parser of printed
expressions and the exact arithmetic, and the inverse of the Lie operator of uU."""
import random
from fractions import Fraction

import pytest

from ephem.rotation.polynomials import GaussianPoly, beta_poly, beta_poly_shift_down, parse_polynomial


def _random_poly(rng: random.Random, terms: int = 5) -> GaussianPoly:
    return GaussianPoly({(rng.randrange(4), rng.randrange(4), rng.randrange(3)):
                         (Fraction(rng.randrange(-9, 10), rng.randrange(1, 6)), Fraction(rng.randrange(-9, 10), 7))
                         for _ in range(terms)})


def test_poisson_bracket_algebra():
    rng = random.Random(2018)
    for _ in range(20):
        f, g, h = (_random_poly(rng) for _ in range(3))
        assert f.bracket(g) == -g.bracket(f)
        assert f.bracket(g * h) == f.bracket(g) * h + g * f.bracket(h)               # Leibniz
        jacobi = f.bracket(g.bracket(h)) + g.bracket(h.bracket(f)) + h.bracket(f.bracket(g))
        assert jacobi.is_zero()
    assert GaussianPoly.monomial(1, 0).bracket(GaussianPoly.monomial(0, 1)) == 1  # {u; U} = 1


def test_parse_polynomial_and_exact_arithmetic():
    p = parse_polynomial("i/64*(24*i*(b**2 + 2)*u*U)")
    assert p.terms() == {(1, 1, 2): (Fraction(-3, 8), 0), (1, 1, 0): (Fraction(-3, 4), 0)}
    assert parse_polynomial("(u + U)**2 - u**2 - U**2") == parse_polynomial("2*u*U")
    with pytest.raises(ValueError):
        parse_polynomial("u/U")
    with pytest.raises(ValueError):
        parse_polynomial("u**b")


def test_the_lie_operator_of_uU_is_inverted_on_its_image():
    # {w; uU} = image with no (uU)^j in w: the homological equation of any h₀ ∝ uU
    rng = random.Random(29)
    uU = GaussianPoly.monomial(1, 1)
    for _ in range(20):
        kernel, image = _random_poly(rng).split_kernel()
        assert all(j == k for j, k in kernel.monomials_uU()) and all(j != k for j, k in image.monomials_uU())
        w = image.invert_bracket_with_uU()
        assert w.bracket(uU) == image
        assert w.split_kernel()[0].is_zero()
    assert parse_polynomial("3*u**3*U").invert_bracket_with_uU() == parse_polynomial("3/2*u**3*U")
    with pytest.raises(ValueError):
        parse_polynomial("u**2 + 2*u*U").invert_bracket_with_uU()


def test_beta_poly_shift_down_divides_exactly():
    assert beta_poly_shift_down(beta_poly([0, 0, Fraction(1, 2), 3]), 2) == (Fraction(1, 2), 3)
    assert beta_poly_shift_down(beta_poly([0, 0]), 2) == ()
    with pytest.raises(ValueError):
        beta_poly_shift_down(beta_poly([1, 0, 3]), 1)
