"""Families receive the request and a model choice, not a dozen loose parameters (issue 43).

A track request's model travels below the public answers as one :class:`~ephem.theory.requests.ModelChoice` (its
name, e-order, free wobble and rotation-scale terms) and the request as one
:class:`~ephem.theory.requests.TrackRequest` or :class:`~ephem.bodies.catalogue.Body` (which carries its dataset) or
family (which carries its perturbers), never as ``model`` and ``order`` side by side, nor ``dataset`` or
``perturbers`` handed from function to function. Counted here from the source (ast), for every function and method
of ``ephem/``:

- ``order`` with ``model``: a model asked for by its pieces;
- ``dataset``: a catalogue named again beside the body that comes from it;
- ``perturbers``: the torquing bodies named again beside the family that holds them.

The public surfaces are left out: the answer functions of ``ephem/answers/`` that :mod:`ephem.api` exports (their
keywords are what a program writes, and where the request is made from them) and the CLI's commands (typer maps each
option to a parameter). What else takes one is an exception, listed below with its reason: the lowest layer (the
catalogue's look-up by dataset, the families' test of a body under its perturbers, the numeric series summed over
the named perturbers), each count at most its stated limit. A new loose function fails here, naming itself; an
exception that no longer takes the parameter fails too, so the list only shrinks.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LIBRARY = ROOT / "ephem"

#: what a function is counted for: the parameters that make it loose
KINDS = {
    "order+model": {"order", "model"},
    "dataset": {"dataset"},
    "perturbers": {"perturbers"},
}

#: the exceptions of each kind, "path:qualified name" -> why it takes the parameter
EXCEPTIONS: dict[str, dict[str, str]] = {
    "order+model": {
        # the lowest numeric layer: ``model`` there is a first-order model object (PrecessionNutation), not a name,
        # and ``order`` the e-power order of the series it is evaluated to
        "ephem/forced/second_order.py:second_order_theory": "rung 4 built on a first-order model object",
        "ephem/sun/bounds.py:_series_coefficients": "a model object's coefficients to an e-order",
        "ephem/sun/bounds.py:truncation_bound": "a model object's truncation bound at an e-order",
        "ephem/sun/bounds.py:_truncation_parts": "the parts of that bound",
    },
    "dataset": {
        # the catalogue itself: where a dataset's name becomes its bodies
        "ephem/bodies/catalogue.py:_body_from_record": "a body made from its dataset's record",
        "ephem/bodies/catalogue.py:parse_catalogue": "a dataset's text parsed",
        "ephem/bodies/catalogue.py:_load_catalogue_file": "a dataset's file read",
        "ephem/bodies/catalogue.py:load_catalogue": "the catalogue of a dataset",
        "ephem/bodies/catalogue.py:get_body": "a body looked up by name in a dataset",
        "ephem/bodies/catalogue.py:resolve_body": "a name, id or Body made a Body, looked up in a dataset",
        "ephem/bodies/datasets.py:dataset_file": "where a dataset's file is",
        # exported by ephem.api (api.model_for) and taking a body's name: the name is looked up in the dataset
        "ephem/forced/precession_nutation.py:model_for": "public (api.model_for): a name looked up in a dataset",
        # the host's start-up: where the caches are filled for a catalogue
        "ephem/answers/requests.py:warm_up": "the host's start-up: the dataset whose caches it fills",
    },
    "perturbers": {
        # the families' test of a body under its perturbers, which chooses the family (ephem.families)
        "ephem/bodies/catalogue.py:is_synchronous": "the Moon's family's test",
        "ephem/bodies/catalogue.py:is_lunisolar": "the lunisolar Earth's family's test",
        "ephem/bodies/catalogue.py:is_centre_alone": "the single-perturber ladder's test",
        "ephem/sun/family.py:SunLadder.serves": "the family's test (SpinAxisTheory.serves)",
        "ephem/earth/family.py:LunisolarTheory.serves": "the family's test (SpinAxisTheory.serves)",
        "ephem/moon/family.py:SynchronousTheory.serves": "the family's test (SpinAxisTheory.serves)",
        "ephem/longterm/with_long_term.py:WithLongTerm.serves": "the family's test (SpinAxisTheory.serves)",
        "ephem/theory/interface.py:SpinAxisTheory.serves": "the family's test, declared",
        "ephem/families.py:theory_for": "the family serving a body under its perturbers: where the family is made",
        "ephem/theory/interface.py:SpinAxisTheory.__init__": "the family made for a request holds its perturbers",
        # the numeric layer: the forcing summed over the named bodies, each a key of the series' caches
        "ephem/earth/lunisolar.py:orbital_spectrum": "the FFT of the named bodies' orbital functions (disk cache)",
        "ephem/earth/lunisolar.py:_spectrum_arrays": "its arrays",
        "ephem/earth/lunisolar.py:_build_spectrum": "its computation",
        "ephem/earth/lunisolar.py:earth_lunisolar": "the lunisolar series of the named bodies (validated)",
        "ephem/earth/lunisolar.py:_build": "its cached build",
        "ephem/earth/model.py:lunisolar_earth": "the Earth's lunisolar model for the named bodies (cached)",
        "ephem/earth/estimates.py:nonrigid_earth": "the non-rigid Earth's model for the named bodies (cached)",
        "ephem/earth/estimates.py:_all_terms": "the cut-free series of the named bodies (cached)",
        "ephem/earth/de421_integration.py:integrate_de421": "the torque of the named bodies integrated along DE421",
        "ephem/orbit/de421.py:perturber_table": "the named bodies' masses and DE421 segments",
        "ephem/orbit/de421.py:integrate_heliocentric": "an orbit integrated under the named bodies",
    },
}

#: the most exceptions of each kind: a new one is a decision, made here with its reason above
LIMITS = {"order+model": 4, "dataset": 9, "perturbers": 21}


def _functions(tree: ast.AST, prefix: str = ""):
    """(qualified name, node) of every function and method, nested ones included."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield prefix + node.name, node
            yield from _functions(node, f"{prefix}{node.name}.")
        elif isinstance(node, ast.ClassDef):
            yield from _functions(node, f"{prefix}{node.name}.")


