"""The library's public answers: plain dicts with the contract's keys and units.

The CLI and the HTTP service both render these; the science stays in
:mod:`ephem.forced.precession_nutation` and below. Angles in degrees, precession and nutation in
arcseconds, rates per Julian year, times as JD TDB.
"""
from __future__ import annotations

import math
import time

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
from ..theory.requests import Epochs, ModelChoice
from ..theory.results import selection
from . import render
from ..forced.catalogue_sigmas import input_sigmas
from ..forced.pole_uncertainty import pole_uncertainty
from ..forced.uncertainty import propagated
from ..base.grids import check_step
from ..base.times import check_calendar_scale, to_jd_tdb
from ..base.units import in_unit, with_units

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


def _perturbers(b: Body, perturbers) -> tuple[str, ...]:
    """The perturbers of a request: the catalogue's (None), or validated names (a list, or a comma-separated
    string such as "moon,sun")."""
    if perturbers is None:
        return b.perturbers
    return resolve_perturbers(perturbers, b)


def warm_up(dataset: str = DEFAULT_DATASET) -> None:
    """Build the caches the Earth's answers share, so the first request does not pay for them.

    The lunisolar series (FFT of the Moon's and the Sun's forcing, about 1.5 s), its cut-free
    companion and the track's error-estimate ingredients: about 2.3 s once per process, after
    which an Earth precession, nutation or track answer takes milliseconds; and the Moon's libration
    series (read from data/moon_librations: 0.1 s; built, 2 s a moment set, if the catalogue's moments change). Also the rational
    Hansen series every e-order is cut from (~0.1 s), which every track's error estimate needs and
    no request's cost counts; and a short history, which loads the orbit's spline (scipy.interpolate: 0.5 s, more
    than a whole 4-Myr history since issue 33). The service calls it at start-up.
    """
    hansen_series(4)
    track("moon", "2000-01-01", "2000-01-02", 1.0, dataset=dataset)    # the Moon's shipped libration series
    precession("earth", dataset=dataset)
    nutation("earth", dataset=dataset)
    track("earth", "2000-01-01", "2000-02-01", 10.0, dataset=dataset)
    history("ceres", -1000.0, 0.0, 500.0, dataset=dataset)


def list_bodies(dataset: str = DEFAULT_DATASET) -> list[dict]:
    cat = load_catalogue(dataset)
    return [{
        "name": b.name, "naif_id": b.naif_id, "kind": b.kind, "dataset": b.dataset,
        "a_au": b.orbit.a_au, "e": b.orbit.e, "orbit_center": b.orbit.center,
        "rotation_period_hours": b.rotation_period_hours,
        "pole_ra_deg": b.pole.ra_deg, "pole_dec_deg": b.pole.dec_deg,
        "dynamical_ellipticity": b.hd,
    } for b in cat.bodies]


def body_record(body: str | int, dataset: str = DEFAULT_DATASET) -> dict:
    """The full catalogue record: every value with unit, uncertainty (or the reason none is published) and resolved
    source, the values derived from others (``inertia.derived_from.*`` are the inputs of the moments), and the
    correlations of their errors (``correlations``: [{inputs: [key, key], value: ρ}]), and the interior model of
    the forced nutation (``interior``: :meth:`ephem.bodies.interior.Interior.as_dict`, data/interiors.toml)."""
    b = get_body(body, dataset)
    refs = load_references()
    values = {}
    for key, m in b.values.items():
        values[key] = {"value": m.value, "unit": m.unit, "uncertainty": m.uncertainty,
                       "no_uncertainty": m.no_uncertainty, "source": m.source, "reference": refs.get(m.source),
                       "note": m.note}
    return {"name": b.name, "naif_id": b.naif_id, "kind": b.kind, "dataset": b.dataset,
            "orbit_center": b.orbit.center, "dynamical_ellipticity": b.hd,
            "dynamical_ellipticity_from": b.hd_from, "perturbers": list(b.perturbers), "values": values,
            "correlations": [{"inputs": list(pair), "value": rho} for pair, rho in b.correlations.items()],
            "interior": interior_record(b.name)}


