"""The fidelity ladder of one body: its rungs' estimates, the choice by tolerance, the price, the tracks.

:class:`Ladder`: a rung's track is evaluated with the free wobble and the rotation-scale terms.

The rungs, cheapest first, are the records of :mod:`ephem.sun.rungs` (secular, series, hansen, second_order,
nonrigid, numerical, real_orbit); the full rigid body (:mod:`ephem.forced.rigid_body`) is a reference for what rotation
averaging leaves out, too costly to serve (thousands of rotations per orbit).

Every rung carries an error *estimate*: an upper bound, in radians, on the angle
between its pole and the truth over the requested epochs, as a sum of named terms:

* ``nutation_omitted`` (rung 1): the largest the nutation reaches over the mean anomalies
  the epochs cover; ``truncation`` (rung 2): the largest the difference series (order N
  minus exact) moves the pole from where it was at the pole epoch, with the precession
  rates' difference;
* ``second_order`` (rungs 1-3): what the first-order theory leaves against rung 5 (the
  equinox drift, the second-order mean rates and periodic terms);
* ``higher_order`` (rung 4): what the second-order theory leaves (the second-order periodic
  nutation and the third-order drift, :class:`ephem.forced.second_order.Remainder`), with a
  third-order rest measured against rung 5;

The theory terms (the four above) are span-aware: every rung starts from the catalogue pole, so
each is the largest excursion since the pole epoch of a periodic function of the mean anomaly
over the orbit's part the epochs cover (a table over one orbit per body, no sum over the
epochs, :mod:`ephem.sun.bounds`), plus drifts growing with the time from the pole epoch
(:mod:`ephem.sun.bounds`).
* ``geodesic`` (rungs 1-4): what turning the torque's solution by the mean geodesic precession (rungs 1-3) or by
  the instantaneous one (rung 4) leaves against the numerical rungs, which integrate it (:mod:`ephem.sun.geodesic`);
* ``interior_rigid`` (every rung but ``nonrigid``, for a body with a liquid core): what the core changes, which a
  rigid answer leaves out; ``interior_parameters`` and ``interior_mantle`` (``nonrigid``): its parameters' 2σ and
  the mantle's elasticity (:mod:`ephem.forced.interior_response`);
* ``integration`` (numerical rungs): the ODE tolerance;
* ``orbit_motion`` (rungs 1-5): the fixed Keplerian orbit against the real one: for a catalogue
  body the gap measured between rungs 5 and 6 inside DE421 (``data/orbit_motion/``), beyond it
  extrapolated with the envelopes of ``data/orbit_motion.toml`` (:mod:`ephem.forced.physics_errors`);
* ``rotation_averaging`` (all): what averaging over the rotation leaves out against the full rigid
  body, for the axis followed and the rotation-scale terms the track includes
  (:func:`ephem.forced.rotation_scale.error_terms`);
* ``ephemeris`` (rung 6): the real orbit's own error; ``rounding``: double precision;
* ``free_wobble`` (all, for the figure axis): the published free-wobble amplitude J0 the track
  leaves out, or ``free_wobble_model`` when the track includes the wobble (:mod:`ephem.rotation.free_motion`).

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
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from ..base.budget import Cost
from ..base.memo import POOL, bytes_bounded, epochs_digest
from ..base.constants import ARCSEC, ROUNDING
from ..base.errors import InvalidInputError
from ..bodies.catalogue import Body
from ..forced import rotation_scale
from ..forced.interior_response import interior_terms
from ..forced.physics_errors import (orbit_motion_bound, rotation_averaging_bound, rotation_averaging_samples,
                                     rotation_averaging_sides)
from ..forced.precession_nutation import PrecessionNutation, Track, cached_model, check_domain
from ..forced.rigid_numerics import body_moments
from ..forced.second_order import SecondOrderTheory
from ..orbit.kepler import mean_motion_rad_per_day
from ..rotation.free_motion import Wobble, add_free_wobble, free_wobble_bound, wobble_model_bound
from ..theory import cost
from ..theory.choice import choose
from ..theory.interface import refuse
from ..theory.results import Estimate
from ..theory.tracks import check_axis, check_tolerance, check_wobble_axis, pole_vectors, with_free_wobble
from .bounds import Window, cached_tables, cached_theory, tables_built, theory_terms
from .rungs import RUNGS, EstimateInputs, TrackPrice, epoch_span, real_orbit_kept, rung_named


@dataclass(frozen=True)
class Ladder:
    """The rungs for one body: estimates, choice by tolerance, and evaluation.

    ``axis`` is the pole followed ("figure" or "angular_momentum"); ``wobble``, for the figure axis, the
    free wobble a track may add when the tolerance needs it (its amplitude and phase)."""

    body: Body
    axis: str = "figure"
    wobble: Wobble | None = None
    #: the A axis's angle (radians) from the orbit's ascending node on the equator at the pole epoch
    #: (:mod:`ephem.forced.rotation_scale`); None: unknown, the semi-diurnal terms stay an error term
    rotation_phase: float | None = None
    #: whether the figure axis's free wobble is an error (False: the forced figure axis, which leaves it to polar
    #: motion, :data:`ephem.base.constants.FORCED_FIGURE`)
    counts_free_wobble: bool = True

    def __post_init__(self):
        check_axis(self.axis, self.body.name)
        if self.wobble is not None:
            check_wobble_axis(self.axis, self.body.name)

    @property
    def model(self) -> PrecessionNutation:
        return cached_model(self.body)

    @property
    def theory(self) -> SecondOrderTheory:
        return cached_theory(self.body)

    @property
    def rotation_modelled(self) -> str:
        """What of the rotation-scale terms a track that adds them includes (:data:`ephem.forced.rotation_scale.MODELLED`)."""
        return "oppolzer" if self.rotation_phase is None else "all"

    def physics_terms(self, jd_tdb: np.ndarray, modelled: str = "none") -> dict:
        """Error terms every fixed-orbit rung shares: the orbit's motion and rotation averaging, with ``modelled``
        of the rotation-scale terms in the track (the real-orbit rung drops the first). A user's body has no
        measured orbit motion."""
        terms = {"rotation_averaging": rotation_averaging_bound(self.body, self.model, jd_tdb,
                                                                self.axis, modelled)}
        orbit = orbit_motion_bound(self.body, self.model, jd_tdb)
        if orbit is not None:
            terms["orbit_motion"] = orbit
        if "interior_rigid" in self._interior:
            terms["interior_rigid"] = self._interior["interior_rigid"]
        return terms

    @cached_property
    def _interior(self) -> dict:
        """The interior's estimate terms (:func:`ephem.forced.interior_response.interior_terms`): empty for a body
        the Sun-only answers treat as rigid."""
        m = self.model
        return interior_terms(m.nutation, m.obliquity, m.spin_rate, self.body)

    def _with_rotation_scale(self, estimates: list[Estimate], t: np.ndarray) -> list[Estimate]:
        """Each available rung followed by the same rung with the rotation-scale terms added (a little dearer,
        and its ``rotation_averaging`` term is what they leave)."""
        if self.model.hd == 0.0:
            return estimates
        modelled = self.rotation_modelled
        # physics_terms' rotation averaging alone (its orbit-motion bound, the same for every variant, not again)
        averaging = rotation_averaging_bound(self.body, self.model, t, self.axis, modelled)
        out = []
        for e in estimates:
            out.append(e)
            if e.available and "rotation_averaging" in e.terms:
                out.append(Estimate(e.rung, e.order, {**e.terms, "rotation_averaging": averaging},
                                    unestimated=e.unestimated, rotation_scale=modelled))
        return out

    def estimates(self, jd_tdb) -> list[Estimate]:
        """Every rung's estimate for these epochs, cheapest first (rung 2 once per order): a pure function of the
        ladder and the epochs, kept per ladder and epochs while the per-body caches' byte budget lets it
        (:func:`_cached_estimates`), so that a repeated question does not bound its errors again."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        if t.size > MEMO_EPOCHS:
            return self._estimates(t)
        if t.size:     # which epochs (first, last, count) stood for, so that the price of the same question sees the memo
            POOL.put((GRIDS, (self, float(t[0]), float(t[-1]), t.size)), epochs_digest(t))
        return list(_cached_estimates(self, t))

    def _estimates_kept(self, start: float, stop: float, count: int) -> bool:
        """Whether the estimates of the grid of ``count`` epochs from ``start`` to ``stop`` (as a track builds it) are
        kept from the same question asked before: its estimates then cost a look-up. The grid's last asked epochs
        are looked up by (first, last, count): another array of the same ends and count would be priced as kept
        and estimated in full (a price's error, never an answer's)."""
        try:
            digest = POOL.get((GRIDS, (self, start, stop, count)))
        except KeyError:
            return False
        return _cached_estimates.holds((self, digest))

    def _estimates(self, t: np.ndarray) -> list[Estimate]:
        m, th = self.model, self.theory
        inputs = EstimateInputs(t, epoch_span(m, t), physics=self.physics_terms(t),
                                theory={**theory_terms(m, th, cached_tables(self.body), Window.of(m, t)),
                                        **self._interior})
        out = [e for rung in RUNGS for e in rung.estimates(self, inputs)]
        out = self._with_rotation_scale(out, t)
        return self._wobble_estimates(out, t) if self.axis == "figure" and self.counts_free_wobble else out

    def _wobble_estimates(self, estimates: list[Estimate], t: np.ndarray) -> list[Estimate]:
        """For the figure axis: each rung leaves out the free wobble (its amplitude, a term) and, when the
        wobble's phase is given, follows it at the cost of the wobble model's error (a second estimate)."""
        left_out = free_wobble_bound(self.body) if self.wobble is None else self.wobble.J_arcsec * ARCSEC
        modelled = None
        if self.wobble is not None:
            modelled = wobble_model_bound(self.body, self.wobble, t, pole_vectors(self.model.track(t)),
                                          self._pole_at_wobble_epoch()) + ROUNDING
        # a modelled wobble takes the catalogue pole as L (ephem.rotation.free_motion): the figure axis then carries the
        # whole Oppolzer offset
        averaging = None if modelled is None else rotation_averaging_bound(
            self.body, self.model, t, self.axis, "none", pole="momentum")
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
        """What a track of ``count`` epochs from ``start`` to ``stop`` (JD TDB) will cost (:meth:`price`), kept per
        question and state of the body's caches (a choice by tolerance prices every model and variant, ~20 us
        each)."""
        return _cached_cost(self, rung, start, stop, count, order, free_wobble, rotation_scale,
                            self._kept(start, stop, count, rung == "real_orbit"))

    def _kept(self, start: float, stop: float, count: int, real_orbit: bool) -> tuple:
        """What of the body's caches a price reads (the model, the second-order theory, the estimates' tables, the
        estimates of the same epochs, and for the real orbit its path over the span): part of a price memo's key."""
        b = self.body
        return (cached_model.cached(b, None), cached_theory.cached(b), tables_built(b),
                self._estimates_kept(start, stop, count), real_orbit and real_orbit_kept(b, start, stop))

    def plan_costs(self, plan: list, start: float, stop: float, count: int) -> list:
        """:meth:`cost` of each available estimate of ``plan`` (None for the unavailable ones), priced together and
        kept per question and state of the body's caches (a choice by tolerance prices some 40 variants)."""
        variants = tuple((p.rung, p.order, p.free_wobble, p.rotation_scale is not None) for p in plan if p.available)
        costs = iter(_cached_costs(self, variants, start, stop, count,
                                   self._kept(start, stop, count, any(v[0] == "real_orbit" for v in variants))))
        return [next(costs) if p.available else None for p in plan]

    def price(self, rung: str | None, start: float, stop: float, count: int, order: int | None = None,
              free_wobble: bool = False, rotation_scale: bool = False) -> Cost:
        """What a track of ``count`` epochs from ``start`` to ``stop`` (JD TDB) will cost (:mod:`ephem.theory.cost`),
        from the body's parameters alone, before anything is built. ``rung`` None: what every track pays, named or
        chosen by tolerance: the request and its answer, every rung's estimate, and what the estimates read that the
        process keeps once built (the body's model, second-order theory and tables: charged while they are not
        kept); a rung: its own track (the chosen rung's is charged once it is known). The rung's price holds no
        cache's state, so that a choice by cost is the same in a worker that has served the body and in one that
        has not (save the real orbit's path, built once per span)."""
        b = self.body
        check_domain(b)                       # not applicable: refused before any cost
        e = b.orbit.e
        k = cost.body_harmonics(b)
        if rung is None:
            parts = [cost.track_answer(count), cost.ladder_estimates_kept(count) if self._estimates_kept(start, stop, count)
                     else cost.ladder_estimates(count, k, rotation_averaging_samples(b, start, stop),
                                                rotation_averaging_sides(b, start, stop), count <= MEMO_EPOCHS)]
            if not cached_model.cached(b, None):
                parts.append(cost.model_build(e))
            if not cached_theory.cached(b):
                parts.append(cost.theory_build(k))
            if not tables_built(b):
                parts.append(cost.estimate_tables(e))
            if free_wobble:
                parts.append(cost.free_rotation("exact", count, 0.0))
            return Cost(tuple(parts))
        # the numerical rungs integrate from the pole epoch to the farthest epoch on each side of it
        t0 = b.pole.epoch_jd_tdb
        orbits = (max(stop, t0) - min(start, t0)) * mean_motion_rad_per_day(b.orbit.a_au, b.orbit.center) \
            / (2.0 * math.pi)
        parts = list(rung_named(rung, b.name).cost(TrackPrice(b, order, start, stop, count, k, orbits)))
        if free_wobble:
            parts.append(cost.free_rotation("exact", count, 0.0))
        if rotation_scale:   # the rung from the mean pole (its model built), and the closed-form terms at every epoch
            parts += [cost.model_build(e), cost.harmonic_sum(count, 8, "step_days", "the rotation-scale terms")]
        return Cost(tuple(parts))

    def choose(self, jd_tdb, tolerance: float) -> Estimate:
        """The rung predicted cheapest (:meth:`cost`) for these epochs among those whose estimated error over them
        is within ``tolerance`` (radians): the rule of every track (:func:`ephem.theory.choice.choose`).

        Raises :class:`NotApplicableError` when none is, naming the best estimate available.
        """
        check_tolerance(tolerance, self.body.name)
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        start, stop = (float(t.min()), float(t.max())) if t.size else (self.body.pole.epoch_jd_tdb,) * 2
        plan = self.estimates(t)
        return choose(plan, self.plan_costs(plan, start, stop, t.size), tolerance,
                      lambda made: refuse(made, tolerance, self.body.name, self.wobble is not None)).chosen

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
        """A rung's track with the rotation-scale terms of :mod:`ephem.forced.rotation_scale`: the rung run from the mean
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
        m = self.model
        return rung_named(rung, self.body.name).track(self, m, t, order)


#: requests of at most this many epochs keep their estimates (:meth:`Ladder.estimates`); beyond, the estimates are a
#: small part of the track's cost and the epochs' digest would cost more than it saves
MEMO_EPOCHS = 65536


#: the memo's entries that give, for a ladder and a grid's (first, last, count), the digest of the epochs last estimated
GRIDS = "ephem.sun.ladder.estimated_grids"


@bytes_bounded(key=lambda ladder, t: (ladder, epochs_digest(t)))
def _cached_estimates(ladder: Ladder, t: np.ndarray) -> tuple[Estimate, ...]:
    return tuple(ladder._estimates(t))


@bytes_bounded      # a pure function of its arguments (the tables' state among them): ~1 kB an entry, counted
def _cached_cost(ladder: Ladder, rung, start, stop, count, order, free_wobble, rotation_scale, built: tuple) -> Cost:
    return ladder.price(rung, start, stop, count, order, free_wobble, rotation_scale)


@bytes_bounded
def _cached_costs(ladder: Ladder, variants: tuple, start, stop, count, built: tuple) -> tuple[Cost, ...]:
    # priced here, not through each variant's own memo (Ladder.cost): this entry keeps them, and a put and a weighing
    # per variant cost a new question more than the ~35 prices themselves
    return tuple(ladder.price(rung, start, stop, count, order, wobble, scale) for rung, order, wobble, scale in variants)
