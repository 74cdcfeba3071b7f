"""The work-precision chart of one request: each model's estimated error against its predicted cost.

Every model serving a body over the request's epochs: its estimated
error (mas, vertical, log scale) against its predicted cost (CPU ms, horizontal, log scale), as
:func:`ephem.answers.requests.track_models` answers them.

One labelled point per model (its name, its e-order where it has one, and what the variant adds: ``+wobble``,
``+rotation scale``; the marker's shape says the variant too; e-orders of one model drawn at the same place share a
label that lists them, "series e⁴–e¹⁹"), the tolerance as a horizontal dashed line, the
chosen model ringed (and named in the legend), the models outside the tolerance (not eligible) dimmed to
:data:`DIM_ALPHA`. A model with no estimate or no predicted cost (not available for these epochs) is not drawn:
a note under the axes lists it with its reason.

In SVG each point is its own group ``<g id="wp-point-N" class="point ...">`` (N: the model's index in the answer's
``models``; class ``chosen`` on the chosen one, ``ineligible`` on the dimmed ones) whose ``<title>`` names the
model, its order, its estimated error (mas) and predicted cost (ms): a browser shows it on hover. The root carries a
``<title>`` and a ``<desc>`` (the chart in words: its text alternative). The labels are placed from the measured
size of their text alone (no random jitter, no layout engine), so the same answer gives the same figure, which
:func:`ephem.answers.figures.figure_bytes` writes as the same bytes.

``eligible`` is the answer's own key where it gives one; else a model is eligible when it is available and, with a
tolerance, estimated within it (:func:`is_eligible`). Entry points: :func:`figure` (the matplotlib figure, Agg
canvas, no pyplot state), :func:`svg_with_titles` (its SVG given the hover titles and the text alternative),
:func:`model_rows` (the comparison as flat rows, for CSV and tables), :func:`describe` (the chart in words).
matplotlib is imported when a chart is drawn.
"""
from __future__ import annotations

import math
import re
import textwrap
from xml.sax.saxutils import escape

from ..base.constants import J2000_JD, JULIAN_YEAR_DAYS
from ..base.extras import require

#: the id of model N's group in the SVG
POINT_ID = "wp-point-{}"
#: the opacity of a point outside the tolerance (not eligible)
DIM_ALPHA = 0.3
#: the chart's size, inches (648 x 432 pt in SVG, 900 x 600 px at 100 dpi)
FIGSIZE = (9.0, 6.0)
#: the marker of each variant: what the model adds to its track
MARKERS = {"": "o", "+rotation scale": "s", "+wobble": "^", "+wobble +rotation scale": "D"}
#: the tolerance line is drawn when within this factor of the estimates drawn (else a note says where it lies)
TOLERANCE_REACH = 1e3
#: points of one model and variant this near each other, in points, share a label (their e-orders listed)
SAME_PLACE_PT = 4.0
#: an axis spanning at least this ratio has no minor ticks (its decades are labelled)
MINOR_TICKS_BELOW = 100.0
#: the ring round the chosen point, its span in points
RING_PT = 17.0
#: the longest reason a note under the axes prints for a model not drawn, characters; its lines' length
NOTE_REASON_CHARS = 90
#: ... and of why the chosen model was chosen, in the chart's description
WHY_CHARS = 300
NOTE_LINE_CHARS = 170
#: the margins, inches: the title above the axes, the tick labels and axis label below, each line of the note
TITLE_IN, AXIS_LABEL_IN, NOTE_LINE_IN = 0.4, 0.55, 0.13
#: the legend under the axes: its columns, and each row's height, inches
LEGEND_COLUMNS, LEGEND_ROW_IN = 2, 0.2

_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


# --- the answer's models, read --------------------------------------------------------------------

def is_eligible(model: dict, tolerance_mas: float | None) -> bool:
    """The model's ``eligible`` key where the answer gives one; else available and, with a tolerance, estimated
    within it (``estimated_error_mas`` <= ``tolerance_mas``, both mas)."""
    if model.get("eligible") is not None:
        return bool(model["eligible"])
    if not model.get("available"):
        return False
    error = model.get("estimated_error_mas")
    return tolerance_mas is None or (error is not None and error <= tolerance_mas)


