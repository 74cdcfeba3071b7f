"""Bounded work per request: the budget every request runs under, and what answers when it is broken.

- Before the work: each request runs inside :func:`ephem.base.budget.budget` with the service's limits, so
  every entry point of :mod:`ephem.api` charges its predicted cost first and a request over budget
  gets a 422 naming the parameter and the estimate (``over-budget``).
- During the work: the deadline (:func:`ephem.base.budget.checkpoint` in the long loops) stops a request
  whose estimate was wrong with a 503 (``deadline``); a ``MemoryError`` under the worker's memory
  ceiling (``service/gunicorn_conf.py``) is a 503 (``memory``) too, and the worker recycles itself.
- Beside it, admission: a request whose estimate exceeds ``heavy_request_cpu_s`` must hold one of
  ``heavy_slots`` slots shared by all the workers (a lock file each) while it runs; when all are taken
  it gets a 503 (``busy``) with ``Retry-After`` at once, at the first checkpoint of its work (after
  every part was charged, before any large step). A per-request budget alone
  lets a few clients looping on requests just under it take every core from everyone else.
- And memory admission: the predicted peak memory of the requests running in one worker, summed, stays within
  ``worker_request_memory_mb`` (:class:`MemoryAllowance`): a request's own budget bounds it alone, but up to four
  requests at once, each within it, took a worker from its ~320 MB to 427-554 MB (benchmarks/RESULTS_memory_soak.md).
  A request is counted at its first checkpoint with what its charges predict (``Budget.peak_memory_mb``), and for more
  if a later part predicts more; one that does not fit waits up to ``memory_wait_s`` for others to finish, then gets
  a 503 (``busy``, naming the memory) with ``Retry-After``. One predicted over the whole allowance alone never fits:
  the per-request budget (``max_request_memory_mb``, at most the allowance: :meth:`Settings.check`) refuses it first,
  422 ``over-budget`` with its estimate, before any work. A request whose work has no checkpoint (no long loop, no
  large step: a precession, a nutation table) is not counted; it is predicted at a few MB.
- Beyond that, the watchdog: a request still running ``hard_kill_after_s`` past its deadline (stuck
  in compiled code that never reaches a check) ends the worker process, which the supervisor
  (gunicorn) replaces. It is armed only under a supervisor (``EPHEM_SUPERVISED``), never in a bare
  uvicorn or the tests' client, where it would take the service down.
- And the worker's memory, bounded by ``worker_rss_mb`` (``EPHEM_WORKER_RSS_MB``, 400 MB), which the allowance for
  the requests in flight and the per-body caches follow (:func:`service.settings.derived_memory`): the worker's own
  memory, its caches, its requests' allowance and a measured slack sum within it, and a request charged above
  :data:`TRIM_AFTER_REQUEST_MB` returns its freed memory to the system as it ends. What a worker keeps after its
  requests is its code, the per-body caches (``EPHEM_MODEL_CACHE_MB``, bounded in bytes) and what the C allocator
  holds freed but not returned to the system: glibc gives each thread of the worker's pool an arena of its own (up
  to 8 per core) and keeps freed blocks in each, so a worker grew to 500-800 MB over 2,000-8,000 varied requests
  while its caches held 64 MB (benchmarks/RESULTS_memory_soak.md). Under the supervisor the worker keeps two
  arenas and maps large blocks on their own (:data:`ALLOCATOR`), the watchdog hands the freed memory back
  (``malloc_trim``, ~1 ms) about once a second while requests come, and a worker still above what it may keep
  (``Settings.worker_keep_mb``: the bound less the allowance and the slack) when it goes idle is recycled
  gracefully (SIGTERM: its requests finish, the supervisor starts a fresh one), one worker of the service at a time.
"""
from __future__ import annotations

import asyncio
import ctypes
import ctypes.util
import fcntl
import gc
import logging
import math
import os
import resource
import signal
import tempfile
import threading
import time

from fastapi import FastAPI, Request

from ephem.api import EphemError
from ephem.host import Budget, BusyError, DeadlineExceededError, OverBudgetError, budget

