"""The rungs of the single-perturber ladder, one record each, cheapest first.

A :class:`Rung` holds its name, what it computes and drops, what it assumes, its price, its track and its error
terms. :data:`RUNGS` lists them cheapest first; adding a rung is adding one record there (and its functions here).
With them, the numerical rungs' integration error and reach (the orbits from the pole epoch they may integrate
through).

Rungs, cheapest first (names as reported in a track's ``model.name``):

1. ``secular``       ψ = ψ̇ (t - t0), ε = ε̄0: precession only.
2. ``series``        Kinoshita-Cayley nutation with the Hansen coefficients as e-power series truncated at e^N.
3. ``hansen``        the same with exact Hansen coefficients (the science core's default).
4. ``second_order``  rung 3 with the equinox drift fed back into the phases and the second-order mean rates, and
                     the geodesic precession's periodic part.
5. ``nonrigid``      rung 4 with the body's liquid core: each circular nutation component times the transfer
                     function of its interior model (:mod:`ephem.forced.interior_response`; Mars).
6. ``numerical``     the rotation-averaged torque integrated along the Keplerian orbit.
7. ``real_orbit``    the same along the real, perturbed orbit from DE421, inside DE421's span (1899-2053).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..base.constants import ROUNDING
from ..base.errors import InvalidInputError, NotApplicableError
from ..bodies.catalogue import Body
from ..forced import interior_response
from ..forced.integration import integrate_spin_axis
from ..forced.kinoshita import eccentricity_factor
from ..forced.precession_nutation import PrecessionNutation, Track, cached_model
from ..forced.second_order import SecondOrderTheory
from ..orbit.de421 import DE421_BODIES, de421_span, path_kept, sun_path, tdb_date
from ..orbit.hansen import LAPLACE_LIMIT
from ..orbit.relativity import geodesic_angle
from ..theory import cost
from ..theory.results import Estimate


#: Relative tolerance of the numerical rungs.
NUMERICAL_RTOL = 1e-12


# --- the numerical rungs' error and reach ----------------------------------------------------------

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
    return epoch_span(model, t) * model.mean_motion / (2.0 * math.pi)




def epoch_span(model: PrecessionNutation, t: np.ndarray) -> float:
    """Largest |t - t0| over the epochs (days): the theories' errors grow from the pole epoch."""
    if t.size == 0:
        return 0.0
    return float(max(abs(t.max() - model.pole_epoch), abs(t.min() - model.pole_epoch)))


def numerical_unavailable(model: PrecessionNutation, t: np.ndarray) -> str | None:
    orbits = orbits_in_span(model, t)
    if orbits <= cost.MAX_NUMERICAL_ORBITS:
        return None
    return (f"the numerical rungs integrate through every orbit from the pole epoch and are limited to "
            f"{cost.MAX_NUMERICAL_ORBITS} orbits per request; these epochs need {orbits:.0f}")


# --- evaluating a rung ----------------------------------------------------------------------------

def secular_track(model: PrecessionNutation, jd_tdb) -> Track:
    """Rung 1: the mean pole precessing uniformly, no nutation."""
    t = np.asarray(jd_tdb, dtype=float)
    zero = np.zeros(t.shape)
    psi = model.track_rate * (t - model.pole_epoch)
    return model.track_from_angles(t, psi, zero, zero, np.full(t.shape, model.obliquity))


def second_order_track(model: PrecessionNutation, theory: SecondOrderTheory, jd_tdb) -> Track:
    """Rung 4: ψ, ε from the second-order theory, in the frame of the orbit and mean equinox at t0."""
    t = np.asarray(jd_tdb, dtype=float)
    m = model.mean_anomaly(t)
    psi, dpsi, deps, eps = theory.angles(m, t)
    # the torque's solution turned about the orbit normal by the instantaneous geodesic precession (the mean rate
    # and its periodic part, ephem.sun.geodesic)
    turned = geodesic_angle(model.geodesic_rate, model.mean_motion, model.eccentricity, m,
                            float(model.mean_anomaly(model.pole_epoch)))
    return model.track_from_angles(t, psi - turned, dpsi, deps, eps)


