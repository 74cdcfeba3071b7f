"""The core computes without any extra (issue 43): with the extras' packages hidden (a ``sys.meta_path`` finder
that refuses to import them, as if they were not installed), ``ephem.api`` answers a track, a precession, a
nutation and a history of Vesta, the same numbers as with them; each feature of an extra says which extra to
install (``ephem-asteroid-pn[plots]``, ``[batch]``, ``[nbody]``, ``[service]``), never a bare ModuleNotFoundError;
and the CLI (core: typer) answers too. Offline: the packages are hidden, not uninstalled (.ci/run installs the core
alone into a fresh venv from the lock, with the network, and computes a track and a precession there).
"""
from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import tomllib
from pathlib import Path

import pytest

from ephem import api
from ephem.base import extras

ROOT = Path(__file__).resolve().parents[2]

#: the top-level modules of every extra (pyproject.toml's [project.optional-dependencies] but ``test``), hidden
HIDDEN = ("fastapi", "starlette", "pydantic", "pydantic_core", "uvicorn", "uvicorn_worker", "gunicorn", "jinja2",
          "multipart", "python_multipart", "orjson", "markdown_it", "dask", "distributed", "pyarrow", "matplotlib",
          "rebound", "lunarsky")

BLOCKER = """
import importlib.abc, json, sys
HIDDEN = set({hidden!r})
class Hidden(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in HIDDEN:
            raise ModuleNotFoundError(f"No module named {{name!r}} (hidden by the test)", name=name)
        return None
sys.meta_path.insert(0, Hidden())
"""


def run(code: str, hidden=HIDDEN) -> subprocess.CompletedProcess:
    script = BLOCKER.format(hidden=tuple(hidden)) + textwrap.dedent(code)
    return subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, timeout=300)


TRACK = ("Vesta", "2040-01-01", "2041-01-01", 73.0)
HISTORY = ("Vesta", -2000.0, 0.0, 500.0)

CORE = f"""
from ephem import api
track = api.track(*{TRACK!r})
precession = api.precession("Vesta")
nutation = api.nutation("Vesta")
history = api.history(*{HISTORY!r})
out = {{"track": {{k: track[k] for k in ("jd_tdb", "psi_arcsec", "delta_psi_arcsec", "delta_epsilon_arcsec",
                                       "pole_ra_deg", "pole_dec_deg")}}, "model": track["model"]["name"],
       "precession": precession["precession_rate_arcsec_per_year"],
       "nutation": [[t["longitude_sin_arcsec"], t["obliquity_cos_arcsec"]] for t in nutation["terms"]],
       "history": {{k: history[k] for k in ("year", "obliquity_deg", "pole_ra_deg")}},
       "loaded": sorted(m for m in sys.modules if m.split(".")[0] in HIDDEN)}}
print(json.dumps(out, default=lambda a: a.tolist()))
"""


@pytest.fixture(scope="module")
def core() -> dict:
    proc = run(CORE)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.splitlines()[-1])


def test_the_hidden_modules_are_every_extra():
    """The list hides what pyproject.toml's extras bring (their import names), so that a new extra is hidden too."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    optional = config["project"]["optional-dependencies"]
    assert set(optional) >= {"plots", "batch", "nbody", "service", "all", "test"}
    imports = {"dask[distributed]": "dask", "uvicorn[standard]": "uvicorn", "uvicorn-worker": "uvicorn_worker",
               "python-multipart": "multipart", "markdown-it-py": "markdown_it"}
    for extra, requirements in optional.items():
        if extra in ("test", "all"):
            continue
        for req in requirements:
            name = req.split(">")[0].split("<")[0].split("=")[0].strip()
            if name.startswith("ephem-asteroid-pn"):
                continue
            assert imports.get(name, name) in HIDDEN, (extra, name)
    for extra, modules in extras.EXTRAS.items():
        assert set(modules) <= set(HIDDEN), extra
    for name in ("numpy", "scipy", "astropy", "skyfield", "typer"):      # the core is not an extra
        assert not any(r.startswith(name) for reqs in optional.values() for r in reqs), name


def test_the_core_answers_without_any_extra(core):
    assert core["loaded"] == []
    assert len(core["track"]["jd_tdb"]) == 6 and core["model"]
    assert len(core["nutation"]) > 4 and len(core["history"]["year"]) == 5


def test_the_core_gives_the_same_numbers_as_with_the_extras(core):
    """Same code, same numbers: the answers in this process (every extra there) within 1e-9 of their own size
    (the JSON round trip keeps 17 digits; no extra takes part in them)."""
    track = api.track(*TRACK)
    for key, values in core["track"].items():
        assert values == pytest.approx(track[key], rel=1e-9, abs=1e-9), key
    assert core["model"] == track["model"]["name"]
    assert core["precession"] == pytest.approx(api.precession("Vesta")["precession_rate_arcsec_per_year"], rel=1e-12)
    terms = api.nutation("Vesta")["terms"]
    mine = [v for t in terms for v in (t["longitude_sin_arcsec"], t["obliquity_cos_arcsec"])]
    assert [v for pair in core["nutation"] for v in pair] == pytest.approx(mine, rel=1e-12, abs=1e-15)
    history = api.history(*HISTORY)
    for key, values in core["history"].items():
        assert values == pytest.approx(history[key], rel=1e-9, abs=1e-9), key


def test_the_precession_is_petit_et_al_s():
    """The rate the core computes for Vesta from Petit et al. (2014)'s inputs is their Table 4's 13.6728"/yr (the
    difference, 0.0016"/yr, is README's: their rounded inputs)."""
    proc = run("""
        from ephem import api
        print(api.precession("Vesta", dataset="petit2014")["precession_rate_arcsec_per_year"])
        """)
    assert proc.returncode == 0, proc.stderr
    assert float(proc.stdout.split()[-1]) == pytest.approx(13.6728, abs=0.005)


