"""The one place answers are rendered: typed results in, the contract's dicts out.

The families compute numbers in radians, rad/day and JD TDB (:mod:`ephem.theory.results`, the
:class:`~ephem.forced.precession_nutation.Track`, :class:`~ephem.longterm.history.HistoryResult`); this module
turns them into the answers the CLI and the service print, with the units in the keys: angles in degrees,
precession and nutation in arcseconds, rates per Julian year (the precession) or per Julian century (the
Poisson terms), estimates in milliarcseconds. A key's name, order and unit are decided here and nowhere else.
"""
from __future__ import annotations

import math
from dataclasses import fields

import numpy as np

from ..base.constants import ARCSEC, JULIAN_YEAR_DAYS, MAS
from ..base.times import calendar_dates
from ..bodies.catalogue import Body
from ..rotation.free_motion import FreeMotion
from ..longterm.history import DESCRIPTIONS as HISTORY_DESCRIPTIONS, HISTORY_ASSUMPTIONS, HistoryResult, total
from ..theory.choice import RULE as CHOICE_RULE, Choice
from ..theory.results import FamilySummary, NutationResult, NutationTerm, PrecessionResult, Selection

#: the precession answer's values (Petit et al. Table 4 columns)
RATE_KEYS = ("obliquity_deg", "dynamical_ellipticity", "scaling_factor_arcsec_per_year",
             "precession_rate_arcsec_per_year")
#: arcsec per Julian year from rad/day
_PER_YEAR = JULIAN_YEAR_DAYS / ARCSEC


def _arcsec(x: float | None) -> float | None:
    return None if x is None else x / ARCSEC


def calendar_key(time_scale: str) -> str:
    """The key of an answer's calendar dates in ``time_scale`` (``utc_iso``, ``tt_iso``, ``tdb_iso``): the scale
    in the name, as a unit is in the others'."""
    return f"{time_scale}_iso"


def _with_dates(ans: dict, time_scale: str | None) -> dict:
    """``ans`` with its epochs' calendar dates in ``time_scale`` (ISO 8601 to the millisecond,
    :func:`ephem.base.times.calendar_dates`) right after ``jd_tdb``; unchanged for None (a figure's or a kernel's
    track, which no person reads)."""
    if time_scale is None:
        return ans
    out = {}
    for key, value in ans.items():
        out[key] = value
        if key == "jd_tdb":
            out[calendar_key(time_scale)] = calendar_dates(value, time_scale)
    return out


def selection(s: Selection) -> dict:
    """The selection part of an answer's ``model`` object (estimates in mas)."""
    return {"name": s.name, "order": s.order, "description": s.description,
            "estimated_error_mas": None if s.estimate is None else s.estimate / MAS, "estimate_covers": s.covers,
            "error_terms_mas": None if s.terms is None else {k: v / MAS for k, v in s.terms.items()},
            "tolerance_mas": None if s.tolerance is None else float(f"{s.tolerance / MAS:.12g}"),
            "cost_ms": s.cost_ms,
            "axis": None, "free_wobble": None, "rotation_scale": None,   # tracks only
            "cut_mas": s.cut_mas}                # the lunisolar and libration series only


def _model(description: dict, s: Selection) -> dict:
    model = dict(description)
    model.update(selection(s))
    return model


def family_summary(s: FamilySummary) -> dict:
    """A family's own summary (the Moon's Cassini state), each field by the unit it declares
    (:func:`ephem.theory.results.quantity`): an angle in degrees (``_deg``), a rate in degrees per Julian year
    (``_deg_per_year``, and its period in years where it names the key), any other number as it is."""
    out = {}
    for f in fields(s):
        value, unit = getattr(s, f.name), f.metadata.get("unit")
        if unit == "rad":
            out[f"{f.name}_deg"] = math.degrees(value)
        elif unit == "rad/day":
            out[f"{f.name}_deg_per_year"] = math.degrees(value) * JULIAN_YEAR_DAYS
            if f.metadata.get("period"):
                out[f.metadata["period"]] = 2.0 * math.pi / abs(value) / JULIAN_YEAR_DAYS
        else:
            out[f.name] = value
    return out


