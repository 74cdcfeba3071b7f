"""The rules the service's OpenAPI document states for each operation: bounds, limits and schemas.

The parameters' and the body's bounds
(patterns, ranges), the texts of the limits the library and the settings set, and the nutation tables' schema;
:func:`document_rules` writes them into the document that :mod:`service.app` serves.
"""
from __future__ import annotations

import re

from ephem.api import (KNOWN_PERTURBERS, LAPLACE_LIMIT, MAX_ANGLE_DEG, MAX_NUMERICAL_ORBITS, MAX_PLOT_POINTS,
                       MIN_ROTATION_PERIOD_HOURS, SERIES_MAX_DELTA, TIME_PATTERN_ECMA, ut1_span)

from . import problems, schemas
from .settings import Settings

# ------------------------------------------------------------------------------------------------ the rules
# What the service enforces beyond the parameter types, stated in the OpenAPI document: as schema constraints
# where JSON Schema can say it (each enforced by ephem with a 422 naming the field, so the document and the
# service agree), and in the operation descriptions where it cannot (rules across fields, or of the body's
# physics). tests/service/test_schemathesis.py holds the service to exactly these: a schema-valid request is refused
# only for a rule written here.


def perturbers_pattern() -> str:
    """The ``perturbers`` query's pattern: a comma-separated list of the names, any case, of ephem.api.KNOWN_PERTURBERS
    as it stands (a perturber registered after this module's import is in the document an app makes then)."""
    name = "|".join("".join(f"[{c.upper()}{c.lower()}]" if c.isalpha() else re.escape(c) for c in n.lower())
                    for n in KNOWN_PERTURBERS)
    return rf"^\s*(?:{name})\s*(?:,\s*(?:{name})\s*)*$"


PERTURBERS_PATTERN = perturbers_pattern()
_JD = {"exclusiveMinimum": 0, "exclusiveMaximum": 1e7}
_POSITIVE = {"exclusiveMinimum": 0}
#: constraints of query parameters, by name, in every operation that has them
PARAMETER_RULES = {
    "start": {"pattern": TIME_PATTERN_ECMA}, "stop": {"pattern": TIME_PATTERN_ECMA},
    "free_wobble_epoch": {"pattern": TIME_PATTERN_ECMA}, "step_days": _POSITIVE,
    "perturbers": {"pattern": PERTURBERS_PATTERN},
    # angles taken modulo 360 deg (ephem.bodies.catalogue.MAX_ANGLE_DEG; the body's are stated by service.schemas.Angle)
    "free_wobble_phase_deg": schemas.ANGLE_BOUNDS, "rotation_phase_deg": schemas.ANGLE_BOUNDS,
}
#: constraints of the POST body's fields: (component, field) -> constraints (on the number or string branch)
BODY_RULES = {
    ("OrbitIn", "a_au"): _POSITIVE, ("OrbitIn", "e"): {"minimum": 0, "exclusiveMaximum": 1},
    ("OrbitIn", "i_deg"): {"minimum": 0, "maximum": 180}, ("PoleIn", "dec_deg"): {"minimum": -90, "maximum": 90},
    ("OrbitIn", "epoch_jd_tdb"): _JD, ("PoleIn", "epoch_jd_tdb"): _JD,
    ("MomentsIn", "A"): _POSITIVE, ("MomentsIn", "B"): _POSITIVE, ("MomentsIn", "C"): _POSITIVE,
    ("UserBody", "rotation_period_hours"): {"minimum": MIN_ROTATION_PERIOD_HOURS},
    ("UserBody", "dynamical_ellipticity"): {"exclusiveMinimum": 0, "maximum": 0.5},
    ("TrackIn", "start"): {"pattern": TIME_PATTERN_ECMA, **_JD},
    ("TrackIn", "stop"): {"pattern": TIME_PATTERN_ECMA, **_JD},
    ("TrackIn", "free_wobble_epoch"): {"pattern": TIME_PATTERN_ECMA, **_JD}, ("TrackIn", "step_days"): _POSITIVE,
}


