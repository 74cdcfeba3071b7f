"""The per-body caches' byte pool (ephem.base.memo): what an entry weighs, and how an entry that fills itself in
after it is stored (the ladder's tables) is weighed again: only when its growth shows, with the pool's accounting
still equal to a fresh weighing of what it holds and within its budget (issue 39: the walk at every warm request)."""
from __future__ import annotations

import sys
from dataclasses import dataclass, field

import numpy as np
import pytest

from ephem import api
from ephem.base import memo


class _Slots:
    __slots__ = ("a", "b")

    def __init__(self, a, b=None):
        self.a = a
        if b is not None:
            self.b = b


class _OneSlot:
    __slots__ = "grid"              # a single slot may be named by a string

    def __init__(self, grid):
        self.grid = grid


class _MoreSlots(_Slots):
    __slots__ = ("c",)

    def __init__(self, a, c):
        super().__init__(a)
        self.c = c


@dataclass
class _Record:
    name: str
    values: np.ndarray
    extra: dict = field(default_factory=dict)


def test_sizeof_counts_every_buffer_and_object_once():
    a, b = np.zeros(10_000), np.ones(20_000)
    buffers = a.nbytes + b.nbytes
    # slots (inherited, and one named by a string), a dataclass's __dict__, dicts, lists, views of one buffer
    assert memo.sizeof(_Slots(a)) >= a.nbytes
    assert memo.sizeof(_OneSlot(a)) >= a.nbytes
    assert memo.sizeof(_MoreSlots(a, b)) >= buffers                  # the parent's slot and its own
    assert memo.sizeof(_Slots(a, b)) >= buffers                      # a slot left unset is skipped, not an error
    rec = _Record("x", a, {"b": b, "view": b[::2]})
    assert buffers <= memo.sizeof(rec) < buffers + 2_000             # the view's buffer is b's: counted once
    assert memo.sizeof([rec, rec, {"again": rec}]) < memo.sizeof(rec) + 500
    # an object array's elements are walked
    objs = np.empty(3, dtype=object)
    objs[:] = [a, b, a]
    assert memo.sizeof(objs) >= buffers
    # the shared and owned-by-nothing objects weigh nothing: types, modules, functions, ints
    assert memo.sizeof([int, np, memo.sizeof, 10**6]) == sys.getsizeof([int, np, memo.sizeof, 10**6])


def test_sizeof_is_exact_for_plain_containers():
    """A list of distinct floats and strings: the list plus each element, once each (the same string twice once)."""
    items = [float(k) + 0.5 for k in range(50)] + [f"name{k}" for k in range(20)]
    value = items + items[:10]
    expected = sys.getsizeof(value) + sum(sys.getsizeof(x) for x in items)
    assert memo.sizeof(value) == expected


def test_an_entry_with_a_growth_mark_is_weighed_again_only_when_it_grows():
    pool = memo.BytePool(200_000)
    grow = memo.bytes_bounded(lambda k: {"grids": {}}, name="g", pool=pool,
                              grows=lambda value: tuple(value["grids"]))
    grow(0)
    for _ in range(20):                                # handed out 20 times, nothing added: not walked again
        grow(0)
    assert pool.reweighs == 0
    grow(0)["grids"]["a"] = np.zeros(5_000)           # 40 kB filled in after it was stored
    assert pool.nbytes >= 40_000                       # seen at the pool's next use
    assert pool.reweighs == 1
    for _ in range(5):
        grow(0)
    assert pool.reweighs == 1
    # growth beyond the budget: weighed again, the least recently used entries go
    for k in range(1, 6):
        grow(k)["grids"]["a"] = np.zeros(5_000)
        assert pool.nbytes <= pool.budget_bytes
    assert not grow.cached(0) and grow.cached(5)
    assert pool.evictions >= 1


def test_an_entry_without_a_mark_is_weighed_again_after_every_hand_out():
    pool = memo.BytePool(1_000_000)
    grow = memo.bytes_bounded(lambda k: [], name="g", grows=True, pool=pool)
    grow(0)
    for _ in range(4):
        grow(0)
    _ = pool.nbytes
    assert pool.reweighs == 5                          # each hand-out (the one at the store too), whatever grew


def _tables_entry() -> tuple[int, object, tuple]:
    (value, size, _, mark), = [entry for (name, _), entry in memo.POOL._entries.items()
                               if name.endswith("bounds.cached_tables")]
    return size, value, mark


