"""FastAPI application: ``service.app:app``. Routes are thin: each calls :mod:`ephem.api`."""
from __future__ import annotations

import math
import pathlib
from contextlib import asynccontextmanager
from enum import Enum
from typing import Annotated, Optional

import numpy as np
import orjson
from fastapi import Body as BodyParam, Depends, FastAPI, Path, Query, Request
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html
from fastapi.responses import JSONResponse, PlainTextResponse, Response, StreamingResponse
from fastapi.staticfiles import StaticFiles
from starlette.concurrency import run_in_threadpool

import ephem
from ephem import api, host
from ephem.api import (AXES, DEFAULT_DATASET, FORMATS, MODELS,
                       available_datasets, icrf_to_ecliptic_matrix, load_catalogue, render_nutation)
from ephem.host import memo

from . import caching, downloads, guards, pages, problems, schemas
from .batch_input import batch_rows
from .limits import BodySizeLimit
from .fast_routes import OnePassRoute, one_pass, projection
from .offload import compute
from .openapi_rules import document_rules
from .settings import Settings
from .json_body import UniqueJsonKeys
from .unexpected import UnexpectedErrors


# the names the library knows, one source each: datasets (data/catalogue), models (ephem.families), axes
Dataset = Enum("Dataset", {name: name for name in available_datasets()}, type=str)


def model_enum() -> type[Enum]:
    """The ``model`` query's names: the families' registry's (ephem.api.MODELS) as it stands."""
    return Enum("Rung", {name: name for name in MODELS}, type=str)


#: the ``model`` query's enum, made anew by each create_app (its routes' annotations name it) so that an app has the
#: models of the families registered when it was made (a plug-in's, a test's toy family)
Rung = model_enum()
Axis = Enum("Axis", {name: name for name in AXES}, type=str)
DEFAULT_DATASET_VALUE = Dataset(DEFAULT_DATASET)


class TableFormat(str, Enum):
    json = "json"
    csv = "csv"
    markdown = "markdown"
    latex = "latex"
    table_json = "table-json"
    ecsv = "ecsv"


class TrackFormat(str, Enum):
    json = "json"
    csv = "csv"
    ecsv = "ecsv"


class AnswerFormat(str, Enum):
    """The answer as JSON, or its table as astropy's ECSV (ephem.api.to_ecsv)."""
    json = "json"
    ecsv = "ecsv"


TimeScale = Enum("TimeScale", {name: name for name in api.CALENDAR_SCALES}, type=str)
TimeScaleQuery = Annotated[TimeScale, Query(description="the scale of the epochs' calendar dates beside jd_tdb (ISO "
                                                        "8601 to the millisecond): utc (key utc_iso), tt (tt_iso) or "
                                                        "tdb (tdb_iso)")]
#: the ``format`` query's words for ECSV, and an ECSV response's documentation
ECSV_TEXT = ("ecsv: astropy's Enhanced CSV (text/x-ecsv), written by astropy: each column's unit, type and description "
             "and the answer's metadata (model, estimate, time scale, source, version, citations) in its YAML header; "
             "astropy.table.QTable.read(url, format='ascii.ecsv') gives Quantity columns and jd_tdb as a TDB Time")
ECSV_CONTENT = {api.ECSV_MEDIA_TYPE: {"schema": {"type": "string"}, "example": (
    "# %ECSV 1.0\n# ---\n# datatype:\n# - {name: jd_tdb, datatype: float64, description: 'the epoch, Julian date "
    "TDB'}\n# - {name: utc_iso, datatype: string, ...}\n# - {name: psi_arcsec, unit: arcsec, datatype: float64, "
    "...}\n# meta: !!omap\n# - {table: track}\n...\njd_tdb utc_iso psi_arcsec ...\n")}}


BodyPath = Annotated[str, Path(description="case-insensitive name or NAIF id", examples=["vesta", "2000004"])]
DatasetQuery = Annotated[Dataset, Query(description="catalogue dataset")]
OrderQuery = Annotated[Optional[int], Query(ge=0, le=api.MAX_ORDER, description="truncate the Hansen coefficients at e^order "
                                                                     "(the paper: 4); omit for exact")]
ToleranceQuery = Annotated[Optional[float], Query(gt=0, description="pick the cheapest model estimated within this "
                                                  "many milliarcseconds of the truth (see /docs/accuracy)",
                                                  examples=[10.0])]
# the query of GET /v1/bodies/{body}/track/models and its charts (the track's, where it applies)
ModelsStart = Annotated[str, Query(description="ISO 8601 (UTC unless a scale follows) or JD TDB",
                                   examples=["2025-01-01"])]
ModelsStop = Annotated[str, Query(description="ISO 8601 or JD TDB", examples=["2026-01-01"])]
ModelsStep = Annotated[float, Query(description="sampling step, days", examples=[10.0])]
ModelsAxis = Annotated[Axis, Query(description="the pole to follow, as the track's axis")]
ModelsPerturbers = Annotated[Optional[str], Query(
    description="the torquing bodies: default the catalogue's; sun alone for the single-perturber ladder",
    examples=["sun", "moon,sun"], max_length=100)]


class PlotKind(str, Enum):
    precession = "precession"
    nutation_loop = "nutation-loop"
    obliquity = "obliquity"
    free_wobble = "free-wobble"


class TableLayout(str, Enum):
    sin_cos = "sin-cos"
    amp_period = "amp-period"


class FreeMethod(str, Enum):
    auto = "auto"
    exact = "exact"
    series = "series"
    numeric = "numeric"


ERRORS = {404: {"description": "unknown body (problem+json lists the known ones)"},
          422: {"description": "invalid input (the field is named) or not applicable (with the reason)"}}
