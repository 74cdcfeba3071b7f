"""The exact polynomial ring Q(i)[u, U, β] of the Lie-transform engine, with its Poisson bracket.

A :class:`GaussianPoly` is a polynomial in u, U and β with Gaussian-rational coefficients, u a
coordinate and U its momentum: sums, products, powers and the Poisson bracket

    {f; g} = f_u g_U − f_U g_u,   {uᵃUᵇ; uᶜUᵈ} = (ad − bc) u^{a+c−1} U^{b+d−1},

all exact, on Python ints. The Lie operator of uU is diagonal on monomials, {uʲUᵏ; uU} = (j − k) uʲUᵏ:
:meth:`GaussianPoly.split_kernel` separates its kernel, the (uU)ʲ, from its image and
:meth:`GaussianPoly.invert_bracket_with_uU` inverts it on the image (the homological equation of any
h₀ ∝ uU). A :data:`BetaPoly` is a real polynomial in β alone (the coefficients of printed series);
:func:`parse_polynomial` reads the printed expressions of data/lara/.

Public API: :class:`GaussianPoly`, :data:`BetaPoly`, :func:`beta_poly`, :func:`beta_poly_str`,
:func:`beta_poly_shift_down`, :func:`parse_polynomial`. Dimensionless.
"""
from __future__ import annotations

import ast
import math
from collections.abc import Iterable, Mapping
from fractions import Fraction

# A monomial u^j U^k β^b is keyed by one int, j<<42 | k<<21 | b: the key of a product is then the
# sum of the keys, which keeps the bracket's inner loop to integer additions (10x faster than tuples).
_SH_K = 21
_SH_J = 42
_MASK = (1 << _SH_K) - 1
_BRACKET_SHIFT = (1 << _SH_J) + (1 << _SH_K)  # the bracket lowers j and k by one
_MAX_EXP = 1 << 20


def _key(j: int, k: int, b: int) -> int:
    if not (0 <= j < _MAX_EXP and 0 <= k < _MAX_EXP and 0 <= b < _MAX_EXP):
        raise ValueError(f"exponents must lie in [0, 2^20), got {(j, k, b)}")
    return (j << _SH_J) | (k << _SH_K) | b


def _unkey(key: int) -> tuple[int, int, int]:
    return key >> _SH_J, (key >> _SH_K) & _MASK, key & _MASK


def _as_gaussian(c) -> tuple[Fraction, Fraction]:
    """A Gaussian rational (re, im) from an int, a Fraction, a (re, im) pair or a complex with integral parts."""
    if isinstance(c, tuple):
        return Fraction(c[0]), Fraction(c[1])
    if isinstance(c, complex):
        if c.real != int(c.real) or c.imag != int(c.imag):
            raise TypeError("a complex float is only accepted with integral parts; pass (re, im) Fractions")
        return Fraction(int(c.real)), Fraction(int(c.imag))
    return Fraction(c), Fraction(0)


