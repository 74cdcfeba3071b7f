"""Every public function says what it takes and what it gives, numpydoc's way, and takes its options by name.

For every function of ``ephem.api.__all__``: its docstring has a ``Parameters`` section naming each parameter of its
signature (``a, b : type`` names two; ``**kwargs`` its own) and a ``Returns`` section. numpydoc's own parser is not
in the environment, so a small one reads the sections here (a section is a title line underlined with dashes; an
entry is a line at the section's indentation). The classes of ``__all__`` (the catalogue's records, the errors, the
answers' classes, the budget) are not functions: their fields are documented on the class.

And the answers' functions (those of ``ephem.answers``) take the body, the bodies, the rows or the answer and the
epochs by position and everything else by name only, their options in one order everywhere (ORDER), so that
``api.track("vesta", "2040-01-01", "2041-01-01", 10.0, dataset="petit2014")`` is the only way to say it.
"""
from __future__ import annotations

import inspect
import re

import pytest

from ephem import api

#: the names a public function may take by position: what it is about and its epochs (or the request holding them)
POSITIONAL = {"kind", "body", "bodies", "rows", "answer", "path", "input_path", "out_path",
              "start", "stop", "step_days", "start_year", "stop_year", "step_years", "request"}


def public_functions() -> list[tuple[str, object]]:
    out = []
    for name in api.__all__:
        value = getattr(api, name)
        if inspect.isfunction(value):
            out.append((name, value))
    return out


FUNCTIONS = public_functions()
ANSWERS = [(n, f) for n, f in FUNCTIONS if f.__module__.startswith("ephem.answers.")]


def sections(doc: str) -> dict[str, list[str]]:
    """{title: its lines} of a numpydoc docstring (cleaned by inspect.getdoc): a title is a line followed by a line of
    dashes as long."""
    lines = doc.splitlines()
    found, current = {}, None
    i = 0
    while i < len(lines):
        line = lines[i]
        if i + 1 < len(lines) and line.strip() and re.fullmatch(r"-{3,}", lines[i + 1].strip()) \
                and len(lines[i + 1].strip()) == len(line.strip()):
            current = line.strip()
            found[current] = []
            i += 2
            continue
        if current is not None:
            found[current].append(line)
        i += 1
    return found


def documented_names(lines: list[str]) -> set[str]:
    """The parameters a Parameters section names: its lines at the section's least indentation, before `` : ``."""
    entries = [ln for ln in lines if ln.strip()]
    if not entries:
        return set()
    indent = min(len(ln) - len(ln.lstrip()) for ln in entries)
    names = set()
    for ln in entries:
        if len(ln) - len(ln.lstrip()) != indent:
            continue
        head = ln.strip().split(" : ")[0]
        names.update(n.strip() for n in head.split(","))
    return names


def signature_names(fn) -> set[str]:
    names = set()
    for p in inspect.signature(fn).parameters.values():
        names.add({p.VAR_POSITIONAL: f"*{p.name}", p.VAR_KEYWORD: f"**{p.name}"}.get(p.kind, p.name))
    return names


def docstring_problem(fn) -> str | None:
    """Why ``fn``'s docstring is not numpydoc's Parameters and Returns for its signature, or None."""
    doc = inspect.getdoc(fn)
    if not doc:
        return "no docstring"
    found = sections(doc)
    want = signature_names(fn)
    if want and "Parameters" not in found:
        return "no Parameters section"
    missing = sorted(want - documented_names(found.get("Parameters", [])))
    if missing:
        return f"Parameters does not name {', '.join(missing)}"
    if "Returns" not in found and "Yields" not in found:
        return "no Returns section"
    if not any(ln.strip() for ln in found.get("Returns", found.get("Yields", []))):
        return "an empty Returns section"
    return None


@pytest.mark.parametrize("name, fn", FUNCTIONS, ids=[n for n, _ in FUNCTIONS])
def test_every_public_function_has_numpydoc_parameters_and_returns(name, fn):
    problem = docstring_problem(fn)
    assert problem is None, f"ephem.api.{name} ({fn.__module__}.{fn.__qualname__}): {problem}"


@pytest.mark.parametrize("name, fn", ANSWERS, ids=[n for n, _ in ANSWERS])
def test_an_answer_takes_only_its_subject_and_epochs_by_position(name, fn):
    positional = [p.name for p in inspect.signature(fn).parameters.values()
                  if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    extra = [p for p in positional if p not in POSITIONAL]
    assert not extra, f"ephem.api.{name} takes {', '.join(extra)} by position: make it keyword-only (after *)"


def test_the_answers_options_come_in_one_order_everywhere():
    """Two answer functions that both take options a and b take them in the same order (the signature's order is
    what help() and a notebook's completion show)."""
    orders = {name: [p.name for p in inspect.signature(fn).parameters.values() if p.kind is p.KEYWORD_ONLY]
              for name, fn in ANSWERS}
    clashes = []
    for a, first in orders.items():
        for b, second in orders.items():
            common = [p for p in first if p in second]
            if a < b and common != [p for p in second if p in first]:
                clashes.append(f"{a} {common} against {b} {[p for p in second if p in first]}")
    assert not clashes, "; ".join(clashes)


def test_the_parser_can_fail():
    def documented(body, start, *, dataset="current"):
        """A thing.

        Parameters
        ----------
        body, start : str
            What.
        dataset : str
            Which.

        Returns
        -------
        dict
            The answer.
        """

    def undocumented(body, *, dataset="current", model=None):
        """A thing.

        Parameters
        ----------
        body : str
            What.
            model : str
                an indented line is a description, not an entry

        Returns
        -------
        """

    def positional(body, dataset):
        """A thing."""

    assert docstring_problem(documented) is None
    assert docstring_problem(undocumented) == "Parameters does not name dataset, model"
    assert docstring_problem(positional) == "no Parameters section"
    assert documented_names(sections(inspect.getdoc(documented))["Parameters"]) == {"body", "start", "dataset"}