def variant(model: dict) -> str:
    """What the model adds to its track: "+wobble", "+rotation scale", both, or "" (nothing)."""
    adds = (["+wobble"] if model.get("free_wobble") else []) + (["+rotation scale"] if model.get("rotation_scale")
                                                                 else [])
    return " ".join(adds)


def label(model: dict) -> str:
    """The point's label: the model's name, its e-order (``series e⁴``) and its variant."""
    text = str(model["name"])
    if model.get("order") is not None:
        text += " e" + str(model["order"]).translate(_SUPERSCRIPT)
    adds = variant(model)
    return f"{text} {adds}" if adds else text


def _plotted(model: dict) -> bool:
    error, cpu = model.get("estimated_error_mas"), model.get("estimated_cpu_ms")
    return bool(model.get("available")) and error is not None and cpu is not None and \
        math.isfinite(error) and math.isfinite(cpu) and error > 0.0 and cpu > 0.0


def _why_not_drawn(model: dict) -> str:
    if not model.get("available"):
        return model.get("why_not") or "not available"
    if model.get("estimated_error_mas") is None:
        return "no error estimate"
    if model.get("estimated_cpu_ms") is None:
        return "no predicted cost"
    return "an estimate or a cost of zero, which a log scale cannot show"


def _why(model: dict) -> str | None:
    return model.get("why") or model.get("why_not")


def model_rows(answer: dict, reasons: bool = False) -> list[dict]:
    """The comparison as flat rows, one per model in the answer's order: name, order, variant, estimated error
    (mas), predicted cost (CPU ms), memory (MB), eligible, chosen; with ``reasons`` also ``why`` (the answer's
    ``why``, else ``why_not``: a sentence, for CSV rather than a terminal's table).

    Parameters
    ----------
    answer : dict
        A models comparison (:func:`ephem.api.track_models`): each model's estimate (mas) and predicted cost.
    reasons : bool
        Add each row's ``why``.

    Returns
    -------
    list of dict
        One row per model: ``name``, ``order`` (e-order or None), ``variant``, ``estimated_error_mas`` (mas),
        ``estimated_cpu_ms`` (CPU ms of one core), ``estimated_memory_mb`` (MB), ``eligible``, ``chosen`` (and
        ``why``).
    """
    tol = answer.get("tolerance_mas")
    rows = []
    for m in answer["models"]:
        row = {"name": m["name"], "order": m.get("order"), "variant": variant(m),
               "estimated_error_mas": m.get("estimated_error_mas"), "estimated_cpu_ms": m.get("estimated_cpu_ms"),
               "estimated_memory_mb": m.get("estimated_memory_mb"), "eligible": is_eligible(m, tol),
               "chosen": bool(m.get("chosen"))}
        if reasons:
            row["why"] = _why(m)
        rows.append(row)
    return rows


def point_title(model: dict, tolerance_mas: float | None) -> str:
    """The hover text of a point: model, order, estimated error (mas) and predicted cost (ms), 6 digits."""
    order = "" if model.get("order") is None else f", e-order {model['order']}"
    adds = variant(model)
    text = (f"{model['name']}{order}{' ' + adds if adds else ''}: estimated error "
            f"{model['estimated_error_mas']:.6g} mas, predicted cost {model['estimated_cpu_ms']:.6g} ms")
    if model.get("estimated_memory_mb") is not None:
        text += f", {model['estimated_memory_mb']:.3g} MB"
    if model.get("chosen"):
        text += "; chosen"
    elif not is_eligible(model, tolerance_mas):
        text += "; not eligible (over the tolerance)" if model.get("available") else "; not eligible"
    return text


def _years(jd: float) -> str:
    return f"{2000.0 + (jd - J2000_JD) / JULIAN_YEAR_DAYS:.2f}"


