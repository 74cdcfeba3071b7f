"""The library's public answers: plain dicts with the contract's keys and units.

The CLI and the HTTP service both render these; the science stays in
:mod:`ephem.forced.precession_nutation` and below. Angles in degrees, precession and nutation in
arcseconds, rates per Julian year, times as JD TDB.
"""
from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Union

import numpy as np

from ..theory import cost
from ..base.budget import OverBudgetError, charge, checkpoint, prepaid
from ..bodies.catalogue import (DEFAULT_DATASET, Body, check_angle, get_body, load_catalogue, load_references,
                                resolve_body, resolve_perturbers)
from ..bodies.interior import interior_record
from ..base.constants import MAS
from ..base.errors import InvalidInputError, NotApplicableError, count_text
from ..orbit.hansen import hansen_series
from ..longterm.history import MAX_HISTORY_SAMPLES, spin_axis_history
from ..rotation.free_motion import free_motion, make_wobble
from ..theory.tracks import check_axis, check_tolerance, check_wobble_axis
from ..forced.precession_nutation import check_order
from ..families import MODELS, refuse_model, theory_for
from ..theory.choice import choose
from ..theory.interface import refuse
from ..theory.requests import Epochs, ModelChoice, TrackRequest
from ..theory.results import selection
from . import render
from .results import (BodiesAnswer, BodyRecord, FreeMotionAnswer, HistoryAnswer, ModelsAnswer, NutationAnswer,
                      PrecessionAnswer, PrecessionNutationAnswer, TrackAnswer)
from ..forced.catalogue_sigmas import input_sigmas
from ..forced.pole_uncertainty import pole_uncertainty
from ..forced.uncertainty import propagated
from ..base.grids import check_step
from ..base.times import check_calendar_scale, to_jd_tdb
from ..base.units import in_unit, with_units
from .parameters import shared_parameters

if TYPE_CHECKING:       # the types of the annotations only: astropy loads with the first answer that needs it
    from astropy.time import Time
    from astropy.units import Quantity

#: an epoch as the answers take it: ISO 8601 text (UTC unless a scale is named), a JD TDB number or an astropy Time
Epoch = Union[str, float, "Time"]

#: Highest e-power order served: the exact-rational series costs ~0.7 s to build at 30 and grows
#: steeply beyond (a request could tie up a worker); exact Hansen coefficients have no such limit.
#: Default cap on the number of epochs in one track.
MAX_TRACK_SAMPLES = 1_000_000
#: A track whose estimated error exceeds this (mas; 1°) carries a warning that its poles are uncertain by
#: more than a degree.
WARN_ESTIMATE_MAS = 3.6e6
#: ... and beyond this (mas; 10°) it is refused: the pole could be anywhere within a cone wider than most
#: asteroids' obliquity changes, so no number served would mean anything.
REFUSE_ESTIMATE_MAS = 3.6e7



def _tolerance(tolerance_mas) -> float | None:
    tolerance_mas = in_unit(tolerance_mas, "mas", "tolerance_mas")
    if tolerance_mas is None:
        return None
    check_tolerance(tolerance_mas, unit=" of milliarcseconds")
    return float(tolerance_mas) * MAS


def _rung(name) -> str | None:
    if name is None:
        return None
    if name not in MODELS:
        raise InvalidInputError("model", f"unknown model {name!r}; one of {', '.join(MODELS)}")
    return name


def request_perturbers(b: Body, given) -> tuple[str, ...]:
    """The perturbers a request's ``perturbers`` keyword gives (``given``, as the caller wrote it): the body's own
    (None; the catalogue's, which for the Earth add the Moon to the orbit's centre), or the names validated
    (:func:`~ephem.bodies.catalogue.resolve_perturbers`: a list, or a comma-separated string such as "moon,sun").
    Where a public answer or a request (:func:`track_request`, :func:`ephem.answers.figures.plot_request`) is made
    from the keyword; below it the perturbers travel with the request or the family."""
    if given is None:
        return b.perturbers
    return resolve_perturbers(given, b)


@shared_parameters
def warm_up(*, dataset: str = DEFAULT_DATASET) -> None:
    """Build the caches the Earth's answers share, so the first request does not pay for them.

    The lunisolar series (FFT of the Moon's and the Sun's forcing, about 1.5 s), its cut-free
    companion and the track's error-estimate ingredients: about 2.3 s once per process, after
    which an Earth precession, nutation or track answer takes milliseconds; and the Moon's libration
    series (read from data/moon_librations: 0.1 s; built, 2 s a moment set, if the catalogue's moments change). Also the
    rational Hansen series every e-order is cut from (~0.1 s), which every track's error estimate needs and
    no request's cost counts; and a short history, which loads the orbit's spline (scipy.interpolate: 0.5 s, more
    than a whole 4-Myr history since issue 33). The service calls it at start-up.

    Parameters
    ----------
    dataset

    Returns
    -------
    None
    """
    hansen_series(4)
    track("moon", "2000-01-01", "2000-01-02", 1.0, dataset=dataset)    # the Moon's shipped libration series
    precession("earth", dataset=dataset)
    nutation("earth", dataset=dataset)
    track("earth", "2000-01-01", "2000-02-01", 10.0, dataset=dataset)
    history("ceres", -1000.0, 0.0, 500.0, dataset=dataset)


