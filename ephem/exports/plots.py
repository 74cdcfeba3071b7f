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
example figures of ``docs/plots.md``).
"""
from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np

from ..bodies.catalogue import DEFAULT_DATASET
from ..base.constants import J2000_JD, JULIAN_YEAR_DAYS
from ..base.errors import InvalidInputError, count_text

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
#: ``nutation-loop`` is drawn to equal scales unless one component's amplitude exceeds the other's
#: by more than this factor (Eros: Δε 30″ against Δψ sin ε 0.8″), when each axis gets its own scale,
#: as in Petit et al. (2014) Fig. 5 ("scales ... adjusted according to the amplitudes"), and a note says so.
LOOP_ASPECT_LIMIT = 5.0
#: Fewer samples per orbit than this: the track is drawn with a marker at each epoch.
_MARK_BELOW_PER_ORBIT = 16

_FIGSIZE = {"precession": (8.0, 6.0), "nutation-loop": (6.4, 7.0), "obliquity": (8.0, 4.5),
            "free-wobble": (10.0, 5.8), "obliquity-history": (8.0, 6.0)}
_TRACK_OPTIONS = ("tolerance_mas", "model", "order")
_WOBBLE_OPTIONS = ("J_arcsec", "method")
_HISTORY_OPTIONS = ("step_years", "orbit_model", "perturbers")
#: ``obliquity-history``: the default step aims at about this many epochs ...
_HISTORY_TARGET_POINTS = 1000
#: ... rounded to a nice number of years, and never below this many years
MIN_DEFAULT_STEP_YEARS = 100.0
#: ... with a marker at each epoch when fewer than this many are drawn
_HISTORY_MARK_BELOW = 60


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
        wrong = [k for k in ("model", "order", "J_arcsec", "method") if options.get(k) not in (None, "auto")]
        if wrong:
            raise InvalidInputError(wrong[0], f"does not apply to kind {HISTORY_KIND} (its options: tolerance_mas, "
                                    "orbit_model, perturbers, step_years)")
        return
    wrong = [k for k in _HISTORY_OPTIONS if options.get(k) is not None]
    if wrong:
        raise InvalidInputError(wrong[0], f"applies to kind {HISTORY_KIND}, not to {kind}")
    if kind == "free-wobble":
        wrong = [k for k in _TRACK_OPTIONS if options.get(k) is not None]
        if wrong:
            raise InvalidInputError(wrong[0], "applies to the track kinds (precession, nutation-loop, obliquity), "
                                    "not to free-wobble")
    else:
        wrong = [k for k in _WOBBLE_OPTIONS if options.get(k) not in (None, "auto")]
        if wrong:
            raise InvalidInputError(wrong[0], f"applies to kind free-wobble, not to {kind}")


def _span(start, stop) -> tuple[float, float]:
    from ..base.times import to_jd_tdb

    t0, t1 = to_jd_tdb(start, "start"), to_jd_tdb(stop, "stop")
    if t1 < t0:
        raise InvalidInputError("stop", f"stop (JD {t1}) is before start (JD {t0})")
    if t1 == t0:
        raise InvalidInputError("stop", "a plot needs a time span: stop equals start")
    return t0, t1


def _orbital_period_days(b) -> float:
    from ..orbit.kepler import mean_motion_rad_per_day

    return 2.0 * math.pi / mean_motion_rad_per_day(b.orbit.a_au, b.orbit.center)


def _wobble_periods(b, t0: float, J_arcsec, method: str) -> tuple[float, float]:
    """(wobble, precession) periods in days, from the free-motion module at one epoch (this also
    raises the clear J_arcsec error for a body without a published amplitude)."""
    from ..rotation.free_motion import free_motion

    one = free_motion(b, np.array([t0]), J_arcsec, method)
    return float(one["wobble_period_days"]), float(one["precession_period_days"])


def _fastest_wobble_period(periods: tuple[float, float]) -> float:
    finite = [p for p in periods if math.isfinite(p) and p > 0.0]
    return min(finite) if finite else math.inf


def default_step_days(kind: str, body, start, stop, dataset: str = DEFAULT_DATASET,
                      J_arcsec: float | None = None, method: str = "auto") -> float:
    """The step (days) :func:`figure` uses when none is given.

    Tracks: about 2000 epochs over the span, but at least 100 per orbit (the nutation's shortest
    terms, M/6, keep ~16 samples per cycle). Free wobble: 32 epochs per cycle of the faster of the
    wobble and the figure axis's precession about L (23.9 h for the Earth). Either way no more than
    :data:`MAX_PLOT_POINTS` epochs; a free-wobble span too long to resolve within that cap is refused
    (``stop``), since a coarser step would alias the cone.
    """
    from ..answers.requests import resolve_body

    _check_kind(kind)
    if kind == HISTORY_KIND:
        raise InvalidInputError("kind", f"{HISTORY_KIND} samples in Julian years: see default_step_years")
    b = resolve_body(body, dataset)
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
                                        f"points at {_MIN_PER_CYCLE} per {_fmt_period(fast)} cycle of the free "
                                        f"wobble; use a span of at most {longest:.6g} d", b.name)
        return step
    step = min(span / _TARGET_POINTS, _orbital_period_days(b) / _PER_ORBIT)
    if span / step + 1 > MAX_PLOT_POINTS:
        step = span / (MAX_PLOT_POINTS - 1)
    return step


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
    from ..longterm.history import MAX_SPAN_YEARS

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


def default_step_years(start, stop) -> float:
    """The step (Julian years) ``obliquity-history`` uses when none is given: the span over 1000 rounded to a
    nice number ({1, 2, 2.5, 5} x 10^k), at least :data:`MIN_DEFAULT_STEP_YEARS`, and no more than
    :data:`MAX_PLOT_POINTS` epochs. ``start``/``stop``: Julian years from J2000.0 TDB."""
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

def _fmt_period(days: float) -> str:
    if not math.isfinite(days):
        return "∞"
    if days < 2.0:
        return f"{days * 24.0:.4g} h"
    if days < 2.0 * JULIAN_YEAR_DAYS:
        return f"{days:.5g} d"
    return f"{days / JULIAN_YEAR_DAYS:.5g} yr"


def _fmt_mas(mas) -> str:
    if mas is None:
        return "not estimated"
    if mas >= 1000.0:
        return f"{mas / 1000.0:.3g}″"
    return f"{mas:.3g} mas"


def _iso(jd: float) -> str:
    import warnings

    from astropy.time import Time
    from erfa import ErfaWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ErfaWarning)
        return Time(jd, format="jd", scale="tdb").isot[:16].replace("T", " ")


def time_axis(jd_tdb: np.ndarray) -> tuple[np.ndarray, str]:
    """(x values, axis label) for epochs: Julian epoch (TDB, years) over a span of a Julian year or
    more, otherwise days since the first epoch."""
    jd = np.asarray(jd_tdb, dtype=float)
    if jd[-1] - jd[0] >= JULIAN_YEAR_DAYS:
        return 2000.0 + (jd - J2000_JD) / JULIAN_YEAR_DAYS, "Julian epoch (TDB) [yr]"
    return jd - jd[0], f"days since {_iso(float(jd[0]))} TDB (JD {jd[0]:.5f})"


def arcsec_scale(values_arcsec) -> tuple[float, str]:
    """(factor, unit) to draw angles given in arcsec: mas when all are under 1″, degrees when one
    reaches 1° (a free wobble of large J), arcsec otherwise."""
    peak = float(np.max(np.abs(values_arcsec))) if np.size(values_arcsec) else 0.0
    if peak >= 3600.0:
        return 1.0 / 3600.0, "deg"
    return (1.0, "arcsec") if peak >= 1.0 else (1000.0, "mas")


def _plain_ticks(ax) -> None:
    """No offset ('1e6+…') and no scientific multiplier on either axis."""
    from matplotlib.ticker import ScalarFormatter

    for axis in (ax.xaxis, ax.yaxis):
        fmt = ScalarFormatter(useOffset=False)
        fmt.set_scientific(False)
        axis.set_major_formatter(fmt)


def _new_figure(kind: str):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=_FIGSIZE[kind], layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _model_line(model: dict) -> str:
    name = model.get("name")
    rung = f"{name} N={model['order']}" if model.get("order") is not None else str(name)
    return f"model: {rung}, estimated error {_fmt_mas(model.get('estimated_error_mas'))}"


def _symmetric_square(ax, x, y) -> None:
    """Equal aspect, centred on 0, room for the whole path."""
    r = max(float(np.max(np.abs(x))), float(np.max(np.abs(y)))) if np.size(x) else 0.0
    r = 1.08 * r if r > 0.0 else 1.0
    # autoscaled (not fixed) limits, so that "datalim" may widen the longer side: the axes keep the
    # box the layout gave them (a fixed-aspect box fights the constrained layout: titles collide)
    ax.margins(0.0)
    ax.update_datalim([(-r, -r), (r, r)])
    ax.autoscale_view()
    ax.set_aspect("equal", adjustable="datalim")


def _direction_arrow(ax, x, y) -> None:
    """An arrow from the first point along the path (about 10% of the plot's half-width long)."""
    if np.size(x) < 2:
        return
    reach = 0.10 * max(float(np.max(np.abs(x))), float(np.max(np.abs(y))), 1e-300)
    walked = np.hypot(x - x[0], y - y[0])
    k = int(np.argmax(walked >= reach)) if np.any(walked >= reach) else np.size(x) - 1
    ax.annotate("", xy=(x[k], y[k]), xytext=(x[0], y[0]),
                arrowprops={"arrowstyle": "-|>", "color": "k", "lw": 1.2, "shrinkA": 0, "shrinkB": 0})


def _legend_below(ax) -> None:
    """The legend under the axes, off the path (the square plots leave no free corner)."""
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.11), ncol=2, fontsize="small", frameon=False)


