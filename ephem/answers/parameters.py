"""The answers' shared parameter descriptions: each numpydoc entry written once, filled into each docstring.

A public answer's ``Parameters`` section (numpydoc) names a parameter that several answers share on a line of its
own, the name alone (``body``, ``start, stop``, ``dataset``); :func:`shared_parameters` replaces that line, when the
function is defined, by the entry of :data:`PARAMETERS` (its type, and what it is, with units), so that
``help(api.track)`` and ``api.track.__doc__`` show every parameter in full and each description has one home (as
matplotlib's docstring interpolation does). An entry whose text differs for one answer (``time_scale``, which one
answer allows None) is written in full in that answer's docstring, as a parameter of one answer alone is.
"""
from __future__ import annotations

import re
from collections.abc import Callable
from typing import TypeVar

F = TypeVar("F", bound=Callable)

#: The shared entries, as a numpydoc Parameters section reads: a line ``name : type``, then its description indented
_SECTION = """\
start, stop : str, float or astropy.time.Time
    The first and last epochs: ISO 8601 text (UTC unless a scale is named: "2040-01-01 TDB"), a Julian date TDB
    (days), or an astropy ``Time``. ``stop`` is included when it falls on the grid.
kind : str
    One of :data:`KINDS`: "precession", "nutation-loop", "obliquity", "free-wobble", "obliquity-history".
body : str, int or Body
    The body: a catalogue name (any case), a NAIF id, or a :class:`~ephem.bodies.catalogue.Body` of the user's own.
step_days : float or Quantity
    The step between epochs, days (a ``Quantity`` in any unit of time).
tolerance_mas : float or Quantity, optional
    The largest error the answer may be estimated to carry, milliarcseconds: the cheapest model whose estimate
    meets it over these epochs answers (not with ``model`` or ``order``).
model : str, optional
    A model named instead (one of ``ephem.api.MODELS`` that the body's family has); default the family's own.
orbit_model : str, optional
    ``obliquity-history`` only: "secular" or "nbody", as :func:`ephem.answers.requests.history`.
order : int, optional
    The eccentricity order of the series, 0 to ``ephem.api.MAX_ORDER``; None for exact Hansen coefficients.
axis : str
    The axis followed: "figure" (default; the axis of largest inertia, its free wobble counted as an error unless
    followed), "angular_momentum", "forced_figure" (the figure axis's forced motion, as the IAU's celestial
    intermediate pole), or "mean_rotation" (a synchronous body's mean rotation axis: the Moon's).
free_wobble_phase_deg : float or Quantity, optional
    The figure axis's position angle about the angular momentum at ``free_wobble_epoch``, degrees from the ICRF
    north through east: with it the track can add the free wobble (and does, with a named model).
free_wobble_J_arcsec : float or Quantity, optional
    The free wobble's amplitude J, arcseconds; default the published one (only with ``free_wobble_phase_deg``).
free_wobble_epoch : str, float or astropy.time.Time, optional
    The epoch of ``free_wobble_phase_deg``; default the pole epoch (only with ``free_wobble_phase_deg``).
J_arcsec : float or Quantity, optional
    ``free-wobble`` only: the wobble's amplitude, arcseconds (required for a body without a published one: only the
    Earth, the Moon, Mars and Eros have one).
method : str
    ``free-wobble`` only: "auto" (default), "series" or "numeric".
step_years : float or Quantity, optional
    ``obliquity-history`` only: the step, Julian years (None: :func:`default_step_years`).
dataset : str
    The catalogue dataset: "current" (default), "petit2014" (Petit et al. 2014's parameters) or one imported.
perturbers : str or sequence of str, optional
    The torquing bodies: None for the catalogue's (the Earth: the Moon and the Sun; others: the Sun), or names
    ("sun", ["Sun"], "moon,sun").
request : PlotRequest
    The plot's request, checked (:func:`plot_request`).
dpi : float
    A PNG's resolution, dots per inch, 30 to 300.
fmt : str
    "svg" (default) or "png".
max_samples : int
    The most epochs allowed (default ``MAX_TRACK_SAMPLES``); more is refused naming ``step_days``.
quantities : bool
    True: every unit-named number as an astropy ``Quantity`` and ``jd_tdb`` as a TDB ``Time``; default plain
    numbers (lists).
rotation_phase_deg : float or Quantity, optional
    The angle of the body's long (least-inertia) axis in its equator from the orbit's ascending node on the equator
    at the pole epoch, degrees: with it the track can add the rotation-scale (semi-diurnal) terms.
time_scale : str or None
    The scale of the epochs' calendar dates, "utc" (default), "tt" or "tdb"; None for none.
output : str
    How the caller will write the answer out, "json" (default), "csv" or "ecsv": its cost is charged with it.
"""

#: entry name (``body``, ``start, stop``) -> its entry: the ``name : type`` line, then the description indented by four
PARAMETERS: dict[str, str] = {}


def entries(section: str) -> dict[str, str]:
    """A section of entries (a line ``name : type``, then its description indented) as {name: entry}."""
    return {entry.split(" : ")[0]: entry.rstrip() for entry in re.split(r"\n(?=\S)", section) if entry.strip()}


def shared_parameters(function: F | None = None, *, own: dict[str, str] | None = None):
    """Fill ``function``'s ``Parameters`` section from :data:`PARAMETERS` and return ``function``. ``own``: entries
    (:func:`entries`) that stand instead of the shared ones for a family of answers whose parameter of the same name
    means more (a plot's span, in years for a history), written once for all of them.

    Each line of the section that holds a name alone (``body``, ``start, stop``) at the entries' indentation becomes
    that name's entry, indented as the line; lines indented below the name stay, adding to its description (a
    plot's ``tolerance_mas`` says what it means for a history). A name alone that the table has not raises KeyError as the function's
    module is imported, so no entry is left empty.
    """
    if function is None:
        return lambda f: shared_parameters(f, own=own)
    table = PARAMETERS if not own else {**PARAMETERS, **own}
    lines = (function.__doc__ or "").split("\n")
    out, indent = [], None   # indent: the entries' indentation while in the Parameters section
    for i, line in enumerate(lines):
        underline = lines[i + 1].strip() if i + 1 < len(lines) else ""
        if line.strip() and re.fullmatch(r"-{3,}", underline) and len(underline) == len(line.strip()):
            indent = line[:len(line) - len(line.lstrip())] if line.strip() == "Parameters" else None
        elif indent is not None and _ALONE.fullmatch(line) and line.startswith(indent) \
                and not line[len(indent)].isspace():
            name = line.strip()
            if name not in table:
                raise KeyError(f"{function.__qualname__}: no shared description of {name!r} in "
                               "ephem.answers.parameters.PARAMETERS: write its entry in full")
            head, *description = table[name].split("\n")
            out += [indent + head, *(indent + "    " + d.strip() for d in description)]
            continue
        out.append(line)
    function.__doc__ = "\n".join(out)
    return function


PARAMETERS.update(entries(_SECTION))

#: a line holding parameter names alone: ``body``, ``start, stop``, ``**kwargs``
_ALONE = re.compile(r"[ \t]*\**\w+(, \**\w+)*[ \t]*")