def test_the_ladders_tables_are_weighed_again_when_they_keep_new_grids_and_only_then():
    """Itokawa's tracks over spans whose epochs reach new phases of the second-order remainder: the tables keep
    those grids (their only growth). After each request the tables' weight in the pool equals a fresh weighing
    (the growth mark misses nothing), and a request at phases already kept walks them no more."""
    memo.POOL.clear()
    start = 2451545.0
    walks = memo.POOL.reweighs                         # the process's count so far (other tests used the pool)
    try:
        for years, offset in ((1, 0.0), (10, 0.0), (100, -20000.0), (1, 30000.0), (1, 30000.0), (10, 0.0)):
            before = memo.POOL.reweighs
            _, tables, mark = _tables_entry() if years != 1 or offset else (0, None, None)
            api.track_arrays("itokawa", start + offset, start + offset + 365.25 * years, 365.25 * years / 9,
                             model="series", order=6)
            _ = memo.POOL.nbytes                       # the pool's next use: a grown entry is weighed then
            size, tables, mark_after = _tables_entry()
            assert size == memo.sizeof(tables), (years, offset)
            assert memo.POOL.nbytes <= memo.POOL.budget_bytes
            if mark is not None:
                assert memo.POOL.reweighs - before == (mark_after != mark), (years, offset)
        assert memo.POOL.reweighs - walks <= 3         # the store, and the new phases: not each of 6 requests
    finally:
        memo.POOL.clear()


# --- the pool's eviction and sizeof, with no service (moved from tests/service/test_service_guards.py, issue 43)

def test_the_pool_evicts_the_least_recently_used_to_its_budget():
    pool = memo.BytePool(3 * 8_000 + 2_000)            # three 8000-byte arrays and their headers
    cached = memo.bytes_bounded(lambda k: np.zeros(1000) + k, name="t", pool=pool)
    for k in range(3):
        cached(k)
    cached(0)                                          # 0 is now the most recently used: 1 goes first
    cached(3)
    assert [cached.cached(k) for k in range(4)] == [True, False, True, True]
    assert pool.nbytes <= pool.budget_bytes and cached.cache_info().currsize == 3
    big = memo.bytes_bounded(lambda: np.zeros(10_000), name="big", pool=pool)
    assert big().size == 10_000 and not big.cached()   # larger than the whole budget: answered, not kept
    assert cached.cache_info().currsize == 3


def test_an_entry_that_grows_is_weighed_again():
    pool = memo.BytePool(100_000)
    grow = memo.bytes_bounded(lambda k: {"grids": []}, name="g", grows=True, pool=pool)
    grow(0)["grids"].append(np.zeros(5_000))           # 40 kB added after it was stored
    grow(1)["grids"].append(np.zeros(5_000))
    grow(2)["grids"].append(np.zeros(5_000))
    assert pool.nbytes <= pool.budget_bytes            # weighed again: the oldest went
    assert not grow.cached(0) and grow.cached(2)


def test_sizeof_counts_array_buffers_once_and_python_objects():
    a = np.zeros(100_000)
    assert memo.sizeof(a) >= a.nbytes
    assert memo.sizeof([a, a[10:], a.reshape(1000, 100)]) < 1.01 * memo.sizeof(a) + 1_000   # views share a
    assert memo.sizeof([{"k": None} for _ in range(1000)]) > 1000 * 64       # pure-Python entries count too


def test_a_call_and_its_defaults_spelt_out_are_one_entry_however_given():
    """f(x), f(x, None) and f(x, y=None) are one entry (the defaults filled in without binding the signature where every
    parameter is positional, by binding it otherwise); a keyword-only parameter's default fills in as well, and a
    missing required argument is still refused as the function would refuse it."""
    pool = memo.BytePool(2**20)
    calls = []

    @memo.bytes_bounded(pool=pool)
    def f(x, y=None, z=3):
        calls.append((x, y, z))
        return x

    @memo.bytes_bounded(pool=pool)
    def g(x, *, y=None):
        calls.append((x, y))
        return x

    assert f(1) == f(1, None) == f(1, None, 3) == f(1, y=None) == f(x=1) == 1
    assert calls == [(1, None, 3)] and f.cached(1) and f.cached(1, None, 3) and f.cache_info().currsize == 1
    assert f(1, 2) == 1 and calls[-1] == (1, 2, 3)
    assert g(5) == g(5, y=None) == 5 and calls[-1] == (5, None) and len(calls) == 3
    try:
        f()
    except TypeError:
        pass
    else:
        raise AssertionError("a missing argument must be refused")


def test_a_signature_with_args_still_binds():
    """A signature with *args is completed by binding (the position-only shortcut of the test above does not apply):
    g(1) and g(1, k=1) are one entry."""
    pool = memo.BytePool(10**7)
    calls = []

    @memo.bytes_bounded(pool=pool)
    def g(a, *rest, k=1):
        calls.append((a, rest, k))
        return a

    g(1)
    g(1, k=1)
    assert g.cache_info().hits == 1