def _marker(ans: dict, orbit_days: float) -> str:
    jd = ans["jd_tdb"]
    step = float(jd[1] - jd[0]) if jd.size > 1 else 0.0
    return "." if step > 0 and orbit_days / step < _MARK_BELOW_PER_ORBIT else ""


# --- the kinds ------------------------------------------------------------------------------------

def _precession(fig, ans: dict, orbit_days: float) -> None:
    x, xlabel = time_axis(ans["jd_tdb"])
    psi = ans["psi_arcsec"]
    dpsi = ans["delta_psi_arcsec"]
    big = float(np.max(np.abs(psi))) >= 36000.0
    f_psi, u_psi = (1.0 / 3600.0, "deg") if big else (1.0, "arcsec")
    f_d, u_d = arcsec_scale(dpsi)
    mark = _marker(ans, orbit_days)
    top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    top.plot(x, psi * f_psi, color="C0", lw=1.4, marker=mark, ms=3, label="ψ = precession + Δψ")
    top.plot(x, (psi - dpsi) * f_psi, color="0.35", lw=1.0, ls="--",
             label=f"precession alone (ψ − Δψ), 0 at the pole epoch JD {ans['model']['pole_epoch_jd_tdb']:.1f}")
    top.set_ylabel(f"ψ [{u_psi}]")
    top.legend(loc="best", fontsize="small", frameon=False)
    bottom.plot(x, dpsi * f_d, color="C1", lw=1.2, marker=mark, ms=3)
    bottom.axhline(0.0, color="0.6", lw=0.6)
    bottom.set_ylabel(f"Δψ [{u_d}]")
    bottom.set_xlabel(xlabel)
    for ax in (top, bottom):
        _plain_ticks(ax)
        ax.grid(True, lw=0.4, alpha=0.5)
    fig.suptitle(f"{ans['body']} ({ans['dataset']} dataset): precession and nutation in longitude\n"
                 f"{_model_line(ans['model'])}", fontsize="medium")