@shared_parameters
def list_bodies(*, dataset: str = DEFAULT_DATASET) -> BodiesAnswer:
    """The catalogue's bodies, one row each: name, NAIF id, kind, orbit, period, pole and H_d.

    Parameters
    ----------
    dataset

    Returns
    -------
    BodiesAnswer
        A list of dicts: ``name``, ``naif_id``, ``kind``, ``dataset``, ``a_au`` (au), ``e``, ``orbit_center``,
        ``rotation_period_hours`` (h), ``pole_ra_deg``, ``pole_dec_deg`` (deg, ICRF), ``dynamical_ellipticity``.
        ``.to_qtable()`` gives it as an astropy ``QTable``.
    """
    cat = load_catalogue(dataset)
    return BodiesAnswer([{
        "name": b.name, "naif_id": b.naif_id, "kind": b.kind, "dataset": b.dataset,
        "a_au": b.orbit.a_au, "e": b.orbit.e, "orbit_center": b.orbit.center,
        "rotation_period_hours": b.rotation_period_hours,
        "pole_ra_deg": b.pole.ra_deg, "pole_dec_deg": b.pole.dec_deg,
        "dynamical_ellipticity": b.hd,
    } for b in cat.bodies])


@shared_parameters
def body_record(body: str | int, *, dataset: str = DEFAULT_DATASET) -> BodyRecord:
    """The full catalogue record of a body: every value with its unit, 1-sigma and source.

    Each value carries its unit, uncertainty (or the reason none is published) and resolved source; the values derived
    from others (``inertia.derived_from.*`` are the inputs of the moments), the correlations of their errors
    (``correlations``: [{inputs: [key, key], value: ρ}]), and the interior model of the forced nutation
    (``interior``: :meth:`ephem.bodies.interior.Interior.as_dict`, data/interiors.toml).

    Parameters
    ----------
    body : str or int
        A catalogue name (any case) or NAIF id.
    dataset

    Returns
    -------
    BodyRecord
        A dict: ``name``, ``naif_id``, ``kind``, ``dataset``, ``orbit_center``, ``dynamical_ellipticity``,
        ``perturbers``, ``values`` ({key: {value, unit, uncertainty, source, reference, note}}), ``correlations``,
        ``interior``. Not table-shaped: ``.to_qtable()`` says so.
    """
    b = get_body(body, dataset)
    refs = load_references()
    values = {}
    for key, m in b.values.items():
        values[key] = {"value": m.value, "unit": m.unit, "uncertainty": m.uncertainty,
                       "no_uncertainty": m.no_uncertainty, "source": m.source, "reference": refs.get(m.source),
                       "note": m.note}
    return BodyRecord({"name": b.name, "naif_id": b.naif_id, "kind": b.kind, "dataset": b.dataset,
                       "orbit_center": b.orbit.center, "dynamical_ellipticity": b.hd,
                       "dynamical_ellipticity_from": b.hd_from, "perturbers": list(b.perturbers), "values": values,
                       "correlations": [{"inputs": list(pair), "value": rho} for pair, rho in b.correlations.items()],
                       "interior": interior_record(b.name)})


@shared_parameters
def precession(body: str | int | Body, *, tolerance_mas: float | Quantity | None = None, order: int | None = None,
               dataset: str = DEFAULT_DATASET, perturbers: str | Sequence[str] | None = None,
               quantities: bool = False) -> PrecessionAnswer:
    """Obliquity, H_d, K and the precession rate ψ̇ (Petit et al. Table 4 columns).

    ``tolerance_mas`` picks the lowest e-order whose truncated nutation stays within it
    (the rate is then the truncated one); ``model`` reports what was used. With the Moon among the perturbers the
    Earth's rate is the lunisolar theory's (:mod:`ephem.earth.family`); the Sun alone reproduces the
    single-perturber answer.

    Parameters
    ----------
    body
    tolerance_mas
    order
    dataset
    perturbers
    quantities

    Returns
    -------
    PrecessionAnswer
        A dict: ``obliquity_deg`` (deg), ``dynamical_ellipticity``, ``scaling_factor_arcsec_per_year`` (K) and
        ``precession_rate_arcsec_per_year`` (arcsec per Julian year), each with its ``_uncertainty`` (1-sigma, null:
        unknown), the geodesic precession, ``perturbers`` and ``model``. ``.to_qtable()``: a one-row table.

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    start = time.perf_counter()
    b = resolve_body(body, dataset)
    per = request_perturbers(b, perturbers)
    tol, order = _tolerance(tolerance_mas), check_order(order)
    ans = render.with_perturbers(render.precession(theory_for(b, per).precession(order, tol, start)), b, per)
    return PrecessionAnswer(with_units(ans) if quantities else ans)


@shared_parameters
def answer_cost(body: Body, *, order: int | None = None, nutation: bool = False, tolerance: bool = False) -> cost.Cost:
    """What a precession (or, with ``nutation``, a nutation) answer for a body will cost.

    Under the body's catalogue perturbers (:meth:`ephem.theory.interface.SpinAxisTheory.answer_cost`); a host charges it
    before the work (:func:`ephem.base.budget.charge`).

    Parameters
    ----------
    body : Body
        The body (:func:`ephem.api.resolve_body` gives it from a name).
    order
    nutation : bool
        The cost of the nutation answer (its terms) rather than the precession's.
    tolerance : bool
        Whether the request gives a tolerance (the order is then chosen, at the cost of the candidates).

    Returns
    -------
    Cost
        The predicted CPU seconds and memory (MB) of the answer, by part.
    """
    return theory_for(body, body.perturbers).answer_cost(order, nutation, tolerance)


@shared_parameters
def nutation(body: str | int | Body, *, tolerance_mas: float | Quantity | None = None, order: int | None = None,
             cut_mas: float | None = None, nonrigid: bool = False, dataset: str = DEFAULT_DATASET,
             perturbers: str | Sequence[str] | None = None, quantities: bool = False) -> NutationAnswer:
    """Nutation terms: Δψ = Σ S sin kM + C cos kM (likewise Δε), arcsec.

    ``tolerance_mas`` picks the lowest e-order whose terms move the pole by no more than
    that from the exact-coefficient series (the bound in ``model.estimated_error_mas``). With the Moon among the
    perturbers (the Earth) the terms are the lunisolar series' in the Delaunay arguments: each carries
    ``delaunay_multipliers`` [l, l′, F, D, Ω] (and ``multiple`` null), signed periods (negative where the argument
    decreases) and its Poisson rates; ``cut_mas`` or ``tolerance_mas`` (the largest cut whose omitted terms move the
    pole by no more than that in all) chooses the amplitude cut.

    Parameters
    ----------
    body
    tolerance_mas
    order
    cut_mas : float, optional
        The lunisolar series' amplitude cut, milliarcseconds (default 0.1); the Earth with the Moon only.
    nonrigid : bool
        The terms with the body's interior model applied (data/interiors.toml): Mars' liquid core, the Earth's IERS
        1996 transfer function; ``model.name`` is then "nonrigid". A rigid body is refused (not applicable) with the
        catalogue's reason.
    dataset
    perturbers
    quantities

    Returns
    -------
    NutationAnswer
        A dict: ``terms`` (each ``multiple`` or ``delaunay_multipliers``, ``period_days`` (d), the sine and cosine
        coefficients in longitude and obliquity (arcsec) with their 1-sigma), the argument and its rate
        (``mean_motion_deg_per_day``), the half peak-to-peak nutation (arcsec), ``perturbers`` and ``model``.
        ``.to_qtable()``: a row per term.

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    start = time.perf_counter()
    b = resolve_body(body, dataset)
    per = request_perturbers(b, perturbers)
    tol, order = _tolerance(tolerance_mas), check_order(order)
    if not isinstance(nonrigid, bool):
        raise InvalidInputError("nonrigid", f"must be true or false, got {nonrigid!r}", b.name)
    ans = render.with_perturbers(render.nutation(theory_for(b, per).nutation(order, tol, cut_mas, start,
                                                                             nonrigid=nonrigid)), b, per)
    return NutationAnswer(with_units(ans) if quantities else ans)