def _parameters(node) -> set[str]:
    a = node.args
    return {p.arg for p in (*a.posonlyargs, *a.args, *a.kwonlyargs)}


def _public_answers() -> set[str]:
    """``path:name`` of the answer functions of ``ephem/answers/`` that :mod:`ephem.api` exports (its lazy table)."""
    tree = ast.parse((LIBRARY / "api.py").read_text(encoding="utf-8"))
    table = next(n.value for n in tree.body if isinstance(n, (ast.Assign, ast.AnnAssign))
                 and any(isinstance(t, ast.Name) and t.id == "_NAMES"
                         for t in (n.targets if isinstance(n, ast.Assign) else [n.target])))
    out = set()
    for value in ast.literal_eval(table).values():
        module, attr = value
        if module.startswith(".answers."):
            out.add(f"ephem/answers/{module.split('.')[-1]}.py:{attr}")
    return out


def _is_command(node) -> bool:
    """A typer command (``@app.command()``): its parameters are the command line's options."""
    for d in node.decorator_list:
        target = d.func if isinstance(d, ast.Call) else d
        if isinstance(target, ast.Attribute) and target.attr == "command":
            return True
    return False


def loose_functions() -> dict[str, list[str]]:
    """Each kind's loose functions of ``ephem/`` outside the public surfaces, as ``path:qualified name``."""
    public = _public_answers()
    found: dict[str, list[str]] = {kind: [] for kind in KINDS}
    for path in sorted(LIBRARY.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        for name, node in _functions(ast.parse(path.read_text(encoding="utf-8"))):
            key = f"{rel}:{name}"
            if key in public or (rel.startswith("ephem/cli/") and _is_command(node)):
                continue
            params = _parameters(node)
            for kind, needs in KINDS.items():
                if needs <= params:
                    found[kind].append(key)
    return found


FOUND = loose_functions()


@pytest.mark.parametrize("kind", KINDS)
def test_no_function_takes_the_request_in_loose_pieces_beyond_the_stated_exceptions(kind):
    new = [key for key in FOUND[kind] if key not in EXCEPTIONS[kind]]
    assert not new, (f"these take {kind} loosely: pass a ModelChoice, a TrackRequest, a Body (its dataset) or the "
                     f"family (its perturbers) instead, or add them to EXCEPTIONS with the reason: {new}")


@pytest.mark.parametrize("kind", KINDS)
def test_the_exceptions_are_few_and_each_still_one(kind):
    assert len(EXCEPTIONS[kind]) <= LIMITS[kind]
    gone = [key for key in EXCEPTIONS[kind] if key not in FOUND[kind]]
    assert not gone, f"no longer loose (or gone): remove from EXCEPTIONS[{kind!r}]: {gone}"


def test_the_public_surfaces_are_found():
    """The exclusion is what it says: the public track answers and a CLI command are recognised as such (else the
    count above would pass for want of finding them)."""
    public = _public_answers()
    assert {"ephem/answers/requests.py:track", "ephem/answers/requests.py:track_arrays"} <= public
    tree = ast.parse((LIBRARY / "cli" / "one_body.py").read_text(encoding="utf-8"))
    assert any(name == "track" and _is_command(node) for name, node in _functions(tree))
