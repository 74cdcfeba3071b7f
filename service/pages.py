"""The web page: the service's answers for a person with a browser, server-rendered (Jinja2), no JavaScript needed.

Every form is a GET whose parameters are the API's, so the page's URL is its permalink and each result shows
the equivalent API URL, a ``curl`` line and a Python snippet. The page asks :mod:`ephem.api` exactly what the
API routes ask, under the same request budget (the service's middleware); a refusal or an invalid input is the
API's own problem (its ``detail`` and ``errors[].field``), shown inline next to the field it names, with the
status the API would give. The numbers are the API's: the templates only lay them out (no science here).

Routes (not in the OpenAPI document: they are pages, not the API):

- ``GET /``: the catalogue, a dataset chooser, links to each body's page;
- ``GET /bodies/{body}``: the body's key facts (value, 1σ or why there is none, unit, source), its precession
  (the rate, obliquity, H_d, K with their 1σ and the model that answered), its nutation terms with the tables'
  downloads, and the track form;
- ``GET /my-body``: a body of one's own, the fields of ``POST /v1/precession-nutation`` as a GET form validated by
  the same model: its precession and nutation;
- ``GET /bodies/{body}/history``: the spin axis over millennia, with the API's figure;
- ``GET /batch`` and ``POST /batch``: a CSV of bodies uploaded (up to the service's row limit; the form posts the
  file, the one form that cannot be a GET) and the answers as a table and a CSV download (a ``data:`` link: the
  service keeps nothing);
- ``GET /bodies/{body}/track``: a track (start, stop, step, the time scale stated; tolerance or model; axis): the
  model chosen with its estimate by term, every model's estimate against its predicted cost charted (the
  work-precision chart, inline SVG, the table folded below it), the first rows with the count, the plot, the CSV
  download.
"""
from __future__ import annotations

import contextvars
import csv
import functools
import io
import json
import math
import pathlib
import re
import shlex
from urllib.parse import quote, urlencode

from typing import Annotated, Literal, Optional

import anyio
from fastapi import FastAPI, File, Form, Request, UploadFile
from fastapi.responses import HTMLResponse, Response
from jinja2 import Environment, FileSystemLoader, select_autoescape

from fastapi.exceptions import RequestValidationError
from pydantic import Field, ValidationError

from ephem import api

from . import docs_pages, downloads
from .batch_input import csv_batch_rows
from .fast_routes import one_pass
from .schemas import HistoryIn, TrackIn, UserBody

TEMPLATES = pathlib.Path(__file__).resolve().parent / "templates"
#: rows of a track shown on the page (the CSV download holds them all)
TRACK_ROWS_SHOWN = 20
#: the form's default span: a year from 2025 at a 10-day step
TRACK_DEFAULTS = {"start": "2025-01-01", "stop": "2026-01-01", "step_days": "10"}
#: the history form's default: the last ten thousand years at a century
HISTORY_DEFAULTS = {"start_year": "-10000", "stop_year": "0", "step_years": "100"}
HISTORY_FIELDS = ("start_year", "stop_year", "step_years", "tolerance_mas", "orbit_model", "dataset")
HISTORY_KEYS = ("year", "obliquity_deg", "precession_angle_deg", "pole_ra_deg", "pole_dec_deg",
                "orbit_inclination_deg", "estimated_error_deg")
ORBIT_MODELS = ("secular", "nbody")
#: the rule of an angle that may turn (a longitude), as the API states and applies it; a latitude or an inclination
#: is bounded instead (its label says so): one rule per kind of angle, the API's
_TURNS = "; any number of turns, taken modulo 360"
#: the fields holding such an angle: a value outside [0, 360) is shown as read (500 is 140)
TURNING_ANGLES = ("orbit.node_deg", "orbit.peri_deg", "orbit.mean_anomaly_deg", "pole.ra_deg")
#: a body of the user's own: the POST /v1/precession-nutation fields by their paths, with a label each; the
#: form starts from the POST's own example (an asteroid like Vesta)
MY_BODY_FIELDS = (
    ("name", "Name"), ("rotation_period_hours", "Rotation period (hours)"),
    ("dynamical_ellipticity", "Dynamical ellipticity H_d (or the moments below)"),
    ("order", "e-order of the Hansen coefficients (empty: exact)"),
    ("orbit.a_au", "a (AU)"), ("orbit.e", "e (0 to 1, 1 excluded)"),
    ("orbit.i_deg", "i (deg, 0 to 180, to the ecliptic J2000)"),
    ("orbit.node_deg", f"Ω, the ascending node (deg{_TURNS})"),
    ("orbit.peri_deg", f"ω, the argument of perihelion (deg{_TURNS})"),
    ("orbit.mean_anomaly_deg", f"M, the mean anomaly (deg{_TURNS})"),
    ("orbit.epoch_jd_tdb", "Epoch of the elements (JD TDB)"),
    ("orbit.center", "The body orbited"),
    ("pole.ra_deg", f"Pole right ascension (deg, ICRF{_TURNS})"), ("pole.dec_deg", "Pole declination (deg, ICRF, −90 to 90)"),
    ("pole.epoch_jd_tdb", "Epoch of the pole (JD TDB)"),
    ("moments.A", "Moment A (the smallest)"), ("moments.B", "Moment B"), ("moments.C", "Moment C (the largest)"),
    ("track.start", "Start (ISO 8601, UTC unless a scale follows, or JD TDB; empty: no track)"),
    ("track.stop", "Stop"), ("track.step_days", "Step (days)"),
    ("track.tolerance_mas", "Tolerance (mas; the cheapest model within it)"), ("track.model", "Or a model"),
    ("track.axis", "Axis"))