def _within(part: str, answer):
    """``answer()``, a part of the POST answer (``track``, ``history``): errors in the part's own inputs name
    their full path (``track.step_days``); those in the body's (orbit, pole, moments...) stay as they are."""
    try:
        return answer()
    except InvalidInputError as exc:
        # the body's own fields (rotation_period_hours, not the track's rotation_phase_deg)
        if exc.field.startswith(("orbit.", "pole.", "moments", "order", "rotation_period", "dynamical")):
            raise
        raise InvalidInputError(f"{part}.{exc.field}", exc.reason, exc.body) from None
    except OverBudgetError as exc:
        if exc.field.startswith("orbit."):
            raise
        raise exc.within(f"{part}.") from None


@shared_parameters
def precession_nutation(body: Body, *, order: int | None = None, track: dict | None = None,
                        history_request: dict | None = None,
                        max_samples: int = MAX_TRACK_SAMPLES) -> PrecessionNutationAnswer:
    """The POST answer for a body of the user's own: its precession, nutation and optionally track and history.

    Every part's cost is charged before any part is computed (the track's own check comes first, then
    the two answers'); errors in the track's inputs name their full path (``track.step_days``).

    Parameters
    ----------
    body : Body
        The body of the user's own (orbit, pole, period, moments).
    order
    track : dict, optional
        The keyword arguments of :func:`track_arrays` (``start``, ``stop``, ``step_days``, ``tolerance_mas``,
        ``model``, ``axis``, ``free_wobble_*``...): with it the answer has ``track``.
    history_request : dict, optional
        The keyword arguments of :func:`history` (``start_year``, ``stop_year``, ``step_years``, ``tolerance_mas``,
        ``orbit_model``): with it the answer has ``history``.
    max_samples

    Returns
    -------
    PrecessionNutationAnswer
        A dict of answers: ``precession`` (:class:`PrecessionAnswer`), ``nutation`` (:class:`NutationAnswer`) and,
        when asked, ``track`` (:class:`TrackAnswer`, numpy arrays) and ``history`` (:class:`HistoryAnswer`).

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    charge(answer_cost(body, order=check_order(order), nutation=True), body.name)
    ans = {}
    if track is not None:
        ans["track"] = _within("track", lambda: track_arrays(body, order=order, max_samples=max_samples, **track))
    if history_request is not None:
        ans["history"] = _within("history", lambda: history(body, **history_request))
    with prepaid():     # charged above
        ans["precession"] = precession(body, order=order)
        ans["nutation"] = nutation(body, order=order)
    return PrecessionNutationAnswer({k: ans[k] for k in ("precession", "nutation", "track", "history") if k in ans})


@shared_parameters
def history(body: str | int | Body, start_year: float, stop_year: float, step_years: float | Quantity, *,
            tolerance_mas: float | Quantity | None = None, orbit_model: str | None = None,
            dataset: str = DEFAULT_DATASET, perturbers: str | Sequence[str] | None = None,
            max_samples: int = MAX_HISTORY_SAMPLES,
            progress: Callable[[float], None] | None = None) -> HistoryAnswer:
    """The spin axis over millennia and millions of years (:func:`ephem.longterm.history.spin_axis_history`).

    The orbit model is chosen by ``tolerance_mas`` or named by ``orbit_model``; the spin equation, averaged over the
    rotation and the orbit, through the theory serving the body under ``perturbers``.

    Parameters
    ----------
    body
    start_year, stop_year : float
        The first and last epochs, Julian years from J2000.0 TDB (negative: the past); at most 20 Myr apart.
    step_years : float or Quantity
        The step between epochs, Julian years.
    tolerance_mas : float or Quantity, optional
        The largest error the obliquity may be estimated to carry, milliarcseconds: the cheapest orbit model meeting
        it answers (not with ``orbit_model``).
    orbit_model : str, optional
        "secular" or "nbody" (the shipped N-body orbit, -3 to +1 Myr); default: by tolerance, else the N-body orbit
        where it is shipped.
    dataset
    perturbers
    max_samples : int
        The most epochs allowed (default ``MAX_HISTORY_SAMPLES``).
    progress : callable, optional
        Called with the fraction done (0 to 1) as the integration advances.

    Returns
    -------
    HistoryAnswer
        A dict: per epoch ``year`` (Julian years from J2000.0 TDB), ``obliquity_deg``, ``precession_angle_deg``,
        ``pole_ra_deg``, ``pole_dec_deg``, ``orbit_inclination_deg``, ``estimated_error_deg``, ``obliquity_error_deg``
        (deg); ``meaningful_from_year``/``meaningful_to_year``; ``perturbers`` and ``model``. ``.to_qtable()``: a row
        per epoch.

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    b = resolve_body(body, dataset)
    per = request_perturbers(b, perturbers)
    result = spin_axis_history(b, theory_for(b, per), start_year, stop_year, step_years, _tolerance(tolerance_mas),
                               orbit_model, max_samples, progress)
    return HistoryAnswer(render.with_perturbers(render.history(result), b, per))