class GaussianPoly:
    """An exact polynomial in u, U and β with Gaussian-rational coefficients (Q(i)[u, U, β]).

    Stored as integer Gaussian numerators over one positive common denominator, kept
    in lowest terms, so that equality is structural and the arithmetic is on Python
    ints (no per-coefficient Fraction gcds in the inner loops).
    """

    __slots__ = ("_d", "_t")

    def __init__(self, terms: Mapping[tuple[int, int, int], object] | None = None):
        """``terms`` maps (j, k, b), the exponents of u, U, β, to a coefficient (int, Fraction or (re, im))."""
        if not terms:
            self._t, self._d = {}, 1
            return
        coeffs = {_key(*jkb): _as_gaussian(c) for jkb, c in terms.items()}
        den = 1
        for re, im in coeffs.values():
            den = math.lcm(den, re.denominator, im.denominator)
        raw = {key: (int(re * den), int(im * den)) for key, (re, im) in coeffs.items()}
        self._t, self._d = _normalise(raw, den)

    # ------------------------------------------------------------------ construction
    @classmethod
    def _raw(cls, terms: dict[int, tuple[int, int]], den: int) -> GaussianPoly:
        p = cls.__new__(cls)
        p._t, p._d = _normalise(terms, den)
        return p

    @classmethod
    def monomial(cls, j: int, k: int, b: int = 0, coeff=1) -> GaussianPoly:
        """coeff · uʲ Uᵏ βᵇ."""
        return cls({(j, k, b): coeff})

    @classmethod
    def constant(cls, coeff) -> GaussianPoly:
        return cls({(0, 0, 0): coeff})

    # ------------------------------------------------------------------ inspection
    def terms(self) -> dict[tuple[int, int, int], tuple[Fraction, Fraction]]:
        """{(j, k, b): (Re, Im)} with exact Fractions."""
        d = self._d
        return {_unkey(key): (Fraction(re, d), Fraction(im, d)) for key, (re, im) in self._t.items()}

    def __len__(self) -> int:
        return len(self._t)

    def is_zero(self) -> bool:
        return not self._t

    def monomials_uU(self) -> set[tuple[int, int]]:
        """The (j, k) of the u^j U^k present (whatever their β powers)."""
        return {(key >> _SH_J, (key >> _SH_K) & _MASK) for key in self._t}

    def __eq__(self, other) -> bool:
        if not isinstance(other, GaussianPoly):
            other = GaussianPoly.constant(other)
        return self._d == other._d and self._t == other._t

    __hash__ = None  # mutable-looking value type: compare, don't hash

    def __repr__(self) -> str:
        return f"GaussianPoly({self})"

    def __str__(self) -> str:
        if not self._t:
            return "0"
        parts = []
        for (j, k, b), (re, im) in sorted(self.terms().items(), key=lambda t: (-(t[0][0] + t[0][1]), t[0])):
            c = _gaussian_str(re, im)
            mono = "*".join(s for s in (_pow_str("u", j), _pow_str("U", k), _pow_str("b", b)) if s)
            parts.append(f"({c})*{mono}" if mono else f"({c})")
        return " + ".join(parts)

    # ------------------------------------------------------------------ arithmetic
    def _combine(self, other: GaussianPoly, cs: int, co: int) -> GaussianPoly:
        """cs·self + co·other for integer cs, co."""
        den = math.lcm(self._d, other._d)
        fs, fo = den // self._d * cs, den // other._d * co
        out = {key: (re * fs, im * fs) for key, (re, im) in self._t.items()}
        get = out.get
        for key, (re, im) in other._t.items():
            old = get(key)
            out[key] = (re * fo, im * fo) if old is None else (old[0] + re * fo, old[1] + im * fo)
        return GaussianPoly._raw(out, den)

    def __add__(self, other) -> GaussianPoly:
        if not isinstance(other, GaussianPoly):
            other = GaussianPoly.constant(other)
        return self._combine(other, 1, 1)

    __radd__ = __add__

    def __sub__(self, other) -> GaussianPoly:
        if not isinstance(other, GaussianPoly):
            other = GaussianPoly.constant(other)
        return self._combine(other, 1, -1)

    def __rsub__(self, other) -> GaussianPoly:
        return GaussianPoly.constant(other) - self

    def __neg__(self) -> GaussianPoly:
        return GaussianPoly._raw({key: (-re, -im) for key, (re, im) in self._t.items()}, self._d)

    def add_multiple(self, other: GaussianPoly, times: int) -> GaussianPoly:
        """self + times·other, times an integer (a binomial coefficient in the triangle)."""
        return self._combine(other, 1, times)

    def scale(self, coeff) -> GaussianPoly:
        """coeff·self for a Gaussian rational coeff (int, Fraction, (re, im))."""
        cr, ci = _as_gaussian(coeff)
        den = cr.denominator * ci.denominator
        a, b = cr.numerator * ci.denominator, ci.numerator * cr.denominator
        out = {key: (re * a - im * b, re * b + im * a) for key, (re, im) in self._t.items()}
        return GaussianPoly._raw(out, self._d * den)

    def __mul__(self, other) -> GaussianPoly:
        if not isinstance(other, GaussianPoly):
            return self.scale(other)
        out: dict[int, tuple[int, int]] = {}
        get = out.get
        olist = list(other._t.items())
        for kp, (pr, pi) in self._t.items():
            for kq, (qr, qi) in olist:
                key = kp + kq
                re, im = pr * qr - pi * qi, pr * qi + pi * qr
                old = get(key)
                out[key] = (re, im) if old is None else (old[0] + re, old[1] + im)
        return GaussianPoly._raw(out, self._d * other._d)

    __rmul__ = __mul__

    def __pow__(self, n: int) -> GaussianPoly:
        if not isinstance(n, int) or n < 0:
            raise ValueError("only non-negative integer powers")
        out = GaussianPoly.constant(1)
        for _ in range(n):
            out = out * self
        return out

    def bracket(self, other: GaussianPoly) -> GaussianPoly:
        """The Poisson bracket {self; other} = self_u other_U − self_U other_u (u coordinate, U momentum).

        For monomials, {uᵃUᵇ; uᶜUᵈ} = (ad − bc) u^{a+c−1} U^{b+d−1}, so the bracket is one
        pass over the pairs of terms; this is where the engine spends its time.
        """
        out: dict[int, tuple[int, int]] = {}
        get = out.get
        olist = [(kq, kq >> _SH_J, (kq >> _SH_K) & _MASK, qr, qi) for kq, (qr, qi) in other._t.items()]
        shift = _BRACKET_SHIFT
        for kp, (pr, pi) in self._t.items():
            a, b = kp >> _SH_J, (kp >> _SH_K) & _MASK
            for kq, c, d, qr, qi in olist:
                f = a * d - b * c
                if f:
                    key = kp + kq - shift
                    re, im = f * (pr * qr - pi * qi), f * (pr * qi + pi * qr)
                    old = get(key)
                    out[key] = (re, im) if old is None else (old[0] + re, old[1] + im)
        return GaussianPoly._raw(out, self._d * other._d)

    # ------------------------------------------------------------------ structure
    def split_kernel(self) -> tuple[GaussianPoly, GaussianPoly]:
        """(the (uU)ʲ terms, the rest): the kernel and image parts of the Lie operator {·; uU} (of h₀ ∝ uU)."""
        kern, rest = {}, {}
        for key, v in self._t.items():
            (kern if key >> _SH_J == (key >> _SH_K) & _MASK else rest)[key] = v
        return GaussianPoly._raw(kern, self._d), GaussianPoly._raw(rest, self._d)

    def invert_bracket_with_uU(self) -> GaussianPoly:
        """The w with {w; uU} = self and no (uU)ʲ term: Σ q_jk/(j − k) uʲUᵏ for self = Σ q_jk uʲUᵏ.

        {uʲUᵏ; uU} = (j − k) uʲUᵏ, so the Lie operator of uU is inverted monomial by monomial on its
        image; a kernel term (uU)ʲ of self has no solution (ValueError). This is the homological
        equation of any h₀ ∝ uU (:func:`ephem.rotation.lie_series.solve_sam_homological` for Lara's problem).
        """
        lcm = 1
        for key in self._t:
            j, k, _ = _unkey(key)
            if j == k:
                raise ValueError(f"(uU)^{j} is in the kernel: it has no solution")
            lcm = math.lcm(lcm, abs(j - k))
        out = {}
        for key, (re, im) in self._t.items():
            j, k, _ = _unkey(key)
            f = lcm // (j - k)
            out[key] = (re * f, im * f)
        return GaussianPoly._raw(out, self._d * lcm)

    def euler_operator_over_uU(self) -> GaussianPoly:
        """(u ∂_u + U ∂_U) self / (uU): exact when every monomial has j, k ≥ 1 (else ValueError)."""
        out = {}
        for key, (re, im) in self._t.items():
            j, k, b = _unkey(key)
            if j == 0 or k == 0:
                raise ValueError(f"u^{j} U^{k} is not divisible by uU")
            out[_key(j - 1, k - 1, b)] = ((j + k) * re, (j + k) * im)
        return GaussianPoly._raw(out, self._d)

    def divide_by_beta_u2_plus_U2(self) -> GaussianPoly:
        """self / (β(u² + U²)), exactly (ValueError if it does not divide: then Lara (2018) eq. 32's form
        of the generator fails).

        Long division in u: the term of highest power of u, c u^j U^k, gives the quotient
        term c u^{j−2} U^k and leaves −c u^{j−2} U^{k+2}; the remainder must vanish.
        """
        rem = dict(self._t)
        quot: dict[int, tuple[int, int]] = {}
        while rem:
            key = max(rem, key=lambda q: q >> _SH_J)
            j, k, b = _unkey(key)
            if j < 2 or b < 1:
                raise ValueError("not divisible by β(u² + U²)")
            re, im = rem.pop(key)
            quot[_key(j - 2, k, b - 1)] = (re, im)
            other = _key(j - 2, k + 2, b)
            ore, oim = rem.get(other, (0, 0))
            ore, oim = ore - re, oim - im
            if ore or oim:
                rem[other] = (ore, oim)
            else:
                rem.pop(other, None)
        return GaussianPoly._raw(quot, self._d)

    def beta_coefficients(self, j: int, k: int) -> list[tuple[Fraction, Fraction]]:
        """The coefficient of uʲUᵏ as a polynomial in β: [(Re, Im) of β⁰, β¹, ...]."""
        top = max((b for (jj, kk, b) in self.terms() if (jj, kk) == (j, k)), default=-1)
        out = [(Fraction(0), Fraction(0))] * (top + 1)
        for (jj, kk, b), c in self.terms().items():
            if (jj, kk) == (j, k):
                out[b] = c
        return out

    # ------------------------------------------------------------------ numerics
    def collapse(self, beta: float) -> dict[tuple[int, int], complex]:
        """{(j, k): coefficient of uʲUᵏ at this β} in complex floating point."""
        out: dict[tuple[int, int], complex] = {}
        d = self._d
        for key, (re, im) in self._t.items():
            j, k, b = _unkey(key)
            c = complex(Fraction(re, d), Fraction(im, d)) * beta**b
            out[(j, k)] = out.get((j, k), 0.0) + c
        return out

    def evaluate(self, u: complex, U: complex, beta: float) -> complex:
        """The polynomial's value in complex floating point (for checks; for speed, :meth:`collapse` once)."""
        return sum(c * u**j * U**k for (j, k), c in self.collapse(beta).items())