def _nutation_loop(fig, ans: dict, orbit_days: float) -> None:
    x_arc = ans["delta_psi_arcsec"] * np.sin(np.radians(ans["obliquity_deg"]))
    y_arc = ans["delta_epsilon_arcsec"]
    f, unit = arcsec_scale(np.concatenate([x_arc, y_arc]))
    ax = fig.subplots()
    ax.plot(x_arc * f, y_arc * f, color="C3", lw=1.2, marker=_marker(ans, orbit_days), ms=3)
    ax.plot([x_arc[0] * f], [y_arc[0] * f], "o", color="k", ms=4,
            label=f"first epoch, {_iso(float(ans['jd_tdb'][0]))[:10]} (arrow: direction of motion)")
    _direction_arrow(ax, x_arc * f, y_arc * f)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel(f"Δψ sin ε [{unit}]")
    ax.set_ylabel(f"Δε [{unit}]")
    _legend_below(ax)
    rx, ry = float(np.max(np.abs(x_arc))) * f, float(np.max(np.abs(y_arc))) * f
    stretch = max(rx, ry) / min(rx, ry) if min(rx, ry) > 0.0 else math.inf
    if stretch <= LOOP_ASPECT_LIMIT:
        _symmetric_square(ax, x_arc * f, y_arc * f)
    else:   # one component dwarfs the other: scale each axis to its own amplitude, and say so
        ax.set_xlim(-1.08 * rx if rx > 0.0 else -1.0, 1.08 * rx if rx > 0.0 else 1.0)
        ax.set_ylim(-1.08 * ry if ry > 0.0 else -1.0, 1.08 * ry if ry > 0.0 else 1.0)
        note = (f"unequal scales: this axis stretched ×{stretch:.3g} against the other" if math.isfinite(stretch)
                else "unequal scales: this component is zero")
        small = ax.xaxis if rx < ry else ax.yaxis
        small.set_label_text(f"{small.get_label_text()}\n({note})")
    _plain_ticks(ax)
    ax.grid(True, lw=0.4, alpha=0.5)
    fig.suptitle(f"{ans['body']} ({ans['dataset']} dataset): nutation of the pole on the equatorial plane\n"
                 f"{_model_line(ans['model'])}; orbital period {_fmt_period(orbit_days)}", fontsize="medium")


