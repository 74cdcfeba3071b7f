"""Generic numerics of a rigid body's integration: normalised moments, attitude quaternions, ODE helpers.

The principal moments normalised by C (a catalogue body's, or the worst case its H_d allows), attitude
quaternions and rotation matrices, a warm-started Kepler solver for a right-hand side, and DOP853 both ways
from an epoch.

Shared by the Sun-torqued rigid body (:mod:`ephem.forced.rigid_body`), the Moon's integrated rotation
(:mod:`ephem.moon.rigid_integration`) and the error estimates (:mod:`ephem.forced.physics_errors`), and kept
free of the forced model so that none of them reaches it through these helpers. ``model`` below is a
:class:`ephem.forced.precession_nutation.PrecessionNutation`, read by its attributes only.

Quaternions are unit, scalar first, body to the integration's frame (Markley & Crassidis, Fundamentals of
Spacecraft Attitude Determination and Control, 2014, ch. 3).
"""
from __future__ import annotations

import math

import numpy as np

from ..base.errors import InvalidInputError, UnknownBodyError
from ..bodies.catalogue import get_body
from ..orbit.kepler import solve_kepler_scalar

# --------------------------------------------------------------------------- principal moments


def normalised_moments(moments=None, hd: float | None = None) -> tuple[float, float, float]:
    """Principal moments (A/C, B/C, 1) from (A, B, C) in any common unit, or A = B = 1 - H_d from H_d alone.

    With only H_d the body is taken as axisymmetric, H_d = (C - A)/C.
    """
    if moments is not None:
        a, b, c = (float(x) for x in moments)
        if not 0.0 < a <= b <= c or c > a + b:
            raise ValueError(f"principal moments must satisfy 0 < A <= B <= C <= A + B, got {moments}")
        return a / c, b / c, 1.0
    if hd is None or not 0.0 < hd <= 0.5:
        raise ValueError(f"need the moments or a dynamical ellipticity in (0, 0.5], got {hd!r}")
    return 1.0 - hd, 1.0 - hd, 1.0


def model_moments(model) -> tuple[float, float, float]:
    """The normalised moments of the catalogue body a model was built from (axisymmetric if it has only H_d).

    A model of a body outside the shipped catalogues has to be given its moments
    explicitly (or :func:`worst_case_moments`).
    """
    try:
        body = get_body(model.body, model.dataset)
    except (UnknownBodyError, InvalidInputError):
        raise ValueError(f"{model.body!r} is not in the {model.dataset!r} catalogue: pass its moments "
                         "(or worst_case_moments(model.hd))") from None
    return normalised_moments(body.moments, body.hd)


def worst_case_moments(hd: float) -> tuple[float, float, float]:
    """(1 - 2 H_d, 1, 1): of all rigid bodies with this H_d, the one with the largest triaxiality, (B - A)/C =
    2 H_d, which drives the semi-diurnal terms of :mod:`ephem.forced.rotation_scale`, for an error bound when the shape is
    unknown (tests/forced/test_rigid.py checks that it bounds the catalogue shapes)."""
    if not 0.0 < hd <= 0.5:
        raise ValueError(f"H_d must lie in (0, 0.5], got {hd!r}")
    # H_d = 0.5 is the needle A = 0, a limit no body reaches: keep A positive for the moment checks
    return max(1.0 - 2.0 * hd, 1e-9), 1.0, 1.0


def body_moments(body, model) -> tuple[float, float, float]:
    """A body's (A/C, B/C, 1): its own moments, or for a body known only by H_d the worst case its H_d allows
    (:func:`worst_case_moments`), which the error estimates take."""
    return normalised_moments(body.moments) if body.moments is not None else worst_case_moments(model.hd)


# --------------------------------------------------------------------------- attitude


def quaternion_from_matrix(m: np.ndarray) -> np.ndarray:
    """Unit quaternion (scalar first) of a rotation matrix (Shepperd's method: the largest pivot)."""
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    pivots = [tr, m[0, 0], m[1, 1], m[2, 2]]
    k = int(np.argmax(pivots))
    if k == 0:
        s = 2.0 * math.sqrt(1.0 + tr)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    else:
        i, j, l = (k - 1, k % 3, (k + 1) % 3)
        s = 2.0 * math.sqrt(1.0 + m[i, i] - m[j, j] - m[l, l])
        q = [0.0] * 4
        q[0] = (m[l, j] - m[j, l]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + l] = (m[l, i] + m[i, l]) / s
    q = np.array(q)
    return q / np.linalg.norm(q)


