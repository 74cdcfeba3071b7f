"""The provenance the data carries speaks of its sources and of what is not verified, never of how it was collected
(issue 41: a reference's note named a temporary file of research notes; others cited "the brief", a "helper", an
extraction's path on a machine). Every text file of ``data/`` (the catalogue, the references, the interiors, the
long-term and free-motion tables, the Lara series and their READMEs) is read whole, and none of the phrases below
may appear; the body page shows these strings (a value's source, why it has no σ, a reference's ``where``).
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

DATA = Path(__file__).resolve().parents[2] / "data"
TEXT = sorted(p for p in DATA.rglob("*") if p.suffix in (".toml", ".md", ".csv", ".json", ".txt") and p.is_file())

#: what a provenance string must not say: a machine's paths, the research process's notes, sessions and briefs
FORBIDDEN = {
    "a machine's path": re.compile(r"(?<![\w.])/(?:tmp|home|work|var|root|mnt|Users)/|[A-Za-z]:\\\\|shared/seeds|"
                                   r"\bseeds?/\d|\bseed file\b"),
    "research notes": re.compile(r"\bresearch notes?\b|\bmy notes\b|\bthe notes (?:recall|say)\b", re.I),
    "the research session": re.compile(r"\bhelper\b|\bsession\b|\bthe brief\b|\bbrief's\b", re.I),
    "this machine's reach": re.compile(r"\b(?:read|retrievable|reachable|re-read) here\b|\bnot reachable\b", re.I),
}


def test_the_data_has_text_to_read():
    assert len(TEXT) > 10 and any(p.name == "interiors.toml" for p in TEXT)


@pytest.mark.parametrize("path", TEXT, ids=[str(p.relative_to(DATA)) for p in TEXT])
def test_provenance_speaks_of_sources_not_of_how_it_was_collected(path):
    text = path.read_text(encoding="utf-8")
    found = [(what, m.group(0), text.count("\n", 0, m.start()) + 1)
             for what, pattern in FORBIDDEN.items() for m in pattern.finditer(text)]
    assert not found, f"{path.relative_to(DATA)}: {found}"


@pytest.mark.parametrize("bad", ["(research notes /tmp/mars_core_sources.md, label READ-SECONDARY)",
                                 "value supplied in the brief; not re-read here", "extraction shared/seeds/000.txt",
                                 "collected by a helper session", "the MPC file itself was not reachable"])
def test_the_check_catches_what_it_should(bad):
    assert any(p.search(bad) for p in FORBIDDEN.values()), bad