def obliquity_reference_deg(obliquity_deg: np.ndarray) -> float | None:
    """ε₀ (deg) the ``obliquity`` plot subtracts, or None when it plots ε itself (a range ≥ 0.5°):
    the mean rounded to 1e-6°, so that the value printed in the label is exactly the one subtracted."""
    eps = np.asarray(obliquity_deg, dtype=float)
    if float(np.ptp(eps)) >= 0.5:
        return None
    return round(float(np.mean(eps)), 6)


def _obliquity(fig, ans: dict, orbit_days: float) -> None:
    x, xlabel = time_axis(ans["jd_tdb"])
    eps = ans["obliquity_deg"]
    ref = obliquity_reference_deg(eps)
    ax = fig.subplots()
    mark = _marker(ans, orbit_days)
    if ref is None:
        ax.plot(x, eps, color="C2", lw=1.2, marker=mark, ms=3)
        ax.set_ylabel("ε [deg]")
    else:
        off = (eps - ref) * 3600.0
        f, unit = arcsec_scale(off)
        ax.plot(x, off * f, color="C2", lw=1.2, marker=mark, ms=3)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_ylabel(f"ε − {ref:.6f}° [{unit}]")
    ax.set_xlabel(xlabel)
    _plain_ticks(ax)
    ax.grid(True, lw=0.4, alpha=0.5)
    fig.suptitle(f"{ans['body']} ({ans['dataset']} dataset): obliquity ε(t)\n{_model_line(ans['model'])}",
                 fontsize="medium")


