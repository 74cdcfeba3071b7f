"""The full rigid synchronous satellite, integrated: the independent check of the Cassini-state theory.

Euler's equations for the angular velocity ω_b in the principal-axis (body) frame and the attitude as a unit
quaternion q (scalar first, body to the Laplace frame), under the gravity-gradient torques of the primary and
of the Sun (MacCullagh; the equations, units and quaternion kinematics of :mod:`ephem.forced.rigid_body`, with the
helpers of :mod:`ephem.forced.rigid_numerics`):

    A ω̇1 = (B − C) ω2 ω3 + Σ_j 3 (GM_j/r_j³) (C − B) y_j z_j       (and cyclically)
    q̇    = ½ q ⊗ (0, ω_b)

with r̂_j = (x_j, y_j, z_j) the body-frame direction of perturber j. No averaging of any kind: the
rotation is resolved, the orbit is followed point by point, and every part of the torque (C − A, B − A, the
Sun's) is kept. The torque is quadratic in r̂, so the primary-from-satellite and satellite-from-primary
directions give the same torque.

Frame: the Laplace frame of :class:`ephem.forced.cassini.SynchronousOrbit` (z the Laplace pole K, x its origin of
longitudes). Time: τ = t − t0 days from the start; the state is (ω_b/n, q), n the orbit's (sidereal) mean
motion, so that one tolerance fits every component.

**The primary's orbit.**

* ``real_moon=False``: the precessing Kepler ellipse of the ``SynchronousOrbit``: Ω(t) = Ω0 + Ω̇ (t − t_ep),
  ω(t) likewise, and the mean anomaly at the rate n − Ω̇ − ω̇, so that the mean longitude Ω + ω + M moves at
  the sidereal n (the contract's "n: sidereal"); torque factor ``primary_gm_over_a3`` × (a/r)³. The Sun, if
  ``sun_tidal_rate_sq`` > 0, on a circle in the Laplace plane at the mean longitude
  ``sun_longitude_at_epoch`` + ``sun_mean_motion`` (t − t_ep), with the torque factor g_s (1 − e_s²)^(−3/2),
  its orbit mean (the eccentric Sun's monthly-period variation is left out: its torque is 0.6 % of the
  Earth's on the Moon, and its e_s-terms ±5 % of that).
* ``real_moon=True`` (the Moon only): the geocentric Moon of :func:`ephem.orbit.lunar.moon_position` (Meeus 1998
  ch. 47: ELP-2000/82 truncated, ~10″ in longitude, 4″ in latitude, Meeus's planetary terms A1-A3, up to 14″,
  left out) and the Sun of :func:`ephem.orbit.lunar.sun_position` (the Earth-Moon barycentre's Kepler ellipse),
  both on the mean ecliptic and equinox of date, rotated to the ecliptic and equinox of J2000 (the Laplace frame
  of :func:`ephem.moon.model.synchronous_orbit`: equinox of J2000, inertial node rate) by the IAU 2006
  ecliptic matrices, R = ecm06(J2000) · ecm06(t)ᵀ (erfa; the frame bias cancels in the product). Left out:
  the difference between Meeus's ecliptic and equinox of date and IAU 2006's (mas), and the ecliptic's own
  motion (47″ per century) as a motion of the Laplace plane (the orbit regresses on the ecliptic of date, the
  frame is the fixed J2000 one: 9″ over one node period from J2000, against the test's 0.1°). The Sun is
  seen from the Moon (geocentric Sun minus geocentric Moon). GM: the Earth's and the Sun's of
  :mod:`ephem.base.constants` (IAU 2015 nominal; the Earth's, not the Earth + Moon's: the torque on the Moon).
  These are tabulated once on a grid of :data:`TABLE_STEP_DAYS` as the vectors v_j = sqrt(3 GM_j / (n r_j³)) r̂_j
  (so that v_j v_jᵀ is the torque's matrix) and interpolated by 4-point (cubic) Lagrange in plain floats:
  interpolation error ≤ 3/128 (ν h)⁴ of a term of frequency ν, 3e-7 relative at the monthly ν; measured
  (:func:`table_interpolation_error`) 1.3e-6 of |v| and 0.16″ in direction at worst, a torque error far below
  any pole effect tested (the torque's forced librations are ~100″: 1e-6 of them is 1e-4″).

**The start** (at ``start_jd``), ``start="mean"``: the C axis on the analytic Cassini pole
(:func:`ephem.forced.cassini.cassini_pole`) or ``pole0``; the A axis at the primary's mean longitude (mean, not true)
as τ below measures it, turned by ``longitude_offset`` about C; the angular velocity that keeps the A axis
there while the node turns: ω = Ḟ c + Ω̇ K, Ḟ = n − Ω̇ the mean argument of latitude's rate (the body turns
once per draconic period relative to the node, which turns at Ω̇ about K: ω·c = n + |Ω̇|(1 − cos I) ≈ n;
ω = n c + Ω̇ K instead spins the body |Ω̇| slow and starts a free libration in longitude of |Ω̇|/ω_lon, 8.8° for
the Moon); plus ``omega_offset`` (body frame). ``start="forced"`` (default) adds the forced terms to first
order in e (:func:`forced_start`): the fortnightly nutation and the e-driven polar motion (the figure axis
displaced from the mean pole, ω⊥ the forced one) and the forced libration in longitude (angle and rate). The
mean start leaves them to become free librations: for the Moon on its real orbit a free wobble of ~150″ and a
free libration in longitude of ~450″ (the forced start: ~35″ and ~150″, from the terms of order e², the Sun
and the approximations it makes); on a circular orbit a free wobble of ~40″ (forced start: 0.1″).

**Outputs**: the figure (C) axis, the angular-momentum direction, the long (A) axis (unit vectors, Laplace
frame) and the physical libration in longitude τ: the A axis's longitude measured along the Laplace plane to
the equator's ascending node and then along the equator, minus the primary's mean longitude + 180° (the
usual lunar definition: zero in the locked mean state, the optical libration excluded).

Cost: the rotation is a month long, so the cost is per orbit, not per rotation of a fast rotator. DOP853 calls
the right-hand side 2.3 times a day at rtol 1e-7 on a circular orbit (3.4 with e and the Sun, 3.7 on the real
Moon) and 4.3-6.9 times a day at rtol 1e-9; a call costs 3.5-6 µs, but solve_ivp's own work, ~110 µs a step
(12 calls), dominates. Measured on two shared cores: 56 years (3 node periods) 0.6-1.1 s on a circular orbit,
1.2-2.9 s with e and the Sun, 2.2-2.7 s on the real Moon plus 0.4-0.8 s to build its table
(:attr:`SynchronousTrack.calls_per_day`, :attr:`SynchronousTrack.wall_seconds`). Global error at rtol 1e-7,
3 node periods: 0.02″ in the pole, 0.08″ in τ (1e-6: 0.14″ and 0.6″), against a run at 1e-10.

Validity: rigid body, point-mass primary and Sun, quadrupole torque only; no tides, no core, no dissipation
(the real Moon's dissipation shifts its pole by ~0.26″, Williams et al. 2001, not modelled).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..forced.cassini import SynchronousOrbit, cassini_pole, cassini_state
from ..base.constants import DAY_S, GM_EARTH, GM_SUN, J2000_JD
from ..forced.rigid_numerics import (normalised_moments, quaternion_from_matrix, rotation_matrices, solve_both_ways,
                                     warm_kepler)
from ..orbit.lunar import centuries, delaunay_arguments, delaunay_rates, lunisolar_data, moon_position, sun_position

#: Grid of the tabulated real Moon and Sun, days (cubic Lagrange interpolation: see the module docstring).
TABLE_STEP_DAYS = 0.25
#: Extra grid points beyond the span on each side (the 4-point stencil needs one before and two after).
TABLE_MARGIN = 3
K_AXIS = np.array([0.0, 0.0, 1.0])


# --------------------------------------------------------------------------- the mean orbit's geometry


def _angles(orbit: SynchronousOrbit, jd_tdb):
    """Ω, ω, M (radians) of the mean orbit at JD TDB: the node and pericentre linear in time, M at n − Ω̇ − ω̇."""
    dt = np.asarray(jd_tdb, dtype=float) - orbit.epoch
    node = orbit.node_at_epoch + orbit.node_rate * dt
    peri = orbit.pericentre_at_epoch + orbit.pericentre_rate * dt
    mean = orbit.mean_anomaly_at_epoch + (orbit.mean_motion - orbit.node_rate - orbit.pericentre_rate) * dt
    return node, peri, mean


def mean_longitude(orbit: SynchronousOrbit, jd_tdb) -> np.ndarray:
    """The satellite's mean longitude Ω + ω + M (radians, unreduced; rate n, sidereal) at JD TDB."""
    node, peri, mean = _angles(orbit, jd_tdb)
    return node + peri + mean