MY_BODY_GROUPS = (("body", "The body"), ("orbit", "Its orbit (osculating, ecliptic and equinox J2000)"),
                  ("pole", "Its spin pole"), ("moments", "Its principal moments of inertia (any common unit)"),
                  ("track", "A track of its spin axis (the POST's track object; leave the start empty for none)"))
#: the text fields of a body of one's own (the rest are numbers)
_TEXT_FIELDS = ("name", "orbit.center", "track.start", "track.stop", "track.model", "track.axis")
def _my_body_choices() -> dict[str, tuple]:
    """The select fields of a body of one's own: their options, the models read from the families' registry when
    the page is drawn (a family registered after start-up is offered)."""
    return {"orbit.center": tuple(api.GM_CENTER), "track.model": ("", *api.MODELS), "track.axis": api.AXES}


#: the track form's fields, in the API's names, and the nutation tables' formats offered for download
TRACK_FIELDS = ("start", "stop", "step_days", "tolerance_mas", "model", "order", "axis", "free_wobble_phase_deg",
                "free_wobble_J_arcsec", "dataset", "time_scale")
TABLE_DOWNLOADS = (("csv", "CSV"), ("markdown", "Markdown"), ("latex", "LaTeX"))
#: the nutation tables' layouts (Petit et al. Tables 5-8 and 9-10)
TABLE_LAYOUTS = (("sin-cos", "Sin, Cos and Amp in arcseconds, periods in years (Petit et al. Tables 5-8)"),
                 ("amp-period", "Amp in milliarcseconds, periods in days (Tables 9-10)"))

_env = Environment(loader=FileSystemLoader(str(TEMPLATES)), autoescape=select_autoescape(["html"]),
                   trim_blocks=True, lstrip_blocks=True)


#: the format specs of 0 to 17 significant digits, made once (a track page formats some 250 numbers)
_G_SPECS = tuple(f".{d}g" for d in range(18))


def _number(value, digits: int = 10) -> str:
    """A number as the page prints it: ``digits`` significant digits, '—' where there is none."""
    if type(value) is float:        # the common case first: inf and nan print as str() prints them
        return format(value, _G_SPECS[digits] if 0 <= digits < 18 else f".{digits}g")
    if value is None:
        return "—"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    if not math.isfinite(value):
        return str(value)
    return f"{value:.{digits}g}"


_env.filters["num"] = _number


def _api_url(request: Request, path: str, params: dict, absolute: bool = False) -> str:
    """The API's URL for ``path`` and ``params``: under the configured public base URL (EPHEM_PUBLIC_BASE_URL), else
    relative (a link the browser resolves against the page's own address), or with ``absolute`` (a curl line) under
    the address the connection reached, the server's own socket. Never the request's Host header: a client could
    write any name there, and the page would hand it to the next reader (issue 42)."""
    return _api_at(request, path, _query(params), absolute)


def _query(params: dict) -> str:
    """``params``' query string, the empty ones left out (~25 us for a track's: a page encodes them once for its
    several links, :func:`_joined`)."""
    return urlencode({k: v for k, v in params.items() if v not in (None, "")})


def _joined(*queries: str) -> str:
    """Query strings one after the other: ``_joined(_query(params), "format=csv")`` is
    ``_query({**params, "format": "csv"})``."""
    return "&".join(q for q in queries if q)


def _api_at(request: Request, path: str, query: str, absolute: bool = False) -> str:
    """:func:`_api_url` of a query string already encoded (:func:`_query`)."""
    return _api_base(request, absolute) + path + (f"?{query}" if query else "")


def _api_base(request: Request, absolute: bool) -> str:
    configured = request.app.state.settings.public_base_url
    root = request.scope.get("root_path", "").rstrip("/")
    if configured:
        return configured + root
    server = request.scope.get("server")
    if not absolute or not server or server[1] is None:       # a unix socket has no address to print
        return root
    host, port = server[0], server[1]
    host = f"[{host}]" if ":" in str(host) else str(host)          # an IPv6 address
    scheme = request.scope.get("scheme", "http")
    default = {"http": 80, "https": 443}.get(scheme)
    return f"{scheme}://{host}" + ("" if port in (None, default) else f":{port}") + root


def _snippets(request: Request, path: str, params: dict, call: str, query: str | None = None) -> dict:
    """The equivalent API URL (``href`` the page's link to it), a curl line and a Python call for a result (``query``:
    ``params`` already encoded, :func:`_query`)."""
    query = _query(params) if query is None else query
    url = _api_at(request, path, query, absolute=True)
    return {"url": url, "href": _api_at(request, path, query), "curl": f"curl -s {shlex.quote(url)}",
            "python": f"from ephem import api\n{call}"}