CSV_CHUNK = 20_000
#: Swagger UI and ReDoc, vendored (service/static/README.md): the docs pages load nothing from the network
STATIC_DIR = pathlib.Path(__file__).resolve().parent / "static"
#: docs/accuracy.md, served at /docs/accuracy as HTML (service/docs_pages.py): the package's copy
#: (service/static/accuracy.md, which ships in the wheel and the image; tests/service/test_http.py keeps it identical
#: to docs/), and the repository's
ACCURACY_DOC_CANDIDATES = (STATIC_DIR / "accuracy.md",
                           pathlib.Path(__file__).resolve().parent.parent / "docs" / "accuracy.md")


def create_app(settings: Settings | None = None) -> FastAPI:
    global Rung
    settings = settings or Settings.from_env()
    Rung = model_enum()     # before the routes whose annotations read it

    @asynccontextmanager
    async def lifespan(app: FastAPI):
        for ds in available_datasets():  # read (and validate) the catalogue once, at start-up
            load_catalogue(ds)
        icrf_to_ecliptic_matrix()
        if settings.warm_up:
            host.warm_up()  # the Earth's lunisolar series: ~2 s here instead of in the first request
        yield

    app = FastAPI(title="ephem: asteroid precession-nutation ephemeris", version=ephem.__version__,
                  description="Forced precession and nutation of the spin axes of asteroids, planets and moons "
                              "(Kinoshita's theory, Petit et al. 2014). Angles in degrees, precession and nutation "
                              "in arcseconds, times as JD TDB or ISO 8601 (UTC unless a scale follows). "
                              "Errors are RFC 9457 problems (application/problem+json); the accuracy of each "
                              "model is documented at /docs/accuracy. Each query parameter is given at most "
                              "once: a repeated one (?order=2&order=4) is a 422 naming it, never a silent choice.",
                  lifespan=lifespan, docs_url=None, redoc_url=None,
                  dependencies=[Depends(problems.single_query_values)])     # every route: no repeated parameter
    app.state.settings = settings
    app.router.route_class = OnePassRoute       # the endpoints marked one_pass: their parameters validated in one pass
    memo.set_budget_mb(settings.model_cache_mb)      # the process's per-body caches (one app per worker process)
    app.add_middleware(UniqueJsonKeys)     # inside the size limit, which reads the body whole: a key twice is a 422
    app.add_middleware(BodySizeLimit, max_bytes=settings.max_body_bytes)
    problems.install(app)
    guards.install(app, settings)
    caching.install(app, settings)  # ETag, Cache-Control; a 304 before the budget and the route (outermost)
    _install_docs(app)
    pages.install(app)              # the web page for a person (service/pages.py)
    app.add_middleware(UnexpectedErrors)    # outside all: a bug's 500 problem, the keep-alive connection kept

    def health_response() -> JSONResponse:
        return JSONResponse({"status": "ok", "version": ephem.__version__, "datasets": available_datasets()})

    @app.get("/healthz", response_model=schemas.Health, tags=["service"],
             responses={200: {"content": {"application/json": {"example": {
                 "status": "ok", "version": ephem.__version__, "datasets": ["current", "petit2014"]}}}}})
    def healthz():
        """Liveness: the service answers and its catalogue is loaded. HEAD /healthz answers with the same status
        and headers, without the body (for load balancers)."""
        return health_response()

    @app.head("/healthz", include_in_schema=False)    # stated in GET's description
    def healthz_head():
        """GET /healthz without the body, for load balancers."""
        return Response(status_code=200, headers=dict(health_response().headers))

    @app.get("/v1/bodies", response_model=list[schemas.BodySummary], tags=["catalogue"],
             responses={200: {"content": {"application/json": {"example": [{
                 "name": "Vesta", "naif_id": 2000004, "kind": "asteroid", "dataset": "current", "a_au": 2.3615413,
                 "e": 0.0901676, "orbit_center": "Sun", "rotation_period_hours": 5.342128248, "pole_ra_deg": 309.031,
                 "pole_dec_deg": 42.235, "dynamical_ellipticity": 0.168871}]}, **ECSV_CONTENT}}})
    def bodies(request: Request, dataset: DatasetQuery = DEFAULT_DATASET_VALUE,
               format: Annotated[AnswerFormat, Query(description="json, or " + ECSV_TEXT)] = AnswerFormat.json):
        answer = api.list_bodies(dataset=dataset.value)
        if format is AnswerFormat.ecsv:
            return ecsv_response(answer, request, "bodies", dataset.value)
        return answer

    @app.get("/v1/bodies/{body}", response_model=schemas.BodyRecord, tags=["catalogue"], responses={
        **ERRORS, 200: {"content": {"application/json": {"example": {
            "name": "Vesta", "naif_id": 2000004, "kind": "asteroid", "dataset": "current", "orbit_center": "Sun",
            "dynamical_ellipticity": 0.168871, "dynamical_ellipticity_from": "moments",
            "values": {"pole.ra": {"value": 309.031, "unit": "deg", "uncertainty": None, "source": "archinal2018",
                                   "reference": {"authors": "Archinal, B. A. et al.", "year": 2018},
                                   "note": None}}}}}}})
    def body_record(body: BodyPath, dataset: DatasetQuery = DEFAULT_DATASET_VALUE):
        return api.body_record(body, dataset=dataset.value)

    precession_json = projection(schemas.Precession)   # the answer as response_model_exclude_unset sends it
    @app.get("/v1/bodies/{body}/precession", response_model=schemas.Precession, tags=["theory"],
             response_model_exclude_unset=True, responses={     # ``cassini``: a synchronous rotator's only
        **ERRORS, 200: {"content": {"application/json": {"example": {
            "body": "Vesta", "dataset": "petit2014", "obliquity_deg": 27.46, "dynamical_ellipticity": 0.16917,
            "scaling_factor_arcsec_per_year": 30.4404, "precession_rate_arcsec_per_year": 13.6713,
            "model": {"theory": "Kinoshita (1977) …", "eccentricity_order": "exact", "assumptions": ["…"],
                      "warnings": [], "spin_orbit_ratio": 5949.6, "min_spin_orbit_ratio": 30.0,
                      "pole_epoch_jd_tdb": 2451545.0, "orbit_epoch_jd_tdb": 2461000.5, "name": "hansen",
                      "order": None, "description": "Kinoshita-Cayley nutation with exact Hansen coefficients …",
                      "estimated_error_mas": 0.0, "error_terms_mas": None, "tolerance_mas": None,
                      "cost_ms": 0.05}}}, **ECSV_CONTENT}}})
    @one_pass
    async def precession(request: Request, body: BodyPath, dataset: DatasetQuery = DEFAULT_DATASET_VALUE,
                   order: OrderQuery = None, tolerance_mas: ToleranceQuery = None,
                   perturbers: Annotated[Optional[str], Query(
                       description="the torquing bodies: default the catalogue's (the Earth: the Moon and the Sun, "
                                   "the lunisolar theory); sun alone for the single-perturber answer",
                       examples=["sun", "moon,sun"], max_length=100)] = None,
                   format: Annotated[AnswerFormat, Query(description="json, or " + ECSV_TEXT + " (one row)")]
                   = AnswerFormat.json):
        # the track's path (its parameters in one pass, the work on the loop when cheap): FastAPI's thread hops
        # and its validation of the answer against the schema cost more than the rates themselves (~0.2 ms)
        def answer() -> Response:
            ans = api.precession(body, dataset=dataset.value, order=order, tolerance_mas=tolerance_mas,
                                 perturbers=perturbers)
            if format is AnswerFormat.ecsv:
                return ecsv_response(ans, request, ans["body"], ans["dataset"], "precession")
            return finite_json(precession_json(ans))    # response_model's keys, order and types
        return await compute(settings.inline_cpu_ms, answer)

    nutation_json = projection(schemas.Nutation)
    @app.get("/v1/bodies/{body}/nutation", response_model=schemas.Nutation, tags=["theory"],
             response_model_exclude_unset=True, responses={    # a term carries the keys of its theory only
        **ERRORS, 200: {"content": {
            "application/json": {"example": {"terms": [{
                "multiple": 2, "period_days": 662.69, "period_years": 1.8143, "longitude_sin_arcsec": -2.6118,
                "longitude_cos_arcsec": -2.6478, "obliquity_sin_arcsec": -1.3763, "obliquity_cos_arcsec": 1.4318}]}},
            "text/csv": {"example": "component,multiple,arg,sin_arcsec,cos_arcsec,amp_arcsec,period_years,amp_of\n"
                                    "longitude,1,M,2.3784,0.2431,1.1025,3.6287,Δψ sin ε\n"},
            "text/markdown": {"example": "| Δψ Sin (\") | Δψ Cos (\") | Amp Δψ sin ε (\") | Period (year) | Arg |\n"},
            "application/x-latex": {"example": "\\begin{tabular}{rrrrl}\n\\toprule\n"}, **ECSV_CONTENT}}})
    @one_pass
    async def nutation(request: Request, body: BodyPath, dataset: DatasetQuery = DEFAULT_DATASET_VALUE,
                 order: OrderQuery = None, tolerance_mas: ToleranceQuery = None,
                 perturbers: Annotated[Optional[str], Query(
                       description="the torquing bodies: default the catalogue's (the Earth: the Moon and the Sun, "
                                   "the lunisolar theory); sun alone for the single-perturber answer",
                       examples=["sun", "moon,sun"], max_length=100)] = None,
                 cut_mas: Annotated[Optional[float], Query(
                     ge=0.001, description="the lunisolar series (the Earth with the Moon): keep the terms whose "
                                           "amplitude reaches this many mas (default 0.1; not with tolerance_mas)",
                     examples=[0.1])] = None,
                 nonrigid: Annotated[bool, Query(
                     description="apply the body's interior model to the terms (data/interiors.toml): Mars' liquid "
                                 "core, the Earth's IERS 1996 transfer function; a rigid body is refused (422) with "
                                 "the catalogue's reason")] = False,
                 format: Annotated[TableFormat, Query(description="json (this answer), or the paper's table "
                                                                  "layout as csv, markdown, latex (booktabs) or "
                                                                  "table-json; or " + ECSV_TEXT + " (every key of "
                                                                  "the terms a column in its unit: the layout does "
                                                                  "not apply)")] = TableFormat.json,
                 layout: Annotated[TableLayout, Query(description="table layout: sin-cos (Petit et al. Tables "
                                                                  "5-8: Sin, Cos, Amp in arcsec, Period in years) "
                                                                  "or amp-period (Tables 9-10: Amp in mas, Period "
                                                                  "in days)")] = TableLayout.sin_cos):
        # parameters in one pass and one thread hop (FastAPI's sync route takes two, the answer validated in the
        # second); the work stays in the thread pool: a nutation's price can still fall short of its work (the Moon's
        # amplitude cuts for a tolerance, ~10 ms, are not charged), which on the event loop would hold every request
        def answer() -> Response:
            ans = api.nutation(body, dataset=dataset.value, order=order, tolerance_mas=tolerance_mas,
                               perturbers=perturbers, cut_mas=cut_mas,
                               nonrigid=nonrigid)
            if format is TableFormat.json:
                return finite_json(nutation_json(ans))      # response_model's keys, order and types
            if format is TableFormat.ecsv:
                return ecsv_response(ans, request, ans["body"], ans["dataset"], "nutation")
            fmt = "json" if format is TableFormat.table_json else format.value
            return PlainTextResponse(render_nutation(ans, fmt, layout=layout.value), media_type=FORMATS[fmt],
                                     headers=downloads.disposition(downloads.filename(
                                         ans["body"], ans["dataset"], "nutation", layout.value, fmt=format.value)))
        return await run_in_threadpool(answer)

    @app.get("/v1/bodies/{body}/track", response_model=schemas.Track, tags=["theory"], responses={
        **ERRORS, 200: {"content": {"application/json": {"example": {
            "body": "Ceres", "dataset": "current", "jd_tdb": [2466154.5008], "psi_arcsec": [257.5227],
            "delta_psi_arcsec": [-1.92987], "delta_epsilon_arcsec": [0.15848], "obliquity_deg": [4.039563],
            "pole_ra_deg": [291.430308], "pole_dec_deg": [66.765141],
            "model": {"name": "series", "order": 1, "estimated_error_mas": 925.0,
                      "error_terms_mas": {"truncation": 212.2, "second_order": 2.44, "rotation_averaging": 0.361,
                                          "orbit_motion": 710.0, "rounding": 0.0002},
                      "tolerance_mas": 1000.0, "cost_ms": 1.9}}},
            "text/csv": {"example": "jd_tdb,utc_iso,psi_arcsec,delta_psi_arcsec,delta_epsilon_arcsec,obliquity_deg,"
                                    "pole_ra_deg,pole_dec_deg\n"}, **ECSV_CONTENT}}})
    @one_pass
    async def track(request: Request, body: BodyPath,
              start: Annotated[str, Query(description="ISO 8601 (UTC unless a scale follows) or JD TDB",
                                          examples=["2040-01-01"])],
              stop: Annotated[str, Query(description="ISO 8601 or JD TDB", examples=["2041-01-01"])],
              step_days: Annotated[float, Query(description="sampling step, days", examples=[10.0])],
              dataset: DatasetQuery = DEFAULT_DATASET_VALUE, order: OrderQuery = None,
              tolerance_mas: ToleranceQuery = None,
              model: Annotated[Optional[Rung], Query(description="a model of the family serving the body (not "
                                                                 "with tolerance_mas; each family's models: "
                                                                 "/v1/bodies/{body}/track/models); omitted, the "
                                                                 "family's default (the answer's model.name)")] = None,
              axis: Annotated[Axis, Query(description="the pole to follow: the figure axis (the body's axis of "
                                                      "largest inertia, which circles the angular momentum by the "
                                                      "free wobble, counted as an error), the angular momentum, "
                                                      "forced_figure (the figure axis's forced motion, as the IAU's "
                                                      "CIP: the free wobble is polar motion), or mean_rotation (a "
                                                      "synchronous body's mean rotation axis: the Moon's mean-Earth "
                                                      "pole, the IAU's; its figure axis is 78.56″ from it)")]
              = Axis("figure"),
              free_wobble_phase_deg: Annotated[Optional[float], Query(
                  description="the figure axis's position angle about the angular momentum at free_wobble_epoch, "
                              "from the ICRF north through east, deg: lets the track add the free wobble when the "
                              "tolerance needs it (always, with a named model)" + schemas.ANGLE_RULE)] = None,
              free_wobble_J_arcsec: Annotated[Optional[float], Query(
                  ge=0, le=3600, description="the wobble's amplitude (default: the published one)")] = None,
              free_wobble_epoch: Annotated[Optional[str], Query(
                  description="epoch of the phase, ISO 8601 or JD TDB (default: the pole epoch)")] = None,
              rotation_phase_deg: Annotated[Optional[float], Query(
                  description=schemas.RotationPhase + schemas.ANGLE_RULE)] = None,
              format: Annotated[TrackFormat, Query(description="json, csv (streamed; one header line) or "
                                                               + ECSV_TEXT)] = TrackFormat.json,
              time_scale: TimeScaleQuery = TimeScale("utc"),
              perturbers: Annotated[Optional[str], Query(
                       description="the torquing bodies: default the catalogue's (the Earth: the Moon and the Sun, "
                                   "the lunisolar theory); sun alone for the single-perturber answer",
                       examples=["sun", "moon,sun"], max_length=100)] = None):
        def answer() -> Response:
            arrays = api.track_arrays(body, start, stop, step_days, tolerance_mas=tolerance_mas,
                                      model=None if model is None else model.value, order=order, axis=axis.value,
                                      free_wobble_phase_deg=free_wobble_phase_deg,
                                      free_wobble_J_arcsec=free_wobble_J_arcsec, free_wobble_epoch=free_wobble_epoch,
                                      rotation_phase_deg=rotation_phase_deg, dataset=dataset.value,
                                      perturbers=perturbers, time_scale=time_scale.value, output=format.value,
                                      max_samples=settings.max_track_samples)
            if format is TrackFormat.csv:
                return StreamingResponse(_csv_rows(arrays, time_scale.value), media_type="text/csv; charset=utf-8",
                                         headers=downloads.disposition(downloads.filename(
                                             arrays["body"], arrays["dataset"], "track", fmt="csv")))
            if format is TrackFormat.ecsv:
                with host.prepaid():    # its writing was charged with the track (output="ecsv")
                    return ecsv_response(arrays, request, arrays["body"], arrays["dataset"], "track")
            return finite_json(arrays)      # its serialisation is charged with the track (on the loop only if cheap)
        return await compute(settings.inline_cpu_ms, answer)

    # speed against accuracy for a track's request: every model's estimate and predicted cost, and its chart
    @app.get("/v1/bodies/{body}/track/models", response_model=schemas.TrackModels, tags=["theory"], responses={
        **ERRORS, 200: {"content": {"application/json": {"example": {
            "body": "Vesta", "dataset": "current", "perturbers": ["Sun"], "theory": "the single-perturber ladder …",
            "start_jd_tdb": 2460676.5008, "stop_jd_tdb": 2461036.5008, "epochs": 13, "tolerance_mas": 100.0,
            "chosen": "hansen", "models": [{
                "name": "hansen", "order": None, "description": "Kinoshita-Cayley nutation with exact Hansen …",
                "available": True, "why_not": None, "estimated_error_mas": 63.08,
                "error_terms_mas": {"orbit_motion": 62.0, "second_order": 0.9}, "free_wobble": False,
                "rotation_scale": None, "estimated_cpu_ms": 2.05, "estimated_memory_mb": 0.05, "chosen": True}]}}}}})
    def track_models(body: BodyPath, start: ModelsStart, stop: ModelsStop, step_days: ModelsStep,
                     dataset: DatasetQuery = DEFAULT_DATASET_VALUE, tolerance_mas: ToleranceQuery = None,
                     axis: ModelsAxis = Axis("figure"), perturbers: ModelsPerturbers = None):
        """Speed against accuracy for a track's request (ephem.api.track_models): every model of the family
        serving the body over these epochs, with its estimated error by term (mas) and predicted cost (CPU ms, MB),
        and the one tolerance_mas picks. Computes no track; the same query charted: track/models.svg, .png."""
        return finite_json(api.track_models(body, start, stop, step_days, dataset=dataset.value,
                                            tolerance_mas=tolerance_mas, axis=axis.value,
                                            perturbers=perturbers, max_samples=settings.max_track_samples))

    def models_chart_route(ext: str):
        def chart(body: BodyPath, start: ModelsStart, stop: ModelsStop, step_days: ModelsStep,
                  dataset: DatasetQuery = DEFAULT_DATASET_VALUE, tolerance_mas: ToleranceQuery = None,
                  axis: ModelsAxis = Axis("figure"), perturbers: ModelsPerturbers = None,
                  dpi: Annotated[float, Query(ge=30, le=300, description="PNG resolution")] = 100):
            image = api.track_models_chart(body, start, stop, step_days, dataset=dataset.value,
                                           tolerance_mas=tolerance_mas,
                                           axis=axis.value, perturbers=perturbers, fmt=ext, dpi=dpi,
                                           max_samples=settings.max_track_samples)
            return Response(image, media_type=api.PLOT_CONTENT_TYPES[ext])
        chart.__name__ = f"track_models_{ext}"
        chart.__doc__ = (f"The work-precision chart of GET /v1/bodies/{{body}}/track/models as {ext.upper()}: each "
                         "model's estimated error (mas, log) against its predicted cost (CPU ms, log), the tolerance "
                         "as a line, the chosen model ringed, the ineligible dimmed"
                         + (" (in SVG each point's <title> gives its model, order, error and cost)." if ext == "svg"
                            else "."))
        return chart

    for ext in ("png", "svg"):
        media = "image/png" if ext == "png" else "image/svg+xml"
        app.get(f"/v1/bodies/{{body}}/track/models.{ext}", tags=["figures"], response_class=Response,
                responses={**ERRORS, 200: {"content": {media: {"example": "(PNG bytes)" if ext == "png" else
                                                          "<?xml version=\"1.0\" encoding=\"utf-8\"?><svg …"}}}})(
            models_chart_route(ext))

    @app.get("/v1/bodies/{body}/history", response_model=schemas.History, tags=["theory"], responses={
        **ERRORS, 200: {"content": {"application/json": {"example": {
            "body": "Ceres", "dataset": "current", "year": [-3000000.0], "obliquity_deg": [12.3],
            "precession_angle_deg": [-5432.1], "pole_ra_deg": [291.4], "pole_dec_deg": [66.8],
            "orbit_inclination_deg": [10.1], "estimated_error_deg": [0.4], "meaningful_from_year": None,
            "meaningful_to_year": None,
            "model": {"name": "nbody", "estimated_error_mas": 1440000.0, "cost_ms": 2100.0}}},
            "text/csv": {"example": ",".join(downloads.HISTORY_CSV_KEYS) + "\n"}, **ECSV_CONTENT}}})
    def history(request: Request, body: BodyPath,
                start_year: Annotated[float, Query(description="Julian years (365.25 d) from J2000.0 TDB; negative "
                                                               "is the past", examples=[-3000000])],
                stop_year: Annotated[float, Query(description="Julian years from J2000.0 TDB",
                                                  examples=[1000000])],
                step_years: Annotated[float, Query(description="sampling step, Julian years", examples=[500])],
                dataset: DatasetQuery = DEFAULT_DATASET_VALUE, tolerance_mas: ToleranceQuery = None,
                orbit_model: Annotated[Optional[schemas.OrbitModelName], Query(
                    description="secular (Laplace-Lagrange) or nbody (REBOUND from DE421; shipped for the "
                                "catalogue's bodies); not with tolerance_mas. Default: the shipped N-body orbit where "
                                "it covers the span, else the secular one")] = None,
                perturbers: Annotated[Optional[str], Query(
                    description="the torquing bodies (default the catalogue's)", examples=["sun", "moon,sun"],
                    max_length=100)] = None,
                format: Annotated[TrackFormat, Query(description="json, or csv: the arrays, one row per epoch "
                                                                 "(the model in the JSON only), or " + ECSV_TEXT
                                                                 + " (year in Julian years from J2000.0 TDB)")]
                = TrackFormat.json):
        """The spin axis over millennia and millions of years (ephem.longterm.history): obliquity, precession angle, pole
        and the orbit's inclination, with the estimate at each epoch and where the history stops meaning
        anything."""
        answer = api.history(body, start_year, stop_year, step_years, dataset=dataset.value,
                             tolerance_mas=tolerance_mas, orbit_model=orbit_model,
                             perturbers=perturbers, max_samples=settings.max_track_samples)
        if format is TrackFormat.csv and _all_finite(answer):
            return Response(downloads.history_csv(answer), media_type="text/csv; charset=utf-8",
                            headers=downloads.disposition(downloads.filename(answer["body"], answer["dataset"],
                                                                             "history", fmt="csv")))
        if format is TrackFormat.ecsv and _all_finite(answer):
            return ecsv_response(answer, request, answer["body"], answer["dataset"], "history")
        return finite_json(answer)

    def plot_route(ext: str):
        def plot(body: BodyPath,
                 start: Annotated[str, Query(description="ISO 8601 (UTC unless a scale follows) or JD TDB",
                                             examples=["2020-01-01"])],
                 stop: Annotated[str, Query(description="ISO 8601 or JD TDB", examples=["2030-01-01"])],
                 kind: Annotated[PlotKind, Query(description="precession (psi and its nutation against time, Petit "
                                                             "et al. Fig. 4), nutation-loop (Fig. 5), obliquity, "
                                                             "or free-wobble")] = PlotKind.precession,
                 step_days: Annotated[Optional[float], Query(gt=0, description="sampling step, days (default: "
                                                                               "chosen for the kind and span)")] = None,
                 dataset: DatasetQuery = DEFAULT_DATASET_VALUE, order: OrderQuery = None,
                 tolerance_mas: ToleranceQuery = None,
                 model: Annotated[Optional[Rung], Query(description="a model of the family serving the body")] = None,
                 J_arcsec: Annotated[Optional[float], Query(ge=0, le=648000, description="free-wobble amplitude "
                                                                                          "(free-wobble kind)")] = None,
                 dpi: Annotated[float, Query(ge=30, le=300, description="PNG resolution")] = 100,
                 # the track's own pole and free wobble (the track kinds), as GET /v1/bodies/{body}/track takes them
                 axis: Annotated[Axis, Query(description="the pole to follow, as the track's axis")] = Axis("figure"),
                 free_wobble_phase_deg: Annotated[Optional[float], Query(
                     description="as the track's (track kinds)" + schemas.ANGLE_RULE)] = None,
                 free_wobble_J_arcsec: Annotated[Optional[float], Query(
                     ge=0, le=3600, description="as the track's (track kinds)")] = None,
                 free_wobble_epoch: Annotated[Optional[str], Query(description="as the track's (track kinds)")] = None):
            image = api.render_plot(kind.value, body, start, stop, step_days, fmt=ext, dataset=dataset.value, dpi=dpi,
                                    tolerance_mas=tolerance_mas, model=None if model is None else model.value,
                                    order=order, J_arcsec=J_arcsec, axis=axis.value,
                                    free_wobble_phase_deg=free_wobble_phase_deg,
                                    free_wobble_J_arcsec=free_wobble_J_arcsec, free_wobble_epoch=free_wobble_epoch)
            return Response(image, media_type=api.PLOT_CONTENT_TYPES[ext])
        plot.__name__ = f"track_{ext}"
        plot.__doc__ = f"The track (or the free wobble) as a {ext.upper()} figure, axes in units (ephem.answers.figures)."
        return plot

    for ext in ("png", "svg"):
        media = "image/png" if ext == "png" else "image/svg+xml"
        app.get(f"/v1/bodies/{{body}}/track.{ext}", tags=["figures"], response_class=Response,
                responses={**ERRORS, 200: {"content": {media: {"example": "(PNG bytes)" if ext == "png" else
                                                          "<?xml version=\"1.0\" encoding=\"utf-8\"?><svg …"}}}})(
            plot_route(ext))

    def history_plot_route(ext: str):
        def plot(body: BodyPath,
                 start_year: Annotated[float, Query(description="Julian years (365.25 d) from J2000.0 TDB; negative "
                                                                "is the past", examples=[-300000])],
                 stop_year: Annotated[float, Query(description="Julian years from J2000.0 TDB, after start_year",
                                                   examples=[100000])],
                 step_years: Annotated[Optional[float], Query(gt=0, description="sampling step, Julian years "
                                                                                "(default: the span over 1000, "
                                                                                "rounded, at least 100)")] = None,
                 dataset: DatasetQuery = DEFAULT_DATASET_VALUE, tolerance_mas: ToleranceQuery = None,
                 orbit_model: Annotated[Optional[schemas.OrbitModelName], Query(
                     description="secular (Laplace-Lagrange) or nbody (REBOUND from DE421; shipped for the "
                                 "catalogue's bodies); not with tolerance_mas. Default: the shipped N-body orbit "
                                 "where it covers the span, else the secular one")] = None,
                 dpi: Annotated[float, Query(ge=30, le=300, description="PNG resolution")] = 100):
            image = api.render_plot(api.HISTORY_PLOT_KIND, body, start_year, stop_year, None, fmt=ext,
                                    dataset=dataset.value,
                                    dpi=dpi, tolerance_mas=tolerance_mas, step_years=step_years,
                                    orbit_model=orbit_model)
            return Response(image, media_type=api.PLOT_CONTENT_TYPES[ext])
        plot.__name__ = f"history_{ext}"
        plot.__doc__ = (f"The obliquity history (ephem.api.history) as a {ext.upper()} figure: obliquity with its "
                        "estimated error band, the precession angle, the orbit's inclination to the J2000 ecliptic, "
                        "and the span where "
                        "the history stops meaning anything hatched (ephem.answers.figures, kind obliquity-history).")
        return plot

    for ext in ("png", "svg"):
        media = "image/png" if ext == "png" else "image/svg+xml"
        path = f"/v1/bodies/{{body}}/history.{ext}"
        app.get(path, tags=["figures"], response_class=Response,
                responses={**ERRORS, 200: {"content": {media: {"example": "(PNG bytes)" if ext == "png" else
                                                          "<?xml version=\"1.0\" encoding=\"utf-8\"?><svg …"}}}})(
            history_plot_route(ext))
        # the figure's errors name start and stop: the client wrote start_year and stop_year
        problems.FIELD_PATHS[("GET", path)] = {"start": "start_year", "stop": "stop_year"}

    @app.get("/v1/bodies/{body}/free-motion", response_model=schemas.FreeMotion, tags=["theory"],
             responses={**ERRORS, 200: {"content": {
        "application/json": {"example": {
            "body": "Mars", "dataset": "current", "jd_tdb": [2451544.5007], "figure_axis_offset_x_arcsec": [0.0],
            "figure_axis_offset_y_arcsec": [-0.1], "wobble_angle_J_arcsec": [0.1], "andoyer_nu_deg": [0.0],
            "wobble_period_days": 190.65, "precession_period_days": 1.0205, "mode": "short-axis",
            "method": "exact", "J_arcsec": 0.1, "moments_over_C": [0.9942917, 0.9949813, 1.0],
            "cost_ms": 3.1}}, **ECSV_CONTENT}}})
    def free_motion(request: Request, body: BodyPath,
                    start: Annotated[str, Query(description="ISO 8601 (UTC unless a scale follows) or JD TDB",
                                                examples=["2030-01-01"])],
                    stop: Annotated[str, Query(description="ISO 8601 or JD TDB", examples=["2031-01-01"])],
                    step_days: Annotated[float, Query(description="sampling step, days", examples=[1.0])],
                    J_arcsec: Annotated[Optional[float], Query(
                        ge=0, le=648000, description="wobble amplitude: the angle between the angular momentum and "
                                                     "the C axis at start (default: the published one)")] = None,
                    method: Annotated[FreeMethod, Query(description="auto (the exact solution, measured cheapest "
                                                                    "and most accurate), exact, series (short-axis "
                                                                    "mode, δ <= 0.1) or numeric")]
                    = None,
                    dataset: DatasetQuery = DEFAULT_DATASET_VALUE, time_scale: TimeScaleQuery = TimeScale("utc"),
                    format: Annotated[AnswerFormat, Query(description="json, or " + ECSV_TEXT)] = AnswerFormat.json):
        """The torque-free wobble of the figure axis about the angular momentum (ephem.rotation.free_motion)."""
        answer = api.free_motion_arrays(body, start, stop, step_days, J_arcsec=J_arcsec,
                                        method=(method or FreeMethod.auto).value,
                                        dataset=dataset.value, max_samples=settings.max_track_samples,
                                        time_scale=time_scale.value,
                                        output=format.value)
        if format is AnswerFormat.ecsv and _all_finite(answer):
            with host.prepaid():        # its writing was charged with the answer (output="ecsv")
                return ecsv_response(answer, request, answer["body"], answer["dataset"], "free-motion")
        return finite_json(answer)

    @app.post("/v1/batch", response_model=schemas.Batch, tags=["theory"],
              responses={200: {"content": {"application/json": {}, **ECSV_CONTENT}}, 422: ERRORS[422]},
              openapi_extra={"requestBody": {"required": True, "content": {
                  "application/json": {"schema": {"oneOf": [
                      {"type": "array", "items": {"type": "object"}},
                      {"type": "object", "additionalProperties": False, "properties": {
                          "rows": {"type": "array", "items": {"type": "object"}},
                          "history": {"type": "object", "additionalProperties": False,
                                      "required": ["start_year", "stop_year", "step_years"],
                                      "properties": {k: {"type": "number"}
                                                     for k in ("start_year", "stop_year", "step_years")}}}}]}},
                  "text/csv": {"schema": {"type": "string"}}}}})
    async def batch(request: Request,
                    start_year: Annotated[Optional[float], Query(description="with stop_year and step_years: each "
                                                                             "body's obliquity history")] = None,
                    stop_year: Annotated[Optional[float], Query()] = None,
                    step_years: Annotated[Optional[float], Query()] = None,
                    format: Annotated[AnswerFormat, Query(description="json, or " + ECSV_TEXT + " (a row per "
                                                                      "input row)")] = AnswerFormat.json):
        """Precession and nutation of up to EPHEM_MAX_BATCH_ROWS bodies at once: a JSON array of row objects (or
        {rows, history}) or CSV with the columns of docs/batch_input.md. Beyond, run `ephem batch` (Dask)."""
        rows, history = batch_rows(await request.body(), request.headers.get("content-type", ""))
        path = "history."
        if start_year is not None or stop_year is not None or step_years is not None:
            history = {"start_year": start_year, "stop_year": stop_year, "step_years": step_years}
            path = ""       # its errors name ?step_years=, as the client wrote it
        # the work in a thread (the event loop stays free), in this request's budget (the context is copied)
        answer = await run_in_threadpool(api.batch, rows, history=history, max_rows=settings.max_batch_rows,
                                         history_path=path)
        if format is AnswerFormat.ecsv and _all_finite(answer):
            return await run_in_threadpool(ecsv_response, answer, request, "batch", "")
        return finite_json(answer)

    @app.post("/v1/precession-nutation", response_model=schemas.PrecessionNutation, tags=["theory"],
              response_model_exclude_unset=True,
              responses={422: ERRORS[422]})        # no {body} to be unknown: no 404
    def precession_nutation(user: Annotated[schemas.UserBody, BodyParam()]):
        b = user.to_body()
        track = None if user.track is None else user.track.model_dump()
        history = None if user.history is None else user.history.model_dump()
        return finite_json(api.precession_nutation(b, order=user.order, track=track,
                                                   max_samples=settings.max_track_samples, history_request=history))

    return app


