"""The optional extras of the distribution: which one a feature needs, checked before the feature runs.

The core (numpy, scipy, astropy, skyfield, erfa; typer for the ``ephem`` command) computes every answer: tracks,
precession, nutation, histories along the shipped orbits, tables, SPICE kernels. What lies beyond it is an extra of
``ephem-asteroid-pn`` (pyproject.toml), loaded only by the feature that needs it:

- ``plots``: matplotlib, for the figures (:mod:`ephem.exports.plot_drawing`, :mod:`ephem.exports.work_precision`);
- ``batch``: dask.distributed and pyarrow, for a catalogue on Dask (:mod:`ephem.batch.distributed`);
- ``nbody``: REBOUND, for an N-body orbit run for a body of the user's own (:mod:`ephem.longterm.nbody_orbit`; the
  catalogue's bodies read theirs from the shipped files);
- ``lunar``: the package whose wheel ships JPL's DE421 lunar kernels, for the Moon's ``de421`` model
  (:mod:`ephem.moon.lunar_kernel` finds the files without importing it, and refuses the model naming the extra);
- ``service``: FastAPI and its server (the ``service`` package, which checks for itself).

:func:`require` raises :class:`~ephem.base.errors.MissingExtraError` naming the extra to install, never a bare
``ModuleNotFoundError`` from deep inside a feature.
"""
from __future__ import annotations

import importlib.util
import sys

from .errors import MissingExtraError

#: the distribution whose extras these are (pyproject.toml's ``[project] name``)
DISTRIBUTION = "ephem-asteroid-pn"
#: each extra the library checks for, and the top-level modules it brings that the library imports
EXTRAS = {
    "plots": ("matplotlib",),
    "batch": ("dask", "distributed", "pyarrow"),
    "nbody": ("rebound",),
}


def installed(module: str) -> bool:
    """Whether ``module`` (a top-level package) can be imported here, without importing it: already loaded, or
    found on the path (an import hook that refuses it counts as absent)."""
    if module in sys.modules:
        return sys.modules[module] is not None
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def missing(extra: str) -> str | None:
    """The first module of ``extra`` (:data:`EXTRAS`) that is not installed, None when all are."""
    return next((m for m in EXTRAS[extra] if not installed(m)), None)


def require(extra: str, feature: str) -> None:
    """Raise :class:`~ephem.base.errors.MissingExtraError` when a module of ``extra`` is not installed: ``feature``
    (e.g. "a plot") needs it, and the message says ``pip install 'ephem-asteroid-pn[EXTRA]'``."""
    module = missing(extra)
    if module is not None:
        raise MissingExtraError(feature, module, extra, DISTRIBUTION)