from .problems import problem
from .settings import Settings

log = logging.getLogger("ephem.service")
#: each request's predicted peak memory as it ends, at DEBUG (off by default): the charged peak
#: (``Budget.peak_memory_mb``) and what the worker's allowance counted of it, MB, in the record's ``peak_memory_mb`` and
#: ``admitted_memory_mb``; benchmarks/bench_request_memory.py sets it to DEBUG to set them beside the measured rise
memory_log = logging.getLogger("ephem.service.memory")


#: a request whose charged peak memory (``Budget.peak_memory_mb``) is above this, MB, hands the allocator's freed memory
#: back to the system as it ends (``malloc_trim``), before its share of the worker's allowance is given back; the
#: smaller ones leave it to the watchdog's trim, once a second. The arithmetic: the trim costs 0.3-1.6 ms in a worker
#: of ~300 MB; a request predicted at 4 MB touched at least ~2 MB of fresh pages (the predictions are upper values,
#: about twice the measured), ~0.8 ms at the ~0.4 ms per MB measured here, and the soak's requests above it (tracks
#: with a tolerance, figures) take 28-500 ms at their median, so the trim adds ~0.2-4 % to those alone. What a
#: request below it frees is under 4 MB and reused by the next request before the once-a-second trim: with up to 4
#: requests at once, under 16 MB of the slack service.settings.RSS_SLACK_MB (32 MB) stays unreturned
TRIM_AFTER_REQUEST_MB = 4.0


class RequestBudget:
    """ASGI middleware: every HTTP request runs under the service's budget (a context variable, which
    the thread pool running the routes inherits), and is known to the watchdog while it runs. A request whose charged
    peak memory was above ``trim_after_mb`` returns the allocator's freed memory to the system as it ends, before its
    share of the worker's allowance is given back (the next request admitted finds it returned)."""

    def __init__(self, app, settings: Settings, watchdog: "Watchdog | None" = None,
                 heavy: "HeavySlots | None" = None, memory: "MemoryAllowance | None" = None,
                 trim_after_mb: float | None = TRIM_AFTER_REQUEST_MB):
        self.app = app
        self.settings = settings
        self.watchdog = watchdog
        self.heavy = heavy
        self.memory = memory
        self.trim_after_mb = trim_after_mb

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        s = self.settings
        token = self.watchdog.enter(scope) if self.watchdog is not None else None
        admission = _Admission(self.heavy, self.memory) if self.heavy is not None or self.memory is not None else None
        b = None
        try:
            with budget(s.max_request_cpu_s, s.max_request_memory_mb, s.request_deadline_s, admit=admission) as b:
                await self.app(scope, receive, send)     # a streamed answer holds its slot until sent
        finally:
            if b is not None and memory_log.isEnabledFor(logging.DEBUG):     # off unless asked: a cached level check
                admitted = admission.memory_mb if admission is not None and admission.memory is not None else 0.0
                memory_log.debug("%s %s: charged peak %.3f MB, admitted %.3f MB", scope.get("method"),
                                 scope.get("path"), b.peak_memory_mb, admitted,
                                 extra={"peak_memory_mb": b.peak_memory_mb, "admitted_memory_mb": admitted})
            if b is not None and self.trim_after_mb is not None and b.peak_memory_mb > self.trim_after_mb:
                release_free_memory()   # ~1 ms (ctypes lets the interpreter's lock go meanwhile): the work is freed
            if admission is not None:
                admission.release()
            if token is not None:
                self.watchdog.leave(token)


class HeavySlots:
    """At most ``slots`` requests estimated above ``threshold_cpu_s`` run at once, across every worker of
    the service: each running one holds an exclusive ``flock`` on one of ``slots`` files in ``lock_dir``
    (the kernel releases it when the holder ends, even by ``kill -9``). Waiting would hold a thread of the
    worker's pool per waiting client, so a request that finds every slot taken is refused at once."""

    def __init__(self, threshold_cpu_s: float, slots: int, lock_dir: str | None = None):
        self.threshold_cpu_s = threshold_cpu_s
        self.slots = slots
        self.lock_dir = lock_dir or tempfile.mkdtemp(prefix="ephem-heavy-")
        self.paths = [os.path.join(self.lock_dir, f"heavy-{i}.lock") for i in range(slots)]

    def admission(self) -> "_Admission":
        return _Admission(self)