def orbit_normal(orbit: SynchronousOrbit, jd_tdb) -> np.ndarray:
    """The mean orbit's unit normal (N, 3) in the Laplace frame: longitude Ω − 90°, colatitude i."""
    node = np.atleast_1d(_angles(orbit, jd_tdb)[0])
    si, ci = math.sin(orbit.inclination), math.cos(orbit.inclination)
    return np.stack([si * np.sin(node), -si * np.cos(node), np.full(node.shape, ci)], axis=-1)


def mean_direction(orbit: SynchronousOrbit, jd_tdb) -> np.ndarray:
    """Unit vectors (N, 3), Laplace frame, from the primary to the satellite's mean position: the inclined
    circular orbit at the mean argument of latitude ω + M (the primary is seen from the satellite along −this)."""
    node, peri, mean = (np.atleast_1d(a) for a in _angles(orbit, jd_tdb))
    u = peri + mean
    ci, si = math.cos(orbit.inclination), math.sin(orbit.inclination)
    cn, sn, cu, su = np.cos(node), np.sin(node), np.cos(u), np.sin(u)
    return np.stack([cn * cu - sn * su * ci, sn * cu + cn * su * ci, su * si], axis=-1)


# --------------------------------------------------------------------------- the real Moon and Sun, tabulated


