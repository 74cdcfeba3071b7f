#!/usr/bin/env python
"""Record a broad set of the library's answers, and compare two recordings (the reorganisation's guard).

    python tools/record_answers.py record OUT.json
    python tools/record_answers.py compare BEFORE.json AFTER.json

``record`` asks the three surfaces that survive a reorganisation of ``ephem/`` into sub-packages, with
deterministic inputs only (fixed dates, spans, bodies; nothing read from the clock):

* the library's public face, ``from ephem import api`` (list_bodies, body_record, precession, nutation, track,
  history, batch, free_motion_answer);
* the HTTP service in-process, ``TestClient(service.app.create_app(Settings(warm_up=False)))``: every catalogue
  body's record, precession, nutation and track, the nutation tables (csv, markdown, latex, table-json, both
  layouts), a history, free motion, POST /v1/batch (JSON and CSV bodies, a user's asteroid), POST
  /v1/precession-nutation, and the figures (status, content type and non-empty only: their bytes change with
  matplotlib's metadata);
* a dozen CLI commands, ``python -m ephem.cli ...`` in subprocesses (slow: a second or two each), in json, csv
  and table formats, among them ``ephem pck`` (the service has no PCK route: the kernel's text is recorded) and
  ``ephem tables`` (the csv, markdown and LaTeX files it writes, by name).

It writes ``{case: {"status": int, "content_type": str, "body": parsed JSON, or text}}`` (an API call's status
is 200, or 404/422/500 for UnknownBodyError/other EphemError/anything else, its body then the error's class name
and message; a CLI command's status is its exit code). The script imports only ``ephem.api``, ``service.*``,
FastAPI's TestClient, the standard library and numpy, so that it runs unchanged on the old flat layout
(``PYTHONPATH=<old tree>``) and on the new one; the CLI subprocesses are pointed at the same tree.

``compare`` requires the same cases, statuses, content types and structure (dict keys, list lengths, types), and
every number equal within a relative 1e-9 or an absolute 1e-12. Why so tight: a reorganisation moves code and
renames modules but changes no arithmetic, so the answers should be bit-identical; the tolerance admits only
last-bit noise (a different summation order of a reduction, a BLAS kernel picked differently), about 10^7 ulp
short of any physical change (the library's smallest served quantities are micro-arcseconds on angles of
degrees, ~10^-10 relative). Numbers inside texts (CSV, markdown and LaTeX tables, the PCK kernel, CLI output)
are parsed and compared the same way, and the rest of the text must be identical once its numbers are replaced
by a placeholder. A number printed rounded (e.g. "0.05614 mas") whose last digit flips under last-bit noise
would show as a failure: look at it before believing it.

Not failures, but listed:

* module paths renamed: strings (or texts) that differ only by an ephem module path, anything matching
  ``ephem(\\.\\w+)+`` ("ephem.ladder" -> "ephem.sun.ladder"), which is what the reorganisation changes;
* excluded: the measured times, never equal twice (keys ``cost_ms``, ``elapsed*``, other ``*_ms`` keys, which
  in these answers are all wall times: model.cost_ms of precession, nutation, track and history answers, the
  free motion's cost_ms, and those of the POST answers' parts, wherever they nest), and timestamps (keys naming
  a creation time, and the PCK's "Generated: <UTC time>" line).

It prints the cases, the numbers compared, the largest relative difference and where, the exclusions, the
renamed module paths and every failure, and exits 1 on any failure.
"""
from __future__ import annotations

import concurrent.futures
import csv
import importlib.util
import io
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from collections import Counter, defaultdict

if importlib.util.find_spec("ephem") is None:        # run as a script from a checkout without PYTHONPATH
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# ------------------------------------------------------------------ the inputs (deterministic)

BODIES = ("Ceres", "Vesta", "Eros", "Steins", "Itokawa", "Earth", "Moon", "Mars")
DATASET = "current"
SPAN = {"start": "2020-01-01", "stop": "2021-01-01", "step_days": 30}          # 13 epochs
HISTORY = {"start_year": -2000, "stop_year": 0, "step_years": 500}             # Ceres, within its N-body orbit