def nonrigid_track(ladder, model: PrecessionNutation, theory: SecondOrderTheory, jd_tdb) -> Track:
    """Rung 5: rung 4 with the fluid core's change to every nutation term (:mod:`ephem.forced.interior_response`),
    counted from the pole epoch so that the track still starts at the catalogue pole. The change keeps the
    first-order phases: the equinox drift re-phases it by ψ̇ (t − t0) (Mars: 1e-3 rad in 30 years, 0.04 mas of
    its 36 mas), inside the rung's estimate."""
    why = interior_response.not_applicable(ladder.body)
    if why is not None:
        raise NotApplicableError(ladder.body.name, f"the 'nonrigid' model does not apply: {why}")
    t = np.asarray(jd_tdb, dtype=float)
    base = second_order_track(model, theory, t)
    change = interior_response.series_change(model.nutation, model.obliquity,
                                             interior_response.fluid_core(ladder.body))
    dpsi, deps = change.evaluate(model.mean_anomaly(t))
    dpsi0, deps0 = change.evaluate(model.mean_anomaly(model.pole_epoch))
    return model.track_from_angles(t, base.psi + dpsi - dpsi0, base.delta_psi + dpsi, base.delta_epsilon + deps,
                                   base.obliquity + deps - deps0)


def track_from_vectors(model: PrecessionNutation, theory: SecondOrderTheory, jd_tdb, pole_icrf) -> Track:
    """A :class:`Track` from ICRF pole vectors (the numerical rungs).

    ψ and ε are read off the pole in the frame of the orbit and mean equinox at t0; the
    nutation Δψ, Δε is what remains after the second-order theory's mean ψ̄, ε̄ (with the geodesic precession
    the integration carries).
    """
    t = np.asarray(jd_tdb, dtype=float)
    s = pole_icrf @ model.icrf_from_orbit   # rows: orbit-frame vectors
    psi_bar, eps_bar = theory.mean_track(t)(t)
    psi_bar = psi_bar - model.geodesic_rate * (t - model.pole_epoch)
    raw = np.arctan2(s[:, 0], s[:, 1])
    psi = psi_bar + np.remainder(raw - psi_bar + math.pi, 2.0 * math.pi) - math.pi  # unwrap about ψ̄
    eps = np.arctan2(np.hypot(s[:, 0], s[:, 1]), s[:, 2])
    ra = np.arctan2(pole_icrf[:, 1], pole_icrf[:, 0])
    ra += (ra < 0.0) * (2.0 * math.pi)
    dec = np.arctan2(pole_icrf[:, 2], np.hypot(pole_icrf[:, 0], pole_icrf[:, 1]))
    return Track(t, psi, psi - psi_bar, eps - eps_bar, eps, ra, dec)



# --- what a rung's price, estimate and track read -------------------------------------------------

@dataclass(frozen=True)
class TrackPrice:
    """What a rung's price reads, from the body's parameters alone: ``count`` epochs from ``start`` to ``stop``
    (JD TDB), the e-order, the body's nutation harmonics and the orbits from the pole epoch."""

    body: Body
    order: int | None
    start: float
    stop: float
    count: int
    harmonics: int
    orbits: float

    @property
    def e(self) -> float:
        return self.body.orbit.e

    @property
    def sides(self) -> int:
        """The sides of the pole epoch the epochs reach (:func:`ephem.theory.cost.pole_epoch_sides`): the mean track
        is integrated from it to each."""
        return cost.pole_epoch_sides(self.body.pole.epoch_jd_tdb, self.start, self.stop)


@dataclass(frozen=True)
class EstimateInputs:
    """What a rung's error terms read: the epochs, their largest |t - t0| (days), the theory terms
    (:func:`ephem.sun.bounds.theory_terms`) and the physics terms every fixed-orbit rung shares."""

    t: np.ndarray
    span_days: float
    theory: dict
    physics: dict


