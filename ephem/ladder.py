"""The fidelity ladder: models of rising cost and accuracy, each with an error estimate; a tolerance picks one.

Rungs, cheapest first (names as reported in a track's ``model.name``):

1. ``secular``       ψ = ψ̇ (t - t0), ε = ε̄0: precession only.
2. ``series``        Kinoshita-Cayley nutation with the Hansen coefficients as e-power
                     series truncated at e^N (``order`` N; the paper: 4). Only below the
                     Laplace limit e < 0.6627, where the series converge.
3. ``hansen``        the same with exact Hansen coefficients (the science core's default).
4. ``second_order``  rung 3 with the equinox drift fed back into the phases and the
                     second-order mean rates (:mod:`ephem.second_order`).
5. ``numerical``     the rotation-averaged torque integrated along the Keplerian orbit
                     (:mod:`ephem.numerical`).
6. ``real_orbit``    the same along the real, perturbed orbit from DE421
                     (:mod:`ephem.ephemeris`), inside DE421's span (1899-2053).
7. the full rigid body (:mod:`ephem.rigid`): a reference for what rotation averaging
   leaves out, too costly to serve (thousands of rotations per orbit).

Every rung carries an error *estimate*: an upper bound, in radians, on the angle
between its pole and the truth over the requested epochs, as a sum of named terms:

* ``nutation_omitted`` (rung 1), ``truncation`` (rung 2): exact sums of the omitted
  coefficients;
* ``second_order`` (rungs 1-3): the equinox drift and the second-order mean rates,
  growing with the time T from the pole epoch;
* ``higher_order`` (rungs 1-4): what the second-order theory leaves (periodic terms
  of relative size K/n and a third-order drift), calibrated against rung 5;
* ``integration`` (rungs 5-6): the ODE tolerance;
* ``orbit_motion`` (rungs 1-5): the fixed Keplerian orbit against the real one
  (the orbit plane turns, the mean motion differs from the osculating one), from the
  measured drift rates in ``data/orbit_motion.toml``;
* ``rotation_averaging`` (all): what averaging over the rotation leaves out, against
  the full rigid body (the figure axis);
* ``ephemeris`` (rung 6): the real orbit's own error; ``rounding``: double precision;
* ``free_wobble`` (all, for the figure axis): the published free-wobble amplitude J0 the track
  leaves out, or ``free_wobble_model`` when the track includes the wobble (:mod:`ephem.free_motion`).

Two poles can be asked for. ``axis="figure"`` (the default) is the body's axis of largest inertia,
the pole a body-fixed frame shows: it circles the angular momentum by the free wobble (amplitude
J0: Earth 1", Mars 0.1", Eros 55", Lara 2014 Table 1), which every rung adds only when the
tolerance needs it and its phase is given (``Wobble``). ``axis="angular_momentum"`` is the axis the
forced theory describes (the analogue of the IAU's celestial intermediate pole, which leaves the
free wobble to polar motion); the free wobble does not move it.

The estimate is a promise about the pole direction against the truth over the requested
epochs; it does not include the catalogue's own uncertainties (a pole known to 0.1° is
still 0.1° uncertain). :meth:`Ladder.choose` takes the cheapest rung whose estimate meets
a tolerance, or refuses naming the best one.

The tests hold each estimate against the next rungs up for many bodies and spans.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from functools import cached_property, lru_cache

import numpy as np

from . import cost
from .budget import charge
from .catalogue import Body
from .cost import Cost
from .constants import ARCSEC, J2000_JD, JULIAN_CENTURY_DAYS, JULIAN_YEAR_DAYS, MAS
from .errors import InvalidInputError, NotApplicableError
from .hansen import LAPLACE_LIMIT, hansen_exact, hansen_series
from .kepler import mean_motion_rad_per_day
from .kinoshita import eccentricity_factor, nutation_coefficients, pole_displacement_sum, pole_displacements
from .model import (MAX_ORDER, MIN_SPIN_ORBIT_RATIO, PrecessionNutation, Track, cached_model, check_domain,
                    model_for)
from .free_motion import Wobble, add_free_wobble, free_wobble_bound, wobble_model_bound
from . import rotation_scale
from .physics_errors import (ephemeris_bound, orbit_motion_bound, real_orbit_unavailable, rotation_averaging_bound,
                             sun_path_for)
from .rigid import body_moments
from .second_order import SecondOrderTheory, second_order_theory
from .theory import Estimate, SpinAxisTheory, Spectrum, cheapest_within, rate_values, selection_info
from .uncertainty import input_sigmas, propagated, summary

RUNGS = ("secular", "series", "hansen", "second_order", "numerical", "real_orbit")
#: The poles a track can follow (see the module docstring).
AXES = ("figure", "angular_momentum")
#: Highest e-power order the ladder tries for rung 2 (a truncated series is cheaper than the
#: exact one only while it has fewer harmonics).
MAX_LADDER_ORDER = 20
#: Relative tolerance of the numerical rungs.
NUMERICAL_RTOL = 1e-12
#: The numerical rungs integrate through every orbit (~5 ms each); beyond this many orbits from the
#: pole epoch a request would tie up a worker for seconds, so they are not offered.
MAX_NUMERICAL_ORBITS = 1000
#: Rounding floor of any pole computed in double precision through a few rotations (radians, 0.2 µas).
ROUNDING = 1e-12


def _series_coefficients(model: PrecessionNutation, order: int | None, kmax: int):
    """The nutation coefficients (lon_sin, lon_cos, obl_sin, obl_cos) for k = 1..kmax at the model's ε̄, θ̄."""
    h = hansen_exact(model.eccentricity) if order is None else hansen_series(order).evaluate(model.eccentricity)
    out = np.zeros((4, kmax))
    m = min(kmax, len(h.k) - 1)
    k = np.arange(1, m + 1, dtype=float)
    out[:, :m] = nutation_coefficients(model.scaling_factor, model.mean_motion, model.obliquity,
                                       model.equinox_to_pericentre, k,
                                       *(np.asarray(x[1:m + 1]) for x in (h.c0, h.c2, h.s2)))
    return out


