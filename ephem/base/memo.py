"""Caches of per-body work bounded in bytes, not in entries.

A process keeps what it built for a body (its model, its second-order theory, the ladder's tables, its
uncertainties) so that the next request for the same body costs nothing. Counted in entries, such a cache is
unbounded in memory: an entry's size grows with the body's eccentricity (the harmonics kept grow like
(1 - e²)^(-3/2)), from kilobytes at e = 0.1 to megabytes at e = 0.9 and tens of megabytes at e = 0.95, and a
service's client chooses the bodies: 512 distinct eccentric bodies walked a worker to its recycle threshold.

Here the caches of a process share one byte budget (:data:`DEFAULT_BUDGET_MB`, the service's
``EPHEM_MODEL_CACHE_MB``): each entry is weighed once, when it is stored (:func:`sizeof`: its numpy arrays'
buffers and its Python objects), and the least recently used entries of any cache are dropped until the total
is within the budget. An entry larger than the whole budget is returned to its caller and not kept. Entries are
weighed with their shared parts counted in each (an upper estimate): the budget holds however they share. An
entry that fills itself in after it is stored (the ladder's tables keep the grids asked of them) is weighed again
at the pool's next use after each time it was handed out, and the pool evicted to the budget then.
"""
from __future__ import annotations

import functools
import hashlib
import inspect
import sys
import threading
import types
from collections import OrderedDict
from dataclasses import dataclass
from typing import Callable, Hashable

import numpy as np

#: the bytes all the caches of a process hold together, MB (the service sets its own: EPHEM_MODEL_CACHE_MB)
DEFAULT_BUDGET_MB = 64.0

#: objects that are shared by everything and owned by nothing cached: not weighed
_UNWEIGHED = (type, types.ModuleType, types.FunctionType, types.BuiltinFunctionType, types.MethodType,
              str, bytes, int, float, complex, bool, type(None))


def sizeof(obj) -> int:
    """Bytes ``obj`` holds: the buffers of the numpy arrays it reaches (each buffer once, a view counted by the
    array that owns its memory), and the Python objects (containers, dataclasses, objects with ``__dict__`` or
    ``__slots__``) on the way. Strings and numbers are counted as their containers' slots only: small beside
    the arrays, and often shared (interned names)."""
    seen: set[int] = set()
    total = 0
    stack = [obj]
    while stack:
        o = stack.pop()
        if id(o) in seen:
            continue
        seen.add(id(o))
        if isinstance(o, np.ndarray):
            total += sys.getsizeof(o)       # numpy's: the header, and the buffer when the array owns it
            if o.base is not None:
                stack.append(o.base)        # a view keeps its base alive: weighed once, whoever reaches it
            if o.dtype == object:
                stack.extend(o.ravel().tolist())
            continue
        if isinstance(o, _UNWEIGHED):
            total += sys.getsizeof(o) if isinstance(o, (str, bytes, float, complex)) else 0
            continue
        total += sys.getsizeof(o)
        if isinstance(o, dict):
            stack.extend(o.keys())
            stack.extend(o.values())
        elif isinstance(o, (list, tuple, set, frozenset)):
            stack.extend(o)
        else:
            d = getattr(o, "__dict__", None)
            if d is not None:
                stack.append(d)
            for cls in type(o).__mro__:
                for slot in getattr(cls, "__slots__", ()):
                    if slot not in ("__dict__", "__weakref__") and hasattr(o, slot):
                        stack.append(getattr(o, slot))
    return total


@dataclass(frozen=True)
class CacheInfo:
    """What a cache holds: as functools' (hits, misses, currsize), with the bytes it holds, the bytes all the
    caches hold together, and their budget."""

    hits: int
    misses: int
    currsize: int
    nbytes: int
    pool_nbytes: int
    budget_bytes: int