def rung_estimate(rung: str, order: int | None, terms: dict, physics: dict, rotation_scale: str | None = None
                  ) -> Estimate:
    """A rung's estimate: its own terms, the shared physics terms (the real orbit drops the orbit's motion, the
    non-rigid rung what a rigid body leaves out) and the rounding."""
    shared = {k: v for k, v in physics.items() if not (rung == "real_orbit" and k == "orbit_motion")
              and not (rung == "nonrigid" and k == "interior_rigid")}
    missing = () if rung == "real_orbit" or "orbit_motion" in physics else ("orbit_motion",)
    return Estimate(rung, order, {**terms, **shared, "rounding": ROUNDING}, unestimated=missing,
                    rotation_scale=rotation_scale)


@dataclass(frozen=True)
class Rung:
    """One rung of the ladder: ``description`` (what it computes and drops: an answer's ``model.description``),
    ``assumptions`` (besides what every rung assumes), ``cost`` (its own parts of a track's price, after the
    exact Hansen coefficients every track builds), ``track`` (ladder, exact model, epochs, order -> Track) and
    ``estimates`` (ladder, :class:`EstimateInputs` -> its estimates: one per e-order for the series, or one
    unavailable saying why)."""

    name: str
    description: str
    assumptions: tuple[str, ...]
    cost: Callable[[TrackPrice], list]
    track: Callable[..., Track]
    estimates: Callable[..., list]


FIXED_ORBIT = "fixed Keplerian orbit (osculating elements at their epoch)"


def _refuse_long(ladder, model: PrecessionNutation, t: np.ndarray) -> None:
    why = numerical_unavailable(model, t)
    if why is not None:
        raise NotApplicableError(ladder.body.name, why)


def _numerical_track(ladder, m: PrecessionNutation, t: np.ndarray, order: int | None) -> Track:
    _refuse_long(ladder, m, t)
    return track_from_vectors(m, ladder.theory, t, integrate_spin_axis(m, t, rtol=NUMERICAL_RTOL))


def _real_orbit_track(ladder, m: PrecessionNutation, t: np.ndarray, order: int | None) -> Track:
    _refuse_long(ladder, m, t)
    why = real_orbit_unavailable(ladder.body, t)
    if why is not None:
        raise NotApplicableError(ladder.body.name, why)
    path = sun_path_for(ladder.body, t)
    return track_from_vectors(m, ladder.theory, t, integrate_spin_axis(
        m, t, rtol=NUMERICAL_RTOL, sun=path.position_scalar))


def _series_estimates(ladder, x: EstimateInputs) -> list:
    m = ladder.model
    if m.eccentricity < LAPLACE_LIMIT:
        return [rung_estimate("series", order, {"truncation": float(truncation),
                                                "second_order": x.theory["second_order"],
                                                "geodesic": x.theory["geodesic"]}, x.physics)
                for order, truncation in enumerate(x.theory["truncation"])]
    return [Estimate("series", None, {}, available=False, why_not=(
        f"e = {m.eccentricity:.4g} exceeds the Laplace limit {LAPLACE_LIMIT:.4f}: the e-power series "
        "of the Hansen coefficients diverge"))]


def _nonrigid_estimates(ladder, x: EstimateInputs) -> list:
    why = interior_response.not_applicable(ladder.body)
    if why is not None:
        return [Estimate("nonrigid", None, {}, available=False, why_not=why)]
    return [rung_estimate("nonrigid", None, {"higher_order": x.theory["higher_order"],
                                             "geodesic": x.theory["geodesic_rephasing"],
                                             "interior_parameters": x.theory["interior_parameters"],
                                             "interior_mantle": x.theory["interior_mantle"]}, x.physics)]


