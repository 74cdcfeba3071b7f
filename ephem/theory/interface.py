"""One interface for every theory of a body's spin axis.

A :class:`SpinAxisTheory` is what a request is answered with: for one body, the torquing bodies
(perturbers), the axis followed and, for the figure axis, the free wobble the track may add, it
offers a family of models (the Sun-only ladder's rungs, the lunisolar Earth, …), cheapest first,
and for each:

- its domain of validity, checked before any work (:meth:`check_request`: a model this family does
  not have, an order it does not take, or "not applicable" with the reason);
- the model a request asks for, as one value (:class:`~ephem.theory.requests.ModelChoice`: its name, e-order and
  whether its track adds the free wobble and the rotation-scale terms), never as loose parameters; a track's epochs as
  one :class:`~ephem.theory.requests.Epochs` (an even grid or any array);
- what a request will cost before it runs (:class:`Pricing`: :meth:`choice_cost`, :meth:`track_cost`,
  :meth:`answer_cost`, each a :class:`~ephem.base.budget.Cost` the service charges against its budget);
- its error estimate over given epochs, by named term (:meth:`estimates`, one
  :class:`Estimate` per model, cheapest first; :func:`ephem.theory.choice.choose` picks one by tolerance);
- the track over given epochs (:meth:`track`, each family's fast path on an even grid);
- a description, the ``model`` object of the answer (:meth:`describe`);
- the precession and nutation answers' numbers (:meth:`precession`, :meth:`nutation`), typed results in radians
  (:mod:`ephem.theory.results`) that :mod:`ephem.answers.render` alone turns into the answers' dicts;
- optionally, the frequencies of its track for the SPICE kernel writer (:class:`SpectrumExport`).

:mod:`ephem.families` lists the families; :func:`ephem.families.theory_for` gives the one serving a
body and its perturbers. :mod:`ephem.answers.requests` answers every body through this interface and never asks
which theory it holds: adding a theory is writing one module and adding it to the registry.
"""
from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..base.budget import Cost
from ..bodies.catalogue import Body
from ..base.constants import FORCED_FIGURE, JULIAN_CENTURY_DAYS, MAS, followed_axis
from ..base.errors import NotApplicableError
from ..forced.precession_nutation import Track
from .choice import choose
from .requests import Epochs, ModelChoice, TrackRequest
from .results import Estimate, NutationResult, PrecessionResult

#: what to suggest when the largest term of the best estimate is a theory's own limit
THEORY_LIMIT_HINTS = {
    "nutation_residual": "the Earth's rungs are this far from the real Earth as IAU 2006/2000A gives it (the "
                         "non-rigid rung: by IAU 2000A's planetary terms and MHB2000's corrections beyond the 1996 "
                         "transfer function); no lunisolar model here does better (IAU 2006/2000A, e.g. ERFA, does)",
}
THEORY_LIMIT_HINTS["precession"] = THEORY_LIMIT_HINTS["axis_relation"] = THEORY_LIMIT_HINTS["nutation_residual"]
THEORY_LIMIT_HINTS["interior_rigid"] = ("the body has a liquid core, which changes its nutation by this much: ask for "
                                        "model 'nonrigid', which applies it (data/interiors.toml)")
THEORY_LIMIT_HINTS["interior_parameters"] = (
    "the liquid core's transfer function is known only as well as its parameters (F and P_FCN at 2 sigma, "
    "data/interiors.toml): near the free core nutation's resonance no model here does better")