class MemoryBusyError(BusyError):
    """The request is within its own memory budget, but the requests running in this worker already hold so much of
    its allowance that it does not fit, and none finished within the wait; raised before its work."""

    def __init__(self, memory_mb: float, limit_mb: float, held_mb: float, waited_s: float, retry_after_s: int = 1):
        self.memory_mb = memory_mb
        self.limit_mb = limit_mb
        self.held_mb = held_mb
        self.retry_after_s = retry_after_s
        EphemError.__init__(self, f"this request is estimated to need {memory_mb:.3g} MB of memory at its peak, and "
                            f"the requests running in this worker hold {held_mb:.3g} MB of the {limit_mb:.3g} MB they "
                            f"may hold together (EPHEM_WORKER_REQUEST_MEMORY_MB); none finished within {waited_s:g} s: "
                            f"retry in {retry_after_s} s, or ask for less")


class MemoryAllowance:
    """The predicted peak memory of the requests running in this worker, summed, MB, stays within ``limit_mb``
    (one per worker process: memory is the process's own). :meth:`take` counts more of it for a request, waiting
    up to ``wait_s`` for others to give theirs back; :meth:`give_back` returns it when the request ends."""

    def __init__(self, limit_mb: float, wait_s: float):
        self.limit_mb = limit_mb
        self.wait_s = wait_s
        self.held_mb = 0.0
        self.waiting = 0                # requests waiting for their share now
        self._cond = threading.Condition()

    def take(self, mb: float, wait: bool = True) -> bool:
        """Count ``mb`` more for a request if the sum stays within the limit, waiting up to ``wait_s`` (``wait``
        False: not at all) for others to give theirs back; whether it was counted."""
        end = time.monotonic() + (self.wait_s if wait else 0.0)
        with self._cond:
            while self.held_mb + mb > self.limit_mb * (1.0 + 1e-12):
                left = end - time.monotonic()
                if left <= 0.0:
                    return False
                self.waiting += 1
                try:
                    self._cond.wait(left)
                finally:
                    self.waiting -= 1
            self.held_mb += mb
            return True

    def give_back(self, mb: float) -> None:
        with self._cond:
            self.held_mb = max(0.0, self.held_mb - mb)
            self._cond.notify_all()


def _on_event_loop() -> bool:
    """Whether this thread runs an event loop (an inline request, service/offload.py), which must never wait."""
    try:
        asyncio.get_running_loop()
    except RuntimeError:
        return False
    return True


class _Admission:
    """One request's admission, called at the work's checkpoints: its predicted peak memory is counted against the
    worker's allowance (more of it if a later part predicts more; it may wait there, never on the event loop), then
    a slot is taken the first time the request's charged total is over the heavy threshold (every part is charged
    before the first checkpoint). Memory first: a request waiting for memory holds no slot another worker wants."""

    def __init__(self, slots: HeavySlots | None, memory: MemoryAllowance | None = None):
        self.slots = slots
        self.memory = memory
        self.memory_mb = 0.0            # what this request holds of the worker's allowance
        self.fd: int | None = None

    def __call__(self, b: Budget) -> None:
        if self.memory is not None and b.peak_memory_mb > self.memory_mb:
            wait = not _on_event_loop()
            if not self.memory.take(b.peak_memory_mb - self.memory_mb, wait):
                raise MemoryBusyError(b.peak_memory_mb, self.memory.limit_mb, self.memory.held_mb,
                                      self.memory.wait_s if wait else 0.0)
            self.memory_mb = b.peak_memory_mb
        if self.slots is None or self.fd is not None or b.spent_cpu_s <= self.slots.threshold_cpu_s:
            return
        for path in self.slots.paths:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                continue
            self.fd = fd
            return
        # the slot frees when a request like this one ends: about its own estimate from now
        raise BusyError(b.spent_cpu_s, self.slots.threshold_cpu_s, self.slots.slots,
                        retry_after_s=max(1, math.ceil(b.spent_cpu_s)))

    def release(self) -> None:
        if self.fd is not None:
            os.close(self.fd)      # closing the descriptor drops its lock
            self.fd = None
        if self.memory is not None and self.memory_mb > 0.0:
            self.memory.give_back(self.memory_mb)
            self.memory_mb = 0.0


