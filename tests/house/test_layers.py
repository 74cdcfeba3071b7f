"""The house of the library (docs/architecture.md): sub-packages by topic, each importing only the packages its
row of :data:`ALLOWED` names; no import cycle among the modules; no private name crossing a module; imports at
the top of a module, save those that defer a slow third-party package (:data:`DEFERRED`); the library imports
neither the service nor the studies, and the service and the CLI take the library only through ``ephem.api`` (the
service, a host, also through ``ephem.host``: its budgets, caches and warm-up, which a user's program never sets).

Read from the source text (ast), so a function-local import counts as much as one at the top.
"""
from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import pytest

from ephem.families import FAMILIES

ROOT = Path(__file__).resolve().parents[2]
LIBRARY = ROOT / "ephem"

#: The families' packages, from their entries in ephem.families.FAMILIES (a new family's row comes with its entry), and
#: what each may import: the packages below the families, never another family (they are siblings)
FAMILY_PACKAGES = tuple(dict.fromkeys(f.module.split(".")[1] for f in FAMILIES))
FAMILY_ROW = {"base", "orbit", "bodies", "rotation", "forced", "theory", "longterm"}

#: Each package (or top-level module) of ``ephem`` and the packages it may import besides itself, lowest first.
ALLOWED = {
    "base": set(),
    "orbit": {"base"},
    "bodies": {"base", "orbit"},
    "rotation": {"base", "orbit", "bodies"},
    "forced": {"base", "orbit", "bodies"},
    "theory": {"base", "orbit", "bodies", "rotation", "forced"},
    "longterm": {"base", "orbit", "bodies", "forced", "theory"},
    **{package: FAMILY_ROW for package in FAMILY_PACKAGES},
    "families": {"base", "bodies", "theory", "longterm", *FAMILY_PACKAGES},
    "batch": {"base", "orbit", "bodies", "forced", "theory", "longterm", "sun"},
    "exports": {"base", "orbit", "bodies", "rotation", "theory", "longterm"},
    "answers": {"base", "orbit", "bodies", "rotation", "forced", "theory", "longterm", "families", "batch", "exports"},
    # the public face asks no family (sun, earth, moon) for a name: what it states is the house's (issue 30)
    "api": {"base", "orbit", "bodies", "rotation", "forced", "theory", "longterm", "families", "batch", "answers",
            "exports"},
    # the hosts' face (budgets, caches, warm-up): the budget is base's, the warm-up an answer's
    "host": {"base", "answers"},
    "cli": {"api"},
}

#: Function-local imports of the library's own modules, each deferring a slow third-party package that the
#: importing module must not load at its own import: (importer, imported) -> why.
DEFERRED = {
    (f"ephem.cli.{m}", "ephem.api"): "numpy, astropy and the theories: `ephem --help` answers without them "
                                     "(tests/cli/test_cli_imports.py)" for m in ("one_body", "files", "demo")
}


def _name(path: Path) -> str:
    return ".".join(path.relative_to(ROOT).with_suffix("").parts)


def _package(module: str) -> str:
    """ephem.sun.ladder -> sun; ephem.api -> api"""
    return module.split(".")[1]


def _modules() -> dict[str, ast.Module]:
    return {_name(p): ast.parse(p.read_text(encoding="utf-8")) for p in sorted(LIBRARY.rglob("*.py"))
            if p.name != "__init__.py"}


MODULES = _modules()
PACKAGES = {_name(p.parent) for p in LIBRARY.rglob("__init__.py")} - {"ephem"}


def _resolve(module: str, node: ast.ImportFrom) -> str | None:
    if node.level == 0:
        return node.module
    base = module.split(".")[:-node.level]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(module: str, tree: ast.Module) -> list[tuple[str, list[str], int, bool]]:
    """(ephem module, names taken, line, at the top) of every import of the library in a module."""
    top = {id(n) for n in tree.body}
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            target = _resolve(module, node)
            if not target or not (target == "ephem" or target.startswith("ephem.")):
                continue
            for a in node.names:
                full = f"{target}.{a.name}"
                if full in MODULES or full in PACKAGES:       # from ephem.sun import ladder: the module
                    out.append((full, [], node.lineno, id(node) in top))
                else:
                    out.append((target, [a.name], node.lineno, id(node) in top))
        elif isinstance(node, ast.Import):
            out.extend((a.name, [], node.lineno, id(node) in top) for a in node.names
                       if a.name == "ephem" or a.name.startswith("ephem."))
    return out


