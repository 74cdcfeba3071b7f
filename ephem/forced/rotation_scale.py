"""The rotation-scale terms: what averaging the solar torque over the rotation leaves out, in closed form.

The averaged theories (every rung of :mod:`ephem.sun.ladder`) give the mean angular momentum L̄. The full
rigid body (:mod:`ephem.forced.rigid_body`) differs from it by terms at the rotation's scale. To first order in
the torque, for principal moments A <= B <= C, a spin ω about the C axis s and the Sun in the unit
direction u with g = 3 GM / r³ (= 3 n² (a/r)³):

* the torque T = g u × (I u) splits, with z = s·u and u⊥ = u - z s, into the averaged part
  g (C - (A+B)/2) z (u × s) and a part of size g (B - A)/2 |z| |u⊥| that turns at -2ω (its
  direction is u⊥ reflected in the A axis â, R_â(u⊥) = 2 (â·u⊥) â - u⊥);
* L therefore carries a **semi-diurnal circle**: integrating the turning part over the rotation,
  δL̂ = -g z (B - A) / (4 C ω²) R_â(u⊥), radius g |z| |u⊥| (B - A) / (4 C ω²);
* Euler's equations forced at the rotation frequency give the body a transverse angular velocity
  ω⊥ = (g z / (C ω)) ((C - B) x, (C - A) y) (x, y the Sun's body-frame components along the A and
  B axes), which sets the **figure axis** apart from L by -(A ω1, B ω2)/(C ω): a steady
  **Oppolzer offset** -g z M / (C² ω²) u⊥, M = (C (A + B) - 2 A B) / 2, and a semi-diurnal part
  +g z (B - A) / (2 C ω²) R_â(u⊥). The figure axis thus carries the semi-diurnal term of L with the
  opposite sign, +g z (B - A) / (4 C ω²) R_â(u⊥).

The derivation is that of the forced (Oppolzer) terms of the Earth's rotation (Kinoshita 1977,
sect. 6; Moritz & Mueller, *Earth Rotation*, 1987, ch. 5), written here for a triaxial body and a
single perturber; it drops terms of relative order ν̇ / ω (the Sun's angular rate over the spin,
which shifts the forcing frequency) and of order g / ω² (the torque acting on the offset figure
axis). The tests compare every term with the integrated rigid body (:mod:`ephem.forced.rigid_body`).

The semi-diurnal terms need the rotation phase: φ, the angle of the A axis in the body's equator
from the ascending node of the orbit on it, e₁ = (s × W)/|s × W| (W the orbit normal), counted
towards e₂ = s × e₁, at the pole epoch. It advances as φ̇ = ω + ψ̇ cos ε (the node itself turns by
-ψ̇ about W). Without it the Oppolzer offset alone is modelled and the semi-diurnal terms stay an
error of known size (:func:`semi_diurnal_radius`).

Vectors are in the orbit frame of the model (x the mean equinox at the pole epoch, z the orbit
normal); radians and days. ``model`` is a :class:`ephem.forced.precession_nutation.PrecessionNutation`, read by its
attributes: the error estimates (:mod:`ephem.forced.physics_errors`) take these terms without the import chain of
the model.
"""
from __future__ import annotations

import math
import threading
import weakref
from collections import OrderedDict
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..orbit.kepler import solve_kepler, true_anomaly
from .precession_nutation import PrecessionNutation