USER_ASTEROID = {
    "name": "record-asteroid",
    "orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
              "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
    "pole": {"ra_deg": 309.03, "dec_deg": 42.23, "epoch_jd_tdb": 2451545.0},
    "rotation_period_hours": 5.342, "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42}}
_BETA, _GAMMA = 0.0006310213, 0.0002277317
USER_SATELLITE = {
    "name": "record-satellite",
    "orbit": {"a_au": 384400.0 / 149597870.7, "e": 0.0549, "i_deg": 5.145, "node_deg": 125.0445479,
              "peri_deg": 318.3085034, "mean_anomaly_deg": 134.9633964, "epoch_jd_tdb": 2451545.0,
              "center": "Earth", "node_rate_deg_per_year": -19.341362891},
    "pole": {"ra_deg": 266.8577, "dec_deg": 65.6411}, "rotation_period_hours": 27.321661 * 24.0,
    "moments": {"A": 1.0, "B": 1.0 + _GAMMA, "C": (1.0 + _GAMMA) * (1.0 + _BETA)}}


def batch_rows() -> list[dict]:
    u = USER_ASTEROID
    first = {"name": u["name"], **u["orbit"], "pole_ra_deg": u["pole"]["ra_deg"],
             "pole_dec_deg": u["pole"]["dec_deg"], "rotation_period_hours": u["rotation_period_hours"],
             "moment_a": u["moments"]["A"], "moment_b": u["moments"]["B"], "moment_c": u["moments"]["C"],
             "e_sigma": 0.001}
    second = dict(first, name="record-second", pole_dec_deg=-10.0)
    third = {"name": "record-hd", "a_au": 2.77, "e": 0.0785, "i_deg": 10.59, "node_deg": 80.3, "peri_deg": 73.6,
             "mean_anomaly_deg": 10.0, "epoch_jd_tdb": 2460200.5, "pole_ra_deg": 291.42, "pole_dec_deg": 66.76,
             "rotation_period_hours": 9.074, "dynamical_ellipticity": 0.0684}
    return [first, second, third]


def batch_csv(rows: list[dict]) -> str:
    columns = list(dict.fromkeys(k for r in rows for k in r))
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return out.getvalue()


# ------------------------------------------------------------------ recording

def plain(obj):
    """A JSON-able copy: numpy arrays and scalars to lists and Python numbers, tuples to lists."""
    if isinstance(obj, dict):
        return {str(k): plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(v) for v in obj]
    if obj is None or isinstance(obj, (bool, int, float, str)):
        return obj
    tolist = getattr(obj, "tolist", None)             # numpy arrays and scalars
    if tolist is not None:
        return plain(tolist())
    return str(obj)


def api_cases(api) -> list[tuple[str, object]]:
    """(case, thunk) for the library's public functions."""
    cases = [("api list_bodies current", lambda: api.list_bodies(dataset=DATASET)),
             ("api list_bodies petit2014", lambda: api.list_bodies(dataset="petit2014"))]
    for b in BODIES:
        cases += [(f"api body_record {b}", lambda b=b: api.body_record(b, dataset=DATASET)),
                  (f"api precession {b}", lambda b=b: api.precession(b, dataset=DATASET)),
                  (f"api nutation {b}", lambda b=b: api.nutation(b, dataset=DATASET)),
                  (f"api track {b}", lambda b=b: api.track(b, SPAN["start"], SPAN["stop"], SPAN["step_days"],
                                                           dataset=DATASET))]
    for b in BODIES:                       # the other dataset, a long coarse track, a tolerance, the other axis
        cases += [(f"api precession {b} petit2014", lambda b=b: api.precession(b, dataset="petit2014")),
                  (f"api nutation {b} petit2014 order=4", lambda b=b: api.nutation(b, dataset="petit2014", order=4)),
                  (f"api track {b} 2000-2040", lambda b=b: api.track(b, "2000-01-01", "2040-01-01", 730.5,
                                                                      dataset=DATASET)),
                  (f"api track {b} tolerance_mas=1e5", lambda b=b: api.track(
                      b, "2025-01-01", "2026-01-01", 73.0, dataset=DATASET, tolerance_mas=1e5)),
                  (f"api track {b} axis=angular_momentum", lambda b=b: api.track(
                      b, "2025-01-01", "2025-06-01", 50.0, dataset=DATASET, axis="angular_momentum")),
                  (f"api free_motion_answer {b} J=10", lambda b=b: api.free_motion_answer(
                      b, "2020-01-01", "2020-01-11", 1.0, J_arcsec=10.0, method="auto", dataset=DATASET))]
    cases += [
        ("api precession Vesta order=4", lambda: api.precession("Vesta", dataset=DATASET, order=4)),
        ("api precession Ceres tolerance_mas=100", lambda: api.precession("Ceres", dataset=DATASET, order=None,
                                                                          tolerance_mas=100.0)),
        ("api precession Earth perturbers=sun", lambda: api.precession("Earth", dataset=DATASET, perturbers="sun")),
        ("api nutation Earth cut_mas=10", lambda: api.nutation("Earth", dataset=DATASET, cut_mas=10.0)),
        ("api nutation Vesta petit2014", lambda: api.nutation("Vesta", dataset="petit2014")),
        ("api track Vesta tolerance_mas=10", lambda: api.track("Vesta", "2030-01-01", "2030-06-30", 15.0,
                                                               dataset=DATASET,
                                                              tolerance_mas=10.0)),
        ("api track Ceres model=series order=2", lambda: api.track("Ceres", "2030-01-01", "2031-01-01", 60.0,
                                                                   dataset=DATASET, order=2, model="series")),
        ("api track Mars axis=angular_momentum 2020", lambda: api.track("Mars", "2020-01-01", "2020-06-01", 30.0,
                                                                   dataset=DATASET, axis="angular_momentum")),
        ("api track Mars free_wobble_phase_deg=30", lambda: api.track(
            "Mars", "2000-01-01", "2010-01-01", 1000.0, dataset=DATASET, tolerance_mas=10.0,
            free_wobble_phase_deg=30.0)),
        ("api history Ceres", lambda: api.history("Ceres", HISTORY["start_year"], HISTORY["stop_year"],
                                                  HISTORY["step_years"], dataset=DATASET)),
        ("api history Ceres orbit_model=secular", lambda: api.history("Ceres", -20000, 0, 5000, dataset=DATASET,
                                                                      orbit_model="secular")),
        ("api history Itokawa (not applicable)", lambda: api.history("Itokawa", -2000, 0, 1000, dataset=DATASET)),
        ("api batch user asteroid", lambda: api.batch(batch_rows())),
        ("api batch user asteroid with history", lambda: api.batch(batch_rows()[:1],
                                                                   history={**HISTORY, "step_years": 1000})),
        ("api free_motion_answer Mars", lambda: api.free_motion_answer("Mars", "2020-01-01", "2020-03-01", 5.0,
                                                                       dataset=DATASET)),
        ("api free_motion_answer Vesta J=10 series", lambda: api.free_motion_answer(
            "Vesta", "2020-01-01", "2020-01-03", 0.25, J_arcsec=10.0, method="series", dataset=DATASET)),
        ("api free_motion_answer Eros J=100 numeric", lambda: api.free_motion_answer(
            "Eros", "2020-01-01", "2020-01-02", 0.1, J_arcsec=100.0, method="numeric", dataset=DATASET)),
        ("api precession Pluto (unknown)", lambda: api.precession("Pluto", dataset=DATASET)),
    ]
    return cases


def run_api(api, thunk) -> dict:
    try:
        body = plain(thunk())
        status = 200
    except Exception as exc:                           # an answer too: the refusal must not change
        names = [c.__name__ for c in type(exc).__mro__]
        status = 404 if "UnknownBodyError" in names else 422 if "EphemError" in names else 500
        body = {"error": type(exc).__name__, "message": str(exc)}
    return {"status": status, "content_type": "application/json", "body": body}


def http_cases() -> list[tuple[str, str, str, dict]]:
    """(case, method, url, request kwargs) for the service."""
    out = []

    def get(url, **params):
        query = "&".join(f"{k}={v}" for k, v in params.items())
        out.append((f"http GET {url}" + (f"?{query}" if query else ""), "GET", url, {"params": params}))

    get("/v1/bodies")
    get("/v1/bodies", dataset="petit2014")
    for b in BODIES:
        low = b.lower()
        get(f"/v1/bodies/{low}")
        get(f"/v1/bodies/{low}/precession")
        get(f"/v1/bodies/{low}/nutation")
        get(f"/v1/bodies/{low}/track", **SPAN)
    get("/v1/bodies/2000004")                                       # by NAIF id
    get("/v1/bodies/vesta/precession", order=4)
    get("/v1/bodies/ceres/precession", tolerance_mas=100)
    get("/v1/bodies/earth/precession", perturbers="sun")
    get("/v1/bodies/earth/nutation", cut_mas=10)
    for b in BODIES:                       # by NAIF id, the other dataset, a tolerance, the table as markdown
        low = b.lower()
        get(f"/v1/bodies/{low}/precession", dataset="petit2014")
        get(f"/v1/bodies/{low}/nutation", tolerance_mas=1000)
        if b != "Vesta":                   # Vesta's: with the tables below
            get(f"/v1/bodies/{low}/nutation", format="markdown", layout="amp-period")
        get(f"/v1/bodies/{low}/track", start="2025-01-01", stop="2026-01-01", step_days=73, tolerance_mas=1e5)
        get(f"/v1/bodies/{low}/free-motion", start="2020-01-01", stop="2020-01-11", step_days=1, J_arcsec=10)
    for naif in (2000001, 2025143, 399, 301, 499):
        get(f"/v1/bodies/{naif}/precession")
    # the nutation tables, as text
    for b, extra in (("vesta", {}), ("earth", {"cut_mas": 10}), ("moon", {}), ("mars", {})):
        for fmt in ("csv", "markdown", "latex", "table-json"):
            for layout in ("sin-cos", "amp-period"):
                if b in ("moon", "mars") and (layout == "amp-period" or fmt == "table-json"):
                    continue
                get(f"/v1/bodies/{b}/nutation", format=fmt, layout=layout, **extra)
    get("/v1/bodies/vesta/nutation", format="csv", dataset="petit2014")
    # tracks: csv for two; a tolerance; named models; the angular momentum; Mars with its free wobble
    get("/v1/bodies/ceres/track", format="csv", **SPAN)
    get("/v1/bodies/earth/track", format="csv", **SPAN)
    get("/v1/bodies/vesta/track", start="2030-01-01", stop="2030-06-30", step_days=15, tolerance_mas=10)
    get("/v1/bodies/eros/track", start="2030-01-01", stop="2030-06-30", step_days=15, tolerance_mas=1000)   # 422
    get("/v1/bodies/eros/track", start="2030-01-01", stop="2030-06-30", step_days=15, tolerance_mas=1e5)
    get("/v1/bodies/ceres/track", start="2030-01-01", stop="2031-01-01", step_days=60, model="series", order=2)
    get("/v1/bodies/steins/track", start="2030-01-01", stop="2031-01-01", step_days=60, model="second_order")
    get("/v1/bodies/vesta/track", start="2030-01-01", stop="2031-01-01", step_days=60, model="secular")
    get("/v1/bodies/itokawa/track", start="2030-01-01", stop="2030-03-01", step_days=20, model="hansen")
    get("/v1/bodies/vesta/track", start="2030-01-01", stop="2030-06-01", step_days=30, axis="angular_momentum")
    get("/v1/bodies/earth/track", start="2030-01-01", stop="2030-06-01", step_days=30, axis="angular_momentum")
    get("/v1/bodies/mars/track", start="2030-01-01", stop="2030-06-01", step_days=30, axis="angular_momentum")
    get("/v1/bodies/moon/track", start="2030-01-01", stop="2030-06-01", step_days=30, axis="angular_momentum")
    get("/v1/bodies/mars/track", start="2000-01-01", stop="2010-01-01", step_days=1000, tolerance_mas=10,
        free_wobble_phase_deg=30)
    get("/v1/bodies/mars/track", start="2020-01-01", stop="2020-06-01", step_days=30, model="hansen",
        free_wobble_phase_deg=30)
    get("/v1/bodies/vesta/track", start="2020-01-01", stop="2020-03-01", step_days=30, model="hansen",
        free_wobble_phase_deg=45, free_wobble_J_arcsec=10)
    get("/v1/bodies/earth/track", start="2020-01-01", stop="2020-03-01", step_days=30, perturbers="sun")
    get("/v1/bodies/vesta/track", start="2020-01-01", stop="2020-03-01", step_days=30, format="csv",
        rotation_phase_deg=20)
    # a history: Ceres, a short span, a coarse step; and one the theory refuses
    get("/v1/bodies/ceres/history", **HISTORY)
    get("/v1/bodies/itokawa/history", start_year=-2000, stop_year=0, step_years=1000)
    for b in ("vesta", "earth", "moon", "mars"):
        get(f"/v1/bodies/{b}/history", start_year=-2000, stop_year=0, step_years=1000)
    get("/v1/bodies/ceres/history", start_year=-20000, stop_year=0, step_years=5000, orbit_model="secular")
    # free motion
    get("/v1/bodies/mars/free-motion", start="2020-01-01", stop="2020-03-01", step_days=5)
    get("/v1/bodies/vesta/free-motion", start="2020-01-01", stop="2020-01-03", step_days=0.25, J_arcsec=10)
    get("/v1/bodies/earth/free-motion", start="2020-01-01", stop="2021-01-01", step_days=30, method="exact")
    # refusals
    get("/v1/bodies/pluto/precession")
    get("/v1/bodies/vesta/track", start="2020-01-01", stop="2020-03-01", step_days=-1)
    # the POSTs: a batch (JSON, JSON with a history, CSV), a user's own bodies
    rows = batch_rows()
    out.append(("http POST /v1/batch json", "POST", "/v1/batch", {"json": rows}))
    out.append(("http POST /v1/batch json+history", "POST", "/v1/batch",
                {"json": {"rows": rows[:1], "history": {**HISTORY, "step_years": 1000}}}))
    out.append(("http POST /v1/batch csv", "POST", "/v1/batch",
                {"content": batch_csv(rows).encode(), "headers": {"content-type": "text/csv"}}))
    out.append(("http POST /v1/batch csv?history", "POST", "/v1/batch",
                {"content": batch_csv(rows[:1]).encode(), "headers": {"content-type": "text/csv"},
                 "params": {**HISTORY, "step_years": 1000}}))
    track = {"start": "2020-01-01", "stop": "2020-03-01", "step_days": 30}
    for user in (USER_ASTEROID, USER_SATELLITE):
        out.append((f"http POST /v1/precession-nutation {user['name']}", "POST", "/v1/precession-nutation",
                    {"json": {**user, "track": track, "history": {"start_year": -400, "stop_year": 0,
                                                                  "step_years": 200}}}))
    # the figures: status, content type, non-empty
    for url, params in (("/v1/bodies/vesta/track.png", {"start": "2020-01-01", "stop": "2020-04-01", "dpi": 30}),
                        ("/v1/bodies/mars/track.svg", {"start": "2020-01-01", "stop": "2020-04-01",
                                                       "kind": "nutation-loop"}),
                        ("/v1/bodies/ceres/history.png", {"start_year": -400, "stop_year": 0, "dpi": 30})):
        query = "&".join(f"{k}={v}" for k, v in params.items())
        out.append((f"http GET {url}?{query}", "GET", url, {"params": params}))
    get("/healthz")
    return out


def run_http(client, method, url, kwargs) -> dict:
    r = client.request(method, url, **kwargs)
    ctype = r.headers.get("content-type", "")
    media = ctype.split(";")[0].strip()
    if media.startswith("image/"):
        body = {"non_empty": len(r.content) > 0}
    elif media.endswith("json"):
        body = json.loads(r.text)
    else:
        body = r.text
    return {"status": r.status_code, "content_type": ctype, "body": body}


#: (case, argv after ``-m ephem.cli``, what stdout holds); {tmp} is a temporary directory of the case's own
CLI_CASES = [
    ("cli precession vesta --format json", ["precession", "vesta", "--dataset", DATASET, "--format", "json"],
     "application/json"),
    ("cli nutation earth --cut-mas 10 --format csv", ["nutation", "earth", "--dataset", DATASET, "--cut-mas", "10",
                                                      "--format", "csv"], "text/csv"),
    ("cli track mars (README example) --format csv",
     ["track", "mars", "--dataset", DATASET, "--start", "2000-01-01", "--stop", "2010-01-01", "--step-days", "1000",
      "--tolerance-mas", "10", "--free-wobble-phase-deg", "30", "--format", "csv"], "text/csv"),
    ("cli history ceres --format table", ["history", "ceres", "--dataset", DATASET, "--start-year", "-2000",
                                          "--stop-year", "0", "--step-years", "1000", "--quiet", "--format",
                                          "table"], "text/plain"),
    ("cli body moon --format json", ["body", "moon", "--dataset", DATASET, "--format", "json"], "application/json"),
    ("cli pck vesta mars", ["pck", "vesta", "mars", "--dataset", DATASET, "--start", "2000-01-01", "--stop",
                            "2000-05-01", "--out", "{tmp}/kernel.tpc"], "application/x-pck"),
    ("cli tables vesta mars --format csv,markdown,latex",
     ["tables", "vesta", "mars", "--dataset", DATASET, "--format", "csv", "--format", "markdown", "--format",
      "latex", "--out", "{tmp}/files"], "files"),
    ("cli bodies --format csv", ["bodies", "--dataset", DATASET, "--format", "csv"], "text/csv"),
    ("cli nutation moon --format table", ["nutation", "moon", "--dataset", DATASET, "--format", "table"],
     "text/plain"),
    ("cli track earth --axis angular_momentum --format json",
     ["track", "earth", "--dataset", DATASET, "--start", "2030-01-01", "--stop", "2030-06-01", "--step-days", "30",
      "--axis", "angular_momentum", "--format", "json"], "application/json"),
    ("cli free-motion vesta --J-arcsec 10 --format csv",
     ["free-motion", "vesta", "--dataset", DATASET, "--start", "2020-01-01", "--stop", "2020-01-03", "--step-days",
      "0.25", "--J-arcsec", "10", "--format", "csv"], "text/csv"),
]


def run_cli(argv: list[str], media: str, env: dict) -> dict:
    with tempfile.TemporaryDirectory(prefix="record_answers_") as tmp:
        args = [a.replace("{tmp}", tmp) for a in argv]
        res = subprocess.run([sys.executable, "-m", "ephem.cli", *args], capture_output=True, text=True, env=env,
                             timeout=300)
        stdout = res.stdout.replace(tmp, "<tmp>")
        if res.returncode != 0:
            body = {"stdout": stdout, "stderr": res.stderr.replace(tmp, "<tmp>")[-2000:]}
        elif media == "application/json":
            body = json.loads(stdout)
        elif media == "application/x-pck":
            with open(os.path.join(tmp, "kernel.tpc"), encoding="ascii") as f:
                body = {"stdout": stdout, "kernel": f.read()}
        elif media == "files":                       # the files written to {tmp}/files, by name
            folder = os.path.join(tmp, "files")
            files = {}
            for name in sorted(os.listdir(folder)):
                with open(os.path.join(folder, name), encoding="utf-8") as f:
                    files[name] = f.read()
            body = {"stdout": stdout, "files": files}
        else:
            body = stdout
    return {"status": res.returncode, "content_type": media, "body": body}


def record(out_path: str) -> int:
    t0 = time.perf_counter()
    from ephem import api
    import ephem
    from fastapi.testclient import TestClient
    from service.app import create_app
    from service.settings import Settings

    tree = os.path.dirname(os.path.dirname(os.path.abspath(ephem.__file__)))
    print(f"recording the answers of {tree} (ephem at {ephem.__file__})", flush=True)
    # the CLI subprocesses import the same tree
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in (tree, os.environ.get("PYTHONPATH")) if p))
    answers: dict[str, dict] = {}
    timings: dict[str, float] = {}

    def timed(name, fn, *args):
        start = time.perf_counter()
        result = fn(*args)
        timings[name] = time.perf_counter() - start
        return result

    names = [n for n, _ in api_cases(api)] + [c[0] for c in http_cases()] + [c[0] for c in CLI_CASES]
    twice = sorted(n for n, k in Counter(names).items() if k > 1)
    assert not twice, f"cases named twice: {twice}"
    # the slow CLI cases run one at a time beside the in-process ones (two cores)
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        futures = {name: pool.submit(timed, name, run_cli, argv, media, env) for name, argv, media in CLI_CASES}
        for name, thunk in api_cases(api):
            answers[name] = timed(name, run_api, api, thunk)
        with TestClient(create_app(Settings(warm_up=False))) as client:
            for name, method, url, kwargs in http_cases():
                answers[name] = timed(name, run_http, client, method, url, kwargs)
        for name, future in futures.items():
            answers[name] = future.result()
    with open(out_path, "w", encoding="utf-8") as f:
        json.dump(dict(sorted(answers.items())), f, indent=1, sort_keys=False, allow_nan=True)
        f.write("\n")
    statuses = Counter(a["status"] for a in answers.values())
    slow = sorted(timings.items(), key=lambda kv: -kv[1])[:5]
    print(f"{len(answers)} cases ({sum(1 for n in answers if n.startswith('api'))} api, "
          f"{sum(1 for n in answers if n.startswith('http'))} http, {sum(1 for n in answers if n.startswith('cli'))} "
          f"cli), statuses {dict(sorted(statuses.items()))}, {time.perf_counter() - t0:.1f} s; slowest: "
          + ", ".join(f"{n} {t:.1f} s" for n, t in slow))
    print(f"wrote {out_path}")
    return 0