def precession(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None,
               tolerance_mas: float | None = None, quantities: bool = False, perturbers=None) -> dict:
    """Obliquity, H_d, K and the precession rate ψ̇ (Petit et al. Table 4 columns).

    ``tolerance_mas`` picks the lowest e-order whose truncated nutation stays within it
    (the rate is then the truncated one); ``model`` reports what was used.

    ``perturbers``: None for the catalogue's (the Earth: the Moon and the Sun), or names ("sun",
    ["Sun"], "moon,sun"). With the Moon the Earth's rate is the lunisolar theory's
    (:mod:`ephem.earth.family`); the Sun alone reproduces the single-perturber answer.
    """
    start = time.perf_counter()
    b = resolve_body(body, dataset)
    per = _perturbers(b, perturbers)
    tol, order = _tolerance(tolerance_mas), check_order(order)
    ans = render.with_perturbers(render.precession(theory_for(b, per).precession(order, tol, start)), b, per)
    return with_units(ans) if quantities else ans


def answer_cost(b: Body, order: int | None, nutation: bool = False, tolerance: bool = False) -> cost.Cost:
    """What a precession (or, with ``nutation``, a nutation) answer for ``b`` under its catalogue perturbers
    will cost (:meth:`ephem.theory.interface.SpinAxisTheory.answer_cost`)."""
    return theory_for(b, b.perturbers).answer_cost(order, nutation, tolerance)


def nutation(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None,
             tolerance_mas: float | None = None, quantities: bool = False, perturbers=None,
             cut_mas: float | None = None, nonrigid: bool = False) -> dict:
    """Nutation terms: Δψ = Σ S sin kM + C cos kM (likewise Δε), arcsec.

    ``tolerance_mas`` picks the lowest e-order whose terms move the pole by no more than
    that from the exact-coefficient series (the bound in ``model.estimated_error_mas``).

    ``perturbers`` as :func:`precession`. With the Moon (the Earth) the terms are the lunisolar
    series' in the Delaunay arguments: each carries ``delaunay_multipliers`` [l, l′, F, D, Ω] (and
    ``multiple`` null), signed periods (negative where the argument decreases) and its Poisson rates;
    ``cut_mas`` (default 0.1) or ``tolerance_mas`` (the largest cut whose omitted terms move the pole by
    no more than that in all) chooses the amplitude cut.

    ``nonrigid``: the terms with the body's interior model applied (data/interiors.toml): Mars' liquid core (each
    circular component times T(σ), the 1σ with the core parameters'), the Earth's IERS 1996 transfer function;
    ``model.name`` is then "nonrigid". A rigid body is refused (not applicable) with the catalogue's reason.
    """
    start = time.perf_counter()
    b = resolve_body(body, dataset)
    per = _perturbers(b, perturbers)
    tol, order = _tolerance(tolerance_mas), check_order(order)
    if not isinstance(nonrigid, bool):
        raise InvalidInputError("nonrigid", f"must be true or false, got {nonrigid!r}", b.name)
    ans = render.with_perturbers(render.nutation(theory_for(b, per).nutation(order, tol, cut_mas, start,
                                                                             nonrigid=nonrigid)), b, per)
    return with_units(ans) if quantities else ans


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


def precession_nutation(body: Body, order: int | None = None, track: dict | None = None,
                        max_samples: int = MAX_TRACK_SAMPLES, history_request: dict | None = None) -> dict:
    """The POST answer for a body of the user's own: ``precession``, ``nutation`` and, with ``track``
    (the keyword arguments of :func:`track_arrays`: start, stop, step_days, tolerance_mas, model, axis,
    free_wobble_*), ``track`` (arrays), and with ``history_request`` (the keyword arguments of :func:`history`:
    start_year, stop_year, step_years, tolerance_mas, orbit_model), ``history``.

    Every part's cost is charged before any part is computed (the track's own check comes first, then
    the two answers'); errors in the track's inputs name their full path (``track.step_days``).
    """
    charge(answer_cost(body, check_order(order), nutation=True), body.name)
    ans = {}
    if track is not None:
        ans["track"] = _within("track", lambda: track_arrays(body, order=order, max_samples=max_samples, **track))
    if history_request is not None:
        ans["history"] = _within("history", lambda: history(body, **history_request))
    with prepaid():     # charged above
        ans["precession"] = precession(body, order=order)
        ans["nutation"] = nutation(body, order=order)
    return {k: ans[k] for k in ("precession", "nutation", "track", "history") if k in ans}