def _python_call(function: str, body: str, params: dict) -> str:
    args = [repr(body)] + [f"{k}={v!r}" for k, v in params.items() if v not in (None, "")]
    return f"{function}({', '.join(args)})"


async def _answer(request: Request, compute, fields=()):
    """``compute()`` in the thread pool under the request's context (its budget), as a sync route runs; an
    exception becomes the problem the API would send for it: (result, None) or (None, problem). ``fields``: the
    names the page's form shows; the problem's ``marked`` says whether one of its fields stands among them (the
    page then says "at the field marked below", and only then)."""
    ctx = contextvars.copy_context()
    try:
        return await anyio.to_thread.run_sync(ctx.run, compute), None
    except Exception as exc:              # the app's handlers decide what is a problem and say it
        handler = next((request.app.exception_handlers[cls] for cls in type(exc).__mro__
                        if cls in request.app.exception_handlers), None)
        if handler is None:               # pragma: no cover - the app handles Exception itself
            raise
        response = await handler(request, exc)
        problem = json.loads(response.body)
        problem["fields"] = {e["field"]: e["reason"] for e in problem.get("errors", [])}
        problem["marked"] = any(f in fields for f in problem["fields"])
        return None, problem


def _page(template: str, status: int = 200, **context) -> HTMLResponse:
    return HTMLResponse(_env.get_template(template).render(**context), status_code=status)


def _status(problem: dict | None) -> int:
    return 200 if problem is None else int(problem.get("status", 422))