class BytePool:
    """One least-recently-used order over the entries of several caches, evicted to keep their weighed bytes
    within ``budget_bytes``. Thread-safe: a value is built outside the lock (two threads may both build it; the
    second stored wins), stored and evicted under it."""

    def __init__(self, budget_bytes: int):
        self.budget_bytes = int(budget_bytes)
        self._entries: OrderedDict[tuple[str, Hashable], tuple[object, int, bool]] = OrderedDict()
        self._nbytes = 0
        self._lent: set = set()        # entries that grow, handed out since they were last weighed
        self._lock = threading.Lock()

    def set_budget(self, budget_bytes: int) -> None:
        with self._lock:
            self.budget_bytes = int(budget_bytes)
            self._evict()

    def get(self, key: tuple[str, Hashable]):
        """The value stored at ``key`` (now the most recently used), or a KeyError."""
        with self._lock:
            self._reweigh()
            value, _, grows = self._entries[key]
            self._entries.move_to_end(key)
            if grows:
                self._lent.add(key)
            return value

    def __contains__(self, key) -> bool:
        with self._lock:
            return key in self._entries

    def put(self, key: tuple[str, Hashable], value, grows: bool = False) -> None:
        """Store ``value`` at ``key`` and evict to the budget. ``grows``: the value fills itself in when used
        (weighed again after each time it is handed out)."""
        size = sizeof(value)            # outside the lock: a large entry takes a few ms to walk
        with self._lock:
            self._reweigh()
            old = self._entries.pop(key, None)
            if old is not None:
                self._nbytes -= old[1]
            if size > self.budget_bytes:        # kept, it alone would break the bound: the caller uses it once
                return
            self._entries[key] = (value, size, grows)
            self._nbytes += size
            if grows:
                self._lent.add(key)
            self._evict()

    def _reweigh(self) -> None:
        """Weigh again the growing entries handed out since their last weighing, and evict to the budget."""
        for key in self._lent:
            entry = self._entries.get(key)
            if entry is not None:
                size = sizeof(entry[0])
                self._nbytes += size - entry[1]
                self._entries[key] = (entry[0], size, True)
        self._lent.clear()
        self._evict()

    def _evict(self) -> None:
        while self._nbytes > self.budget_bytes and self._entries:
            key, (_, size, _) = self._entries.popitem(last=False)
            self._nbytes -= size
            self._lent.discard(key)

    def clear(self, cache: str | None = None) -> None:
        """Drop the entries of one cache (by name), or all."""
        with self._lock:
            for key in [k for k in self._entries if cache is None or k[0] == cache]:
                self._nbytes -= self._entries.pop(key)[1]
                self._lent.discard(key)

    def held(self, cache: str) -> tuple[int, int]:
        """(entries, bytes) of one cache, as last weighed."""
        with self._lock:
            self._reweigh()
            sizes = [entry[1] for (name, _), entry in self._entries.items() if name == cache]
        return len(sizes), sum(sizes)

    @property
    def nbytes(self) -> int:
        """The bytes the entries hold together, as last weighed (growing ones weighed again first)."""
        with self._lock:
            self._reweigh()
            return self._nbytes


#: the pool every bounded cache of the library shares
POOL = BytePool(int(DEFAULT_BUDGET_MB * 2**20))


def set_budget_mb(megabytes: float) -> None:
    """Set the bytes the library's per-body caches may hold together, MB (2^20 bytes); evicts at once."""
    POOL.set_budget(int(megabytes * 2**20))


def budget_mb() -> float:
    return POOL.budget_bytes / 2**20


def bytes_bounded(func: Callable | None = None, *, name: str | None = None, grows: bool = False,
                  pool: BytePool = POOL, key: Callable | None = None):
    """Memoise ``func`` (of hashable arguments) in ``pool``: as ``functools.lru_cache``, with ``cache_clear``
    and ``cache_info`` (a :class:`CacheInfo`), but bounded by the pool's bytes rather than a count of entries.
    ``func.cached(*args, **kwargs)`` tells whether a call would find its value stored, ``func.holds(k)`` the same
    by the key ``k`` that ``key`` gives. ``grows``: the values
    fill themselves in as they are used (see :meth:`BytePool.put`). ``key``: a function of the call's arguments
    giving the hashable key that stands for them (an array's digest, say), where they are not hashable
    themselves; it must tell apart every two calls whose values differ."""
    if func is None:
        return functools.partial(bytes_bounded, name=name, grows=grows, pool=pool, key=key)
    label = name or f"{func.__module__}.{func.__qualname__}"
    counts = {"hits": 0, "misses": 0}
    signature = inspect.signature(func)
    positional = len(signature.parameters)

    def key_of(args, kwargs):
        if key is not None:
            return (label, key(*args, **kwargs))
        # f(body) and f(body, None) are one entry: the arguments as the function sees them, defaults filled in
        if kwargs or len(args) < positional:
            bound = signature.bind(*args, **kwargs)
            bound.apply_defaults()
            args = tuple(bound.arguments.values())
        return (label, args)

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        key = key_of(args, kwargs)
        try:
            value = pool.get(key)
        except KeyError:
            pass
        else:
            counts["hits"] += 1
            return value
        counts["misses"] += 1
        value = func(*args, **kwargs)
        pool.put(key, value, grows)
        return value

    def cache_info() -> CacheInfo:
        entries, nbytes = pool.held(label)
        return CacheInfo(counts["hits"], counts["misses"], entries, nbytes, pool.nbytes, pool.budget_bytes)

    def cache_clear() -> None:
        pool.clear(label)
        counts["hits"] = counts["misses"] = 0

    wrapper.cache_info = cache_info
    wrapper.cache_clear = cache_clear
    wrapper.cached = lambda *args, **kwargs: key_of(args, kwargs) in pool
    wrapper.holds = lambda k: (label, k) in pool        # by the key itself (``key``'s value), the arguments gone
    return wrapper



def epochs_digest(t: np.ndarray) -> tuple:
    """A key that stands for an array of epochs in a memo (:func:`bytes_bounded`'s ``key``): its shape, dtype and a
    128-bit BLAKE2b digest of its bytes (two different arrays share it with probability 2^-128)."""
    a = np.ascontiguousarray(t)
    return a.shape, a.dtype.str, hashlib.blake2b(a.view(np.uint8), digest_size=16).digest()
