"""Exceptions raised by the science core.

Every error names what was wrong, so that the CLI and the HTTP service can
pass the message straight to the user (a 4xx, never a 500).
"""
from __future__ import annotations

import math


class EphemError(Exception):
    """Base class of every error the library raises on purpose."""


class InvalidInputError(EphemError, ValueError):
    """An input value is malformed or outside its physical domain.

    ``field`` is the dotted name of the offending input (``orbit.e``,
    ``inertia.A``…), ``body`` the body it belongs to, if any.
    """

    def __init__(self, field: str, reason: str, body: str | None = None):
        self.field = field
        self.reason = reason
        self.body = body
        where = f"{body}: " if body else ""
        super().__init__(f"{where}{field}: {reason}")


class UnknownBodyError(EphemError, LookupError):
    """A body name or NAIF id that is not in the catalogue."""

    def __init__(self, query: str, known: list[str]):
        self.query = query
        self.known = list(known)
        super().__init__(
            f"unknown body {query!r}; known bodies: {', '.join(self.known)}"
        )

    def __str__(self) -> str:  # LookupError would repr() the message
        return self.args[0]


class NotApplicableError(EphemError):
    """The theory does not hold for this body (for instance a synchronous rotator).

    ``ratio`` is the quantity that decided it (spin rate over orbital mean
    motion for the rotation-averaging condition) and ``threshold`` the limit.
    """

    def __init__(self, body: str, reason: str, ratio: float | None = None,
                 threshold: float | None = None):
        self.body = body
        self.reason = reason
        self.ratio = ratio
        self.threshold = threshold
        super().__init__(f"not applicable to {body}: {reason}")


def count_text(count: float) -> str:
    """A count of samples or epochs for a message ("100078 samples exceed the cap of 100000"), from the float
    ``span / step + 1`` whose whole part it is: that integer while a float holds it exactly (below 2**53), its
    order of magnitude beyond ("about 1.2e+20"), and a bound for a count that overflowed to infinity (a span
    over a subnormal step). A count printed as "1e+05" read as the cap itself."""
    if math.isnan(count):
        return "an undefined number of"
    if math.isinf(count):
        return "more than 1e+308"
    if count < 2.0 ** 53:
        return str(math.floor(count))
    return f"about {count:.3g}"


class MissingExtraError(EphemError, ImportError):
    """A feature needs a package of an optional extra of the distribution that is not installed.

    An :class:`ImportError` (as a missing package would raise) and an :class:`EphemError` (so the CLI prints it as
    any library error); the message names the extra to install: ``pip install 'ephem-asteroid-pn[plots]'``.
    ``feature`` is what was asked for, ``module`` the missing package, ``extra`` the extra that brings it.
    """

    def __init__(self, feature: str, module: str, extra: str, distribution: str = "ephem-asteroid-pn"):
        self.feature = feature
        self.module = module
        self.extra = extra
        super().__init__(f"{feature} needs {module}, which is not installed: install {distribution}[{extra}] "
                         f"(pip install '{distribution}[{extra}]')", name=module)

    def __str__(self) -> str:
        return self.args[0]
