"""Rung 7: the full rigid body, spinning and torqued by the Sun, without rotation averaging.

Euler's equations for the angular velocity ω_b in the principal-axis (body)
frame, with the principal moments A <= B <= C normalised by C, and the attitude
as a unit quaternion q (scalar first) taking body vectors to the model's orbit
frame:

    A ω̇1 = (B - C) ω2 ω3 + 3 n² (a/r)³ (C - B) y z
    B ω̇2 = (C - A) ω3 ω1 + 3 n² (a/r)³ (A - C) z x
    C ω̇3 = (A - B) ω1 ω2 + 3 n² (a/r)³ (B - A) x y
    q̇    = ½ q ⊗ (0, ω_b)

where r̂_b = (x, y, z) is the Sun's direction in the body frame. The torque is
MacCullagh's gravity-gradient torque T = (3 GM / r⁵) r_b × I r_b (Goldstein,
Poole & Safko, Classical Mechanics, 3rd ed., ch. 5: Euler's equations, and
the torque of the Sun on an oblate body in "precession of the equinoxes";
Hughes, Spacecraft Attitude Dynamics, 1986, for the same torque as the
gravity-gradient torque of a satellite); the quaternion kinematics are those
of Markley & Crassidis, Fundamentals of Spacecraft Attitude Determination and
Control (2014), ch. 3. GM / a³ is written n² (the
model's mean motion is sqrt(GM_sun / a³), the planet's mass neglected exactly
as in :func:`ephem.forced.integration.integrate_spin_axis`), so the torque constant is
the same 3 n² that enters K = 3 n² H_d / ω.

Frame and phase are those of rung 5 (:func:`ephem.forced.integration.integrate_spin_axis`):
x = the mean equinox at the pole epoch, z = the orbit normal, and the Sun's
longitude from x is λ = θ + ν (θ = ``model.equinox_to_pericentre``, ν the true
anomaly of the Keplerian orbit of :mod:`ephem.orbit.kepler`). The torque is
quadratic in r̂, so the Sun-from-body and body-from-Sun conventions agree.

Units: time in days (integrated as τ = t - t0 from the pole epoch, so that the
rotation phase is not rounded to the ~1e-10 day resolution of a Julian date),
ω in rad/day, moments dimensionless.

Initial state at the pole epoch t0: rotation about the C axis at ω =
``model.spin_rate``, the C axis along the model's initial spin axis (the
catalogue's instantaneous pole), and the A axis at ``initial_angle`` from the
body's equinox of date, ê1 = (s × z)/|s × z| (the x axis when ψ = 0), towards
ê2 = s × ê1. So L, ω and the figure axis coincide at t0, as Kinoshita's J = 0.

What this adds to the averaged theory (Kinoshita 1977; Petit et al. 2014,
eq. 5): the P₂² (triaxial, (B - A)) part of the torque, which the averaged
theory drops because it averages to zero over a rotation, and the free and
forced wobble of the figure axis about L, which it removes by taking L, ω and
the figure axis as one. The rung-5 error these cause is studied by
:func:`studies.rigid_body.averaging_error_study` (docs/rigid_body_study.md; a study of the
checkout, not part of the library), modelled in closed form and bounded by :mod:`ephem.forced.rotation_scale`.

Validity: a rigid body (no elasticity, no dissipation, no core), a point-mass
Sun on a fixed Keplerian orbit, the quadrupole (second-degree) potential only;
no restriction on ω/n, obliquity or shape. The cost is per rotation
simulated: DOP853 at rtol 1e-12 takes ~17 steps (~200 right-hand-side calls,
~2.6 µs each plus ~6 µs of solve_ivp overhead) a rotation, ~1.8 ms CPU; a
Vesta orbit (5955 rotations) costs ~10 s, an Itokawa orbit (1101) ~2 s.
Directions of L and of the C axis converge to ~1e-14 rad over a year.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .precession_nutation import PrecessionNutation
from .rigid_numerics import (initial_attitude, model_moments, normalised_moments, rotation_matrices, solve_both_ways,
                             warm_kepler)
from .rotation_scale import SunGeometry, forced_angular_velocity, forcing_amplitude_rate, sun_azimuth_rate

# --------------------------------------------------------------------------- inputs


@dataclass(frozen=True)
class SunOrbit:
    """The Sun's Keplerian motion as seen in a model's orbit frame (angles in rad, times JD TDB)."""

    mean_motion: float            # n, rad/day
    eccentricity: float
    mean_anomaly_at_epoch: float  # M at orbit_epoch
    orbit_epoch: float
    equinox_to_pericentre: float  # θ

    @classmethod
    def from_model(cls, model: PrecessionNutation) -> SunOrbit:
        return cls(model.mean_motion, model.eccentricity, model.mean_anomaly_at_epoch, model.orbit_epoch,
                   model.equinox_to_pericentre)


# --------------------------------------------------------------------------- the equations


def make_rhs(moments, spin_rate: float, sun: SunOrbit | None, t0: float):
    """Right-hand side f(τ, y) of Euler's equations plus the quaternion kinematics, τ = t - t0 in days.

    State y = (ω_b / ω0, q): the angular velocity in units of ω0 = ``spin_rate``
    (so one tolerance suits every component) and the quaternion, body to orbit
    frame. ``sun`` None is the torque-free body. Plain floats and ``math``:
    2.6 µs a call, against ~160 µs for the same algebra on small numpy arrays.
    """
    A, B, C = (float(x) for x in moments)
    k1, k2, k3 = (B - C) / A, (C - A) / B, (A - B) / C
    w0 = float(spin_rate)
    h = 0.5 * w0
    if sun is None:
        def rhs(tau, y):
            w1, w2, w3, a, b, c, d = y.tolist()
            return [k1 * w0 * w2 * w3, k2 * w0 * w3 * w1, k3 * w0 * w1 * w2,
                    -h * (b * w1 + c * w2 + d * w3), h * (a * w1 + c * w3 - d * w2),
                    h * (a * w2 + d * w1 - b * w3), h * (a * w3 + b * w2 - c * w1)]
        return rhs

    n, e = sun.mean_motion, sun.eccentricity
    m_t0 = sun.mean_anomaly_at_epoch + n * (t0 - sun.orbit_epoch)
    cth, sth = math.cos(sun.equinox_to_pericentre), math.sin(sun.equinox_to_pericentre)
    sq = math.sqrt(1.0 - e * e)
    gc = 3.0 * n * n / w0   # torque / ω0 per unit (a/r)³ and unit moment difference

    kepler = warm_kepler(e, m_t0)

    def rhs(tau, y):
        w1, w2, w3, a, b, c, d = y.tolist()
        ce, se = kepler(m_t0 + n * tau)
        a_r = 1.0 / (1.0 - e * ce)
        cnu, snu = (ce - e) * a_r, sq * se * a_r
        cl, sl = cnu * cth - snu * sth, snu * cth + cnu * sth   # the Sun's (cos λ, sin λ)
        g = gc * a_r * a_r * a_r
        s = 2.0 / (a * a + b * b + c * c + d * d)   # rotation of a not-quite-unit q stays orthogonal
        # r̂_b = Rᵀ r̂ with r̂ = (cos λ, sin λ, 0)
        x = (1.0 - s * (c * c + d * d)) * cl + s * (b * c + a * d) * sl
        yb = s * (b * c - a * d) * cl + (1.0 - s * (b * b + d * d)) * sl
        z = s * (b * d + a * c) * cl + s * (c * d - a * b) * sl
        return [k1 * (w0 * w2 * w3 - g * yb * z), k2 * (w0 * w3 * w1 - g * z * x), k3 * (w0 * w1 * w2 - g * x * yb),
                -h * (b * w1 + c * w2 + d * w3), h * (a * w1 + c * w3 - d * w2),
                h * (a * w2 + d * w1 - b * w3), h * (a * w3 + b * w2 - c * w1)]
    return rhs


def integrate_states(moments, spin_rate: float, y0, t0: float, jd_tdb, sun: SunOrbit | None,
                     rtol: float = 1e-12, atol: float = 1e-14) -> tuple[np.ndarray, int]:
    """States (N, 7) = (ω_b/ω0, q) at ``jd_tdb`` from y0 at t0, forwards and backwards; and the call count.

    DOP853; the quaternion is renormalised on output.
    """
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    out, nfev = solve_both_ways(make_rhs(moments, spin_rate, sun, t0), y0, t - t0, rtol, atol)
    out[:, 3:] /= np.linalg.norm(out[:, 3:], axis=1, keepdims=True)
    return out, nfev


# --------------------------------------------------------------------------- the model-level integrator


@dataclass(frozen=True)
class RigidTrack:
    """A rung-7 run at epochs (JD TDB). Vectors are unit vectors in the ICRF unless named ``*_orbit``."""

    jd_tdb: np.ndarray
    moments: tuple[float, float, float]  # (A/C, B/C, 1)
    omega_body: np.ndarray       # (N, 3) angular velocity in the body frame, rad/day
    quaternion: np.ndarray       # (N, 4) unit, scalar first, body -> orbit frame
    angular_momentum: np.ndarray  # (N, 3) direction of L
    figure_axis: np.ndarray      # (N, 3) the C axis
    icrf_from_orbit: np.ndarray
    nfev: int                    # right-hand-side calls (the cost)

    @property
    def angular_momentum_orbit(self) -> np.ndarray:
        return self.angular_momentum @ self.icrf_from_orbit

    @property
    def figure_axis_orbit(self) -> np.ndarray:
        return self.figure_axis @ self.icrf_from_orbit

    def energy(self) -> np.ndarray:
        """Rotational kinetic energy per unit C, ½ Σ I_i ω_i² (rad²/day²)."""
        return 0.5 * (self.omega_body**2 @ np.asarray(self.moments))

    def momentum_norm(self) -> np.ndarray:
        """|L| per unit C (rad/day)."""
        return np.linalg.norm(self.omega_body * np.asarray(self.moments), axis=1)


def integrate_rigid_body(model: PrecessionNutation, jd_tdb, moments=None, initial_angle: float = 0.0,
                         initial_omega_body=None, solar_torque: bool = True, rtol: float = 1e-12,
                         atol: float = 1e-14, start: str = "forced") -> RigidTrack:
    """Rung 7 at ``jd_tdb`` (JD TDB, either side of the pole epoch): see the module docstring.

    ``moments`` (A, B, C) in any common unit, default the catalogue body's;
    ``initial_angle`` (rad) places the A axis; ``solar_torque`` False is the
    torque-free body (GM = 0). The C axis starts on the model's pole. ``start``
    sets the angular velocity there: "forced" (default) the forced solution of
    :func:`ephem.forced.rotation_scale.forced_angular_velocity`, so the body starts
    without free wobble (to relative order ν̇/ω); "aligned" ω = (0, 0, ω), which
    puts L on the C axis and excites a free wobble of the size of the forced
    offset. ``initial_omega_body`` (rad/day, body frame) overrides both.
    """
    if start not in ("forced", "aligned"):
        raise ValueError(f"start must be 'forced' or 'aligned', got {start!r}")
    mom = model_moments(model) if moments is None else normalised_moments(moments)
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    w0 = model.spin_rate
    s0 = model.catalogue_pole_orbit
    q0 = initial_attitude(s0, initial_angle)
    if initial_omega_body is not None:
        w_init = np.asarray(initial_omega_body, dtype=float)
    elif start == "forced" and solar_torque:
        sun = SunGeometry.at(model, [model.pole_epoch])
        sun_body = rotation_matrices(q0[None])[0].T @ sun.direction[0]
        w_init = forced_angular_velocity(mom, w0, sun_body, float(sun.torque_strength[0]),
                                         sun_azimuth_rate(model, s0, model.pole_epoch),
                                         forcing_amplitude_rate(model, s0, model.pole_epoch))
    else:
        w_init = np.array([0.0, 0.0, w0])
    y0 = np.concatenate([w_init / w0, q0])
    sun = SunOrbit.from_model(model) if solar_torque else None
    states, nfev = integrate_states(mom, w0, y0, model.pole_epoch, t, sun, rtol, atol)
    omega = states[:, :3] * w0
    rot = rotation_matrices(states[:, 3:])
    ang = np.einsum("nij,nj->ni", rot, omega * np.asarray(mom))
    ang /= np.linalg.norm(ang, axis=1, keepdims=True)
    fig = rot[:, :, 2]
    r = model.icrf_from_orbit
    return RigidTrack(t, mom, omega, states[:, 3:], ang @ r.T, fig @ r.T, r, nfev)
