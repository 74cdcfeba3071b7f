"""Publication-quality plots of spin-axis tracks and of the free wobble (matplotlib, PNG and SVG).

Five kinds (:data:`KINDS`):

``precession``
    Petit, Souchay & Lhotka (2014) Fig. 4: the motion in longitude ψ = precession + Δψ against
    time (top panel, with the precession alone dashed), and its nutation part Δψ (bottom panel).
    ψ in arcsec, or in degrees once |ψ| reaches 10°; Δψ in arcsec, or in mas below 1″.
``nutation-loop``
    Petit et al. (2014) Fig. 5: the nutation of the pole projected onto the equatorial plane,
    Δψ sin ε (horizontal) against Δε (vertical), same unit on both axes (arcsec, or mas when the
    loop is under 1″), equal aspect (unless one amplitude exceeds the other more than
    :data:`LOOP_ASPECT_LIMIT` times: then each axis has its own scale, as in the paper, and a note
    on the plot says so), an arrow from the first epoch in the direction of motion.
    ε is the obliquity at each epoch.
``obliquity``
    The obliquity ε(t) against time (Petit et al. 2014 has no figure of it; its conclusion
    speaks of "the evolution of the obliquity and precession", Table 4 gives ε): in degrees when
    it moves by 0.5° or more, otherwise as the offset from a reference value ε₀ (the mean rounded
    to 1e-6°, printed in the axis label) in arcsec, or mas below 1″.
``free-wobble``
    The torque-free rigid-body wobble (:mod:`ephem.rotation.free_motion`; Lara 2014): left, the figure
    axis's path about the angular momentum L in space (offsets along the inertial x and y axes,
    z along L); right, L's path about the figure axis in the body frame (J sin ν along the body's
    A axis, J cos ν along its B axis), which closes once per wobble period. Arcsec (mas below
    1″, degrees from 1°), equal aspect. This one is not in Petit et al. (2014), which takes J = 0.
``obliquity-history``
    The obliquity over millennia to millions of years (:func:`ephem.answers.requests.history`: the spin equation
    averaged over the rotation and the orbit, along a secular or N-body orbit): ε in degrees with the
    band ε ± ``obliquity_error_deg`` shaded (the answer's 1-σ-like estimate), and below it the orbit's
    inclination to the J2000 ecliptic. The part of the span outside [``meaningful_from_year``,
    ``meaningful_to_year``], where neighbouring solutions or orbits part by more than a degree, is
    hatched grey, and the legend says so. For this kind ``start``/``stop`` are Julian years from
    J2000.0 TDB (numbers or numeric strings; negative is the past) and the step is ``step_years``
    (default :func:`default_step_years`); the time axis is in years from J2000.0 (TDB), in kyr, or in
    Myr from a span of 1 Myr (yr below 2 kyr).

Time axes (tracks; ``obliquity-history`` has its own, above): the Julian epoch in TDB, 2000 + (JD_TDB − 2451545)/365.25 years, when the
span reaches one Julian year (within about a day of the calendar decimal year from 1900 to 2100:
J2000.0 is 2000 January 1.5 and the Julian year is 365.25 d against the Gregorian 365.2425 d);
days since the first epoch otherwise.

Figures are built on :class:`matplotlib.figure.Figure` with the Agg canvas, never through
pyplot's global state, so :func:`figure` and :func:`render` may run in several threads at once.

Entry points: :func:`figure` (a Figure), :func:`render` (PNG or SVG bytes; :data:`CONTENT_TYPES`
gives the media types), :func:`default_step_days`, :func:`default_step_years`, and :func:`regenerate_doc_figures` (the
example figures of ``docs/plots.md``); the work-precision chart of a request, every model's estimated error against
its predicted cost: :func:`track_models_chart` (from the request) and :func:`models_chart` (from its
``track_models`` answer).
"""
from __future__ import annotations

import gc
import io
import math
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

# the answers through their module, as tests patch them there (tests/answers/test_figures.py)
from . import requests as answers
from ..base.errors import InvalidInputError, count_text
from ..base.grids import SAFE_SPACINGS, resolution
from ..base.times import to_jd_tdb
from ..bodies.catalogue import DEFAULT_DATASET, Body, resolve_body
from ..longterm.history import MAX_SPAN_YEARS
from ..orbit.kepler import mean_motion_rad_per_day
from ..rotation.free_motion import free_motion
from ..exports.plot_drawing import (draw_free_wobble, draw_nutation_loop, draw_obliquity, draw_obliquity_history,
                           draw_precession, new_figure, period_text)
from ..exports import work_precision
from ..base.budget import Cost, Part, charge
from .requests import Epoch
from ..theory.requests import TrackRequest
from .parameters import entries, shared_parameters

if TYPE_CHECKING:       # the types of the annotations only: matplotlib loads with the first figure
    from astropy.units import Quantity
    from matplotlib.figure import Figure

#: The kinds of plot, as ``figure(kind, …)`` takes them.
KINDS = ("precession", "nutation-loop", "obliquity", "free-wobble", "obliquity-history")
#: The kind whose start/stop are Julian years from J2000.0 (TDB) and whose step is ``step_years``.
HISTORY_KIND = "obliquity-history"
#: Output formats of :func:`render` and their media (Content-Type) types.
CONTENT_TYPES = {"png": "image/png", "svg": "image/svg+xml"}
#: Most epochs one plot draws (the drawing cost and the SVG size grow with them).
MAX_PLOT_POINTS = 100_000
#: Resolution range accepted by :func:`render`, dots per inch.
DPI_RANGE = (30, 300)
#: Default resolution of :func:`render`.
DEFAULT_DPI = 100

