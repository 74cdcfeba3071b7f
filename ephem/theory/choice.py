"""Every decision a tolerance makes: the candidate predicted cheapest among those whose estimate meets it.

Cheapest as predicted for this request (issue 39).

Every family lists its models and their variants (e-orders, the free wobble followed, the rotation-scale terms) with
an :class:`~ephem.theory.results.Estimate` each (:meth:`~ephem.theory.interface.SpinAxisTheory.estimate_plan`); a
model whose estimate is made by running it (the long-term model's history) stands in the plan as a :class:`Deferred`
estimate, made only when the choice reaches it. :func:`choose` prices every model first (its track's
:class:`~ephem.base.budget.Cost` for these epochs: cheap arithmetic on the request's parameters), then makes the
estimates in order of predicted CPU, cheapest first, and stops at the first within the tolerance: no dearer model's
estimate is made. Models predicted within :data:`TIE` of the first eligible one are a tie, won by the smaller
estimated error, so that a cost that differs in its last bits between two machines cannot change the answer's
accuracy for nothing. Where no model meets the tolerance every estimate is made, and the refusal names the best
(:func:`ephem.theory.interface.refuse`).

Every other decision a tolerance makes follows the same rule here (issue 43): the Sun's e-order of the rate and the
nutation terms (:meth:`ephem.sun.family.SunLadder.order_candidates`), the amplitude cut of the Earth's and the Moon's
nutation terms (:func:`ephem.earth.estimates.cut_candidates`, :func:`ephem.moon.family.cut_candidates`), a history's
orbit model (:func:`ephem.longterm.history.spin_axis_history`, through :func:`choose`). A family supplies its
:class:`Candidates` (what each is, its price, its bound: the physics); :func:`decide` makes the decision, the one rule
for all: :func:`choose` is :func:`decide` over a plan's estimates.
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Callable, Sequence

import numpy as np

from ..base.budget import Cost
from ..base.constants import MAS
from .results import Estimate

#: predicted costs within this fraction of the cheapest eligible one are a tie: the more accurate model wins
TIE = 0.01
#: estimates within this fraction of each other count as equal in a tie (then the cheaper wins): far above the last
#: bits a CPU's SIMD kernels move them by (~1e-15), far below any difference in accuracy worth a choice
SAME_ESTIMATE = 1e-9

RULE = (f"the model predicted cheapest for these epochs among those whose estimate meets the tolerance (costs within "
        f"{TIE:.0%} of each other: the smaller estimate); models are estimated in order of predicted cost and the "
        "dearer ones are not estimated")


@dataclass(frozen=True)
class Deferred:
    """A model of a plan whose estimate is made by running the model (``make``): made only when the choice reaches
    it, or when every estimate is asked for (:func:`resolve`)."""

    rung: str
    order: int | None
    make: Callable[[], Estimate]
    free_wobble: bool = False
    rotation_scale: str | None = None
    available: bool = True


@dataclass(frozen=True)
class Candidates:
    """A family's priced candidates for one decision, in its own order: what each is (``values``: an e-order, an
    amplitude cut...), its predicted price (``costs``: any one unit within a decision, the smaller the cheaper; None:
    the candidate cannot serve) and its bound (radians: an array, or a function of the index made only when the
    decision reaches it, in order of price; None: unavailable). ``tie``: prices within this fraction of the cheapest
    eligible one are a tie (0 where prices are counts, never equal but by the same count); ``what`` names the kind."""

    values: Sequence
    costs: Sequence[float | None] | np.ndarray
    bound: Callable[[int], float | None] | np.ndarray
    tie: float = TIE
    what: str = "model"


@dataclass(frozen=True)
class Decision:
    """What :func:`decide` found: the index chosen (``best``; None: no candidate meets the tolerance), the cheapest
    eligible one (``first``, the tie's), the bounds made (``bounds``: index -> radians, None unavailable; every one for
    an array of bounds) and the order of price the candidates were tried in (``order``)."""

    best: int | None
    first: int | None
    bounds: dict[int, float | None]
    order: tuple[int, ...]


def decide(candidates: Candidates, tolerance: float) -> Decision:
    """The candidate predicted cheapest among those whose bound is within ``tolerance`` (radians): bounds are made in
    order of price, cheapest first (the index breaking equal prices), up to the first within the tolerance and those
    tied with it (prices within ``candidates.tie`` of its); of a tie the smallest bound wins (bounds within
    :data:`SAME_ESTIMATE` of it counted equal), then the cheaper. No dearer candidate's bound is made."""
    costs, tie = candidates.costs, candidates.tie
    if isinstance(candidates.bound, np.ndarray):
        return _decide_arrays(np.asarray(costs, dtype=float), candidates.bound, tolerance, tie)
    return Decision(*_rank(costs, candidates.bound, tolerance, tie))


