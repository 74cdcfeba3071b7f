"""How each kind of plot is drawn on a matplotlib figure: axes, units, panels, titles and legends.

The kinds are :mod:`ephem.answers.figures`'s. The units and scales of
the axes (time, arcsec or mas, degrees), the panels of the five kinds, their titles and legends.

Each ``draw_*`` function fills a figure from :func:`new_figure` with one answer's arrays;
:mod:`ephem.answers.figures` checks the request, computes the answer and renders the bytes.
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from ..base.constants import J2000_JD, JULIAN_YEAR_DAYS
from ..base.extras import require
from ..longterm.averaged_spin import MEANINGFUL_LIMIT

#: ``nutation-loop`` is drawn to equal scales unless one component's amplitude exceeds the other's
#: by more than this factor (Eros: Δε 30″ against Δψ sin ε 0.8″), when each axis gets its own scale,
#: as in Petit et al. (2014) Fig. 5 ("scales ... adjusted according to the amplitudes"), and a note says so.
LOOP_ASPECT_LIMIT = 5.0
#: Fewer samples per orbit than this: the track is drawn with a marker at each epoch.
_MARK_BELOW_PER_ORBIT = 16

_FIGSIZE = {"precession": (8.0, 6.0), "nutation-loop": (6.4, 7.0), "obliquity": (8.0, 4.5),
            "free-wobble": (10.0, 5.8), "obliquity-history": (8.0, 6.0)}
#: ``obliquity-history``: a marker at each epoch when fewer than this many are drawn
_HISTORY_MARK_BELOW = 60


def period_text(days: float) -> str:
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
    from astropy.time import Time
    from erfa import ErfaWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ErfaWarning)
        return Time(jd, format="jd", scale="tdb").isot[:16].replace("T", " ")


#: a track shorter than this many days (~14 min) is drawn in s, ms, µs or ns since its first epoch
SHORT_SPAN_DAYS = 0.01


def time_axis(jd_tdb: np.ndarray) -> tuple[np.ndarray, str]:
    """(x values, axis label) for epochs: Julian epoch (TDB, years) over a span of a Julian year or
    more, otherwise days since the first epoch."""
    jd = np.asarray(jd_tdb, dtype=float)
    span = float(jd[-1] - jd[0])
    if span >= JULIAN_YEAR_DAYS:
        return 2000.0 + (jd - J2000_JD) / JULIAN_YEAR_DAYS, "Julian epoch (TDB) [yr]"
    since = f"since {_iso(float(jd[0]))} TDB (JD {jd[0]:.5f})"
    if span >= SHORT_SPAN_DAYS:
        return jd - jd[0], f"days {since}"
    # seconds down to nanoseconds (a span of a few float64 spacings of a JD: 4.66e-10 d is 40 µs), so that the ticks
    # read 0, 100, 200 rather than 0.0000000005
    unit, scale = next(((u, k) for u, k in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6)) if span * 86400.0 >= 10.0 * k),
                       ("ns", 1e-9))
    return (jd - jd[0]) * (86400.0 / scale), f"{unit} {since}"


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


def new_figure(kind: str):
    require("plots", "a plot")
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

def draw_precession(fig, ans: dict, orbit_days: float) -> None:
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


def draw_nutation_loop(fig, ans: dict, orbit_days: float) -> None:
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
                 f"{_model_line(ans['model'])}; orbital period {period_text(orbit_days)}", fontsize="medium")


def obliquity_reference_deg(obliquity_deg: np.ndarray) -> float | None:
    """ε₀ (deg) the ``obliquity`` plot subtracts, or None when it plots ε itself (a range ≥ 0.5°):
    the mean rounded to 1e-6°, so that the value printed in the label is exactly the one subtracted."""
    eps = np.asarray(obliquity_deg, dtype=float)
    if float(np.ptp(eps)) >= 0.5:
        return None
    return round(float(np.mean(eps)), 6)


def draw_obliquity(fig, ans: dict, orbit_days: float) -> None:
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


def draw_free_wobble(fig, ans: dict) -> None:
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
                 f"wobble period {period_text(ans['wobble_period_days'])}, figure axis about L every "
                 f"{period_text(ans['precession_period_days'])}; {period_text(span)} shown from "
                 f"{_iso(float(ans['jd_tdb'][0]))} TDB", fontsize="medium")


def history_time_axis(years) -> tuple[float, str]:
    """(divisor, axis label) for the ``obliquity-history`` time axis: Myr from a span of 1 Myr, kyr from
    2 kyr, years below."""
    y = np.asarray(years, dtype=float)
    span = float(y[-1] - y[0]) if y.size else 0.0
    if 0.0 < span < 1.0:    # a history within a year: years since its first epoch, in a power of ten of a year
        factor = 10.0 ** math.floor(math.log10(span))
        return factor, f"years since {float(y[0])!r} from J2000.0 (TDB) [{factor:g} yr]"
    factor, unit = (1e6, "Myr") if span >= 1e6 else (1e3, "kyr") if span >= 2e3 else (1.0, "yr")
    return factor, f"years from J2000.0 (TDB) [{unit}]"


def _history_origin(years) -> float:
    """Where :func:`history_time_axis`'s x is 0 (years from J2000.0): J2000.0, or the first epoch of a span within
    a year."""
    y = np.asarray(years, dtype=float)
    return float(y[0]) if y.size and 0.0 < float(y[-1] - y[0]) < 1.0 else 0.0


def _fmt_deg(deg: float | None) -> str:
    """An estimate in degrees, the unit of the history's own estimates (estimated_error_deg, obliquity_error_deg):
    one unit for the error on the figure, its axes and the page it stands on."""
    return "none" if deg is None else f"{deg:.3g}°"


def _history_model_line(ans: dict) -> str:
    m = ans["model"]
    # the pole's: the largest of its per-epoch estimates, or the model's own (mas) in the same unit
    per_epoch = ans.get("estimated_error_deg")
    pole = float(np.max(per_epoch)) if per_epoch is not None and np.size(per_epoch) else (
        None if m.get("estimated_error_mas") is None else m["estimated_error_mas"] / 3.6e6)
    obl = float(np.max(ans["obliquity_error_deg"])) if np.size(ans["obliquity_error_deg"]) else None
    by = ans.get("perturbers")
    return (f"model: averaged spin along the {m.get('name')} orbit, estimated error "
            f"{_fmt_deg(pole)} (pole), {_fmt_deg(obl)} (obliquity)"
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


def draw_obliquity_history(fig, ans: dict) -> None:
    years = np.asarray(ans["year"], dtype=float)
    factor, xlabel = history_time_axis(years)
    origin = _history_origin(years)
    x = (years - origin) / factor
    eps = np.asarray(ans["obliquity_deg"], dtype=float)
    err = np.asarray(ans["obliquity_error_deg"], dtype=float)
    inc = np.asarray(ans["orbit_inclination_deg"], dtype=float)
    psi = np.asarray(ans["precession_angle_deg"], dtype=float)
    mark = "." if years.size < _HISTORY_MARK_BELOW else ""
    top, middle, bottom = fig.subplots(3, 1, sharex=True, height_ratios=(3, 1.3, 1.3))
    lo, hi = np.clip(eps - err, 0.0, 180.0), np.clip(eps + err, 0.0, 180.0)
    top.fill_between(x, lo, hi, color="C2", alpha=0.25, lw=0, label="ε ± estimated error (obliquity_error_deg)")
    top.plot(x, eps, color="C2", lw=1.3, marker=mark, ms=3, label="obliquity ε")
    middle.plot(x, psi, color="C1", lw=1.1, marker=mark, ms=3)
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
        for ax in (top, middle, bottom):
            ax.axvspan((a - origin) / factor, (b - origin) / factor, facecolor="0.88", edgecolor="0.55", hatch="///",
                       lw=0.0, zorder=0,
                       label=(f"history not meaningful: neighbouring solutions or orbits part by > "
                              f"{math.degrees(MEANINGFUL_LIMIT):g}°") if i == 0 and ax is top else None)
    top.set_ylabel("obliquity ε [deg]")
    top.legend(loc="best", fontsize="small", framealpha=0.85)
    middle.set_ylabel("precession angle ψ\n[deg]")
    bottom.set_ylabel("orbit inclination to\nJ2000 ecliptic [deg]")
    bottom.set_xlabel(xlabel)
    bottom.set_xlim(x[0], x[-1])
    for ax in (top, middle, bottom):
        _plain_ticks(ax)
        ax.grid(True, lw=0.4, alpha=0.5)
    unit = xlabel[xlabel.rindex("[") + 1:-1] if factor >= 1.0 else "yr"
    fig.suptitle(f"{ans['body']} ({ans['dataset']} dataset): obliquity history, {years[0] / max(factor, 1.0):g} to "
                 f"{years[-1] / max(factor, 1.0):g} {unit} from J2000.0\n{_history_model_line(ans)}", fontsize="medium")
