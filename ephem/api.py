"""The library's public answers: plain dicts with the contract's keys and units.

The CLI and the HTTP service both render these; the science stays in
:mod:`ephem.model` and below. Angles in degrees, precession and nutation in
arcseconds, rates per Julian year, times as JD TDB.
"""
from __future__ import annotations

import math
import time
from functools import lru_cache

import numpy as np

from . import cost
from .budget import OverBudgetError, charge, prepaid
from .catalogue import (DEFAULT_DATASET, Body, get_body, load_catalogue, load_references, resolve_body,
                        resolve_perturbers)
from .constants import ARCSEC, JULIAN_YEAR_DAYS, MAS
from .errors import InvalidInputError, NotApplicableError
from .hansen import LAPLACE_LIMIT, hansen_series
from . import earth
from .earth import LunisolarTheory
from .ladder import AXES, SunLadder, model_info, truncation_bound
from .registry import MODELS, refuse_model, theory_for
from .theory import cheapest_within
from .model import MAX_ORDER, cached_model, check_domain, check_order, model_for
from .timeparse import to_jd_tdb
from .units import in_unit, with_units

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



@lru_cache(maxsize=512)
def _semi_amplitudes(body: Body, order: int | None) -> tuple[float, float]:
    return cached_model(body, order).nutation.semi_peak_to_peak()


def _tolerance(tolerance_mas) -> float | None:
    tolerance_mas = in_unit(tolerance_mas, "mas", "tolerance_mas")
    if tolerance_mas is None:
        return None
    if isinstance(tolerance_mas, bool) or not isinstance(tolerance_mas, (int, float)) \
            or not math.isfinite(tolerance_mas) or tolerance_mas <= 0.0:
        raise InvalidInputError("tolerance_mas", f"must be a positive finite number of milliarcseconds, "
                                f"got {tolerance_mas!r}")
    return float(tolerance_mas) * MAS


def _rung(name) -> str | None:
    if name is None:
        return None
    if name not in MODELS:
        raise InvalidInputError("model", f"unknown model {name!r}; one of {', '.join(MODELS)}")
    return name


def _perturbers(b: Body, perturbers) -> tuple[str, ...]:
    """The perturbers of a request: the catalogue's (None), or validated names (a list, or a comma-separated
    string such as "moon,sun"). A body the theory does not apply to (the Moon) is refused for that first."""
    if perturbers is None:
        return b.perturbers
    try:
        return resolve_perturbers(perturbers, b)
    except NotApplicableError:
        cached_model(b)     # the Moon: "synchronous" is the reason that matters
        raise


def _moon_left_out(b: Body, per: tuple[str, ...]) -> list[str]:
    """The warning a single-perturber answer carries when the catalogue gives the body the Moon too."""
    if "Moon" not in b.perturbers or "Moon" in per:
        return []
    return [f"perturbers={','.join(per)} leaves out the Moon, which the catalogue lists for {b.name}: this is the "
            f"Sun's part of the motion only (about a third of the Earth's precession), and its error estimate is "
            f"against a Sun-only {b.name}, not the real one"]


def _tag_perturbers(ans: dict, b: Body, per: tuple[str, ...]) -> dict:
    model = ans.pop("model")        # the perturbers go before the model object, which closes every answer
    ans["perturbers"] = list(per)
    ans["model"] = model
    ans["model"]["perturbers"] = list(per)
    ans["model"]["warnings"].extend(_moon_left_out(b, per))
    return ans


def _order_for_tolerance(b: Body, tolerance: float | None, order: int | None) -> int | None:
    """The lowest e-order whose truncation error is within the tolerance (None: exact coefficients).

    For the rate and the nutation terms (no time span): the truncation bound alone.
    """
    if tolerance is None:
        return order
    if order is not None:
        raise InvalidInputError("order", "give either order or tolerance_mas, not both")
    m = cached_model(b)
    if m.eccentricity < LAPLACE_LIMIT:
        kmax = int(m.nutation.multiple.max()) if m.nutation.multiple.size else 0
        for n in range(0, min(kmax, MAX_ORDER)):
            if truncation_bound(m, n, 0.0) <= tolerance:
                return n
    return None