#: the catalogue inputs (by key prefix) that move each value: where one of them has no σ, the value's σ is a lower
#: bound (it covers only the inputs that have one)
_ORBIT_SHAPE, _ORBIT_PLANE = ("orbit.a", "orbit.e"), ("orbit.i", "orbit.node")
_ALL_INPUTS = (*_ORBIT_SHAPE, *_ORBIT_PLANE, "orbit.peri", "pole.", "rotation.", "inertia.")
_MOVED_BY = {"obliquity_deg": (*_ORBIT_PLANE, "pole."), "dynamical_ellipticity": ("inertia.",),
             "scaling_factor_arcsec_per_year": (*_ORBIT_SHAPE, "rotation.", "inertia."),
             "precession_rate_arcsec_per_year": (*_ORBIT_SHAPE, *_ORBIT_PLANE, "pole.", "rotation.", "inertia."),
             "delta_psi_half_peak_to_peak_arcsec": _ALL_INPUTS, "delta_epsilon_half_peak_to_peak_arcsec": _ALL_INPUTS,
             "terms": _ALL_INPUTS}
_MOVED_BY["observable_precession_rate_arcsec_per_year"] = _MOVED_BY["precession_rate_arcsec_per_year"]
#: the inputs' names in a sentence, by key prefix (the first that matches), and the measurements moments derive from
_INPUT_NAMES = (("orbit.", "the orbit"), ("pole.", "the pole"), ("rotation.", "the rotation period"),
                ("inertia.dynamical_ellipticity", "H_d"), ("inertia.", "the moments of inertia"))
_DERIVED_NAMES = {"polar_moment": "C/MR²", "mean_moment": "(A+B+C)/3MR²", "beta": "β", "gamma": "γ"}
_PLURAL = ("the moments of inertia",)


def _names(b: Body, keys: list[str], without: bool) -> list[str]:
    names: list[str] = []
    for key in keys:
        name = next(n for prefix, n in _INPUT_NAMES if key.startswith(prefix))
        if name == "the moments of inertia" and without:   # the measurement they derive from that has no σ
            lacking = [k.rsplit(".", 1)[1] for k, v in b.values.items()
                       if k.startswith("inertia.derived_from.") and v.uncertainty is None]
            if lacking:
                names += [n for n in (_DERIVED_NAMES.get(k, k) for k in lacking) if n not in names]
                continue
        if name not in names:
            names.append(name)
    return names


def _listed(names: list[str]) -> str:
    """'a', 'a and b', 'a, b and c', with the verb's number: ('the pole', 'has')."""
    text = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
    return f"{text} {'has' if len(names) == 1 and names[0] not in _PLURAL else 'have'}"


def lower_bounds(b: Body, uncertainty: dict, sigmas: dict) -> dict:
    """{value key: why its 1σ is a lower bound} for each value given a σ that an input without one also moves:
    "only the rotation period has a σ; the orbit, the pole and C/MR² have none" (``sigmas``: the values' σ, None
    where unknown; ``terms`` for the nutation terms')."""
    missing = set(uncertainty.get("unpropagated_inputs") or ())
    inputs = [k for k in b.values if not k.endswith(".epoch") and not k.startswith("inertia.derived_from.")
              and k.startswith(_ALL_INPUTS)]
    if "inertia.dynamical_ellipticity" in b.values:      # H_d given: the moments are not what sets it
        inputs = [k for k in inputs if k not in ("inertia.A", "inertia.B", "inertia.C")]
    out = {}
    for key, sigma in sigmas.items():
        if sigma is None:
            continue
        moved = [k for k in inputs if k.startswith(_MOVED_BY[key])]
        without = [k for k in moved if k in missing]
        if not without:
            continue
        having = [k for k in moved if k not in missing and b.values[k].uncertainty is not None]
        dominant = (uncertainty.get("dominant_input") or {}).get(key)
        if not having and dominant:
            having = [dominant]
        have, lack = _names(b, having, False), _names(b, without, True)
        out[key] = (f"only {_listed(have)} a σ; " if have else "") + f"{_listed(lack)} none"
    return out