def _install_docs(app: FastAPI) -> None:
    """/docs (Swagger UI), /redoc (ReDoc), their assets under /static, /docs/accuracy, and the OpenAPI
    document with the problem+json error responses (problems.document)."""
    app.mount("/static", StaticFiles(directory=STATIC_DIR), name="static")

    base = app.openapi      # FastAPI's generator: builds the document once and caches it in app.openapi_schema

    def openapi() -> dict:
        if app.openapi_schema is None:
            document_rules(problems.document(base()), app.state.settings)
        return app.openapi_schema

    app.openapi = openapi

    @app.get("/docs", include_in_schema=False)
    def swagger_ui(request: Request):
        root = request.scope.get("root_path", "").rstrip("/")
        return get_swagger_ui_html(openapi_url=root + app.openapi_url, title=app.title + " - Swagger UI",
                                   swagger_js_url=f"{root}/static/swagger-ui/swagger-ui-bundle.js",
                                   swagger_css_url=f"{root}/static/swagger-ui/swagger-ui.css",
                                   swagger_favicon_url=f"{root}/static/swagger-ui/favicon-32x32.png",
                                   oauth2_redirect_url=None,
                                   swagger_ui_parameters={"validatorUrl": None})  # no badge from validator.swagger.io

    @app.get("/redoc", include_in_schema=False)
    def redoc(request: Request):
        root = request.scope.get("root_path", "").rstrip("/")
        return get_redoc_html(openapi_url=root + app.openapi_url, title=app.title + " - ReDoc",
                              # the vendored bundle with its CDN logo replaced (service/docs_pages.py)
                              redoc_js_url=f"{root}/redoc/redoc.standalone.js",
                              redoc_favicon_url=f"{root}/static/swagger-ui/favicon-32x32.png",
                              with_google_fonts=False)
    # /docs/accuracy (and every docs/*.md) as HTML, its source at /docs/accuracy.md: service/docs_pages.py


