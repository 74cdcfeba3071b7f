"""The watchdog's memory check after a worker's requests (service/guards.py Watchdog.leave, check_memory): a worker
whose resident memory is above the limit (EPHEM_WORKER_RSS_MB) when it goes idle, and still above it once the freed
memory is handed back, asks the supervisor for a fresh one (SIGTERM to itself), one worker of the service at a time;
below the limit it does not, and its peak (one getrusage call) spares it the /proc read on every request."""
from __future__ import annotations

import signal
import time

import numpy as np
import pytest

from service import guards
from service.app import create_app
from service.guards import RecycleTurns, RequestBudget
from service.settings import Settings

SCOPE = {"method": "GET", "path": "/v1/bodies/ceres/track"}


@pytest.fixture
def kills(monkeypatch):
    sent: list[tuple[int, int]] = []
    monkeypatch.setattr(guards.os, "kill", lambda pid, sig: sent.append((pid, sig)))
    return sent


def _watchdog(limit_mb: float) -> guards.Watchdog:
    return guards.Watchdog(deadline_s=3600.0, grace_s=60.0, rss_limit_mb=limit_mb, interval_s=60.0)


def test_peak_is_never_below_the_resident_memory():
    block = np.ones(8 * 2**20 // 8)          # 8 MB touched: the resident memory moves
    assert block.sum() > 0
    rss = guards.resident_mb()
    if rss == 0.0:
        pytest.skip("no /proc/self/statm here")
    assert guards.peak_resident_mb() >= rss - 0.5      # the kernel's per-thread counters may lag by a few pages


def test_a_worker_over_its_limit_asks_for_a_restart_when_idle(kills):
    if guards.resident_mb() == 0.0:
        pytest.skip("no /proc/self/statm here")
    wd = _watchdog(limit_mb=1.0)             # every Python process holds more than 1 MB
    outer = wd.enter(SCOPE)
    wd.leave(wd.enter(SCOPE))                # another request still runs: not idle, no check
    assert kills == []
    wd.leave(outer)
    assert kills == [(guards.os.getpid(), signal.SIGTERM)]


def test_below_the_peak_no_proc_read_and_no_restart(kills, monkeypatch):
    def no_read():
        raise AssertionError("read /proc although the peak is below the limit")
    monkeypatch.setattr(guards, "resident_mb", no_read)
    wd = _watchdog(limit_mb=guards.peak_resident_mb() + 1e6)
    for _ in range(3):
        wd.leave(wd.enter(SCOPE))
    assert kills == []


def test_a_peak_over_the_limit_alone_is_no_restart(kills, monkeypatch):
    monkeypatch.setattr(guards, "peak_resident_mb", lambda: 1e9)     # a large request came and went
    monkeypatch.setattr(guards, "resident_mb", lambda: 100.0)        # and its memory was returned
    wd = _watchdog(limit_mb=500.0)
    wd.leave(wd.enter(SCOPE))
    assert kills == []


@pytest.fixture
def memory(monkeypatch):
    """A worker's resident memory as the test sets it; handing the freed memory back (gc, malloc_trim) brings it to
    ``after_trim`` when that is set."""
    state = {"rss": 100.0, "after_trim": None, "trims": 0, "collections": 0}

    def trim():
        state["trims"] += 1
        if state["after_trim"] is not None:
            state["rss"] = state["after_trim"]
    monkeypatch.setattr(guards, "resident_mb", lambda: state["rss"])
    monkeypatch.setattr(guards, "peak_resident_mb", lambda: max(state["rss"], 1e9))
    monkeypatch.setattr(guards, "release_free_memory", trim)
    monkeypatch.setattr(guards.gc, "collect", lambda *a: state.update(collections=state["collections"] + 1) or 0)
    return state


def test_resident_memory_above_the_setting_recycles_the_worker_once(kills, memory):
    wd = _watchdog(limit_mb=400.0)
    memory["rss"] = 401.0
    assert wd.check_memory() == "recycle"
    assert kills == [(guards.os.getpid(), signal.SIGTERM)]
    assert memory["trims"] == 2 and memory["collections"] == 1     # freed memory and garbage returned first
    wd.leave(wd.enter(SCOPE))                    # the worker finishes its requests: no second signal
    assert wd.check_memory() == "ok" and len(kills) == 1


def test_within_the_setting_no_recycle(kills, memory):
    wd = _watchdog(limit_mb=400.0)
    memory["rss"] = 399.0
    assert wd.check_memory() == "ok"
    wd.leave(wd.enter(SCOPE))
    assert kills == [] and memory["trims"] == 0


def test_memory_handed_back_below_the_setting_is_no_recycle(kills, memory):
    wd = _watchdog(limit_mb=400.0)
    memory["rss"], memory["after_trim"] = 520.0, 310.0       # freed blocks the allocator kept, now returned
    wd.leave(wd.enter(SCOPE))
    assert memory["trims"] == 1 and memory["collections"] == 0 and kills == []   # the trim alone was enough
    assert wd.check_memory() == "ok"


def test_an_idle_worker_s_memory_is_checked_at_most_every_few_seconds(kills, memory):
    wd = _watchdog(limit_mb=400.0)
    memory["rss"] = 450.0
    wd.recycle = type("Busy", (), {"take": lambda self: False})()     # another worker is being replaced
    wd.leave(wd.enter(SCOPE))
    wd.leave(wd.enter(SCOPE))                   # idle again at once: no second collection (~0.1 s each)
    assert memory["collections"] == 1 and kills == []
    wd.tick(time.monotonic() + guards.MEMORY_CHECK_S + 1)     # later, still idle: the watchdog's round asks again
    assert memory["collections"] == 2 and kills == []


def test_a_check_left_for_later_is_made_by_the_watchdog_s_round_once_idle(kills, memory):
    wd = _watchdog(limit_mb=400.0)
    memory["rss"], memory["after_trim"] = 500.0, 300.0
    wd.leave(wd.enter(SCOPE))                   # the first check: trimmed under the limit
    memory["rss"], memory["after_trim"] = 500.0, None
    busy = wd.enter(SCOPE)
    wd.leave(wd.enter(SCOPE))                   # not idle: nothing
    wd.leave(busy)                              # idle, over the limit, too soon after the last check: left for later
    assert kills == []
    wd.tick(time.monotonic() + guards.MEMORY_CHECK_S + 1)     # no request since: the worker is recycled
    assert kills == [(guards.os.getpid(), signal.SIGTERM)]


def test_one_worker_of_the_service_recycles_at_a_time(kills, memory, tmp_path):
    turns = RecycleTurns(str(tmp_path), spacing_s=3600.0)   # one lock directory, as the workers of a service share
    first = guards.Watchdog(3600.0, 60.0, 400.0, interval_s=60.0, recycle=turns)
    second = guards.Watchdog(3600.0, 60.0, 400.0, interval_s=60.0, recycle=RecycleTurns(str(tmp_path), 3600.0))
    memory["rss"] = 600.0
    assert first.check_memory() == "recycle"
    assert second.check_memory() == "wait"                  # asked again after its next request
    assert len(kills) == 1
    assert RecycleTurns(str(tmp_path), spacing_s=0.0).take()   # once the spacing has passed, the next may go


def test_the_service_s_watchdog_takes_its_limit_from_the_setting(monkeypatch):
    monkeypatch.setenv("EPHEM_WORKER_RSS_MB", "523.5")
    settings = Settings.from_env()
    assert settings.worker_rss_mb == 523.5
    monkeypatch.setattr(guards, "tune_allocator", lambda: [])   # the test process's allocator untouched
    app = create_app(Settings(warm_up=False, supervised=True, worker_rss_mb=settings.worker_rss_mb))
    budget = next(m for m in app.user_middleware if m.cls is RequestBudget)
    # what an idle worker may keep: the bound less its requests' allowance and the slack (service/settings.py)
    assert budget.kwargs["watchdog"].rss_limit_mb == settings.worker_keep_mb < 523.5 - settings.worker_request_memory_mb


def test_the_allocator_is_tuned_where_the_environment_leaves_it(monkeypatch):
    monkeypatch.setenv("MALLOC_ARENA_MAX", "4")           # the operator's, read by glibc at start: left alone
    for name in ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_"):
        monkeypatch.delenv(name, raising=False)
    done = guards.tune_allocator()
    if not done:
        pytest.skip("not glibc: nothing to tune")
    assert "MALLOC_ARENA_MAX" not in done
    assert sorted(done) == ["MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_"]
