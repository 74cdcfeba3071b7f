"""What a family computes for an answer: typed results in the library's own units.

A family (:class:`~ephem.theory.interface.SpinAxisTheory`) returns these; one module,
:mod:`ephem.answers.render`, turns them into the answers' dicts, with the contract's units in the keys
(degrees, arcseconds, per Julian year). Here every angle is in radians, every rate in radians per day,
every time a JD TDB or a duration in days; a 1σ is in its value's unit, None where it is unknown (a σ of
0 would claim a certainty no input has).

- :class:`Estimate`: a model's estimated pole error over a request's epochs, by named term;
- :class:`Selection`: which of a family's models answered, its estimated error and what that bounds, its cost;
- :class:`PrecessionResult`: the mean obliquity, H_d, K and the precession rate with their 1σ
  (:class:`RateSigmas`), and a family's own :class:`FamilySummary` (a synchronous satellite's Cassini state);
- :class:`NutationResult`: the terms (:class:`NutationTerm`) with their 1σ and the half peak-to-peak.

The texts that describe a model (its theory, assumptions, warnings, epochs: the ``model`` object before the
selection) are the family's own words and travel as they are (``description``).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar, Mapping

from ..bodies.catalogue import Body
from .requests import ModelChoice

#: what a track's estimate bounds (``model.estimate_covers``)
COVERS_TRACK = ("the whole: the pole's distance from the truth over the epochs, every named term (error_terms_mas) "
                "summed")
#: a closed-form rate with nothing truncated: no number to give
COVERS_NOTHING_TRUNCATED = ("nothing: the rate and the mean obliquity are the theory's closed form, nothing is "
                            "truncated, so the estimate is null; the theory's own error is a track's estimate")
#: a series served with every term it has
COVERS_ALL_TERMS = ("nothing: every term of the series is served, nothing is truncated here, so the estimate is "
                    "null; the series' own error is a track's estimate")
#: what a rate's or a nutation series' estimate bounds: they have no epochs, so no theory term applies
COVERS_TRUNCATION = ("the truncation alone: the series served against the same first-order theory untruncated "
                     "(exact coefficients, every term); not the theory's own error, which a track's estimate "
                     "gives")


#: what a non-rigid series' estimate bounds (the nutation answer with the body's interior applied)
COVERS_INTERIOR = ("the truncation and the interior model: the series served against the same first-order theory "
                   "untruncated, plus how far the interior's parameters (2 sigma) and what it leaves out (the "
                   "mantle's elasticity) can move the pole; not the theory's own error, which a track's estimate "
                   "gives")

#: Error terms of the physics left out rather than of a theory's approximations (the orbit's motion, the
#: rotation, the free wobble): what :attr:`Estimate.theory_total` leaves out
PHYSICS_TERMS = ("orbit_motion", "rotation_averaging", "free_wobble", "free_wobble_model", "interior_rigid")

#: what the precession answer's observable rate is (its ``model.assumptions``)
OBSERVABLE_RATE = ("observable_precession_rate_arcsec_per_year: the torque's rate less the geodesic (de Sitter) "
                   "precession (geodesic_precession_rate_arcsec_per_year, ephem.orbit.relativity), which turns the "
                   "axis about the orbit normal the other way: the rate radio tracking measures; "
                   "precession_rate_arcsec_per_year is the torque's alone; the geodesic rate's own uncertainty (from "
                   "a and e) is negligible beside the torque rate's")


@dataclass(frozen=True)
class Estimate:
    """Estimated pole error of one model (radians), by named term."""

    rung: str
    order: int | None
    terms: dict = field(compare=False)
    available: bool = True
    why_not: str | None = None
    #: terms that could not be estimated (a user's body: its orbit's motion was never measured)
    unestimated: tuple = ()
    #: the track adds the free wobble of the figure axis (:func:`ephem.rotation.free_motion.add_free_wobble`)
    free_wobble: bool = False
    #: the track adds the rotation-scale terms (:mod:`ephem.forced.rotation_scale`): "oppolzer" or "all"; None: not
    rotation_scale: str | None = None

    @property
    def choice(self) -> ModelChoice:
        """The model this estimate is of, as a family's track and description take it."""
        return ModelChoice(self.rung, self.order, self.free_wobble, self.rotation_scale is not None)

    @cached_property            # the terms are not changed once estimated (a new Estimate carries new terms)
    def total(self) -> float:
        return float(sum(self.terms.values()))

    @property
    def theory_total(self) -> float:
        """The estimate without the physics terms: the error against the numerical integration."""
        return float(sum(v for k, v in self.terms.items() if k not in PHYSICS_TERMS))


@dataclass(frozen=True)
class Selection:
    """Which of a family's models answered and how good it is estimated to be.

    An estimate is never 0 (issue 29: no bound is): a rate or series with nothing truncated states the floor
    of its exact coefficients, or None with the reason in ``covers``."""

    name: str
    order: int | None
    description: str
    estimate: float | None               # radians; None: nothing to bound (``covers`` says why)
    covers: str
    terms: Mapping[str, float] | None    # the estimate by named term, radians
    tolerance: float | None              # the request's, radians
    cost_ms: float                       # wall time from the request's start to the choice
    #: the amplitude cut of a lunisolar or libration series, in mas (the unit the lunisolar theory takes it in)
    cut_mas: float | None = None