def refuse(candidates: list, tolerance: float, body: str, wobble_given: bool) -> None:
    """Raise :class:`NotApplicableError`: no model meets ``tolerance`` (radians), naming the best of the available
    estimates ``candidates``, its largest term and what would help."""
    if not candidates:
        raise NotApplicableError(body, "no model can serve these epochs")
    best = min(candidates, key=lambda e: e.total)
    largest = max(best.terms, key=best.terms.get)
    hint = THEORY_LIMIT_HINTS.get(largest, "widen the tolerance or shorten the span")
    if largest == "free_wobble" and wobble_given:
        followed = next(e for e in candidates if e.free_wobble and e.rung == best.rung and e.order == best.order)
        hint = (f"following the free wobble does not help: its model is estimated good to only "
                f"{followed.terms['free_wobble_model'] / MAS:.6g} mas here (the rigid wobble drifts in phase "
                "from the observed one, or L moves far from its epoch direction); give a wobble epoch "
                "(free_wobble_epoch) nearer these epochs, or ask for axis=angular_momentum")
    elif largest == "free_wobble":
        hint = ("the figure axis wobbles about the angular momentum by the free wobble; give its phase "
                "(free_wobble_phase_deg) to follow it, or ask for axis=forced_figure (its forced motion, as the "
                "IAU's CIP: the wobble is polar motion) or axis=angular_momentum")
    raise NotApplicableError(body, (
        f"no model meets the tolerance of {tolerance / MAS:.6g} mas over these epochs: the best, "
        f"'{best.rung}', is estimated good to {best.total / MAS:.6g} mas (largest term: {largest}); {hint}"))


@dataclass(frozen=True)
class Spectrum:
    """The base frequencies a theory's track is made of: each a phase linear in T (θ0 deg at J2000, θ1 deg
    per Julian century), with the largest pole displacement its term makes (radians; 0 where unknown); and
    the precession angle Ψ = ψ̇ (t - t_p), whose multiples j Ψ (|j| <= ``max_sideband``) the track also holds
    about each base. The SPICE kernel writer (:mod:`ephem.answers.kernels`) fits the track with these."""

    labels: tuple                 # what identifies each base: k (a multiple of the mean anomaly), Delaunay multipliers
    theta0: np.ndarray
    theta1: np.ndarray
    amplitude: np.ndarray
    psi_theta0: float             # Ψ at J2000, deg
    psi_theta1: float             # ψ̇, deg per century
    max_sideband: int
    describe: str                 # what a label is, for the kernel's comments

    def frequency(self, i: int, j: int) -> float:
        """rad/day of base i with sideband j."""
        return math.radians(self.theta1[i] + j * self.psi_theta1) / JULIAN_CENTURY_DAYS

    def angle(self, i: int, j: int) -> tuple[float, float]:
        return (float(self.theta0[i] + j * self.psi_theta0) % 360.0, float(self.theta1[i] + j * self.psi_theta1))


class Pricing(ABC):
    """What a family's requests will cost before they run (:class:`~ephem.base.budget.Cost`, charged by the
    service against its budget): the choice by tolerance, one model's track, a precession or nutation answer."""

    @abstractmethod
    def choice_cost(self, start: float, stop: float, count: int) -> Cost:
        """The cost of the estimates that choose a model by tolerance over ``count`` epochs in [start, stop]."""

    def named_estimate_cost(self, choice: ModelChoice, start: float, stop: float, count: int) -> Cost:
        """The cost of the estimate of one named model (``choice.model`` None: the default) over ``count`` epochs:
        the family's estimates, which it makes together (:meth:`choice_cost`), unless a family says otherwise."""
        return self.choice_cost(start, stop, count)

    @abstractmethod
    def track_cost(self, choice: ModelChoice, start: float, stop: float, count: int) -> Cost:
        """The cost of one model's track (``choice.model`` None: the family's default) over ``count`` epochs from
        ``start`` to ``stop`` (JD TDB), with the free wobble and the rotation-scale terms where ``choice`` adds them."""

    @abstractmethod
    def answer_cost(self, order: int | None, nutation: bool = False, tolerance: bool = False) -> Cost:
        """What a precession (or, with ``nutation``, a nutation) answer will cost; ``tolerance``: the model is
        chosen by a tolerance."""


class SpectrumExport(ABC):
    """An optional capability of a family: the base frequencies of its track, for the SPICE kernel writer
    (:mod:`ephem.answers.kernels`)."""

    @abstractmethod
    def spectrum(self, aim_mas: float, mid_centuries: float, jd_tdb=None, psi=None) -> Spectrum:
        """The base frequencies of the family's track whose terms move the pole by more than a hundredth of
        ``aim_mas``, their phases linear about ``mid_centuries`` (Julian centuries TDB from J2000); given a
        computed track (epochs ``jd_tdb``, ψ in radians), as the track has them (the rates the higher models
        change)."""