def install(app: FastAPI) -> None:
    """The page's routes on ``app`` (outside the OpenAPI document)."""
    docs_pages.install(app, _page)

    @app.get("/", include_in_schema=False, response_class=HTMLResponse)
    async def index(request: Request, dataset: str = api.DEFAULT_DATASET):
        bodies, problem = await _answer(request, lambda: api.list_bodies(dataset=dataset))
        return _page("index.html", _status(problem), bodies=bodies or [], dataset=dataset, problem=problem,
                     datasets=api.available_datasets(), title="Spin axes of the catalogue's bodies")

    @app.get("/bodies/{body}", include_in_schema=False, response_class=HTMLResponse)
    async def body_page(request: Request, body: str, dataset: str = api.DEFAULT_DATASET):
        def compute():
            return {"record": api.body_record(body, dataset=dataset), "precession": api.precession(body,
                                              dataset=dataset),
                    "nutation": api.nutation(body, dataset=dataset)}

        result, problem = await _answer(request, compute)
        name = result["record"]["name"] if result else body
        params = {"dataset": dataset}
        facts, why_notes = _facts(result["record"]) if result else ([], [])
        return _page("body.html", _status(problem), body=name, dataset=dataset, result=result, problem=problem,
                     facts=facts, why_notes=why_notes,
                     form={**TRACK_DEFAULTS, "dataset": dataset}, models=api.MODELS, axes=api.AXES,
                     history_form={**HISTORY_DEFAULTS, "tolerance_mas": "", "orbit_model": "", "dataset": dataset},
                     orbit_models=ORBIT_MODELS,
                     downloads=[(layout_label, [(label, _api_url(request, f"/v1/bodies/{name}/nutation",
                                                                 {**params, "format": fmt, "layout": layout}),
                                                 downloads.filename(name, dataset, "nutation", layout, fmt=fmt))
                                                for fmt, label in TABLE_DOWNLOADS])
                                for layout, layout_label in TABLE_LAYOUTS],
                     # every quantity in its unit, for astropy (layout-free): the nutation's terms, the precession's row
                     ecsv_downloads={what: (_api_url(request, f"/v1/bodies/{name}/{what}", {**params, "format": "ecsv"}),
                                            downloads.filename(name, dataset, what, fmt="ecsv"))
                                     for what in ("precession", "nutation")},
                     orbit_span=api.shipped_orbit_span(name),
                     precession_code=_snippets(request, f"/v1/bodies/{name}/precession", params,
                                               _python_call("api.precession", name, params)),
                     nutation_code=_snippets(request, f"/v1/bodies/{name}/nutation", params,
                                             _python_call("api.nutation", name, params)),
                     title=f"{name}: precession and nutation")

    @app.get("/bodies/{body}/track", include_in_schema=False, response_class=HTMLResponse)
    @one_pass       # its eleven text parameters read in one pass, as the API's track route reads its own
    async def track_page(request: Request, body: str, start: str = TRACK_DEFAULTS["start"],
                         stop: str = TRACK_DEFAULTS["stop"], step_days: str = TRACK_DEFAULTS["step_days"],
                         tolerance_mas: str = "", model: str = "", order: str = "", axis: str = "figure",
                         free_wobble_phase_deg: str = "", free_wobble_J_arcsec: str = "",
                         dataset: str = api.DEFAULT_DATASET, time_scale: str = "utc"):
        form = {"start": start, "stop": stop, "step_days": step_days, "tolerance_mas": tolerance_mas,
                "model": model, "order": order, "axis": axis, "free_wobble_phase_deg": free_wobble_phase_deg,
                "free_wobble_J_arcsec": free_wobble_J_arcsec, "dataset": dataset, "time_scale": time_scale}
        params = {k: form[k] for k in TRACK_FIELDS}

        def compute():
            _check_form(_TrackForm, form)       # every field as the API's query checks it: all the errors at once
            # the API's own parsing: the query's text as the route would get it
            step, tol = _float(step_days, "step_days"), _float(tolerance_mas, "tolerance_mas") if tolerance_mas else None
            track = api.track_arrays(body, start, stop, step, dataset=dataset,
                                     max_samples=request.app.state.settings.max_track_samples, tolerance_mas=tol,
                                     model=model or None, order=_int(order, "order") if order else None, axis=axis,
                                     free_wobble_phase_deg=_optional_float(free_wobble_phase_deg,
                                                                           "free_wobble_phase_deg"),
                                     free_wobble_J_arcsec=_optional_float(free_wobble_J_arcsec, "free_wobble_J_arcsec"),
                                     time_scale=time_scale)
            # speed against accuracy for this scene: every model's estimate and cost over these epochs
            models = api.track_models(body, start, stop, step, dataset=dataset, tolerance_mas=tol, axis=axis,
                                      max_samples=request.app.state.settings.max_track_samples)
            # ... charted from the same answer (the drawing charged, as the .svg route charges it), inline: the
            # points' hover titles work and no second request is made
            chart = _inline_svg(api.models_chart(models, fmt="svg"))
            # each model beside its row of the comparison's table (whether the tolerance admits it), for the table
            return {**track, "models": models, "models_chart": chart,
                    "comparison": list(zip(models["models"],
                                           (row["eligible"] for row in api.track_models_rows(models))))}

        result, problem = await _answer(request, compute, TRACK_FIELDS)
        rows, count = [], 0
        if result is not None:
            count = len(result["jd_tdb"])
            keys = (api.TRACK_KEYS[0], f"{time_scale}_iso", *api.TRACK_KEYS[1:])     # the date beside jd_tdb
            shown = min(count, TRACK_ROWS_SHOWN)      # by column: a slice each (not 200 numpy scalars), as floats
            rows = list(zip(*(result[k][:shown] if k.endswith("_iso") else result[k][:shown].astype(float).tolist()
                              for k in keys)))
        name = result["body"] if result else body
        query = _query(params)      # encoded once: the track's links (its CSV, its ECSV, the API's URL) share it
        models_query = urlencode({k: form[k] for k in ("start", "stop", "step_days", "tolerance_mas", "axis", "dataset")
                                  if form[k] not in (None, "")})
        return _page("track.html", _status(problem), body=name, form=form, result=result, problem=problem,
                     models_json_url=f"/v1/bodies/{quote(name)}/track/models?{models_query}",
                     models_svg_url=f"/v1/bodies/{quote(name)}/track/models.svg?{models_query}",
                     rows=rows, count=count, keys=keys if result is not None else api.TRACK_KEYS, models=api.MODELS,
                     axes=api.AXES, time_scales=api.CALENDAR_SCALES,
                     ecsv_url=_api_at(request, f"/v1/bodies/{name}/track", _joined(query, "format=ecsv")),
                     ecsv_name=downloads.filename(name, dataset, "track", fmt="ecsv"),
                     csv_url=_api_at(request, f"/v1/bodies/{name}/track", _joined(query, "format=csv")),
                     csv_name=downloads.filename(name, dataset, "track", fmt="csv"),
                     # every parameter of the track reaches its figure (the figure of this track, not a default's)
                     plot_url=_api_url(request, f"/v1/bodies/{name}/track.svg",
                                       {k: v for k, v in params.items() if k != "time_scale"}),
                     snippets=_snippets(request, f"/v1/bodies/{name}/track", params,
                                    _python_call("api.track", name, {**params, "step_days": _maybe_float(step_days),
                                                                     "tolerance_mas": _maybe_float(tolerance_mas),
                                                                     "order": _maybe_int(order),
                                                                     "free_wobble_phase_deg": _maybe_float(free_wobble_phase_deg),
                                                                     "free_wobble_J_arcsec": _maybe_float(free_wobble_J_arcsec)}),
                                    query=query),
                     title=f"{name}: spin-axis track")


    @app.get("/bodies/{body}/history", include_in_schema=False, response_class=HTMLResponse)
    async def history_page(request: Request, body: str, start_year: str = HISTORY_DEFAULTS["start_year"],
                           stop_year: str = HISTORY_DEFAULTS["stop_year"],
                           step_years: str = HISTORY_DEFAULTS["step_years"], tolerance_mas: str = "",
                           orbit_model: str = "", dataset: str = api.DEFAULT_DATASET):
        form = {"start_year": start_year, "stop_year": stop_year, "step_years": step_years,
                "tolerance_mas": tolerance_mas, "orbit_model": orbit_model, "dataset": dataset}
        params = {k: form[k] for k in HISTORY_FIELDS}

        def compute():
            _check_form(_HistoryForm, form)     # every field as the API's query checks it: all the errors at once
            return api.history(body, _float(start_year, "start_year"), _float(stop_year, "stop_year"),
                               _float(step_years, "step_years"), dataset=dataset,
                               tolerance_mas=_float(tolerance_mas, "tolerance_mas") if tolerance_mas else None,
                               orbit_model=orbit_model or None,
                               max_samples=request.app.state.settings.max_track_samples)

        result, problem = await _answer(request, compute, HISTORY_FIELDS)
        rows, count, largest = [], 0, None
        if result is not None:
            count = len(result["year"])
            rows = [[float(result[k][i]) for k in HISTORY_KEYS] for i in range(min(count, TRACK_ROWS_SHOWN))]
            # the estimate in the unit of the answer's own per-epoch estimates (deg): one unit for the error
            largest = max(float(x) for x in result["estimated_error_deg"])
        name = result["body"] if result else body
        plot_params = {k: form[k] for k in HISTORY_FIELDS}
        return _page("history.html", _status(problem), body=name, form=form, result=result, problem=problem,
                     rows=rows, count=count, keys=HISTORY_KEYS, orbit_models=ORBIT_MODELS, largest_error_deg=largest,
                     orbit_span=api.shipped_orbit_span(name), fallback=_fallback(result, orbit_model),
                     csv_url=_api_url(request, f"/v1/bodies/{name}/history", {**params, "format": "csv"}),
                     csv_name=downloads.filename(name, dataset, "history", fmt="csv"),
                     ecsv_url=_api_url(request, f"/v1/bodies/{name}/history", {**params, "format": "ecsv"}),
                     ecsv_name=downloads.filename(name, dataset, "history", fmt="ecsv"),
                     # an SVG: it scales with the page (a phone's width too)
                     plot_url=_api_url(request, f"/v1/bodies/{name}/history.svg", plot_params),
                     snippets=_snippets(request, f"/v1/bodies/{name}/history", params,
                                        _python_call("api.history", name, {
                                            **params, "start_year": _maybe_float(start_year),
                                            "stop_year": _maybe_float(stop_year),
                                            "step_years": _maybe_float(step_years),
                                            "tolerance_mas": _maybe_float(tolerance_mas)})),
                     title=f"{name}: the spin axis over millennia")


    @app.get("/my-body", include_in_schema=False, response_class=HTMLResponse)
    async def my_body_page(request: Request):
        query = dict(request.query_params)
        example = UserBody.model_config["json_schema_extra"]["examples"][0]
        form = {name: query.get(name, "" if query else _example_value(example, name)) for name, _ in MY_BODY_FIELDS}
        result, problem = None, None
        if query:
            def compute():
                user = _user_body(form)
                body = user.to_body()
                track = None if user.track is None else user.track.model_dump()
                ans = api.precession_nutation(body, order=user.order, track=track,
                                              max_samples=request.app.state.settings.max_track_samples)
                if track is not None:       # its figure, drawn from the same request (inline SVG: it scales)
                    ans["track_chart"] = _inline_svg(api.render_plot(
                        "precession", body, track["start"], track["stop"], track["step_days"], fmt="svg",
                        tolerance_mas=track["tolerance_mas"], model=track["model"], order=user.order,
                        axis=track["axis"])).replace("<svg ", '<svg role="img" aria-labelledby="user-track-caption" ', 1)
                return ans

            result, problem = await _answer(request, compute,
                                            [n for n, _ in MY_BODY_FIELDS] + [g for g, _ in MY_BODY_GROUPS])
        doc = _user_document(form)
        track_rows, track_csv = [], None
        if result is not None and "track" in result:
            t = result["track"]
            track_rows = [[float(t[k][i]) for k in api.TRACK_KEYS] for i in range(min(len(t["jd_tdb"]),
                                                                                      TRACK_ROWS_SHOWN))]
            track_csv = "data:text/csv;charset=utf-8," + quote(_track_csv(t))
        return _page("my_body.html", _status(problem), body=form["name"] or "your body", form=form, result=result,
                     problem=problem, fields=MY_BODY_FIELDS, groups=MY_BODY_GROUPS, choices=_my_body_choices(),
                     turned=_turned(form) if result else [], track_rows=track_rows, track_keys=api.TRACK_KEYS,
                     track_csv=track_csv, track_csv_name=downloads.filename(form["name"] or "user body", "user",
                                                                            "track", fmt="csv"),
                     precession_code={
                         "url": _api_url(request, "/v1/precession-nutation", {}, absolute=True),
                         "href": _api_url(request, "/v1/precession-nutation", {}),
                         "curl": f"curl -s -X POST "
                                 f"{shlex.quote(_api_url(request, '/v1/precession-nutation', {}, absolute=True))} "
                                 f"-H 'content-type: application/json' -d {shlex.quote(json.dumps(doc))}",
                         "python": "from ephem import api\n" + _python_body(doc)},
                     title="A body of your own")


    @app.get("/about", include_in_schema=False, response_class=HTMLResponse)
    async def about(request: Request):
        """The version, how to cite it, the theories the answers rest on, the data sets and every source of their
        values, the licence: all read from the answers and the catalogue (nothing written twice)."""
        about, problem = await _answer(request, lambda: _about(request.app.version))
        return _page("about.html", _status(problem), problem=problem, **(about or {}),
                     title="About ephem, and how to cite it")

    @app.get("/batch", include_in_schema=False, response_class=HTMLResponse)
    async def batch_form(request: Request):
        return _page("batch.html", result=None, problem=None, form={}, max_rows=_max_rows(request),
                     template_url=BATCH_TEMPLATE_URL, title="A batch of bodies")

    @app.get(BATCH_TEMPLATE_URL, include_in_schema=False)
    async def batch_template():
        """A CSV to start from: the columns of docs/batch_input.md, one row per form of the inertia."""
        return Response(BATCH_TEMPLATE, media_type="text/csv; charset=utf-8",
                        headers=downloads.disposition(BATCH_TEMPLATE_NAME))

    @app.post("/batch", include_in_schema=False, response_class=HTMLResponse)
    async def batch_page(request: Request, file: Optional[UploadFile] = File(None), start_year: str = Form(""),
                         stop_year: str = Form(""), step_years: str = Form("")):
        # no file chosen: the form again, the problem at its file field (not the framework's raw JSON)
        raw = await file.read() if file is not None and file.filename else None
        form = {"start_year": start_year, "stop_year": stop_year, "step_years": step_years}

        def compute():
            if raw is None:
                raise api.InvalidInputError("file", "choose a CSV file of bodies to upload (the columns of "
                                                    "docs/batch_input.md; the template on this page is one)")
            rows = csv_batch_rows(raw)
            history = None
            if start_year or stop_year or step_years:
                history = {"start_year": _float(start_year, "start_year"), "stop_year": _float(stop_year, "stop_year"),
                           "step_years": _float(step_years, "step_years")}
            answer = api.batch(rows, history=history, max_rows=_max_rows(request), history_path="")
            # its table as astropy's ECSV too, written (and charged) within the request
            return {**answer, "ecsv": api.to_ecsv(answer, source=str(request.url))}

        result, problem = await _answer(request, compute, ("file", "start_year", "stop_year", "step_years"))
        if problem is not None and problem.get("fields"):
            problem["marked"] = True                    # every problem of a batch stands at its file field
        download = download_ecsv = None
        if result is not None:
            out = io.StringIO()
            writer = csv.writer(out, lineterminator="\n")
            writer.writerow(result["columns"])
            writer.writerows([["" if r.get(c) is None else r.get(c) for c in result["columns"]] for r in result["rows"]])
            download = "data:text/csv;charset=utf-8," + quote(out.getvalue())
            download_ecsv = "data:text/x-ecsv;charset=utf-8," + quote(result["ecsv"])
        history = {k: v for k, v in form.items() if v}
        url = _api_url(request, "/v1/batch", history, absolute=True)
        name = (file.filename if file is not None else "") or "bodies.csv"
        snippets = {"url": url, "href": _api_url(request, "/v1/batch", history),
                    "curl": f"curl -s -X POST {shlex.quote(url)} -H 'content-type: text/csv' --data-binary @{shlex.quote(name)}",
                    "python": "import csv\nfrom ephem import api\n"
                              f"rows = list(csv.DictReader(open({name!r}, newline='')))\n"
                              f"api.batch(rows{', history=' + repr({k: float(v) for k, v in history.items()}) if history else ''})"}
        return _page("batch.html", _status(problem), result=result, problem=problem, form=form,
                     max_rows=_max_rows(request), download=download, shown=TRACK_ROWS_SHOWN,
                     template_url=BATCH_TEMPLATE_URL, download_name=downloads.filename(
                         name.rsplit(".", 1)[0], "batch", "answers", fmt="csv"),
                     download_ecsv=download_ecsv, download_ecsv_name=downloads.filename(
                         name.rsplit(".", 1)[0], "batch", "answers", fmt="ecsv"),
                     filename=name, snippets=snippets, title="A batch of bodies")


