"""Even grids of epochs that float64 can hold: the one rule every track, figure, kernel and history grid obeys.

A grid's epochs are ``start + k * step`` in float64 (Julian dates in days, or Julian years from J2000.0). Near a
date of magnitude ``|t|`` consecutive doubles are ``math.ulp(|t|)`` apart (4.66e-10 d, 40 µs, at JD 2451545; 3.6e-15
years at year 24): a step below that spacing gives epochs that repeat (a track of 932 rows, many at one date, whose
error estimate divides by their zero spacing) or an uneven grid of crowded ones. Such a grid is not what was asked
for, so it is refused, naming the step and the smallest step the span's dates resolve (:func:`resolution`); it is
never computed. A step of a few spacings is checked epoch by epoch (:func:`check_step`): rounding can make two
neighbours equal there; from :data:`SAFE_SPACINGS` spacings up it cannot.
"""
from __future__ import annotations

import math

import numpy as np

from .errors import InvalidInputError

#: from this many spacings of doubles (at the grid's largest magnitude) up, ``start + k * step`` is strictly
#: increasing whatever the rounding: each epoch is within 1.5 spacings of its exact value (the product's rounding,
#: then the sum's), so neighbours differ by at least step - 3 spacings
SAFE_SPACINGS = 4.0


def resolution(*ends: float) -> float:
    """The smallest step (in the ends' unit) an even grid between ``ends`` can take: the spacing of doubles at the
    largest magnitude among them (``math.ulp``; the smallest subnormal at zero)."""
    return math.ulp(max(abs(float(e)) for e in ends))


def duration_text(days: float) -> str:
    """A short duration in days, and in the unit a person reads it in (``4.657e-10 d (40.2 µs)``)."""
    seconds = days * 86400.0
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if seconds >= scale:
            return f"{days:.4g} d ({seconds / scale:.3g} {unit})"
    return f"{days:.4g} d ({seconds:.3g} s)"


def check_step(field: str, start: float, stop: float, step: float, count: int, unit: str = "d",
               what: str = "Julian dates") -> None:
    """Refuse (:class:`InvalidInputError` naming ``field``) a grid of ``count`` epochs ``start + k * step`` over
    [start, stop] whose epochs are not strictly increasing as float64: a step below :func:`resolution`, or one of
    a few spacings at which rounding makes neighbours equal. ``unit``: the step's (``d`` or ``years``), in the
    reason with ``what`` the epochs are."""
    if count < 2:
        return                   # one epoch: nothing to tell apart
    smallest = math.ulp(max(abs(start), abs(stop)))     # resolution(start, stop), without its generator: ~0.3 us
    if step >= SAFE_SPACINGS * smallest:
        return                   # every grid a track asks for in practice
    span = f"[{start:.17g}, {stop:.17g}]"
    shown = duration_text(smallest) if unit == "d" else f"{smallest:.4g} {unit}"
    if step < smallest:
        raise InvalidInputError(field, f"a step of {step:.6g} {unit} is finer than float64 {what} resolve over "
                                f"{span}: its epochs would repeat; the smallest step these dates resolve is {shown}")
    if step < SAFE_SPACINGS * smallest:
        epochs = start + step * np.arange(count)
        if not bool(np.all(np.diff(epochs) > 0.0)):
            raise InvalidInputError(field, f"a step of {step:.6g} {unit} is within rounding of what float64 {what} "
                                    f"resolve over {span}: some of its epochs would repeat; use a step of at least "
                                    f"{SAFE_SPACINGS * smallest:.4g} {unit} (the smallest these dates resolve is "
                                    f"{shown})")
