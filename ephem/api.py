"""The library's public face: every name a program, the CLI or the HTTP service needs, and nothing else.

Answers are dicts with the contract's keys and units in their names (angles in degrees, precession
and nutation in arcseconds, rates per Julian year, times as JD TDB), made by :mod:`ephem.answers`: each of a class of
:mod:`ephem.answers.results` (``TrackAnswer``...), a ``dict`` with ``.to_qtable()`` (astropy, units, ``Time``),
``.to_dict()`` and a short repr. A function takes the body and the epochs by position, the rest by name; the
numeric model of a body (radians, days) is :func:`model_for`. Importing this module loads nothing: each name
loads its module on first use (PEP 562), so a one-body answer pays only for what it runs (the CLI's start-up,
benchmarks/RESULTS_cli.md); matplotlib, SPICE and Dask load with the first plot, kernel or batch.

As skyfield's ``api``: ``from ephem import api`` then ``api.track("Vesta", "2040-01-01", ...)``. A host serving
many requests in one process (the HTTP service) sets budgets and caches and warms them up through :mod:`ephem.host`.
"""
from __future__ import annotations

from .base.lazy import lazy_names

#: public name -> (module relative to ``ephem``, attribute): loaded on first access
_NAMES = {
    "MAX_BATCH_ROWS": (".answers.batches", "MAX_BATCH_ROWS"),
    "batch": (".answers.batches", "batch"),
    "FREE_MOTION_KEYS": (".answers.requests", "FREE_MOTION_KEYS"),
    "MAX_TRACK_SAMPLES": (".answers.requests", "MAX_TRACK_SAMPLES"),
    "REFUSE_ESTIMATE_MAS": (".answers.requests", "REFUSE_ESTIMATE_MAS"),
    "TRACK_KEYS": (".answers.requests", "TRACK_KEYS"),
    "WARN_ESTIMATE_MAS": (".answers.requests", "WARN_ESTIMATE_MAS"),
    "answer_cost": (".answers.requests", "answer_cost"),
    "body_record": (".answers.requests", "body_record"),
    "epoch_grid": (".answers.requests", "epoch_grid"),
    "free_motion_answer": (".answers.requests", "free_motion_answer"),
    "free_motion_arrays": (".answers.requests", "free_motion_arrays"),
    "history": (".answers.requests", "history"),
    "list_bodies": (".answers.requests", "list_bodies"),
    "nutation": (".answers.requests", "nutation"),
    "precession": (".answers.requests", "precession"),
    "precession_nutation": (".answers.requests", "precession_nutation"),
    "track": (".answers.requests", "track"),
    "track_arrays": (".answers.requests", "track_arrays"),
    "track_models": (".answers.requests", "track_models"),
    "track_models_of": (".answers.requests", "track_models_of"),
    "track_request": (".answers.requests", "track_request"),
    "TrackRequest": (".theory.requests", "TrackRequest"),
    "Answer": (".answers.results", "Answer"),
    "BatchAnswer": (".answers.results", "BatchAnswer"),
    "BodiesAnswer": (".answers.results", "BodiesAnswer"),
    "BodyRecord": (".answers.results", "BodyRecord"),
    "FreeMotionAnswer": (".answers.results", "FreeMotionAnswer"),
    "HistoryAnswer": (".answers.results", "HistoryAnswer"),
    "ModelsAnswer": (".answers.results", "ModelsAnswer"),
    "NutationAnswer": (".answers.results", "NutationAnswer"),
    "PrecessionAnswer": (".answers.results", "PrecessionAnswer"),
    "PrecessionNutationAnswer": (".answers.results", "PrecessionNutationAnswer"),
    "TrackAnswer": (".answers.results", "TrackAnswer"),
    "BusyError": (".base.budget", "BusyError"),
    "DeadlineExceededError": (".base.budget", "DeadlineExceededError"),
    "OverBudgetError": (".base.budget", "OverBudgetError"),
    "AXES": (".base.constants", "AXES"),
    "GM_CENTER": (".base.centres", "GM_CENTER"),
    "EphemError": (".base.errors", "EphemError"),
    "InvalidInputError": (".base.errors", "InvalidInputError"),
    "NotApplicableError": (".base.errors", "NotApplicableError"),
    "UnknownBodyError": (".base.errors", "UnknownBodyError"),
    "MissingExtraError": (".base.errors", "MissingExtraError"),
    "TIME_PATTERN_ECMA": (".base.times", "TIME_PATTERN_ECMA"),
    "CALENDAR_SCALES": (".base.times", "CALENDAR_SCALES"),
    "calendar_dates": (".base.times", "calendar_dates"),
    "ut1_span": (".base.times", "ut1_span"),
    "DEFAULT_DATASET": (".bodies.catalogue", "DEFAULT_DATASET"),
    "KNOWN_PERTURBERS": (".base.centres", "KNOWN_PERTURBERS"),
    "MAX_ANGLE_DEG": (".bodies.catalogue", "MAX_ANGLE_DEG"),
    "MIN_ROTATION_PERIOD_HOURS": (".bodies.catalogue", "MIN_ROTATION_PERIOD_HOURS"),
    "Body": (".bodies.catalogue", "Body"),
    "Orbit": (".bodies.catalogue", "Orbit"),
    "Pole": (".bodies.catalogue", "Pole"),
    "get_body": (".bodies.catalogue", "get_body"),
    "load_catalogue": (".bodies.catalogue", "load_catalogue"),
    "resolve_body": (".bodies.catalogue", "resolve_body"),
    "available_datasets": (".bodies.datasets", "available_datasets"),
    "user_catalogue_dir": (".bodies.datasets", "user_catalogue_dir"),
    "data_dir": (".base.paths", "data_dir"),
    "BatchFailed": (".batch.distributed", "BatchFailed"),
    "run_batch": (".answers.batches", "run_batch"),
    "HistorySpec": (".batch.population", "HistorySpec"),
    "shipped_orbit_span": (".longterm.nbody_orbit", "shipped_span"),
    "import_catalogue": (".bodies.importer", "import_catalogue"),
    "write_pck": (".answers.kernels", "write_pck"),
    "write_pck_file": (".answers.kernels", "write_pck_file"),
    "PLOT_CONTENT_TYPES": (".answers.figures", "CONTENT_TYPES"),
    "PLOT_DPI_RANGE": (".answers.figures", "DPI_RANGE"),
    "HISTORY_PLOT_KIND": (".answers.figures", "HISTORY_KIND"),
    "PLOT_KINDS": (".answers.figures", "KINDS"),
    "MAX_PLOT_POINTS": (".answers.figures", "MAX_PLOT_POINTS"),
    "render_plot": (".answers.figures", "render"),
    "plot_request": (".answers.figures", "plot_request"),
    "PlotRequest": (".answers.figures", "PlotRequest"),
    "track_models_chart": (".answers.figures", "track_models_chart"),
    "models_chart": (".answers.figures", "models_chart"),
    "track_models_rows": (".exports.work_precision", "model_rows"),
    "FORMATS": (".exports.tables", "FORMATS"),
    "LAYOUTS": (".exports.tables", "LAYOUTS"),
    "render_nutation": (".exports.tables", "render_nutation"),
    "write_tables": (".exports.tables", "write_tables"),
    "ECSV_MEDIA_TYPE": (".exports.qtable", "ECSV_MEDIA_TYPE"),
    "TABLE_KINDS": (".exports.qtable", "TABLE_KINDS"),
    "to_ecsv": (".exports.qtable", "to_ecsv"),
    "to_qtable": (".exports.qtable", "to_qtable"),
    "MODELS": (".families", "MODELS"),
    "model_families": (".families", "model_families"),
    "Family": (".families", "Family"),
    "register_family": (".families", "register"),
    "unregister_family": (".families", "unregister"),
    "register_centres": (".base.centres", "register_centres"),
    "unregister_centres": (".base.centres", "unregister_centres"),
    "MAX_ORDER": (".forced.precession_nutation", "MAX_ORDER"),
    "model_for": (".forced.precession_nutation", "model_for"),
    "icrf_to_ecliptic_matrix": (".orbit.geometry", "icrf_to_ecliptic_matrix"),
    "LAPLACE_LIMIT": (".orbit.hansen", "LAPLACE_LIMIT"),
    "DELAUNAY_NAMES": (".orbit.lunar", "DELAUNAY_NAMES"),
    "SERIES_MAX_DELTA": (".rotation.free_motion", "SERIES_MAX_DELTA"),
    "MAX_NUMERICAL_ORBITS": (".theory.cost", "MAX_NUMERICAL_ORBITS"),
}

