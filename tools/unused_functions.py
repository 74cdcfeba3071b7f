#!/usr/bin/env python3
"""The functions of ``ephem/`` that nothing uses, or that only tests, studies, benchmarks or tools use.

    python tools/unused_functions.py            # from the project root

Reads the source (ast), imports nothing. A module-level function or a method of ``ephem/`` is *used* where
its name is called or read elsewhere than in its own definition: for a module-level function, its own
module's names, a ``from MODULE import NAME``, or ``.NAME`` in a file that imports its module (``ephem.api``'s
and ``ephem.host``'s lazy tables count: ``api.X`` or ``from ephem.api import X`` uses the function it loads, and
the table itself is a use by ``ephem``, the public face); for a method, ``.NAME`` anywhere. The uses are sorted by
where they are: ``ephem``, ``service``, ``studies``, ``benchmarks``, ``tests``, ``tools``. Printed:

- ``UNUSED``: no use at all (delete it, or say why it stays);
- ``STRING-ONLY``: named only inside strings (``ephem.api``'s table, ``getattr``, a docstring): check by hand;
- ``OUTSIDE``: used, but not by ``ephem/`` or ``service/``: a helper of the tests, a study, a benchmark or a
  tool, which may belong there, or a documented part of the library that only its tests exercise.

Names a framework calls (dunder methods, typer's commands registered by decorator, overrides of a base class
from a third-party package) look unused here: the decorator and base-class cases are skipped, the rest are
for the reader. Issue 43 pruned with it; its reasons for what stays are in the commits.
"""
from __future__ import annotations

import ast
import re
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
AREAS = ("ephem", "service", "studies", "benchmarks", "tests", "tools")
WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".")
    base = base[:len(base) - node.level + (1 if is_package else 0)]
    return ".".join(base + ([node.module] if node.module else []))


#: the library's lazy faces: the public one and the hosts' (each a ``_NAMES`` table of what it loads)
FACES = ("ephem.api", "ephem.host")


def api_table(trees: dict[Path, ast.Module]) -> dict[str, tuple[str, str]]:
    """The faces' lazy names (:data:`FACES`) -> (the module it loads, the attribute taken there):
    ``"current_budget": ("ephem.base.budget", "current")``."""
    table = {}
    for node in (n for face in FACES for n in ast.walk(trees[ROOT / (face.replace(".", "/") + ".py")])):
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "_NAMES" for t in node.targets):
            for key, value in zip(node.value.keys, node.value.values):
                module, attribute = (e.value for e in value.elts)
                table[key.value] = ("ephem" + module if module.startswith(".") else module, attribute)
    return table


def definitions(trees: dict[Path, ast.Module]):
    """(module, class or None, name, path, line) of every function of ephem/ a framework does not call."""
    for path, tree in trees.items():
        module = module_name(path)
        if not module.startswith("ephem."):
            continue
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.decorator_list and \
                    not (node.name.startswith("__") and node.name.endswith("__")):
                yield module, None, node.name, path, node.lineno
            elif isinstance(node, ast.ClassDef):
                for item in node.body:
                    if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and \
                            not (item.name.startswith("__") and item.name.endswith("__")) and \
                            not any(isinstance(d, ast.Name) and d.id in ("abstractmethod",) for d in item.decorator_list):
                        yield module, node.name, item.name, path, item.lineno


def main() -> int:
    trees = {p: ast.parse(p.read_text(encoding="utf-8")) for area in AREAS for p in sorted((ROOT / area).rglob("*.py"))}
    api = api_table(trees)
    names = defaultdict(lambda: defaultdict(int))     # (file, name) read as a Name -> count
    attributes = defaultdict(set)                     # file -> attribute names read
    strings = defaultdict(set)                        # file -> words in its string constants
    imported = defaultdict(set)                       # file -> modules it imports (and those ephem.api names load)
    taken = defaultdict(set)                          # file -> (module, name) of its from-imports
    for path, tree in trees.items():
        module, package = module_name(path), path.name == "__init__.py"
        for node in ast.walk(tree):
            if isinstance(node, ast.Name):
                names[path][node.id] += 1
            elif isinstance(node, ast.Attribute):
                attributes[path].add(node.attr)
            elif isinstance(node, ast.Constant) and isinstance(node.value, str):
                strings[path].update(WORD.findall(node.value))
            elif isinstance(node, ast.Import):
                imported[path].update(a.name for a in node.names)
            elif isinstance(node, ast.ImportFrom):
                target = resolve(module, package, node)
                imported[path].add(target)
                for a in node.names:
                    imported[path].add(f"{target}.{a.name}")
                    taken[path].add((target, a.name))
                    if target in FACES and a.name in api:             # from ephem.host import memo
                        taken[path].add(api[a.name])
                        imported[path].add(".".join(api[a.name]))
                    if f"{target}.{a.name}" in FACES:                   # from ephem import api
                        imported[path].add(f"{target}.{a.name}")
        if any(face in imported[path] for face in FACES):               # api.track(...): its module's track
            taken[path].update(api[a] for a in attributes[path] if a in api)
    rows = []
    for module, cls, name, path, line in definitions(trees):
        used, mentioned = ({"ephem"} if (module, name) in set(api.values()) else set()), set()
        for other in trees:
            area = other.relative_to(ROOT).parts[0]
            if cls is not None:
                hit = name in attributes[other] or (other == path and names[other][name] > 0)
            elif other == path:       # its own module: a def is no Name, so any Name is a use (a recursion too)
                hit = names[other][name] > 0 or name in attributes[other]
            else:
                hit = (module, name) in taken[other] or (module in imported[other] and name in attributes[other])
            if hit:
                used.add(area)
            elif name in strings[other]:
                mentioned.add(area)
        where = f"{path.relative_to(ROOT)}:{line}"
        label = f"{cls}.{name}" if cls else name
        if not used:
            rows.append(("UNUSED" if not mentioned else "STRING-ONLY", where, label, sorted(mentioned)))
        elif not used & {"ephem", "service"}:
            rows.append(("OUTSIDE", where, label, sorted(used)))
    for row in sorted(rows):
        print(*row, sep="\t")
    return 0


if __name__ == "__main__":
    sys.exit(main())