#: the POST's fields as the library names them -> as the request body nests them (problems.FIELD_PATHS)
POST_FIELD_PATHS = {**{f: f"track.{f}" for f in ("start", "stop", "step_days", "tolerance_mas", "model", "axis",
                                                 "free_wobble_phase_deg", "free_wobble_J_arcsec",
                                                 "free_wobble_epoch")},
                    "inertia": "moments"}
problems.FIELD_PATHS[("POST", "/v1/precession-nutation")] = POST_FIELD_PATHS


def _rule_texts(settings: Settings) -> dict[str, str]:
    lo, hi = ut1_span()
    na = ("422 not-applicable when the theory does not hold for the request, with the reason: a spin slower than "
          "30 times the orbital mean motion (ω/n < 30: the Moon), no model within tolerance_mas over these "
          f"epochs, a numerical rung over more than {MAX_NUMERICAL_ORBITS} orbits, the real orbit outside "
          "DE421's span (1899-07-29 to 2053-10-09 TDB), or a perturber the theory does not take.")
    texts = {
        "times": "Times (start, stop, free_wobble_epoch) follow the pattern: an ISO 8601 date or date-time, UTC "
                 "unless a space and a scale follow (TDB, TT, TAI, TCB, TCG, UTC, UT1), or a Julian date in TDB, "
                 "digits in (0, 1e7) (2451545.0, JD2451545.0); the date must exist in the calendar (no 30 "
                 f"February); UT1 is accepted from {lo} through {hi} only, the span of the IERS tables bundled "
                 "with astropy (UT1 - UTC is not known beyond).",
        "grid": f"stop must not be before start; step_days > 0, and the epochs start, start + step_days, ... up to "
                f"stop number at most {settings.max_track_samples} (EPHEM_MAX_TRACK_SAMPLES); step_days is one the "
                "span's Julian dates resolve in float64 (at least the spacing of doubles at its largest date: "
                "4.657e-10 d near J2000), else its epochs would repeat.",
        "tolerance": "tolerance_mas lets the fidelity ladder choose the model: give it or order, not both.",
        "tolerance_model": "tolerance_mas lets the fidelity ladder choose the model: give it, or model and "
                           "order, not both. order goes with model=series, which needs one (order alone means "
                           "series); lunisolar is the Earth's model under the Moon and the Sun.",
        "laplace": f"order needs e below the Laplace limit {LAPLACE_LIMIT:.4f} (beyond it the e-power series "
                   "diverge: omit order for the exact coefficients).",
        "perturbers": "perturbers: names among sun, earth, moon, comma-separated, each at most once; the Moon is "
                      "a perturber of the Earth only, and any other must be the orbit's centre (else 422 "
                      "not-applicable).",
        "cut": "cut_mas applies to the lunisolar series (the Earth with the Moon) only, and not with tolerance_mas.",
        "wobble": "free_wobble_J_arcsec and free_wobble_epoch need free_wobble_phase_deg, which needs axis=figure; "
                  "a body without a published wobble amplitude (Earth, Moon, Mars and Eros have one) needs "
                  "free_wobble_J_arcsec with the phase; rotation_phase_deg is not given with free_wobble_phase_deg, "
                  "and only where the single-perturber ladder serves the body (not the Earth with the Moon, nor "
                  "the Moon: their theories do not model the rotation scale).",
        "free_motion": "J_arcsec is needed for a body without a published wobble amplitude (Earth, Moon, Mars and "
                       f"Eros have one); method=series only in the short-axis mode with δ = 2 sin²(J/2) <= "
                       f"{SERIES_MAX_DELTA} (else 422 not-applicable); a body needs its three principal moments, "
                       "not all equal.",
        "plot": "stop must be after start; J_arcsec applies to kind free-wobble only, and tolerance_mas, model, "
                "order, axis and the free wobble's phase, amplitude and epoch (as the track's) to the other kinds; "
                "a figure draws at most "
                f"{MAX_PLOT_POINTS} epochs: step_days (default: chosen for the span) must leave from 2 to that many "
                "epochs in the span, which float64 Julian dates resolve, and, for the free wobble, sample its "
                "period; J_arcsec is needed for a body "
                "without a published wobble amplitude (Earth, Moon, Mars and Eros have one).",
        "user": "orbit: a_au > 0, 0 <= e < 1, 0 <= i_deg <= 180, and a bound orbit clear of the Sun: the "
                "pericentre a(1 - e) outside the Sun's radius and a inside its Hill sphere; pole: -90 <= dec_deg <= "
                f"90; angles (node_deg, peri_deg, mean_anomaly_deg, ra_deg, the track's phases) within "
                f"±{MAX_ANGLE_DEG:g} deg; rotation_period_hours >= {MIN_ROTATION_PERIOD_HOURS:g} (0.36 s); give "
                "moments (0 < A <= B <= C <= A + B) or dynamical_ellipticity in (0, 0.5]; epochs are Julian dates "
                "in (0, 1e7); track as GET /v1/bodies/{body}/track; each key of a JSON object is given once.",
        "history": "stop_year must be after start_year, within 2e7 years of it; step_years must be positive and "
                   "leave at most 100001 epochs in the span (a plot: 2 to 100000), at least the spacing of float64 "
                   "doubles at the span's largest year (else its epochs would repeat); give orbit_model or "
                   "tolerance_mas, not both; nbody for a body without a shipped orbit is run on request within the "
                   "budget.",
        "batch": f"rows: 1 to {settings.max_batch_rows} objects (EPHEM_MAX_BATCH_ROWS; for more, `ephem batch` on "
                 "Dask), each with only the columns of docs/batch_input.md (a bad value, or a cell that is not a "
                 "number, gets its reason in the row's `error`, with a 200); history, the object's or start_year, "
                 "stop_year and step_years together: finite numbers, start_year < stop_year within 2e7 years, "
                 "step_years > 0 leaving at most 100001 epochs, at least the spacing of float64 doubles at the "
                 "span's largest year; the body is JSON (an array of rows, or {rows, history} and nothing else, "
                 "each key of an object given once) or CSV (text/csv, UTF-8) with a header of distinct column "
                 "names and as many cells on every line. Each row is priced before the work at its own "
                 "eccentricity (the FFT of its Hansen coefficients grows like (1 - e^2)^(-3/2)) and, with a history, "
                 "at its integration from its pole's epoch through the span (docs/batch.md).",
        "na": na,
    }
    if hasattr(settings, "max_request_cpu_s"):      # service/guards.py: the per-request budget
        texts["budget"] = (f"a request estimated to need more than {settings.max_request_cpu_s:g} s of CPU "
                           f"(EPHEM_MAX_REQUEST_CPU_S) or {settings.max_request_memory_mb:g} MB "
                           "(EPHEM_MAX_REQUEST_MEMORY_MB) is refused before any work: 422 over-budget, naming the "
                           "parameter to change; one still running after "
                           f"{settings.request_deadline_s:g} s (EPHEM_REQUEST_DEADLINE_S) is stopped: 503. Only "
                           f"{settings.heavy_slots} request(s) estimated above {settings.heavy_request_cpu_s:g} s "
                           "(EPHEM_HEAVY_SLOTS, EPHEM_HEAVY_REQUEST_CPU_S) run at once: another gets 503 busy "
                           "with Retry-After.")
    return texts


