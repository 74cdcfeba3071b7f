"""Numerical reference: the rotation-averaged solar torque integrated along the Keplerian orbit.

    ds/dt = (3 GM H_d / (ω r³)) (s·r̂)(r̂ × s) = K (a/r)³ (s·r̂)(r̂ × s)

with s the spin (angular-momentum) axis and r̂ the direction of the Sun
(the sign of r̂ drops out). It carries no expansion in e, no constant
obliquity or node in the coefficients and no first-order truncation, so it is
the arbiter of the analytic theory's signs and phases. Integrated with scipy's
DOP853 in the frame of the orbit and the mean equinox at the pole epoch.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from .kepler import solve_kepler_scalar
from .model import PrecessionNutation


def integrate_spin_axis(model: PrecessionNutation, jd_tdb, rtol: float = 1e-12,
                        atol: float = 1e-14) -> np.ndarray:
    """Spin-axis unit vectors (N, 3) in the ICRF at ``jd_tdb``, by numerical integration.

    Starts from the catalogue (instantaneous) pole at the model's pole epoch and
    integrates forwards and backwards to cover the requested epochs.
    """
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    e = model.eccentricity
    K = model.scaling_factor
    n = model.mean_motion
    theta = model.equinox_to_pericentre
    beta = e / (1.0 + math.sqrt(1.0 - e * e))
    t0 = model.pole_epoch

    def rhs(tt, s):
        m = model.mean_anomaly_at_epoch + n * (tt - model.orbit_epoch)
        ecc = solve_kepler_scalar(m, e)
        nu = ecc + 2.0 * math.atan2(beta * math.sin(ecc), 1.0 - beta * math.cos(ecc))
        a_over_r = 1.0 / (1.0 - e * math.cos(ecc))
        lam = theta + nu
        rx, ry = math.cos(lam), math.sin(lam)
        sr = s[0] * rx + s[1] * ry
        f = K * a_over_r**3 * sr
        # r̂ × s with r̂ = (rx, ry, 0)
        return [f * (ry * s[2]), f * (-rx * s[2]), f * (rx * s[1] - ry * s[0])]

    dpsi0, deps0 = model.nutation_at_pole_epoch
    s0 = model.pole_orbit_frame(dpsi0, model.obliquity + deps0)
    out = np.empty((t.size, 3))
    for mask in (t >= t0, t < t0):
        if not mask.any():
            continue
        tt = t[mask]
        end = tt.max() if tt[0] >= t0 else tt.min()
        if end == t0:  # only the start epoch itself
            out[mask] = s0
            continue
        order = np.argsort(tt) if end > t0 else np.argsort(-tt)
        sol = solve_ivp(rhs, (t0, end), s0, method="DOP853", t_eval=tt[order], rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(f"integration failed: {sol.message}")
        res = np.empty((tt.size, 3))
        res[order] = sol.y.T
        out[mask] = res
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    return out @ model.icrf_from_orbit.T


def angular_separation(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Angle between unit vectors along the last axis (radians), accurate at small angles."""
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), np.sum(u * v, axis=-1))
