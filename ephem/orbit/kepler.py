"""Two-body orbit: Kepler's equation, anomalies and the orbit's orientation.

Pure numerics: angles in radians, times in days, distances in AU.
"""
from __future__ import annotations

import math

import numpy as np

from ..base.centres import GM_CENTER
from ..base.constants import AU_M, DAY_S


def mean_motion_rad_per_day(a_au, center: str = "Sun", mass_ratio: float = 0.0):
    """Keplerian mean motion n = sqrt(GM (1 + m/M) / a^3), rad/day (a float, or an array for an array of a).

    ``mass_ratio`` is the orbiting body's mass over the centre's (negligible
    for asteroids; 1/328900.56 for the Earth-Moon barycentre).
    """
    gm = GM_CENTER[center] * (1.0 + mass_ratio)
    if np.ndim(a_au) == 0:
        return math.sqrt(gm / (a_au * AU_M) ** 3) * DAY_S
    return np.sqrt(gm / (np.asarray(a_au, dtype=float) * AU_M) ** 3) * DAY_S


def _e_minus_sin(E: np.ndarray) -> np.ndarray:
    """``E - sin E`` without cancellation for small ``|E|`` (Taylor series
    below 1, summed to ``E^25/25!`` < 1e-25; direct above)."""
    E = np.asarray(E, dtype=float)
    small = np.abs(E) < 1.0
    if not small.any():          # no point takes the series (Newton's last steps on a few points, often one)
        return E - np.sin(E)
    x2 = E * E
    series = np.ones_like(E)
    for n in range(11, 0, -1):   # E^3/3! (1 - E^2/(4*5) (1 - E^2/(6*7) (...))), on every point: no gather
        series = 1.0 - x2 / ((2 * n + 2) * (2 * n + 3)) * series
    if small.all():
        return E * x2 / 6.0 * series
    return np.where(small, E * x2 / 6.0 * series, E - np.sin(E))


def solve_kepler(M, e) -> np.ndarray:
    """Eccentric anomaly ``E`` with ``E - e sin E = M``, to round-off, vectorised (``e`` a number, or an array
    broadcast with ``M``: one orbit per row of a population).

    ``M`` is reduced to ``[-pi, pi]`` and solved for ``|M|``.  Newton's method
    starts at ``E0 = min(|M| + e, pi)``, where ``E - e sin E - |M| >= 0``; as
    that function is increasing and convex on ``[0, pi]`` the iterates decrease
    monotonically onto the root, for every ``0 <= e < 1``.  Both
    ``E - e sin E = (1-e) E + e (E - sin E)`` and ``1 - e cos E =
    (1-e) + 2 e sin^2(E/2)`` are evaluated without cancellation, so ``E`` is
    accurate to a few ulps even for ``e -> 1`` near pericentre.  Each point
    stops once its residual is at round-off level (plus that last step).
    The returned ``E`` lies in ``[-pi, pi]`` with the sign of the reduced ``M``.
    """
    M = np.asarray(M, dtype=float)
    # Exact (no rounding) whenever |M| <= pi already: keeps M tiny near
    # pericentre, where E is most sensitive to it.
    reduced = M - 2.0 * np.pi * np.round(M / (2.0 * np.pi))
    if np.ndim(e) > 0:
        return _solve_kepler_many(reduced, np.asarray(e, dtype=float))
    m = np.abs(reduced).ravel()
    E = np.minimum(m + e, np.pi)
    eps = np.finfo(float).eps
    active = np.arange(m.size)
    for _ in range(200):
        Ea, ma = E[active], m[active]
        residual = (1.0 - e) * Ea + e * _e_minus_sin(Ea) - ma
        slope = (1.0 - e) + 2.0 * e * np.sin(0.5 * Ea) ** 2
        Ea = Ea - residual / slope
        E[active] = Ea
        active = active[np.abs(residual) > 4.0 * eps * (Ea + ma)]
        if active.size == 0:
            break
    else:  # pragma: no cover - monotone Newton always converges
        raise RuntimeError(f"Kepler solver did not converge for e={e!r}")
    return np.copysign(E.reshape(reduced.shape), reduced)