#: operation -> the rules its description states, in this order
OPERATION_RULES = {
    ("/v1/bodies/{body}/precession", "get"): ("tolerance", "laplace", "perturbers", "na"),
    ("/v1/bodies/{body}/nutation", "get"): ("tolerance", "laplace", "perturbers", "cut", "na"),
    ("/v1/bodies/{body}/track", "get"): ("times", "grid", "tolerance_model", "laplace", "wobble", "perturbers", "na"),
    ("/v1/bodies/{body}/track.png", "get"): ("times", "plot", "tolerance_model", "laplace", "wobble", "na"),
    ("/v1/bodies/{body}/track.svg", "get"): ("times", "plot", "tolerance_model", "laplace", "wobble", "na"),
    ("/v1/bodies/{body}/track/models", "get"): ("times", "grid", "perturbers", "na"),
    ("/v1/bodies/{body}/track/models.png", "get"): ("times", "grid", "perturbers", "na"),
    ("/v1/bodies/{body}/track/models.svg", "get"): ("times", "grid", "perturbers", "na"),
    ("/v1/bodies/{body}/free-motion", "get"): ("times", "grid", "free_motion", "na"),
    ("/v1/bodies/{body}/history", "get"): ("history", "perturbers", "na"),
    ("/v1/bodies/{body}/history.png", "get"): ("history", "na"),
    ("/v1/bodies/{body}/history.svg", "get"): ("history", "na"),
    ("/v1/precession-nutation", "post"): ("user", "times", "grid", "tolerance_model", "laplace", "wobble", "history",
                                          "na"),
    ("/v1/batch", "post"): ("batch",),
}