def _facts(record: dict) -> tuple[list[dict], list[tuple[list[str], str]]]:
    """The body's catalogue values as the key facts table's rows, each without a 1σ pointing to its reason by number,
    and the reasons, one line each with the values it applies to (six orbit elements share one: one line)."""
    rows, notes = [], {}
    for key, v in record["values"].items():
        note = None
        if v.get("uncertainty") is None and v.get("no_uncertainty"):
            keys = notes.setdefault(v["no_uncertainty"], [])
            keys.append(key)
            note = list(notes).index(v["no_uncertainty"]) + 1
        rows.append({"key": key, **v, "note": note})
    return rows, [(keys, reason) for reason, keys in notes.items()]


class _TrackForm(TrackIn):
    """The track form's fields as the API's query takes them (TrackIn: the POST's track object, the same rules),
    with the e-order and the dataset."""
    order: Optional[Annotated[int, Field(ge=0, le=api.MAX_ORDER)]] = None
    dataset: Literal[tuple(api.available_datasets())] = api.DEFAULT_DATASET


class _HistoryForm(HistoryIn):
    """The history form's fields as the API's query takes them."""
    dataset: Literal[tuple(api.available_datasets())] = api.DEFAULT_DATASET


def _check_form(model, form: dict) -> None:
    """Every field of a GET form checked at once, as the API's query is (text parsed as the query's: "10" is a
    number, "abc" is not), so that the page shows every error of a submission, not the first: a 422 naming them
    all."""
    try:
        model.model_validate({k: v for k, v in form.items() if v not in ("", None)}, strict=False)
    except ValidationError as exc:
        raise RequestValidationError([{**e, "loc": ("query",) + tuple(e["loc"])} for e in exc.errors()]) from None