def _free_wobble(fig, ans: dict) -> None:
    x = ans["figure_axis_offset_x_arcsec"]
    y = ans["figure_axis_offset_y_arcsec"]
    J = ans["wobble_angle_J_arcsec"]
    nu = np.radians(ans["andoyer_nu_deg"])
    bx, by = J * np.sin(nu), J * np.cos(nu)
    f, unit = arcsec_scale(np.concatenate([x, y, J]))
    space, body = fig.subplots(1, 2)
    space.plot(x * f, y * f, color="C0", lw=0.6)
    space.plot([x[0] * f], [y[0] * f], "o", color="k", ms=4, label="first epoch (arrow: direction)")
    space.plot([0.0], [0.0], "+", color="C3", ms=12, mew=1.5, label="angular momentum L")
    space.set_title("figure axis about L, in space", fontsize="medium")
    space.set_xlabel(f"x offset from L [{unit}]")
    space.set_ylabel(f"y offset from L [{unit}]")
    body.plot(bx * f, by * f, color="C1", lw=1.0)
    body.plot([bx[0] * f], [by[0] * f], "o", color="k", ms=4, label="first epoch (arrow: direction)")
    body.plot([0.0], [0.0], "+", color="C2", ms=12, mew=1.5, label="figure axis C")
    body.set_title("L about the figure axis, in the body (polhode)", fontsize="medium")
    body.set_xlabel(f"J sin ν, along the A axis [{unit}]")
    body.set_ylabel(f"J cos ν, along the B axis [{unit}]")
    for ax, (px, py) in ((space, (x, y)), (body, (bx, by))):
        _symmetric_square(ax, px * f, py * f)
        _plain_ticks(ax)
        ax.grid(True, lw=0.4, alpha=0.5)
        _direction_arrow(ax, px * f, py * f)
        _legend_below(ax)
    span = float(ans["jd_tdb"][-1] - ans["jd_tdb"][0])
    fig.suptitle(f"{ans['body']} ({ans['dataset']} dataset): torque-free rigid-body wobble, J₀ = {ans['J_arcsec']:g}″, "
                 f"{ans['mode']} mode, method {ans['method']}\n"
                 f"wobble period {_fmt_period(ans['wobble_period_days'])}, figure axis about L every "
                 f"{_fmt_period(ans['precession_period_days'])}; {_fmt_period(span)} shown from "
                 f"{_iso(float(ans['jd_tdb'][0]))} TDB", fontsize="medium")


def history_time_axis(years) -> tuple[float, str]:
    """(divisor, axis label) for the ``obliquity-history`` time axis: Myr from a span of 1 Myr, kyr from
    2 kyr, years below."""
    y = np.asarray(years, dtype=float)
    span = float(y[-1] - y[0]) if y.size else 0.0
    factor, unit = (1e6, "Myr") if span >= 1e6 else (1e3, "kyr") if span >= 2e3 else (1.0, "yr")
    return factor, f"years from J2000.0 (TDB) [{unit}]"


def _fmt_mas_or_deg(mas: float) -> str:
    """mas, arcsec, or degrees from 1000″."""
    return f"{mas / 3.6e6:.3g}°" if mas is not None and mas >= 1.0e6 else _fmt_mas(mas)


def _history_model_line(ans: dict) -> str:
    m = ans["model"]
    obl = float(np.max(ans["obliquity_error_deg"])) * 3.6e6 if np.size(ans["obliquity_error_deg"]) else None
    by = ans.get("perturbers")
    return (f"model: averaged spin along the {m.get('name')} orbit, estimated error "
            f"{_fmt_mas_or_deg(m.get('estimated_error_mas'))} (pole), {_fmt_mas_or_deg(obl)} (obliquity)"
            + (f"; torqued by {', '.join(by)}" if by else ""))


def meaningless_spans(ans: dict) -> list[tuple[float, float]]:
    """The parts [from, to] (years from J2000.0) of the answer's span where the history stops meaning anything:
    before ``meaningful_from_year`` and after ``meaningful_to_year`` (None: not limited)."""
    y = ans["year"]
    lo, hi = float(y[0]), float(y[-1])
    out = []
    first, last = ans.get("meaningful_from_year"), ans.get("meaningful_to_year")
    if first is not None and first > lo:
        out.append((lo, min(float(first), hi)))
    if last is not None and last < hi:
        out.append((max(float(last), lo), hi))
    return out