def precession(r: PrecessionResult) -> dict:
    """The precession answer: obliquity (deg), H_d, K and ψ̇ (arcsec/yr), each with its 1σ (null: unknown),
    the family's own summary (a synchronous satellite's Cassini state), the uncertainty's method and the ``model``
    object."""
    b, s = r.body, r.sigmas
    ans = {"body": b.name, "dataset": b.dataset, "obliquity_deg": math.degrees(r.obliquity),
           "dynamical_ellipticity": r.dynamical_ellipticity,
           "scaling_factor_arcsec_per_year": r.scaling_factor * _PER_YEAR,
           "precession_rate_arcsec_per_year": r.precession_rate * _PER_YEAR}
    sigmas = (None, None, None, None) if s is None else (
        None if s.obliquity is None else math.degrees(s.obliquity), s.dynamical_ellipticity,
        None if s.scaling_factor is None else s.scaling_factor * _PER_YEAR,
        None if s.precession_rate is None else s.precession_rate * _PER_YEAR)
    for key, sigma in zip(RATE_KEYS, sigmas):
        ans[f"{key}_uncertainty"] = sigma
    # what radio tracking measures: the torque's rate less the geodesic precession (the same ψ sense as the track)
    geodesic = None if r.geodesic_rate is None else r.geodesic_rate * _PER_YEAR
    ans["geodesic_precession_rate_arcsec_per_year"] = geodesic
    ans["geodesic_precession_in_rate"] = None if geodesic is None else r.geodesic_in_rate
    ans["observable_precession_rate_arcsec_per_year"] = None if geodesic is None else \
        ans["precession_rate_arcsec_per_year"] - (0.0 if r.geodesic_in_rate else geodesic)
    ans["observable_precession_rate_arcsec_per_year_uncertainty"] = None if geodesic is None else \
        ans["precession_rate_arcsec_per_year_uncertainty"]
    if r.summary is not None:
        ans[r.summary.answer_key] = family_summary(r.summary)
    ans["uncertainty"] = {**r.uncertainty, "lower_bounds": lower_bounds(
        b, r.uncertainty, {k: ans.get(f"{k}_uncertainty") for k in (*RATE_KEYS,
                                                                    "observable_precession_rate_arcsec_per_year")})}
    ans["model"] = _model(r.description, r.selection)
    return ans


def _term(t: NutationTerm, longitude_factor: float) -> dict:
    term = {"multiple": t.multiple}
    if t.delaunay_multipliers is not None:
        term["delaunay_multipliers"] = list(t.delaunay_multipliers)
    term["period_days"] = t.period_days
    term["period_years"] = t.period_days / JULIAN_YEAR_DAYS
    for comp in ("longitude", "obliquity"):
        for part in ("sin", "cos"):
            term[f"{comp}_{part}_arcsec"] = getattr(t, f"{comp}_{part}") / ARCSEC
    term["period_days_uncertainty"] = t.period_days_sigma
    for i, comp in enumerate(("longitude", "obliquity")):
        for j, part in enumerate(("sin", "cos")):
            term[f"{comp}_{part}_arcsec_uncertainty"] = _arcsec(getattr(t, f"{comp}_{part}_sigma"))
            if t.rates is not None:
                term[f"{comp}_{part}_rate_arcsec_per_century"] = t.rates[2 * i + j] / ARCSEC
        # the paper's Amp: (Sin² + Cos²)^½, in longitude times sin ε where Δψ runs along the ecliptic
        amp = math.hypot(term[f"{comp}_sin_arcsec"], term[f"{comp}_cos_arcsec"])
        term[f"{comp}_amplitude_arcsec"] = amp * (longitude_factor if comp == "longitude" else 1.0)
        term[f"{comp}_amplitude_arcsec_uncertainty"] = _arcsec(getattr(t, f"{comp}_amplitude_sigma"))
    return term