def _fallback(result: dict | None, orbit_model: str) -> str | None:
    """Why the history's orbit is not the shipped N-body one, where the default chose another (a span beyond it):
    the answer's own words, shown where the result is."""
    if result is None or orbit_model:
        return None
    m = result["model"]
    if m.get("name") == "nbody":
        return None
    why_not = next((c.get("why_not") for c in m.get("candidates") or () if c.get("name") == "nbody"), None)
    return "; ".join(x for x in (why_not, m.get("why_chosen")) if x) or None


def _turned(form: dict) -> list[tuple[str, str, float]]:
    """The angles given outside [0, 360) that the API takes modulo 360 (as it documents): (field, as given, as
    read), shown beside the result so that a 500° right ascension is seen to be 140°."""
    out = []
    for name in TURNING_ANGLES:
        try:
            value = float(form.get(name) or "")
        except ValueError:
            continue
        if math.isfinite(value) and not 0.0 <= value < 360.0:
            out.append((name, form[name], value % 360.0))
    return out


#: the batch page's template: the columns of docs/batch_input.md, a row for each form of the inertia (values of
#: Vesta's and Ceres' kind, for the shape of the file only) and a σ column
BATCH_TEMPLATE_URL = "/batch/template.csv"
BATCH_TEMPLATE_NAME = "bodies_template.csv"
BATCH_TEMPLATE = (
    "name,a_au,e,i_deg,node_deg,peri_deg,mean_anomaly_deg,epoch_jd_tdb,pole_ra_deg,pole_dec_deg,pole_epoch_jd_tdb,"
    "rotation_period_hours,dynamical_ellipticity,moment_a,moment_b,moment_c,axis_a_km,axis_b_km,axis_c_km,"
    "pole_dec_deg_sigma\n"
    "by-ellipticity,2.36,0.089,7.14,103.7,151.7,169.2,2460200.5,309.03,42.23,2451545.0,5.342,0.1689,,,,,,,0.1\n"
    "by-moments,2.77,0.079,10.6,80.3,73.6,77.4,2460200.5,291.4,66.8,2451545.0,9.074,,0.3433,0.3546,0.42,,,,\n"
    "by-axes,2.5,0.1,5.0,10.0,20.0,30.0,2460200.5,100.0,20.0,2451545.0,7.5,,,,,290.0,265.0,229.0,\n")