def _normalise(raw: dict[int, tuple[int, int]], den: int) -> tuple[dict[int, tuple[int, int]], int]:
    """Drop zero terms and reduce numerators and denominator by their gcd (lowest terms, den > 0)."""
    terms = {key: v for key, v in raw.items() if v[0] or v[1]}
    if not terms:
        return {}, 1
    g = den
    for re, im in terms.values():
        g = math.gcd(g, re, im)
        if g == 1:
            return terms, den
    return {key: (re // g, im // g) for key, (re, im) in terms.items()}, den // g


def _pow_str(name: str, e: int) -> str:
    return "" if e == 0 else name if e == 1 else f"{name}**{e}"


def _gaussian_str(re: Fraction, im: Fraction) -> str:
    if im == 0:
        return str(re)
    if re == 0:
        return f"{im}*i"
    return f"{re} + {im}*i"


# ---------------------------------------------------------------------- polynomials in β alone

BetaPoly = tuple[Fraction, ...]  # real coefficients of β⁰, β¹, ... (trailing zeros stripped)


def beta_poly(coeffs: Iterable) -> BetaPoly:
    """A BetaPoly from coefficients of ascending powers, trailing zeros dropped."""
    out = [Fraction(c) for c in coeffs]
    while out and out[-1] == 0:
        out.pop()
    return tuple(out)


def beta_poly_str(p: BetaPoly) -> str:
    return " + ".join(f"{c}*b**{e}" if e else str(c) for e, c in enumerate(p) if c) or "0"


def beta_poly_shift_down(p: BetaPoly, m: int) -> BetaPoly:
    """p / βᵐ, exactly (ValueError if a lower power is present): a printed coefficient that carries βᵐ."""
    if any(c for c in p[:m]):
        raise ValueError(f"{beta_poly_str(p)} is not divisible by β^{m}")
    return beta_poly(p[m:])


# ---------------------------------------------------------------------- printed expressions

def parse_polynomial(text: str) -> GaussianPoly:
    """A GaussianPoly from a Python-syntax expression in u, U, b (β) and i (√−1).

    Integers, + − * / and ** with integer exponents only: division only by a constant.
    Used to read the printed polynomials of data/lara/ (e.g. "i/64*(24*i*(b**2+2)*u*U)").
    """
    return _eval_node(ast.parse(text.strip(), mode="eval").body)


_NAMES = {"u": (1, 0, 0, 1), "U": (0, 1, 0, 1), "b": (0, 0, 1, 1), "i": (0, 0, 0, (0, 1))}


def _eval_node(node) -> GaussianPoly:
    if isinstance(node, ast.Constant) and isinstance(node.value, int):
        return GaussianPoly.constant(node.value)
    if isinstance(node, ast.Name) and node.id in _NAMES:
        j, k, b, c = _NAMES[node.id]
        return GaussianPoly.monomial(j, k, b, c)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        v = _eval_node(node.operand)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp):
        left = _eval_node(node.left)
        if isinstance(node.op, ast.Pow):
            if not (isinstance(node.right, ast.Constant) and isinstance(node.right.value, int)):
                raise ValueError("only integer constant exponents")  # noqa: TRY004 (a parse error)
            return left ** node.right.value
        right = _eval_node(node.right)
        if isinstance(node.op, ast.Add):
            return left + right
        if isinstance(node.op, ast.Sub):
            return left - right
        if isinstance(node.op, ast.Mult):
            return left * right
        if isinstance(node.op, ast.Div):
            terms = right.terms()
            if set(terms) != {(0, 0, 0)}:
                raise ValueError("division only by a constant")
            re, im = terms[(0, 0, 0)]
            n2 = re * re + im * im
            return left.scale((re / n2, -im / n2))
    raise ValueError(f"unsupported expression: {ast.dump(node)}")