def describe(answer: dict) -> str:
    """The chart in words (its text alternative): what is drawn, the tolerance, the chosen model, the cheapest
    and the most accurate drawn, what is left out."""
    models = answer["models"]
    tol = answer.get("tolerance_mas")
    drawn = [m for m in models if _plotted(m)]
    parts = [f"Estimated error (mas, log scale) against predicted cost (CPU ms, log scale) of {len(drawn)} of the "
             f"{len(models)} models of {answer.get('theory', 'the family')} for {answer['body']} over "
             f"{answer['epochs']} epochs ({_years(answer['start_jd_tdb'])} to {_years(answer['stop_jd_tdb'])})."]
    if tol is not None:
        within = sum(1 for m in drawn if is_eligible(m, tol))
        parts.append(f"Tolerance {tol:.6g} mas: {within} of them eligible (the others dimmed).")
    chosen = next((m for m in models if m.get("chosen")), None)
    if chosen is not None and _plotted(chosen):
        parts.append(f"Chosen: {label(chosen)}, estimated error {chosen['estimated_error_mas']:.4g} mas at a "
                     f"predicted {chosen['estimated_cpu_ms']:.4g} ms.")
    elif tol is not None:
        parts.append("None chosen: no model is estimated within the tolerance.")
    else:
        parts.append("No tolerance given: none chosen.")
    if answer.get("why_chosen"):
        parts.append(textwrap.shorten(str(answer["why_chosen"]), WHY_CHARS, placeholder=" …"))
    if drawn:
        cheap = min(drawn, key=lambda m: m["estimated_cpu_ms"])
        best = min(drawn, key=lambda m: m["estimated_error_mas"])
        parts.append(f"Cheapest: {label(cheap)} ({cheap['estimated_cpu_ms']:.4g} ms, "
                     f"{cheap['estimated_error_mas']:.4g} mas); most accurate: {label(best)} "
                     f"({best['estimated_error_mas']:.4g} mas, {best['estimated_cpu_ms']:.4g} ms).")
    left = [m for m in models if not _plotted(m)]
    if left:
        parts.append("Not drawn: " + "; ".join(f"{label(m)} ({_why_not_drawn(m)})" for m in left) + ".")
    return " ".join(parts)


# --- the drawing ----------------------------------------------------------------------------------

#: where a label may stand from its point: directions (unit dx, dy; the label's alignment), tried in turn at each
#: distance of :data:`_DISTANCES`
_DIRECTIONS = ((1, 0, "left", "center"), (0.7, 0.7, "left", "bottom"), (0.7, -0.7, "left", "top"),
               (-1, 0, "right", "center"), (0, 1, "center", "bottom"), (0, -1, "center", "top"),
               (-0.7, 0.7, "right", "bottom"), (-0.7, -0.7, "right", "top"))
#: ... the distances from the point, points (beyond the first a thin leader joins label and point)
_DISTANCES = (6.0, 16.0, 28.0, 42.0, 58.0)
#: a label's font size, points
LABEL_SIZE = 7.0


def _overlap(a: tuple, b: tuple) -> float:
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    return w * h if w > 0 and h > 0 else 0.0


