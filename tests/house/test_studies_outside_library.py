"""The studies are not the library: ``ephem`` and ``service`` never import ``studies`` (nor matplotlib just to
load ``ephem.api``), the wheel does not ship it, and each study runs from the project root as
``python -m studies.NAME``. And ephem.earth.lunisolar and ephem.earth.nonrigid no longer import each other: nonrigid builds on
lunisolar (imported at module top), lunisolar knows nothing of nonrigid.
"""
import ast
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LIBRARY = sorted([*(ROOT / "ephem").rglob("*.py"), *(ROOT / "service").rglob("*.py")])


def imported_modules(path: Path, top_level_only: bool = False) -> list[tuple[str, int]]:
    """(absolute module name, line) of every import in ``path`` (relative imports resolved against ``ephem``
    or ``service``); ``top_level_only``: only the statements at module level."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    nodes = tree.body if top_level_only else list(ast.walk(tree))
    found = []
    for node in nodes:
        if isinstance(node, ast.Import):
            found += [(alias.name, node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                here = list(path.relative_to(ROOT).with_suffix("").parts[:-node.level])
                base = ".".join(here + ([base] if base else []))
            found.append((base, node.lineno))
            found += [(f"{base}.{alias.name}", node.lineno) for alias in node.names]
    return found


def run(code: str) -> str:
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip()


def test_importing_the_api_loads_no_plotting_and_no_study():
    out = run("import ephem.api, sys; print('matplotlib' in sys.modules); "
              "print(sorted(m for m in sys.modules if m == 'studies' or m.startswith('studies.')))")
    assert out.splitlines() == ["False", "[]"]


def test_no_library_module_imports_a_study():
    offenders = [f"{p.relative_to(ROOT)}:{line} imports {name}" for p in LIBRARY
                 for name, line in imported_modules(p) if name == "studies" or name.startswith("studies.")]
    assert offenders == []


def test_the_wheel_ships_the_library_not_the_studies():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    packages = config["tool"]["hatch"]["build"]["targets"]["wheel"]["packages"]
    assert sorted(packages) == ["ephem", "service"]
    assert not (ROOT / "ephem" / "accuracy_bench.py").exists() and not (ROOT / "ephem" / "free_motion_bench.py").exists()


def test_nonrigid_builds_on_lunisolar_without_a_cycle():
    lunisolar = [name for name, _ in imported_modules(ROOT / "ephem" / "earth" / "lunisolar.py")]
    assert not any(n == "ephem.earth.nonrigid" or n.startswith("ephem.earth.nonrigid.") for n in lunisolar), lunisolar
    assert not any(n == "matplotlib" or n.startswith("matplotlib.") for n in lunisolar), lunisolar
    nonrigid_top = [name for name, _ in imported_modules(ROOT / "ephem" / "earth" / "nonrigid.py", top_level_only=True)]
    nonrigid_all = [name for name, _ in imported_modules(ROOT / "ephem" / "earth" / "nonrigid.py")]
    assert "ephem.earth.lunisolar" in nonrigid_top
    # every import of lunisolar is at module top (none hidden in a function), and no private name crosses
    assert [n for n in nonrigid_all if n.startswith("ephem.earth.lunisolar")] == \
        [n for n in nonrigid_top if n.startswith("ephem.earth.lunisolar")]
    assert not any(n.startswith("ephem.earth.lunisolar._") for n in nonrigid_all), nonrigid_all


def test_the_cli_has_no_bench_command():
    from ephem.cli import app

    names = {c.name for c in app.registered_groups}
    assert "bench" not in names


@pytest.mark.parametrize("study, words", [("accuracy", ("--out", "--quick")), ("free_motion", ("--out", "--quick"))])
def test_each_chart_study_runs_as_a_module_from_the_project_root(study, words):
    proc = subprocess.run([sys.executable, "-m", f"studies.{study}", "--help"], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert all(w in proc.stdout for w in words), proc.stdout