@dataclass(frozen=True, eq=False)
class PerturberTable:
    """The real geocentric Moon's and the Sun's torque vectors on a grid (ecliptic and equinox of J2000).

    ``moon`` and ``sun`` (N, 3): v = sqrt(3 GM / (ω0 r³)) r̂ of the Earth-Moon line and of the Moon-Sun line, in
    units where v vᵀ is the torque's matrix over ω0 (rad/day) — see the module docstring."""

    start: float          # JD TDB of the first grid point
    step: float           # days
    spin_rate: float      # ω0, rad/day, the unit of v²
    moon: np.ndarray
    sun: np.ndarray

    @property
    def jd_tdb(self) -> np.ndarray:
        return self.start + self.step * np.arange(self.moon.shape[0])

    def interpolate(self, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """(moon, sun) vectors at JD TDB by the same 4-point Lagrange rule as the right-hand side (vectorised)."""
        x = (np.atleast_1d(np.asarray(jd_tdb, dtype=float)) - self.start) / self.step
        j = np.floor(x).astype(int)
        f = (x - j)[:, None]
        w = (-f * (f - 1) * (f - 2) / 6, (f + 1) * (f - 1) * (f - 2) / 2, -(f + 1) * f * (f - 2) / 2,
             (f + 1) * f * (f - 1) / 6)
        return tuple(sum(w[k] * arr[j - 1 + k] for k in range(4)) for arr in (self.moon, self.sun))


def ecliptic_j2000_from_date(jd_tdb) -> np.ndarray:
    """Rotation matrices (N, 3, 3) from the mean ecliptic and equinox of date to those of J2000 (IAU 2006,
    erfa.ecm06(J2000) · ecm06(t)ᵀ; the ICRS frame bias cancels)."""
    import erfa

    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    of_date = erfa.ecm06(t, np.zeros_like(t))                   # ICRS -> ecliptic of date
    j2000 = erfa.ecm06(J2000_JD, 0.0)
    return np.einsum("ij,nkj->nik", j2000, of_date)


def real_moon_vectors(jd_tdb, spin_rate: float) -> tuple[np.ndarray, np.ndarray]:
    """The torque vectors (moon, sun), each (N, 3), evaluated directly (no table) at JD TDB."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    args = delaunay_arguments(t)
    arg = tuple(args[:, k] for k in range(5))
    # the E factor's and the Sun's eccentricity's drift: T at the middle of the span (their rates are 2.5e-3 and
    # 4e-5 per century: over a century 1e-4 relative of the solar terms of the Moon, far below Meeus's truncation)
    tc = float(np.mean(centuries(t)))
    lam, beta, r = moon_position(arg, tc)
    lam_s, _, r_s = sun_position(arg, tc)
    cb = np.cos(beta)
    moon = r[:, None] * np.stack([cb * np.cos(lam), cb * np.sin(lam), np.sin(beta)], axis=-1)   # km, of date
    sun = r_s[:, None] * np.stack([np.cos(lam_s), np.sin(lam_s), np.zeros_like(lam_s)], axis=-1) - moon
    rot = ecliptic_j2000_from_date(t)
    out = []
    for vec, gm in ((moon, GM_EARTH), (sun, GM_SUN)):
        vec = np.einsum("nij,nj->ni", rot, vec)
        dist = np.linalg.norm(vec, axis=1, keepdims=True)
        gm_km3_day2 = gm * 1e-9 * DAY_S**2
        out.append(np.sqrt(3.0 * gm_km3_day2 / (spin_rate * dist**3)) * vec / dist)
    return out[0], out[1]


def perturber_table(start_jd: float, stop_jd: float, spin_rate: float,
                    step: float = TABLE_STEP_DAYS) -> PerturberTable:
    """The real Moon's and Sun's torque vectors tabulated over [start, stop] (with :data:`TABLE_MARGIN`)."""
    lo, hi = min(start_jd, stop_jd), max(start_jd, stop_jd)
    count = int(math.ceil((hi - lo) / step)) + 1 + 2 * TABLE_MARGIN
    first = lo - TABLE_MARGIN * step
    moon, sun = real_moon_vectors(first + step * np.arange(count), spin_rate)
    return PerturberTable(first, step, spin_rate, moon, sun)


def table_interpolation_error(table: PerturberTable) -> tuple[float, float]:
    """The table's largest interpolation error at the midpoints of its steps: (relative to |v| of the Moon's
    vector, its direction in radians), against the direct evaluation."""
    mid = table.jd_tdb[TABLE_MARGIN:-TABLE_MARGIN] + 0.5 * table.step
    exact, _ = real_moon_vectors(mid, table.spin_rate)
    approx, _ = table.interpolate(mid)
    norm = np.linalg.norm(exact, axis=1)
    rel = np.linalg.norm(approx - exact, axis=1) / norm
    ang = np.linalg.norm(np.cross(approx / np.linalg.norm(approx, axis=1)[:, None], exact / norm[:, None]), axis=1)
    return float(rel.max()), float(ang.max())


# --------------------------------------------------------------------------- the equations


def make_rhs(moments, orbit: SynchronousOrbit, t0: float, table: PerturberTable | None = None, sun: bool = True):
    """Right-hand side f(τ, y), τ = t − t0 days, y = (ω_b/n, q): Euler's equations under the primary and the
    Sun plus the quaternion kinematics, in plain floats (the speed argument of :func:`ephem.forced.rigid_body.make_rhs`).

    ``table`` None: the primary on the orbit's precessing Kepler ellipse and the Sun on its circle (``sun`` False
    or ``sun_tidal_rate_sq`` 0: no Sun); a :class:`PerturberTable`: the tabulated real Moon and Sun."""
    A, B, C = (float(x) for x in moments)
    k1, k2, k3 = (B - C) / A, (C - A) / B, (A - B) / C
    w0 = float(orbit.mean_motion)
    h = 0.5 * w0

    def euler(w1, w2, w3, a, b, c, d, sxy, syz, szx):
        return [k1 * (w0 * w2 * w3 - syz), k2 * (w0 * w3 * w1 - szx), k3 * (w0 * w1 * w2 - sxy),
                -h * (b * w1 + c * w2 + d * w3), h * (a * w1 + c * w3 - d * w2),
                h * (a * w2 + d * w1 - b * w3), h * (a * w3 + b * w2 - c * w1)]

    if table is not None:
        mx, my, mz = (table.moon[:, k].tolist() for k in range(3))
        sx, sy, sz = (table.sun[:, k].tolist() for k in range(3))
        if not sun:
            sx = sy = sz = [0.0] * len(mx)
        tau_first = table.start - t0
        inv = 1.0 / table.step

        def rhs(tau, y):
            w1, w2, w3, a, b, c, d = y.tolist()
            x = (tau - tau_first) * inv
            j = int(x)
            f = x - j
            fm, f1, f2 = f - 1.0, f + 1.0, f - 2.0
            p0, p1, p2, p3 = -f * fm * f2 / 6.0, f1 * fm * f2 * 0.5, -f1 * f * f2 * 0.5, f1 * f * fm / 6.0
            i0, i1, i2, i3 = j - 1, j, j + 1, j + 2
            s = 2.0 / (a * a + b * b + c * c + d * d)
            r11, r12, r13 = 1.0 - s * (c * c + d * d), s * (b * c - a * d), s * (b * d + a * c)
            r21, r22, r23 = s * (b * c + a * d), 1.0 - s * (b * b + d * d), s * (c * d - a * b)
            r31, r32, r33 = s * (b * d - a * c), s * (c * d + a * b), 1.0 - s * (b * b + c * c)
            sxy = syz = szx = 0.0
            for tx, ty, tz in ((mx, my, mz), (sx, sy, sz)):
                X = p0 * tx[i0] + p1 * tx[i1] + p2 * tx[i2] + p3 * tx[i3]
                Y = p0 * ty[i0] + p1 * ty[i1] + p2 * ty[i2] + p3 * ty[i3]
                Z = p0 * tz[i0] + p1 * tz[i1] + p2 * tz[i2] + p3 * tz[i3]
                xb, yb, zb = r11 * X + r21 * Y + r31 * Z, r12 * X + r22 * Y + r32 * Z, r13 * X + r23 * Y + r33 * Z
                sxy += xb * yb
                syz += yb * zb
                szx += zb * xb
            return euler(w1, w2, w3, a, b, c, d, sxy, syz, szx)
        return rhs

    node0, peri0, mean0 = (float(v) for v in _angles(orbit, t0))
    node_rate, peri_rate = orbit.node_rate, orbit.pericentre_rate
    mean_rate = orbit.mean_motion - node_rate - peri_rate
    e = orbit.eccentricity
    sq = math.sqrt(1.0 - e * e)
    ci, si = math.cos(orbit.inclination), math.sin(orbit.inclination)
    gp = 3.0 * orbit.primary_gm_over_a3 / w0          # primary's torque / ω0 at r = a
    kepler = warm_kepler(e, mean0) if e > 0.0 else None
    gs = 0.0
    if sun and orbit.sun_tidal_rate_sq > 0.0:
        gs = 3.0 * orbit.sun_tidal_rate_sq * (1.0 - orbit.sun_eccentricity**2) ** -1.5 / w0
    rs = math.sqrt(gs)
    lam_s0 = orbit.sun_longitude_at_epoch + orbit.sun_mean_motion * (t0 - orbit.epoch)
    n_s = orbit.sun_mean_motion

    def rhs(tau, y):
        w1, w2, w3, a, b, c, d = y.tolist()
        node, peri = node0 + node_rate * tau, peri0 + peri_rate * tau
        if kepler is None:
            u, g = peri + mean0 + mean_rate * tau, gp
        else:
            ce, se = kepler(mean0 + mean_rate * tau)
            a_r = 1.0 / (1.0 - e * ce)
            u = peri + math.atan2(sq * se, ce - e)
            g = gp * a_r * a_r * a_r
        cn, sn, cu, su = math.cos(node), math.sin(node), math.cos(u), math.sin(u)
        rg = math.sqrt(g)
        X, Y, Z = rg * (cn * cu - sn * su * ci), rg * (sn * cu + cn * su * ci), rg * su * si
        s = 2.0 / (a * a + b * b + c * c + d * d)
        r11, r12, r13 = 1.0 - s * (c * c + d * d), s * (b * c - a * d), s * (b * d + a * c)
        r21, r22, r23 = s * (b * c + a * d), 1.0 - s * (b * b + d * d), s * (c * d - a * b)
        r31, r32, r33 = s * (b * d - a * c), s * (c * d + a * b), 1.0 - s * (b * b + c * c)
        xb, yb, zb = r11 * X + r21 * Y + r31 * Z, r12 * X + r22 * Y + r32 * Z, r13 * X + r23 * Y + r33 * Z
        sxy, syz, szx = xb * yb, yb * zb, zb * xb
        if gs:
            lam = lam_s0 + n_s * tau
            X, Y = rs * math.cos(lam), rs * math.sin(lam)
            xb, yb, zb = r11 * X + r21 * Y, r12 * X + r22 * Y, r13 * X + r23 * Y
            sxy, syz, szx = sxy + xb * yb, syz + yb * zb, szx + zb * xb
        return euler(w1, w2, w3, a, b, c, d, sxy, syz, szx)
    return rhs


# --------------------------------------------------------------------------- the start and the run


#: The start's kinds: the brief's locked mean state, or that plus the forced terms its omission would turn into free
#: librations (see :func:`initial_state`).
STARTS = ("forced", "mean")


@dataclass(frozen=True)
class Anomalies:
    """What the forced start needs of the orbit (radians, rad/day): the mean anomaly M and its rate, the argument
    of pericentre's rate ν = Ḟ − Ṁ, and the true-minus-mean longitude's terms (amplitude, phase, rate), Σ A
    sin(phase + rate t): for a Kepler orbit its first-order term 2e sin M, for the real Moon Meeus's longitude
    series (Table 47.A, the largest 2e sin l, evection, variation and the annual equation among them)."""

    mean_anomaly: float
    mean_anomaly_rate: float
    pericentre_rate: float
    longitude_terms: tuple[tuple[float, float, float], ...]

    @classmethod
    def of_orbit(cls, orbit: SynchronousOrbit, jd_tdb: float) -> Anomalies:
        _, _, mean = _angles(orbit, jd_tdb)
        m_dot = orbit.mean_motion - orbit.node_rate - orbit.pericentre_rate
        return cls(float(mean), m_dot, orbit.pericentre_rate, ((2.0 * orbit.eccentricity, float(mean), m_dot),))

    @classmethod
    def of_moon(cls, jd_tdb: float) -> Anomalies:
        args = delaunay_arguments(jd_tdb)
        rates = delaunay_rates(float(centuries(jd_tdb)))
        rows = np.array(lunisolar_data()["moon"]["longitude_distance"], dtype=float)
        k = rows[:, :5]
        amp = np.radians(rows[:, 5] * 1e-6)
        terms = tuple((float(a), float(k_ @ args), float(k_ @ rates)) for a, k_ in zip(amp, k) if a != 0.0)
        return cls(float(args[0]), float(rates[0]), float(rates[2] - rates[0]), terms)


def forced_start(moments, orbit: SynchronousOrbit, c: np.ndarray, start_jd: float,
                 anomalies: Anomalies) -> tuple[float, float, np.ndarray]:
    """The forced librations at the start that the locked mean state leaves out, to first order in e and in the
    moment differences: (τ_f, dτ_f/dt, ω⊥_f) — the libration in longitude (rad) and its rate (rad/day), and the
    angular velocity's body-frame (a, b) components (rad/day) that replace the steady precession's Ω̇ K⊥, and the
    figure axis's forced displacement from the mean pole (body-frame a, b components, rad).

    With the A axis on the primary's mean direction, the primary's body-frame direction is u ≈ (1, 2e sin M,
    −sin θ sin u_true), (a/r)³ ≈ 1 + 3e cos M (u_true = F + 2e sin M, F the mean argument of latitude from the
    orbit's ascending node on the equator, θ the obliquity). Euler's equations with ω3 ≈ n:

    * longitude: τ̈ = −ω0² (τ − δ), δ = Σ A_k sin φ_k the primary's true-minus-mean longitude (2e sin M on a
      Kepler orbit), ω0² = 3 g γ cos⁴(θ/2) (the tilt's factor: the (B − A) part of ⟨u·I·u⟩ over an orbit varies
      as cos⁴(θ/2) cos² τ), forced τ_f = −Σ ω0² A_k sin φ_k / (φ̇_k² − ω0²) (and its rate: a monthly term's rate
      is n/ω0 ≈ 38 times its angle in units of the free frequency, so leaving a 16″ term out starts a 600″ free
      libration);
    * the equator: A ω̇1 = T1 = 3g (C − B) e sin θ [cos(F + M) − cos(F − M)],
      B ω̇2 = T2 = 3g (C − A) sin θ [sin F + (5/2) e sin(F + M) + (1/2) e sin(F − M)], integrated as forced terms
      (ω̇ ≈ T/A: the gyroscopic coupling, relative (C − A)/B · n/ν, and the gravity-gradient stiffness are left out).
      The sin F term is the steady precession Ω̇ K⊥ plus the fortnightly (2F) forced nutation's rate (the mean
      start's Ω̇ K⊥ is half of it); the e sin(F − M) terms, at the argument of pericentre's rate ν (2190 d for
      the Moon), are the large ones: 3 g β sin θ e / (2 ν) ~ 100″ × n for the Moon. They are left out when |ν|
      < 1e-6 rad/day: a pericentre fixed on the equator's node drives the free wobble near resonance (no forced
      solution to start on)."""
    A, B, C = (float(x) for x in moments)
    g, n = orbit.primary_gm_over_a3, orbit.mean_motion
    e = orbit.eccentricity
    h = orbit_normal(orbit, [start_jd])[0]
    cross = np.cross(c, h)
    sin_t = float(np.linalg.norm(cross))
    theta = math.atan2(sin_t, float(c @ h))
    node = cross / sin_t                                          # the orbit's ascending node on the equator
    r = mean_direction(orbit, [start_jd])[0]
    F = math.atan2(float(np.cross(node, r) @ h), float(node @ r))  # mean argument of latitude from it
    M, m_dot, nu = anomalies.mean_anomaly, anomalies.mean_anomaly_rate, anomalies.pericentre_rate
    f_dot = n - orbit.node_rate
    w0_sq = 3.0 * g * (B - A) / C * math.cos(0.5 * theta) ** 4
    tau = tau_dot = 0.0
    for amp, phase, rate in anomalies.longitude_terms:
        gain = -w0_sq * amp / (rate * rate - w0_sq)
        tau += gain * math.sin(phase)
        tau_dot += gain * rate * math.cos(phase)
    k1, k2 = 3.0 * g * (C - B) * e * sin_t / A, 3.0 * g * (C - A) * sin_t / B
    # (phase, its rate, a, b): ω1 = Σ a sin(phase), ω2 = Σ b cos(phase)
    terms = [(F, f_dot, 0.0, -k2 / f_dot),
             (F + M, f_dot + m_dot, k1 / (f_dot + m_dot), -2.5 * e * k2 / (f_dot + m_dot))]
    if abs(nu) >= 1e-6:
        terms.append((F - M, nu, -k1 / nu, -0.5 * e * k2 / nu))
    w_perp = np.zeros(2)
    shift = 0j
    for phase, rate, a, b in terms:
        w_perp += (a * math.sin(phase), b * math.cos(phase))
        # in the frame turning with the node the body turns at Ḟ, so ω1 + i ω2 = (i/2)[(b − a) e^{iφ} + (b + a)
        # e^{−iφ}] are circles at Ḟ ± φ̇ there; ċ = ω × c moves the figure axis on each by −W/(its rate): the
        # steady one (φ = F, rate 0) is the precession the Cassini state already holds
        for amp, sign in ((0.5j * (b - a), 1.0), (0.5j * (b + a), -1.0)):
            rate_there = f_dot + sign * rate
            if abs(rate_there) > 1e-9:
                shift -= amp * complex(math.cos(sign * phase), math.sin(sign * phase)) / rate_there
    return tau, tau_dot, w_perp, np.array([shift.real, shift.imag])



def initial_state(moments, orbit: SynchronousOrbit, start_jd: float, pole0=None, longitude_offset: float = 0.0,
                  omega_offset=None, start: str = "forced", anomalies: Anomalies | None = None) -> np.ndarray:
    """y0 = (ω_b/n, q) at ``start_jd``, see the module docstring: the C axis on the Cassini pole (or ``pole0``),
    the A axis on the primary's mean direction, ω = Ḟ c + Ω̇ K (``start="mean"``); ``start="forced"`` adds the
    forced librations of :func:`forced_start` (the A axis at τ_f, the spin along c by dτ_f/dt, ω⊥ the forced
    one), so that the free librations start from what first order in e leaves out. ``longitude_offset`` (rad)
    turns the A axis about C, ``omega_offset`` (rad/day, body frame) adds to ω. ``anomalies`` default: the
    orbit's."""
    if start not in STARTS:
        raise ValueError(f"start must be one of {STARTS}, got {start!r}")
    if pole0 is None:
        c = cassini_pole(cassini_state(orbit, moments), orbit, [start_jd])[0]
    else:
        c = np.asarray(pole0, dtype=float)
        c = c / np.linalg.norm(c)
    n, node_rate = orbit.mean_motion, orbit.node_rate

    def locked(c: np.ndarray, tau: float) -> np.ndarray:
        # the A axis at the primary's mean longitude + π + τ, measured as τ is (the equator's node on the Laplace
        # plane, then along the equator): the lock of the averaged theory, the angle from the common node the same
        # along the equator as along the orbit (a projection of the mean direction on the equator would be off by
        # (θ²/4) sin 2u, 80″ for the Moon, and start a free libration of that size)
        node_lon = math.atan2(c[0], -c[1])
        node = np.array([math.cos(node_lon), math.sin(node_lon), 0.0])
        phi = float(mean_longitude(orbit, start_jd)) + math.pi - node_lon + longitude_offset + tau
        a1 = math.cos(phi) * node + math.sin(phi) * np.cross(c, node)
        return np.column_stack([a1, np.cross(c, a1), c])

    rot = locked(c, 0.0)
    w_body = rot.T @ ((n - node_rate) * c + node_rate * K_AXIS)   # Ḟ c + Ω̇ K: the lock with the node turning
    if start == "forced":
        anomalies = Anomalies.of_orbit(orbit, start_jd) if anomalies is None else anomalies
        tau, tau_dot, w_perp, shift = forced_start(moments, orbit, c, start_jd, anomalies)
        # the figure axis on its forced position: the mean pole plus the forced terms' displacement at the start
        c = c + rot[:, :2] @ shift
        c /= np.linalg.norm(c)
        rot = locked(c, tau)
        spin = float(c @ ((n - node_rate) * c + node_rate * K_AXIS))
        w_body = np.array([w_perp[0], w_perp[1], spin + tau_dot])
    q0 = quaternion_from_matrix(rot)
    if omega_offset is not None:
        w_body = w_body + np.asarray(omega_offset, dtype=float)
    return np.concatenate([w_body / n, q0])


