"""The watchdog's memory check after a worker's requests (service/guards.py Watchdog.leave): a worker whose
resident memory is above the limit when it goes idle asks the supervisor for a fresh one (SIGTERM to itself);
below the limit it does not, and its peak (one getrusage call) spares it the /proc read on every request."""
from __future__ import annotations

import signal

import numpy as np
import pytest

from service import guards

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