#: Default sampling: about this many epochs over the span ...
_TARGET_POINTS = 2000
#: ... but at least this many per orbit (tracks) ...
_PER_ORBIT = 100
#: ... or per cycle of the fastest free-wobble motion (the figure axis about L in space: the step
#: divides that period exactly, so every cycle is drawn through the same 64 vertices).
_PER_CYCLE = 64
#: Fewer samples per cycle than this alias the free wobble's cone: refused.
_MIN_PER_CYCLE = 8
_TRACK_OPTIONS = ("tolerance_mas", "model", "order", "axis", "free_wobble_phase_deg", "free_wobble_J_arcsec",
                  "free_wobble_epoch")
_WOBBLE_OPTIONS = ("J_arcsec", "method")
_HISTORY_OPTIONS = ("step_years", "orbit_model", "perturbers")
#: ``obliquity-history``: the default step aims at about this many epochs ...
_HISTORY_TARGET_POINTS = 1000
#: ... rounded to a nice number of years, and never below this many years
MIN_DEFAULT_STEP_YEARS = 100.0


# --- inputs ---------------------------------------------------------------------------------------

def _check_kind(kind) -> str:
    if kind not in KINDS:
        raise InvalidInputError("kind", f"must be one of {', '.join(KINDS)}, got {kind!r}")
    return kind


def _check_options(kind: str, options: dict) -> None:
    """Refuse an option given (not None/default) to a kind it does not apply to."""
    if kind == HISTORY_KIND:
        if options.get("step_days") is not None:
            raise InvalidInputError("step_days", f"{HISTORY_KIND} samples in Julian years: give step_years")
        wrong = [k for k in ("model", "order", "J_arcsec", "method", *_TRACK_OPTIONS[3:])
                 if options.get(k) not in (None, "auto", "figure")]
        if wrong:
            raise InvalidInputError(wrong[0], f"does not apply to kind {HISTORY_KIND} (its options: tolerance_mas, "
                                    "orbit_model, perturbers, step_years)")
        return
    wrong = [k for k in _HISTORY_OPTIONS if options.get(k) is not None]
    if wrong:
        raise InvalidInputError(wrong[0], f"applies to kind {HISTORY_KIND}, not to {kind}")
    if kind == "free-wobble":
        wrong = [k for k in _TRACK_OPTIONS if options.get(k) not in (None, "figure")]
        if wrong:
            raise InvalidInputError(wrong[0], "applies to the track kinds (precession, nutation-loop, obliquity), "
                                    "not to free-wobble")
    else:
        wrong = [k for k in _WOBBLE_OPTIONS if options.get(k) not in (None, "auto")]
        if wrong:
            raise InvalidInputError(wrong[0], f"applies to kind free-wobble, not to {kind}")


def _span(start, stop) -> tuple[float, float]:
    t0, t1 = to_jd_tdb(start, "start"), to_jd_tdb(stop, "stop")
    if t1 < t0:
        raise InvalidInputError("stop", f"stop (JD {t1}) is before start (JD {t0})")
    if t1 == t0:
        raise InvalidInputError("stop", "a plot needs a time span: stop equals start")
    least = SAFE_SPACINGS * resolution(t0, t1)
    if t1 - t0 < least:
        raise InvalidInputError("stop", f"a plot needs a time span float64 Julian dates resolve into two epochs: "
                                f"stop is {t1 - t0:.4g} d after start, at least {least:.4g} d is needed")
    return t0, t1


def _orbital_period_days(b) -> float:
    return 2.0 * math.pi / mean_motion_rad_per_day(b.orbit.a_au, b.orbit.center)


def _wobble_periods(b, t0: float, J_arcsec, method: str) -> tuple[float, float]:
    """(wobble, precession) periods in days, from the free-motion module at one epoch (this also
    raises the clear J_arcsec error for a body without a published amplitude)."""
    one = free_motion(b, np.array([t0]), J_arcsec, method)
    return float(one.wobble_period_days), float(one.precession_period_days)


def _fastest_wobble_period(periods: tuple[float, float]) -> float:
    finite = [p for p in periods if math.isfinite(p) and p > 0.0]
    return min(finite) if finite else math.inf