def _obliquity_history(fig, ans: dict) -> None:
    from ..longterm.averaged_spin import MEANINGFUL_LIMIT

    years = np.asarray(ans["year"], dtype=float)
    factor, xlabel = history_time_axis(years)
    x = years / factor
    eps = np.asarray(ans["obliquity_deg"], dtype=float)
    err = np.asarray(ans["obliquity_error_deg"], dtype=float)
    inc = np.asarray(ans["orbit_inclination_deg"], dtype=float)
    mark = "." if years.size < _HISTORY_MARK_BELOW else ""
    top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=(3, 1.3))
    lo, hi = np.clip(eps - err, 0.0, 180.0), np.clip(eps + err, 0.0, 180.0)
    top.fill_between(x, lo, hi, color="C2", alpha=0.25, lw=0, label="ε ± estimated error (obliquity_error_deg)")
    top.plot(x, eps, color="C2", lw=1.3, marker=mark, ms=3, label="obliquity ε")
    bottom.plot(x, inc, color="C0", lw=1.1, marker=mark, ms=3)
    # the limits: the curve everywhere, its band only where the history means something (outside, the band
    # may reach 180° and would flatten the curve; that part is hatched anyway)
    spans = meaningless_spans(ans)
    first, last = ans.get("meaningful_from_year"), ans.get("meaningful_to_year")
    inside = ((years >= first) if first is not None else True) & ((years <= last) if last is not None else True)
    inside = np.broadcast_to(inside, years.shape)
    ys = [eps] + ([lo[inside], hi[inside]] if inside.any() else [])
    ymin, ymax = min(float(np.min(v)) for v in ys), max(float(np.max(v)) for v in ys)
    pad = 0.06 * (ymax - ymin) if ymax > ymin else max(0.05, 1e-3 * abs(ymax))
    top.set_ylim(ymin - pad, ymax + pad)
    for i, (a, b) in enumerate(spans):
        for ax in (top, bottom):
            ax.axvspan(a / factor, b / factor, facecolor="0.88", edgecolor="0.55", hatch="///", lw=0.0, zorder=0,
                       label=(f"history not meaningful: neighbouring solutions or orbits part by > "
                              f"{math.degrees(MEANINGFUL_LIMIT):g}°") if i == 0 and ax is top else None)
    top.set_ylabel("obliquity ε [deg]")
    top.legend(loc="best", fontsize="small", framealpha=0.85)
    bottom.set_ylabel("orbit inclination to\nJ2000 ecliptic [deg]")
    bottom.set_xlabel(xlabel)
    bottom.set_xlim(x[0], x[-1])
    for ax in (top, bottom):
        _plain_ticks(ax)
        ax.grid(True, lw=0.4, alpha=0.5)
    unit = xlabel[xlabel.rindex("[") + 1:-1]
    fig.suptitle(f"{ans['body']} ({ans['dataset']} dataset): obliquity history, {x[0]:g} to {x[-1]:g} {unit} "
                 f"from J2000.0\n{_history_model_line(ans)}", fontsize="medium")


# --- entry points ---------------------------------------------------------------------------------

def _history_data(body, start, stop, step_years, dataset: str, tolerance_mas, orbit_model, perturbers) -> dict:
    from ..answers import requests as api

    y0, y1 = _year_span(start, stop)
    step = default_step_years(y0, y1) if step_years is None else _check_step_years(step_years, y0, y1)
    try:
        return api.history(body, y0, y1, step, dataset, tolerance_mas=tolerance_mas, orbit_model=orbit_model,
                           perturbers=perturbers, max_samples=MAX_PLOT_POINTS)
    except InvalidInputError as exc:     # the history's own names for the plot's start and stop
        field = {"start_year": "start", "stop_year": "stop"}.get(exc.field)
        if field is None:
            raise
        raise InvalidInputError(field, exc.reason, exc.body) from exc