def _place_labels(fig, ax, points: list[tuple[float, float, str, float]]) -> None:
    """One label per point (x, y, its text, its marker's half span in points), greedy in the order given: at the
    first place (:data:`_DIRECTIONS` at each of
    :data:`_DISTANCES`) where it overlaps no label placed before and no point and stays inside the axes, else where
    it overlaps least; a label away from its point has a thin leader. Places are reckoned in display pixels from
    each text's measured size, and only the chosen one is drawn."""
    from matplotlib.collections import LineCollection
    from matplotlib.font_manager import FontProperties

    renderer = fig.canvas.get_renderer()
    scale = fig.dpi / 72.0
    x0, y0, x1, y1 = ax.get_window_extent(renderer).extents
    font = FontProperties(size=LABEL_SIZE)
    at = [tuple(ax.transData.transform((x, y))) for x, y, _, _ in points]
    marks = [(px - r * scale, py - r * scale, px + r * scale, py + r * scale)
             for (px, py), (_, _, _, r) in zip(at, points)]
    placed: list[tuple] = []
    leaders = []
    to_data = ax.transData.inverted()
    for (x, y, text, r), (px, py) in zip(points, at):
        w, h, _ = renderer.get_text_width_height_descent(text, font, ismath=False)
        best = None
        for d in _DISTANCES:
            for ux, uy, ha, va in _DIRECTIONS:
                ax_ = px + ux * d * scale
                ay = py + uy * d * scale
                left = {"left": ax_, "right": ax_ - w, "center": ax_ - w / 2}[ha]
                bottom = {"bottom": ay, "top": ay - h, "center": ay - h / 2}[va]
                box = (left, bottom, left + w, bottom + h)
                inside = _overlap(box, (x0, y0, x1, y1))
                cost = (sum(_overlap(box, b) for b in placed) + sum(_overlap(box, m) for m in marks)
                        + 4.0 * (w * h - inside))
                if best is None or cost < best[0] - 1e-9:
                    best = (cost, box, ux * d, uy * d, ha, va, d)
                if cost == 0.0:
                    break
            if best[0] == 0.0:
                break
        _, box, dx, dy, ha, va, d = best
        ann = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", ha=ha, va=va,
                          fontsize=LABEL_SIZE, color="0.15", annotation_clip=False)
        ann.set_in_layout(False)
        placed.append(box)
        if d != _DISTANCES[0]:      # a leader from the marker's edge to a point short of the label
            ux, uy = dx / d, dy / d
            leaders.append(to_data.transform([(px + ux * r * scale, py + uy * r * scale),
                                              (px + ux * (d - 2.0) * scale, py + uy * (d - 2.0) * scale)]))
    if leaders:     # one artist for all (in data coordinates: the same at any dpi, as the figure's inches are)
        ax.add_collection(LineCollection(leaders, colors="0.55", linewidths=0.5, zorder=2.5, gid="wp-leaders"),
                          autolim=False)


def _orders_text(orders: list[int]) -> str:
    """e-orders as runs: [0, 1, 2, 5] -> "e⁰–e², e⁵"."""
    runs: list[list[int]] = []
    for o in sorted(orders):
        if runs and o == runs[-1][-1] + 1:
            runs[-1].append(o)
        else:
            runs.append([o])
    sup = [("e" + str(r[0]).translate(_SUPERSCRIPT)) + ("" if len(r) == 1 else
                                                        "–e" + str(r[-1]).translate(_SUPERSCRIPT)) for r in runs]
    return ", ".join(sup)


def _label_groups(fig, ax, points: list[tuple[float, float, dict, float]]) -> list[tuple[float, float, str, float]]:
    """The labels to place: one per point (x, y, the model, its marker's half span in points), save that points
    of the same model and variant lying within :data:`SAME_PLACE_PT` of each other (e-orders of equal cost and
    near-equal error) share one label naming their orders ("series e⁴–e¹⁹"): their labels could not be told apart.
    Each point keeps its own hover title. The chosen point is never grouped."""
    near = SAME_PLACE_PT * fig.dpi / 72.0
    at = ax.transData.transform([(x, y) for x, y, _, _ in points])
    groups: list[list] = []
    for (x, y, m, r), (px, py) in zip(points, at):
        key = (m["name"], variant(m))
        home = None
        if m.get("order") is not None and not m.get("chosen"):
            home = next((g for g in groups if g[0] == key and abs(g[1] - px) <= near and abs(g[2] - py) <= near),
                        None)
        if home is None:
            groups.append([key if m.get("order") is not None and not m.get("chosen") else None, px, py,
                           [(x, y, m, r)]])
        else:
            home[3].append((x, y, m, r))
    out = []
    for _, _, _, members in groups:
        x, y, m, r = members[0]
        if len(members) == 1:
            out.append((x, y, label(m), r))
        else:
            adds = variant(m)
            text = f"{m['name']} {_orders_text([mm['order'] for _, _, mm, _ in members])}"
            out.append((x, y, f"{text} {adds}" if adds else text, max(mr for *_, mr in members)))
    return out