#: a body of each family, for the theories its answers name: (who they serve, body)
ABOUT_FAMILIES = (("An asteroid, a dwarf planet or a planet under the Sun's torque", "vesta"),
                  ("The Earth under the Moon and the Sun", "earth"),
                  ("The Moon, a synchronous rotator", "moon"))
#: the distribution whose metadata gives the summary and the licence
DISTRIBUTION = "ephem-asteroid-pn"


@functools.lru_cache(maxsize=4)
def _about(version: str) -> dict:
    """The About page's content, from the answers (their model.theory), the catalogue (each dataset's description,
    each value's reference) and the package's metadata; computed once per process (none of it changes)."""
    import importlib.metadata

    try:
        meta = importlib.metadata.metadata(DISTRIBUTION)
        summary, licence = meta.get("Summary") or "", meta.get("License-Expression") or meta.get("License") or ""
    except importlib.metadata.PackageNotFoundError:        # pragma: no cover - a source tree not installed
        summary, licence = "", ""
    theories = [(who, api.precession(body)["model"]["theory"]) for who, body in ABOUT_FAMILIES]
    for orbit in ("nbody", "secular"):             # a history's two orbits (its spin: Kinoshita's first order)
        model = api.history("ceres", -1000.0, 0.0, 500.0, orbit_model=orbit)["model"]
        theories.append((f"The spin axis over millennia, the {orbit} orbit", f"{model['spin']}; {model['description']}"))
    sources: dict[tuple, dict] = {}
    for dataset in api.available_datasets():
        for entry in api.list_bodies(dataset=dataset):
            record = api.body_record(entry["name"], dataset=dataset)
            for key, value in record["values"].items():
                ref = value.get("reference") or {}
                if not ref:
                    continue
                ident = (ref.get("authors"), ref.get("year"), ref.get("title"))
                source = sources.setdefault(ident, {
                    "citation": ". ".join(str(x).rstrip(".") for x in (ref.get("authors"), ref.get("year"),
                                                                       ref.get("title"), ref.get("journal")) if x),
                    "doi": ref.get("doi"), "where": ref.get("where"), "uses": []})
                use = f"{dataset}: {record['name']} {key}"
                if use not in source["uses"]:
                    source["uses"].append(use)
    bibtex = ("@software{ephem_" + version.replace(".", "_") + ",\n"
              "  title = {ephem: asteroid precession-nutation ephemeris},\n"
              f"  version = {{{version}}},\n"
              f"  note = {{{summary}; cite also the papers its answers rest on}},\n"
              f"  license = {{{licence}}}\n}}")
    return {"version": version, "summary": summary, "licence": licence, "bibtex": bibtex, "theories": theories,
            "datasets": [(name, api.load_catalogue(name).description) for name in api.available_datasets()],
            "sources": sorted(sources.values(), key=lambda x: x["citation"])}