def _rank(costs, bound, tolerance: float, tie: float) -> tuple:
    """:func:`decide` on a list of prices and a function of the bounds: (best, first, bounds made, order). Apart from
    :class:`Decision` so that :func:`choose`, on every track with a tolerance, builds no record it does not need."""
    # by price, the index breaking equal prices: a stable sort of the indices in increasing order by price alone is
    # the order of the keys (price, index), at a C-level key (prices are sums of positive parts, never NaN)
    order = sorted(range(len(costs)), key=costs.__getitem__) if None not in costs else \
        sorted([i for i, c in enumerate(costs) if c is not None], key=costs.__getitem__)
    made: dict[int, float | None] = {}
    first, tied = None, []
    for i in order:
        if first is not None and costs[i] > costs[first] * (1.0 + tie):
            break
        b = made[i] = bound(i)
        if b is None or b > tolerance:
            continue
        if first is None:
            first = i
        tied.append(i)
    if not tied:
        return None, None, made, tuple(order)
    if len(tied) == 1:
        return first, first, made, tuple(order)
    least = min(made[i] for i in tied)
    return next(i for i in tied if made[i] <= least * (1.0 + SAME_ESTIMATE)), first, made, tuple(order)


def _decide_arrays(costs: np.ndarray, bounds: np.ndarray, tolerance: float, tie: float) -> Decision:
    """:func:`decide` over arrays of prices (NaN: unavailable) and bounds, at once (the Earth's 17 000 cuts)."""
    order = np.lexsort((np.arange(costs.size), costs))
    order = order[~np.isnan(costs[order])]
    eligible = ~np.isnan(costs) & (bounds <= tolerance)
    made = dict(enumerate(bounds.tolist()))
    if not eligible.any():
        return Decision(None, None, made, tuple(order.tolist()))
    ranked = order[eligible[order]]
    first = int(ranked[0])
    tied = ranked[costs[ranked] <= costs[first] * (1.0 + tie)]
    least = float(bounds[tied].min())
    best = int(tied[np.argmax(bounds[tied] <= least * (1.0 + SAME_ESTIMATE))])
    return Decision(best, first, made, tuple(order.tolist()))


def cheapest(candidates: Candidates, tolerance: float, default=None):
    """The value :func:`decide` chooses, or ``default`` where no candidate meets ``tolerance`` (radians)."""
    best = decide(candidates, tolerance).best
    return default if best is None else candidates.values[best]


def resolve(plan: list) -> list[Estimate]:
    """Every estimate of a plan, the deferred ones made."""
    return [p.make() if isinstance(p, Deferred) else p for p in plan]


@dataclass(frozen=True)
class Candidate:
    """One model of the choice: its estimate (None where it is made by running the model and the choice stopped
    before it, dearer than the chosen one) and its predicted cost (None: the model cannot serve these epochs)."""

    rung: str
    order: int | None
    free_wobble: bool
    rotation_scale: str | None
    estimate: Estimate | None
    cost: Cost | None

    @property
    def eligible(self) -> bool | None:
        """Whether its estimate meets the tolerance (None: not estimated)."""
        return None if self.estimate is None else self._eligible

    _eligible: bool = False


@dataclass(frozen=True)
class Choice:
    """The model a tolerance chose (``chosen``), every model as the choice saw it, in the family's order
    (``candidates``), and why the chosen one won (``reason``)."""

    chosen: Estimate
    candidates: tuple[Candidate, ...]
    reason: str