@shared_parameters
def epoch_grid(start: Epoch, stop: Epoch, step_days: float | Quantity, *,
               max_samples: int = MAX_TRACK_SAMPLES) -> tuple[float, float, int]:
    """(first JD TDB, step in days, count) of the evenly spaced epochs from start to stop.

    stop is included when it falls on the grid. Every grid of the library's tracks, figures and kernels is made
    here: a step finer than the span's Julian dates resolve (:func:`ephem.base.grids.check_step`) is refused naming
    ``step_days``, never computed.

    Parameters
    ----------
    start, stop
    step_days
    max_samples

    Returns
    -------
    tuple of (float, float, int)
        The first epoch (JD TDB, days), the step (days) and the number of epochs.

    Raises
    ------
    InvalidInputError
        Naming ``start``, ``stop`` or ``step_days``.
    """
    t0 = to_jd_tdb(start, "start")
    t1 = to_jd_tdb(stop, "stop")
    step_days = in_unit(step_days, "d", "step_days")
    if isinstance(step_days, bool) or not isinstance(step_days, (int, float)) or not math.isfinite(step_days):
        raise InvalidInputError("step_days", f"must be a finite number, got {step_days!r}")
    if step_days <= 0:
        raise InvalidInputError("step_days", f"must be positive, got {step_days}")
    if t1 < t0:
        raise InvalidInputError("stop", f"stop (JD {t1}) is before start (JD {t0})")
    steps = (t1 - t0) / step_days      # inf for a subnormal step: compared before it becomes an int
    if not steps < max_samples:        # floor(steps) + 1 > the cap (steps + 1 > it would refuse a part step)
        raise InvalidInputError("step_days", f"{count_text(steps + 1)} samples exceed the cap of {max_samples}; "
                                "use a larger step or a shorter span")
    count = int(math.floor(steps + 1e-9)) + 1
    if count > max_samples:
        raise InvalidInputError("step_days", f"{count} samples exceed the cap of {max_samples}; "
                                "use a larger step or a shorter span")
    check_step("step_days", t0, t1, float(step_days), count)     # epochs a float64 JD tells apart, or refused
    return t0, float(step_days), count


TRACK_KEYS = ("jd_tdb", "psi_arcsec", "delta_psi_arcsec", "delta_epsilon_arcsec", "obliquity_deg",
              "pole_ra_deg", "pole_dec_deg")


def _wobble_request(b: Body, axis: str, phase_deg, J_arcsec, epoch):
    if phase_deg is None:
        for name, value in (("free_wobble_J_arcsec", J_arcsec), ("free_wobble_epoch", epoch)):
            if value is not None:
                raise InvalidInputError(name, "give the wobble's phase (free_wobble_phase_deg) with it", b.name)
        return None
    check_wobble_axis(axis, b.name)
    return make_wobble(b, phase_deg, J_arcsec, None if epoch is None else to_jd_tdb(epoch, "free_wobble_epoch"))


@shared_parameters
def track_request(body: str | int | Body, start: Epoch, stop: Epoch, step_days: float | Quantity, *,
                  tolerance_mas: float | Quantity | None = None, model: str | None = None, order: int | None = None,
                  axis: str = "figure", free_wobble_phase_deg: float | Quantity | None = None,
                  free_wobble_J_arcsec: float | Quantity | None = None, free_wobble_epoch: Epoch | None = None,
                  rotation_phase_deg: float | Quantity | None = None, dataset: str = DEFAULT_DATASET,
                  perturbers: str | Sequence[str] | None = None,
                  max_samples: int = MAX_TRACK_SAMPLES) -> TrackRequest:
    """The track request a notebook holds: the public keywords checked, as one frozen ``TrackRequest``.

    Every check of a track's inputs is made here, and only here: :func:`track` and :func:`track_arrays` compute the
    request this returns. So a bad input is refused naming its field before any work, the same way on every surface, and
    a request can be made, looked at and kept before it is computed. The request carries the body (its dataset with it),
    the perturbers, the axis, the epochs (an even grid, JD TDB), the tolerance (radians), the model asked for, the free
    wobble and the rotation phase (radians).

    Parameters
    ----------
    body
    start, stop
    step_days
    tolerance_mas
    model
    order
    axis
    free_wobble_phase_deg
    free_wobble_J_arcsec
    free_wobble_epoch
    rotation_phase_deg
    dataset
    perturbers
    max_samples

    Returns
    -------
    TrackRequest
        The checked request (:class:`ephem.theory.requests.TrackRequest`, frozen): ``body``, ``perturbers``, ``axis``,
        ``epochs`` (``start`` JD TDB, ``step`` days, ``count``), ``tolerance`` (radians, or None), ``choice`` (the model
        and e-order named), ``wobble`` and ``rotation_phase`` (radians, or None).

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input (a model the body's family does not have among them).
    NotApplicableError
        Where no theory serves the body under these perturbers and axis.
    """
    b = resolve_body(body, dataset)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples=max_samples)
    order, tol, name = check_order(order), _tolerance(tolerance_mas), _rung(model)
    check_axis(axis, b.name)
    if tol is not None and (order is not None or name is not None):
        raise InvalidInputError("tolerance_mas", "give a tolerance, or a model and order, not both")
    per = request_perturbers(b, perturbers)
    theory = theory_for(b, per, axis)
    if name is not None and name not in theory.models:
        refuse_model(theory, name)
    theory.check_request(ModelChoice(name, order))
    wobble = _wobble_request(b, axis, in_unit(free_wobble_phase_deg, "deg", "free_wobble_phase_deg"),
                             in_unit(free_wobble_J_arcsec, "arcsec", "free_wobble_J_arcsec"), free_wobble_epoch)
    phase = in_unit(rotation_phase_deg, "deg", "rotation_phase_deg")
    if phase is not None:
        check_angle(b.name, "rotation_phase_deg", phase)
        if wobble is not None:
            raise InvalidInputError("rotation_phase_deg", "the rotation-scale terms and a modelled free wobble are "
                                    "not combined: give the rotation phase or the wobble's phase, not both", b.name)
        if not theory.models_rotation_scale:
            raise InvalidInputError("rotation_phase_deg", f"{theory.summary} does not model the rotation "
                                    "scale: leave it out", b.name)
    return TrackRequest(b, per, axis, Epochs.grid(t0, step, count), tol, ModelChoice(name, order), wobble,
                        None if phase is None else math.radians(phase))