def default_step_days(kind: str, body: str | int | Body, start: Epoch, stop: Epoch, *,
                      J_arcsec: float | Quantity | None = None, method: str = "auto") -> float:
    """The step (days) :func:`figure` uses when none is given.

    Tracks: about 2000 epochs over the span, but at least 100 per orbit (the nutation's shortest
    terms, M/6, keep ~16 samples per cycle). Free wobble: 64 epochs per cycle of the faster of the
    wobble and the figure axis's precession about L (23.9 h for the Earth). Either way no more than
    :data:`MAX_PLOT_POINTS` epochs; a free-wobble span too long to resolve within that cap is refused
    (``stop``), since a coarser step would alias the cone.

    Parameters
    ----------
    kind : str
        One of :data:`KINDS` but ``obliquity-history`` (see :func:`default_step_years`).
    body : str, int or Body
        The body: a name (any case) or NAIF id of the current catalogue, or a :class:`~ephem.bodies.catalogue.Body`
        (a catalogue's, with its dataset, or the user's own).
    start, stop : str, float or astropy.time.Time
        The span: ISO 8601 text (UTC unless a scale is named), a JD TDB or a ``Time``.
    J_arcsec : float or Quantity, optional
        ``free-wobble``: the wobble's amplitude, arcseconds (default the published one).
    method : str
        ``free-wobble``: "auto" (default), "series" or "numeric".

    Returns
    -------
    float
        The step, days: never finer than the span's Julian dates resolve.
    """
    _check_kind(kind)
    if kind == HISTORY_KIND:
        raise InvalidInputError("kind", f"{HISTORY_KIND} samples in Julian years: see default_step_years")
    b = resolve_body(body)
    t0, t1 = _span(start, stop)
    span = t1 - t0
    if kind == "free-wobble":
        fast = _fastest_wobble_period(_wobble_periods(b, t0, J_arcsec, method))
        step = min(fast / _PER_CYCLE, span / _TARGET_POINTS) if math.isfinite(fast) else span / _TARGET_POINTS
        if span / step + 1 > MAX_PLOT_POINTS:
            step = span / (MAX_PLOT_POINTS - 1)
            if step > fast / _MIN_PER_CYCLE:
                longest = fast / _MIN_PER_CYCLE * (MAX_PLOT_POINTS - 1)
                raise InvalidInputError("stop", f"a span of {span:.6g} d cannot be drawn within {MAX_PLOT_POINTS} "
                                        f"points at {_MIN_PER_CYCLE} per {period_text(fast)} cycle of the free "
                                        f"wobble; use a span of at most {longest:.6g} d", b.name)
        return max(step, SAFE_SPACINGS * resolution(t0, t1))    # a step the span's dates resolve
    step = min(span / _TARGET_POINTS, _orbital_period_days(b) / _PER_ORBIT)
    if span / step + 1 > MAX_PLOT_POINTS:
        step = span / (MAX_PLOT_POINTS - 1)
    return max(step, SAFE_SPACINGS * resolution(t0, t1))


def _year(value, field: str) -> float:
    """A Julian year from J2000.0 TDB: a finite number, or a string holding one ("-3e6")."""
    v = value
    if isinstance(v, str):
        text = v.strip().replace("\u2212", "-")       # a typographic minus, as copied from a document
        try:
            v = float(text)
        except ValueError:
            raise InvalidInputError(field, f"{HISTORY_KIND} takes Julian years from J2000.0 TDB (a number such as "
                                    f"-3e6), got {value!r}") from None
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not math.isfinite(v):
        raise InvalidInputError(field, f"must be a finite number of Julian years from J2000.0 TDB, got {value!r}")
    return float(v)


def _year_span(start, stop) -> tuple[float, float]:
    y0, y1 = _year(start, "start"), _year(stop, "stop")
    if y1 <= y0:
        raise InvalidInputError("stop", f"must be after start ({y1:g} <= {y0:g} years from J2000.0): a plot "
                                "needs a time span")
    if y1 - y0 > MAX_SPAN_YEARS:
        raise InvalidInputError("stop", f"the span {y1 - y0:.4g} years exceeds {MAX_SPAN_YEARS:.3g} years: no orbit "
                                "of the solar system is known beyond ~20 Myr")
    return y0, y1


def _nice(x: float) -> float:
    """The number of the form {1, 2, 2.5, 5} x 10^k nearest to x > 0 (in ratio)."""
    k = math.floor(math.log10(x))
    candidates = [m * 10.0 ** e for e in (k - 1, k, k + 1) for m in (1.0, 2.0, 2.5, 5.0)]
    return min(candidates, key=lambda c: abs(math.log(c / x)))


def default_step_years(start: float | str, stop: float | str) -> float:
    """The step (Julian years) ``obliquity-history`` uses when none is given.

    The span over 1000 rounded to a nice number ({1, 2, 2.5, 5} x 10^k), at least :data:`MIN_DEFAULT_STEP_YEARS`, and
    no more than :data:`MAX_PLOT_POINTS` epochs.

    Parameters
    ----------
    start, stop : float or str
        The span, Julian years from J2000.0 TDB (negative: the past).

    Returns
    -------
    float
        The step, Julian years.
    """
    y0, y1 = _year_span(start, stop)
    span = y1 - y0
    step = max(_nice(span / _HISTORY_TARGET_POINTS), MIN_DEFAULT_STEP_YEARS)
    if span / step + 1 > MAX_PLOT_POINTS:
        step = span / (MAX_PLOT_POINTS - 1)
    return min(step, span)      # a span shorter than the least step: its two ends


def _check_step_years(step_years, y0: float, y1: float) -> float:
    if isinstance(step_years, str):
        try:
            step_years = float(step_years)
        except ValueError:
            raise InvalidInputError("step_years", f"must be a number of Julian years, got {step_years!r}") from None
    if isinstance(step_years, bool) or not isinstance(step_years, (int, float, np.integer, np.floating)) \
            or not math.isfinite(step_years):
        raise InvalidInputError("step_years", f"must be a finite number of Julian years, got {step_years!r}")
    if step_years <= 0:
        raise InvalidInputError("step_years", f"must be positive, got {step_years:g}")
    count = (y1 - y0) / step_years + 1      # the epochs are its whole part (ephem.longterm.history.history_grid)
    if not count < MAX_PLOT_POINTS + 1:    # inf too (a subnormal step)
        raise InvalidInputError("step_years", f"{count_text(count)} epochs exceed the cap of {MAX_PLOT_POINTS}; use a "
                                f"step of at least {(y1 - y0) / (MAX_PLOT_POINTS - 1):.4g} years or a shorter span")
    if count < 2:
        raise InvalidInputError("step_years", f"a step of {step_years:g} years leaves a single epoch between start "
                                "and stop; a plot needs at least two")
    return float(step_years)