#: Candidate's fields in their order, read from the class (so :func:`_candidate` follows a field added or moved); a
#: ``__post_init__`` or slots would not be honoured there, so they are refused as the module loads
_CANDIDATE_FIELDS = tuple(f.name for f in fields(Candidate))
if hasattr(Candidate, "__post_init__") or hasattr(Candidate, "__slots__"):
    raise TypeError("_candidate sets Candidate's fields directly: give it the __post_init__'s work, or build by the "
                    "constructor")


def _candidate(p, estimate: Estimate | None, cost: Cost | None, eligible: bool) -> Candidate:
    """``Candidate(p.rung, p.order, p.free_wobble, p.rotation_scale, estimate, cost, eligible)``, its fields set in one
    go: a choice makes one per model of the plan (~40 a track with a tolerance), and a frozen dataclass's
    ``__init__`` sets each field by ``object.__setattr__``; the same object (equal, the same repr and hash)."""
    c = object.__new__(Candidate)
    c.__dict__.update(zip(_CANDIDATE_FIELDS, (p.rung, p.order, p.free_wobble, p.rotation_scale, estimate, cost,
                                              eligible)))
    return c


def _label(c) -> str:
    what = c.rung + ("" if c.order is None else f" e^{c.order}")
    if c.free_wobble:
        what += " with the free wobble"
    if c.rotation_scale is not None:
        what += f" with the rotation-scale terms ({c.rotation_scale})"
    return what


def choose(plan: list, price: Callable[[Estimate | Deferred], Cost] | list, tolerance: float,
           refuse: Callable[[list[Estimate]], None]) -> Choice:
    """The model of ``plan`` (estimates and :class:`Deferred` ones, in the family's order) predicted cheapest by
    ``price`` (a function of a plan's item, or the costs already made: a list in the plan's order, None where a
    model is unavailable) among those whose estimate is within ``tolerance`` (radians); ``refuse`` (given every
    estimate, made) raises when none is."""
    costs = list(price) if isinstance(price, list) else [price(p) if p.available else None for p in plan]
    made: dict[int, Estimate] = {}

    def bound(i: int) -> float | None:
        est = made[i] = plan[i].make() if isinstance(plan[i], Deferred) else plan[i]
        return est.total if est.available else None

    # the most accurate of a tie, estimates within SAME_ESTIMATE of the smallest counted equal (e-orders past
    # convergence differ in their last bits, which a CPU's SIMD kernels change): then the cheaper, as ordered
    best, first, _, order = _rank([None if c is None else c.cpu_s for c in costs], bound, tolerance, TIE)
    if best is None:      # every estimate, those made above not made again (a deferred one is a run of its model)
        refuse([e for e in (made[i] if i in made else resolve([p])[0] for i, p in enumerate(plan)) if e.available])
        raise AssertionError("refuse() must raise")      # pragma: no cover
    known = [made.get(i, None if isinstance(p, Deferred) else p) for i, p in enumerate(plan)]
    candidates = tuple(map(_candidate, plan, known, costs, [k is not None and k.available and k.total <= tolerance
                                                            for k in known]))
    won = made[best]
    tried = [i for i in order if i in made]
    cheaper = [i for i in tried[:tried.index(first)] if made[i].available]
    reason = (f"{_label(won)} is the model predicted cheapest ({1e3 * costs[best].cpu_s:.3g} ms) whose estimate "
              f"({won.total / MAS:.4g} mas) meets the tolerance of {tolerance / MAS:.6g} mas")
    if best != first:
        reason = (f"{_label(won)} ties in predicted cost ({1e3 * costs[best].cpu_s:.3g} ms) with "
                  f"{_label(made[first])} ({1e3 * costs[first].cpu_s:.3g} ms) and is estimated the more accurate "
                  f"({won.total / MAS:.4g} mas): it meets the tolerance of {tolerance / MAS:.6g} mas")
    if cheaper:
        reason += "; cheaper, and estimated beyond it: " + ", ".join(
            f"{_label(made[i])} ({made[i].total / MAS:.4g} mas)" for i in cheaper)
    dearer = [plan[i] for i in order if known[i] is None]
    if dearer:
        reason += "; dearer, and not run for an estimate: " + ", ".join(_label(p) for p in dearer)
    return Choice(won, candidates, reason)