def _numerical_estimates(ladder, x: EstimateInputs) -> list:
    too_long = numerical_unavailable(ladder.model, x.t)
    if too_long is None:
        return [rung_estimate("numerical", None, {"integration": integration_bound(ladder.model, x.span_days)},
                              x.physics)]
    return [Estimate("numerical", None, {}, available=False, why_not=too_long)]


def _real_orbit_estimates(ladder, x: EstimateInputs) -> list:
    m = ladder.model
    why = numerical_unavailable(m, x.t) or real_orbit_unavailable(ladder.body, x.t)
    if why is None:
        return [rung_estimate("real_orbit", None, {"integration": integration_bound(m, x.span_days),
                                                   "ephemeris": ephemeris_bound(ladder.body, m, x.span_days)},
                              x.physics)]
    return [Estimate("real_orbit", None, {}, available=False, why_not=why)]


def real_orbit_kept(body: Body, start: float, stop: float) -> bool:
    """Whether the real orbit a track from ``start`` to ``stop`` (JD TDB) integrates along (:func:`sun_path_for`) is
    kept from an earlier request (its price then leaves the orbit's integration out)."""
    t0 = body.pole.epoch_jd_tdb
    return path_kept(body, min(start, t0), max(stop, t0))


def _real_orbit_cost(p: TrackPrice) -> list:
    parts = [cost.integrated_track(p.count, p.sides), cost.spin_integration(p.orbits, p.e, p.count, real_orbit=True)]
    t0 = p.body.pole.epoch_jd_tdb
    if not real_orbit_kept(p.body, p.start, p.stop):
        # integrated from the elements' epoch through the pole's and the track's (once per span: kept)
        epochs_jd = (p.start, p.stop, t0, p.body.orbit.epoch_jd_tdb)
        parts.append(cost.orbit_integration(max(epochs_jd) - min(epochs_jd), p.body.naif_id not in DE421_BODIES))
    return parts


#: The rungs, cheapest first.
RUNGS: tuple[Rung, ...] = (
    Rung("secular", "precession only: no nutation", ("no nutation", FIXED_ORBIT),
         lambda p: [cost.secular_track(p.count)],
         lambda ladder, m, t, order: secular_track(m, t),
         lambda ladder, x: [rung_estimate("secular", None, {"nutation_omitted": x.theory["nutation_omitted"],
                                                            "second_order": x.theory["second_order"],
                                                            "geodesic": x.theory["geodesic"]}, x.physics)]),
    Rung("series", "Kinoshita-Cayley nutation, Hansen coefficients as e-power series truncated at e^order",
         ("first order in the torque", "Hansen coefficients truncated at a power of e", FIXED_ORBIT),
         lambda p: [*([cost.hansen_build(p.e, p.order)] if p.order > cost.SHARED_SERIES_ORDER else []),  # once, above
                    cost.harmonic_sum(p.count, p.order + 2, "step_days", "the track")],
         lambda ladder, m, t, order: cached_model(ladder.body, order).track(t),
         _series_estimates),
    Rung("hansen", "Kinoshita-Cayley nutation with exact Hansen coefficients (first order in the torque)",
         ("first order in the torque: the equinox drift is not fed back into the nutation phases", FIXED_ORBIT),
         lambda p: [cost.harmonic_sum(p.count, p.harmonics, "step_days", "the track")],
         lambda ladder, m, t, order: m.track(t),
         lambda ladder, x: [rung_estimate("hansen", None, {"second_order": x.theory["second_order"],
                                                           "geodesic": x.theory["geodesic"]}, x.physics)]),
    Rung("second_order", "second order in the torque: the equinox drift re-phases the nutation, plus the "
                         "second-order mean rates",
         ("second order in the torque", FIXED_ORBIT),
         lambda p: [cost.second_order(p.count, p.harmonics, p.sides)],
         lambda ladder, m, t, order: second_order_track(m, ladder.theory, t),
         lambda ladder, x: [rung_estimate("second_order", None, {"higher_order": x.theory["higher_order"],
                                                                 "geodesic": x.theory["geodesic_rephasing"]},
                                          x.physics)]),
    Rung("nonrigid", "second order in the torque, with the body's liquid core: each circular nutation component "
                     "times its interior model's transfer function (data/interiors.toml)",
         ("second order in the torque", FIXED_ORBIT,
          "a liquid core in a rigid mantle: T(sigma) = 1 + F sigma/(sigma - sigma_FCN) on every circular component "
          "(F and P_FCN from data/interiors.toml; the mantle's elasticity estimated as interior_mantle)"),
         lambda p: [cost.second_order(p.count, p.harmonics, p.sides),
                    cost.harmonic_sum(p.count, p.harmonics, "step_days", "the core's change")],
         lambda ladder, m, t, order: nonrigid_track(ladder, m, ladder.theory, t),
         _nonrigid_estimates),
    # the numerical rungs: the second-order mean track is subtracted from the integrated pole
    Rung("numerical", "rotation-averaged torque integrated numerically along the fixed Keplerian orbit",
         (FIXED_ORBIT,),
         lambda p: [cost.integrated_track(p.count, p.sides), cost.spin_integration(p.orbits, p.e, p.count)],
         _numerical_track, _numerical_estimates),
    Rung("real_orbit", "rotation-averaged torque integrated along the real orbit (DE421 and planetary perturbations)",
         ("orbit from DE421 (planets) or integrated under the DE421 planets (asteroids)",),
         _real_orbit_cost, _real_orbit_track, _real_orbit_estimates),
)
#: Their names, cheapest first (a track's ``model.name``).
RUNG_NAMES: tuple[str, ...] = tuple(r.name for r in RUNGS)
_BY_NAME = {r.name: r for r in RUNGS}