# --- formatting helpers ---------------------------------------------------------------------------

# --- entry points ---------------------------------------------------------------------------------

@dataclass(frozen=True, repr=False)
class PlotRequest:
    """One plot request, checked (:func:`plot_request`): what :func:`figure` draws and :func:`data` computes.

    ``kind`` (:data:`KINDS`), ``body`` (its dataset with it), the span ``start``-``stop`` (JD TDB; for
    ``obliquity-history`` Julian years from J2000.0 TDB) and the ``step`` (days; years for the history), the default
    filled in. The track kinds carry their :class:`~ephem.theory.requests.TrackRequest` (``track``: the model asked
    for, the axis, the free wobble, the perturbers); ``free-wobble`` its ``J_arcsec`` and ``method``;
    ``obliquity-history`` its ``perturbers`` (canonical names), ``tolerance_mas`` and ``orbit_model`` as given,
    which the history answer (:func:`ephem.answers.requests.history`) checks where it checks them for every
    caller."""

    kind: str
    body: Body
    start: float
    stop: float
    step: float
    track: TrackRequest | None = None
    J_arcsec: object = None
    method: str = "auto"
    perturbers: tuple[str, ...] | None = None
    tolerance_mas: object = None
    orbit_model: str | None = None

    def __repr__(self) -> str:
        """One short line: the kind, the body and its dataset, the span and the step (and the track's request, or the
        history's perturbers); not the Body's every value."""
        unit = "yr" if self.kind == HISTORY_KIND else "d"
        where = "" if self.kind == HISTORY_KIND else "JD "
        text = (f"PlotRequest({self.kind} of {self.body.name} ({self.body.dataset}), {where}{self.start:.10g} to "
                f"{self.stop:.10g} by {self.step:g} {unit}")
        if self.perturbers is not None:
            text += f", under {', '.join(self.perturbers)}"
        return text + ("" if self.track is None else f", {self.track!r}") + ")"


#: a plot's span and step, as :func:`plot_request` and :func:`render` take them (in years for a history)
_PLOT_SPAN = entries("""\
start, stop : str, float or astropy.time.Time
    The span: ISO 8601 text (UTC unless a scale is named), a JD TDB or a ``Time``; for ``obliquity-history``
    Julian years from J2000.0 TDB (numbers or numeric strings, negative in the past).
step_days : float or Quantity, optional
    The step, days (None: :func:`default_step_days`); at most :data:`MAX_PLOT_POINTS` epochs. Not for
    ``obliquity-history``.
""")


@shared_parameters(own=_PLOT_SPAN)
def plot_request(kind: str, body: str | int | Body, start: Epoch, stop: Epoch,
                 step_days: float | Quantity | None = None, *,
                 tolerance_mas: float | Quantity | None = None, model: str | None = None,
                 orbit_model: str | None = None, order: int | None = None, axis: str = "figure",
                 free_wobble_phase_deg: float | Quantity | None = None,
                 free_wobble_J_arcsec: float | Quantity | None = None, free_wobble_epoch: Epoch | None = None,
                 J_arcsec: float | Quantity | None = None, method: str = "auto",
                 step_years: float | Quantity | None = None, dataset: str = DEFAULT_DATASET,
                 perturbers: str | Sequence[str] | None = None) -> PlotRequest:
    """A plot's request, its inputs checked once, before any work: what :func:`figure` draws.

    An option of one kind given to another is refused naming it; the span, the step (its default filled in,
    :func:`default_step_days` or :func:`default_step_years`) and, for the track kinds, the track's every input
    (:func:`ephem.answers.requests.track_request`, at most :data:`MAX_PLOT_POINTS` epochs) are checked here.

    Parameters
    ----------
    kind
    body
    start, stop
    step_days
    tolerance_mas
        A history's: the orbit model's tolerance.
    model
    orbit_model
    order
    axis
    free_wobble_phase_deg
    free_wobble_J_arcsec
    free_wobble_epoch
    J_arcsec
    method
    step_years
    dataset
    perturbers

    Returns
    -------
    PlotRequest
        The checked request (frozen): ``kind``, ``body``, the span and step, and the track's request, the wobble's or
        the history's options.

    Raises
    ------
    InvalidInputError
        Naming the field, for bad input (an option given to a kind it does not apply to among them).
    UnknownBodyError
        For an unknown body.
    NotApplicableError
        Where no theory serves the body's track.
    """
    _check_kind(kind)
    _check_options(kind, {"tolerance_mas": tolerance_mas, "model": model, "order": order,
                          "J_arcsec": J_arcsec, "method": method, "step_days": step_days,
                          "step_years": step_years, "orbit_model": orbit_model, "perturbers": perturbers,
                          "axis": axis, "free_wobble_phase_deg": free_wobble_phase_deg,
                          "free_wobble_J_arcsec": free_wobble_J_arcsec, "free_wobble_epoch": free_wobble_epoch})
    if kind == HISTORY_KIND:
        y0, y1 = _year_span(start, stop)
        step = default_step_years(y0, y1) if step_years is None else _check_step_years(step_years, y0, y1)
        b = resolve_body(body, dataset)
        return PlotRequest(kind, b, y0, y1, step, perturbers=answers.request_perturbers(b, perturbers),
                           tolerance_mas=tolerance_mas, orbit_model=orbit_model)
    b = resolve_body(body, dataset)
    t0, t1 = _span(start, stop)
    if step_days is None:
        step_days = default_step_days(kind, b, start, stop, J_arcsec=J_arcsec, method=method)
    if kind == "free-wobble":
        # validate the step first (a number, positive, within the cap), then refuse an aliasing one
        answers.epoch_grid(start, stop, step_days, max_samples=MAX_PLOT_POINTS)
        fast = _fastest_wobble_period(_wobble_periods(b, t0, J_arcsec, method))
        if step_days > fast / _MIN_PER_CYCLE:
            raise InvalidInputError("step_days", f"a step of {step_days:.6g} d aliases the free wobble, whose "
                                    f"fastest cycle takes {period_text(fast)}: use at most "
                                    f"{fast / _MIN_PER_CYCLE:.6g} d (or leave the step out for the default)", b.name)
        return PlotRequest(kind, b, t0, t1, step_days, J_arcsec=J_arcsec, method=method)
    track = answers.track_request(b, start, stop, step_days, tolerance_mas=tolerance_mas, model=model, order=order,
                                  axis=axis, free_wobble_phase_deg=free_wobble_phase_deg,
                                  free_wobble_J_arcsec=free_wobble_J_arcsec, free_wobble_epoch=free_wobble_epoch,
                                  max_samples=MAX_PLOT_POINTS)
    return PlotRequest(kind, b, t0, t1, step_days, track=track)