def test_every_module_is_in_a_package_of_the_table():
    assert {_package(m) for m in MODULES} == set(ALLOWED), \
        f"without a row: {({_package(m) for m in MODULES}) - set(ALLOWED)}; rows without a module: " \
        f"{set(ALLOWED) - {_package(m) for m in MODULES}}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_a_package_imports_only_the_packages_of_its_row(module):
    mine = _package(module)
    wrong = [f"{module}:{line} imports {target}" for target, _, line, _ in _imports(module, MODULES[module])
             if target != "ephem" and _package(target) != mine and _package(target) not in ALLOWED[mine]]
    assert not wrong, wrong


def test_the_table_has_no_upward_edge():
    """Each row names only rows above it: the packages form a stack, not a web."""
    order = list(ALLOWED)
    for i, (package, allowed) in enumerate(ALLOWED.items()):
        assert allowed <= set(order[:i]), (package, allowed - set(order[:i]))


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_private_name_crosses_a_module(module):
    private = [f"{module}:{line} takes {name} from {target}" for target, taken, line, _ in
               _imports(module, MODULES[module]) for name in taken
               if name.startswith("_") and not (name.startswith("__") and name.endswith("__"))]   # __version__ is public
    assert not private, private


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_are_at_the_top(module):
    local = [f"{module}:{line} imports {target} inside a function" for target, _, line, top in
             _imports(module, MODULES[module]) if not top and (module, target) not in DEFERRED]
    assert not local, local


def _graph() -> dict[str, set[str]]:
    return {m: {t for t, _, _, _ in _imports(m, tree) if t in MODULES} - {m} for m, tree in MODULES.items()}


def test_the_imports_form_no_cycle():
    graph = _graph()
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


def import_depth() -> tuple[int, list[str]]:
    """The longest chain of imports among the modules, and the chain."""
    graph = _graph()
    memo: dict[str, list[str]] = {}

    def chain(m: str) -> list[str]:
        if m not in memo:
            memo[m] = [m] + max((chain(t) for t in graph[m]), key=len, default=[])
        return memo[m]

    longest = max((chain(m) for m in graph), key=len)
    return len(longest), longest


#: The flat package's longest import chain was 18 modules; the house's is 13: cli -> api -> the Dask batch
#: (distributed -> task -> population) or an answer (figures or kernels -> requests -> families) -> the Sun's
#: family -> ladder -> bounds -> precession_nutation -> kinoshita -> hansen -> budget -> errors. What is left is the
#: physics' own layering; a change that deepens the chain fails here.
MAX_IMPORT_DEPTH = 13


def test_the_import_graph_is_shallow():
    depth, longest = import_depth()
    assert depth <= MAX_IMPORT_DEPTH, " -> ".join(longest)


def test_the_layering_check_can_fail():
    """The checks see a package import outside its row, a local import and a private name (synthetic trees)."""
    tree = ast.parse("def f():\n    from ..answers.requests import track\n")
    [(target, taken, _, top)] = _imports("ephem.orbit.kepler", tree)
    assert target == "ephem.answers.requests" and not top and _package(target) not in ALLOWED["orbit"]
    tree = ast.parse("from ephem.sun.ladder import _span\nfrom ephem.sun import ladder\n")
    assert [(t, n) for t, n, _, _ in _imports("ephem.api", tree)] == [("ephem.sun.ladder", ["_span"]),
                                                                      ("ephem.sun.ladder", [])]


def test_the_library_imports_neither_the_service_nor_the_studies():
    for module, tree in MODULES.items():
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
                assert not any(n.split(".")[0] in ("service", "studies") for n in names if n), module


#: the library's modules the service may import: the public face and the hosts' interface
SERVICE_FACES = ("ephem.api", "ephem.host")


