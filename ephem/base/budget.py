"""A request's budget: predicted costs charged before the work, and a deadline while it runs.

The service opens one :func:`budget` per request. Each entry point of :mod:`ephem.answers.requests` states
its cost (a :class:`Cost`, predicted by :mod:`ephem.theory.cost`) and calls :func:`charge` before doing the work: a cost that would
take the request over its CPU or memory budget raises :class:`OverBudgetError` naming the
parameter that drives it and the estimate, before anything is computed. The long loops
(integrations, harmonic sums, the Hansen FFT) call :func:`checkpoint`, the backstop for an
estimate that was wrong: past the deadline they raise :class:`DeadlineExceededError`.

A budget may carry an admission hook, called at each checkpoint: the service uses it to let only
a few large requests run at once (a request's own budget does not stop many of them together
from starving the rest); the hook refuses with :class:`BusyError`. It is called at the work's
checkpoints rather than at the charges so that a request charged in several parts is admitted
on its total, and one over its budget is refused as such (422), whether or not the service is busy.

Outside a budget (the library, the CLI) charging and the deadline are no-ops: a scientist's own
script may run for an hour.
"""
from __future__ import annotations

import time
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable

from .errors import EphemError


@dataclass(frozen=True)
class Part:
    """One piece of work: ``what`` it is, the request ``parameter`` that drives it, its cost."""

    parameter: str
    what: str
    cpu_s: float
    memory_mb: float


@dataclass(frozen=True)
class Cost:
    """The predicted cost of a request: the sum of its parts (CPU) and their largest (memory)."""

    parts: tuple[Part, ...] = ()

    @cached_property            # the parts never change: summed once (a choice by cost reads it some 40 times)
    def cpu_s(self) -> float:
        return float(sum(p.cpu_s for p in self.parts))

    @cached_property
    def memory_mb(self) -> float:
        # parts run one after another and free their work arrays; the largest sets the peak
        return float(max((p.memory_mb for p in self.parts), default=0.0))

    def __add__(self, other: "Cost") -> "Cost":
        return Cost(self.parts + other.parts)

    def largest(self, by: str = "cpu_s") -> Part | None:
        return max(self.parts, key=lambda p: getattr(p, by), default=None)

    def describe(self) -> str:
        cpu, mem = self.largest("cpu_s"), self.largest("memory_mb")
        text = f"{self.cpu_s:.3g} s of one core and {self.memory_mb:.3g} MB"
        if cpu is not None:
            text += f" (largest: {cpu.what}, set by {cpu.parameter}"
            if mem is not None and mem is not cpu and mem.memory_mb > 0.5 * self.memory_mb:
                text += f"; most memory: {mem.what}, set by {mem.parameter}"
            text += ")"
        return text

    def as_dict(self) -> dict:
        return {"cpu_s": self.cpu_s, "memory_mb": self.memory_mb,
                "parts": [{"parameter": p.parameter, "what": p.what, "cpu_s": p.cpu_s, "memory_mb": p.memory_mb}
                          for p in self.parts]}


#: a cost of nothing (a part charged elsewhere)
FREE = Cost()


class OverBudgetError(EphemError):
    """The predicted cost of a request exceeds its budget; raised before any work.

    ``cost`` is the part being charged when the budget broke, ``spent_cpu_s`` what the request's earlier
    parts had charged already; the request's estimate is both together (``total``, ``estimated_cpu_s``): the
    number the message prints and the service's problem reports, so that the two agree and the estimate
    refused is the one that exceeds the budget."""

    def __init__(self, cost: Cost, limit: "Budget", spent_cpu_s: float, body: str | None = None,
                 prefix: str = ""):
        self.cost = cost
        self.limit = limit
        self.spent_cpu_s = spent_cpu_s
        self.body = body
        self.cpu_s_budget = limit.cpu_s
        self.memory_mb_budget = limit.memory_mb
        # the earlier parts as one part of the whole: its parts then sum to the estimate reported
        earlier = (Part("request", "the request's earlier parts, already charged", spent_cpu_s, 0.0),) \
            if spent_cpu_s > 0 else ()
        self.total = Cost(earlier + cost.parts)
        over_memory = cost.memory_mb > limit.memory_mb
        part = cost.largest("memory_mb" if over_memory else "cpu_s")     # the refused part names the parameter
        self.field = prefix + (part.parameter if part is not None else "request")
        what = (f"{cost.memory_mb:.3g} MB of memory, over the budget of {limit.memory_mb:.3g} MB" if over_memory
                else f"{self.estimated_cpu_s:.3g} s of one core, over the budget of {limit.cpu_s:.3g} s")
        estimate = cost.describe()
        if spent_cpu_s > 0:
            estimate = f"{spent_cpu_s:.3g} s already charged for its earlier parts, then {estimate}"
        self.reason = (f"this request is estimated to need {what} (estimate: {estimate}); change {self.field} to "
                       "ask for less")
        where = f"{body}: " if body else ""
        super().__init__(f"{where}{self.field}: {self.reason}")

    @property
    def estimated_cpu_s(self) -> float:
        """The whole request's estimated CPU time, s: what was charged already and the part refused."""
        return self.total.cpu_s

    @property
    def estimated_memory_mb(self) -> float:
        """The request's estimated peak memory, MB (parts run one after another: the largest)."""
        return self.total.memory_mb

    def within(self, prefix: str) -> "OverBudgetError":
        """The same refusal with the parameter named by its full path (``track.step_days``)."""
        return OverBudgetError(self.cost, self.limit, self.spent_cpu_s, self.body, prefix)