def _history_data(request: PlotRequest) -> dict:
    """The history a plot draws: :func:`ephem.answers.requests.history` over the request's years."""
    try:
        return answers.history(request.body, request.start, request.stop, request.step,
                               tolerance_mas=request.tolerance_mas, orbit_model=request.orbit_model,
                               perturbers=request.perturbers, max_samples=MAX_PLOT_POINTS)
    except InvalidInputError as exc:     # the history's own names for the plot's start and stop
        field = {"start_year": "start", "stop_year": "stop"}.get(exc.field)
        if field is None:
            raise
        raise InvalidInputError(field, exc.reason, exc.body) from exc


@shared_parameters
def data(request: PlotRequest) -> dict:
    """The arrays a plot draws, the answer :func:`figure` draws from.

    :func:`ephem.answers.requests.track_arrays_of` the request's track for the track kinds,
    :func:`ephem.answers.requests.free_motion_arrays` for ``free-wobble``, :func:`ephem.answers.requests.history` for
    ``obliquity-history``.

    Parameters
    ----------
    request

    Returns
    -------
    TrackAnswer, FreeMotionAnswer or HistoryAnswer
        The answer drawn, with numpy arrays and no calendar dates.
    """
    if request.kind == HISTORY_KIND:
        return _history_data(request)
    b = request.body
    if request.kind == "free-wobble":
        ans = answers.free_motion_arrays(b, request.start, request.stop, request.step, J_arcsec=request.J_arcsec,
                                         method=request.method, max_samples=MAX_PLOT_POINTS,
                                         time_scale=None)     # a figure reads jd_tdb
    else:
        ans = answers.track_arrays_of(request.track, time_scale=None)
    if np.size(ans["jd_tdb"]) < 2:
        raise InvalidInputError("step_days", f"a step of {request.step:.6g} d leaves a single epoch between start and "
                                "stop; a plot needs at least two", b.name)
    return ans


@shared_parameters
def figure(request: PlotRequest) -> Figure:
    """A :class:`matplotlib.figure.Figure` (Agg canvas, no pyplot state) of one plot request.

    The module's docstring says what each kind draws, its units and the paper figure it reproduces. Track kinds are
    drawn from the request's track (:func:`ephem.answers.requests.track_arrays_of`), ``free-wobble`` from
    :func:`ephem.answers.requests.free_motion_arrays`, ``obliquity-history`` from
    :func:`ephem.answers.requests.history`.

    Parameters
    ----------
    request

    Returns
    -------
    matplotlib.figure.Figure
        The figure, axes in units (arcsec, mas or deg; years or days), free of pyplot's global state.

    Raises
    ------
    NotApplicableError
        Where the track's own error estimate makes it meaningless.
    MissingExtraError
        Without matplotlib (the ``plots`` extra).
    """
    ans = data(request)
    kind = request.kind
    fig = new_figure(kind)
    if kind == HISTORY_KIND:
        draw_obliquity_history(fig, ans)
    elif kind == "free-wobble":
        draw_free_wobble(fig, ans)
    else:
        orbit_days = _orbital_period_days(request.body)
        {"precession": draw_precession, "nutation-loop": draw_nutation_loop, "obliquity": draw_obliquity}[kind](
            fig, ans, orbit_days)
    return fig


#: matplotlib's ``svg.hashsalt`` while an SVG is written: its ids then follow from the figure alone
SVG_HASH_SALT = "ephem-plots"
#: rc_context sets a process-wide parameter (the service draws in several threads): one SVG written at a time
_SVG_LOCK = threading.Lock()


def _check_fmt(fmt) -> str:
    if fmt not in CONTENT_TYPES:
        raise InvalidInputError("fmt", f"must be one of {', '.join(CONTENT_TYPES)}, got {fmt!r}")
    return fmt


def _check_dpi(dpi) -> float:
    lo, hi = DPI_RANGE
    if isinstance(dpi, bool) or not isinstance(dpi, (int, float)) or not math.isfinite(dpi) or not lo <= dpi <= hi:
        raise InvalidInputError("dpi", f"must be a number from {lo} to {hi}, got {dpi!r}")
    return float(dpi)


