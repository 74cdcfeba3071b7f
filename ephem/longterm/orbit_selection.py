"""How a history's orbit model was chosen (issue 39): every model as the choice saw it, the rule and the reason.

:func:`ephem.longterm.history.spin_axis_history` chooses the orbit model of a history: named by ``orbit_model``; without a
tolerance, the default (:data:`DEFAULT_RULE`); with one, by :func:`ephem.theory.choice.choose`, the rule every
track's choice follows (the cheapest predicted among the models estimated within the tolerance, the estimates made in
order of predicted cost). A history's estimate is made by running it along the orbit (:class:`RunEstimate`); the
:class:`OrbitSelection` records each model's predicted cost, its estimate where it was run, whether that meets the
tolerance, and :func:`why_chosen` says why the chosen one won. :func:`ephem.answers.render.history` renders it.
Radians and CPU seconds.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..base.constants import MAS
from ..theory.choice import TIE
from ..theory.results import Estimate

#: how the orbit model is chosen without a tolerance, and when it is named (the answer's ``model.rule``)
DEFAULT_RULE = ("no tolerance given: the shipped N-body orbit where it covers the span (the more accurate, and priced "
                "least), else the cheapest available")
NAMED_RULE = "the orbit model named by orbit_model"


@dataclass(frozen=True)
class OrbitCandidate:
    """One orbit model as the choice saw it: why it is unavailable (None: available), its predicted cost (CPU
    seconds; None: unavailable), its estimate (radians, the largest over the epochs; None: not run for one) and
    whether that meets the tolerance (None: not estimated, or no tolerance given)."""

    name: str
    why_not: str | None
    cost_s: float | None
    estimate: float | None
    eligible: bool | None
    chosen: bool


@dataclass(frozen=True)
class OrbitSelection:
    """How the orbit model was chosen: the rule, why the chosen one won, every model examined."""

    rule: str
    reason: str
    candidates: tuple[OrbitCandidate, ...]


@dataclass(frozen=True)
class RunEstimate(Estimate):
    """A history's estimate as :func:`ephem.theory.choice.choose` reads it: ``total`` is the history's own measure,
    the largest over the epochs of the terms' sum (``terms`` holds each term's largest, which may fall at other
    epochs)."""

    largest: float = 0.0

    @property
    def total(self) -> float:
        return self.largest


def ms_text(seconds: float) -> str:
    """CPU seconds as the reason writes them (ms, three digits)."""
    return f"{1e3 * seconds:.3g} ms"


def why_chosen(candidates: tuple[OrbitCandidate, ...], tolerance: float) -> str:
    """Why the chosen orbit model won: the eligible ones cheapest first, then the others and why not."""
    eligible = sorted((k for k in candidates if k.eligible), key=lambda k: k.cost_s)
    won = next(k for k in candidates if k.chosen)
    text = f"cheapest predicted of {len(eligible)} eligible: " + ", ".join(
        f"{k.name} ({ms_text(k.cost_s)}, {k.estimate / MAS:.4g} mas)" for k in eligible)
    if won is not eligible[0]:
        text += (f"; {won.name} ties within {TIE:.0%} of {eligible[0].name}'s predicted cost and is estimated the "
                 "more accurate")
    beyond = [k for k in candidates if k.eligible is False]
    if beyond:
        text += f"; beyond the tolerance of {tolerance / MAS:.6g} mas: " + ", ".join(
            f"{k.name} ({ms_text(k.cost_s)}, {k.estimate / MAS:.4g} mas)" for k in beyond)
    dearer = [k for k in candidates if k.eligible is None and k.why_not is None]
    if dearer:
        text += "; dearer, not run for an estimate: " + ", ".join(f"{k.name} ({ms_text(k.cost_s)})" for k in dearer)
    unavailable = [k for k in candidates if k.why_not is not None]
    if unavailable:
        text += "; unavailable: " + ", ".join(f"{k.name} ({k.why_not})" for k in unavailable)
    return text