def _selection_info(theory, name: str, order: int | None, estimate: float | None, cost_ms: float,
                    tolerance: float | None, terms: dict | None = None) -> dict:
    """The selection part of an answer's ``model`` object: which of ``theory``'s models answered, how good it is
    estimated to be and what it cost."""
    return {"name": name, "order": order, "description": theory.descriptions[name],
            "estimated_error_mas": None if estimate is None else estimate / MAS,
            "error_terms_mas": None if terms is None else {k: v / MAS for k, v in terms.items()},
            "tolerance_mas": None if tolerance is None else float(f"{tolerance / MAS:.12g}"), "cost_ms": cost_ms,
            "axis": None, "free_wobble": None,   # tracks only
            "cut_mas": None}                     # the lunisolar series only


def warm_up(dataset: str = DEFAULT_DATASET) -> None:
    """Build the caches the Earth's answers share, so the first request does not pay for them.

    The lunisolar series (FFT of the Moon's and the Sun's forcing, about 1.5 s), its cut-free
    companion and the track's error-estimate ingredients: about 2.3 s once per process, after
    which an Earth precession, nutation or track answer takes milliseconds. Also the rational
    Hansen series every e-order is cut from (~0.1 s), which every track's error estimate needs and
    no request's cost counts. The service calls it at start-up.
    """
    hansen_series(4)
    precession("earth", dataset=dataset)
    nutation("earth", dataset=dataset)
    track("earth", "2000-01-01", "2000-02-01", 10.0, dataset=dataset)


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
    """The full catalogue record: every value with unit, uncertainty and resolved source."""
    b = get_body(body, dataset)
    refs = load_references()
    values = {}
    for key, m in b.values.items():
        values[key] = {"value": m.value, "unit": m.unit, "uncertainty": m.uncertainty,
                       "source": m.source, "reference": refs.get(m.source), "note": m.note}
    return {"name": b.name, "naif_id": b.naif_id, "kind": b.kind, "dataset": b.dataset,
            "orbit_center": b.orbit.center, "dynamical_ellipticity": b.hd,
            "dynamical_ellipticity_from": b.hd_from, "perturbers": list(b.perturbers), "values": values}


def precession(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None,
               tolerance_mas: float | None = None, quantities: bool = False, perturbers=None) -> dict:
    """Obliquity, H_d, K and the precession rate ψ̇ (Petit et al. Table 4 columns).

    ``tolerance_mas`` picks the lowest e-order whose truncated nutation stays within it
    (the rate is then the truncated one); ``model`` reports what was used.

    ``perturbers``: None for the catalogue's (the Earth: the Moon and the Sun), or names ("sun",
    ["Sun"], "moon,sun"). With the Moon the Earth's rate is the lunisolar theory's
    (:mod:`ephem.earth`); the Sun alone reproduces the single-perturber answer.
    """
    start = time.perf_counter()
    b = resolve_body(body, dataset)
    per = _perturbers(b, perturbers)
    if "Moon" in per:
        ans = _lunisolar_precession(b, per, dataset, order, tolerance_mas, start)
        return with_units(ans) if quantities else ans
    tol = _tolerance(tolerance_mas)
    order = check_order(order)
    charge(answer_cost(b, order, tolerance=tol is not None), b.name)
    order = _order_for_tolerance(b, tol, order)
    m = model_for(b, dataset, order)
    unc = _propagated(b, order)
    ans = _rates(b, m, unc)
    ans["uncertainty"] = _uncertainty_summary(unc)
    ans["model"] = model_info(m, b)
    ans["model"].update(_series_selection(b, order, tol, start))
    _tag_perturbers(ans, b, per)
    return with_units(ans) if quantities else ans


def answer_cost(b: Body, order: int | None, nutation: bool = False, tolerance: bool = False) -> cost.Cost:
    """What a precession (or, with ``nutation``, a nutation) answer will cost (:mod:`ephem.cost`): the
    Hansen coefficients, the nutation's extremes, and the propagation of the inputs' σ (each input with
    a σ re-evaluates the model twice). ``tolerance``: the e-order is chosen by the truncation bound."""
    if "Moon" in b.perturbers:
        return cost.Cost((cost.lunisolar_answer(),))
    from .uncertainty import input_sigmas

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
    return cost.Cost(tuple(parts))