def truncation_bound(model: PrecessionNutation, order: int, span_days: float) -> float:
    """Pole error (radians) of the e^order series against the exact Hansen coefficients.

    Twice the sum of the coefficient differences (the track's error, plus the error it
    makes in the mean pole through the nutation removed at the pole epoch) and the
    difference of the precession rates over the span.
    """
    periodic, drift = _truncation_parts(model, order)
    return periodic + drift * span_days


def _truncation_parts(model: PrecessionNutation, order: int) -> tuple[float, float]:
    """(periodic bound, rate of the secular part) of :func:`truncation_bound`, radians and rad/day."""
    exact = model.nutation
    kmax = max(int(exact.multiple.max()) if exact.multiple.size else 0, order + 3)
    diff = _series_coefficients(model, order, kmax) - _series_coefficients(model, None, kmax)
    rate_diff = 0.5 * model.scaling_factor * abs(math.cos(model.obliquity)) * abs(
        eccentricity_factor(model.eccentricity, order) - eccentricity_factor(model.eccentricity))
    return 2.0 * pole_displacement_sum(diff.T, model.obliquity), abs(math.sin(model.obliquity)) * rate_diff


@lru_cache(maxsize=4096)
def _cached_truncation_parts(body: Body, order: int) -> tuple[float, float]:
    # independent of the epochs: computed once per body and order
    return _truncation_parts(cached_model(body), order)


def second_order_bound(model: PrecessionNutation, theory: SecondOrderTheory, span_days: float) -> float:
    """What the first-order theory leaves over ``span_days`` from the pole epoch (radians).

    The θ-dependent terms b, c of the nutation change phase at 2|ψ̇| per unit time, moving
    the pole by at most 2 sin ε (|cos ε| + 1) Σ(|b_k| + |c_k|) per radian of ψ; the
    second-order mean rates move it at most by their bound times T.
    """
    comp = theory.components
    phase_amp = float(np.sum(np.abs(comp.sin_coef[:, 1]) + np.abs(comp.cos_coef[:, 2])))
    se, ce = abs(math.sin(model.obliquity)), abs(math.cos(model.obliquity))
    rephase = 2.0 * se * (ce + 1.0) * phase_amp * abs(model.precession_rate) * span_days
    return rephase + theory.second_order_rate_bound() * span_days


def higher_order_bound(model: PrecessionNutation, theory: SecondOrderTheory, span_days: float) -> float:
    """What the second-order theory leaves (radians): periodic terms of relative size K/n
    (the second-order nutation, and the initial mean pole taken to first order) and a
    third-order drift, K/n times the second-order rates.

    The factors are set from the measured residuals against rung 5 (largest ratio seen:
    0.47 for the periodic term) with a margin of 4; the tests check them across bodies,
    spans, e up to 0.95 and a random sweep.
    """
    # the small parameter is the torque over the orbital rate; near pericentre both grow, the torque
    # faster, and its mean over the orbit carries f(e) = (1 - e²)^(-3/2) (needed at e = 0.9)
    ratio = model.scaling_factor / model.mean_motion * eccentricity_factor(model.eccentricity)
    amplitude = pole_displacement_sum(model.nutation, model.obliquity)
    return 2.0 * ratio * amplitude + 4.0 * ratio * theory.second_order_rate_bound() * span_days \
        + ratio * ratio * abs(model.precession_rate) * span_days * amplitude


def integration_bound(model: PrecessionNutation, span_days: float) -> float:
    """Error of the numerical rungs (radians) at rtol 1e-12.

    Measured against rtol 1e-14: the error per orbit is a few times rtol times the pole's motion
    per orbit, 2π (K/n)(1-e²)^(-3/2) (5e-16 for the Earth, 5e-15 for Itokawa, 1.2e-12 for a
    K/n = 5e-3 body on an e = 0.5 orbit); the bound allows 100 rtol per orbit on that motion
    plus 1e-3 rad, and a floor of 1e-12.
    """
    orbits = abs(span_days) * model.mean_motion / (2.0 * math.pi)
    motion = 2.0 * math.pi * model.scaling_factor / model.mean_motion * eccentricity_factor(model.eccentricity)
    return 1e-12 + orbits * 100.0 * NUMERICAL_RTOL * (motion + 1e-3)


def orbits_in_span(model: PrecessionNutation, t: np.ndarray) -> float:
    """Orbits the numerical rungs integrate through to reach the epochs from the pole epoch."""
    return _span(model, t) * model.mean_motion / (2.0 * math.pi)


# --- evaluating a rung ----------------------------------------------------------------------------

def secular_track(model: PrecessionNutation, jd_tdb) -> Track:
    """Rung 1: the mean pole precessing uniformly, no nutation."""
    t = np.asarray(jd_tdb, dtype=float)
    zero = np.zeros(t.shape)
    psi = model.precession_rate * (t - model.pole_epoch)
    return model.track_from_angles(t, psi, zero, zero, np.full(t.shape, model.obliquity))


def second_order_track(model: PrecessionNutation, theory: SecondOrderTheory, jd_tdb) -> Track:
    """Rung 4: ψ, ε from the second-order theory, in the frame of the orbit and mean equinox at t0."""
    t = np.asarray(jd_tdb, dtype=float)
    psi, dpsi, deps, eps = theory.angles(model.mean_anomaly(t), t)
    return model.track_from_angles(t, psi, dpsi, deps, eps)