@shared_parameters
def figure_bytes(fig: Figure, *, fmt: str = "png", dpi: float = DEFAULT_DPI) -> bytes:
    """A figure as PNG or SVG bytes, the same bytes for the same figure.

    No timestamp, no software tag, SVG ids from :data:`SVG_HASH_SALT`: what the service's strong ETag promises.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    fmt : str
        "png" (default) or "svg".
    dpi

    Returns
    -------
    bytes
        The image.
    """
    fmt, dpi = _check_fmt(fmt), _check_dpi(dpi)
    buf = io.BytesIO()
    if fmt == "png":
        fig.savefig(buf, format=fmt, dpi=dpi, metadata={"Software": None})
        return buf.getvalue()
    import matplotlib      # loaded already: the figure is matplotlib's

    # without a salt matplotlib draws a random one for each SVG's clip-path and marker ids; the text is written as
    # text (a browser sets it in its own sans-serif), not as glyph outlines: a third of the bytes, selectable and read
    # by screen readers, and the drawing ~25 % cheaper (benchmarks/RESULTS_work_precision.md)
    with _SVG_LOCK, matplotlib.rc_context({"svg.hashsalt": SVG_HASH_SALT, "svg.fonttype": "none"}):
        fig.savefig(buf, format=fmt, dpi=dpi, metadata={"Date": None})
    return buf.getvalue()


@shared_parameters(own=_PLOT_SPAN)
def render(kind: str, body: str | int | Body, start: Epoch, stop: Epoch,
           step_days: float | Quantity | None = None, *,
           tolerance_mas: float | Quantity | None = None, model: str | None = None, orbit_model: str | None = None,
           order: int | None = None, axis: str = "figure", free_wobble_phase_deg: float | Quantity | None = None,
           free_wobble_J_arcsec: float | Quantity | None = None, free_wobble_epoch: Epoch | None = None,
           J_arcsec: float | Quantity | None = None, method: str = "auto", step_years: float | Quantity | None = None,
           dataset: str = DEFAULT_DATASET, perturbers: str | Sequence[str] | None = None,
           fmt: str = "png", dpi: float = DEFAULT_DPI) -> bytes:
    """The plot :func:`figure` draws, as PNG or SVG bytes (what ``ephem.api.render_plot`` is).

    The bytes carry no timestamp and SVG ids follow from the figure alone: the same request gives the same bytes.

    Parameters
    ----------
    kind
    body
    start, stop
    step_days
    tolerance_mas
        A history's: the orbit model's tolerance.
    model
    orbit_model
    order
    axis
    free_wobble_phase_deg
    free_wobble_J_arcsec
    free_wobble_epoch
    J_arcsec
    method
    step_years
    dataset
    perturbers
    fmt : str
        "png" (default) or "svg"; :data:`CONTENT_TYPES` maps it to its media type.
    dpi : float
        A PNG's resolution, dots per inch, 30 to 300 (default 100: 800 x 600 px for ``precession``).

    Returns
    -------
    bytes
        The image: ``image/png`` or ``image/svg+xml``.

    Raises
    ------
    InvalidInputError
        Naming the field, for bad input (an option given to a kind it does not apply to among them).
    UnknownBodyError
        For an unknown body.
    NotApplicableError
        Where no theory serves the body's track.
    MissingExtraError
        Without matplotlib (the ``plots`` extra).
    """
    _check_fmt(fmt)
    _check_dpi(dpi)
    charge(drawing_cost(fmt, dpi))      # before the data: its checkpoint then admits the request with the drawing
    request = plot_request(kind, body, start, stop, step_days, dataset=dataset, tolerance_mas=tolerance_mas,
                           model=model, order=order, J_arcsec=J_arcsec, method=method, step_years=step_years,
                           orbit_model=orbit_model, perturbers=perturbers, axis=axis,
                           free_wobble_phase_deg=free_wobble_phase_deg, free_wobble_J_arcsec=free_wobble_J_arcsec,
                           free_wobble_epoch=free_wobble_epoch)      # the request made, and checked, once
    if request.kind == "free-wobble":
        charge(wobble_drawing_cost(request, fmt, dpi), request.body.name)   # its loops' raster, before the data too
    return _written_once(figure(request), fmt, dpi)


def _written_once(fig, fmt: str, dpi: float) -> bytes:
    """:func:`figure_bytes` of a figure used for nothing else, which is then freed at once. A figure's objects form
    cycles (figure, canvas, axes, artists, their renderer's pixels) that only the cyclic collector frees, and left to
    it they wait for a full collection, which comes when the survivors reach a quarter of the process's long-lived
    objects: ~3.5 MB a figure, tens of MB at a time in a server drawing them (benchmarks/RESULTS_memory_soak.md).
    The young generations, where the figure's objects still are, are collected right after (~1 ms, against
    150 ms to draw and write the figure); the caller holds no reference to the figure."""
    try:
        return figure_bytes(fig, fmt=fmt, dpi=dpi)
    finally:
        del fig
        gc.collect(1)


# --- the work-precision chart of a request (ephem.exports.work_precision) --------------------------

