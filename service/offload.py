"""Where a route's work runs: on the event loop when it is predicted cheap, in the worker's thread pool otherwise.

A plain ``def`` route costs every request a hop to the thread pool and back: ~0.1 ms of a worker's CPU and more of
its wall time (``benchmarks/RESULTS_overhead.md``), more than the physics of a small track. The library charges a
request's predicted cost to its budget before the work it stands for (:mod:`ephem.base.budget`), so the route can
try the work on the event loop under a budget of ``inline_cpu_ms`` (:class:`service.settings.Settings`): a request
predicted within it is answered there, without the hop; the first charge over it stops the request before that
work, and the request is made again in the thread pool under its own budget. The loop is thus held about
``inline_cpu_ms`` at most by one request (the predictions hold to 0.5-2x, ``benchmarks/RESULTS_calibration.md``),
and what a refused try did before its refusal was charged within that limit (its memos serve the second try).
The budget's deadline and admission (``service/guards.py``) apply to both tries.
"""
from __future__ import annotations

import time
from typing import Callable, TypeVar

from starlette.concurrency import run_in_threadpool

from ephem.host import OverBudgetError, budget, current_budget

T = TypeVar("T")


async def compute(inline_cpu_ms: float, fn: Callable[..., T], /, *args, **kwargs) -> T:
    """``fn(*args, **kwargs)``, on the event loop if its charges stay within ``inline_cpu_ms`` of CPU, else in the
    thread pool (outside a request's budget, or with ``inline_cpu_ms`` 0: always in the thread pool)."""
    outer = current_budget()
    if outer is None or inline_cpu_ms <= 0:
        return await run_in_threadpool(fn, *args, **kwargs)
    remaining = None if outer.deadline_at is None else max(outer.deadline_at - time.monotonic(), 0.0)
    try:
        with budget(min(1e-3 * inline_cpu_ms, outer.cpu_s - outer.spent_cpu_s), outer.memory_mb, remaining,
                    admit=outer.admit) as inner:
            result = fn(*args, **kwargs)
        # the request's peak is the outer budget's: the worker hands a large request's freed memory back by it
        outer.peak_memory_mb = max(outer.peak_memory_mb, inner.peak_memory_mb)
        return result
    except OverBudgetError:
        # over the loop's share (or the request's own budget, which the second try then refuses with its estimate)
        return await run_in_threadpool(fn, *args, **kwargs)
