"""Each package of the library opens with an ``__init__.py`` that lists its modules and what each holds
(docs/architecture.md): a reader finds a module from its package's docstring, so a module left out of the list is
one a reader does not find. Checked for ``ephem`` and every sub-package: each module and sub-package is named in
the docstring as a ``:mod:`` reference (``:mod:`ephem.sun.bounds``` or ``:mod:`~ephem.cli.usage```) and something
said of it on its line.
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = sorted(p.parent for p in (ROOT / "ephem").rglob("__init__.py"))


def _qualified(path: Path) -> str:
    return ".".join(path.relative_to(ROOT).with_suffix("").parts)


def members(package: Path) -> list[str]:
    """The qualified names of a package's modules (``__init__`` aside) and sub-packages."""
    names = [_qualified(p) for p in package.glob("*.py") if p.stem != "__init__"]
    names += [_qualified(p) for p in package.iterdir() if (p / "__init__.py").is_file()]
    return sorted(names)


def unlisted(doc: str, names: list[str]) -> list[str]:
    """The names the docstring does not list: no ``:mod:`` reference to it followed, on its line, by what it holds."""
    return [n for n in names if not re.search(rf":mod:`~?{re.escape(n)}`[^\n]*\w", doc)]


@pytest.mark.parametrize("package", PACKAGES, ids=lambda p: _qualified(p))
def test_every_module_is_listed_in_its_package(package):
    doc = ast.get_docstring(ast.parse((package / "__init__.py").read_text(encoding="utf-8"))) or ""
    missing = unlisted(doc, members(package))
    assert not missing, f"{_qualified(package)}/__init__.py does not list {missing}: a line each, saying what it holds"


def test_the_listing_check_can_fail():
    doc = """The package.

- :mod:`ephem.x.a`: what a holds.
- :mod:`ephem.x.b`:
"""
    assert unlisted(doc, ["ephem.x.a", "ephem.x.b", "ephem.x.c"]) == ["ephem.x.b", "ephem.x.c"]
    assert unlisted("the modules: :mod:`~ephem.x.a` (its parsing)", ["ephem.x.a"]) == []