def selection(theory, name: str, order: int | None, estimate: float | None, cost_ms: float,
              tolerance: float | None, terms: Mapping[str, float] | None = None, covers: str = COVERS_TRACK,
              cut_mas: float | None = None) -> Selection:
    """The :class:`Selection` of ``theory``'s model ``name`` (``theory``: a family or an instance, whose
    ``descriptions`` name the model)."""
    return Selection(name, order, theory.descriptions[name], estimate, covers, terms, tolerance, cost_ms, cut_mas)


@dataclass(frozen=True)
class RateSigmas:
    """The 1σ of a precession answer's values (None: unknown): the mean obliquity (rad), H_d, the scaling
    factor K and the precession rate ψ̇ (rad/day)."""

    obliquity: float | None
    dynamical_ellipticity: float | None
    scaling_factor: float | None
    precession_rate: float | None


def quantity(unit: str | None = None, period: str | None = None):
    """A field of a :class:`FamilySummary` in ``unit``: "rad" (an angle; the answer's key adds ``_deg``), "rad/day" (a
    rate; ``_deg_per_year``, and with ``period`` the key of its period in Julian years beside it) or None (a number
    whose name says its unit, ``_days``, or none)."""
    return field(metadata={"unit": unit, "period": period})


@dataclass(frozen=True)
class FamilySummary:
    """What a family derives beside the precession answer's values, in its own object of the answer (the Moon's
    Cassini state, ``ephem.moon.results``): a subclass in the family's package names the answer's key
    (``answer_key``) and declares each field's unit (:func:`quantity`), so that :mod:`ephem.answers.render` writes
    every family's summary the same way, without knowing the family."""

    #: the answer's key of the object
    answer_key: ClassVar[str] = ""


@dataclass(frozen=True)
class PrecessionResult:
    """The mean obliquity ε, the dynamical ellipticity H_d, the scaling factor K and the precession rate ψ̇
    (Petit et al. 2014 Table 4's columns; radians and rad/day) with their 1σ, how those were found
    (``uncertainty``: the method, the inputs without a σ and why), the model's description and the
    selection."""

    body: Body
    obliquity: float
    dynamical_ellipticity: float
    scaling_factor: float
    precession_rate: float
    sigmas: RateSigmas | None            # None: not propagated
    uncertainty: dict
    description: dict
    selection: Selection
    #: the family's own summary (a :class:`FamilySummary`: the Moon's Cassini state), or None
    summary: FamilySummary | None = None
    #: the geodesic (de Sitter) precession Ω_gp (rad/day, :mod:`ephem.orbit.relativity`), which turns the axis
    #: about the orbit normal the other way from the torque's ψ̇: the observable rate is ψ̇ − Ω_gp
    geodesic_rate: float | None = None
    #: whether the served rate is an observed one that already contains Ω_gp (the Moon's: its node's regression,
    #: fitted to lunar laser ranging): the observable rate is then the rate itself
    geodesic_in_rate: bool = False


@dataclass(frozen=True)
class NutationTerm:
    """One term of Δψ = S sin φ + C cos φ (likewise Δε), in radians; φ a multiple of the mean anomaly
    (``multiple``) or an integer combination of the Delaunay arguments (``delaunay_multipliers``).
    ``rates``: the Poisson terms' (Ṡψ, Ċψ, Ṡε, Ċε) in radians per Julian century, for series that have them."""

    multiple: int | None
    delaunay_multipliers: tuple[int, ...] | None
    period_days: float                   # signed: negative where the argument decreases
    longitude_sin: float
    longitude_cos: float
    obliquity_sin: float
    obliquity_cos: float
    period_days_sigma: float | None = None
    longitude_sin_sigma: float | None = None
    longitude_cos_sigma: float | None = None
    obliquity_sin_sigma: float | None = None
    obliquity_cos_sigma: float | None = None
    longitude_amplitude_sigma: float | None = None
    obliquity_amplitude_sigma: float | None = None
    rates: tuple[float, float, float, float] | None = None


@dataclass(frozen=True)
class NutationResult:
    """A nutation series: its terms (:class:`NutationTerm`), the argument they are in, the orbit's mean
    anomaly and motion at its epoch, the mean obliquity and the half peak-to-peak Δψ, Δε (radians) with their
    1σ, the uncertainty's method, the model's description and the selection.

    ``longitude_amplitude_factor``: what turns a longitude amplitude into the pole's displacement (sin ε for
    Δψ along the ecliptic, the paper's Amp; 1 where Δψ is already a displacement, the Moon's σ)."""

    body: Body
    argument: str
    mean_anomaly_at_epoch: float
    orbit_epoch_jd_tdb: float
    mean_motion: float
    obliquity: float
    terms: tuple[NutationTerm, ...]
    longitude_amplitude_factor: float
    half_peak_to_peak: tuple[float, float]
    half_peak_to_peak_sigma: tuple[float | None, float | None]
    uncertainty: dict
    description: dict
    selection: Selection