def finite_json(content) -> Response:
    """JSON with numpy arrays serialised natively (orjson: 1.7 ms for a 10^4-epoch track against
    ~45 ms for json.dumps of lists). orjson would write NaN as null, so non-finite numbers are
    refused here instead: they would be a bug, reported as a problem, never sent."""
    if not _all_finite(content):
        return problems.problem(500, "internal", "Internal error", "the computation produced non-finite values")
    return Response(orjson.dumps(content, option=orjson.OPT_SERIALIZE_NUMPY), media_type="application/json")


_LEAVES = frozenset((str, int, bool, type(None)))


def _all_finite(obj) -> bool:
    """Every float in ``obj`` (nested dicts, lists, tuples, numpy arrays) finite. A loop over a stack, dispatched on
    the exact type, rather than a recursive call per item: a track's answer holds ~300 of them (31 -> ~10 us)."""
    stack = [obj]
    pop, push, extend = stack.pop, stack.append, stack.extend
    while stack:
        o = pop()
        t = type(o)
        if t is float:
            if o - o != 0.0:               # inf - inf and nan - nan are nan, unequal to anything
                return False
        elif t is dict:
            extend(o.values())
        elif t is list or t is tuple:
            extend(o)
        elif t in _LEAVES:
            continue
        elif isinstance(o, np.ndarray):
            if o.dtype.kind in "fc" and not np.isfinite(o).all():
                return False
        elif isinstance(o, (float, np.floating)):
            if not math.isfinite(o):
                return False
        elif isinstance(o, dict):
            extend(o.values())
        elif isinstance(o, (list, tuple)):
            extend(o)
    return True