def _plain_number(value: float, _position=None) -> str:
    """A log axis's tick label: the number as ``%g`` writes it."""
    return f"{value:g}"


def _log_limits(values: list[float], extra: list[float] = ()) -> tuple[float, float]:
    lo, hi = min([*values, *extra]), max([*values, *extra])
    return lo / 2.5, hi * 2.5


def figure(answer: dict):
    """The work-precision chart of a :func:`ephem.answers.requests.track_models` answer, a
    :class:`matplotlib.figure.Figure` on the Agg canvas (no pyplot state)."""
    require("plots", "the work-precision chart")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FuncFormatter, NullLocator

    fig = Figure(figsize=FIGSIZE)
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    models = answer["models"]
    tol = answer.get("tolerance_mas")
    names = list(dict.fromkeys(m["name"] for m in models))
    colours = {name: f"C{k % 10}" for k, name in enumerate(names)}
    drawn, points = [], []
    for i, m in enumerate(models):
        if not _plotted(m):
            continue
        x, y = float(m["estimated_cpu_ms"]), float(m["estimated_error_mas"])
        ok = is_eligible(m, tol)
        ax.plot([x], [y], linestyle="none", marker=MARKERS.get(variant(m), "o"), ms=7, color=colours[m["name"]],
                markeredgecolor="black" if m.get("chosen") else colours[m["name"]], alpha=1.0 if ok else DIM_ALPHA,
                gid=POINT_ID.format(i), zorder=3)
        drawn.append(m)
        points.append((x, y, m, RING_PT / 2 + 0.5 if m.get("chosen") else 4.0))
    handles = []
    chosen = next((m for m in drawn if m.get("chosen")), None)
    if chosen is not None:
        handles.append(ax.plot([chosen["estimated_cpu_ms"]], [chosen["estimated_error_mas"]], linestyle="none",
                               marker="o", ms=RING_PT, markerfacecolor="none", markeredgecolor="black",
                               markeredgewidth=1.8, gid="wp-chosen-ring", zorder=4,
                               label=f"chosen: {label(chosen)}, {chosen['estimated_error_mas']:.4g} mas, "
                                     f"{chosen['estimated_cpu_ms']:.4g} ms")[0])
    errors = [m["estimated_error_mas"] for m in drawn]
    # the tolerance drawn where it is within TOLERANCE_REACH of the estimates (else a note says where it lies)
    tol_drawn = tol is not None and (not errors or
                                     min(errors) / TOLERANCE_REACH <= tol <= max(errors) * TOLERANCE_REACH)
    if tol_drawn:
        handles.append(ax.axhline(tol, color="C3", lw=1.2, ls="--", zorder=2, gid="wp-tolerance",
                                  label=f"tolerance {tol:.6g} mas"))
    present = list(dict.fromkeys(variant(m) for m in drawn))
    for v in present:
        handles.append(Line2D([], [], linestyle="none", marker=MARKERS.get(v, "o"), color="0.3", ms=6,
                              label=f"model {v}" if v else "model (adds nothing)"))
    if any(not is_eligible(m, tol) for m in drawn):
        handles.append(Line2D([], [], linestyle="none", marker="o", color="0.3", alpha=DIM_ALPHA, ms=6,
                              label="dimmed: not eligible (estimated over the tolerance)"))
    ax.set_xscale("log")
    ax.set_yscale("log")
    # the decades as plain numbers (0.01, 1, 100, 1e+06), not matplotlib's typeset 10^k: parsing the mathtext of
    # every tick label was a quarter of the chart's drawing
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(FuncFormatter(_plain_number))
    if drawn:
        ax.set_xlim(*_log_limits([m["estimated_cpu_ms"] for m in drawn]))
        ax.set_ylim(*_log_limits(errors, [tol] if tol_drawn else []))
    for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        if hi / lo >= MINOR_TICKS_BELOW:     # decades enough to read: no minor ticks (a third of the drawing)
            axis.set_minor_locator(NullLocator())
    ax.set_xlabel("predicted cost [CPU ms of one core]")
    ax.set_ylabel("estimated error [mas]")
    ax.grid(True, which="major", lw=0.4, alpha=0.5)
    notes = []
    if tol is not None and not tol_drawn and errors:
        notes.append(f"tolerance {tol:.6g} mas: off the chart, {'below' if tol < min(errors) else 'above'} every "
                     "model's estimate")
    if chosen is None:
        notes.append("none chosen: no model is estimated within the tolerance" if tol is not None else
                     "no tolerance given: none chosen")
    left = [m for m in models if not _plotted(m)]
    if left:
        notes.append("not drawn: " + "; ".join(
            f"{label(m)} ({textwrap.shorten(_why_not_drawn(m), NOTE_REASON_CHARS, placeholder=' …')})" for m in left))
    lines = [line for n in notes for line in textwrap.wrap(n, NOTE_LINE_CHARS)]
    note_in = NOTE_LINE_IN * len(lines) + (0.05 if lines else 0.0)
    if lines:
        fig.text(0.01, 0.05 / FIGSIZE[1], "\n".join(lines), fontsize="x-small", ha="left", va="bottom", color="0.25")
    rows = math.ceil(len(handles) / LEGEND_COLUMNS)
    if handles:     # under the axes, where no point can be
        fig.legend(handles=handles, loc="lower left", bbox_to_anchor=(0.06, note_in / FIGSIZE[1]),
                   ncol=LEGEND_COLUMNS, fontsize="small", frameon=False, borderaxespad=0.0)
    # fixed margins (no layout engine: the chart's parts are known, and the labels are placed once, on them)
    fig.subplots_adjust(left=0.08, right=0.98, top=1.0 - TITLE_IN / FIGSIZE[1],
                        bottom=(AXIS_LABEL_IN + LEGEND_ROW_IN * rows + note_in) / FIGSIZE[1])
    fig.suptitle(f"{answer['body']} ({answer['dataset']} dataset): speed against accuracy of every model, "
                 f"{answer['epochs']} epochs {_years(answer['start_jd_tdb'])}–{_years(answer['stop_jd_tdb'])} (TDB)",
                 fontsize="medium", y=1.0 - 0.1 / FIGSIZE[1], va="top")
    if points:      # the chosen one's label first, then from the cheapest
        _place_labels(fig, ax, sorted(_label_groups(fig, ax, points), key=lambda p: (p[3] < 5.0, p[0])))
    return fig