def history(body: str | int | Body, start_year, stop_year, step_years, dataset: str = DEFAULT_DATASET,
            tolerance_mas=None, orbit_model: str | None = None, perturbers=None,
            max_samples: int = MAX_HISTORY_SAMPLES, progress=None) -> dict:
    """The spin axis over millennia and millions of years (:func:`ephem.longterm.history.spin_axis_history`): times in Julian
    years from J2000.0 TDB (negative: the past), the orbit model chosen by ``tolerance_mas`` or named by
    ``orbit_model`` ("secular" or "nbody"), through the theory serving the body under ``perturbers``."""
    b = resolve_body(body, dataset)
    per = _perturbers(b, perturbers)
    result = spin_axis_history(b, theory_for(b, per), start_year, stop_year, step_years, _tolerance(tolerance_mas),
                               orbit_model, max_samples, progress)
    return render.with_perturbers(render.history(result), b, per)


def epoch_grid(start, stop, step_days: float, max_samples: int = MAX_TRACK_SAMPLES) -> tuple[float, float, int]:
    """(first JD TDB, step in days, count) of the evenly spaced epochs from start to stop.

    stop is included when it falls on the grid. Every grid of the library's tracks, figures and kernels is made
    here: a step finer than the span's Julian dates resolve (:func:`ephem.base.grids.check_step`) is refused naming
    ``step_days``, never computed.
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


def track_arrays(body: str | int | Body, start, stop, step_days: float, dataset: str = DEFAULT_DATASET,
                 order: int | None = None, max_samples: int = MAX_TRACK_SAMPLES,
                 tolerance_mas: float | None = None, model: str | None = None, axis: str = "figure",
                 free_wobble_phase_deg: float | None = None, free_wobble_J_arcsec: float | None = None,
                 free_wobble_epoch=None, perturbers=None, output: str = "json",
                 rotation_phase_deg: float | None = None, time_scale: str | None = "utc") -> dict:
    """As :func:`track`, with numpy arrays instead of lists (for streaming and numerical use).

    ``output``: how the caller will write the answer out (``json``, ``csv`` or ``ecsv``), which its cost includes.
    ``time_scale`` None leaves out the calendar dates (a figure's or a kernel's track, which no person reads)."""
    begin = time.perf_counter()
    b = resolve_body(body, dataset)
    time_scale = None if time_scale is None else check_calendar_scale(time_scale)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples)
    order, tol, name = check_order(order), _tolerance(tolerance_mas), _rung(model)
    check_axis(axis, b.name)
    if tol is not None and (order is not None or name is not None):
        raise InvalidInputError("tolerance_mas", "give a tolerance, or a model and order, not both")
    per = _perturbers(b, perturbers)
    if output not in cost.SERIALISATIONS:
        raise InvalidInputError("format", f"must be one of {', '.join(cost.SERIALISATIONS)}, got {output!r}", b.name)
    theory = theory_for(b, per, axis)
    if name is not None and name not in theory.models:
        refuse_model(theory, name)
    theory.check_request(ModelChoice(name, order))
    wobble = _wobble_request(b, axis, in_unit(free_wobble_phase_deg, "deg", "free_wobble_phase_deg"),
                             in_unit(free_wobble_J_arcsec, "arcsec", "free_wobble_J_arcsec"), free_wobble_epoch)
    theory = theory.with_wobble(wobble)
    phase = in_unit(rotation_phase_deg, "deg", "rotation_phase_deg")
    if phase is not None:
        check_angle(b.name, "rotation_phase_deg", phase)
        if wobble is not None:
            raise InvalidInputError("rotation_phase_deg", "the rotation-scale terms and a modelled free wobble are "
                                    "not combined: give the rotation phase or the wobble's phase, not both", b.name)
        if not theory.models_rotation_scale:
            raise InvalidInputError("rotation_phase_deg", f"{theory.summary} does not model the rotation "
                                    "scale: leave it out", b.name)
        theory = theory.with_rotation_phase(math.radians(phase))
    t_end = t0 + step * (count - 1)
    output = cost.Cost((cost.serialised(count, len(TRACK_KEYS) + (time_scale is not None), output),)
                       + ((cost.calendar_dates(count),) if time_scale is not None else ()))
    # the model asked for by name: its track adds the free wobble and the rotation-scale terms the request gave
    asked = ModelChoice(name, order, wobble is not None, phase is not None)
    # the estimates, and the named model's own cost, charged before anything is built
    charge((theory.choice_cost(t0, t_end, count) if tol is not None
            else theory.named_estimate_cost(asked, t0, t_end, count)
            + theory.track_cost(asked, t0, t_end, count) + output),
           b.name)
    t = t0 + step * np.arange(count)
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
    tr = theory.track(model, Epochs.grid(t0, step, count))
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
    ans = render.track(b, tr, info, chosen, axis, wobble if with_wobble else None, sigma, pole_sigma,
                       theory.track_cut_mas, scale, time_scale)
    return render.with_perturbers(ans, b, per)


def track_models(body: str | int | Body, start, stop, step_days: float, dataset: str = DEFAULT_DATASET,
                 tolerance_mas: float | None = None, axis: str = "figure", perturbers=None,
                 max_samples: int = MAX_TRACK_SAMPLES) -> dict:
    """Speed against accuracy for one request: every model of the family serving ``body`` with its estimated
    error over these epochs (by term) and its predicted cost (:mod:`ephem.theory.cost`), in the family's order
    (the order in which a tolerance tries them), and which one ``tolerance_mas`` picks: the first within it, as
    :func:`track` chooses. Charges the estimates' cost first; computes no track. A model that cannot serve these
    epochs says why."""
    b = resolve_body(body, dataset)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples)
    tol = _tolerance(tolerance_mas)
    check_axis(axis, b.name)
    per = _perturbers(b, perturbers)
    theory = theory_for(b, per, axis)
    t_end = t0 + step * (count - 1)
    charge(theory.choice_cost(t0, t_end, count), b.name)
    estimates = theory.estimates(t0 + step * np.arange(count))      # every one: the comparison is asked for
    costs = theory.plan_costs(estimates, t0, t_end, count)           # the prices a track's choice ranks
    choice = None
    if tol is not None:
        try:       # the track's own rule on the same estimates and prices (nothing deferred here): the same model
            choice = choose(estimates, costs, tol, lambda made: refuse(made, tol, b.name, False))
        except NotApplicableError:
            choice = None
    return render.track_models(b, theory, estimates, costs, choice, tol, (t0, t_end, count))


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


def track(body: str | int | Body, start, stop, step_days: float, dataset: str = DEFAULT_DATASET,
          order: int | None = None, max_samples: int = MAX_TRACK_SAMPLES, tolerance_mas: float | None = None,
          model: str | None = None, axis: str = "figure", free_wobble_phase_deg: float | None = None,
          free_wobble_J_arcsec: float | None = None, free_wobble_epoch=None, quantities: bool = False,
          perturbers=None, rotation_phase_deg: float | None = None, time_scale: str = "utc") -> dict:
    """Spin-axis track: ψ, Δψ, Δε (arcsec), obliquity and pole RA/Dec (deg) at each epoch, and the epochs as
    calendar dates beside ``jd_tdb``.

    ``time_scale``: the scale of those dates, "utc" (default; key ``utc_iso``), "tt" (``tt_iso``) or "tdb"
    (``tdb_iso``): ISO 8601 to the millisecond (:func:`ephem.base.times.calendar_dates`). ``jd_tdb`` stays the
    epochs' exact value; :func:`ephem.api.to_qtable` gives the answer as an astropy ``QTable`` with ``jd_tdb`` as a
    TDB ``Time``.

    ``tolerance_mas`` lets the fidelity ladder (:mod:`ephem.sun.ladder`) pick the cheapest model
    whose pole is estimated within that many milliarcseconds of the truth at every epoch;
    ``model`` (a rung name) and ``order`` choose one explicitly. The answer's ``model``
    reports ``name``, ``order``, ``estimated_error_mas`` and ``cost_ms``.

    ``axis``: "figure" (default; the body's axis of largest inertia, which circles the angular
    momentum by the free wobble, counted as an error unless followed), "angular_momentum", or "forced_figure" (the
    figure axis's forced motion, as the IAU's celestial intermediate pole: the free wobble is polar motion, neither
    added nor an error), or "mean_rotation" (a synchronous body's mean rotation axis: the Moon's mean-Earth pole, the
    IAU's, whose figure axis, DE421's principal axis, is 78.56″ from it; other families refuse it).
    ``free_wobble_phase_deg`` (the figure
    axis's position angle about the angular momentum at ``free_wobble_epoch``, default the pole
    epoch, from the ICRF north through east, with the angular momentum in the body's b2-b3 plane
    then) lets the track add the free wobble when the tolerance needs it (or always, with a named
    model); ``free_wobble_J_arcsec`` overrides the published amplitude.

    ``rotation_phase_deg``: the angle of the body's long (A, least-inertia) axis in its equator from the
    ascending node of the orbit on the equator at the pole epoch (counted towards the pole's right-hand
    sense). With it a track can add the semi-diurnal terms of :mod:`ephem.forced.rotation_scale` (and does, with a
    named model); without it the ladder can add the Oppolzer offset alone, and the semi-diurnal terms stay
    in ``rotation_averaging``.

    ``perturbers`` as :func:`precession`. The Earth with the Moon (its default) is served by the
    ``lunisolar`` model (:mod:`ephem.earth.family`), whose estimate holds against IAU 2006/2000A over
    1900-2100 (outside, not applicable); ``perturbers="sun"`` gives the single-perturber ladder.

    Times may be astropy ``Time``, unit-named arguments ``Quantity`` (:mod:`ephem.base.units`);
    ``quantities=True`` returns Quantity arrays and a TDB ``Time`` for ``jd_tdb``.
    """
    ans = track_arrays(body, start, stop, step_days, dataset, order, max_samples, tolerance_mas, model, axis,
                       free_wobble_phase_deg, free_wobble_J_arcsec, free_wobble_epoch, perturbers,
                       rotation_phase_deg=rotation_phase_deg, time_scale=time_scale)
    if quantities:
        return with_units(ans)
    for key in TRACK_KEYS:
        ans[key] = ans[key].tolist()
    if ans.get("pole_uncertainty_deg") is not None:
        ans["pole_uncertainty_deg"] = np.asarray(ans["pole_uncertainty_deg"]).tolist()
    return ans


FREE_MOTION_KEYS = ("jd_tdb", "figure_axis_offset_x_arcsec", "figure_axis_offset_y_arcsec",
                    "wobble_angle_J_arcsec", "andoyer_nu_deg")


def free_motion_arrays(body: str | int | Body, start, stop, step_days: float, J_arcsec: float | None = None,
                       method: str = "auto", dataset: str = DEFAULT_DATASET,
                       max_samples: int = MAX_TRACK_SAMPLES, time_scale: str | None = "utc",
                       output: str = "json") -> dict:
    """The torque-free wobble: the figure axis's offsets from the angular momentum (arcsec) over time,
    the angle J and Andoyer's ν, and the periods (see :mod:`ephem.rotation.free_motion`). J defaults to the
    published amplitude (Lara 2014 Table 1: Earth, Moon, Mars, Eros). ``time_scale``: the scale of the epochs'
    calendar dates beside ``jd_tdb`` (utc, tt, tdb; None: none), as :func:`track`'s; ``output`` as
    :func:`track_arrays`'."""

    b = resolve_body(body, dataset)
    time_scale = None if time_scale is None else check_calendar_scale(time_scale)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples)
    if output not in cost.SERIALISATIONS:
        raise InvalidInputError("format", f"must be one of {', '.join(cost.SERIALISATIONS)}, got {output!r}", b.name)
    rotations = step * (count - 1) * 24.0 / b.rotation_period_hours
    charge(cost.Cost((cost.free_rotation(method, count, rotations),
                      cost.serialised(count, len(FREE_MOTION_KEYS) + (time_scale is not None), output))
                     + ((cost.calendar_dates(count),) if time_scale is not None else ())), b.name)
    checkpoint()    # charged: the service admits its memory (and a large one takes its turn) before the series is summed
    return render.free_motion(free_motion(b, t0 + step * np.arange(count), in_unit(J_arcsec, "arcsec", "J_arcsec"),
                                          method), time_scale)


def free_motion_answer(body: str | int | Body, start, stop, step_days: float, J_arcsec: float | None = None,
                       method: str = "auto", dataset: str = DEFAULT_DATASET, quantities: bool = False,
                       time_scale: str = "utc") -> dict:
    """As :func:`free_motion_arrays`, with lists (or, with ``quantities=True``, Quantity arrays)."""
    ans = free_motion_arrays(body, start, stop, step_days, J_arcsec, method, dataset, time_scale=time_scale)
    if quantities:
        return with_units(ans)
    for key in FREE_MOTION_KEYS:
        ans[key] = np.asarray(ans[key]).tolist()
    return ans
