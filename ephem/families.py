"""The theories of the spin axis the library serves, and which one answers for a body.

Each entry is a :class:`~ephem.theory.interface.SpinAxisTheory` family. The first whose test of a body under its
perturbers holds answers; a new theory (the Moon's Cassini state, the spin axis over millions of years) is one
module and one entry here, placed before the families it takes bodies from.

A family's module is imported only when it answers (or when :data:`THEORIES` is asked for): choosing needs only
each family's test of a body (plain functions of :mod:`ephem.bodies.catalogue`, which the family classes' ``serves``
call too) and the model names of :data:`MODELS`, a table that tests/theory/test_families_registry.py checks against the classes. A
one-body answer then loads one family, not three (issue 33: the CLI's start-up).

The registry is the one list of models: :data:`MODELS` is a live view of it, which the CLI's help, the service's
schema (its ``model`` enums, built when the app is) and the docs' list (tests/house/test_docs_models.py) read.
:func:`register` adds a family from outside the library (a plug-in, or a test's toy family) and :func:`unregister`
takes it out again.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from importlib import import_module

from .base.errors import NotApplicableError
from .bodies.catalogue import Body, is_centre_alone, is_lunisolar, is_synchronous
from .longterm.with_long_term import NAME as LONG_TERM, WithLongTerm


@dataclass(frozen=True)
class Family:
    """Where a family lives, the models it answers to and its test of a body, without importing it."""

    module: str
    name: str
    models: tuple[str, ...]
    serves: object  # (Body, perturbers) -> bool
    #: the class's ``summary`` (what the family is, in a few words), for the help texts without importing it
    summary: str = ""

    def load(self):
        return getattr(import_module(self.module), self.name)


#: the families, most specific first
FAMILIES: tuple[Family, ...] = (
    Family("ephem.moon.family", "SynchronousTheory", ("cassini", "librations", "integration", "de421"),
           is_synchronous, "the Cassini-state theory of a synchronous rotator (the Moon)"),
    Family("ephem.earth.family", "LunisolarTheory", ("lunisolar", "nonrigid"), is_lunisolar,
           "the Earth's lunisolar theory (the Earth under the Moon and the Sun)"),
    Family("ephem.sun.family", "SunLadder", ("secular", "series", "hansen", "second_order", "nonrigid",
                                             "numerical", "real_orbit"), is_centre_alone,
           "the single-perturber ladder (a body torqued by the centre of its orbit)"),
)


class ModelNames(Sequence):
    """Every model name any family of the registry answers to, the most general family's first, then the long-term
    model (a name two families share, "nonrigid", once: the family that serves the body gives its meaning).

    A view, read anew at each use, so that a family :func:`register` adds is in every list taken from it."""

    def _names(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys(name for family in reversed(FAMILIES) for name in family.models)) + (LONG_TERM,)

    def __getitem__(self, index):
        return self._names()[index]

    def __len__(self) -> int:
        return len(self._names())

    def __contains__(self, name) -> bool:
        return name in self._names()

    def __iter__(self):
        return iter(self._names())

    def __eq__(self, other) -> bool:
        return isinstance(other, (tuple, list, ModelNames)) and tuple(self) == tuple(other)

    __hash__ = None

    def __repr__(self) -> str:
        return repr(self._names())


#: what the long-term model is, in a few words (the help texts' and the docs' list)
LONG_TERM_SUMMARY = "every family's long-term model (the spin averaged along the orbit's history)"
#: every model name any family answers to (a live view of the registry)
MODELS = ModelNames()


def model_families() -> list[tuple[str, tuple[str, ...]]]:
    """Each family's ``summary`` and model names, the most general family first (as :data:`MODELS` lists them), then
    the long-term model, which every family has after its own: the lists a help text or a document gives.

    Returns
    -------
    list of (str, tuple of str)
        (summary, model names cheapest first) per family, then the long-term model's.
    """
    return [(f.summary, f.models) for f in reversed(FAMILIES)] + [(LONG_TERM_SUMMARY, (LONG_TERM,))]


def register(family: Family, before: str | None = None) -> Family:
    """Add ``family`` to the registry, before the family whose class is named ``before`` (None: first, the most
    specific), so that the bodies its test takes are served by it; its models join :data:`MODELS`. A family of
    that class name already registered is an error.

    Parameters
    ----------
    family : Family
        The registry entry: the family's module and class, its model names and its test of a body.
    before : str or None
        The class name of the registered family it goes before; None: first.

    Returns
    -------
    Family
        ``family``, as registered.
    """
    global FAMILIES
    if any(f.name == family.name for f in FAMILIES):
        raise ValueError(f"a family {family.name!r} is registered already")
    names = [f.name for f in FAMILIES]
    if before is not None and before not in names:
        raise ValueError(f"no family {before!r} is registered to go before; registered: {', '.join(names)}")
    at = 0 if before is None else names.index(before)
    FAMILIES = FAMILIES[:at] + (family,) + FAMILIES[at:]
    return family


def unregister(name: str) -> None:
    """Take the family whose class is named ``name`` out of the registry (a test's toy family, once done).

    Parameters
    ----------
    name : str
        The family's class name.

    Returns
    -------
    None
    """
    global FAMILIES
    FAMILIES = tuple(f for f in FAMILIES if f.name != name)


def __getattr__(name: str):
    if name == "THEORIES":  # the family classes themselves (imports all three)
        return tuple(f.load() for f in FAMILIES)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def theory_for(body: Body, perturbers: tuple[str, ...], axis: str = "figure"):
    """The family serving ``body`` under ``perturbers`` (without a free wobble: see
    :meth:`~ephem.theory.interface.SpinAxisTheory.with_wobble`), with the long-term model after its own
    (:class:`~ephem.longterm.with_long_term.WithLongTerm`)."""
    for family in FAMILIES:
        if family.serves(body, perturbers):
            cls = family.load()
            if axis not in cls.axes:
                raise NotApplicableError(body.name, f"{cls.summary} follows the axes {', '.join(cls.axes)}, not "
                                         f"{axis}" + ("" if axis != "mean_rotation" else
                                                      ": the mean rotation axis is a synchronous body's"))
            return WithLongTerm(cls(body, perturbers, axis))
    raise NotApplicableError(body.name, f"no theory here models {body.name} under {', '.join(perturbers)}")


def refuse_model(theory, model: str) -> None:
    """Refuse a model name the serving family does not have, saying which family has it and what serves
    this body."""
    b = theory.body
    owner = next((f.load() for f in FAMILIES if model in f.models), None)
    where = f"there is no '{model}' model" if owner is None else \
        f"the '{model}' model belongs to {owner.summary}: {owner.how_to_reach(b)}"
    raise NotApplicableError(b.name, f"{where}; {b.name} under {', '.join(theory.perturbers)} is served by "
                                     f"{theory.summary} ({', '.join(theory.models)})")