FEATURES = """
from ephem import api
from ephem.base.errors import EphemError
def attempt(f, *args, **kw):
    try:
        f(*args, **kw)
    except Exception as exc:
        return [type(exc).__name__, isinstance(exc, ImportError), isinstance(exc, EphemError), str(exc)]
    return None
out = {
    "plot": attempt(api.render_plot, "obliquity", "Vesta", "2040-01-01", "2041-01-01", 30.0, fmt="png"),
    "chart": attempt(api.track_models_chart, "Vesta", "2025-01-01", "2026-01-01", 30.0, tolerance_mas=100.0),
    "batch": attempt(api.run_batch, "rows.csv", "out"),
    "nbody": attempt(api.history, "Ceres", -1000.0, 0.0, 100.0, dataset="petit2014", orbit_model="nbody"),
    "service": attempt(__import__, "service.app"),
}
# without REBOUND, a tolerance takes the secular orbit for a body with no shipped N-body orbit
out["secular"] = api.history("Ceres", -1000.0, 0.0, 100.0, dataset="petit2014", tolerance_mas=1e9)["model"]["name"]
out["loaded"] = sorted(m for m in sys.modules if m.split(".")[0] in HIDDEN)
print(json.dumps(out, default=lambda a: a.tolist()))
"""


@pytest.fixture(scope="module")
def features() -> dict:
    proc = run(FEATURES)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.splitlines()[-1])


@pytest.mark.parametrize("feature, extra", [("plot", "plots"), ("chart", "plots"), ("batch", "batch")])
def test_a_feature_of_an_extra_names_the_extra(features, feature, extra):
    name, is_import_error, is_ephem_error, message = features[feature]
    assert name == "MissingExtraError" and is_import_error and is_ephem_error, features[feature]
    assert f"install ephem-asteroid-pn[{extra}]" in message, message


def test_an_nbody_orbit_on_request_names_its_extra(features):
    name, _, is_ephem_error, message = features["nbody"]
    assert name == "NotApplicableError" and is_ephem_error, features["nbody"]
    assert message.startswith("not applicable to Ceres") and "install ephem-asteroid-pn[nbody]" in message, message
    assert features["secular"] == "secular"


def test_the_service_names_its_extra(features):
    name, is_import_error, _, message = features["service"]
    assert name == "ImportError" and is_import_error and "install ephem-asteroid-pn[service]" in message, message
    assert "ModuleNotFoundError" not in message


def test_no_feature_loaded_a_hidden_module(features):
    assert features["loaded"] == []


CLI = """
from ephem.cli import app
app(sys.argv[1:], prog_name="ephem")
"""


def run_cli(*args: str, tmp_path: Path) -> subprocess.CompletedProcess:
    # typer needs pydantic to parse some options: pydantic is the core's (typer requires it), not an extra's
    script = BLOCKER.format(hidden=tuple(m for m in HIDDEN if not m.startswith("pydantic"))) + CLI
    return subprocess.run([sys.executable, "-c", script, *args], cwd=tmp_path, capture_output=True, text=True,
                          timeout=300, env={**__import__("os").environ, "PYTHONPATH": str(ROOT)})


def test_the_cli_is_core(tmp_path):
    proc = run_cli("precession", "vesta", "--format", "csv", tmp_path=tmp_path)
    assert proc.returncode == 0, proc.stderr
    header, row = proc.stdout.splitlines()[:2]
    rate = float(dict(zip(header.split(","), row.split(",")))["precession_rate_arcsec_per_year"])
    assert rate == pytest.approx(api.precession("Vesta")["precession_rate_arcsec_per_year"], rel=1e-12)
    proc = run_cli("plot", "vesta", "--kind", "obliquity", "--start", "2040-01-01", "--stop", "2041-01-01",
                   "--out", str(tmp_path / "vesta.png"), tmp_path=tmp_path)
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    assert proc.stderr.startswith("error: a plot needs matplotlib") and "ephem-asteroid-pn[plots]" in proc.stderr
    assert "Traceback" not in proc.stderr and not (tmp_path / "vesta.png").exists()


def test_the_blocker_can_fail():
    """The finder does hide a module: importing one of the extras fails under it, and succeeds without it."""
    proc = run("import matplotlib\n")
    assert proc.returncode != 0 and "hidden by the test" in proc.stderr
    assert run("import matplotlib\n", hidden=()).returncode == 0


def test_the_extras_check_sees_what_is_installed(monkeypatch):
    assert extras.missing("plots") is None and extras.installed("numpy")
    assert not extras.installed("no_such_package_of_ephem")
    monkeypatch.setitem(extras.EXTRAS, "plots", ("matplotlib", "no_such_package_of_ephem"))
    with pytest.raises(api.EphemError, match=r"install ephem-asteroid-pn\[plots\]") as info:
        extras.require("plots", "a plot")
    assert isinstance(info.value, ImportError) and info.value.name == "no_such_package_of_ephem"


def test_the_package_is_typed():
    """PEP 561: ``ephem/py.typed`` marks the package's annotations for type checkers; the wheel takes every file of
    the ``ephem`` package (pyproject.toml's hatch config, no exclusion), so it ships the marker (checked by building
    the wheel: ``pip wheel --no-deps .`` lists ``ephem/py.typed``)."""
    assert (ROOT / "ephem" / "py.typed").is_file()
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    wheel = config["tool"]["hatch"]["build"]["targets"]["wheel"]
    assert "ephem" in wheel["packages"] and not wheel.get("exclude") and not wheel.get("only-include")
    assert "py.typed" not in (ROOT / ".gitignore").read_text(encoding="utf-8")