@dataclass(frozen=True)
class SunGeometry:
    """The Sun on the model's Keplerian orbit, seen in its orbit frame, at epochs (JD TDB)."""

    jd_tdb: np.ndarray
    direction: np.ndarray   # (N, 3) unit vectors
    torque_strength: np.ndarray   # g = 3 n² (a/r)³, rad²/day²

    @classmethod
    def at(cls, model, jd_tdb) -> SunGeometry:
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        e = model.eccentricity
        nu = true_anomaly(model.mean_anomaly(t), e)
        lam = model.equinox_to_pericentre + nu
        a_over_r = (1.0 + e * np.cos(nu)) / (1.0 - e * e)
        u = np.stack([np.cos(lam), np.sin(lam), np.zeros_like(lam)], axis=-1)
        return cls(t, u, 3.0 * model.mean_motion**2 * a_over_r**3)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def equator_basis(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """e₁ = (s × W)/|s × W|, the ascending node of the orbit (normal W = z) on the equator of ``axis`` s,
    and e₂ = s × e₁ (orbit-frame vectors, (N, 3)). A pole on the orbit normal takes the x axis's
    projection as e₁ (the node is undefined there)."""
    s = np.atleast_2d(axis)
    e1 = np.stack([s[:, 1], -s[:, 0], np.zeros(len(s))], axis=-1)
    norm = np.linalg.norm(e1, axis=-1)
    polar = norm < 1e-12
    if polar.any():
        e1[polar] = np.array([1.0, 0.0, 0.0]) - s[polar, :1] * s[polar]
        norm = np.linalg.norm(e1, axis=-1)
    e1 = e1 / norm[:, None]
    return e1, np.cross(s, e1)


def long_axis(axis: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """The A axis â = cos φ e₁ + sin φ e₂ (:func:`equator_basis`), (N, 3)."""
    e1, e2 = equator_basis(axis)
    return np.cos(phase)[:, None] * e1 + np.sin(phase)[:, None] * e2


def rotation_phase(model, jd_tdb, phase_at_pole_epoch: float, psi: np.ndarray) -> np.ndarray:
    """φ(t) = φ₀ + ω (t - t₀) + cos ε̄ (ψ(t) - ψ(t₀)), radians (ψ the track's precession angle, ψ(t₀) = Δψ(t₀))."""
    t = np.asarray(jd_tdb, dtype=float)
    psi0 = model.nutation_at_pole_epoch[0]
    return phase_at_pole_epoch + model.spin_rate * (t - model.pole_epoch) \
        + math.cos(model.obliquity) * (np.asarray(psi) - psi0)


@dataclass(frozen=True)
class RotationTerms:
    """The rotation-scale departures from the mean angular momentum L̄ at epochs (orbit-frame vectors,
    (N, 3), radians). ``semi_diurnal`` is that of L (the figure axis has its opposite); None when the
    rotation phase is not known. ``oppolzer`` is the figure axis's steady offset from L."""

    oppolzer: np.ndarray
    semi_diurnal: np.ndarray | None
    semi_diurnal_radius: np.ndarray   # (N,) radius of the semi-diurnal circle

    def figure_offset(self) -> np.ndarray:
        """Figure axis minus L̄ (without the semi-diurnal part when the phase is not known)."""
        return self.oppolzer if self.semi_diurnal is None else self.oppolzer - self.semi_diurnal

    def momentum_offset(self) -> np.ndarray:
        """L minus L̄."""
        return np.zeros_like(self.oppolzer) if self.semi_diurnal is None else self.semi_diurnal


def oppolzer_factor(moments) -> float:
    """M / C² = (C (A + B) - 2 A B) / (2 C²): the Oppolzer offset is g |z| |u⊥| M / (C² ω²)."""
    A, B, C = moments
    return (C * (A + B) - 2.0 * A * B) / (2.0 * C * C)


def semi_diurnal_factor(moments) -> float:
    """(B - A) / (4 C): the semi-diurnal radius is g |z| |u⊥| (B - A) / (4 C ω²)."""
    A, B, C = moments
    return (B - A) / (4.0 * C)


def rotation_terms(moments, spin_rate: float, axis: np.ndarray, sun: SunGeometry,
                   phase: np.ndarray | None = None) -> RotationTerms:
    """The rotation-scale terms (module docstring) for mean poles ``axis`` (N, 3) under ``sun``;
    ``phase`` φ (N,) of the A axis, or None if unknown. ``moments`` (A, B, C), any normalisation."""
    s = np.atleast_2d(axis)
    u, g = sun.direction, sun.torque_strength
    z = np.sum(s * u, axis=-1)
    u_perp = u - z[:, None] * s
    scale = g * z / spin_rate**2
    oppolzer = -(scale * oppolzer_factor(moments))[:, None] * u_perp
    radius = np.abs(scale) * np.linalg.norm(u_perp, axis=-1) * semi_diurnal_factor(moments)
    sd = None
    if phase is not None:
        a = long_axis(s, np.asarray(phase, dtype=float))
        reflected = 2.0 * np.sum(a * u_perp, axis=-1)[:, None] * a - u_perp
        sd = -(scale * semi_diurnal_factor(moments))[:, None] * reflected
    return RotationTerms(oppolzer, sd, radius)


def forced_angular_velocity(moments, spin_rate: float, sun_body: np.ndarray, g: float,
                            sun_rate: float = 0.0, forcing_rate: float = 0.0) -> np.ndarray:
    """The body-frame angular velocity (rad/day) of the forced solution with no free wobble, for the Sun at
    (x, y, z) in the body frame whose azimuth about the spin axis turns at ``sun_rate`` λ̇ (rad/day), with
    ``forcing_rate`` the rate of change of g (x² + y²) (rad²/day³):

        (g z (C - B) x / (C ω),  g z (C - A) y / (C ω),
         ω + (B - A) / (4 C Ω) [g (x² - y²) + (d(g p²)/dt) x y / (p² Ω)]),   Ω = ω - λ̇, p² = x² + y².

    The transverse part solves Euler's equations exactly for a Sun fixed in space. The third component is the
    oscillation of the spin rate that the (B - A) torque g (B - A) x y / C drives about its mean ω, so that the
    mean spin is the catalogue's: C ω̇₃ = g (B - A) (p²/2) sin 2θ with θ̇ = -Ω, integrated by parts to the term in
    the amplitude's rate. Starting at ω exactly would shift the mean by up to g (B - A)/(4 C ω); the first term
    with Ω = ω leaves that times λ̇/ω (measured 3·10⁻⁶ ω at ω/n = 45, turning the long axis by 0.012 rad over
    4000 rotations), and without the second a shift of relative size ġ/(g ω) (measured 2.7·10⁻⁷ ω at ω/n = 129).
    The same shift of frequency in the transverse part made the start no better on the cases measured: there the
    Sun's declination and distance change as fast, which a steady forcing leaves out."""
    A, B, C = moments
    x, y, z = (float(c) for c in sun_body)
    k = g * z / (C * spin_rate)
    big = spin_rate - sun_rate
    p2 = x * x + y * y
    change = forcing_rate * x * y / (p2 * big) if p2 > 0.0 else 0.0
    return np.array([k * (C - B) * x, k * (C - A) * y,
                     spin_rate + (B - A) / (4.0 * C * big) * (g * (x * x - y * y) + change)])


def forcing_amplitude_rate(model, axis: np.ndarray, jd_tdb: float) -> float:
    """d(g p²)/dt (rad²/day³) at ``jd_tdb`` for the spin ``axis`` (orbit frame) held: g = 3 n² (a/r)³ and
    p² = 1 - (s·u)², the Sun's distance from the axis. A central difference over 10⁻⁴ of the time the Sun takes to
    pass pericentre, (1 - e)^(3/2)/n, where g changes fastest: its error, of relative order 10⁻⁸, is far below
    what the start's next order leaves."""
    e = model.eccentricity
    h = 1e-4 * (1.0 - e) ** 1.5 / model.mean_motion
    sun = SunGeometry.at(model, [jd_tdb - h, jd_tdb + h])
    s = np.asarray(axis, dtype=float)
    gp2 = sun.torque_strength * (1.0 - (sun.direction @ s) ** 2)
    return float(gp2[1] - gp2[0]) / (2.0 * h)


def sun_azimuth_rate(model, axis: np.ndarray, jd_tdb: float) -> float:
    """λ̇ (rad/day): the rate at which the Sun's azimuth about the spin ``axis`` (orbit frame) turns, ν̇ (W·s)/|u⊥|²,
    W the orbit normal and ν̇ = n (1 + e cos ν)² / (1 - e²)^(3/2) the Sun's angular rate along the orbit."""
    e = model.eccentricity
    nu = float(true_anomaly(model.mean_anomaly(np.array([jd_tdb])), e)[0])
    nu_dot = model.mean_motion * (1.0 + e * math.cos(nu)) ** 2 / (1.0 - e * e) ** 1.5
    u = SunGeometry.at(model, [jd_tdb]).direction[0]
    s = np.asarray(axis, dtype=float)
    perp2 = 1.0 - float(s @ u) ** 2
    return nu_dot * float(s[2]) / perp2


def apply(axis: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """Unit vectors of ``axis`` moved by the small ``offset`` vectors."""
    return _unit(np.atleast_2d(axis) + offset)


# --------------------------------------------------------------------------- the error estimate

#: The second-order drift. The mean torque acts on the figure axis, which stands off L by the Oppolzer offset:
#: the averaged torque g (C - (A+B)/2) z (u × f) evaluated at f = L̂ + O is the rungs' torque at L̂ times
#: 1 - ε cos 2δ, ε = g M / (C² ω²) (δ the Sun's declination over the equator, z = sin δ). Integrated along the
#: track, |∫ ε cos 2δ dL̂/dt dt| is what the averaged pole drifts from the rigid body's. This factor over it is
#: measured: on 160 rigid integrations (docs/accuracy.md) the track with every term modelled left up to 1.13 times
#: that integral where it dominated (the long spans at ω/n 50-120: the next order in ν̇/ω); 1.5 keeps a margin
#: of 1.33. A drift from the (B - A) torque acting on the semi-diurnal circles
#: (∝ (B - A)² g² / ω³), which the earlier estimate bounded at its peak rate over the whole span, was not seen:
#: where it would dominate the residual stays within the next-order piece.
DRIFT_FACTOR = 1.5
#: The first-order terms take the forcing F = g z u⊥ as steady. It changes as the Sun moves (and the pole
#: precesses), at a rate |dF/dt| up to ~ ν̇ g; the response to a forcing that changes shifts the figure axis by
#: ~ |dF/dt| / ω³ times its factors, amplified by the body's resonance (:func:`resonance_factor`) when the free
#: wobble's body-frame frequency nears ω (A + B → C), and the start leaves a free wobble of that size. This
#: constant times max (1 + Γ) |dF/dt| (M/C² + (B - A)/(2C)) / ω³ over the span bounds what is left of the figure
#: axis. Measured on the same 160 integrations with the drift above: the largest constant any case needed was
#: 0.93 (the figure axis, every term modelled); 1.5 keeps a margin of 1.6.
NEXT_ORDER = 1.5
#: L is not moved by the free wobble the start leaves (the figure axis circles L), nor amplified by the resonance:
#: its next order is that of its own semi-diurnal circle, |dF/dt| (B - A)/(2 C ω³). Measured: the largest constant
#: any of the 160 cases needed was 0.51 with every term modelled (cases whose residual is at the reference's
#: noise, below 1e-12 rad, aside); for axisymmetric bodies, where this piece vanishes, L's residual with every
#: term modelled was the drift integral itself to 1 % (five bodies, e 0-0.9, ω/n 35-300), so the start leaves L
#: no offset of this order. 0.75 keeps a margin of 1.5.
NEXT_ORDER_MOMENTUM = 0.75
#: The rotation phase model φ = φ₀ + ω τ + cos ε Δψ (:func:`rotation_phase`) follows the mean pole L̄, not the
#: figure axis, and counts φ from the orbit's node on the equator, a reference that twists as the pole moves: its
#: error grows with how far the pole moves. Measured on 160 rigid integrations (the integrated A axis's angle from
#: the node, the reference started in the forced state: :func:`forced_angular_velocity` with the spin's
#: oscillation at ω - λ̇ and its amplitude's rate, without which the mean spin is off by up to 3·10⁻⁶ ω and the
#: phase drifts by 0.01 rad over thousands of rotations): at most 0.027 × (Σ|Δψ_k| + Σ|Δε_k| + |ψ̇| × span),
#: median 0.002; 0.04 keeps a margin of 1.5. A phase error δφ moves the semi-diurnal terms by 2 R δφ.
PHASE_FACTOR = 0.04
#: Beyond this many orbits the estimate uses orientation-free bounds instead of sampling the span.
MAX_SAMPLED_ORBITS = 20.0
#: The least span the estimate samples (days, ~14 min): 65 epochs over it are 3e4 float64 spacings of a JD apart.
MIN_SAMPLED_SPAN_DAYS = 0.01
#: Pole azimuths (ψ, evenly over a turn) at which a long span's drift rate is sampled: the rate's orbit mean
#: depends on where the pole leans relative to the pericentre, through harmonics 1 and 2 of ψ.
LONG_SPAN_AZIMUTHS = 24
#: What a track includes: nothing of the rotation scale, the Oppolzer offset (the phase unknown), or all.
MODELLED = ("none", "oppolzer", "all")


def _span_grid(model, span_days: float, count: int) -> np.ndarray:
    """``count`` epochs over [t₀, t₀ + span], even in the eccentric anomaly: the torque peaks at pericentre over
    a time ∝ (1 - e)^(3/2) of the orbit, which an even grid in time misses at high e (30 % low at e = 0.94
    with 512 epochs an orbit), but over a range ∝ (1 - e)^(1/2) of the eccentric anomaly."""
    e, n, t0 = model.eccentricity, model.mean_motion, model.pole_epoch
    ends = float(model.mean_anomaly(t0)) + np.array([0.0, n * span_days])
    reduced = solve_kepler(ends, e)
    ecc = reduced + (ends - (reduced - e * np.sin(reduced)))     # E unwrapped: M - M(E reduced) is a whole turn
    grid = np.linspace(ecc[0], ecc[1], count)
    return t0 + (grid - e * np.sin(grid) - ends[0]) / n


def samples_per_orbit(e: float) -> int:
    """Epochs an orbit for the estimate's samples, even in the eccentric anomaly E. In E the torque's strength
    (a/r)³ has harmonics falling as q^k, q = e/(1 + √(1 - e²)); 64 points resolve the Sun's own harmonics (1 and 2
    of its longitude) to a sampled maximum within 0.5 % (the margins of the measured constants cover it), and
    every factor 10 in q^k needs ~ln 10/|ln q| harmonics more: 64 + 512 e, i.e. 72 for the Earth, 112 for Mars,
    525 at e = 0.9 (the 512 used throughout before)."""
    return int(64 + 512 * e)


def sampled_epochs(e: float, orbits: float) -> int:
    """The epochs at which :func:`error_terms` samples a span of ``orbits`` orbits (eccentricity ``e``): 65 at least,
    :func:`samples_per_orbit` an orbit; none beyond :data:`MAX_SAMPLED_ORBITS`, where its bounds take no samples."""
    if orbits > MAX_SAMPLED_ORBITS:
        return 0
    return max(65, int(samples_per_orbit(e) * orbits) + 2)


def _drift_rate(model, moments, s: np.ndarray, sun: SunGeometry) -> np.ndarray:
    """ε cos 2δ dL̂/dt (rad/day, (N, 3)) for poles ``s``: the rate at which the averaged pole departs from the
    rigid body's because the torque acts on the offset figure axis (:data:`DRIFT_FACTOR`)."""
    g, u = sun.torque_strength, sun.direction
    z = np.sum(s * u, axis=-1)
    rate = (model.scaling_factor * g / (3.0 * model.mean_motion**2) * z)[:, None] * np.cross(u, s)
    return (g / model.spin_rate**2 * oppolzer_factor(moments) * (1.0 - 2.0 * z * z))[:, None] * rate


def _cumulative(f: np.ndarray, t: np.ndarray) -> np.ndarray:
    """∫_{t₀}^t f dt at every sample (trapezoids), (N, 3): scipy's cumulative_trapezoid, written out because every
    tolerance request runs it and importing scipy.integrate costs a cold process 0.35 s."""
    steps = 0.5 * (f[1:] + f[:-1]) * np.diff(t)[:, None]
    return np.vstack([np.zeros((1, f.shape[1])), np.cumsum(steps, axis=0)])


def _long_span_drift(model, moments, span: float) -> float:
    """max |∫ ε cos 2δ dL̂/dt| over a span of many orbits: the orbit-mean rate, largest over the pole's azimuths
    (:data:`LONG_SPAN_AZIMUTHS`), times the span, plus the largest departure within an orbit from that mean
    (:func:`_orbit_drift`, which depends on the body alone)."""
    worst_rate, worst_wiggle = _orbit_drift(
        model.mean_motion, model.eccentricity, model.equinox_to_pericentre, model.mean_anomaly_at_epoch,
        model.orbit_epoch, model.pole_epoch, model.obliquity, model.scaling_factor, model.spin_rate,
        tuple(float(x) for x in moments))
    # a sampled azimuth can miss the largest rate by the harmonic's curvature: (π / N)² / 2 of it for harmonic 2
    return worst_rate * (1.0 + 0.5 * (2.0 * math.pi / LONG_SPAN_AZIMUTHS) ** 2) * abs(span) + worst_wiggle


@lru_cache(maxsize=256)     # the body's alone (~26 ms: 24 azimuths over an orbit), asked by every estimate of a long span
def _orbit_drift(mean_motion, eccentricity, equinox_to_pericentre, mean_anomaly_at_epoch, orbit_epoch, pole_epoch,
                 obliquity, scaling_factor, spin_rate, moments) -> tuple[float, float]:
    """(the largest orbit-mean drift rate over the pole's azimuths, rad/day; the largest departure within an orbit
    from it, rad) of a model given by the values :func:`_drift_rate` and :class:`SunGeometry` read."""
    model = _DriftModel(mean_motion, eccentricity, equinox_to_pericentre, mean_anomaly_at_epoch, orbit_epoch,
                        pole_epoch, obliquity, scaling_factor, spin_rate)
    period = 2.0 * math.pi / mean_motion
    t = _span_grid(model, period, 1025)
    sun = SunGeometry.at(model, t)
    worst_rate, worst_wiggle = 0.0, 0.0
    for psi in np.linspace(0.0, 2.0 * math.pi, LONG_SPAN_AZIMUTHS, endpoint=False):
        s = np.broadcast_to(model.pole_orbit_frame(np.array([psi]), np.array([obliquity])), (t.size, 3))
        c = _cumulative(_drift_rate(model, moments, s, sun), t)
        mean = c[-1] / period
        worst_rate = max(worst_rate, float(np.linalg.norm(mean)))
        worst_wiggle = max(worst_wiggle, float(np.max(np.linalg.norm(c - np.outer(t - t[0], mean), axis=1))))
    return worst_rate, worst_wiggle


@dataclass(frozen=True)
class _DriftModel:
    """The values of a :class:`~ephem.forced.precession_nutation.PrecessionNutation` that the drift over an orbit
    reads (its Keplerian orbit, pole epoch, mean obliquity and rates), with the same methods."""

    mean_motion: float
    eccentricity: float
    equinox_to_pericentre: float
    mean_anomaly_at_epoch: float
    orbit_epoch: float
    pole_epoch: float
    obliquity: float
    scaling_factor: float
    spin_rate: float

    mean_anomaly = PrecessionNutation.mean_anomaly
    pole_orbit_frame = PrecessionNutation.pole_orbit_frame


def error_terms(model, moments, span_days: float, axis: str = "figure",
                modelled: str = "none", pole: str = "figure") -> dict[str, float]:
    """Upper bounds (radians) on what a rotation-averaged track leaves out against the rigid body over
    [t₀, t₀ + span], by named piece, for the pole ``axis`` ("figure" or "momentum") when the track
    includes ``modelled`` (:data:`MODELLED`) of the rotation-scale terms.

    ``pole`` says what the catalogue pole is at t₀. "figure" (default): the figure axis, so the mean L̄
    starts from it less the figure's offset there; a track that starts L̄ on the pole (``modelled`` "none")
    or without the semi-diurnal part carries that start error ``δ₀`` along. "momentum": L, as a track with a
    modelled free wobble takes it (:mod:`ephem.rotation.free_motion`); then only L's semi-diurnal part is a start
    error, and the figure axis carries the whole Oppolzer offset (``modelled`` "none" only). Pieces:

    ``oppolzer``      the Oppolzer offset not modelled: max |O(t) - O₀'| for the figure axis (O₀' the
                      offset at t₀ carried by the precession; max |O(t)| when the pole is L), |O₀| for L
                      (0 when the pole is L);
    ``semi_diurnal``  the semi-diurnal terms without the phase: max R(t) + R(t₀);
    ``start``         the start error's own drift: the precession rate's dependence on the obliquity,
                      (K f(e) / 2) sin²ε δ₀ |span|;
    ``drift``         second order: the torque acting on the offset figure axis,
                      :data:`DRIFT_FACTOR` × max |∫ ε cos 2δ dL̂/dt dt| along the track;
    ``phase``         ("all" only) the rotation phase model's error δφ moving the semi-diurnal terms:
                      2 max R × :data:`PHASE_FACTOR` × (Σ|Δψ_k| + Σ|Δε_k| + |ψ̇ span|);
    ``next_order``    the response to the forcing's change and the free wobble the start leaves:
                      :data:`NEXT_ORDER` × max (1 + Γ) |dF/dt| (M/C² + (B - A)/(2C)) / ω³ over the span,
                      F = g z u⊥ the forcing, Γ the :func:`resonance_factor`; for L,
                      :data:`NEXT_ORDER_MOMENTUM` × max |dF/dt| (B - A)/(2C) / ω³.

    ``moments`` (A, B, C) in any normalisation. Perturbative in ν̇/ω: meant for ω/n >= 30 with the Sun's
    peak rate well below ω (:func:`sun_rate_ratio`).
    """
    if axis not in ("figure", "momentum"):
        raise ValueError(f"axis must be 'figure' or 'momentum', got {axis!r}")
    if modelled not in MODELLED:
        raise ValueError(f"modelled must be one of {MODELLED}, got {modelled!r}")
    if pole not in ("figure", "momentum") or (pole == "momentum" and modelled != "none"):
        raise ValueError(f"pole must be 'figure', or 'momentum' with nothing modelled, got {pole!r} with {modelled!r}")
    A, B, C = (float(x) / float(moments[2]) for x in moments)
    mom = (A, B, 1.0)
    w, e = model.spin_rate, model.eccentricity
    span = float(span_days)
    o0, r0, o_max, r_max, figure_change, forcing_rate, drift = span_samples(model, mom, span)
    start_offset = r0 if pole == "momentum" else {"none": o0 + r0, "oppolzer": r0, "all": 0.0}[modelled]
    out = {}
    if modelled == "none":
        if pole == "momentum":
            out["oppolzer"] = o_max if axis == "figure" else 0.0
        else:
            out["oppolzer"] = figure_change if axis == "figure" else o0
    if modelled != "all":
        out["semi_diurnal"] = r_max + r0
    out["start"] = 0.5 * model.scaling_factor * (1.0 - e * e) ** -1.5 * math.sin(model.obliquity) ** 2 \
        * start_offset * abs(span)
    out["drift"] = DRIFT_FACTOR * drift
    if modelled == "all":
        nut = model.nutation
        moved = float(np.sum(np.hypot(nut.lon_sin, nut.lon_cos)) + np.sum(np.hypot(nut.obl_sin, nut.obl_cos))) \
            + abs(model.precession_rate * span)
        out["phase"] = 2.0 * r_max * PHASE_FACTOR * moved
    if axis == "figure":
        figure = (1.0 + resonance_factor(mom)) * (oppolzer_factor(mom) + 2.0 * semi_diurnal_factor(mom))
        out["next_order"] = NEXT_ORDER * figure * forcing_rate / w**3
    else:
        out["next_order"] = NEXT_ORDER_MOMENTUM * 2.0 * semi_diurnal_factor(mom) * forcing_rate / w**3
    return out


#: what :func:`span_samples` keeps: its last few answers, and the terms at the pole epoch they start from, keyed by
#: the model's identity (held weakly: a model the process drops is not kept alive here), the normalised moments and
#: the span; a few floats an entry
_SAMPLES_KEPT = 16
_samples: OrderedDict = OrderedDict()
_samples_lock = threading.Lock()


@dataclass(frozen=True)
class SpanSamples:
    """What :func:`error_terms` reads of a span [t₀, t₀ + span] (radians; rad²/day³ for ``forcing_rate``): the same
    for every pole ``axis``, ``modelled`` and catalogue ``pole`` it is asked about, so that the several estimates of
    one request (none, the Oppolzer offset or all modelled, the pole as L) sample the span once."""

    o0: float              # |O(t₀)|, the Oppolzer offset at t₀
    r0: float              # R(t₀), the semi-diurnal radius at t₀
    o_max: float           # max |O(t)| over the span (the sampled maximum's margin included)
    r_max: float           # max R(t) over the span (likewise)
    figure_change: float   # max |O(t) - O₀'| (O₀' the offset at t₀ carried by the precession)
    forcing_rate: float    # max |dF/dt|, F = g z u⊥
    drift: float           # max |∫ ε cos 2δ dL̂/dt dt| (before :data:`DRIFT_FACTOR`)

    def __iter__(self):
        return iter((self.o0, self.r0, self.o_max, self.r_max, self.figure_change, self.forcing_rate, self.drift))


def span_samples(model, moments, span_days: float) -> SpanSamples:
    """:class:`SpanSamples` of ``model`` over a span of ``span_days`` (signed) for ``moments`` (A/C, B/C, 1):
    sampled once and kept for the next few asks (:data:`_SAMPLES_KEPT`), since a request bounds the same span for
    several variants (each of :func:`error_terms`' pieces is then a few float operations on these)."""
    mom, span = tuple(float(x) for x in moments), float(span_days)
    return _kept(model, (mom, span), lambda: _span_samples(model, mom, span))


def forget_spans() -> None:
    """Drop the spans' kept samples (:func:`span_samples`), keeping each model's terms at its pole epoch: what a
    process that has served the body but never these spans holds (the calibration's warm call of a new question)."""
    with _samples_lock:
        for key in [k for k in _samples if k[-1] != "pole epoch"]:
            del _samples[key]


def _kept(model, key: tuple, build):
    """``build()``, kept in :data:`_samples` under the model's identity and ``key`` for the next few asks."""
    key = (id(model),) + key
    with _samples_lock:
        kept = _samples.get(key)
        if kept is not None and kept[0]() is model:
            _samples.move_to_end(key)
            return kept[1]
    value = build()
    try:
        ref = weakref.ref(model)
    except TypeError:           # a model that cannot be referred to weakly is not kept
        return value
    with _samples_lock:
        _samples[key] = (ref, value)
        _samples.move_to_end(key)
        while len(_samples) > _SAMPLES_KEPT:
            _samples.popitem(last=False)
    return value


def _at_pole_epoch(model, mom: tuple[float, float, float]) -> tuple[float, float, tuple]:
    """(|O(t₀)|, R(t₀), O(t₀)): the Oppolzer offset's size, the semi-diurnal radius and the offset (orbit frame,
    radians) at the pole epoch, from the catalogue pole; the same for every span (a single epoch's Kepler solve and
    terms, ~0.15 ms)."""
    sun0 = SunGeometry.at(model, [model.pole_epoch])
    s0 = model.catalogue_pole_orbit[None]
    first = rotation_terms(mom, model.spin_rate, s0, sun0)
    return float(np.linalg.norm(first.oppolzer[0])), float(first.semi_diurnal_radius[0]), tuple(first.oppolzer[0])


def _span_samples(model, mom: tuple[float, float, float], span: float) -> SpanSamples:
    """:func:`span_samples` computed."""
    n, w, e = model.mean_motion, model.spin_rate, model.eccentricity
    orbits = abs(span) * n / (2.0 * math.pi)
    o0, r0, first = _kept(model, (mom, "pole epoch"), lambda: _at_pole_epoch(model, mom))
    if orbits <= MAX_SAMPLED_ORBITS:
        # a span within minutes of t₀ (a track at the pole's epoch: zero, or a few float64 spacings of a JD) is
        # sampled over MIN_SAMPLED_SPAN_DAYS on its side: the largest rate and change over a longer span bound those
        # of the shorter one, where a grid of 65 equal or crowded epochs gave the rate 0/0 (NaN)
        sampled = math.copysign(max(abs(span), MIN_SAMPLED_SPAN_DAYS), span)
        t = _span_grid(model, sampled, sampled_epochs(e, orbits))
        sun = SunGeometry.at(model, t)
        psi, _, _, eps = model.angles(t)
        s = model.pole_orbit_frame(psi, eps)
        here = rotation_terms(mom, w, s, sun)
        offset = np.linalg.norm(here.oppolzer, axis=-1)
        radius = here.semi_diurnal_radius
        turn = -(psi - psi[0])           # the pole, and an offset it carries, turn by -Δψ about the orbit normal
        c, sn = np.cos(turn), np.sin(turn)
        ox, oy, oz = first
        carried = np.stack([c * ox - sn * oy, sn * ox + c * oy, np.full_like(c, oz)], axis=-1)
        figure_change = float(np.max(np.linalg.norm(here.oppolzer - carried, axis=-1)))
        sd = np.sum(s * sun.direction, axis=-1)          # z, the sine of the Sun's declination
        forcing = (sun.torque_strength * sd)[:, None] * (sun.direction - sd[:, None] * s)   # F = g z u⊥
        rates = np.linalg.norm(np.gradient(forcing, t, axis=0), axis=-1)
        forcing_rate = float(np.max(rates))
        drift = float(np.max(np.linalg.norm(_cumulative(_drift_rate(model, mom, s, sun), t), axis=1)))
        # a sampled maximum of the Sun's second harmonic can fall short of the peak by (2π/N)²/2 of it (N a turn)
        peak = 1.0 + 2.0 * (math.pi / samples_per_orbit(e)) ** 2
        r_max, o_max = peak * float(radius.max()), peak * float(offset.max())
    else:
        # long spans: bounds for any orientation of the Sun over the equator (|δ| <= ε, so
        # |sin δ cos δ| <= sin(2 min(ε, 45°))/2), instead of sampling hundreds of points per orbit
        tilt = min(model.obliquity, math.pi - model.obliquity)
        geo = 0.5 * math.sin(2.0 * min(tilt, 0.25 * math.pi)) * 1.01
        g_max = 3.0 * n * n / (1.0 - e) ** 3
        o_max = g_max * geo * oppolzer_factor(mom) / w**2
        r_max = g_max * geo * semi_diurnal_factor(mom) / w**2
        figure_change = o_max + o0
        # |d(z u⊥)/dλ| <= 2 sin(tilt) as the Sun's longitude λ turns at ν̇, and g changes at |ġ| <= 3 ν̇ e g/(1 - e)
        nu_dot = sun_rate_ratio(model) * w
        forcing_rate = g_max * nu_dot * (2.0 * math.sin(tilt) + 3.0 * e / (1.0 - e) * geo)
        drift = _long_span_drift(model, mom, span)
    return SpanSamples(o0, r0, o_max, r_max, figure_change, forcing_rate, drift)


def resonance_factor(moments) -> float:
    """Γ = max(B |C - 2A|, A |C - 2B|) / (C (A + B - C)): how much the forced transverse spin changes, relative
    to itself, per relative change of the forcing frequency. It grows without bound as A + B → C, where the free
    wobble's body-frame frequency ω √((C - A)(C - B)/(A B)) reaches the forcing's ω."""
    A, B, C = moments
    return max(B * abs(C - 2.0 * A), A * abs(C - 2.0 * B)) / (C * (A + B - C))


def sun_rate_ratio(model) -> float:
    """The Sun's peak angular rate over the spin, n (1 + e)² / ((1 - e²)^(3/2) ω): the small parameter
    the rotation-scale terms drop."""
    e = model.eccentricity
    return model.mean_motion * (1.0 + e) ** 2 / (1.0 - e * e) ** 1.5 / model.spin_rate
