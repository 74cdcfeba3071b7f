"""The theories of the spin axis the library serves, and which one answers for a body.

Each entry is a :class:`~ephem.theory.interface.SpinAxisTheory` family. The first whose test of a body under its
perturbers holds answers; a new theory (the Moon's Cassini state, the spin axis over millions of years) is one
module and one entry here, placed before the families it takes bodies from.

A family's module is imported only when it answers (or when :data:`THEORIES` is asked for): choosing needs only
each family's test of a body (plain functions of :mod:`ephem.bodies.catalogue`, which the family classes' ``serves``
call too) and the model names of :data:`MODELS`, a table that tests/theory/test_families_registry.py checks against the classes. A
one-body answer then loads one family, not three (issue 33: the CLI's start-up).
"""
from __future__ import annotations

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

    def load(self):
        return getattr(import_module(self.module), self.name)


#: the families, most specific first
FAMILIES: tuple[Family, ...] = (
    Family("ephem.moon.family", "SynchronousTheory", ("cassini", "librations", "integration", "de421"),
           is_synchronous),
    Family("ephem.earth.family", "LunisolarTheory", ("lunisolar", "nonrigid"), is_lunisolar),
    Family("ephem.sun.family", "SunLadder", ("secular", "series", "hansen", "second_order", "nonrigid",
                                             "numerical", "real_orbit"), is_centre_alone),
)
#: every model name any family answers to, the most general family's first
#: (a name two families share, "nonrigid", once: the family that serves the body gives its meaning)
MODELS: tuple[str, ...] = tuple(dict.fromkeys(name for family in reversed(FAMILIES) for name in family.models)) \
    + (LONG_TERM,)


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