# ------------------------------------------------------------------ comparing

REL_TOL, ABS_TOL = 1e-9, 1e-12
#: dict keys that are measured wall times or timestamps (never equal twice): excluded, and listed
TIMING_KEY = re.compile(r"cost_ms|elapsed|_ms$|^wall|_seconds_wall|timestamp|generated|created_at|^created$")
#: timestamps inside texts: the PCK's "Generated:      2026-11-28T19:57:09 UTC"
TIMESTAMP_TEXT = re.compile(r"(?i)(generated|created|written)(\s*:?\s*(on|at)?\s*)"
                            r"\d{4}-\d{2}-\d{2}[T ]\d{2}:\d{2}(:\d{2}(\.\d+)?)?(\s*UTC|Z)?")
MODULE_PATH = re.compile(r"\bephem(?:\.\w+)+")
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?")


def _generic(path: str) -> str:
    return re.sub(r"\[\d+\]", "[*]", path)


class Comparison:
    def __init__(self):
        self.numbers = 0
        self.largest = (0.0, None)                   # (relative difference, where)
        self.failures: list[str] = []
        self.renamed: Counter = Counter()            # (before, after) -> occurrences
        self.renamed_where: dict = defaultdict(set)
        self.excluded: dict[str, set] = defaultdict(set)   # generic path -> cases

    def number(self, a, b, where: str) -> None:
        self.numbers += 1
        a, b = float(a), float(b)
        if a == b or (math.isnan(a) and math.isnan(b)):
            return
        diff = abs(a - b)
        scale = max(abs(a), abs(b))
        rel = diff / scale if scale > 0 and math.isfinite(diff) else math.inf
        if rel > self.largest[0] or self.largest[1] is None:
            self.largest = (rel, f"{where}: {a!r} vs {b!r}")
        if not (diff <= ABS_TOL or rel <= REL_TOL):
            self.failures.append(f"{where}: {a!r} -> {b!r} (relative {rel:.3g}, absolute {diff:.3g})")

    def text(self, a: str, b: str, where: str, case: str) -> None:
        if TIMESTAMP_TEXT.search(a) or TIMESTAMP_TEXT.search(b):
            self.excluded[f"{_generic(where.split(': ', 1)[1]) if ': ' in where else where} "
                          f"(a timestamp in the text)"].add(case)
            a = TIMESTAMP_TEXT.sub(r"\1\2<timestamp>", a)
            b = TIMESTAMP_TEXT.sub(r"\1\2<timestamp>", b)
        mods_a, mods_b = MODULE_PATH.findall(a), MODULE_PATH.findall(b)
        a_n, b_n = MODULE_PATH.sub("ephem.<module>", a), MODULE_PATH.sub("ephem.<module>", b)
        if len(mods_a) == len(mods_b):
            for x, y in zip(mods_a, mods_b):
                if x != y:
                    self.renamed[(x, y)] += 1
                    self.renamed_where[(x, y)].add(case)
        else:                                        # the skeletons below differ: a failure, shown there
            a_n, b_n = a, b
        nums_a, nums_b = NUMBER.findall(a_n), NUMBER.findall(b_n)
        skel_a, skel_b = NUMBER.sub("#", a_n), NUMBER.sub("#", b_n)
        if skel_a != skel_b:
            la, lb = skel_a.splitlines(), skel_b.splitlines()
            i = next((k for k, (x, y) in enumerate(zip(la, lb)) if x != y), min(len(la), len(lb)))
            show = lambda lines: repr(lines[i][:160]) if i < len(lines) else "(no line)"     # noqa: E731
            self.failures.append(f"{where}: the text differs (numbers aside) at line {i + 1}: {show(la)} -> "
                                 f"{show(lb)}")
            return
        if len(nums_a) == 1 and skel_a == "#":
            self.number(nums_a[0], nums_b[0], where)
            return
        place = _number_places(a_n)
        for k, (x, y) in enumerate(zip(nums_a, nums_b)):
            line, nth = place[k]
            self.number(x, y, f"{where} <text line {line}, number {nth} of the line>")

    def walk(self, a, b, where: str, case: str) -> None:
        if isinstance(a, dict) and isinstance(b, dict):
            if set(a) != set(b):
                self.failures.append(f"{where}: keys differ: only before {sorted(set(a) - set(b))}, only after "
                                     f"{sorted(set(b) - set(a))}")
            for k in a:
                if k not in b:
                    continue
                sub = f"{where}.{k}"
                if TIMING_KEY.search(k):
                    self.excluded[_generic(sub.split(": ", 1)[1]) if ": " in sub else sub].add(case)
                    if (a[k] is None) != (b[k] is None):
                        self.failures.append(f"{sub}: {a[k]!r} -> {b[k]!r} (a time, present in one only)")
                    continue
                self.walk(a[k], b[k], sub, case)
        elif isinstance(a, list) and isinstance(b, list):
            if len(a) != len(b):
                self.failures.append(f"{where}: length {len(a)} -> {len(b)}")
                return
            for i, (x, y) in enumerate(zip(a, b)):
                self.walk(x, y, f"{where}[{i}]", case)
        elif isinstance(a, bool) or isinstance(b, bool):
            if a is not b:
                self.failures.append(f"{where}: {a!r} -> {b!r}")
        elif isinstance(a, (int, float)) and isinstance(b, (int, float)):
            self.number(a, b, where)
        elif isinstance(a, str) and isinstance(b, str):
            self.text(a, b, where, case)
        elif a is None and b is None:
            return
        else:
            self.failures.append(f"{where}: {type(a).__name__} {_short(a)} -> {type(b).__name__} {_short(b)}")