@shared_parameters
def track_arrays(body: str | int | Body, start: Epoch, stop: Epoch, step_days: float | Quantity, *,
                 tolerance_mas: float | Quantity | None = None, model: str | None = None, order: int | None = None,
                 axis: str = "figure", free_wobble_phase_deg: float | Quantity | None = None,
                 free_wobble_J_arcsec: float | Quantity | None = None, free_wobble_epoch: Epoch | None = None,
                 rotation_phase_deg: float | Quantity | None = None, dataset: str = DEFAULT_DATASET,
                 perturbers: str | Sequence[str] | None = None, time_scale: str | None = "utc",
                 output: str = "json", max_samples: int = MAX_TRACK_SAMPLES) -> TrackAnswer:
    """As :func:`track`, with numpy arrays instead of lists (for streaming and numerical use).

    ``time_scale`` None leaves out the calendar dates (a figure's or a kernel's track, which no person reads).

    Parameters
    ----------
    body
    start, stop
    step_days
    tolerance_mas
    model
    order
    axis
    free_wobble_phase_deg
    free_wobble_J_arcsec
    free_wobble_epoch
    rotation_phase_deg
    dataset
    perturbers
    time_scale
    output
    max_samples

    Returns
    -------
    TrackAnswer
        A dict: ``body``, ``dataset``; per epoch, as numpy arrays, ``jd_tdb`` (JD TDB, days), the calendar dates, ``psi_arcsec``,
        ``delta_psi_arcsec``, ``delta_epsilon_arcsec`` (arcsec), ``obliquity_deg``, ``pole_ra_deg``, ``pole_dec_deg``
        (deg, ICRF), ``pole_uncertainty_deg`` (deg, 1-sigma from the catalogue's); ``obliquity_deg_uncertainty``;
        ``perturbers``; ``model`` (``name``, ``order``, ``estimated_error_mas``, ``cost_ms``, warnings...).
        ``.to_qtable()`` gives it as an astropy ``QTable``.

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    begin = time.perf_counter()
    # the request, checked, as one value (track_request: every check of a track's inputs): the family set as it
    # asks, and the model asked for by name (its track adds the free wobble and the rotation-scale terms the request
    # gave)
    request = track_request(body, start, stop, step_days, tolerance_mas=tolerance_mas, model=model, order=order,
                            axis=axis, free_wobble_phase_deg=free_wobble_phase_deg,
                            free_wobble_J_arcsec=free_wobble_J_arcsec, free_wobble_epoch=free_wobble_epoch,
                            rotation_phase_deg=rotation_phase_deg, dataset=dataset, perturbers=perturbers,
                            max_samples=max_samples)
    return track_arrays_of(request, time_scale=time_scale, output=output, begin=begin,
                           rotation_phase_deg=in_unit(rotation_phase_deg, "deg", "rotation_phase_deg"))


def track_arrays_of(request: TrackRequest, *, time_scale: str | None = "utc", output: str = "json",
                    begin: float | None = None, rotation_phase_deg: float | None = None) -> TrackAnswer:
    """The track of a checked request (:func:`track_request`), as :func:`track_arrays` computes it.

    What a caller holding the request computes (a figure's track: :mod:`ephem.answers.figures`), so the request is
    made, and its inputs checked, once. ``time_scale`` (None: no calendar dates) and ``output`` as
    :func:`track_arrays`'s; ``begin`` the ``time.perf_counter()`` the answer's ``cost_ms`` counts from (default: now);
    ``rotation_phase_deg`` the rotation phase as the caller gave it, degrees, which the answer reports (the request
    holds it in radians).
    """
    begin = time.perf_counter() if begin is None else begin
    b, per, wobble = request.body, request.perturbers, request.wobble
    t0, step, count = request.epochs.start, request.epochs.step, request.epochs.count
    tol, name, order = request.tolerance, request.choice.model, request.choice.order
    time_scale = None if time_scale is None else check_calendar_scale(time_scale)
    if output not in cost.SERIALISATIONS:
        raise InvalidInputError("format", f"must be one of {', '.join(cost.SERIALISATIONS)}, got {output!r}", b.name)
    theory = theory_for(b, per, request.axis).for_request(request)
    phase = rotation_phase_deg      # the answer reports it as given
    asked = request.asked
    t_end = request.epochs.stop
    output = cost.Cost((cost.serialised(count, len(TRACK_KEYS) + (time_scale is not None), output),)
                       + ((cost.calendar_dates(count),) if time_scale is not None else ()))
    # the estimates, and the named model's own cost, charged before anything is built
    charge((theory.choice_cost(t0, t_end, count) if tol is not None
            else theory.named_estimate_cost(asked, t0, t_end, count)
            + theory.track_cost(asked, t0, t_end, count) + output),
           b.name)
    t = request.epochs.jd_tdb
    choice = None
    if tol is not None:
        choice = theory.choose(t, tol, t0, t_end, count)
        est = choice.chosen
        model = est.choice
        charge(theory.track_cost(model, t0, t_end, count) + output, b.name)
    else:
        est = theory.named(t, asked)
        # the named model's estimate says whether its track adds the wobble and the rotation-scale terms
        model = theory.resolved(asked if est is None else ModelChoice(
            name, order, est.free_wobble, est.rotation_scale is not None))
    name, order = model.model, model.order
    checkpoint()    # the track is charged: a large one takes its turn (or is refused busy) before it is built
    tr = theory.track(model, request.epochs)
    with_wobble = wobble is not None and model.free_wobble
    estimate = None if est is None or not est.available else est.total
    info = theory.describe(model)
    if choice is not None:
        info["choice"] = render.choice(choice)
    for term in () if est is None else est.unestimated:
        info["warnings"].append(UNESTIMATED_WARNINGS[term])
    _meaningful(b, estimate, info)
    chosen = selection(theory, name, order, estimate, 1e3 * (time.perf_counter() - begin), tol,
                       None if est is None else est.terms)
    scale = None
    if est is not None and est.rotation_scale is not None:
        scale = {"modelled": est.rotation_scale, "rotation_phase_deg": phase}
    # the mean obliquity's 1σ from the catalogue's uncertainties (null: unknown), as in precession(), and the
    # pole's along the track (its angle's 1σ at each epoch, growing with the rate's)
    sigma, pole_sigma = None, None
    if theory.propagates_uncertainty:
        sigma = propagated(b, order)["obliquity_deg_uncertainty"]
        with_sigma = sum(1 for s in input_sigmas(b).values() if s)
        charge(cost.pole_uncertainty(b, with_sigma, count, order), b.name)
        pole_sigma = pole_uncertainty(b, tr.jd_tdb, order)
    ans = render.track(b, tr, info, chosen, request.axis, wobble if with_wobble else None, sigma, pole_sigma,
                       theory.track_cut_mas, scale, time_scale)
    return TrackAnswer(render.with_perturbers(ans, b, per))


@shared_parameters
def track_models(body: str | int | Body, start: Epoch, stop: Epoch, step_days: float | Quantity, *,
                 tolerance_mas: float | Quantity | None = None, axis: str = "figure",
                 dataset: str = DEFAULT_DATASET, perturbers: str | Sequence[str] | None = None,
                 max_samples: int = MAX_TRACK_SAMPLES) -> ModelsAnswer:
    """Speed against accuracy for one request: every model serving the body, its estimated error and its cost.

    Every model of the family serving ``body`` with its estimated error over these epochs (by term) and its predicted
    cost (:mod:`ephem.theory.cost`), in the family's order (the order in which a tolerance tries them), and which one
    ``tolerance_mas`` picks: the first within it, as :func:`track` chooses. Charges the estimates' cost first; computes
    no track. A model that cannot serve these epochs says why.

    Parameters
    ----------
    body
    start, stop
    step_days
    tolerance_mas : float or Quantity, optional
        The tolerance whose choice the answer shows, milliarcseconds.
    axis
    dataset
    perturbers
    max_samples

    Returns
    -------
    ModelsAnswer
        A dict: ``models`` (each ``name``, ``order``, ``estimated_error_mas`` (mas) and its ``error_terms_mas``,
        ``estimated_cpu_ms`` (ms), ``estimated_memory_mb`` (MB), ``available``/``why_not``, ``eligible``, ``chosen``),
        ``chosen``, ``why_chosen``, the epochs (``start_jd_tdb``, ``stop_jd_tdb``, ``epochs``) and ``tolerance_mas``.
        Its chart: :func:`ephem.api.models_chart`.

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    b = resolve_body(body, dataset)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples=max_samples)
    tol = _tolerance(tolerance_mas)
    check_axis(axis, b.name)
    per = request_perturbers(b, perturbers)
    return track_models_of(TrackRequest(b, per, axis, Epochs.grid(t0, step, count), tol))