#: the least time between two checks of an idle worker's memory over its limit, s
MEMORY_CHECK_S = 5.0


class Watchdog:
    """Ends this worker process when a request overstays its deadline by ``grace_s`` (the supervisor starts
    another); hands the allocator's freed memory back to the system every ``trim_interval_s`` while requests
    finish; and asks for a graceful restart when the worker's resident memory stays above ``rss_limit_mb`` after
    its requests, freed memory returned (:meth:`check_memory`)."""

    def __init__(self, deadline_s: float, grace_s: float, rss_limit_mb: float | None, interval_s: float = 0.5,
                 trim_interval_s: float = 1.0, recycle: "RecycleTurns | None" = None):
        self.deadline_s = deadline_s
        self.grace_s = grace_s
        self.rss_limit_mb = rss_limit_mb
        self.interval_s = interval_s
        self.trim_interval_s = trim_interval_s
        self.recycle = recycle
        self.recycling = False          # the restart was asked for: not again
        self._running: dict[int, tuple[float, str]] = {}
        self._lock = threading.Lock()
        self._next = 0
        self._finished = 0              # requests finished, and their count at the last trim
        self._trimmed = 0
        self._checked = -math.inf       # when the memory was last checked (time.monotonic), and whether one is due
        self._check_due = False
        self._check_lock = threading.Lock()
        self._last_trim = time.monotonic()
        self._thread = threading.Thread(target=self._watch, name="ephem-watchdog", daemon=True)
        self._thread.start()

    def enter(self, scope) -> int:
        with self._lock:
            self._next += 1
            self._running[self._next] = (time.monotonic(), f"{scope.get('method')} {scope.get('path')}")
            return self._next

    def leave(self, token: int) -> None:
        with self._lock:
            self._running.pop(token, None)
            self._finished += 1
            idle = not self._running
        # the peak first (one cheap system call): below the limit, the resident memory is too, and the worker's
        # every request need not read /proc (13 us a request, 1-2 % of a /healthz under gunicorn); then at most one
        # check every MEMORY_CHECK_S (its full collection holds the interpreter ~0.1 s): one asked for sooner is
        # left to the watchdog's thread, which makes it when the time has come if the worker is still idle
        if idle and self.rss_limit_mb is not None and peak_resident_mb() > self.rss_limit_mb:
            self._check_due = True
            self._check_if_time(time.monotonic())

    def _check_if_time(self, now: float) -> None:
        if not (self._check_due and now - self._checked >= MEMORY_CHECK_S) or not self._check_lock.acquire(False):
            return                              # not yet, or the other thread (loop or watchdog) is checking
        try:
            self._checked, self._check_due = now, False
            if self.check_memory() == "wait":
                self._check_due = True          # another worker is being replaced: asked again later
        finally:
            self._check_lock.release()

    def check_memory(self) -> str:
        """The decision on an idle worker's memory: ``"ok"`` (resident within the limit), ``"trimmed"`` (within it
        once the allocator's freed memory, and then the garbage cycles, were returned), ``"recycle"`` (still above:
        SIGTERM to this worker, which finishes its requests and exits; the supervisor starts a fresh one), or
        ``"wait"`` (above, but another worker of the service is being replaced: asked again later)."""
        if self.recycling or self.rss_limit_mb is None or resident_mb() <= self.rss_limit_mb:
            return "ok"
        release_free_memory()
        if resident_mb() <= self.rss_limit_mb:
            return "trimmed"
        gc.collect()                # what waits for a full collection (~0.1 s: only here, idle and over the limit)
        release_free_memory()
        rss = resident_mb()
        if rss <= self.rss_limit_mb:
            return "trimmed"
        if self.recycle is not None and not self.recycle.take():
            return "wait"
        self.recycling = True
        log.warning("worker %d holds %.0f MB after its requests (it may keep %.0f MB: EPHEM_WORKER_RSS_MB less its "
                    "requests' allowance and the slack): restarting it",
                    os.getpid(), rss, self.rss_limit_mb)
        os.kill(os.getpid(), signal.SIGTERM)     # graceful: the supervisor starts a fresh worker
        return "recycle"

    def _watch(self) -> None:
        while True:
            time.sleep(self.interval_s)
            self.tick(time.monotonic())

    def tick(self, now: float) -> None:
        """The watchdog's round (every ``interval_s``, in its thread): a request stuck past its deadline and grace ends
        the worker; the memory freed since the last round goes back to the system (once per ``trim_interval_s``);
        a memory check left for later is made if its time has come and the worker is idle."""
        with self._lock:
            stuck = [(now - t0, what) for t0, what in self._running.values()
                     if now - t0 > self.deadline_s + self.grace_s]
            finished = self._finished
            idle = not self._running
        if stuck:
            age, what = max(stuck)
            log.error("worker %d: %s has run %.1f s, past its deadline of %.1f s: ending the worker", os.getpid(),
                      what, age, self.deadline_s)
            os.kill(os.getpid(), signal.SIGKILL)
        if finished != self._trimmed and now - self._last_trim >= self.trim_interval_s:
            release_free_memory()       # ~1 ms: what the requests since the last time freed goes back
            self._trimmed, self._last_trim = finished, now
        if idle:
            self._check_if_time(now)