def data(kind: str, body, start, stop, step_days: float | None = None, dataset: str = DEFAULT_DATASET, *,
         tolerance_mas: float | None = None, model: str | None = None, order: int | None = None,
         J_arcsec: float | None = None, method: str = "auto", step_years: float | None = None,
         orbit_model: str | None = None, perturbers=None) -> dict:
    """The arrays a plot draws: :func:`ephem.answers.requests.track_arrays` for the track kinds,
    :func:`ephem.answers.requests.free_motion_arrays` for ``free-wobble``, :func:`ephem.answers.requests.history` for
    ``obliquity-history`` (same arguments as :func:`figure`)."""
    from ..answers import requests as api

    _check_kind(kind)
    _check_options(kind, {"tolerance_mas": tolerance_mas, "model": model, "order": order,
                          "J_arcsec": J_arcsec, "method": method, "step_days": step_days,
                          "step_years": step_years, "orbit_model": orbit_model, "perturbers": perturbers})
    if kind == HISTORY_KIND:
        return _history_data(body, start, stop, step_years, dataset, tolerance_mas, orbit_model, perturbers)
    b = api.resolve_body(body, dataset)
    t0, _ = _span(start, stop)
    if step_days is None:
        step_days = default_step_days(kind, b, start, stop, dataset, J_arcsec, method)
    if kind == "free-wobble":
        # validate the step first (a number, positive, within the cap), then refuse an aliasing one
        api.epoch_grid(start, stop, step_days, MAX_PLOT_POINTS)
        fast = _fastest_wobble_period(_wobble_periods(b, t0, J_arcsec, method))
        if step_days > fast / _MIN_PER_CYCLE:
            raise InvalidInputError("step_days", f"a step of {step_days:.6g} d aliases the free wobble, whose "
                                    f"fastest cycle takes {_fmt_period(fast)}: use at most "
                                    f"{fast / _MIN_PER_CYCLE:.6g} d (or leave the step out for the default)", b.name)
        ans = api.free_motion_arrays(b, start, stop, step_days, J_arcsec=J_arcsec, method=method, dataset=dataset,
                                     max_samples=MAX_PLOT_POINTS)
    else:
        ans = api.track_arrays(b, start, stop, step_days, dataset=dataset, order=order,
                               max_samples=MAX_PLOT_POINTS, tolerance_mas=tolerance_mas, model=model)
    if np.size(ans["jd_tdb"]) < 2:
        raise InvalidInputError("step_days", f"a step of {step_days:.6g} d leaves a single epoch between start and "
                                "stop; a plot needs at least two", b.name)
    return ans


def figure(kind: str, body, start, stop, step_days: float | None = None, dataset: str = DEFAULT_DATASET, *,
           tolerance_mas: float | None = None, model: str | None = None, order: int | None = None,
           J_arcsec: float | None = None, method: str = "auto", step_years: float | None = None,
           orbit_model: str | None = None, perturbers=None):
    """A :class:`matplotlib.figure.Figure` (Agg canvas, no pyplot state) of one kind of plot.

    ``kind``: one of :data:`KINDS` (module docstring: what each draws, its units and the paper
    figure it reproduces). ``start``/``stop``: ISO 8601 strings (UTC unless a scale is named) or
    JD TDB numbers. ``step_days``: sampling step in days, or None for :func:`default_step_days`;
    at most :data:`MAX_PLOT_POINTS` epochs. Track kinds take ``tolerance_mas``, ``model`` and
    ``order`` as :func:`ephem.answers.requests.track_arrays`; ``free-wobble`` takes ``J_arcsec`` (required for
    a body without a published amplitude: only Earth, Moon, Mars and Eros have one) and ``method``
    as :func:`ephem.answers.requests.free_motion_arrays`.

    ``obliquity-history`` is the exception: its ``start``/``stop`` are Julian years from J2000.0 TDB
    (numbers or numeric strings, negative in the past), its step is ``step_years`` (None for
    :func:`default_step_years`; at most :data:`MAX_PLOT_POINTS` epochs), and it takes ``tolerance_mas``,
    ``orbit_model`` ("secular" or "nbody") and ``perturbers`` as :func:`ephem.answers.requests.history`; ``step_days``,
    ``model``, ``order``, ``J_arcsec`` and ``method`` do not apply to it (and its options to no other kind).

    Raises :class:`~ephem.base.errors.InvalidInputError` (naming the field) for bad input,
    :class:`~ephem.base.errors.UnknownBodyError` for an unknown body, and whatever the model raises
    (:class:`~ephem.base.errors.NotApplicableError` where no theory serves the body's track).
    """
    ans = data(kind, body, start, stop, step_days, dataset, tolerance_mas=tolerance_mas, model=model,
               order=order, J_arcsec=J_arcsec, method=method, step_years=step_years, orbit_model=orbit_model,
               perturbers=perturbers)
    fig = _new_figure(kind)
    if kind == HISTORY_KIND:
        _obliquity_history(fig, ans)
    elif kind == "free-wobble":
        _free_wobble(fig, ans)
    else:
        from ..answers.requests import resolve_body

        orbit_days = _orbital_period_days(resolve_body(body, dataset))
        {"precession": _precession, "nutation-loop": _nutation_loop, "obliquity": _obliquity}[kind](
            fig, ans, orbit_days)
    return fig