def track_from_vectors(model: PrecessionNutation, theory: SecondOrderTheory, jd_tdb, pole_icrf) -> Track:
    """A :class:`Track` from ICRF pole vectors (the numerical rungs).

    ψ and ε are read off the pole in the frame of the orbit and mean equinox at t0; the
    nutation Δψ, Δε is what remains after the second-order theory's mean ψ̄, ε̄.
    """
    t = np.asarray(jd_tdb, dtype=float)
    s = pole_icrf @ model.icrf_from_orbit   # rows: orbit-frame vectors
    psi_bar, eps_bar = theory.mean_track(t)(t)
    raw = np.arctan2(s[:, 0], s[:, 1])
    psi = psi_bar + np.remainder(raw - psi_bar + math.pi, 2.0 * math.pi) - math.pi  # unwrap about ψ̄
    eps = np.arctan2(np.hypot(s[:, 0], s[:, 1]), s[:, 2])
    ra = np.arctan2(pole_icrf[:, 1], pole_icrf[:, 0])
    ra += (ra < 0.0) * (2.0 * math.pi)
    dec = np.arctan2(pole_icrf[:, 2], np.hypot(pole_icrf[:, 0], pole_icrf[:, 1]))
    return Track(t, psi, psi - psi_bar, eps - eps_bar, eps, ra, dec)


def pole_vectors(track: Track) -> np.ndarray:
    """ICRF unit vectors (N, 3) of a track's pole."""
    cd = np.cos(track.pole_dec)
    return np.stack([cd * np.cos(track.pole_ra), cd * np.sin(track.pole_ra), np.sin(track.pole_dec)], axis=-1)


# --- the ladder of one body -----------------------------------------------------------------------

@lru_cache(maxsize=512)
def cached_theory(body: Body) -> SecondOrderTheory:
    return second_order_theory(cached_model(body))


def _span(model: PrecessionNutation, t: np.ndarray) -> float:
    """Largest |t - t0| over the epochs (days): the theories' errors grow from the pole epoch."""
    if t.size == 0:
        return 0.0
    return float(max(abs(t.max() - model.pole_epoch), abs(t.min() - model.pole_epoch)))


def numerical_unavailable(model: PrecessionNutation, t: np.ndarray) -> str | None:
    orbits = orbits_in_span(model, t)
    if orbits <= MAX_NUMERICAL_ORBITS:
        return None
    return (f"the numerical rungs integrate through every orbit from the pole epoch and are limited to "
            f"{MAX_NUMERICAL_ORBITS} orbits per request; these epochs need {orbits:.0f}")


#: What to tell a user when the largest term of the best estimate is one no rung removes.
def with_free_wobble(model: PrecessionNutation, track: Track, figure_icrf: np.ndarray) -> Track:
    """The track of the figure axis: ``track`` (of the angular momentum) moved to the vectors ``figure_icrf``;
    the wobble's share of ψ and ε goes into Δψ and Δε."""
    s = figure_icrf @ model.icrf_from_orbit
    raw = np.arctan2(s[:, 0], s[:, 1])
    psi = track.psi + np.remainder(raw - track.psi + math.pi, 2.0 * math.pi) - math.pi
    eps = np.arctan2(np.hypot(s[:, 0], s[:, 1]), s[:, 2])
    ra = np.arctan2(figure_icrf[:, 1], figure_icrf[:, 0])
    ra += (ra < 0.0) * (2.0 * math.pi)
    dec = np.arctan2(figure_icrf[:, 2], np.hypot(figure_icrf[:, 0], figure_icrf[:, 1]))
    return Track(track.jd_tdb, psi, track.delta_psi + (psi - track.psi), track.delta_epsilon + (eps - track.obliquity),
                 eps, ra, dec)