def _number_places(text: str) -> list[tuple[int, int]]:
    """(line, index within the line), both from 1, of each number of ``text`` in order."""
    places, line, nth, pos = [], 1, 0, 0
    for m in NUMBER.finditer(text):
        newlines = text.count("\n", pos, m.start())
        line, nth, pos = line + newlines, (0 if newlines else nth) + 1, m.start()
        places.append((line, nth))
    return places


def _short(x) -> str:
    s = repr(x)
    return s if len(s) < 80 else s[:77] + "..."


def compare(before_path: str, after_path: str) -> int:
    with open(before_path, encoding="utf-8") as f:
        before = json.load(f)
    with open(after_path, encoding="utf-8") as f:
        after = json.load(f)
    cmp = Comparison()
    only_before, only_after = sorted(set(before) - set(after)), sorted(set(after) - set(before))
    for name in only_before:
        cmp.failures.append(f"{name}: a case of {before_path} only")
    for name in only_after:
        cmp.failures.append(f"{name}: a case of {after_path} only")
    common = [n for n in before if n in after]
    for name in common:
        x, y = before[name], after[name]
        if x["status"] != y["status"]:
            cmp.failures.append(f"{name}: status {x['status']} -> {y['status']}")
        if x["content_type"] != y["content_type"]:
            cmp.failures.append(f"{name}: content type {x['content_type']!r} -> {y['content_type']!r}")
        cmp.walk(x["body"], y["body"], f"{name}: body", name)

    print(f"compare {before_path} (before) with {after_path} (after)")
    print(f"cases: {len(common)} compared ({len(before)} before, {len(after)} after)")
    print(f"numbers compared: {cmp.numbers} (tolerance: relative {REL_TOL:g} or absolute {ABS_TOL:g})")
    rel, where = cmp.largest
    print(f"largest relative difference: {rel:.3g}" + (f" at {where}" if where else " (all numbers identical)"))
    print(f"excluded (measured times, timestamps): {len(cmp.excluded)} fields")
    for path, cases in sorted(cmp.excluded.items()):
        print(f"  {path}  ({len(cases)} cases)")
    print(f"module paths renamed (not failures): {sum(cmp.renamed.values())} occurrences of "
          f"{len(cmp.renamed)} paths")
    for (x, y), n in sorted(cmp.renamed.items()):
        cases = sorted(cmp.renamed_where[(x, y)])
        print(f"  {x} -> {y}  ({n}x, in {len(cases)} cases: {', '.join(cases[:3])}{', ...' if len(cases) > 3 else ''})")
    print(f"failures: {len(cmp.failures)}")
    for f in cmp.failures:
        print(f"  FAIL {f}")
    print("CLEAN" if not cmp.failures else "DIFFERENT")
    return 1 if cmp.failures else 0


def main(argv: list[str]) -> int:
    if len(argv) == 2 and argv[0] == "record":
        return record(argv[1])
    if len(argv) == 3 and argv[0] == "compare":
        return compare(argv[1], argv[2])
    print(__doc__.split("\n\n")[1] if "\n\n" in __doc__ else __doc__, file=sys.stderr)
    print("usage: record_answers.py record OUT.json | compare BEFORE.json AFTER.json", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