@lru_cache(maxsize=256)
def _propagated(b: Body, order: int | None) -> dict:
    """The 1-σ uncertainties of :func:`ephem.uncertainty.propagate`, with 0 (no input of known σ moves the
    value: its σ is unknown, not zero) replaced by None. A body none of whose inputs has a σ (a user's
    body) skips the propagation: every σ is None, at no cost."""
    from .uncertainty import ASSUMPTIONS, SCALAR_KEYS, TERM_KEYS, input_sigmas, propagate

    def unknown_as_none(d: dict) -> dict:
        return {k: (None if k.endswith("_uncertainty") and v == 0.0 else v) for k, v in d.items()}

    sigmas = input_sigmas(b)
    if all(s is None for s in sigmas.values()):
        u = {f"{k}_uncertainty": None for k in SCALAR_KEYS}
        u["terms"] = [{"multiple": int(k), **{f"{key}_uncertainty": None for key in TERM_KEYS}}
                      for k in cached_model(b, order).nutation.multiple]
        u.update(dominant_input={k: None for k in SCALAR_KEYS}, unpropagated_inputs=list(sigmas),
                 assumptions=list(ASSUMPTIONS))
        return u
    u = unknown_as_none(propagate(b, b.dataset, order, sensitivities=False))
    u["terms"] = [unknown_as_none(t) for t in u["terms"]]
    return u


def _uncertainty_summary(u: dict) -> dict:
    return {"method": "linear propagation of the catalogue's 1-sigma uncertainties (ephem.uncertainty); they "
                      "cover only the inputs with a published sigma, and null means no such input moves the "
                      "value (its uncertainty is unknown, not zero)",
            "dominant_input": u["dominant_input"], "unpropagated_inputs": list(u["unpropagated_inputs"]),
            "assumptions": list(u["assumptions"])}


def _series_selection(b: Body, order: int | None, tol: float | None, start: float) -> dict:
    estimate = None if order is None else truncation_bound(cached_model(b), order, 0.0)
    return _selection_info(SunLadder, "hansen" if order is None else "series", order, estimate or 0.0,
                           1e3 * (time.perf_counter() - start), tol)


def nutation(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None,
             tolerance_mas: float | None = None, quantities: bool = False, perturbers=None,
             cut_mas: float | None = None) -> dict:
    """Nutation terms: Δψ = Σ S sin kM + C cos kM (likewise Δε), arcsec.

    ``tolerance_mas`` picks the lowest e-order whose terms move the pole by no more than
    that from the exact-coefficient series (the bound in ``model.estimated_error_mas``).

    ``perturbers`` as :func:`precession`. With the Moon (the Earth) the terms are the lunisolar
    series' in the Delaunay arguments: each carries ``delaunay_multipliers`` [l, l′, F, D, Ω] (and
    ``multiple`` null), signed periods (negative where the argument decreases) and its Poisson rates;
    ``cut_mas`` (default 0.1) or ``tolerance_mas`` (the largest cut whose omitted terms move the pole by
    no more than that in all) chooses the amplitude cut.
    """
    start = time.perf_counter()
    b = resolve_body(body, dataset)
    per = _perturbers(b, perturbers)
    if "Moon" in per:
        ans = _lunisolar_nutation(b, per, dataset, order, tolerance_mas, cut_mas, start)
        return with_units(ans) if quantities else ans
    if cut_mas is not None:
        raise InvalidInputError("cut_mas", "an amplitude cut applies to the lunisolar series (the Earth with the "
                                "Moon); this series is truncated by e-order (order, tolerance_mas)", b.name)
    tol = _tolerance(tolerance_mas)
    order = check_order(order)
    charge(answer_cost(b, order, nutation=True, tolerance=tol is not None), b.name)
    order = _order_for_tolerance(b, tol, order)
    m = model_for(b, dataset, order)
    s = m.nutation
    periods = s.period_days
    terms = [{
        "multiple": int(k), "period_days": float(p), "period_years": float(p / JULIAN_YEAR_DAYS),
        "longitude_sin_arcsec": float(a / ARCSEC), "longitude_cos_arcsec": float(c / ARCSEC),
        "obliquity_sin_arcsec": float(d / ARCSEC), "obliquity_cos_arcsec": float(f / ARCSEC),
    } for k, p, a, c, d, f in zip(s.multiple, periods, s.lon_sin, s.lon_cos, s.obl_sin, s.obl_cos)]
    unc = _propagated(b, order)
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
    half_psi, half_eps = _semi_amplitudes(b, m.order)
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
        "delta_epsilon_half_peak_to_peak_arcsec_uncertainty": unc["delta_epsilon_half_peak_to_peak_arcsec_uncertainty"],
        "uncertainty": _uncertainty_summary(unc),
        "model": model_info(m, b),
    }
    ans["model"].update(_series_selection(b, order, tol, start))
    _tag_perturbers(ans, b, per)
    return with_units(ans) if quantities else ans