def _float(text: str, field: str) -> float:
    """A query's number as the API route parses it (a 422 naming the field otherwise)."""
    try:
        return float(text)
    except ValueError:
        raise api.InvalidInputError(field, f"must be a number, got {text!r}") from None


def _inline_svg(svg: bytes) -> str:
    """An SVG document as an element of the page: without its XML declaration and doctype, as wide as the page
    (its viewBox keeps the aspect)."""
    text = svg.decode("utf-8")
    text = text[text.index("<svg"):]
    return re.sub(r'^(<svg\b[^>]*?) width="[^"]*" height="[^"]*"', r'\1 width="100%"', text, count=1)


def _maybe_float(text: str):
    try:
        return float(text) if text else None
    except ValueError:
        return text


def _int(text: str, field: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise api.InvalidInputError(field, f"must be a whole number, got {text!r}") from None


def _maybe_int(text: str):
    try:
        return int(text) if text else None
    except ValueError:
        return text


def _optional_float(text: str, field: str) -> float | None:
    return _float(text, field) if text else None


def _example_value(example: dict, path: str) -> str:
    head, _, tail = path.partition(".")
    value = example.get(head)
    if tail:
        value = (value or {}).get(tail)
    return "" if value is None else str(value)


def _user_document(form: dict) -> dict:
    """The POST's JSON body of the form's fields: numbers where they parse, text kept (refused by the model)."""
    doc: dict = {}
    for name, text in form.items():
        if text == "":
            continue
        value = text if name in _TEXT_FIELDS else _number_or_text(text)
        head, _, tail = name.partition(".")
        if tail:
            doc.setdefault(head, {})[tail] = value
        else:
            doc[head] = value
    return doc


def _number_or_text(text: str):
    try:
        value = float(text)
    except ValueError:
        return text
    return int(value) if value.is_integer() and "." not in text and "e" not in text.lower() else value


def _user_body(form: dict) -> UserBody:
    """The form validated as the POST validates its body (the same model), then the library's checks of the orbit,
    the pole and the body each on its own, so that every error of a submission shows at once (the POST stops at
    the first of these): an error names the field's path (the moments' as ``moments``, their fieldset)."""
    try:
        user = UserBody.model_validate(_user_document(form))      # an integer is a number there, as in JSON
    except ValidationError as exc:
        raise RequestValidationError([{**e, "loc": ("body",) + tuple(e["loc"])} for e in exc.errors()]) from None
    example = UserBody.model_validate({k: v for k, v in UserBody.model_config["json_schema_extra"]["examples"][0]
                                       .items() if k != "track"})
    errors = []

    def check(make, fallback):
        try:
            return make()
        except api.InvalidInputError as exc:
            field = exc.field if not exc.field.startswith("inertia") else "moments" + exc.field[len("inertia"):]
            errors.append({"loc": ("body", *field.split(".")), "msg": exc.reason, "type": "value_error"})
            return fallback

    # each part checked with the others' example values where they are wrong, so that each error shows
    orbit = check(lambda: api.Orbit(**user.orbit.model_dump(), body=user.name),
                  api.Orbit(**example.orbit.model_dump(), body=user.name))
    pole = check(lambda: api.Pole(**user.pole.model_dump(), body=user.name),
                 api.Pole(**example.pole.model_dump(), body=user.name))
    check(lambda: api.Body(name=user.name, orbit=orbit, pole=pole, rotation_period_hours=user.rotation_period_hours,
                           moments=None if user.moments is None else (user.moments.A, user.moments.B, user.moments.C),
                           dynamical_ellipticity=user.dynamical_ellipticity), None)
    if errors:
        raise RequestValidationError(errors)
    return user


def _track_csv(track: dict) -> str:
    """A track's arrays as the API's track CSV writes them: its keys, one row per epoch, each number its repr."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(api.TRACK_KEYS)
    writer.writerows([repr(float(track[k][i])) for k in api.TRACK_KEYS] for i in range(len(track["jd_tdb"])))
    return out.getvalue()


def _python_body(doc: dict) -> str:
    orbit = ", ".join(f"{k}={v!r}" for k, v in doc.get("orbit", {}).items())
    pole = ", ".join(f"{k}={v!r}" for k, v in doc.get("pole", {}).items())
    inertia = (f"moments=({doc['moments'].get('A')!r}, {doc['moments'].get('B')!r}, {doc['moments'].get('C')!r})"
               if "moments" in doc else f"dynamical_ellipticity={doc.get('dynamical_ellipticity')!r}")
    return (f"b = api.Body(name={doc.get('name', 'user body')!r}, orbit=api.Orbit({orbit}), pole=api.Pole({pole}),\n"
            f"             rotation_period_hours={doc.get('rotation_period_hours')!r}, {inertia})\n"
            f"api.precession_nutation(b, {doc.get('order')!r}"
            + (f", track={doc['track']!r})" if doc.get("track") else ")"))


def _max_rows(request: Request) -> int:
    return request.app.state.settings.max_batch_rows