class RecycleTurns:
    """One worker of the service at a time is recycled for its memory: a worker may go when no other went within
    ``spacing_s`` (the time a fresh worker takes to start, with a margin), read and stamped under an exclusive
    ``flock`` on a file in ``lock_dir`` shared by the workers. Workers of one age that grow alike would otherwise
    reach the limit together and leave nothing answering while their replacements start."""

    def __init__(self, lock_dir: str | None, spacing_s: float = 15.0):
        self.path = os.path.join(lock_dir or tempfile.mkdtemp(prefix="ephem-recycle-"), "recycle.stamp")
        self.spacing_s = spacing_s

    def take(self) -> bool:
        """Whether this worker may go now (and if so, the turn is stamped as taken)."""
        fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
            try:
                last = float(os.read(fd, 64).decode() or "0")
            except ValueError:
                last = 0.0
            now = time.time()
            if 0.0 <= now - last < self.spacing_s:
                return False
            os.lseek(fd, 0, os.SEEK_SET)
            os.ftruncate(fd, 0)
            os.write(fd, repr(now).encode())
            return True
        finally:
            os.close(fd)        # and its lock


#: glibc's allocator in a supervised worker (mallopt; what the environment sets, glibc's own MALLOC_ARENA_MAX,
#: MALLOC_MMAP_THRESHOLD_, MALLOC_TRIM_THRESHOLD_, is left to it): two arenas, where glibc made one per thread of the
#: pool (up to 8 per core), each keeping the blocks freed in it; blocks over 256 KiB (numpy's arrays of more than
#: 32768 doubles) mapped on their own and unmapped when freed, where glibc raised that threshold to the largest block
#: freed so far (up to 32 MiB), after which such arrays were carved from the arenas and their pages kept; the main
#: heap's free top returned beyond 512 KiB. Measured (benchmarks/RESULTS_memory_soak.md): a worker's RSS under load,
#: median 348-371 MB with the arenas alone, 304 MB with the threshold too, the answers as fast.
ALLOCATOR = {"MALLOC_ARENA_MAX": (-8, 2), "MALLOC_MMAP_THRESHOLD_": (-3, 256 * 1024),
             "MALLOC_TRIM_THRESHOLD_": (-1, 512 * 1024)}       # environment variable: (mallopt parameter, value)
_LIBC = None


def _libc():
    global _LIBC
    if _LIBC is None:
        try:
            _LIBC = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
            _LIBC.malloc_trim, _LIBC.mallopt   # glibc's: elsewhere (musl, macOS) there is nothing to tune
        except (OSError, AttributeError):
            _LIBC = False
    return _LIBC