def precession_nutation(body: Body, order: int | None = None, track: dict | None = None,
                        max_samples: int = MAX_TRACK_SAMPLES) -> dict:
    """The POST answer for a body of the user's own: ``precession``, ``nutation`` and, with ``track``
    (the keyword arguments of :func:`track_arrays`: start, stop, step_days, tolerance_mas, model, axis,
    free_wobble_*), ``track`` (arrays).

    Every part's cost is charged before any part is computed (the track's own check comes first, then
    the two answers'); errors in the track's inputs name their full path (``track.step_days``).
    """
    charge(answer_cost(body, check_order(order), nutation=True), body.name)
    ans = {}
    if track is not None:
        try:
            ans["track"] = track_arrays(body, order=order, max_samples=max_samples, **track)
        except InvalidInputError as exc:
            if exc.field.startswith(("orbit.", "pole.", "moments", "order", "rotation", "dynamical")):
                raise
            raise InvalidInputError(f"track.{exc.field}", exc.reason, exc.body) from None
        except OverBudgetError as exc:
            if exc.field.startswith("orbit."):
                raise
            raise exc.within("track.") from None
    with prepaid():     # charged above
        ans["precession"] = precession(body, order=order)
        ans["nutation"] = nutation(body, order=order)
    return {k: ans[k] for k in ("precession", "nutation", "track") if k in ans}