# --- the bytes ------------------------------------------------------------------------------------

def svg_with_titles(svg: str, answer: dict) -> str:
    """The SVG with its text: a ``<title>`` and a class on each point's group, a ``<title>`` and a ``<desc>`` and
    an image role on the root."""
    tol = answer.get("tolerance_mas")
    for i, m in enumerate(answer["models"]):
        if not _plotted(m):
            continue
        opening = f'<g id="{POINT_ID.format(i)}">'
        classes = "point" + (" chosen" if m.get("chosen") else "") + ("" if is_eligible(m, tol) else " ineligible")
        if svg.count(opening) != 1:          # pragma: no cover - matplotlib writes one group per gid
            raise RuntimeError(f"the SVG has {svg.count(opening)} groups {opening}")
        svg = svg.replace(opening, f'<g id="{POINT_ID.format(i)}" class="{classes}">\n'
                                   f"    <title>{escape(point_title(m, tol))}</title>")
    title = f"{answer['body']}: estimated error against predicted cost of every model"
    root = re.search(r"<svg\b[^>]*>", svg)
    head = root.group(0)[:-1] + ' role="img" aria-labelledby="wp-title wp-desc">'
    return (svg[:root.start()] + head + f'\n <title id="wp-title">{escape(title)}</title>\n'
            f' <desc id="wp-desc">{escape(describe(answer))}</desc>' + svg[root.end():])
