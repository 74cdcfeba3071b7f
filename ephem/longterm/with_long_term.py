"""The ladder across spans: every family's models, and the long-term model beyond them.

A family's models (the single-perturber ladder's rungs, the lunisolar series, the Cassini state) follow the
nutation but hold the orbit fixed, or follow the real orbit only inside DE421 (1900-2050): far from the present
their estimate grows with the orbit's motion until a tolerance refuses them. The ``long_term`` model is the spin
averaged over the rotation and the orbit (:meth:`~ephem.theory.interface.SpinAxisTheory.secular_spin`) integrated along
the long-term orbit (:mod:`ephem.longterm.history`: the shipped N-body orbit where it covers the epochs, else the
secular one): no nutation (its estimate's ``nutation`` term), but an orbit good over millennia. :class:`WithLongTerm`
adds it, last, to whichever family serves a body, so ``tolerance_mas`` picks the series for decades, the real
orbit inside DE421 and the long-term model beyond, through the one interface.
"""
from __future__ import annotations

import numpy as np

from ..theory import cost
from ..base.budget import Cost, charge, prepaid
from ..base.constants import J2000_JD, JULIAN_YEAR_DAYS
from ..base.errors import NotApplicableError
from ..base.memo import bytes_bounded
from .history import DESCRIPTIONS as ORBIT_DESCRIPTIONS
from .history import long_term_run, long_term_cost
from .nbody_orbit import shipped_loaded
from ..forced.precession_nutation import Track
from ..theory.choice import Deferred
from ..theory.interface import SpectrumExport, SpinAxisTheory
from ..theory.requests import ModelChoice
from ..theory.results import Estimate

NAME = "long_term"
DESCRIPTION = ("the spin averaged over the rotation and the orbit, integrated (a 4th-order splitting) along the "
               "long-term orbit (the shipped N-body orbit where it covers the epochs, else the secular one): good "
               "over millennia, without the nutation")
#: the most epochs at which the long-term estimate is evaluated (it is smooth: the largest over a subsample)
ESTIMATE_EPOCHS = 2001


def _years(jd_tdb) -> np.ndarray:
    return (np.asarray(jd_tdb, dtype=float) - J2000_JD) / JULIAN_YEAR_DAYS


@bytes_bounded(key=lambda inner, lo, hi, count: (type(inner), inner.body, inner.perturbers, lo, hi, count,
                                                 shipped_loaded(inner.body.name)))
def _long_term_cost(inner: SpinAxisTheory, lo: float, hi: float, count: int) -> Cost:
    """The long-term model's price over [lo, hi] years (FREE where the family has no secular spin): it reads the
    body's secular orbit and spin, so it is kept per family (its body and perturbers) and span (and whether the
    shipped orbit is held yet: its first read is priced), as every choice by tolerance prices it."""
    try:
        return long_term_cost(inner.body, inner.secular_spin(), lo, hi, count)
    except NotApplicableError:
        return cost.FREE


def _subsample(years: np.ndarray) -> np.ndarray:
    if years.size <= ESTIMATE_EPOCHS:
        return np.unique(years)
    return np.linspace(float(years.min()), float(years.max()), ESTIMATE_EPOCHS)