def epoch_grid(start, stop, step_days: float, max_samples: int = MAX_TRACK_SAMPLES) -> tuple[float, float, int]:
    """(first JD TDB, step in days, count) of the evenly spaced epochs from start to stop.

    stop is included when it falls on the grid.
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
    if steps + 1 > max_samples:
        raise InvalidInputError("step_days", f"{steps + 1:.3g} samples exceed the cap of {max_samples}; "
                                "use a larger step or a shorter span")
    count = int(math.floor(steps + 1e-9)) + 1
    if count > max_samples:
        raise InvalidInputError("step_days", f"{count} samples exceed the cap of {max_samples}; "
                                "use a larger step or a shorter span")
    return t0, float(step_days), count


TRACK_KEYS = ("jd_tdb", "psi_arcsec", "delta_psi_arcsec", "delta_epsilon_arcsec", "obliquity_deg",
              "pole_ra_deg", "pole_dec_deg")


def _wobble_request(b: Body, axis: str, phase_deg, J_arcsec, epoch):
    if phase_deg is None:
        for name, value in (("free_wobble_J_arcsec", J_arcsec), ("free_wobble_epoch", epoch)):
            if value is not None:
                raise InvalidInputError(name, "give the wobble's phase (free_wobble_phase_deg) with it", b.name)
        return None
    if axis != "figure":
        raise InvalidInputError("free_wobble_phase_deg", "the free wobble moves the figure axis, not the "
                                "angular momentum: ask for axis=figure", b.name)
    from .free_motion import make_wobble

    return make_wobble(b, phase_deg, J_arcsec, None if epoch is None else to_jd_tdb(epoch, "free_wobble_epoch"))


def track_arrays(body: str | int | Body, start, stop, step_days: float, dataset: str = DEFAULT_DATASET,
                 order: int | None = None, max_samples: int = MAX_TRACK_SAMPLES,
                 tolerance_mas: float | None = None, model: str | None = None, axis: str = "figure",
                 free_wobble_phase_deg: float | None = None, free_wobble_J_arcsec: float | None = None,
                 free_wobble_epoch=None, perturbers=None, output: str = "json") -> dict:
    """As :func:`track`, with numpy arrays instead of lists (for streaming and numerical use).

    ``output``: how the caller will write the answer out (``json`` or ``csv``), which its cost includes."""
    begin = time.perf_counter()
    b = resolve_body(body, dataset)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples)
    order, tol, name = check_order(order), _tolerance(tolerance_mas), _rung(model)
    if axis not in AXES:
        raise InvalidInputError("axis", f"must be one of {', '.join(AXES)}, got {axis!r}", b.name)
    if tol is not None and (order is not None or name is not None):
        raise InvalidInputError("tolerance_mas", "give a tolerance, or a model and order, not both")
    per = _perturbers(b, perturbers)
    if output not in cost.SERIALISATIONS:
        raise InvalidInputError("format", f"must be one of {', '.join(cost.SERIALISATIONS)}, got {output!r}", b.name)
    theory = theory_for(b, per, axis)
    if name is not None and name not in theory.models:
        refuse_model(theory, name)
    theory.check_request(name, order)
    wobble = _wobble_request(b, axis, in_unit(free_wobble_phase_deg, "deg", "free_wobble_phase_deg"),
                             in_unit(free_wobble_J_arcsec, "arcsec", "free_wobble_J_arcsec"), free_wobble_epoch)
    theory = theory.with_wobble(wobble)
    t_end = t0 + step * (count - 1)
    output = cost.Cost((cost.serialised(count, len(TRACK_KEYS), output),))
    # the estimates, and the named model's own cost, charged before anything is built
    charge(theory.choice_cost(t0, t_end, count)
           + (cost.FREE if tol is not None else theory.track_cost(name, order, t0, t_end, count, wobble is not None)
              + output), b.name)
    t = t0 + step * np.arange(count)
    if tol is not None:
        est = cheapest_within([e for e in theory.estimates(t) if e.available], tol, b.name, wobble is not None)
        name, order = est.rung, est.order
        charge(theory.track_cost(name, order, t0, t_end, count, est.free_wobble) + output, b.name)
    else:
        est = theory.named(t, name, order)
        name = name or theory.default_model(order)
    tr = theory.track(est, name, order, t0, step, count)
    with_wobble = wobble is not None and (est is None or est.free_wobble)
    estimate = None if est is None or not est.available else est.total
    info = theory.describe(est, name, order, with_wobble)
    for term in () if est is None else est.unestimated:
        info["warnings"].append(UNESTIMATED_WARNINGS[term])
    _meaningful(b, estimate, info)
    selection = _selection_info(theory, name, order, estimate, 1e3 * (time.perf_counter() - begin), tol,
                                None if est is None else est.terms)
    # the mean obliquity's 1σ from the catalogue's uncertainties (null: unknown), as in precession()
    sigma = _propagated(b, order)["obliquity_deg_uncertainty"] if theory.propagates_uncertainty else None
    ans = _track_answer(b, tr, info, selection, axis, wobble if with_wobble else None, sigma,
                        theory.extra_description())
    return _tag_perturbers(ans, b, per)


#: the warning an answer carries for each error term its estimate could not include
UNESTIMATED_WARNINGS = {
    "orbit_motion": "the real orbit's departure from the fixed Keplerian one was never measured for this body: the "
                    "error estimate treats the given orbit as exact (see docs/accuracy.md)",
    "free_wobble": "no free-wobble amplitude is published for this body: the estimate takes its figure axis to "
                   "coincide with the angular momentum (a relaxed rotator)",
    "rotation_averaging": "without moments of inertia the rotation-averaging error is not estimated",
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


def _track_answer(b: Body, tr, info: dict, selection: dict, axis: str, wobble, obliquity_sigma,
                  extra_model: dict | None = None, perturbers: tuple[str, ...] | None = None) -> dict:
    """The track answer shared by every theory: the arrays of ``tr`` and the ``model`` object ``info``
    completed with the selection, the axis and the free wobble added (``wobble`` or None)."""
    if wobble is not None:
        info["warnings"].append("the free wobble added is a rigid body's; its amplitude and phase are yours, "
                                "and the estimate does not include their uncertainty")
    info.update(selection)
    info["axis"] = axis
    info["free_wobble"] = None if wobble is None else {
        "J_arcsec": wobble.J_arcsec, "phase_deg": wobble.phase_deg, "epoch_jd_tdb": wobble.epoch_jd_tdb}
    info.update(extra_model or {})
    ans = {
        "body": b.name, "dataset": b.dataset,
        "jd_tdb": tr.jd_tdb,
        "psi_arcsec": tr.psi / ARCSEC,
        "delta_psi_arcsec": tr.delta_psi / ARCSEC,
        "delta_epsilon_arcsec": tr.delta_epsilon / ARCSEC,
        "obliquity_deg": np.degrees(tr.obliquity),
        "obliquity_deg_uncertainty": obliquity_sigma,
        "pole_ra_deg": np.degrees(tr.pole_ra),
        "pole_dec_deg": np.degrees(tr.pole_dec),
    }
    if perturbers is not None:
        ans["perturbers"] = list(perturbers)
    ans["model"] = info
    return ans


def track(body: str | int | Body, start, stop, step_days: float, dataset: str = DEFAULT_DATASET,
          order: int | None = None, max_samples: int = MAX_TRACK_SAMPLES, tolerance_mas: float | None = None,
          model: str | None = None, axis: str = "figure", free_wobble_phase_deg: float | None = None,
          free_wobble_J_arcsec: float | None = None, free_wobble_epoch=None, quantities: bool = False,
          perturbers=None) -> dict:
    """Spin-axis track: ψ, Δψ, Δε (arcsec), obliquity and pole RA/Dec (deg) at each epoch.

    ``tolerance_mas`` lets the fidelity ladder (:mod:`ephem.ladder`) pick the cheapest model
    whose pole is estimated within that many milliarcseconds of the truth at every epoch;
    ``model`` (a rung name) and ``order`` choose one explicitly. The answer's ``model``
    reports ``name``, ``order``, ``estimated_error_mas`` and ``cost_ms``.

    ``axis``: "figure" (default; the body's axis of largest inertia, which circles the angular
    momentum by the free wobble) or "angular_momentum". ``free_wobble_phase_deg`` (the figure
    axis's position angle about the angular momentum at ``free_wobble_epoch``, default the pole
    epoch, from the ICRF north through east, with the angular momentum in the body's b2-b3 plane
    then) lets the track add the free wobble when the tolerance needs it (or always, with a named
    model); ``free_wobble_J_arcsec`` overrides the published amplitude.

    ``perturbers`` as :func:`precession`. The Earth with the Moon (its default) is served by the
    ``lunisolar`` model (:mod:`ephem.earth`), whose estimate holds against IAU 2006/2000A over
    1900-2100 (outside, not applicable); ``perturbers="sun"`` gives the single-perturber ladder.

    Times may be astropy ``Time``, unit-named arguments ``Quantity`` (:mod:`ephem.units`);
    ``quantities=True`` returns Quantity arrays and a TDB ``Time`` for ``jd_tdb``.
    """
    ans = track_arrays(body, start, stop, step_days, dataset, order, max_samples, tolerance_mas, model, axis,
                       free_wobble_phase_deg, free_wobble_J_arcsec, free_wobble_epoch, perturbers)
    if quantities:
        return with_units(ans)
    for key in TRACK_KEYS:
        ans[key] = ans[key].tolist()
    return ans


FREE_MOTION_KEYS = ("jd_tdb", "figure_axis_offset_x_arcsec", "figure_axis_offset_y_arcsec",
                    "wobble_angle_J_arcsec", "andoyer_nu_deg")


def free_motion_arrays(body: str | int | Body, start, stop, step_days: float, J_arcsec: float | None = None,
                       method: str = "auto", dataset: str = DEFAULT_DATASET,
                       max_samples: int = MAX_TRACK_SAMPLES) -> dict:
    """The torque-free wobble: the figure axis's offsets from the angular momentum (arcsec) over time,
    the angle J and Andoyer's ν, and the periods (see :mod:`ephem.free_motion`). J defaults to the
    published amplitude (Lara 2014 Table 1: Earth, Moon, Mars, Eros)."""
    from .free_motion import free_motion

    b = resolve_body(body, dataset)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples)
    rotations = step * (count - 1) * 24.0 / b.rotation_period_hours
    charge(cost.Cost((cost.free_rotation(method, count, rotations), cost.serialised(count, len(FREE_MOTION_KEYS)))),
           b.name)
    return free_motion(b, t0 + step * np.arange(count), in_unit(J_arcsec, "arcsec", "J_arcsec"), method)


def free_motion_answer(body: str | int | Body, start, stop, step_days: float, J_arcsec: float | None = None,
                       method: str = "auto", dataset: str = DEFAULT_DATASET, quantities: bool = False) -> dict:
    """As :func:`free_motion_arrays`, with lists (or, with ``quantities=True``, Quantity arrays)."""
    ans = free_motion_arrays(body, start, stop, step_days, J_arcsec, method, dataset)
    if quantities:
        return with_units(ans)
    for key in FREE_MOTION_KEYS:
        ans[key] = np.asarray(ans[key]).tolist()
    return ans


# ----------------------------------------------------------------------------- the Earth under the Moon and the Sun

def _lunisolar_uncertainty(b: Body) -> dict:
    from .uncertainty import SCALAR_KEYS

    inputs = sorted(k for k in b.values if k.split(".")[0] in ("orbit", "pole", "rotation", "inertia"))
    return {"method": "not propagated: ephem.uncertainty replicates the single-perturber (Sun) theory only, so the "
                      "lunisolar answer's 1-sigma uncertainties are unknown (null), not zero; its error against the "
                      "real Earth is the track's estimate (model.estimated_error_mas) and docs/earth.md",
            "dominant_input": {k: None for k in SCALAR_KEYS}, "unpropagated_inputs": inputs,
            "assumptions": ["the lunisolar theory's inputs (the Moon's and the Sun's orbits, GMs) are published "
                            "series without a stated 1-sigma (data/lunisolar.toml)"]}


RATE_KEYS = ("obliquity_deg", "dynamical_ellipticity", "scaling_factor_arcsec_per_year",
             "precession_rate_arcsec_per_year")


def _rates(b: Body, m, unc: dict | None) -> dict:
    """The precession answer's values (Petit et al. Table 4 columns) from a model with obliquity, hd,
    scaling_factor and precession_rate (either theory), and their 1σ from ``unc`` (None: not propagated)."""
    per_year = JULIAN_YEAR_DAYS / ARCSEC
    ans = {"body": b.name, "dataset": b.dataset, "obliquity_deg": math.degrees(m.obliquity),
           "dynamical_ellipticity": m.hd, "scaling_factor_arcsec_per_year": m.scaling_factor * per_year,
           "precession_rate_arcsec_per_year": m.precession_rate * per_year}
    for key in RATE_KEYS:
        ans[f"{key}_uncertainty"] = None if unc is None else unc[f"{key}_uncertainty"]
    return ans


def _lunisolar_precession(b: Body, per: tuple[str, ...], dataset: str, order, tolerance_mas, start: float) -> dict:
    tol = _tolerance(tolerance_mas)
    model_for(b, dataset)                              # applicability (the Moon)
    earth.no_order(b, check_order(order))
    charge(cost.Cost((cost.lunisolar_answer(),)), b.name)
    lm = earth.lunisolar_earth(b, "figure", earth.TRACK_CUT_MAS, per)
    ans = _rates(b, lm, None)
    ans["uncertainty"] = _lunisolar_uncertainty(b)
    ans["perturbers"] = list(per)
    ans["model"] = earth.describe_model(b, per, lm)
    ans["model"]["assumptions"].append("scaling_factor_arcsec_per_year: with several perturbers, 2ψ̇/cos ε̄ (the K "
                                       "of one perturber on a circular orbit in the ecliptic giving the same rate)")
    # the rate does not depend on the nutation's amplitude cut: nothing truncated
    ans["model"].update(_selection_info(LunisolarTheory, "lunisolar", None, 0.0, 1e3 * (time.perf_counter() - start), tol))
    return ans


@lru_cache(maxsize=32)
def _lunisolar_half_peak_to_peak(lm) -> tuple[float, float]:
    """Half the peak-to-peak Δψ, Δε (radians) of a lunisolar series over 1900-2100, sampled every 0.5 d."""
    from .earth import window

    lo, hi = window()
    dpsi, deps = lm.series.nutation_at(np.arange(lo, hi + 0.25, 0.5))
    return 0.5 * float(np.ptp(dpsi)), 0.5 * float(np.ptp(deps))


def _lunisolar_nutation(b: Body, per: tuple[str, ...], dataset: str, order, tolerance_mas, cut_mas,
                        start: float) -> dict:
    from .lunisolar import delaunay_arguments, delaunay_rates

    tol = _tolerance(tolerance_mas)
    model_for(b, dataset)
    earth.no_order(b, check_order(order))
    if tol is not None and cut_mas is not None:
        raise InvalidInputError("cut_mas", "give either cut_mas or tolerance_mas, not both", b.name)
    if cut_mas is not None:
        cut = earth.check_cut(in_unit(cut_mas, "mas", "cut_mas"))
    elif tol is not None:
        cut = earth.cut_for_tolerance(b, tol, "figure", per)
    else:
        cut = earth.TRACK_CUT_MAS
    charge(cost.Cost((cost.lunisolar_answer(),)), b.name)
    lm = earth.lunisolar_earth(b, "figure", cut, per)
    eps = earth.lunisolar_earth(b, "figure", earth.TRACK_CUT_MAS, per).obliquity   # the track's, any cut
    sin_eps = abs(math.sin(eps))
    terms = []
    for t in lm.series.terms:
        term = {"multiple": None, "delaunay_multipliers": list(t["delaunay_multipliers"]),
                "period_days": t["period_days"], "period_years": t["period_days"] / JULIAN_YEAR_DAYS}
        for comp in ("longitude", "obliquity"):
            for part in ("sin", "cos"):
                term[f"{comp}_{part}_arcsec"] = t[f"{comp}_{part}_mas"] / 1e3
        term["period_days_uncertainty"] = None
        for comp in ("longitude", "obliquity"):
            for part in ("sin", "cos"):
                term[f"{comp}_{part}_arcsec_uncertainty"] = None
                term[f"{comp}_{part}_rate_arcsec_per_century"] = t[f"{comp}_{part}_rate_mas_per_century"] / 1e3
            amp = math.hypot(term[f"{comp}_sin_arcsec"], term[f"{comp}_cos_arcsec"])
            term[f"{comp}_amplitude_arcsec"] = amp * (sin_eps if comp == "longitude" else 1.0)
            term[f"{comp}_amplitude_arcsec_uncertainty"] = None
        terms.append(term)
    half_psi, half_eps = _lunisolar_half_peak_to_peak(lm)
    orbit_epoch = b.orbit.epoch_jd_tdb
    omitted = earth.omitted_bound(b, cut, "figure", per)
    info = earth.describe_model(b, per, lm)
    info.update(_selection_info(LunisolarTheory, "lunisolar", None, omitted, 1e3 * (time.perf_counter() - start), tol,
                                {"truncation": omitted}))
    info["cut_mas"] = cut
    info["assumptions"].append("terms: Δψ = Σ (S + Ṡ T) sin φ + (C + Ċ T) cos φ (likewise Δε), φ = the multipliers "
                               "· (l, l′, F, D, Ω), T Julian centuries TDB from J2000; `multiple` is null (no single "
                               "mean anomaly), periods are signed (negative: the argument decreases); "
                               "half peak-to-peak over 1900-2100")
    return {
        "body": b.name, "dataset": b.dataset, "argument": earth.ARGUMENT,
        # the Earth's orbital mean anomaly is l′ (the Sun's mean anomaly seen from the Earth)
        "mean_anomaly_at_epoch_deg": math.degrees(float(delaunay_arguments(orbit_epoch)[1])) % 360.0,
        "orbit_epoch_jd_tdb": orbit_epoch,
        "mean_motion_deg_per_day": math.degrees(float(delaunay_rates((orbit_epoch - 2451545.0) / 36525.0)[1])),
        "obliquity_deg": math.degrees(eps),
        "terms": terms,
        "delta_psi_half_peak_to_peak_arcsec": half_psi / ARCSEC,
        "delta_epsilon_half_peak_to_peak_arcsec": half_eps / ARCSEC,
        "delta_psi_half_peak_to_peak_arcsec_uncertainty": None,
        "delta_epsilon_half_peak_to_peak_arcsec_uncertainty": None,
        "uncertainty": _lunisolar_uncertainty(b),
        "perturbers": list(per),
        "model": info,
    }
