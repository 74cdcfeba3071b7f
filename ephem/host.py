"""The hosts' interface: what a program that serves the library's answers sets around them (budgets, caches, warm-up).

A host is a program that answers many requests in one long-lived process, as the HTTP service (``service/``) does:
it bounds each request's work, sizes the process's caches and builds the shared ones before the first request. A
scientist's script or notebook needs none of it (outside a budget charging is a no-op, and the caches fill on first
use), so these names live here rather than in :mod:`ephem.api`, the public face a user reads; the errors a budget
raises are in both, since a user may meet them.

The budget (:mod:`ephem.base.budget`):

- :func:`budget` ``(cpu_s, memory_mb, deadline_s=None, admit=None)``: a context manager opening a request's budget
  (CPU seconds, MB, an optional wall-clock deadline in seconds and an admission hook). Every answer of
  :mod:`ephem.api` charges its predicted cost (:mod:`ephem.theory.cost`) before the work; one over the budget raises
  :class:`OverBudgetError` naming the parameter that drives it, a long loop past the deadline
  :class:`DeadlineExceededError`, and a hook that refuses :class:`BusyError`.
- :class:`Budget`: the budget's record (its limits, the CPU charged so far); :func:`current_budget` the one open in
  this context (None: none).
- :func:`charge` ``(cost, body=None)``: charge a host's own work (a :class:`~ephem.base.budget.Cost`) to the budget.
- :func:`prepaid`: a context manager for work already charged with the answer it writes out (an answer's ECSV
  table, charged with the track).

The caches:

- :mod:`memo`: the process's per-body caches (models, theories, the ladder's tables, uncertainties), bounded in bytes
  together (``memo.set_budget_mb(megabytes)``, ``memo.budget_mb()``; one pool per process).
- :func:`warm_up` ``(*, dataset)``: build the caches every process shares (the Earth's lunisolar series, the Moon's
  libration series, the rational Hansen series, the orbit's spline): about 2-4 s once, at a host's start-up, so that
  no first request pays for them.

Importing this module loads nothing: each name loads its module on first use (PEP 562), as :mod:`ephem.api`.
"""
from __future__ import annotations

from .base.lazy import lazy_names

#: public name -> (module relative to ``ephem``, attribute): loaded on first access
_NAMES = {
    "Budget": (".base.budget", "Budget"),
    "budget": (".base.budget", "budget"),
    "charge": (".base.budget", "charge"),
    "prepaid": (".base.budget", "prepaid"),
    "current_budget": (".base.budget", "current"),
    "BusyError": (".base.budget", "BusyError"),
    "DeadlineExceededError": (".base.budget", "DeadlineExceededError"),
    "OverBudgetError": (".base.budget", "OverBudgetError"),
    "memo": (".base", "memo"),
    "warm_up": (".answers.requests", "warm_up"),
}

__all__ = [
    # the budget: set around each request, charged by every answer before its work
    "Budget", "budget", "charge", "prepaid", "current_budget",
    # what it raises (also in ephem.api: a user may meet them)
    "OverBudgetError", "DeadlineExceededError", "BusyError",
    # the caches: the per-body pool's size, and the shared ones built at start-up
    "memo", "warm_up",
]


__getattr__, __dir__ = lazy_names("ephem.host", globals(), _NAMES, __all__)
