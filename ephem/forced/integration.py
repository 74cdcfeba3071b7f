"""Numerical reference: the rotation-averaged solar torque integrated along the Keplerian orbit.

    ds/dt = (3 GM H_d / (ω r³)) (s·r̂)(r̂ × s) = K (a/r)³ (s·r̂)(r̂ × s)

with s the spin (angular-momentum) axis and r̂ the direction of the Sun
(the sign of r̂ drops out). It carries no expansion in e, no constant
obliquity or node in the coefficients and no first-order truncation, so it is
the arbiter of the analytic theory's signs and phases. With the model's geodesic rate Ω_gp
(:mod:`ephem.orbit.relativity`) the axis also turns about the orbit normal at the instantaneous de Sitter
rate (3/2)(GM/c²) h/r³ = Ω_gp (a/r)³ (1 − e²)^(3/2), whose orbit average the analytic rungs apply
(:mod:`ephem.sun.geodesic` bounds what that leaves). Integrated with scipy's
DOP853 in the frame of the orbit and the mean equinox at the pole epoch. ``model`` is a
:class:`ephem.forced.precession_nutation.PrecessionNutation`, read by its attributes: the error estimates
(:mod:`ephem.forced.physics_errors`) measure with this integration without the import chain of the model.
"""
from __future__ import annotations

import math

import numpy as np

from ..base.budget import checkpoint
from ..base.constants import AU_M, DAY_S, GM_SUN
from ..orbit.kepler import solve_kepler_scalar

#: Heliocentric gravitational constant in AU^3/day^2.
GM_SUN_AU3_PER_DAY2 = GM_SUN * DAY_S**2 / AU_M**3


def integrate_spin_axis(model, jd_tdb, rtol: float = 1e-12,
                        atol: float = 1e-14, sun=None) -> np.ndarray:
    """Spin-axis unit vectors (N, 3) in the ICRF at ``jd_tdb``, by numerical integration.

    Starts from the catalogue (instantaneous) pole at the model's pole epoch and
    integrates forwards and backwards to cover the requested epochs.

    ``sun`` None moves the Sun on the model's Keplerian orbit (rung 5 of the ladder).
    Otherwise it is a callable t -> (x, y, z), the Sun's position seen from the body
    in AU, ICRF axes (e.g. :meth:`ephem.orbit.de421.SunPath.position_scalar`): the real,
    perturbed orbit of rung 6, with the torque coefficient 3 GM H_d / (ω r^3).
    """
    from scipy.integrate import solve_ivp  # on first use: 0.2 s, not for angular_separation's importers

    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    e = model.eccentricity
    K = model.scaling_factor
    n = model.mean_motion
    theta = model.equinox_to_pericentre
    beta = e / (1.0 + math.sqrt(1.0 - e * e))
    t0 = model.pole_epoch
    # ICRF -> orbit frame: the transpose of the model's orbit -> ICRF matrix
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = model.icrf_from_orbit.T.tolist()
    coef = 3.0 * GM_SUN_AU3_PER_DAY2 * model.hd / model.spin_rate
    # the geodesic precession about the orbit normal (z here), instantaneous: Ω_gp (a/r)³ (1 − e²)^(3/2)
    geodesic = model.geodesic_rate * (1.0 - e * e) ** 1.5
    a_au = (GM_SUN_AU3_PER_DAY2 / (n * n)) ** (1.0 / 3.0)

    def rhs_real(tt, s):
        checkpoint()    # the service's backstop: ~0.1 us against ~10 us a call
        x, y, z = sun(tt)
        rx, ry, rz = r00 * x + r01 * y + r02 * z, r10 * x + r11 * y + r12 * z, r20 * x + r21 * y + r22 * z
        r2 = rx * rx + ry * ry + rz * rz
        sr = s[0] * rx + s[1] * ry + s[2] * rz
        r = math.sqrt(r2)
        f = coef * sr / (r2 * r2 * r)   # (3 GM H_d / ω r^3) (s·r̂) / r
        g = geodesic * (a_au / r) ** 3  # about the Keplerian orbit's normal: the real one's tilt is ~1e-4 rad
        return [f * (ry * s[2] - rz * s[1]) - g * s[1], f * (rz * s[0] - rx * s[2]) + g * s[0],
                f * (rx * s[1] - ry * s[0])]

    def rhs_kepler(tt, s):
        checkpoint()
        m = model.mean_anomaly_at_epoch + n * (tt - model.orbit_epoch)
        ecc = solve_kepler_scalar(m, e)
        nu = ecc + 2.0 * math.atan2(beta * math.sin(ecc), 1.0 - beta * math.cos(ecc))
        a_over_r = 1.0 / (1.0 - e * math.cos(ecc))
        lam = theta + nu
        rx, ry = math.cos(lam), math.sin(lam)
        sr = s[0] * rx + s[1] * ry
        cube = a_over_r**3
        f = K * cube * sr
        g = geodesic * cube             # ẑ × s = (−s_y, s_x, 0): the orbital sense
        # r̂ × s with r̂ = (rx, ry, 0)
        return [f * (ry * s[2]) - g * s[1], f * (-rx * s[2]) + g * s[0], f * (rx * s[1] - ry * s[0])]

    s0 = model.catalogue_pole_orbit
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
        sol = solve_ivp(rhs_kepler if sun is None else rhs_real, (t0, end), s0, method="DOP853", t_eval=tt[order], rtol=rtol, atol=atol)
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