def nutation(r: NutationResult) -> dict:
    """The nutation answer: the terms (arcsec, periods in days and years, 1σ, Poisson rates per century where
    the series has them), the argument, the half peak-to-peak Δψ and Δε with their 1σ, the uncertainty's
    method and the ``model`` object."""
    b = r.body
    (half_psi, half_eps), (sigma_psi, sigma_eps) = r.half_peak_to_peak, r.half_peak_to_peak_sigma
    return {
        "body": b.name, "dataset": b.dataset, "argument": r.argument,
        "mean_anomaly_at_epoch_deg": math.degrees(r.mean_anomaly_at_epoch) % 360.0,
        "orbit_epoch_jd_tdb": r.orbit_epoch_jd_tdb,
        "mean_motion_deg_per_day": math.degrees(r.mean_motion),
        "obliquity_deg": math.degrees(r.obliquity),
        "terms": [_term(t, r.longitude_amplitude_factor) for t in r.terms],
        # what the amplitudes are: a factor of 1 is a Δψ that is the pole's displacement already (the Moon's σ)
        "amplitude_quantities": {"longitude_amplitude_arcsec": "Δψ" if r.longitude_amplitude_factor == 1.0
                                 else "Δψ sin ε", "obliquity_amplitude_arcsec": "Δε"},
        "delta_psi_half_peak_to_peak_arcsec": half_psi / ARCSEC,
        "delta_epsilon_half_peak_to_peak_arcsec": half_eps / ARCSEC,
        "delta_psi_half_peak_to_peak_arcsec_uncertainty": _arcsec(sigma_psi),
        "delta_epsilon_half_peak_to_peak_arcsec_uncertainty": _arcsec(sigma_eps),
        "uncertainty": {**r.uncertainty, "lower_bounds": lower_bounds(b, r.uncertainty, {
            "delta_psi_half_peak_to_peak_arcsec": sigma_psi, "delta_epsilon_half_peak_to_peak_arcsec": sigma_eps,
            "terms": next((x for t in r.terms for x in (t.longitude_amplitude_sigma, t.obliquity_amplitude_sigma)
                           if x is not None), None)})},
        "model": _model(r.description, r.selection),
    }


def moon_left_out(b: Body, per: tuple[str, ...]) -> list[str]:
    """The warning a single-perturber answer carries when the catalogue gives the body the Moon too."""
    if "Moon" not in b.perturbers or "Moon" in per:
        return []
    return [f"perturbers={','.join(per)} leaves out the Moon, which the catalogue lists for {b.name}: this is the "
            f"Sun's part of the motion only (about a third of the Earth's precession), and its error estimate is "
            f"against a Sun-only {b.name}, not the real one"]


def with_perturbers(ans: dict, b: Body, per: tuple[str, ...]) -> dict:
    """``ans`` with the request's perturbers, before the ``model`` object (which closes every answer) and in it,
    and the warning when they leave out the Moon."""
    model = ans.pop("model")
    ans["perturbers"] = list(per)
    ans["model"] = model
    ans["model"]["perturbers"] = list(per)
    ans["model"]["warnings"].extend(moon_left_out(b, per))
    return ans


def track(b: Body, tr, info: dict, s: Selection, axis: str, wobble, obliquity_sigma_deg: float | None,
          pole_sigma, cut_mas: float | None = None, rotation_scale: dict | None = None,
          time_scale: str | None = None) -> dict:
    """The track answer shared by every theory: the arrays of ``tr`` (numpy; ψ, Δψ, Δε in arcsec, the
    obliquity and the pole in degrees) and the ``model`` object ``info`` completed with the selection, the
    axis and the free wobble added (``wobble`` or None); the mean obliquity's 1σ (``obliquity_sigma_deg``, as
    :func:`ephem.forced.uncertainty.propagated` gives it) and the pole's at each epoch (``pole_sigma``,
    radians), each None where unknown; ``cut_mas``: the amplitude cut of the track's series (None: not cut by
    amplitude); ``rotation_scale``: the rotation-scale terms modelled and the phase given; ``time_scale``: the scale
    of the calendar dates beside ``jd_tdb`` (``utc_iso`` for UTC; None: none)."""
    if wobble is not None:
        info["warnings"].append("the free wobble added is a rigid body's; its amplitude and phase are yours, "
                                "and the estimate does not include their uncertainty")
    info.update(selection(s))
    if rotation_scale is not None:
        info["rotation_scale"] = rotation_scale
    info["axis"] = axis
    info["free_wobble"] = None if wobble is None else {
        "J_arcsec": wobble.J_arcsec, "phase_deg": wobble.phase_deg, "epoch_jd_tdb": wobble.epoch_jd_tdb}
    info["cut_mas"] = cut_mas
    return _with_dates({
        "body": b.name, "dataset": b.dataset,
        "jd_tdb": tr.jd_tdb,
        "psi_arcsec": tr.psi / ARCSEC,
        "delta_psi_arcsec": tr.delta_psi / ARCSEC,
        "delta_epsilon_arcsec": tr.delta_epsilon / ARCSEC,
        "obliquity_deg": np.degrees(tr.obliquity),
        "obliquity_deg_uncertainty": obliquity_sigma_deg,
        "pole_ra_deg": np.degrees(tr.pole_ra),
        "pole_dec_deg": np.degrees(tr.pole_dec),
        "pole_uncertainty_deg": None if pole_sigma is None else np.degrees(pole_sigma),
        "model": info,
    }, time_scale)