def track_models_of(request: TrackRequest) -> ModelsAnswer:
    """:func:`track_models` of a request made and kept (:func:`track_request`): every model compared over its epochs.

    The request names no model: its body, perturbers, axis, epochs and tolerance are compared as
    :func:`track_models` compares its keywords' (a request asking for a model, an e-order, the free wobble or the
    rotation phase is refused naming the field: they choose one track, which a comparison of every model does not
    compute). What the CLI's ``ephem track --models`` computes from the request its options make.

    Parameters
    ----------
    request : TrackRequest
        The checked request (:func:`ephem.api.track_request`), without a model, e-order, wobble or rotation phase.

    Returns
    -------
    ModelsAnswer
        As :func:`track_models`'s.

    Raises
    ------
    InvalidInputError
        Naming the field the request gave that a comparison takes none of.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    b, tol, epochs = request.body, request.tolerance, request.epochs
    for field, given in (("model", request.choice.model), ("order", request.choice.order),
                         ("free_wobble_phase_deg", request.wobble), ("rotation_phase_deg", request.rotation_phase)):
        if given is not None:
            raise InvalidInputError(field, "applies to one track, not to the comparison of every model", b.name)
    theory = theory_for(b, request.perturbers, request.axis)
    t0, t_end, count = epochs.start, epochs.stop, epochs.count
    charge(theory.choice_cost(t0, t_end, count), b.name)
    estimates = theory.estimates(epochs.jd_tdb)      # every one: the comparison is asked for
    costs = theory.plan_costs(estimates, t0, t_end, count)           # the prices a track's choice ranks
    choice = None
    if tol is not None:
        try:       # the track's own rule on the same estimates and prices (nothing deferred here): the same model
            choice = choose(estimates, costs, tol, lambda made: refuse(made, tol, b.name, False))
        except NotApplicableError:
            choice = None
    return ModelsAnswer(render.track_models(b, theory, estimates, costs, choice, tol, (t0, t_end, count)))


#: the warning an answer carries for each error term its estimate could not include
UNESTIMATED_WARNINGS = {
    "orbit_motion": "the real orbit's departure from the fixed Keplerian one was never measured for this body: the "
                    "error estimate treats the given orbit as exact (see docs/accuracy.md)",
    "free_wobble": "no free-wobble amplitude is published for this body: the estimate takes its figure axis to "
                   "coincide with the angular momentum (a relaxed rotator)",
    "rotation_averaging": "without moments of inertia the rotation-averaging error is not estimated",
    "librations": "the forced physical librations of this synchronous body were not modelled (the library has a "
                  "theory of the orbit's periodic terms for the Moon only): the estimate leaves them out",
    "precession_constant_probe": "no 1-sigma is published for this body's precession constant (its moments): the "
                                 "long-term estimate's precession_constant term is the divergence for a probe of "
                                 "1e-3 of it, not for its uncertainty",
    "pole_probe": "no 1-sigma is published for this body's pole: the long-term estimate's pole term is the "
                  "divergence for a probe of 0.01 deg, not for its uncertainty",
}


def _meaningful(b: Body, estimate: float | None, info: dict) -> None:
    """Refuse a track whose own error estimate makes it meaningless; warn when it exceeds a degree."""
    if estimate is None:
        return
    mas = estimate / MAS
    if mas > REFUSE_ESTIMATE_MAS:
        raise NotApplicableError(b.name, f"the model's own error estimate over these epochs is {mas / 3.6e6:.3g} deg "
                                 f"(over {REFUSE_ESTIMATE_MAS / 3.6e6:g} deg): no pole served would mean anything; "
                                 "bring the epochs nearer the pole epoch or shorten the span")
    if mas > WARN_ESTIMATE_MAS:
        info["warnings"].append(f"the estimated error is {mas / 3.6e6:.3g} deg: over {WARN_ESTIMATE_MAS / 3.6e6:g} "
                                "deg, these poles are rough; bring the epochs nearer the pole epoch for better")


@shared_parameters
def track(body: str | int | Body, start: Epoch, stop: Epoch, step_days: float | Quantity, *,
          tolerance_mas: float | Quantity | None = None, model: str | None = None, order: int | None = None,
          axis: str = "figure", free_wobble_phase_deg: float | Quantity | None = None,
          free_wobble_J_arcsec: float | Quantity | None = None, free_wobble_epoch: Epoch | None = None,
          rotation_phase_deg: float | Quantity | None = None, dataset: str = DEFAULT_DATASET,
          perturbers: str | Sequence[str] | None = None, time_scale: str = "utc", quantities: bool = False,
          max_samples: int = MAX_TRACK_SAMPLES) -> TrackAnswer:
    """Spin-axis track: ψ, Δψ, Δε (arcsec), obliquity and pole RA/Dec (deg) at each epoch, with calendar dates.

    ``tolerance_mas`` lets the family's fidelity ladder (:mod:`ephem.sun.ladder`) pick the cheapest model whose pole is
    estimated within that many milliarcseconds of the truth at every epoch; ``model`` and ``order`` choose one
    explicitly. The answer's ``model`` reports ``name``, ``order``, ``estimated_error_mas`` and ``cost_ms``. The Earth
    with the Moon (its default) is served by the ``lunisolar`` model (:mod:`ephem.earth.family`), whose estimate holds
    against IAU 2006/2000A over 1900-2100 (outside, not applicable); ``perturbers="sun"`` gives the single-perturber
    ladder. The figure axis is the body's axis of largest inertia, which circles the angular momentum by the free wobble;
    the Moon's mean-Earth pole (``axis="mean_rotation"``, the IAU's) is 78.56″ from its figure axis. Without
    ``rotation_phase_deg`` the ladder can add the Oppolzer offset alone, and the semi-diurnal terms of
    :mod:`ephem.forced.rotation_scale` stay in the ``rotation_averaging`` error term.

    Times may be astropy ``Time``, unit-named arguments ``Quantity`` (:mod:`ephem.base.units`).

    Parameters
    ----------
    body
    start, stop
    step_days
    tolerance_mas
    model
    order
    axis
    free_wobble_phase_deg
    free_wobble_J_arcsec
    free_wobble_epoch
    rotation_phase_deg
    dataset
    perturbers
    time_scale : str
        The scale of the epochs' calendar dates beside ``jd_tdb``: "utc" (default; key ``utc_iso``), "tt" (``tt_iso``)
        or "tdb" (``tdb_iso``), ISO 8601 to the millisecond.
    quantities
    max_samples

    Returns
    -------
    TrackAnswer
        A dict: ``body``, ``dataset``; per epoch ``jd_tdb`` (JD TDB, days), the calendar dates, ``psi_arcsec``,
        ``delta_psi_arcsec``, ``delta_epsilon_arcsec`` (arcsec), ``obliquity_deg``, ``pole_ra_deg``, ``pole_dec_deg``
        (deg, ICRF), ``pole_uncertainty_deg`` (deg, 1-sigma from the catalogue's); ``obliquity_deg_uncertainty``;
        ``perturbers``; ``model`` (``name``, ``order``, ``estimated_error_mas``, ``cost_ms``, warnings...).
        ``.to_qtable()`` gives it as an astropy ``QTable``.

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    ans = track_arrays(body, start, stop, step_days, tolerance_mas=tolerance_mas, model=model, order=order, axis=axis,
                       free_wobble_phase_deg=free_wobble_phase_deg, free_wobble_J_arcsec=free_wobble_J_arcsec,
                       free_wobble_epoch=free_wobble_epoch, rotation_phase_deg=rotation_phase_deg, dataset=dataset,
                       perturbers=perturbers, time_scale=time_scale, max_samples=max_samples)
    if quantities:
        return TrackAnswer(with_units(ans))
    for key in TRACK_KEYS:
        ans[key] = ans[key].tolist()
    if ans.get("pole_uncertainty_deg") is not None:
        ans["pole_uncertainty_deg"] = np.asarray(ans["pole_uncertainty_deg"]).tolist()
    return ans


FREE_MOTION_KEYS = ("jd_tdb", "figure_axis_offset_x_arcsec", "figure_axis_offset_y_arcsec",
                    "wobble_angle_J_arcsec", "andoyer_nu_deg")


@shared_parameters
def free_motion_arrays(body: str | int | Body, start: Epoch, stop: Epoch, step_days: float | Quantity, *,
                       J_arcsec: float | Quantity | None = None, method: str = "auto", dataset: str = DEFAULT_DATASET,
                       time_scale: str | None = "utc", output: str = "json",
                       max_samples: int = MAX_TRACK_SAMPLES) -> FreeMotionAnswer:
    """The torque-free wobble: the figure axis's offsets from the angular momentum (arcsec) over time.

    With the angle J and Andoyer's ν, and the periods (see :mod:`ephem.rotation.free_motion`). J defaults to the
    published amplitude (Lara 2014 Table 1: Earth, Moon, Mars, Eros).

    Parameters
    ----------
    body
    start, stop
    step_days
    J_arcsec : float or Quantity, optional
        The wobble's amplitude J (the angle between the angular momentum and the C axis), arcseconds; required for a
        body without a published one.
    method : str
        "auto" (default), "series" (Lie series) or "numeric" (integration), :func:`ephem.rotation.free_motion.free_motion`.
    dataset
    time_scale
    output
    max_samples

    Returns
    -------
    FreeMotionAnswer
        A dict: per epoch (numpy arrays) ``jd_tdb`` (JD TDB), the calendar dates, ``figure_axis_offset_x_arcsec``,
        ``figure_axis_offset_y_arcsec``, ``wobble_angle_J_arcsec`` (arcsec), ``andoyer_nu_deg`` (deg); the periods
        ``wobble_period_days`` and ``precession_period_days`` (d), ``mode``, ``method``, ``J_arcsec``,
        ``moments_over_C``. ``.to_qtable()``: a row per epoch.

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """

    b = resolve_body(body, dataset)
    time_scale = None if time_scale is None else check_calendar_scale(time_scale)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples=max_samples)
    if output not in cost.SERIALISATIONS:
        raise InvalidInputError("format", f"must be one of {', '.join(cost.SERIALISATIONS)}, got {output!r}", b.name)
    rotations = step * (count - 1) * 24.0 / b.rotation_period_hours
    charge(cost.Cost((cost.free_rotation(method, count, rotations),
                      cost.serialised(count, len(FREE_MOTION_KEYS) + (time_scale is not None), output))
                     + ((cost.calendar_dates(count),) if time_scale is not None else ())), b.name)
    checkpoint()    # charged: the service admits its memory (and a large one takes its turn) before the series is summed
    return FreeMotionAnswer(render.free_motion(free_motion(b, t0 + step * np.arange(count),
                                                           in_unit(J_arcsec, "arcsec", "J_arcsec"), method), time_scale))