def tune_allocator() -> list[str]:
    """Set glibc's allocator for a long-lived worker (:data:`ALLOCATOR`), each parameter unless its environment
    variable (read by glibc at the process's start) is set; called before the worker's threads start. Returns the
    variables set (none where the C library is not glibc)."""
    libc = _libc()
    if not libc:
        return []
    return [name for name, (param, value) in ALLOCATOR.items()
            if not os.environ.get(name) and libc.mallopt(param, value)]


def release_free_memory() -> None:
    """Return the allocator's free pages to the system (glibc's ``malloc_trim(0)``: every arena, ~1 ms for a few
    hundred MB); nothing where the C library is not glibc."""
    libc = _libc()
    if libc:
        libc.malloc_trim(0)


def resident_mb() -> float:
    """This process's resident memory, MB (Linux /proc; 0 where unavailable)."""
    try:
        with open("/proc/self/statm") as fh:
            return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    except (OSError, ValueError, IndexError):
        return 0.0


def peak_resident_mb() -> float:
    """This process's largest resident memory so far, MB (never below :func:`resident_mb`; Linux counts KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def install(app: FastAPI, settings: Settings) -> None:
    watchdog = None
    if settings.supervised:
        tune_allocator()                # before the worker's thread pool starts (its threads are made on demand)
        watchdog = Watchdog(settings.request_deadline_s, settings.hard_kill_after_s, settings.worker_keep_mb,
                            recycle=RecycleTurns(settings.lock_dir))
    settings.check()                    # the memory settings' coherence: a clear error at start-up, not a 503 later
    heavy = HeavySlots(settings.heavy_request_cpu_s, settings.heavy_slots, settings.lock_dir)
    memory = MemoryAllowance(settings.worker_request_memory_mb, settings.memory_wait_s)
    app.state.memory_allowance = memory         # this worker's (each worker process has its own copy)
    app.add_middleware(RequestBudget, settings=settings, watchdog=watchdog, heavy=heavy, memory=memory)

    @app.exception_handler(OverBudgetError)
    async def over_budget(request: Request, exc: OverBudgetError):
        # the whole request's estimate, as the detail prints it: the parts charged already and the refused one
        return problem(422, "over-budget", "Over budget", str(exc), errors=[{"field": exc.field, "reason": exc.reason}],
                       estimated_cpu_s=exc.estimated_cpu_s, already_charged_cpu_s=exc.spent_cpu_s,
                       estimated_memory_mb=exc.estimated_memory_mb, budget_cpu_s=exc.cpu_s_budget,
                       budget_memory_mb=exc.memory_mb_budget, estimate=exc.total.as_dict())

    @app.exception_handler(MemoryBusyError)
    async def busy_memory(request: Request, exc: MemoryBusyError):
        return problem(503, "busy", "Busy: this worker's memory for requests is taken", str(exc),
                       headers={"Retry-After": str(exc.retry_after_s)}, estimated_memory_mb=exc.memory_mb,
                       worker_request_memory_mb=exc.limit_mb, in_flight_memory_mb=exc.held_mb)

    @app.exception_handler(BusyError)
    async def busy(request: Request, exc: BusyError):
        return problem(503, "busy", "Busy with large requests", str(exc),
                       headers={"Retry-After": str(exc.retry_after_s)}, estimated_cpu_s=exc.cpu_s,
                       heavy_request_cpu_s=exc.threshold_cpu_s, heavy_slots=exc.slots)

    @app.exception_handler(DeadlineExceededError)
    async def deadline(request: Request, exc: DeadlineExceededError):
        return problem(503, "deadline", "Deadline exceeded", str(exc), deadline_s=exc.deadline_s)

    @app.exception_handler(MemoryError)
    async def out_of_memory(request: Request, exc: MemoryError):
        detail = (f"the request needed more memory than this worker's ceiling ({settings.worker_memory_mb:g} MB) "
                  "and was stopped; ask for fewer epochs or a shorter span")
        return problem(503, "memory", "Memory ceiling", detail)
