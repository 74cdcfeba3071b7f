"""What a track request asks a family for: the model chosen, the epochs and the request as one object each.

A family (:class:`~ephem.theory.interface.SpinAxisTheory`) receives these instead of loose parameters (issue 43):

- :class:`ModelChoice`: which model answers, as a request names it or a tolerance picks it: the model's name
  (None: the family's default), its e-order, and whether its track adds the free wobble and the rotation-scale
  terms; an :class:`~ephem.theory.results.Estimate` gives the one it estimated (``Estimate.choice``);
- :class:`Epochs`: the epochs of a track, an even grid (start, step, count; the families' fast path) or any array,
  in JD TDB;
- :class:`TrackRequest`: one track request as the library has checked it: the body, its perturbers, the axis, the
  epochs, the tolerance, the model asked for, the free wobble and the rotation phase; the body carries its dataset.

The public answers (:mod:`ephem.answers.requests`) turn their keywords into these; below them the model travels as
one value, so a new setting of a model is one field here rather than a parameter added to every method.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..base.constants import MAS
from ..bodies.catalogue import Body


@dataclass(frozen=True)
class ModelChoice:
    """One model of a family, as a request names it or a tolerance picks it.

    ``model``: the model's name (None: the family's default, :meth:`~ephem.theory.interface.SpinAxisTheory.
    default_model`); ``order``: the e-order of a truncated series (None: exact coefficients, or a model without
    one); ``free_wobble``: the track adds the request's free wobble of the figure axis; ``rotation_scale``: the track
    adds the rotation-scale terms (:mod:`ephem.forced.rotation_scale`; the request gave the rotation phase)."""

    model: str | None = None
    order: int | None = None
    free_wobble: bool = False
    rotation_scale: bool = False

    def named(self, model: str) -> "ModelChoice":
        """The same choice with its model named (a family's default filled in)."""
        return replace(self, model=model)


@dataclass(frozen=True)
class Epochs:
    """The epochs of a track (JD TDB): an even grid ``start + step * arange(count)``, or any array ``jd`` (then
    ``step`` is None)."""

    start: float
    step: float | None
    count: int
    jd: np.ndarray | None = field(default=None, compare=False, repr=False)

    @classmethod
    def grid(cls, start: float, step: float, count: int) -> "Epochs":
        """An even grid of ``count`` epochs from ``start`` by ``step`` days."""
        return cls(float(start), float(step), int(count))

    @classmethod
    def at(cls, jd_tdb) -> "Epochs":
        """Any epochs (JD TDB, a scalar or an array)."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        return cls(float(t[0]) if t.size else float("nan"), None, int(t.size), t)

    @property
    def is_grid(self) -> bool:
        return self.step is not None

    @property
    def stop(self) -> float:
        """The last epoch (JD TDB)."""
        if self.is_grid:
            return self.start + self.step * (self.count - 1)
        return float(self.jd[-1]) if self.count else float("nan")

    @property
    def jd_tdb(self) -> np.ndarray:
        """Every epoch (JD TDB)."""
        return self.start + self.step * np.arange(self.count) if self.is_grid else self.jd


@dataclass(frozen=True)
class TrackRequest:
    """One track request, checked: ``body`` (its ``dataset`` with it) under ``perturbers``, the ``axis`` followed
    (:data:`ephem.base.constants.AXES`), the ``epochs``, the ``tolerance`` (radians; None: the model is named), the
    model asked for (``choice``; with a tolerance, its order and model are None), the free ``wobble`` (a
    :class:`~ephem.rotation.free_motion.Wobble`, or None) and the ``rotation_phase`` (radians, or None)."""

    body: Body
    perturbers: tuple[str, ...]
    axis: str
    epochs: Epochs
    tolerance: float | None = None
    choice: ModelChoice = ModelChoice()
    wobble: object = None
    rotation_phase: float | None = None

    @property
    def dataset(self) -> str:
        """The catalogue the body comes from (the body's own)."""
        return self.body.dataset

    @property
    def asked(self) -> ModelChoice:
        """The model asked for by name (no tolerance), its track with the free wobble where the request gave its
        phase and the rotation-scale terms where it gave the rotation phase."""
        return replace(self.choice, free_wobble=self.wobble is not None, rotation_scale=self.rotation_phase is not None)

    def __repr__(self) -> str:
        """One short line (a notebook prints it; the dataclass's own printed the whole Body): the body and its
        dataset, the perturbers, the axis, the epochs' count and span (JD TDB, and the step in days on a grid), the
        tolerance (mas) or the model named (and its e-order), and the wobble and rotation phase where given."""
        e = self.epochs
        span = f"JD {e.start:.10g}" + ("" if e.count < 2 else f" to {e.stop:.10g}")
        if e.is_grid:
            span += f" by {e.step:g} d"
        if self.tolerance is not None:
            model = f"tolerance {self.tolerance / MAS:.6g} mas"
        else:
            model = f"model {self.choice.model or 'default'}" + (
                "" if self.choice.order is None else f" order {self.choice.order}")
        extras = "".join(("" if self.wobble is None else ", free wobble",
                          "" if self.rotation_phase is None
                          else f", rotation phase {math.degrees(self.rotation_phase):.6g} deg"))
        return (f"TrackRequest({self.body.name} ({self.dataset}) under {', '.join(self.perturbers)}, "
                f"axis {self.axis}, {e.count} epoch{'s' if e.count != 1 else ''} {span}, {model}{extras})")