def history(r: HistoryResult) -> dict:
    """The history answer: arrays ``year``, ``obliquity_deg``, ``precession_angle_deg``, ``pole_ra_deg``,
    ``pole_dec_deg`` (ICRF), ``orbit_inclination_deg`` (to the J2000 ecliptic), ``estimated_error_deg`` and
    ``obliquity_error_deg`` (numpy), where the history stops meaning anything (years; null: not limited within
    the span) and the ``model`` object (estimates in mas, the largest over the epochs)."""
    b, h = r.body, r.history
    error = r.error
    model = {
        "name": r.orbit_model, "description": HISTORY_DESCRIPTIONS[r.orbit_model],
        "theory": r.theory, "spin": r.spin,
        "orbit": {"model": r.orbit_model, "source": r.orbit_source,
                  "horizon_years": None if r.orbit_horizon_years is None else list(r.orbit_horizon_years)},
        "estimated_error_mas": float(np.max(error)) / MAS,
        "error_terms_mas": {k: float(np.max(v)) / MAS for k, v in r.terms.items()},
        "obliquity_error_terms_mas": {k: float(np.max(v)) / MAS for k, v in h.obliquity_terms.items()},
        "probed_terms": list(h.unestimated),
        "estimates_mas": {k: float(np.max(total(v))) / MAS for k, v in r.estimates.items()},
        "tolerance_mas": None if r.tolerance is None else r.tolerance / MAS,
        "cost_ms": r.cost_ms,
        "assumptions": list(HISTORY_ASSUMPTIONS),
        "warnings": list(r.warnings),
    }
    if r.selection is not None:     # how the orbit model was chosen: each one examined, as the choice saw it
        model["rule"], model["why_chosen"] = r.selection.rule, r.selection.reason
        model["candidates"] = [{
            "name": k.name, "available": k.why_not is None, "why_not": k.why_not,
            "estimated_error_mas": None if k.estimate is None else k.estimate / MAS,
            "estimated_cpu_ms": None if k.cost_s is None else 1e3 * k.cost_s,
            "eligible": k.eligible, "chosen": k.chosen,
        } for k in r.selection.candidates]
    start, stop = r.meaningful
    return {
        "body": b.name, "dataset": b.dataset,
        "year": r.years,
        "obliquity_deg": np.degrees(h.obliquity),
        "precession_angle_deg": np.degrees(h.precession_angle),
        "pole_ra_deg": np.degrees(h.pole_ra),
        "pole_dec_deg": np.degrees(h.pole_dec),
        "orbit_inclination_deg": np.degrees(h.orbit_inclination),
        "estimated_error_deg": np.degrees(error),
        "obliquity_error_deg": np.degrees(r.obliquity_error),
        "meaningful_from_year": None if math.isinf(start) else start,
        "meaningful_to_year": None if math.isinf(stop) else stop,
        "model": model,
    }


def free_motion(r: FreeMotion, time_scale: str | None = None) -> dict:
    """The free-motion answer: the figure axis's offsets from the angular momentum and the angle J (arcsec),
    Andoyer's ν (deg), the periods (days), the mode and the method (numpy arrays); with ``time_scale``, the epochs'
    calendar dates in it beside ``jd_tdb``."""
    b = r.body
    return _with_dates({
        "body": b.name, "dataset": b.dataset, "jd_tdb": r.jd_tdb,
        "figure_axis_offset_x_arcsec": np.ascontiguousarray(r.figure_axis_offsets[:, 0] / ARCSEC),
        "figure_axis_offset_y_arcsec": np.ascontiguousarray(r.figure_axis_offsets[:, 1] / ARCSEC),
        "wobble_angle_J_arcsec": np.degrees(r.wobble_angle) * 3600.0, "andoyer_nu_deg": np.degrees(r.andoyer_nu),
        "wobble_period_days": r.wobble_period_days, "precession_period_days": r.precession_period_days,
        "mode": r.mode, "method": r.method, "J_arcsec": r.J_arcsec,
        "moments_over_C": list(r.moments_over_C), "cost_ms": r.cost_ms,
    }, time_scale)