def rotation_matrices(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (N, 3, 3), body to orbit frame, of quaternions (N, 4) (normalised here)."""
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    a, b, c, d = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack([
        np.stack([1 - 2 * (c * c + d * d), 2 * (b * c - a * d), 2 * (b * d + a * c)], axis=-1),
        np.stack([2 * (b * c + a * d), 1 - 2 * (b * b + d * d), 2 * (c * d - a * b)], axis=-1),
        np.stack([2 * (b * d - a * c), 2 * (c * d + a * b), 1 - 2 * (b * b + c * c)], axis=-1),
    ], axis=-2)


def initial_attitude(spin_axis: np.ndarray, initial_angle: float = 0.0) -> np.ndarray:
    """Quaternion putting the C axis on ``spin_axis`` (orbit frame) and the A axis ``initial_angle`` from its equinox.

    The equinox ê1 = (s × z)/|s × z| is the x axis when ψ = 0; if the spin axis
    is along the orbit normal the x axis is used instead.
    """
    s = np.asarray(spin_axis, dtype=float)
    s = s / np.linalg.norm(s)
    e1 = np.cross(s, [0.0, 0.0, 1.0])
    if np.linalg.norm(e1) < 1e-12:
        e1 = np.array([1.0, 0.0, 0.0]) - s[0] * s
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(s, e1)
    a1 = math.cos(initial_angle) * e1 + math.sin(initial_angle) * e2
    a2 = np.cross(s, a1)
    return quaternion_from_matrix(np.column_stack([a1, a2, s]))


# --------------------------------------------------------------------------- solvers


def warm_kepler(e: float, m_start: float):
    """Solver m -> (cos E, sin E) of Kepler's equation, warm-started from its previous call.

    An ODE right-hand side asks for nearby mean anomalies in turn, so Newton
    from the last root (with a first-order predictor) needs one or two steps
    where :func:`ephem.orbit.kepler.solve_kepler_scalar` needs four or five: it
    halves the cost of the Sun's position. M is not reduced (E stays
    continuous); its rounding, |M| ulp, is 1e-13 rad after a hundred orbits.
    Stops as that solver does, at a residual of a few ulp of |E| + |M|.
    """
    last = [m_start, solve_kepler_scalar(m_start, e)]   # unreduced M, E
    last[1] += m_start - (last[1] - e * math.sin(last[1]))  # move E to M's branch (solver reduces M)

    def solve(m: float) -> tuple[float, float]:
        m_prev, ecc = last
        ecc += (m - m_prev) / (1.0 - e * math.cos(ecc))
        for _ in range(50):
            se, ce = math.sin(ecc), math.cos(ecc)
            residual = ecc - e * se - m
            if abs(residual) <= 4.0 * 2.220446049250313e-16 * (abs(ecc) + abs(m)):
                last[0], last[1] = m, ecc
                return ce, se
            ecc -= residual / (1.0 - e * ce)
        raise RuntimeError(f"Kepler's equation did not converge at M={m!r}, e={e!r}")  # pragma: no cover

    return solve


def solve_both_ways(rhs, y0, tau, rtol: float, atol: float) -> tuple[np.ndarray, int]:
    """States (N, len(y0)) at ``tau`` (either side of 0) from y0 at τ = 0, DOP853 forwards and backwards; and the
    rhs call count."""
    from scipy.integrate import solve_ivp  # on first use: 0.2 s, and the ladder's estimates need none

    tau = np.atleast_1d(np.asarray(tau, dtype=float))
    out = np.empty((tau.size, len(y0)))
    nfev = 0
    for mask in (tau >= 0.0, tau < 0.0):
        if not mask.any():
            continue
        tt = tau[mask]
        end = tt.max() if tt[0] >= 0.0 else tt.min()
        if end == 0.0:
            out[mask] = y0
            continue
        order = np.argsort(tt) if end > 0.0 else np.argsort(-tt)
        sol = solve_ivp(rhs, (0.0, end), y0, method="DOP853", t_eval=tt[order], rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(f"rigid-body integration failed: {sol.message}")
        nfev += sol.nfev
        res = np.empty((tt.size, len(y0)))
        res[order] = sol.y.T
        out[mask] = res
    return out, nfev
