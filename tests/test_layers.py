"""The layers of the library (docs/architecture.md): every import of one ephem module by another goes down
the layers or stays within one, the modules' imports form no cycle, private names do not cross modules,
and the library imports neither the service nor the studies.

Read from the source text (ast), so a function-local import counts as much as one at the top: a local
import may defer a slow third-party package, never hide a cycle.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: lowest first; a module may import from its own layer or below (docs/architecture.md)
LAYERS = {
    "foundation": ("constants", "errors", "budget", "memo", "units", "timeparse"),
    "orbit, geometry and data": ("kepler", "geometry", "inertia", "catalogue", "hansen", "harmonics", "cost", "andoyer",
                                 "euler_poinsot", "polynomials", "deprit", "lie_series"),
    "theories": ("kinoshita", "model", "rotation_scale", "second_order", "numerical", "ephemeris", "lunisolar",
                 "nonrigid", "cassini", "synchronous_rigid", "physical_librations",
                 "free_motion", "rigid", "relativity", "secular_orbit", "orbit_history"),
    "accuracy": ("theory", "physics_errors", "uncertainty", "spin_history", "ladder", "earth", "synchronous",
                 "history", "long_term", "registry"),
    "answers": ("api", "population"),
    "exports and CLI": ("tables", "pck_fit", "pck_text", "pck", "plots", "catalogue_import", "batch", "cli"),
}
LEVEL = {module: level for level, modules in enumerate(LAYERS.values()) for module in modules}


def _modules() -> dict[str, ast.Module]:
    return {p.stem: ast.parse(p.read_text(encoding="utf-8")) for p in sorted((ROOT / "ephem").glob("*.py"))
            if p.stem != "__init__"}


def _imports(tree: ast.Module) -> list[tuple[str, list[str], int]]:
    """(ephem module, names taken, line) of every import of the package in a module, wherever it stands."""
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module:
                out.append((node.module.split(".")[0], [a.name for a in node.names], node.lineno))
            else:
                out.extend((a.name, [], node.lineno) for a in node.names)
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("ephem."):
            out.append((node.module.split(".")[1], [a.name for a in node.names], node.lineno))
        elif isinstance(node, ast.Import):
            out.extend((a.name.split(".")[1], [], node.lineno) for a in node.names if a.name.startswith("ephem."))
    return out


MODULES = _modules()


def test_every_module_has_a_layer():
    assert set(MODULES) == set(LEVEL), f"modules without a layer: {set(MODULES) - set(LEVEL)}; " \
                                       f"layers naming no module: {set(LEVEL) - set(MODULES)}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_go_down_the_layers(module):
    names = list(LAYERS)
    upward = [f"{module}:{line} imports {target} ({names[LEVEL[target]]} above {names[LEVEL[module]]})"
              for target, _, line in _imports(MODULES[module]) if LEVEL[target] > LEVEL[module]]
    assert not upward, upward


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_private_name_crosses_a_module(module):
    private = [f"{module}:{line} takes {name} from {target}" for target, taken, line in _imports(MODULES[module])
               for name in taken if name.startswith("_")]
    assert not private, private


def test_the_imports_form_no_cycle():
    graph = {m: {t for t, _, _ in _imports(tree)} - {m} for m, tree in MODULES.items()}
    state: dict[str, int] = {}

    def visit(m: str, path: list[str]) -> None:
        state[m] = 1
        for t in sorted(graph[m]):
            if state.get(t) == 1:
                raise AssertionError("import cycle: " + " -> ".join(path[path.index(t):] + [t]))
            if t not in state:
                visit(t, path + [t])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])


def test_the_layering_check_can_fail():
    """The checks see an upward import and a cycle (a synthetic module tree)."""
    tree = ast.parse("def f():\n    from .api import track\n")
    assert [t for t, _, _ in _imports(tree)] == ["api"]
    assert LEVEL["api"] > LEVEL["kinoshita"]
    tree = ast.parse("from ephem.ladder import _span\n")
    assert _imports(tree)[0][:2] == ("ladder", ["_span"])


def test_the_library_imports_neither_the_service_nor_the_studies():
    for module, tree in MODULES.items():
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
                assert not any(n.split(".")[0] in ("service", "studies") for n in names if n), module