#: CPU seconds of one work-precision chart, drawn and written (SVG; benchmarks/bench_work_precision.py): measured
#: 36-42 ms for 3-5 models since the SVG's text is text and the decades plain numbers (80-150 ms before, with glyph
#: outlines and typeset labels), set about 1.3x over ...
CHART_BASE_S = 0.05
#: ... and per model drawn: measured ~1.2 ms (36-52 models: 78-95 ms) ...
CHART_MODEL_S = 0.0015
#: ... and per pixel of a PNG: measured 2-5e-8 s (100 dpi: +0.03-0.08 s; 300 dpi, 4.9 Mpx: +0.1-0.3 s)
CHART_PIXEL_S = 6e-8
#: peak memory of a chart, MB: the figure, and a PNG's RGBA buffer and its compressed copy (~8 bytes a pixel); the
#: whole request measured 4.0-4.3 MB as a PNG at 90-103 dpi (predicted 23-24 MB with a base of 20, which took a
#: quarter of a worker's memory for requests: service/guards.py)
CHART_BASE_MB, CHART_PIXEL_BYTES = 6.0, 8.0


#: the largest of the track and history figures, square inches (free-wobble's 10 x 5.8 in)
FIGURE_AREA_IN2 = 58.0
#: a figure's drawing, MB: the figure and its text (a PNG's pixels apart, CHART_PIXEL_BYTES each); measured with the
#: track it draws 1.4-5 MB up to 100 dpi, 18 MB for a PNG at 300 dpi (4.2 bytes a pixel; benchmarks/RESULTS_memory_soak.md)
FIGURE_BASE_MB = 4.0


def drawing_cost(fmt: str, dpi: float) -> Cost:
    """The memory of drawing a track or history figure as ``fmt``, charged before its data.

    The CPU of the drawing is not priced here (0).

    Parameters
    ----------
    fmt : str
        "png" or "svg".
    dpi : float
        A PNG's resolution, dots per inch.

    Returns
    -------
    Cost
        One part: the figure's base (MB) and a PNG's pixels at :data:`CHART_PIXEL_BYTES` each.
    """
    pixels = FIGURE_AREA_IN2 * dpi * dpi if fmt == "png" else 0.0
    return Cost((Part("dpi" if fmt == "png" else "format", f"the figure drawn as {fmt}", 0.0,
                      FIGURE_BASE_MB + CHART_PIXEL_BYTES * pixels / (1024.0 * 1024.0)),))


#: a PNG free-wobble figure's raster, bytes per cycle of its loops drawn and per dpi: matplotlib's Agg rasterizer keeps
#: a cell for every pixel a line crosses until the line is filled, so overlapping loops (the figure axis about L turns
#: once a rotation, ~3,400 times over the Earth's or Mars's 9 years) cost their drawn length, ~2 pi r of the panel each,
#: whatever the pixels. Measured (benchmarks/RESULTS_request_memory.md), the whole request: 604-625 bytes a cycle a dpi
#: over 300-3,800 cycles at 30-110 dpi (the Earth over 9.2 years, 100,000 epochs: 68 MB at 30 dpi, 232 MB at 110),
#: where the drawing was charged 4.4-9.4 MB; SVG writes the path as text: 12 MB at 100,000 epochs, within the data's
#: own charge ...
WOBBLE_CYCLE_BYTES = 640.0
#: ... and the arrays the figure holds while it is drawn, bytes per epoch (its five series and the lines' copies)
WOBBLE_EPOCH_BYTES = 64.0


def wobble_drawing_cost(request: PlotRequest, fmt: str, dpi: float) -> Cost:
    """The memory of drawing a ``free-wobble`` request's loops as ``fmt`` at ``dpi``, MB: :func:`drawing_cost` and,
    for a PNG, :data:`WOBBLE_CYCLE_BYTES` per cycle drawn per dpi (the cycles of both panels over the span, from the
    body's wobble and precession periods) and :data:`WOBBLE_EPOCH_BYTES` per epoch; charged before the data, which
    is held while it is drawn. The CPU is not priced here (0)."""
    base = drawing_cost(fmt, dpi)
    if fmt != "png":
        return base
    span = request.stop - request.start
    cycles = sum(span / p for p in _wobble_periods(request.body, request.start, request.J_arcsec, request.method)
                 if math.isfinite(p) and p > 0.0)
    epochs = span / request.step + 1.0
    lines = (WOBBLE_CYCLE_BYTES * cycles * dpi + WOBBLE_EPOCH_BYTES * epochs) / (1024.0 * 1024.0)
    svg = drawing_cost("svg", dpi).memory_mb        # the way out that keeps the span: said in a refusal's detail
    return Cost((Part("dpi", f"the free wobble's {cycles:.0f} cycles drawn as png at {dpi:g} dpi (as svg: "
                      f"{svg:.3g} MB)", 0.0, base.memory_mb + lines),))


@shared_parameters
def chart_cost(models: int, fmt: str = "svg", dpi: float = DEFAULT_DPI) -> Cost:
    """The predicted cost of drawing a work-precision chart, charged before it is drawn (:func:`models_chart`).

    Parameters
    ----------
    models : int
        The number of models drawn.
    fmt
    dpi : float
        A PNG's resolution, dots per inch.

    Returns
    -------
    Cost
        One part: CPU seconds (:data:`CHART_BASE_S`, per model and per pixel) and memory (MB).
    """
    pixels = work_precision.FIGSIZE[0] * work_precision.FIGSIZE[1] * dpi * dpi if fmt == "png" else 0.0
    return Cost((Part("dpi" if fmt == "png" else "format", f"the work-precision chart of {models} models as {fmt}",
                      CHART_BASE_S + CHART_MODEL_S * models + CHART_PIXEL_S * pixels,
                      CHART_BASE_MB + CHART_PIXEL_BYTES * pixels / (1024.0 * 1024.0)),))