def _check_fmt(fmt) -> str:
    if fmt not in CONTENT_TYPES:
        raise InvalidInputError("fmt", f"must be one of {', '.join(CONTENT_TYPES)}, got {fmt!r}")
    return fmt


def _check_dpi(dpi) -> float:
    lo, hi = DPI_RANGE
    if isinstance(dpi, bool) or not isinstance(dpi, (int, float)) or not math.isfinite(dpi) or not lo <= dpi <= hi:
        raise InvalidInputError("dpi", f"must be a number from {lo} to {hi}, got {dpi!r}")
    return float(dpi)


def figure_bytes(fig, fmt: str = "png", dpi: float = DEFAULT_DPI) -> bytes:
    """A figure as PNG or SVG bytes (no timestamp, no software tag: the same figure gives the same PNG)."""
    fmt, dpi = _check_fmt(fmt), _check_dpi(dpi)
    buf = io.BytesIO()
    metadata = {"Software": None} if fmt == "png" else {"Date": None}
    fig.savefig(buf, format=fmt, dpi=dpi, metadata=metadata)
    return buf.getvalue()


def render(kind: str, body, start, stop, step_days: float | None = None, fmt: str = "png",
           dataset: str = DEFAULT_DATASET, *, dpi: float = DEFAULT_DPI, tolerance_mas: float | None = None,
           model: str | None = None, order: int | None = None, J_arcsec: float | None = None,
           method: str = "auto", step_years: float | None = None, orbit_model: str | None = None,
           perturbers=None) -> bytes:
    """The plot :func:`figure` draws, as ``fmt`` bytes: "png" (``image/png``, ``dpi`` dots per inch,
    30-300, default 100: 800 x 600 px for ``precession``) or "svg" (``image/svg+xml``).
    :data:`CONTENT_TYPES` maps the format to its media type."""
    _check_fmt(fmt)
    _check_dpi(dpi)
    fig = figure(kind, body, start, stop, step_days, dataset, tolerance_mas=tolerance_mas, model=model,
                 order=order, J_arcsec=J_arcsec, method=method, step_years=step_years, orbit_model=orbit_model,
                 perturbers=perturbers)
    return figure_bytes(fig, fmt, dpi)


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
    """Write the PNG and SVG of every :data:`DOC_FIGURES` entry into ``out_dir``; returns the paths.

    The files are reproducible byte for byte (fixed SVG ids, no dates). Run from the repository
    root: ``python -c "from ephem.exports.plots import regenerate_doc_figures as r; r()"``.
    """
    import matplotlib

    from ..answers.requests import resolve_body
    from ..base.times import to_jd_tdb

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    # a script, not the server: the global rc_context is fine here
    with matplotlib.rc_context({"svg.hashsalt": "ephem-plots"}):
        for stem, kind, body, dataset, start, stop in DOC_FIGURES:
            if stop is None:
                start = to_jd_tdb(start, "start")
                stop = start + _orbital_period_days(resolve_body(body, dataset))
            fig = figure(kind, body, start, stop, dataset=dataset)
            for fmt in CONTENT_TYPES:
                path = out / f"{stem}.{fmt}"
                path.write_bytes(figure_bytes(fig, fmt, dpi))
                written.append(path)
    return written