def rung_named(name: str, body: str | None = None) -> Rung:
    """The rung of that name; an unknown name is refused, listing the rungs."""
    if name not in _BY_NAME:
        raise InvalidInputError("model", f"unknown rung {name!r}; one of {', '.join(RUNG_NAMES)}", body)
    return _BY_NAME[name]


# ----------------------------------------------------------------------------- the real orbit (rung 6)

def real_orbit_unavailable(body: Body, jd_tdb: np.ndarray) -> str | None:
    """Why rung 6 cannot serve these epochs, or None if it can."""
    if body.orbit.center != "Sun":
        return (f"the orbit is centred on the {body.orbit.center}: the real-orbit rung follows heliocentric "
                "orbits only")
    lo, hi = de421_span()
    t = np.asarray(jd_tdb, dtype=float)
    need = [body.pole.epoch_jd_tdb] + ([float(t.min()), float(t.max())] if t.size else [])
    if body.naif_id not in DE421_BODIES:
        need.append(body.orbit.epoch_jd_tdb)
    if min(need) < lo or max(need) > hi:
        return (f"the real orbit comes from DE421, which spans {tdb_date(lo)} to {tdb_date(hi)} TDB; these epochs "
                f"(with the pole epoch{'' if body.naif_id in DE421_BODIES else ' and the elements epoch'}) "
                f"need JD {min(need):.1f} to {max(need):.1f}")
    return None


def ephemeris_bound(body: Body, model: PrecessionNutation, span_days: float) -> float:
    """Error of rung 6's orbit: the fit (< 1e-11 relative) and the integrated asteroid orbit (6e-7 au after
    100 years for Mars against DE421) move the Sun's direction by < 1e-9 rad per century; through the
    nutation's phase sensitivity and the precession that is far below a micro-arcsecond, so a floor of
    1e-10 rad per century of span stands for it."""
    return 1e-10 * (1.0 + abs(span_days) / 36525.0)


def sun_path_for(body: Body, jd_tdb: np.ndarray):
    """The real Sun path covering the epochs and the pole epoch (where the integration starts)."""
    t = np.asarray(jd_tdb, dtype=float)
    t0 = body.pole.epoch_jd_tdb
    return sun_path(body, min(t0, float(t.min())), max(t0, float(t.max())))