@shared_parameters
def models_chart(answer: dict, *, fmt: str = "svg", dpi: float = DEFAULT_DPI) -> bytes:
    """The work-precision chart of a :func:`ephem.answers.requests.track_models` answer.

    Each model's estimated error (mas) against its predicted cost (CPU ms), the tolerance, the chosen model
    (:mod:`ephem.exports.work_precision`). Charges the drawing's cost (:func:`chart_cost`) first; the same answer gives
    the same bytes.

    Parameters
    ----------
    answer : dict
        The :func:`ephem.answers.requests.track_models` answer (a :class:`~ephem.answers.results.ModelsAnswer`).
    fmt : str
        "svg" (default; a ``<title>`` on every point: its model, order, error and cost, shown on hover) or "png".
    dpi

    Returns
    -------
    bytes
        The chart as ``image/svg+xml`` or ``image/png``.
    """
    fmt, dpi = _check_fmt(fmt), _check_dpi(dpi)
    charge(chart_cost(len(answer["models"]), fmt, dpi), answer.get("body"))
    data = _written_once(work_precision.figure(answer), fmt, dpi)
    return data if fmt == "png" else work_precision.svg_with_titles(data.decode("utf-8"), answer).encode("utf-8")


@shared_parameters
def track_models_chart(body: str | int | Body, start: Epoch, stop: Epoch, step_days: float | Quantity, *,
                       tolerance_mas: float | Quantity | None = None, axis: str = "figure",
                       dataset: str = DEFAULT_DATASET, perturbers: str | Sequence[str] | None = None,
                       fmt: str = "svg", dpi: float = DEFAULT_DPI,
                       max_samples: int = answers.MAX_TRACK_SAMPLES) -> bytes:
    """Speed against accuracy for one request, charted: :func:`ephem.answers.requests.track_models`, drawn.

    Every model serving ``body`` over these epochs, its estimate and predicted cost, the one ``tolerance_mas`` picks,
    drawn by :func:`models_chart`.

    Parameters
    ----------
    body
    start, stop
    step_days
    tolerance_mas : float or Quantity, optional
        The tolerance whose choice the chart shows, milliarcseconds.
    axis
    dataset
    perturbers
    fmt
    dpi
    max_samples

    Returns
    -------
    bytes
        The chart as ``image/svg+xml`` or ``image/png``.

    Raises
    ------
    InvalidInputError
        Naming the field, for bad input (an option given to a kind it does not apply to among them).
    UnknownBodyError
        For an unknown body.
    NotApplicableError
        Where no theory serves the body's track.
    MissingExtraError
        Without matplotlib (the ``plots`` extra).
    """
    fmt, dpi = _check_fmt(fmt), _check_dpi(dpi)
    ans = answers.track_models(body, start, stop, step_days, tolerance_mas=tolerance_mas, axis=axis, dataset=dataset,
                               perturbers=perturbers, max_samples=max_samples)
    return models_chart(ans, fmt=fmt, dpi=dpi)


# --- the figures of docs/plots.md -----------------------------------------------------------------

#: (file stem, kind, body, dataset, start, stop) of each example figure of docs/plots.md, default
#: steps. A stop of None means one orbital period after start (a loop drawn once, closed).
#: Paper figures use the ``petit2014`` dataset (the paper's own parameters), so that they compare.
DOC_FIGURES = (
    ("itokawa_precession", "precession", "Itokawa", "petit2014", "2020-01-01", "2025-01-01"),  # 3.3 orbits
    ("vesta_precession", "precession", "Vesta", "petit2014", "2020-01-01", "2031-01-01"),      # 3.0 orbits
    ("eros_nutation_loop", "nutation-loop", "Eros", "petit2014", "2020-01-01", None),
    ("itokawa_nutation_loop", "nutation-loop", "Itokawa", "petit2014", "2020-01-01", None),
    ("vesta_nutation_loop", "nutation-loop", "Vesta", "petit2014", "2020-01-01", None),
    ("itokawa_nutation_loop_current", "nutation-loop", "Itokawa", "current", "2020-01-01", None),
    ("vesta_obliquity", "obliquity", "Vesta", "petit2014", "2020-01-01", "2031-01-01"),
    ("earth_free_wobble", "free-wobble", "Earth", "current", "2030-01-01", "2031-01-01"),
    ("eros_free_wobble", "free-wobble", "Eros", "current", "2030-01-01", "2030-01-03 12:00"),
)


def regenerate_doc_figures(out_dir: str | Path = "docs/figures", dpi: float = 110) -> list[Path]:
    """Write the PNG and SVG of every :data:`DOC_FIGURES` entry into ``out_dir``.

    The files are reproducible byte for byte (fixed SVG ids, no dates). Run from the repository
    root: ``python -c "from ephem.answers.figures import regenerate_doc_figures as r; r()"``.

    Parameters
    ----------
    out_dir : str or Path
        The folder written (default docs/figures).
    dpi : float
        The PNGs' resolution, dots per inch (default 110).

    Returns
    -------
    list of Path
        The files written.
    """
    import matplotlib

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    # a script, not the server: the global rc_context is fine here
    with matplotlib.rc_context({"svg.hashsalt": SVG_HASH_SALT}):
        for stem, kind, body, dataset, start, stop in DOC_FIGURES:
            if stop is None:
                start = to_jd_tdb(start, "start")
                stop = start + _orbital_period_days(resolve_body(body, dataset))
            fig = figure(plot_request(kind, body, start, stop, dataset=dataset))
            for fmt in CONTENT_TYPES:
                path = out / f"{stem}.{fmt}"
                path.write_bytes(figure_bytes(fig, fmt=fmt, dpi=dpi))
                written.append(path)
    return written
