"""The documents' lists of models are the families' registry's (ephem.families, issue 43): each block between
``<!-- models ... -->`` and ``<!-- /models -->`` in README.md and docs/*.md is what :func:`models_markdown` writes
from ``ephem.api.model_families()``, so a family added to the registry fails here until the documents list it
(the failure prints the block to paste)."""
from __future__ import annotations

import re
from pathlib import Path

from ephem import api

ROOT = Path(__file__).resolve().parents[2]
BLOCK = re.compile(r"<!-- models\b[^>]*-->\n(.*?)<!-- /models -->", re.S)


def models_markdown(families=None) -> str:
    """One line per family, the most general first: its model names and its summary."""
    lines = [f"`{'|'.join(models)}` ({summary})" for summary, models in (families or api.model_families())]
    return ";\n".join(lines) + ".\n"


def documents() -> dict[Path, list[str]]:
    found = {}
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        blocks = BLOCK.findall(path.read_text(encoding="utf-8"))
        if blocks:
            found[path] = blocks
    return found


def test_every_model_list_of_the_documents_is_the_registrys():
    found = documents()
    assert found, "no <!-- models --> block in README.md or docs/"
    expected = models_markdown()
    for path, blocks in found.items():
        for block in blocks:
            assert block == expected, f"{path.relative_to(ROOT)}: its model list should read\n{expected}"


def test_a_family_registered_and_not_documented_fails_the_check():
    api.register_family(api.Family("nowhere", "ToyTheory", ("toy_uniform",), lambda body, perturbers: False,
                                   "a family of tests"))
    try:
        expected = models_markdown()
    finally:
        api.unregister_family("ToyTheory")
    assert "`toy_uniform` (a family of tests);\n" in expected
    assert all(expected not in blocks for blocks in documents().values())