@dataclass(frozen=True, eq=False)
class SynchronousTrack:
    """A run of the rigid synchronous body at epochs (JD TDB). Vectors are unit vectors in the Laplace frame."""

    jd_tdb: np.ndarray
    moments: tuple[float, float, float]   # (A/C, B/C, 1)
    start_jd: float
    omega_body: np.ndarray           # (N, 3) angular velocity in the body frame, rad/day
    quaternion: np.ndarray           # (N, 4) unit, scalar first, body -> Laplace frame
    figure_axis: np.ndarray          # (N, 3) the C axis
    angular_momentum: np.ndarray     # (N, 3) the direction of L
    long_axis: np.ndarray            # (N, 3) the A axis
    longitude_libration: np.ndarray  # (N,) τ, rad: the A axis's longitude minus the primary's mean longitude + π
    nfev: int                        # right-hand-side calls
    wall_seconds: float              # the integration's wall time (the table's build excluded)
    table_seconds: float = 0.0       # the real Moon's table build (0 on the Kepler orbit)

    @property
    def span_days(self) -> float:
        """Days integrated: forwards plus backwards from the start."""
        tau = self.jd_tdb - self.start_jd
        return float(max(tau.max(), 0.0) - min(tau.min(), 0.0))

    @property
    def calls_per_day(self) -> float:
        """Right-hand-side calls per day integrated (the cost model's unit)."""
        return self.nfev / self.span_days if self.span_days > 0.0 else 0.0

    def obliquity(self, orbit: SynchronousOrbit) -> np.ndarray:
        """θ (rad): the figure axis from the mean orbit's normal."""
        return np.arccos(np.clip(np.sum(self.figure_axis * orbit_normal(orbit, self.jd_tdb), axis=1), -1.0, 1.0))

    def equator_inclination(self) -> np.ndarray:
        """I (rad): the figure axis from the Laplace pole."""
        return np.arccos(np.clip(self.figure_axis[:, 2], -1.0, 1.0))