@dataclass(frozen=True)
class Ladder:
    """The rungs for one body: estimates, choice by tolerance, and evaluation.

    ``axis`` is the pole followed ("figure" or "angular_momentum"); ``wobble``, for the figure axis, the
    free wobble a track may add when the tolerance needs it (its amplitude and phase)."""

    body: Body
    axis: str = "figure"
    wobble: Wobble | None = None
    #: the A axis's angle (radians) from the orbit's ascending node on the equator at the pole epoch
    #: (:mod:`ephem.rotation_scale`); None: unknown, the semi-diurnal terms stay an error term
    rotation_phase: float | None = None

    def __post_init__(self):
        if self.axis not in AXES:
            raise InvalidInputError("axis", f"must be one of {', '.join(AXES)}, got {self.axis!r}", self.body.name)
        if self.wobble is not None and self.axis != "figure":
            raise InvalidInputError("free_wobble_phase_deg", "the free wobble moves the figure axis, not the "
                                    "angular momentum: ask for axis=figure", self.body.name)

    @property
    def model(self) -> PrecessionNutation:
        return cached_model(self.body)

    @property
    def theory(self) -> SecondOrderTheory:
        return cached_theory(self.body)

    @property
    def rotation_modelled(self) -> str:
        """What of the rotation-scale terms a track that adds them includes (:data:`ephem.rotation_scale.MODELLED`)."""
        return "oppolzer" if self.rotation_phase is None else "all"

    def physics_terms(self, jd_tdb: np.ndarray, modelled: str = "none") -> dict:
        """Error terms every fixed-orbit rung shares: the orbit's motion and rotation averaging, with ``modelled``
        of the rotation-scale terms in the track (the real-orbit rung drops the first). A user's body has no
        measured orbit motion."""
        terms = {"rotation_averaging": rotation_averaging_bound(self.body, self.model, _span(self.model, jd_tdb),
                                                                self.axis, modelled)}
        orbit = orbit_motion_bound(self.body, self.model, jd_tdb)
        if orbit is not None:
            terms["orbit_motion"] = orbit
        return terms

    @staticmethod
    def _estimate(rung: str, order: int | None, terms: dict, physics: dict, rotation_scale: str | None = None
                  ) -> Estimate:
        shared = {k: v for k, v in physics.items() if not (rung == "real_orbit" and k == "orbit_motion")}
        missing = () if rung == "real_orbit" or "orbit_motion" in physics else ("orbit_motion",)
        return Estimate(rung, order, {**terms, **shared, "rounding": ROUNDING}, unestimated=missing,
                        rotation_scale=rotation_scale)

    def _with_rotation_scale(self, estimates: list[Estimate], t: np.ndarray) -> list[Estimate]:
        """Each available rung followed by the same rung with the rotation-scale terms added (a little dearer,
        and its ``rotation_averaging`` term is what they leave)."""
        if self.model.hd == 0.0:
            return estimates
        modelled = self.rotation_modelled
        averaging = self.physics_terms(t, modelled)["rotation_averaging"]
        out = []
        for e in estimates:
            out.append(e)
            if e.available and "rotation_averaging" in e.terms:
                out.append(Estimate(e.rung, e.order, {**e.terms, "rotation_averaging": averaging},
                                    unestimated=e.unestimated, rotation_scale=modelled))
        return out

    def estimates(self, jd_tdb) -> list[Estimate]:
        """Every rung's estimate for these epochs, cheapest first (rung 2 once per order)."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        m, th = self.model, self.theory
        T = _span(m, t)
        physics = self.physics_terms(t)
        higher = higher_order_bound(m, th, T)
        second = second_order_bound(m, th, T) + higher
        out = [self._estimate("secular", None, {"nutation_omitted": pole_displacement_sum(m.nutation, m.obliquity),
                                                "second_order": second}, physics)]
        kmax = int(m.nutation.multiple.max()) if m.nutation.multiple.size else 0
        if m.eccentricity < LAPLACE_LIMIT:
            for order in range(0, min(MAX_LADDER_ORDER, kmax)):
                periodic, drift = _cached_truncation_parts(self.body, order)
                out.append(self._estimate("series", order, {"truncation": periodic + drift * T,
                                                             "second_order": second}, physics))
        else:
            out.append(Estimate("series", None, {}, available=False, why_not=(
                f"e = {m.eccentricity:.4g} exceeds the Laplace limit {LAPLACE_LIMIT:.4f}: the e-power series "
                "of the Hansen coefficients diverge")))
        out.append(self._estimate("hansen", None, {"second_order": second}, physics))
        out.append(self._estimate("second_order", None, {"higher_order": higher}, physics))
        too_long = numerical_unavailable(m, t)
        if too_long is None:
            out.append(self._estimate("numerical", None, {"integration": integration_bound(m, T)}, physics))
        else:
            out.append(Estimate("numerical", None, {}, available=False, why_not=too_long))
        why = too_long or real_orbit_unavailable(self.body, t)
        if why is None:
            out.append(self._estimate("real_orbit", None, {"integration": integration_bound(m, T),
                                                           "ephemeris": ephemeris_bound(self.body, m, T)}, physics))
        else:
            out.append(Estimate("real_orbit", None, {}, available=False, why_not=why))
        out = self._with_rotation_scale(out, t)
        return self._wobble_estimates(out, t) if self.axis == "figure" else out

    def _wobble_estimates(self, estimates: list[Estimate], t: np.ndarray) -> list[Estimate]:
        """For the figure axis: each rung leaves out the free wobble (its amplitude, a term) and, when the
        wobble's phase is given, follows it at the cost of the wobble model's error (a second estimate)."""
        left_out = free_wobble_bound(self.body) if self.wobble is None else self.wobble.J_arcsec * ARCSEC
        modelled = None
        if self.wobble is not None:
            modelled = wobble_model_bound(self.body, self.wobble, t, pole_vectors(self.model.track(t)),
                                          self._pole_at_wobble_epoch()) + ROUNDING
        # a modelled wobble takes the catalogue pole as L (ephem.free_motion): the figure axis then carries the
        # whole Oppolzer offset
        averaging = None if modelled is None else rotation_averaging_bound(
            self.body, self.model, _span(self.model, t), self.axis, "none", pole="momentum")
        out = []
        for e in estimates:
            if not e.available:
                out.append(e)
                continue
            if left_out is None:
                out.append(Estimate(e.rung, e.order, e.terms, unestimated=e.unestimated + ("free_wobble",),
                                    rotation_scale=e.rotation_scale))
            else:
                out.append(Estimate(e.rung, e.order, {**e.terms, "free_wobble": left_out}, unestimated=e.unestimated,
                                    rotation_scale=e.rotation_scale))
            if modelled is not None and e.rotation_scale is None:    # the two are not combined
                terms = {**e.terms, "free_wobble_model": modelled}
                if "rotation_averaging" in terms:
                    terms["rotation_averaging"] = averaging
                out.append(Estimate(e.rung, e.order, terms, unestimated=e.unestimated, free_wobble=True))
        return out

    def cost(self, rung: str | None, start: float, stop: float, count: int, order: int | None = None,
             free_wobble: bool = False, rotation_scale: bool = False) -> Cost:
        """What a track of ``count`` epochs from ``start`` to ``stop`` (JD TDB) will cost (:mod:`ephem.cost`),
        from the body's parameters alone, before anything is built. ``rung`` None: the estimates that
        choose a rung by tolerance (the chosen rung's own cost is charged once it is known)."""
        b = self.body
        check_domain(b)                       # not applicable: refused before any cost
        e = b.orbit.e
        n = mean_motion_rad_per_day(b.orbit.a_au, b.orbit.center)
        span = max(abs(stop - b.pole.epoch_jd_tdb), abs(start - b.pole.epoch_jd_tdb))
        orbits = span * n / (2.0 * math.pi)
        k = cost.body_harmonics(b)
        build = cost.hansen_build(e, None)
        if rung is None:
            parts = [build, cost.half_peak_to_peak(e, None, k),     # the second-order theory's components
                     cost.harmonic_sum(count, min(k, MAX_LADDER_ORDER + 2), "step_days", "the truncation bounds")]
            if free_wobble:
                parts.append(cost.free_rotation("exact", count, 0.0))
            return Cost(tuple(parts))
        if rung == "secular":
            parts = [build, cost.harmonic_sum(count, 0, "step_days", "the secular track")]
        elif rung == "series":
            parts = [build, cost.hansen_build(e, order), cost.harmonic_sum(count, order + 2, "step_days", "the track")]
        elif rung == "hansen":
            parts = [build, cost.harmonic_sum(count, k, "step_days", "the track")]
        elif rung == "second_order":
            parts = [build, cost.second_order(count, k)]
        else:   # numerical, real_orbit: the second-order mean track is subtracted from the integrated pole
            parts = [build, cost.second_order(count, k), cost.spin_integration(orbits, e, count)]
            if rung == "real_orbit":   # integrated from the elements' epoch through the pole's and the track's
                epochs_jd = (start, stop, b.pole.epoch_jd_tdb, b.orbit.epoch_jd_tdb)
                parts.append(cost.orbit_integration(max(epochs_jd) - min(epochs_jd)))
        if free_wobble:
            parts.append(cost.free_rotation("exact", count, 0.0))
        if rotation_scale:   # the rung again from the mean pole, and the closed-form terms at every epoch
            parts += [build, cost.harmonic_sum(count, 8, "step_days", "the rotation-scale terms")]
        return Cost(tuple(parts))

    def choose(self, jd_tdb, tolerance: float) -> Estimate:
        """The cheapest rung whose estimated error over the epochs is within ``tolerance`` (radians).

        Raises :class:`NotApplicableError` when none is, naming the best estimate available.
        """
        if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or not math.isfinite(tolerance) \
                or tolerance <= 0.0:
            raise InvalidInputError("tolerance_mas", f"must be a positive finite number, got {tolerance!r}",
                                    self.body.name)
        return cheapest_within([e for e in self.estimates(jd_tdb) if e.available], tolerance, self.body.name,
                               self.wobble is not None)

    def track(self, rung: str, jd_tdb, order: int | None = None, free_wobble: bool = False,
              rotation_scale: bool = False) -> Track:
        """The pole track of one rung at the epochs (JD TDB); with ``rotation_scale``, with the rotation-scale
        terms added (:meth:`rotation_scale_track`); with ``free_wobble``, the figure axis with the ladder's
        wobble added."""
        t = np.asarray(jd_tdb, dtype=float)
        track = self.rotation_scale_track(rung, t, order) if rotation_scale else self._rung_track(rung, t, order)
        return self.add_wobble(track) if free_wobble else track

    def mean_pole_body(self) -> Body:
        """The body with its pole moved from the figure axis at the pole epoch (the catalogue's pole) to the mean
        angular momentum L̄ there: less the Oppolzer offset, and the semi-diurnal term when the phase is known."""
        m = self.model
        s0 = m.catalogue_pole_orbit[None]
        terms = rotation_scale.rotation_terms(self._moments, m.spin_rate, s0, rotation_scale.SunGeometry.at(
            m, [m.pole_epoch]), None if self.rotation_phase is None else np.array([self.rotation_phase]))
        mean = m.icrf_from_orbit @ rotation_scale.apply(s0, -terms.figure_offset())[0]
        ra = math.degrees(math.atan2(mean[1], mean[0])) % 360.0
        dec = math.degrees(math.atan2(mean[2], math.hypot(mean[0], mean[1])))
        return replace(self.body, pole=replace(self.body.pole, ra_deg=ra, dec_deg=dec))

    @property
    def _moments(self) -> tuple[float, float, float]:
        return body_moments(self.body, self.model)

    def rotation_scale_track(self, rung: str, jd_tdb, order: int | None = None) -> Track:
        """A rung's track with the rotation-scale terms of :mod:`ephem.rotation_scale`: the rung run from the mean
        pole (:meth:`mean_pole_body`), then moved by the figure axis's offset (or, for the angular momentum, by
        its semi-diurnal term) at every epoch."""
        t = np.asarray(jd_tdb, dtype=float)
        mean = Ladder(self.mean_pole_body(), "angular_momentum")._rung_track(rung, t, order)
        m = self.model
        pole = pole_vectors(mean) @ m.icrf_from_orbit
        phase = None
        if self.rotation_phase is not None:
            psi = np.arctan2(pole[:, 0], pole[:, 1])
            phase = rotation_scale.rotation_phase(m, t, self.rotation_phase, psi + np.round(
                (mean.psi - psi) / (2.0 * math.pi)) * 2.0 * math.pi)
        terms = rotation_scale.rotation_terms(self._moments, m.spin_rate, pole, rotation_scale.SunGeometry.at(m, t),
                                              phase)
        offset = terms.figure_offset() if self.axis == "figure" else terms.momentum_offset()
        return with_free_wobble(m, mean, rotation_scale.apply(pole, offset) @ m.icrf_from_orbit.T)

    def add_wobble(self, track: Track) -> Track:
        """A rung's track with the free wobble of the figure axis added (needs the ladder's ``wobble``)."""
        if self.wobble is None:
            raise InvalidInputError("free_wobble_phase_deg", "adding the free wobble needs its phase",
                                    self.body.name)
        figure = add_free_wobble(self.body, self.wobble, track.jd_tdb, pole_vectors(track),
                                 self._pole_at_wobble_epoch())
        return with_free_wobble(self.model, track, figure)

    def _pole_at_wobble_epoch(self) -> np.ndarray:
        # where the phase is counted; it sets only the north/east directions there, so rung 3 serves
        return pole_vectors(self.model.track([self.wobble.epoch_jd_tdb]))[0]

    def _rung_track(self, rung: str, t: np.ndarray, order: int | None) -> Track:
        from .numerical import integrate_spin_axis  # scipy.integrate: 0.35 s to import, only for these rungs

        m = self.model
        if rung == "secular":
            return secular_track(m, t)
        if rung == "series":
            return cached_model(self.body, order).track(t)
        if rung == "hansen":
            return m.track(t)
        if rung == "second_order":
            return second_order_track(m, self.theory, t)
        if rung in ("numerical", "real_orbit"):
            why = numerical_unavailable(m, t)
            if why is not None:
                raise NotApplicableError(self.body.name, why)
        if rung == "numerical":
            return track_from_vectors(m, self.theory, t, integrate_spin_axis(m, t, rtol=NUMERICAL_RTOL))
        if rung == "real_orbit":
            why = real_orbit_unavailable(self.body, t)
            if why is not None:
                raise NotApplicableError(self.body.name, why)
            path = sun_path_for(self.body, t)
            return track_from_vectors(m, self.theory, t, integrate_spin_axis(
                m, t, rtol=NUMERICAL_RTOL, sun=path.position_scalar))
        raise InvalidInputError("model", f"unknown rung {rung!r}; one of {', '.join(RUNGS)}", self.body.name)


# --- the ladder as a theory of the spin axis (ephem.theory) -------------------------------------------

#: Obliquity within this many degrees of 90: ψ̇ ∝ cos ε is small and poorly determined.
NEAR_RIGHT_ANGLE_DEG = 2.0
THEORY = ("Kinoshita (1977) forced precession-nutation in the solar torque, as in Petit, Souchay & Lhotka (2014), "
          "on the fidelity ladder of ephem.ladder")
#: What every rung assumes, and what each drops besides (see :mod:`ephem.ladder`).
ASSUMPTIONS = [
    "rigid body; figure, rotation and angular-momentum axes coincide (free wobble J = 0)",
    "torque averaged over the rotation; triaxial P22 term of the potential dropped",
    "single perturber: the orbit's centre",
]
RUNG_ASSUMPTIONS = {
    "secular": ["no nutation", "fixed Keplerian orbit (osculating elements at their epoch)"],
    "series": ["first order in the torque", "Hansen coefficients truncated at a power of e",
               "fixed Keplerian orbit (osculating elements at their epoch)"],
    "hansen": ["first order in the torque: the equinox drift is not fed back into the nutation phases",
               "fixed Keplerian orbit (osculating elements at their epoch)"],
    "second_order": ["second order in the torque", "fixed Keplerian orbit (osculating elements at their epoch)"],
    "numerical": ["fixed Keplerian orbit (osculating elements at their epoch)"],
    "real_orbit": ["orbit from DE421 (planets) or integrated under the DE421 planets (asteroids)"],
}
#: What each rung of the fidelity ladder drops (see :mod:`ephem.ladder`).
RUNG_DESCRIPTIONS = {
    "secular": "precession only: no nutation",
    "series": "Kinoshita-Cayley nutation, Hansen coefficients as e-power series truncated at e^order",
    "hansen": "Kinoshita-Cayley nutation with exact Hansen coefficients (first order in the torque)",
    "second_order": "second order in the torque: the equinox drift re-phases the nutation, plus the "
                    "second-order mean rates",
    "numerical": "rotation-averaged torque integrated numerically along the fixed Keplerian orbit",
    "real_orbit": "rotation-averaged torque integrated along the real orbit (DE421 and planetary perturbations)",
}

AXIS_ASSUMPTIONS = {
    "angular_momentum": "the pole served is the angular momentum, which the free wobble does not move",
    "figure": "the pole served is the figure axis, taken as the angular momentum: the free wobble is left "
              "out and counted in the estimate (free_wobble)",
    "figure+wobble": "the pole served is the figure axis: the torque-free rigid-body wobble (given J and phase) "
                     "added about the forced angular momentum",
}


def model_info(m: PrecessionNutation, b: Body) -> dict:
    warnings = []
    if abs(math.degrees(m.obliquity) - 90.0) < NEAR_RIGHT_ANGLE_DEG:
        warnings.append("obliquity within 2 deg of 90: the precession rate (∝ cos ε) is small and "
                        "dominated by the obliquity's uncertainty")
    if b.hd_from == "dynamical_ellipticity" and b.hd_from_moments is not None \
            and abs(b.hd - b.hd_from_moments) > 1e-4 * b.hd:
        given = b.values.get("inertia.dynamical_ellipticity")
        why = "see data/errata.toml" if given is None or given.source.startswith("petit2014") \
            else f"source {given.source}: {given.note}" if given.note else f"source {given.source}"
        warnings.append(f"dynamical ellipticity {b.hd:.6g} given explicitly; the catalogue moments imply "
                        f"{b.hd_from_moments:.6g} ({why})")
    return {
        "theory": THEORY,
        "eccentricity_order": "exact" if m.order is None else m.order,
        "assumptions": ASSUMPTIONS + RUNG_ASSUMPTIONS["hansen" if m.order is None else "series"],
        "warnings": warnings,
        "spin_orbit_ratio": m.spin_orbit_ratio,
        "min_spin_orbit_ratio": MIN_SPIN_ORBIT_RATIO,
        "pole_epoch_jd_tdb": m.pole_epoch,
        "orbit_epoch_jd_tdb": m.orbit_epoch,
    }



class SunLadder(SpinAxisTheory):
    """The single-perturber ladder (:class:`Ladder`) behind the common interface: a body torqued by the
    centre of its orbit alone, its rungs cheapest first."""

    summary = "the single-perturber ladder (a body torqued by the centre of its orbit)"
    models = RUNGS
    descriptions = RUNG_DESCRIPTIONS
    propagates_uncertainty = True
    models_rotation_scale = True

    @classmethod
    def serves(cls, body: Body, perturbers: tuple[str, ...]) -> bool:
        return tuple(perturbers) == (body.orbit.center,)

    @cached_property
    def ladder(self) -> Ladder:
        return Ladder(self.body, self.axis, self.wobble, self.rotation_phase)   # one per request

    @classmethod
    def how_to_reach(cls, body: Body) -> str:
        return f"pass perturbers={body.orbit.center.lower()} for it (the centre of {body.name}'s orbit alone)"

    def default_model(self, order: int | None) -> str:
        return "hansen" if order is None else "series"

    def check_request(self, model: str | None, order: int | None) -> None:
        rung = model or self.default_model(order)
        if rung == "series" and order is None:
            raise InvalidInputError("order", "the 'series' model needs an e-order")
        if order is not None and rung != "series":
            raise InvalidInputError("order", f"an e-order applies to the 'series' model, not to {rung!r}")
        if order is not None and self.body.orbit.e > LAPLACE_LIMIT:
            model_for(self.body, self.body.dataset, order)     # refuses the diverging series, before any cost

    def choice_cost(self, start: float, stop: float, count: int) -> Cost:
        return self.ladder.cost(None, start, stop, count, free_wobble=self.wobble is not None)

    def track_cost(self, model, order, start, stop, count, free_wobble, rotation_scale=False) -> Cost:
        return self.ladder.cost(model or self.default_model(order), start, stop, count, order, free_wobble,
                                rotation_scale)

    def estimates(self, jd_tdb) -> list[Estimate]:
        return self.ladder.estimates(jd_tdb)

    def named(self, jd_tdb, model, order):
        rung = model or self.default_model(order)
        # a named rung adds the rotation-scale terms when the request gave the rotation phase
        scale = None if self.rotation_phase is None else self.ladder.rotation_modelled
        return next((e for e in self.estimates(jd_tdb) if e.rung == rung and e.order == order
                     and e.free_wobble == (self.wobble is not None) and e.rotation_scale == scale), None)

    def track(self, est, model, order, t0, step, count) -> Track:
        scale = est.rotation_scale is not None if est is not None else self.rotation_phase is not None
        if model in ("hansen", "series") and not scale:   # the fast evaluation on an even grid
            tr = cached_model(self.body, order).track_grid(t0, step, count)
        else:
            tr = self.ladder.track(model, self.grid(t0, step, count), order, rotation_scale=scale)
        if self.wobble is not None and (est is None or est.free_wobble):
            tr = self.ladder.add_wobble(tr)
        return tr

    def track_at(self, model, order, jd_tdb, free_wobble=False) -> Track:
        return self.ladder.track(model or self.default_model(order), jd_tdb, order, free_wobble,
                                 rotation_scale=self.rotation_phase is not None)

    def describe(self, est, model, order, with_wobble) -> dict:
        info = model_info(cached_model(self.body, order), self.body)
        info["assumptions"] = [AXIS_ASSUMPTIONS["figure+wobble" if with_wobble else self.axis]] + ASSUMPTIONS[1:] \
            + RUNG_ASSUMPTIONS[model]
        return info

    def spectrum(self, aim_mas: float, mid_centuries: float, jd_tdb=None, psi=None) -> Spectrum:
        m = cached_model(self.body)
        if jd_tdb is None:
            return mean_anomaly_spectrum(m, aim_mas, m.precession_rate)
        # ψ̇ as the track has it (the rungs above 'hansen' change the mean rates): ψ = a + ψ̇ t + nutation
        t = np.asarray(jd_tdb, dtype=float)
        mt = m.mean_anomaly(t)
        cols = [np.ones_like(t), t - 0.5 * (t[0] + t[-1])]
        for k in np.unique(m.nutation.multiple):
            cols += [np.sin(k * mt), np.cos(k * mt)]
        psi_dot = float(np.linalg.lstsq(np.array(cols).T, np.asarray(psi, dtype=float), rcond=None)[0][1])
        return mean_anomaly_spectrum(m, aim_mas, psi_dot)

    # --- the precession and nutation answers

    def answer_cost(self, order: int | None, nutation: bool = False, tolerance: bool = False) -> Cost:
        """The Hansen coefficients, the nutation's extremes, and the propagation of the inputs' σ (each input
        with a σ re-evaluates the model twice); ``tolerance``: the truncation bounds of the e-orders."""
        b = self.body
        check_domain(b, order)                   # not applicable (the Moon, e -> 1): refused before any cost
        e = b.orbit.e
        if order is not None and e > LAPLACE_LIMIT:
            return cost.FREE      # refused by model_for before any work
        build = cost.hansen_build(e, None)
        parts = [build] if order is None else [build, cost.hansen_build(e, order)]
        if nutation:
            parts.append(cost.half_peak_to_peak(e, order, cost.body_harmonics(b, order)))
        if tolerance:
            parts.append(cost.truncation_bounds(e))
        with_sigma = sum(1 for v in input_sigmas(b).values() if v is not None)
        if with_sigma:
            half = cost.half_peak_to_peak(e, order, cost.body_harmonics(b, order))
            parts.append(cost.Part("the catalogue's uncertainties", f"propagating {with_sigma} input uncertainties",
                                   2 * with_sigma * parts[1 if order is not None else 0].cpu_s + 2 * half.cpu_s,
                                   build.memory_mb))
        return Cost(tuple(parts))

    def order_for_tolerance(self, tolerance: float | None, order: int | None) -> int | None:
        """The lowest e-order whose truncation error is within the tolerance (None: exact coefficients); for
        the rate and the nutation terms (no time span): the truncation bound alone."""
        if tolerance is None:
            return order
        if order is not None:
            raise InvalidInputError("order", "give either order or tolerance_mas, not both")
        m = cached_model(self.body)
        if m.eccentricity < LAPLACE_LIMIT:
            kmax = int(m.nutation.multiple.max()) if m.nutation.multiple.size else 0
            for n in range(0, min(kmax, MAX_ORDER)):
                if truncation_bound(m, n, 0.0) <= tolerance:
                    return n
        return None

    def _selection(self, order: int | None, tol: float | None, start: float) -> dict:
        estimate = None if order is None else truncation_bound(cached_model(self.body), order, 0.0)
        return selection_info(self, "hansen" if order is None else "series", order, estimate or 0.0,
                              1e3 * (time.perf_counter() - start), tol)

    def precession_answer(self, order: int | None, tolerance: float | None, start: float) -> dict:
        b = self.body
        charge(self.answer_cost(order, tolerance=tolerance is not None), b.name)
        order = self.order_for_tolerance(tolerance, order)
        m = model_for(b, b.dataset, order)
        unc = propagated(b, order)
        ans = rate_values(b, m, unc)
        ans["uncertainty"] = summary(unc)
        ans["model"] = model_info(m, b)
        ans["model"].update(self._selection(order, tolerance, start))
        return ans

    def nutation_answer(self, order: int | None, tolerance: float | None, cut_mas, start: float) -> dict:
        b = self.body
        if cut_mas is not None:
            raise InvalidInputError("cut_mas", "an amplitude cut applies to the lunisolar series (the Earth with the "
                                    "Moon); this series is truncated by e-order (order, tolerance_mas)", b.name)
        charge(self.answer_cost(order, nutation=True, tolerance=tolerance is not None), b.name)
        order = self.order_for_tolerance(tolerance, order)
        m = model_for(b, b.dataset, order)
        s = m.nutation
        terms = [{
            "multiple": int(k), "period_days": float(p), "period_years": float(p / JULIAN_YEAR_DAYS),
            "longitude_sin_arcsec": float(a / ARCSEC), "longitude_cos_arcsec": float(c / ARCSEC),
            "obliquity_sin_arcsec": float(d / ARCSEC), "obliquity_cos_arcsec": float(f / ARCSEC),
        } for k, p, a, c, d, f in zip(s.multiple, s.period_days, s.lon_sin, s.lon_cos, s.obl_sin, s.obl_cos)]
        unc = propagated(b, order)
        sin_eps = abs(math.sin(m.obliquity))
        for term, sigma in zip(terms, unc["terms"]):
            if sigma["multiple"] != term["multiple"]:  # pragma: no cover - both come from the same series
                raise RuntimeError("uncertainty terms out of step with the nutation terms")
            term["period_days_uncertainty"] = sigma["period_days_uncertainty"]
            for comp in ("longitude", "obliquity"):
                for part in ("sin", "cos"):
                    term[f"{comp}_{part}_arcsec_uncertainty"] = sigma[f"{comp}_{part}_arcsec_uncertainty"]
                # the paper's Amp: (Sin² + Cos²)^½, times sin ε in longitude
                amp = math.hypot(term[f"{comp}_sin_arcsec"], term[f"{comp}_cos_arcsec"])
                term[f"{comp}_amplitude_arcsec"] = amp * (sin_eps if comp == "longitude" else 1.0)
                term[f"{comp}_amplitude_arcsec_uncertainty"] = sigma[f"amplitude_{comp}_arcsec_uncertainty"]
        half_psi, half_eps = semi_amplitudes(b, m.order)
        ans = {
            "body": b.name, "dataset": b.dataset, "argument": "mean anomaly M",
            "mean_anomaly_at_epoch_deg": math.degrees(m.mean_anomaly_at_epoch) % 360.0,
            "orbit_epoch_jd_tdb": m.orbit_epoch,
            "mean_motion_deg_per_day": math.degrees(m.mean_motion),
            "obliquity_deg": math.degrees(m.obliquity),
            "terms": terms,
            "delta_psi_half_peak_to_peak_arcsec": half_psi / ARCSEC,
            "delta_epsilon_half_peak_to_peak_arcsec": half_eps / ARCSEC,
            "delta_psi_half_peak_to_peak_arcsec_uncertainty": unc["delta_psi_half_peak_to_peak_arcsec_uncertainty"],
            "delta_epsilon_half_peak_to_peak_arcsec_uncertainty":
                unc["delta_epsilon_half_peak_to_peak_arcsec_uncertainty"],
            "uncertainty": summary(unc),
            "model": model_info(m, b),
        }
        ans["model"].update(self._selection(order, tolerance, start))
        return ans


#: Sidebands ±j ψ̇ a track carries about each harmonic of the mean anomaly (the second-order theory's mixing
#: of the precession into the nutation phases, and the kernel's linear-in-T phases).
TRACK_SIDEBANDS = 3
#: Highest multiple of the mean anomaly in a track's spectrum: beyond the last harmonic of the nutation
#: series that moves the pole by a hundredth of the aim, by HARMONIC_MARGIN (its products with others),
#: at most twice the series' own and MAX_MULTIPLE.
MAX_MULTIPLE = 64
HARMONIC_MARGIN = 4


def mean_anomaly_spectrum(m: PrecessionNutation, aim_mas: float, psi_dot: float) -> Spectrum:
    """Harmonics k = 0..kmax of the mean anomaly (k = 0: the precession alone), with ψ̇ (rad/day)."""
    series = m.nutation
    kmax_series = int(series.multiple.max()) if series.multiple.size else 1
    amp = pole_displacements(series, m.obliquity)
    big = series.multiple[amp > 0.01 * aim_mas * MAS]
    kmax = int(min(MAX_MULTIPLE, 2 * kmax_series, (int(big.max()) if big.size else 1) + HARMONIC_MARGIN))
    ks = np.arange(0, kmax + 1)
    amplitude = np.zeros(ks.size)
    for k, a in zip(series.multiple, amp):
        if k <= kmax:
            amplitude[int(k)] = a
    m_j2000 = float(m.mean_anomaly(J2000_JD))
    return Spectrum(tuple(int(k) for k in ks), np.degrees(ks * m_j2000) % 360.0,
                    np.degrees(ks * m.mean_motion) * JULIAN_CENTURY_DAYS, amplitude,
                    math.degrees(psi_dot * (J2000_JD - m.pole_epoch)) % 360.0,
                    math.degrees(psi_dot) * JULIAN_CENTURY_DAYS, TRACK_SIDEBANDS, "k: multiple of the mean anomaly")


@lru_cache(maxsize=512)
def semi_amplitudes(body: Body, order: int | None) -> tuple[float, float]:
    """Half the peak-to-peak Δψ, Δε (radians) of the body's nutation series (Petit et al. Table 4)."""
    return cached_model(body, order).nutation.semi_peak_to_peak()
