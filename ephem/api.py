"""The library's public face: every name a program, the CLI or the HTTP service needs, and nothing else.

Answers are plain dicts with the contract's keys and units in their names (angles in degrees, precession
and nutation in arcseconds, rates per Julian year, times as JD TDB), made by :mod:`ephem.answers`; the
numeric model of a body (radians, days) is :func:`model_for`. Importing this module loads numpy and the
answers, not matplotlib, SPICE or Dask (each loads with the first plot, kernel or batch).

As skyfield's ``api``: ``from ephem import api`` then ``api.track("Vesta", "2040-01-01", ...)``.
"""
from __future__ import annotations

from .answers.batches import MAX_BATCH_ROWS, batch
from .answers.requests import (FREE_MOTION_KEYS, MAX_TRACK_SAMPLES, REFUSE_ESTIMATE_MAS, TRACK_KEYS, WARN_ESTIMATE_MAS,
                               answer_cost, body_record, epoch_grid, free_motion_answer, free_motion_arrays, history,
                               list_bodies, nutation, precession, precession_nutation, track, track_arrays, track_models,
                               warm_up)
from .base import memo
from .base.budget import Budget, BusyError, DeadlineExceededError, OverBudgetError, budget, charge
from .base.constants import AXES, GM_CENTER
from .base.errors import EphemError, InvalidInputError, NotApplicableError, UnknownBodyError
from .base.times import TIME_PATTERN_ECMA, ut1_span
from .bodies.catalogue import (DEFAULT_DATASET, KNOWN_PERTURBERS, MAX_ANGLE_DEG, MIN_ROTATION_PERIOD_HOURS, Body,
                               Orbit, Pole, get_body, load_catalogue, resolve_body)
from .bodies.datasets import available_datasets
from .batch.distributed import BatchFailed
from .batch.distributed import run as run_batch
from .batch.population import HistorySpec
from .bodies.importer import import_catalogue
from .answers.kernels import write_pck, write_pck_file
from .answers.figures import CONTENT_TYPES as PLOT_CONTENT_TYPES
from .answers.figures import DPI_RANGE as PLOT_DPI_RANGE
from .answers.figures import HISTORY_KIND as HISTORY_PLOT_KIND
from .answers.figures import KINDS as PLOT_KINDS
from .answers.figures import MAX_PLOT_POINTS
from .answers.figures import render as render_plot
from .exports.tables import FORMATS, LAYOUTS, render_nutation, write_tables
from .families import MODELS
from .forced.precession_nutation import MAX_ORDER, model_for
from .orbit.geometry import icrf_to_ecliptic_matrix
from .orbit.hansen import LAPLACE_LIMIT
from .orbit.lunar import DELAUNAY_NAMES
from .rotation.free_motion import SERIES_MAX_DELTA
from .theory.cost import MAX_NUMERICAL_ORBITS

__all__ = [
    # answers (dicts, units in the keys)
    "list_bodies", "body_record", "precession", "nutation", "precession_nutation", "track", "track_arrays", "track_models",
    "history", "batch", "free_motion_answer", "free_motion_arrays", "answer_cost", "epoch_grid", "warm_up",
    "TRACK_KEYS", "FREE_MOTION_KEYS", "MAX_TRACK_SAMPLES", "MAX_BATCH_ROWS", "WARN_ESTIMATE_MAS", "REFUSE_ESTIMATE_MAS",
    # the numeric model of a body
    "model_for", "MAX_ORDER",
    # bodies
    "Body", "Orbit", "Pole", "get_body", "resolve_body", "load_catalogue", "available_datasets", "DEFAULT_DATASET",
    "KNOWN_PERTURBERS", "MAX_ANGLE_DEG", "MIN_ROTATION_PERIOD_HOURS", "GM_CENTER", "icrf_to_ecliptic_matrix",
    # what a request may name, and its limits
    "MODELS", "AXES", "LAPLACE_LIMIT", "MAX_NUMERICAL_ORBITS", "SERIES_MAX_DELTA", "TIME_PATTERN_ECMA", "ut1_span",
    # exports: nutation tables, plots, SPICE kernels; catalogue import; batches of bodies
    "render_nutation", "write_tables", "FORMATS", "LAYOUTS", "DELAUNAY_NAMES", "render_plot", "PLOT_KINDS",
    "HISTORY_PLOT_KIND", "PLOT_DPI_RANGE",
    "PLOT_CONTENT_TYPES", "MAX_PLOT_POINTS", "write_pck", "write_pck_file", "import_catalogue", "run_batch", "BatchFailed",
    "HistorySpec",
    # errors
    "EphemError", "InvalidInputError", "NotApplicableError", "UnknownBodyError",
    # bounded work (a host, as the service, sets the budget and the caches)
    "Budget", "budget", "charge", "BusyError", "DeadlineExceededError", "OverBudgetError", "memo",
]