__all__ = [
    # answers (dicts, units in the keys)
    "list_bodies", "body_record", "precession", "nutation", "precession_nutation", "track", "track_arrays", "track_models",
    "history", "batch", "free_motion_answer", "free_motion_arrays", "answer_cost", "epoch_grid",
    "TRACK_KEYS", "FREE_MOTION_KEYS", "MAX_TRACK_SAMPLES", "MAX_BATCH_ROWS", "WARN_ESTIMATE_MAS", "REFUSE_ESTIMATE_MAS",
    # what they return: dicts (the bodies a list) with .to_qtable(), .to_ecsv(), .to_dict() and a short repr
    "Answer", "TrackAnswer", "PrecessionAnswer", "NutationAnswer", "HistoryAnswer", "FreeMotionAnswer", "ModelsAnswer",
    "BodyRecord", "BodiesAnswer", "BatchAnswer", "PrecessionNutationAnswer",
    # a track request checked and kept as one frozen object (what track computes; track_models_of compares its models)
    "track_request", "TrackRequest", "track_models_of",
    # the numeric model of a body
    "model_for", "MAX_ORDER",
    # bodies
    "Body", "Orbit", "Pole", "get_body", "resolve_body", "load_catalogue", "available_datasets", "DEFAULT_DATASET",
    "user_catalogue_dir", "data_dir",
    "KNOWN_PERTURBERS", "MAX_ANGLE_DEG", "MIN_ROTATION_PERIOD_HOURS", "GM_CENTER", "icrf_to_ecliptic_matrix",
    # what a request may name, and its limits
    "MODELS", "model_families", "AXES", "LAPLACE_LIMIT", "MAX_NUMERICAL_ORBITS", "SERIES_MAX_DELTA", "TIME_PATTERN_ECMA", "ut1_span",
    "CALENDAR_SCALES", "calendar_dates",
    # astropy's tables: any table-shaped answer as a QTable (units, Time epochs, metadata) or as ECSV text
    "to_qtable", "to_ecsv", "ECSV_MEDIA_TYPE", "TABLE_KINDS",
    # exports: nutation tables, plots, SPICE kernels; catalogue import; batches of bodies
    "render_nutation", "write_tables", "FORMATS", "LAYOUTS", "DELAUNAY_NAMES", "render_plot", "PLOT_KINDS",
    "plot_request", "PlotRequest", "HISTORY_PLOT_KIND", "PLOT_DPI_RANGE", "track_models_chart", "models_chart", "track_models_rows",
    "PLOT_CONTENT_TYPES", "MAX_PLOT_POINTS", "write_pck", "write_pck_file", "import_catalogue", "run_batch", "BatchFailed",
    "HistorySpec", "shipped_orbit_span",
    # errors
    "EphemError", "InvalidInputError", "NotApplicableError", "UnknownBodyError", "MissingExtraError",
    # a family of theories from outside the library (a plug-in): its registry entry, and its centres' and perturbers'
    # data (a file of data/centres.toml's form)
    "Family", "register_family", "unregister_family", "register_centres", "unregister_centres",
    # what a budget raises: a host (the service) sets it, and the caches, through ephem.host
    "BusyError", "DeadlineExceededError", "OverBudgetError",
]


__getattr__, __dir__ = lazy_names("ephem.api", globals(), _NAMES, __all__)