@shared_parameters
def free_motion_answer(body: str | int | Body, start: Epoch, stop: Epoch, step_days: float | Quantity, *,
                       J_arcsec: float | Quantity | None = None, method: str = "auto", dataset: str = DEFAULT_DATASET,
                       time_scale: str = "utc", quantities: bool = False) -> FreeMotionAnswer:
    """As :func:`free_motion_arrays`, with lists (or, with ``quantities=True``, Quantity arrays).

    Parameters
    ----------
    body
    start, stop
    step_days
    J_arcsec : float or Quantity, optional
        The wobble's amplitude J, arcseconds; required for a body without a published one.
    method : str
        "auto" (default), "series" or "numeric".
    dataset
    time_scale : str
        The scale of the epochs' calendar dates beside ``jd_tdb``: "utc" (default; key ``utc_iso``), "tt" (``tt_iso``)
        or "tdb" (``tdb_iso``), ISO 8601 to the millisecond.
    quantities

    Returns
    -------
    FreeMotionAnswer
        As :func:`free_motion_arrays`', the per-epoch values as lists (or Quantity and Time).

    Raises
    ------
    UnknownBodyError
        For a body the catalogue does not have.
    InvalidInputError
        Naming the field, for a bad input.
    NotApplicableError
        Where no theory serves the request (with the reason).
    OverBudgetError
        When the request's predicted cost exceeds the budget in force (a host's, as the service's).
    """
    ans = free_motion_arrays(body, start, stop, step_days, J_arcsec=J_arcsec, method=method, dataset=dataset,
                             time_scale=time_scale)
    if quantities:
        return FreeMotionAnswer(with_units(ans))
    for key in FREE_MOTION_KEYS:
        ans[key] = np.asarray(ans[key]).tolist()
    return ans