def _csv_rows(arrays: dict, time_scale: str):
    """The track's CSV: one header line, then a row per epoch: jd_tdb, its calendar date in ``time_scale``, the
    other columns, each number as its shortest repr."""
    dates = arrays[f"{time_scale}_iso"]
    yield ",".join((api.TRACK_KEYS[0], f"{time_scale}_iso") + api.TRACK_KEYS[1:]) + "\n"
    columns = np.column_stack([arrays[k] for k in api.TRACK_KEYS])
    for start in range(0, columns.shape[0], CSV_CHUNK):
        block = columns[start:start + CSV_CHUNK]
        yield "".join(f"{row[0]!r},{date}," + ",".join(repr(v) for v in row[1:]) + "\n"
                      for row, date in zip(block.tolist(), dates[start:start + CSV_CHUNK]))


def ecsv_response(answer, request: Request, *name: str) -> Response:
    """The answer's table as ECSV (ephem.api.to_ecsv: astropy's writer, its cost charged there unless prepaid), the
    request's URL as its source, saved as ``<name...>.ecsv`` (``ceres_current_track.ecsv``)."""
    text = api.to_ecsv(answer, source=str(request.url))
    return Response(text, media_type=api.ECSV_MEDIA_TYPE + "; charset=utf-8",
                    headers=downloads.disposition(downloads.filename(*name, fmt="ecsv")))


app = create_app()