@pytest.mark.parametrize("path", sorted((ROOT / "service").glob("*.py")), ids=lambda p: p.name)
def test_the_service_takes_the_library_only_through_its_api(path):
    """The service imports ``ephem.api`` (the answers, what a request may name, the errors) and ``ephem.host`` (the
    budget around each request, the caches' size, the warm-up at start-up: the hosts' interface, kept out of the
    user's face), nothing else of the library."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    taken = [(node.lineno, target) for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))
             for target in ([a.name for a in node.names] if isinstance(node, ast.Import) else
                            [node.module] + [f"{node.module}.{a.name}" for a in node.names
                                             if node.module == "ephem"])
             if target and target.startswith("ephem.") and target not in SERVICE_FACES]
    assert not taken, taken


#: The packages that compute and render nothing: they return typed results in the library's units (radians,
#: rad/day, days, JD TDB; ephem.theory.results, the Track, the HistoryResult, the FreeMotion), and
#: ephem.answers.render alone writes an answer's keys with their units (docs/architecture.md).
COMPUTING = ("base", "orbit", "bodies", "rotation", "forced", "theory", "longterm", *FAMILY_PACKAGES, "families")
#: an answer's key naming its unit
UNIT_KEY = re.compile(r"_(deg|arcsec|mas)(_|$)")
#: modules of those packages that write unit-named keys, each with why that is no answer rendered
UNIT_KEYS_ALLOWED = {
    "ephem.earth.lunisolar": "the lunisolar series' terms as data/lunisolar.toml records them (mas)",
    "ephem.earth.nonrigid": "the IERS transfer function's corrections, records of the same form as the series'",
    "ephem.forced.uncertainty": "propagates the catalogue's 1-sigma through the answers' own values, which it "
                                "names as the answers do",
    "ephem.moon.family": "the uncertainty object's dominant_input, keyed by the answer's value names",
    "ephem.bodies.importer": "reads orbit files into the catalogue's records, whose fields name their units",
    "ephem.bodies.orbit_files": "the catalogue's record fields, which name their units (an input, not an answer)",
    "ephem.bodies.pole_table": "a pole table's records, the catalogue's input fields (an input, not an answer)",
}


def _unit_keys(tree: ast.Module) -> list[tuple[int, str]]:
    """(line, key) of every string key naming a unit that a dict display or a subscript assignment writes."""
    keys = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            keys += [k for k in node.keys if isinstance(k, ast.Constant) and isinstance(k.value, str)]
        elif isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store) and \
                isinstance(node.slice, ast.Constant) and isinstance(node.slice.value, str):
            keys.append(node.slice)
    return [(k.lineno, k.value) for k in keys if UNIT_KEY.search(k.value)]


@pytest.mark.parametrize("module", sorted(m for m in MODULES if _package(m) in COMPUTING))
def test_answers_are_rendered_in_one_place(module):
    found = _unit_keys(MODULES[module])
    if module in UNIT_KEYS_ALLOWED:
        assert found, f"{module} writes no unit-named key now: drop it from UNIT_KEYS_ALLOWED"
        return
    assert not found, f"{module} writes answer keys {found}: return a typed result and render it in " \
                      "ephem.answers.render"


def test_the_rendering_check_can_fail():
    tree = ast.parse("def f(x):\n    out = {'obliquity_deg': x}\n    out['psi_arcsec'] = x\n    return out\n")
    assert _unit_keys(tree) == [(2, "obliquity_deg"), (3, "psi_arcsec")]
    assert set(UNIT_KEYS_ALLOWED) <= set(MODULES), set(UNIT_KEYS_ALLOWED) - set(MODULES)


#: Function-local imports of the standard library (they defer nothing slow), each with why it stays local.
LOCAL_STDLIB = {("ephem.batch.manifest", "fcntl"): "POSIX only: the lock is skipped where it does not exist"}


@pytest.mark.parametrize("module", sorted(MODULES))
def test_the_standard_library_is_imported_at_the_top(module):
    local = []
    top = {id(n) for n in MODULES[module].body}
    for node in ast.walk(MODULES[module]):
        if isinstance(node, (ast.Import, ast.ImportFrom)) and id(node) not in top and not getattr(node, "level", 0):
            name = (node.module if isinstance(node, ast.ImportFrom) else node.names[0].name).split(".")[0]
            if name in sys.stdlib_module_names and (module, name) not in LOCAL_STDLIB:
                local.append(f"{module}:{node.lineno} imports {name} inside a function")
    assert not local, local