def longitude_libration(figure: np.ndarray, long_axis: np.ndarray, orbit: SynchronousOrbit, jd_tdb) -> np.ndarray:
    """τ (rad, in (−π, π]): the A axis's longitude, along the Laplace plane to the equator's ascending node then
    along the equator, minus the primary's mean longitude as seen from the body (the satellite's + π)."""
    node_lon = np.arctan2(figure[:, 0], -figure[:, 1])              # K × c
    node = np.stack([np.cos(node_lon), np.sin(node_lon), np.zeros_like(node_lon)], axis=-1)
    phi = np.arctan2(np.sum(np.cross(node, long_axis) * figure, axis=1), np.sum(node * long_axis, axis=1))
    lon = node_lon + phi - mean_longitude(orbit, jd_tdb) - math.pi
    return np.remainder(lon + math.pi, 2.0 * math.pi) - math.pi


def integrate_synchronous(moments, orbit: SynchronousOrbit, start_jd: float, jd_tdb, *, pole0=None,
                          longitude_offset: float = 0.0, omega_offset=None, real_moon: bool = False,
                          sun: bool = True, start: str = "forced", rtol: float = 1e-9, atol: float = 1e-12,
                          table: PerturberTable | None = None, y0=None) -> SynchronousTrack:
    """Integrate the rigid synchronous body from ``start_jd`` to the epochs ``jd_tdb`` (JD TDB, either side).

    ``moments`` (A, B, C) in any common unit; ``orbit`` the mean orbit (the start, the mean longitude of τ and,
    unless ``real_moon``, the primary's motion); ``real_moon`` the tabulated real Moon and Sun (``table`` one
    built by :func:`perturber_table` over the span, to share between runs); ``sun`` False leaves the Sun out.
    The start: :func:`initial_state` (``start`` "forced" or "mean"). Tolerances: DOP853's, on (ω_b/n, q); the
    pole's global error over three node periods of the Moon, against rtol 1e-10: 0.14″ at rtol 1e-6, 0.02″ at
    1e-7, 0.002″ at 1e-8. ``real_moon`` takes ``orbit`` as the Moon's mean orbit on the ecliptic and equinox of
    J2000 (its mean longitude sets τ and the lock; the forced start takes M, Ṁ and ν from the Delaunay
    arguments, not from the orbit). ``y0``: the start (ω_b/n, q) itself instead of :func:`initial_state`'s."""
    mom = normalised_moments(moments)
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    table_seconds = 0.0
    if real_moon and table is None:
        clock = time.perf_counter()
        table = perturber_table(min(t.min(), start_jd), max(t.max(), start_jd), orbit.mean_motion)
        table_seconds = time.perf_counter() - clock
    if table is not None:
        if not real_moon:
            raise ValueError("a perturber table is the real Moon's: pass real_moon=True with it")
        if table.spin_rate != orbit.mean_motion:
            raise ValueError("the table was built for another mean motion")
        last = table.start + table.step * (table.moon.shape[0] - 1 - TABLE_MARGIN)
        if min(t.min(), start_jd) < table.start + TABLE_MARGIN * table.step or max(t.max(), start_jd) > last:
            raise ValueError("the epochs leave the perturber table's span")
    anomalies = Anomalies.of_moon(start_jd) if real_moon else None
    if y0 is None:
        y0 = initial_state(mom, orbit, start_jd, pole0, longitude_offset, omega_offset, start, anomalies)
    else:       # an explicit start (ω_b/n, q: body to the Laplace frame), e.g. a libration series' state
        y0 = np.asarray(y0, dtype=float)
    rhs = make_rhs(mom, orbit, start_jd, table if real_moon else None, sun)
    clock = time.perf_counter()
    states, nfev = solve_both_ways(rhs, y0, t - start_jd, rtol, atol)
    wall = time.perf_counter() - clock
    q = states[:, 3:] / np.linalg.norm(states[:, 3:], axis=1, keepdims=True)
    omega = states[:, :3] * orbit.mean_motion
    rot = rotation_matrices(q)
    ang = np.einsum("nij,nj->ni", rot, omega * np.asarray(mom))
    ang /= np.linalg.norm(ang, axis=1, keepdims=True)
    fig, lng = rot[:, :, 2], rot[:, :, 0]
    return SynchronousTrack(t, mom, float(start_jd), omega, q, fig, ang, lng,
                            longitude_libration(fig, lng, orbit, t), nfev, wall, table_seconds)
