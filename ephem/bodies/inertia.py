"""Principal moments of inertia from what is measured, with their covariance.

Missions and observers do not measure A, B and C: they measure a gravity field (J2, C22, S22), a polar
moment C/(MR²) or a dynamical ellipticity H_d (from the precession), a shape, or a libration. The moments of a
catalogue record are derived from those (``[body.inertia.derived_from]``, data/catalogue/SCHEMA.md), and since
all three moments come from the same few numbers, their errors are correlated: a polar moment known to 2 %
moves A, B and C together and leaves H_d's 2 % error, not the 2/√3 % three independent moments would give.

Each method maps its inputs to (A, B, C); :func:`derive` returns the moments with their 1-σ and correlation
matrix (Σ_ABC = J Σ_in Jᵀ, J by central differences: the maps are at most quadratic, so the differences are
exact to rounding). The inputs are taken as independent; a moment's σ is None (unknown, not zero) when any
input it depends on has none.

Pure Python: the catalogue loads without numpy.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..base.errors import InvalidInputError


def hd_of_moments(A, B, C):
    """H_d = (C - (A+B)/2) / C (Petit et al. eq. 11) of principal moments A <= B <= C (numbers or arrays; no checks:
    :func:`ephem.bodies.catalogue.dynamical_ellipticity` validates one body's)."""
    return (C - 0.5 * (A + B)) / C


def moments_from_gravity(polar_moment: float, J2: float, C22: float, S22: float) -> tuple[float, float, float]:
    """A, B, C in units of M R² from the normalised polar moment C/(MR²) and the unnormalised degree-2 gravity
    coefficients at the same reference radius R (Petit et al. 2014, eq. 31).

    J2 = (C − (A+B)/2)/(MR²) and, in a frame that is not the principal one, the equatorial term is the invariant
    q = √(C22² + S22²) = (B − A)/(4 MR²); so A = C̄ − J2 − 2q, B = C̄ − J2 + 2q and H_d = J2 / C̄.
    """
    q = math.hypot(C22, S22)
    return polar_moment - J2 - 2.0 * q, polar_moment - J2 + 2.0 * q, polar_moment


def moments_from_gravity_and_mean_moment(mean_moment: float, J2: float, C22: float,
                                         S22: float) -> tuple[float, float, float]:
    """A, B, C in units of M R² from the normalised mean moment Ī = (A + B + C)/(3MR²) (as a hydrostatic
    interpretation of the gravity gives it) and the degree-2 gravity: C/(MR²) = Ī + (2/3) J2, then
    :func:`moments_from_gravity`."""
    return moments_from_gravity(mean_moment + 2.0 * J2 / 3.0, J2, C22, S22)


def moments_from_gravity_and_ellipticity(dynamical_ellipticity: float, J2: float, C22: float,
                                         S22: float) -> tuple[float, float, float]:
    """A, B, C in units of M R² from the dynamical ellipticity H_d (as the precession measures it) and the
    degree-2 gravity: C/(MR²) = J2 / H_d, then :func:`moments_from_gravity`."""
    return moments_from_gravity(J2 / dynamical_ellipticity, J2, C22, S22)


def moments_from_ellipsoid(a: float, b: float, c: float) -> tuple[float, float, float]:
    """A, B, C per unit mass (the square of the semi-axes' unit) of a uniform ellipsoid with semi-axes
    a ≥ b ≥ c (Petit et al. 2014, eq. 30): A = (b² + c²)/5, B = (a² + c²)/5, C = (a² + b²)/5."""
    return (b * b + c * c) / 5.0, (a * a + c * c) / 5.0, (a * a + b * b) / 5.0


def moments_from_libration(beta: float, gamma: float) -> tuple[float, float, float]:
    """A, B, C with C = 1 from the ratios the lunar laser ranging measures, β = (C − A)/B and γ = (B − A)/C:
    B = (1 + γ)/(1 + β), A = B − γ."""
    B = (1.0 + gamma) / (1.0 + beta)
    return B - gamma, B, 1.0


@dataclass(frozen=True)
class Method:
    """A way to the moments: its function, its inputs in order (TOML keys), their units and the moments' unit
    (``None``: the unit of the first input, squared, for lengths)."""

    function: object
    inputs: tuple[str, ...]
    input_unit: str
    description: str


METHODS = {
    "gravity_and_polar_moment": Method(moments_from_gravity, ("polar_moment", "J2", "C22", "S22"), "",
                                       "C/(MR^2) and degree-2 gravity (Petit et al. 2014 eq. 31)"),
    "gravity_and_mean_moment": Method(moments_from_gravity_and_mean_moment, ("mean_moment", "J2", "C22", "S22"), "",
                                      "(A+B+C)/(3MR^2) and degree-2 gravity: C/(MR^2) = mean + 2 J2/3, then eq. 31"),
    "gravity_and_dynamical_ellipticity": Method(moments_from_gravity_and_ellipticity,
                                                ("dynamical_ellipticity", "J2", "C22", "S22"), "",
                                                "H_d and degree-2 gravity: C/(MR^2) = J2/H_d, then eq. 31"),
    "uniform_ellipsoid": Method(moments_from_ellipsoid, ("a", "b", "c"), "km",
                                "uniform-density ellipsoid of semi-axes a >= b >= c (Petit et al. 2014 eq. 30)"),
    "libration": Method(moments_from_libration, ("beta", "gamma"), "",
                        "lunar libration ratios beta = (C-A)/B, gamma = (B-A)/C, with C = 1"),
}


@dataclass(frozen=True)
class DerivedMoments:
    """The moments (A, B, C), their 1-σ (None where an input has none) and their correlations
    {("inertia.A", "inertia.B"): ρ, …} (only where all three σ are known)."""

    moments: tuple[float, float, float]
    unit: str
    sigma: tuple[float | None, float | None, float | None]
    correlations: dict
    missing_sigma: tuple[str, ...]


def derive(method: str, values: dict[str, float], sigmas: dict[str, float | None],
           body: str | None = None) -> DerivedMoments:
    """The moments by ``method`` (:data:`METHODS`) from ``values`` {input: value in the method's unit} and their
    1-σ ``sigmas`` (same unit; None: not published), with the moments' covariance J Σ Jᵀ.

    Raises :class:`~ephem.base.errors.InvalidInputError` naming ``inertia.derived_from.<input>`` for a missing or
    impossible input (moments that are not those of a rigid body spinning about its largest axis).
    """
    where = "inertia.derived_from"
    m = METHODS.get(method)
    if m is None:
        raise InvalidInputError(f"{where}.method", f"must be one of {', '.join(METHODS)}, got {method!r}", body)
    for key in m.inputs:
        if key not in values:
            raise InvalidInputError(f"{where}.{key}", f"missing: method {method!r} needs {', '.join(m.inputs)}", body)
    x = [float(values[k]) for k in m.inputs]
    if method == "uniform_ellipsoid" and not x[0] >= x[1] >= x[2] > 0.0:
        raise InvalidInputError(where, f"semi-axes must satisfy a >= b >= c > 0, got {x}", body)
    if method in ("gravity_and_dynamical_ellipticity",) and not 0.0 < x[0] <= 0.5:
        raise InvalidInputError(f"{where}.dynamical_ellipticity", f"must lie in (0, 0.5], got {x[0]}", body)
    moments = m.function(*x)
    A, B, C = moments
    if not (0.0 < A <= B <= C <= A + B):
        raise InvalidInputError(where, f"the inputs give A={A:.8g}, B={B:.8g}, C={C:.8g}: not the moments of a "
                                f"rigid body with 0 < A <= B <= C <= A + B", body)
    sig = [sigmas.get(k) for k in m.inputs]
    missing = tuple(k for k, s in zip(m.inputs, sig) if s is None)
    # the Jacobian by central differences, a step of 1e-6 of the input's size (the maps are at most quadratic)
    cols = []   # cols[j][i] = d moment_i / d input_j
    for j, xj in enumerate(x):
        h = 1e-6 * (abs(xj) or 1.0)
        xp, xm = list(x), list(x)
        xp[j] += h
        xm[j] -= h
        yp, ym = m.function(*xp), m.function(*xm)
        cols.append([(p - q) / (2.0 * h) for p, q in zip(yp, ym)])
    jac = [[cols[j][i] for j in range(len(x))] for i in range(3)]
    # a moment's σ is unknown if an input it depends on has no σ
    depends = [[abs(jac[i][j]) > 0.0 for j in range(len(x))] for i in range(3)]
    s_in = [s or 0.0 for s in sig]
    cov = [[sum(jac[i][k] * s_in[k] ** 2 * jac[l][k] for k in range(len(x))) for l in range(3)] for i in range(3)]
    sigma = tuple(None if any(depends[i][j] and sig[j] is None for j in range(len(x))) else math.sqrt(cov[i][i])
                  for i in range(3))
    corr = {}
    labels = ("inertia.A", "inertia.B", "inertia.C")
    for i in range(3):
        for l in range(i + 1, 3):
            if sigma[i] and sigma[l]:
                corr[(labels[i], labels[l])] = max(-1.0, min(1.0, cov[i][l] / (sigma[i] * sigma[l])))
    unit = "km2" if m.input_unit == "km" else ""
    return DerivedMoments(moments, unit, sigma, corr, missing)