class WithLongTerm(SpinAxisTheory, SpectrumExport):
    """A family (``inner``) with the ``long_term`` model after its own: everything else is the family's, forwarded
    method by method (the family's own attributes, its model or ladder, are ``inner``'s)."""

    def __init__(self, inner: SpinAxisTheory):
        super().__init__(inner.body, inner.perturbers, inner.requested_axis, inner.wobble, inner.rotation_phase)
        self.inner = inner
        self._secular = None
        self.summary = inner.summary
        self.models = tuple(inner.models) + (NAME,)
        self.descriptions = {**inner.descriptions, NAME: DESCRIPTION}
        self.propagates_uncertainty = inner.propagates_uncertainty
        self.models_rotation_scale = inner.models_rotation_scale

    @classmethod
    def serves(cls, body, perturbers) -> bool:   # pragma: no cover - never listed in the registry
        return False

    @classmethod
    def how_to_reach(cls, body) -> str:          # pragma: no cover
        return ""

    def with_wobble(self, wobble) -> "WithLongTerm":
        return WithLongTerm(self.inner.with_wobble(wobble))

    def with_rotation_phase(self, rotation_phase) -> "WithLongTerm":
        return WithLongTerm(self.inner.with_rotation_phase(rotation_phase))

    def default_model(self, choice):
        return self.inner.default_model(choice)

    def check_request(self, choice) -> None:
        if choice.model != NAME:
            self.inner.check_request(choice)
            return
        if choice.order is not None:
            raise NotApplicableError(self.body.name, f"the {NAME} model takes no e-order (order={choice.order!r})")
        self.secular_spin()              # "not applicable" with the reason where the family has none

    # --- cost

    def choice_cost(self, start, stop, count) -> Cost:
        """The family's: the long-term estimate is charged when it is made (:meth:`_estimate`, when a tolerance
        reaches the model or it is named), so a track that names another model pays nothing for it."""
        try:
            return self.inner.choice_cost(start, stop, count)
        except NotApplicableError:      # the family serves none of these epochs: the long-term model alone is tried
            return Cost((cost.track_answer(count),))

    def named_estimate_cost(self, choice, start, stop, count) -> Cost:
        """The long-term model's estimate is a run of its history, charged when it is made (:meth:`_estimate`): a
        track that names it makes none of the family's estimates, and pays its own request's work (as
        :meth:`choice_cost` does where the family serves none of the epochs); any other model's is the family's."""
        if choice.model == NAME:
            return Cost((cost.track_answer(count),))       # the request's own work, as the families' include it
        return self.inner.named_estimate_cost(choice, start, stop, count)

    def _cost(self, start: float, stop: float, count: int, in_years: bool = False) -> Cost:
        """The long-term model's cost over [start, stop] (JD TDB, or Julian years from J2000 ``in_years``)."""
        lo, hi = (start, stop) if in_years else (float(_years(start)), float(_years(stop)))
        return _long_term_cost(self.inner, lo, hi, count)

    def track_cost(self, choice, start, stop, count) -> Cost:
        if choice.model != NAME:
            return self.inner.track_cost(choice, start, stop, count)
        return self._cost(start, stop, count)

    # --- estimates and tracks

    def _estimate(self, jd_tdb) -> Estimate:
        years = _subsample(_years(jd_tdb))
        try:
            charge(self._cost(float(years.min()), float(years.max()), years.size, in_years=True))
            with prepaid():         # charged just above, before the work
                run = long_term_run(self.body, self.secular_spin(), years)
        except NotApplicableError as exc:
            return Estimate(NAME, None, {}, available=False, why_not=exc.reason)
        terms = {k: float(np.max(v)) for k, v in run.terms.items()}
        return Estimate(NAME, None, terms, unestimated=tuple(f"{t}_probe" for t in run.history.unestimated))

    def estimates(self, jd_tdb) -> list[Estimate]:
        """The family's estimates, then the long-term model's; where the family serves none of the epochs (the
        lunisolar series outside the span it was measured over) its models are unavailable with its reason."""
        try:
            inner = self.inner.estimates(jd_tdb)
        except NotApplicableError as exc:
            own = self._estimate(jd_tdb)
            if not own.available:
                raise                    # neither serves: the family's reason stands
            return [Estimate(m, None, {}, available=False, why_not=exc.reason) for m in self.inner.models] + [own]
        return inner + [self._estimate(jd_tdb)]

    def estimate_plan(self, jd_tdb) -> list:
        """As :meth:`estimates`, the long-term estimate deferred: it is made by running the model's history, so the
        choice by cost makes it only when it reaches the model (:func:`ephem.theory.choice.choose`)."""
        own = Deferred(NAME, None, lambda: self._estimate(jd_tdb))
        try:
            return self.inner.estimate_plan(jd_tdb) + [own]
        except NotApplicableError:
            return self.estimates(jd_tdb)            # the family serves none of the epochs: as estimates() says

    def plan_costs(self, plan, start, stop, count) -> list:
        """The family's models priced together by the family, the long-term model by its own price."""
        own = [i for i, p in enumerate(plan) if p.rung == NAME]
        inner = self.inner.plan_costs([p for p in plan if p.rung != NAME], start, stop, count)
        out = iter(inner)
        return [(self._cost(start, stop, count) if p.available else None) if i in own else next(out)
                for i, p in enumerate(plan)]

    def named(self, jd_tdb, choice):
        if choice.model != NAME:
            return self.inner.named(jd_tdb, choice)
        return self._estimate(jd_tdb)

    def _track(self, jd_tdb) -> Track:
        t = np.asarray(jd_tdb, dtype=float)
        with prepaid():             # charged as the track's cost (track_cost)
            run = long_term_run(self.body, self.secular_spin(), _years(t))
        h = run.history
        zero = np.zeros(t.shape)
        return Track(t, h.precession_angle, zero, zero, h.obliquity, h.pole_ra, h.pole_dec)

    def track(self, choice, epochs) -> Track:
        if choice.model != NAME:
            return self.inner.track(choice, epochs)
        return self._track(epochs.jd_tdb)

    def describe(self, choice) -> dict:
        own = choice.model == NAME
        info = self.inner.describe(choice.named(self.inner.default_model(ModelChoice())) if own else choice)
        if own:
            info["assumptions"] = list(info["assumptions"]) + [
                "long_term: the spin averaged over the rotation and the orbit (no nutation), along the long-term "
                "orbit: " + "; ".join(f"{k}: {v}" for k, v in ORBIT_DESCRIPTIONS.items())]
        return info

    # --- the rest is the family's

    def answer_cost(self, order, nutation=False, tolerance=False) -> Cost:
        return self.inner.answer_cost(order, nutation, tolerance)

    def precession(self, order, tolerance, start):
        return self.inner.precession(order, tolerance, start)

    def nutation(self, order, tolerance, cut_mas, start, nonrigid=False):
        return self.inner.nutation(order, tolerance, cut_mas, start, nonrigid=nonrigid)

    def spectrum(self, aim_mas, mid_centuries, jd_tdb=None, psi=None):
        if not isinstance(self.inner, SpectrumExport):
            raise NotApplicableError(self.body.name, f"{self.summary} gives no spectrum of its track")
        return self.inner.spectrum(aim_mas, mid_centuries, jd_tdb, psi)

    @property
    def track_cut_mas(self) -> float | None:
        return self.inner.track_cut_mas

    def secular_spin(self):
        """The family's secular spin, made once per request (this object): the check, the estimate and the track
        each read it, and the Moon's takes ~0.75 ms (its Cassini estimate)."""
        if self._secular is None:
            self._secular = self.inner.secular_spin()      # "not applicable" raises, every time it is asked
        return self._secular