def _solve_kepler_many(reduced: np.ndarray, e: np.ndarray) -> np.ndarray:
    """:func:`solve_kepler` for an array of eccentricities broadcast with the reduced mean anomalies: the same
    monotone Newton from the same start on every point at once. No active set: for a population's millions of
    points the gathers cost more than the extra steps of the points already converged (which move them by an ulp
    at most); and the plain E - e sin E, whose cancellation near pericentre costs relative, not absolute,
    accuracy in E (a few 1e-16 rad), which is all the Fourier analysis of the samples needs."""
    reduced, e = np.broadcast_arrays(reduced, e)
    m = np.abs(reduced)
    # the start: below e = 0.3 the third-order expansion in e (error ~ e^4: two Newton steps reach round-off),
    # above it Danby's m + 0.85 e, from which Newton converges for every e < 1 (Danby 1988, ch. 6.6)
    sm, cm = np.sin(m), np.cos(m)
    series = m + e * sm * (1.0 + e * cm + 0.5 * e * e * (3.0 * cm * cm - 1.0))
    E = np.where(e < 0.3, series, np.minimum(m + 0.85 * e, np.pi))
    eps, tiny = np.finfo(float).eps, np.finfo(float).tiny
    for _ in range(200):
        residual = E - e * np.sin(E) - m
        E = E - residual / (1.0 - e * np.cos(E))
        # + tiny: at m = 0 Newton can settle on a subnormal E whose residual E (1 - e) never meets a relative test
        if np.all(np.abs(residual) <= 4.0 * eps * (E + m) + tiny):
            break
    else:  # pragma: no cover - monotone Newton always converges
        raise RuntimeError("Kepler solver did not converge")
    return np.copysign(E, reduced)


def solve_kepler_scalar(m: float, e: float) -> float:
    """Scalar twin of :func:`solve_kepler` (same monotone Newton), for ODE right-hand sides."""
    reduced = m - 2.0 * math.pi * round(m / (2.0 * math.pi))
    x = abs(reduced)
    ecc = min(x + e, math.pi)
    for _ in range(200):
        residual = ecc - e * math.sin(ecc) - x
        ecc -= residual / (1.0 - e * math.cos(ecc))
        if abs(residual) <= 4.0 * 2.220446049250313e-16 * (ecc + x) + 2.2250738585072014e-308:   # as above
            break
    return math.copysign(ecc, reduced)


def true_anomaly(mean_anomaly, e: float):
    """True anomaly ν (radians, same shape as M) of a Keplerian ellipse."""
    ecc = solve_kepler(mean_anomaly, e)
    beta = e / (1.0 + math.sqrt(1.0 - e * e))
    # signed and free of the (1+e)/(1-e) overflow of the half-angle tangent form
    return ecc + 2.0 * np.arctan2(beta * np.sin(ecc), 1.0 - beta * np.cos(ecc))


def orbit_basis(i, node, peri) -> np.ndarray:
    """Unit vectors (P, Q, W) of the orbit, as rows, in the frame of the elements: (3, 3), or (..., 3, 3) for
    arrays of angles (one orbit per element).

    P points to pericentre, Q is P advanced 90 degrees in the direction of
    motion, W = P x Q is the orbit normal (the orbital angular momentum).
    W = (sin i sin Ω, -sin i cos Ω, cos i); Petit et al. (2014) eq. 26 prints
    +cos Ω sin i for the second component, a sign slip.
    """
    ci, si = np.cos(i), np.sin(i)
    cn, sn = np.cos(node), np.sin(node)
    cw, sw = np.cos(peri), np.sin(peri)
    p = np.stack(np.broadcast_arrays(cn * cw - sn * sw * ci, sn * cw + cn * sw * ci, sw * si), axis=-1)
    q = np.stack(np.broadcast_arrays(-cn * sw - sn * cw * ci, -sn * sw + cn * cw * ci, cw * si), axis=-1)
    w = np.stack(np.broadcast_arrays(sn * si, -cn * si, ci), axis=-1)
    return np.stack([p, q, w], axis=-2)


def orbit_normal(i: float, node: float) -> np.ndarray:
    """Unit normal W of the orbit plane (direction of the orbital angular momentum)."""
    return np.array([math.sin(node) * math.sin(i), -math.cos(node) * math.sin(i), math.cos(i)])