NUTATION_TABLES_SCHEMA = {
    "title": "NutationTables", "type": "object",
    "description": "format=table-json: the paper's tables in the chosen layout, one per component (rows as in the "
                   "csv, markdown and latex formats)",
    "required": ["body", "dataset", "layout", "obliquity_deg", "tables"],
    "properties": {
        "body": {"type": "string"}, "dataset": {"type": "string"},
        "layout": {"type": "string", "enum": ["sin-cos", "amp-period"]}, "obliquity_deg": {"type": "number"},
        "tables": {"type": "array", "items": {
            "type": "object", "required": ["component", "caption", "rows"],
            "properties": {"component": {"type": "string", "enum": ["longitude", "obliquity"]},
                           "caption": {"type": "string"},
                           "rows": {"type": "array", "items": {
                               "type": "object", "additionalProperties": {"type": ["number", "string", "null"]}}}}}},
    },
}


def _constrain(schema: dict, rules: dict) -> None:
    """Add ``rules`` to a property or parameter schema, on its string or number branch (anyOf with null)."""
    branches = schema.get("anyOf", [schema])
    for branch in branches:
        kind = branch.get("type")
        for key, value in rules.items():
            if (key == "pattern") == (kind == "string") and kind in ("string", "number", "integer"):
                branch[key] = value


def document_rules(schema: dict, settings: Settings) -> dict:
    """State the service's rules in the OpenAPI document, in place (see PARAMETER_RULES, BODY_RULES,
    OPERATION_RULES). A rule naming a parameter or field the document lacks is a KeyError: they move together."""
    texts = _rule_texts(settings)
    for (path, method), keys in OPERATION_RULES.items():
        op = schema["paths"][path][method]
        rules = "\n".join(f"- {texts[k]}" for k in keys + (("budget",) if "budget" in texts else ()))
        op["description"] = (op.get("description", "").rstrip() + "\n\n**Rules** (422 invalid-input naming the "
                             "field, unless said otherwise):\n" + rules).lstrip()
        for param in op.get("parameters", []):
            if param["name"] == "perturbers":
                _constrain(param["schema"], {"pattern": perturbers_pattern()})
            elif param["name"] in PARAMETER_RULES:
                _constrain(param["schema"], PARAMETER_RULES[param["name"]])
    components = schema["components"]["schemas"]
    for (component, field), rules in BODY_RULES.items():
        _constrain(components[component]["properties"][field], rules)
    # format=table-json answers the paper's tables, another JSON shape under the same media type
    components["NutationTables"] = NUTATION_TABLES_SCHEMA
    nutation_json = schema["paths"]["/v1/bodies/{body}/nutation"]["get"]["responses"]["200"]["content"][
        "application/json"]
    nutation_json["schema"] = {"anyOf": [nutation_json["schema"], {"$ref": "#/components/schemas/NutationTables"}]}
    user = components["UserBody"]
    user["anyOf"] = [    # moments or dynamical_ellipticity, not null
        {"required": ["moments"], "properties": {"moments": {"$ref": "#/components/schemas/MomentsIn"}}},
        {"required": ["dynamical_ellipticity"], "properties": {"dynamical_ellipticity": {"type": "number"}}}]
    return schema