class SpinAxisTheory(Pricing):
    """A family of models of one body's spin axis, for one request's perturbers, axis and free wobble.

    Subclasses set :attr:`models` (the names they answer to, cheapest first) and implement the
    abstract methods; :meth:`serves` says which bodies and perturbers they are for.
    """

    #: what the family is, in a few words ("the single-perturber ladder")
    summary: ClassVar[str] = ""
    #: the model names of this family, cheapest first (an answer's ``model.name``)
    models: ClassVar[tuple[str, ...]] = ()
    #: one line per model name: what it computes and what it drops (an answer's ``model.description``)
    descriptions: ClassVar[dict[str, str]] = {}
    #: whether the catalogue's 1σ uncertainties propagate through this family (:mod:`ephem.forced.uncertainty`
    #: replicates the single-perturber theory only)
    propagates_uncertainty: ClassVar[bool] = False

    #: the amplitude cut (mas) of the series a track is made of, where the family cuts its series by amplitude (the
    #: track answer's ``model.cut_mas``); None: it does not
    track_cut_mas: ClassVar[float | None] = None

    #: whether the family's tracks can add the rotation-scale terms (:mod:`ephem.forced.rotation_scale`) and so take
    #: a rotation phase
    models_rotation_scale: ClassVar[bool] = False

    #: the axes (:data:`ephem.base.constants.AXES`) the family's tracks follow; another is not applicable
    axes: ClassVar[tuple[str, ...]] = ("figure", "angular_momentum", "forced_figure")

    def __init__(self, body: Body, perturbers: tuple[str, ...], axis: str = "figure", wobble=None,
                 rotation_phase: float | None = None):
        self.body = body
        self.perturbers = tuple(perturbers)
        #: the axis asked for (:data:`ephem.base.constants.AXES`), and the one the theory computes (the forced figure
        #: axis is the figure axis's track); ``counts_free_wobble``: whether the free wobble is an error (it is not for
        #: the forced figure axis, which leaves it to polar motion)
        self.requested_axis = axis
        self.axis = followed_axis(axis)
        self.counts_free_wobble = axis != FORCED_FIGURE
        self.wobble = wobble
        #: the long (A) axis's angle at the pole epoch, radians (:mod:`ephem.forced.rotation_scale`), or None
        self.rotation_phase = rotation_phase

    @classmethod
    @abstractmethod
    def serves(cls, body: Body, perturbers: tuple[str, ...]) -> bool:
        """Whether this family answers for ``body`` under ``perturbers`` (the first family that does, in the
        registry's order, is used)."""

    def with_wobble(self, wobble) -> "SpinAxisTheory":
        """The same family for the same request, with the free wobble a track of the figure axis may add."""
        return type(self)(self.body, self.perturbers, self.requested_axis, wobble, self.rotation_phase)

    def with_rotation_phase(self, rotation_phase: float | None) -> "SpinAxisTheory":
        """The same family with the body's rotation phase (radians; :mod:`ephem.forced.rotation_scale`)."""
        return type(self)(self.body, self.perturbers, self.requested_axis, self.wobble, rotation_phase)

    def for_request(self, request: TrackRequest) -> "SpinAxisTheory":
        """The same family set as ``request`` asks (its free wobble and rotation phase; the body, perturbers and axis
        are the family's, :func:`ephem.families.theory_for` made it for them)."""
        return self.with_wobble(request.wobble).with_rotation_phase(request.rotation_phase)

    @classmethod
    @abstractmethod
    def how_to_reach(cls, body: Body) -> str:
        """What a request for ``body`` must say to be served by this family (for a refusal elsewhere)."""

    @abstractmethod
    def default_model(self, choice: ModelChoice) -> str:
        """The model answering when none is named and no tolerance is given (it may depend on ``choice.order``)."""

    def resolved(self, choice: ModelChoice) -> ModelChoice:
        """``choice`` with its model named: the family's default where it names none."""
        return choice if choice.model is not None else choice.named(self.default_model(choice))

    @abstractmethod
    def check_request(self, choice: ModelChoice) -> None:
        """Refuse, before any work, a model this family does not have, an e-order it does not take, or a body
        outside its domain (:class:`~ephem.base.errors.NotApplicableError` with the reason)."""

    @abstractmethod
    def estimates(self, jd_tdb) -> list[Estimate]:
        """Every model's estimate over the epochs, cheapest first; unavailable ones say why."""

    def estimate_plan(self, jd_tdb) -> list:
        """Every model's estimate as :meth:`estimates`, where one made by running its model may stand as a
        :class:`~ephem.theory.choice.Deferred` estimate, made only when the choice by cost reaches it."""
        return self.estimates(jd_tdb)

    def choose(self, jd_tdb, tolerance: float, start: float, stop: float, count: int):
        """The model chosen by ``tolerance`` (radians) for ``count`` epochs ``jd_tdb`` from ``start`` to ``stop``:
        the one predicted cheapest (:meth:`track_cost`) among those estimated within it
        (:func:`ephem.theory.choice.choose`, a :class:`~ephem.theory.choice.Choice`)."""
        plan = self.estimate_plan(jd_tdb)
        return choose(plan, self.plan_costs(plan, start, stop, count), tolerance,
                      lambda made: refuse(made, tolerance, self.body.name, self.wobble is not None))

    def plan_costs(self, plan: list, start: float, stop: float, count: int) -> list:
        """The predicted cost of each model of a plan (:meth:`estimate_plan`) over ``count`` epochs from ``start`` to
        ``stop``, None where it is unavailable: :meth:`track_cost` of each (a family may price them together)."""
        return [self.track_cost(ModelChoice(p.rung, p.order, p.free_wobble, p.rotation_scale is not None),
                                start, stop, count) if p.available else None for p in plan]

    @abstractmethod
    def named(self, jd_tdb, choice: ModelChoice) -> Estimate | None:
        """The estimate over ``jd_tdb`` of the model asked for by name (``choice.model`` None: the family's
        default), or None where it has none."""

    @abstractmethod
    def track(self, choice: ModelChoice, epochs: Epochs) -> Track:
        """The track of ``choice``'s model (None: the default) at ``epochs`` (an even grid: the family's fast path,
        or any JD TDB), with the request's free wobble added where ``choice.free_wobble`` says so and the
        rotation-scale terms where ``choice.rotation_scale`` does."""

    @abstractmethod
    def describe(self, choice: ModelChoice) -> dict:
        """The answer's ``model`` object for ``choice`` (its model named) before the selection is added: theory,
        assumptions (the free wobble's where ``choice.free_wobble`` adds the request's), warnings, the spin-orbit
        ratio and epochs."""

    @abstractmethod
    def precession(self, order: int | None, tolerance: float | None, start: float) -> PrecessionResult:
        """The mean obliquity, H_d, K and the precession rate with their 1σ and the selection, charged first;
        ``start``: the request's ``time.perf_counter()`` at its start (for the selection's ``cost_ms``)."""

    @abstractmethod
    def nutation(self, order: int | None, tolerance: float | None, cut_mas, start: float,
                 nonrigid: bool = False) -> NutationResult:
        """The nutation terms with their 1σ, the half peak-to-peak amplitudes and the selection, charged
        first; with ``nonrigid``, the terms with the body's interior model applied (data/interiors.toml), or
        "not applicable" for a rigid body, with the catalogue's reason."""

    def secular_spin(self):
        """The body's spin averaged over the rotation and the orbit, for spans of millennia and more
        (:mod:`ephem.longterm.history`): an object with ``history(orbit, years)`` (a :class:`~ephem.longterm.averaged_spin.
        SpinHistory`), ``orbit_body`` (whose orbit history drives it) and ``source``. A family without one says
        "not applicable" with the reason."""
        raise NotApplicableError(self.body.name, f"{self.summary} has no long-term (secular) model of the spin axis")

    @staticmethod
    def grid(t0: float, step: float, count: int) -> np.ndarray:
        return t0 + step * np.arange(count)

    def adds_wobble(self, choice: ModelChoice) -> bool:
        """Whether ``choice``'s track adds the request's free wobble (asked, and its phase given)."""
        return choice.free_wobble and self.wobble is not None