class DeadlineExceededError(EphemError):
    """A request ran past its deadline (its cost was underestimated); raised from inside the work."""

    def __init__(self, deadline_s: float, predicted_cpu_s: float):
        self.deadline_s = deadline_s
        self.predicted_cpu_s = predicted_cpu_s
        super().__init__(f"the request ran past its deadline of {deadline_s:.3g} s (its cost was estimated at "
                         f"{predicted_cpu_s:.3g} s) and was stopped; ask for fewer epochs or a shorter span")


class BusyError(EphemError):
    """The request is within its budget, but as many large requests as allowed are running already;
    raised before any work. ``retry_after_s``: when to try again."""

    def __init__(self, cpu_s: float, threshold_cpu_s: float, slots: int, retry_after_s: int):
        self.cpu_s = cpu_s
        self.threshold_cpu_s = threshold_cpu_s
        self.slots = slots
        self.retry_after_s = retry_after_s
        super().__init__(f"this request is estimated to need {cpu_s:.3g} s of one core, more than "
                         f"{threshold_cpu_s:.3g} s, and the {slots} such request{'s' if slots != 1 else ''} "
                         f"allowed at once {'are' if slots != 1 else 'is'} running; retry in {retry_after_s} s, "
                         "or ask for less")


@dataclass
class Budget:
    """Limits of one request: predicted CPU seconds (summed over its parts), memory (per part) and
    a wall-clock deadline (None: no deadline)."""

    cpu_s: float
    memory_mb: float
    deadline_s: float | None = None
    spent_cpu_s: float = 0.0
    #: the largest memory of the parts charged so far, MB: the request's predicted peak (its parts run one after
    #: another), which the service's admission counts against the memory of the worker's other requests
    peak_memory_mb: float = 0.0
    started: float = field(default_factory=time.monotonic)
    prepaid: int = 0
    #: called with the budget at each :func:`checkpoint` (may raise :class:`BusyError`)
    admit: Callable[["Budget"], None] | None = None

    @property
    def deadline_at(self) -> float | None:
        return None if self.deadline_s is None else self.started + self.deadline_s


_current: ContextVar[Budget | None] = ContextVar("ephem_budget", default=None)


@contextmanager
def budget(cpu_s: float, memory_mb: float, deadline_s: float | None = None,
           admit: Callable[[Budget], None] | None = None):
    """Run the block under a budget (the service: one per request)."""
    token = _current.set(Budget(cpu_s, memory_mb, deadline_s, admit=admit))
    try:
        yield _current.get()
    finally:
        _current.reset(token)


def current() -> Budget | None:
    return _current.get()


def charge(cost: Cost, body: str | None = None) -> None:
    """Count ``cost`` against the current budget, or raise :class:`OverBudgetError` before the work."""
    b = _current.get()
    if b is None or b.prepaid:
        return
    if b.spent_cpu_s + cost.cpu_s > b.cpu_s or cost.memory_mb > b.memory_mb:
        raise OverBudgetError(cost, b, b.spent_cpu_s, body)
    b.spent_cpu_s += cost.cpu_s
    b.peak_memory_mb = max(b.peak_memory_mb, cost.memory_mb)


@contextmanager
def prepaid():
    """Inside the block charges are not counted again: an answer made of several whose total was charged
    at once (the POST's precession, nutation and track)."""
    b = _current.get()
    if b is not None:
        b.prepaid += 1
    try:
        yield
    finally:
        if b is not None:
            b.prepaid -= 1


def checkpoint() -> None:
    """A point in the work (cheap: call it in loops, and before a large step): the request is admitted
    (the budget's hook, which may raise :class:`BusyError` the first time), and past its deadline
    :class:`DeadlineExceededError` stops it."""
    b = _current.get()
    if b is None:
        return
    if b.admit is not None:
        b.admit(b)
    if b.deadline_s is None:
        return
    if time.monotonic() > b.started + b.deadline_s:
        raise DeadlineExceededError(b.deadline_s, b.spent_cpu_s)