def choice(c: Choice) -> dict:
    """A track's ``model.choice``: the rule, why the chosen model won, and what was eligible: every model whose
    estimate met the tolerance, in the family's order, with its estimate (mas), predicted CPU ms and MB and whether
    it was chosen (the models estimated beyond the tolerance are named in ``reason``; every model, eligible or not,
    is in the comparison, ``GET .../track/models``)."""
    return {"rule": CHOICE_RULE, "reason": c.reason, "eligible": [{
        "name": k.rung, "order": k.order, "free_wobble": k.free_wobble, "rotation_scale": k.rotation_scale,
        "estimated_error_mas": k.estimate.total / MAS, "estimated_cpu_ms": 1e3 * k.cost.cpu_s,
        "estimated_memory_mb": k.cost.memory_mb, "chosen": k.estimate is c.chosen,
    } for k in c.candidates if k.eligible]}


def _why(e, c, chosen, tolerance: float | None) -> str:
    """Why one model of the comparison is (or is not) eligible, or chosen."""
    if not e.available:
        return f"cannot serve these epochs: {e.why_not}"
    if c is None:
        return "no cost can be predicted for it here"
    if tolerance is None:
        return "available (no tolerance given: every available model is eligible)"
    if e.total > tolerance:
        return f"estimated {e.total / MAS:.4g} mas, beyond the tolerance of {tolerance / MAS:.6g} mas"
    if chosen is not None and e is chosen.chosen:
        return "chosen: " + chosen.reason
    return f"within the tolerance ({e.total / MAS:.4g} mas), predicted dearer ({1e3 * c.cpu_s:.3g} ms)" + (
        "" if chosen is None else f" than the chosen {chosen.chosen.rung} or less accurate at a tied cost")


def track_models(b: Body, theory, estimates, costs, chosen: Choice | None, tolerance: float | None,
                 epochs: tuple) -> dict:
    """The speed-against-accuracy answer: each model's estimate (mas, by term) and predicted cost (CPU ms, MB)
    over the request's epochs, in the family's order, whether it is eligible (available, and within the tolerance
    where one is given) and why; ``chosen`` the choice the tolerance makes (None: none given, or none within it),
    as a track makes it (:func:`ephem.theory.choice.choose`)."""
    t0, t1, count = epochs
    models = []
    for e, c in zip(estimates, costs):
        eligible = e.available and c is not None and (tolerance is None or e.total <= tolerance)
        models.append({
            "name": e.rung, "order": e.order, "description": theory.descriptions.get(e.rung, ""),
            "available": e.available, "why_not": e.why_not,
            "estimated_error_mas": e.total / MAS if e.available else None,
            "error_terms_mas": {k: v / MAS for k, v in e.terms.items()} if e.available else None,
            "free_wobble": e.free_wobble, "rotation_scale": e.rotation_scale,
            "estimated_cpu_ms": None if c is None else 1e3 * c.cpu_s,
            "estimated_memory_mb": None if c is None else c.memory_mb,
            "eligible": eligible, "why": _why(e, c, chosen, tolerance),
            "chosen": chosen is not None and e is chosen.chosen,
        })
    return {"body": b.name, "dataset": b.dataset, "perturbers": list(theory.perturbers), "theory": theory.summary,
            "start_jd_tdb": t0, "stop_jd_tdb": t1, "epochs": count,
            "tolerance_mas": None if tolerance is None else float(f"{tolerance / MAS:.12g}"),
            "rule": CHOICE_RULE,
            "chosen": None if chosen is None else chosen.chosen.rung,
            "chosen_order": None if chosen is None else chosen.chosen.order,
            "why_chosen": None if chosen is None else chosen.reason, "models": models}
