"""A module holds one idea, and its docstring's first line says which (docs/architecture.md, "A module holds one
idea"): the rule a reviewer applies in place of a line cap (issue 43). The line cap of 600 decided where code went
(a grid evaluator was put elsewhere "because harmonics.py was at its 600 lines"); the first line is what a reviewer
reads to decide whether a function belongs: does it serve the idea that line states? If not, it goes to the module
whose line it serves, or to a new module with its own line.

Checked here, for every module of ``ephem/`` and ``service/``: a docstring whose first line is one sentence (a
capital or a code literal first, a full stop last, a blank line or the end after it, short enough to read at a
glance). The size limit stays only as an alarm, far above the largest module: a module that long has rarely kept
to one idea.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
MODULES = sorted([*(ROOT / "ephem").rglob("*.py"), *(ROOT / "service").rglob("*.py")])

#: the longest a first line may be (characters): one line of the source at its indentation, read at a glance
MAX_FIRST_LINE = 116
#: the alarm, not the rule: a module over this many lines is reported (the largest today has about 700)
ALARM_LINES = 1200


def first_line_problem(source: str) -> str | None:
    """Why a module's docstring does not open with a one-sentence line saying its idea, or None when it does."""
    doc = ast.get_docstring(ast.parse(source), clean=False)
    if not doc or not doc.strip():
        return "no module docstring: its first line says the one idea the module holds"
    lines = doc.strip("\n").splitlines()
    first = lines[0].strip()
    if not (first[0].isupper() or first[0].isdigit() or first.startswith("``")):
        return f"the first line should start a sentence (a capital or a ``code`` literal): {first!r}"
    if not first.endswith((".", "?", "!")):
        return f"the first line should be a whole sentence, ending with a full stop: {first!r}"
    if len(lines) > 1 and lines[1].strip():
        return f"the first line should stand alone (a blank line after it): {first!r} goes on with {lines[1].strip()!r}"
    if len(first) > MAX_FIRST_LINE:
        return f"the first line is {len(first)} characters (at most {MAX_FIRST_LINE}): say the idea, the rest below"
    return None


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_module_says_its_one_idea_on_its_first_line(path):
    problem = first_line_problem(path.read_text(encoding="utf-8"))
    assert problem is None, f"{path.relative_to(ROOT)}: {problem}"


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_module_reaches_the_size_alarm(path):
    lines = len(path.read_text(encoding="utf-8").splitlines())
    assert lines <= ALARM_LINES, (f"{path.relative_to(ROOT)} has {lines} lines: does it still hold the one idea its "
                                  "first line states? Split it by idea (docs/architecture.md), not by line count")


@pytest.mark.parametrize("source", [
    "x = 1\n",                                                              # no docstring
    '"""the lower-case start of a line."""\n',
    '"""A sentence that goes on\non the next line."""\n',
    '"""A title without its full stop\n\nThe rest."""\n',
    '"""' + "A" * 120 + '."""\n',
])
def test_the_first_line_rule_can_fail(source):
    assert first_line_problem(source) is not None


@pytest.mark.parametrize("source", [
    '"""Exceptions raised by the science core.\n\nEvery error names what was wrong."""\n',
    '"""``python -m ephem.cli``: what the ``ephem`` script runs."""\n',
])
def test_the_first_line_rule_passes_a_sentence(source):
    assert first_line_problem(source) is None
