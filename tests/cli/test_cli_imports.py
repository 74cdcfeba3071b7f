"""A one-body answer of the CLI imports no more than it needs: no plotting (matplotlib), no integrator
(scipy.integrate), no web stack (FastAPI, starlette, pydantic, uvicorn), no astropy.coordinates (the
ICRF -> ecliptic rotation comes from erfa), no study (the studies are not the library). A usage error imports not even ephem.api or numpy.
Each case runs in a fresh interpreter, as the ``ephem`` script does; no timing here
(benchmarks/bench_cli_startup.py measures that)."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FORBIDDEN = ("matplotlib", "scipy.integrate", "fastapi", "starlette", "pydantic", "pydantic_core", "uvicorn",
             "astropy.coordinates", "studies")

PROBE = """
import contextlib, io, json, sys
from ephem.cli import app
out, err = io.StringIO(), io.StringIO()
with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
    try:
        app(args=ARGS, prog_name="ephem")     # what the console script `ephem = ephem.cli:app` runs
        code = 0
    except SystemExit as exc:
        code = exc.code or 0
print(json.dumps({"code": code, "stdout": out.getvalue(), "stderr": err.getvalue(), "modules": sorted(sys.modules)}))
"""


def run_cli(args: list[str]) -> dict:
    proc = subprocess.run([sys.executable, "-c", PROBE.replace("ARGS", repr(args))], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def loaded(modules: list[str], names) -> list[str]:
    return sorted({n for n in names for m in modules if m == n or m.startswith(n + ".")})


@pytest.mark.parametrize("args", [["precession", "vesta"], ["precession", "vesta", "--format", "table"],
                                  ["nutation", "vesta", "--order", "4"], ["body", "vesta"]])
def test_a_one_body_answer_imports_no_plotting_integrator_or_web_stack(args):
    ran = run_cli(args)
    assert ran["code"] == 0, ran["stderr"]
    assert "Vesta" in ran["stdout"]
    assert loaded(ran["modules"], FORBIDDEN) == []


@pytest.mark.parametrize("args", [["precession", "vesta"], ["nutation", "vesta", "--order", "4"], ["body", "vesta"],
                                  ["precession", "moon"]])
def test_a_one_body_answer_needs_neither_astropy_nor_scipy(args):
    """Issue 33: the catalogue's units convert by exact factors (astropy is the fallback), the free wobble's elliptic
    functions and the Moon's root load scipy only when used, and ephem.api loads a name's module on first use."""
    ran = run_cli(args)
    assert ran["code"] == 0, ran["stderr"]
    assert loaded(ran["modules"], ("astropy", "scipy", "ephem.batch", "ephem.answers.kernels")) == []


def test_the_answer_is_unchanged_by_the_lighter_rotation():
    ran = run_cli(["precession", "vesta", "--dataset", "petit2014"])
    assert round(json.loads(ran["stdout"])["precession_rate_arcsec_per_year"], 4) == 13.6713   # Petit et al.: 13.6728


@pytest.mark.parametrize("args", [["track", "vesta", "--start", "2020-01-01", "--stop", "2021-01-01", "--step-days",
                                   "abc"], ["precesion", "vesta"], ["precession", "vesta", "--tolerance-mas", "nan"]])
def test_a_usage_error_answers_before_the_library_loads(args):
    ran = run_cli(args)
    assert ran["code"] == 2 and ran["stderr"].startswith("error: ")
    assert loaded(ran["modules"], FORBIDDEN + ("ephem.api", "numpy", "astropy", "rich")) == []
