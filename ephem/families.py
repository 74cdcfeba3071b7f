"""The theories of the spin axis the library serves, and which one answers for a body.

Each entry is a :class:`~ephem.theory.interface.SpinAxisTheory` family. The first that
:meth:`~ephem.theory.interface.SpinAxisTheory.serves` a body under its perturbers answers; a new theory
(the Moon's Cassini state, the spin axis over millions of years) is one module and one line here,
placed before the families it takes bodies from.
"""
from __future__ import annotations

from .bodies.catalogue import Body
from .earth.family import LunisolarTheory
from .base.errors import NotApplicableError
from .sun.family import SunLadder
from .longterm.with_long_term import NAME as LONG_TERM, WithLongTerm
from .moon.family import SynchronousTheory
from .theory.interface import SpinAxisTheory

#: the families, most specific first
THEORIES: tuple[type[SpinAxisTheory], ...] = (SynchronousTheory, LunisolarTheory, SunLadder)
#: every model name any family answers to, the most general family's first
#: (a name two families share, "nonrigid", once: the family that serves the body gives its meaning)
MODELS: tuple[str, ...] = tuple(dict.fromkeys(name for family in reversed(THEORIES) for name in family.models)) \
    + (LONG_TERM,)


def theory_for(body: Body, perturbers: tuple[str, ...], axis: str = "figure") -> SpinAxisTheory:
    """The family serving ``body`` under ``perturbers`` (without a free wobble: see
    :meth:`~ephem.theory.interface.SpinAxisTheory.with_wobble`), with the long-term model after its own
    (:class:`~ephem.longterm.with_long_term.WithLongTerm`)."""
    for family in THEORIES:
        if family.serves(body, perturbers):
            return WithLongTerm(family(body, perturbers, axis))
    raise NotApplicableError(body.name, f"no theory here models {body.name} under {', '.join(perturbers)}")


def refuse_model(theory: SpinAxisTheory, model: str) -> None:
    """Refuse a model name the serving family does not have, saying which family has it and what serves
    this body."""
    b = theory.body
    owner = next((f for f in THEORIES if model in f.models), None)
    where = f"there is no '{model}' model" if owner is None else \
        f"the '{model}' model belongs to {owner.summary}: {owner.how_to_reach(b)}"
    raise NotApplicableError(b.name, f"{where}; {b.name} under {', '.join(theory.perturbers)} is served by "
                                     f"{theory.summary} ({', '.join(theory.models)})")
