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
entry that fills itself in after it is stored (the ladder's tables keep the grids asked of them) is looked at
again at the pool's next use after each time it was handed out, and the pool evicted to the budget then: weighed
again every time (``grows=True``), or, where its cache says how its growth shows (``grows=mark``, a cheap function
of the value, the keys of the grids it keeps, say), weighed again only when that mark has changed since it was last
weighed. Walking a body's tables costs ~0.15 ms, paid by every warm request when it was done at each hand-out.
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

#: how an entry grows after it is stored (:meth:`BytePool.put`): not (False), weighed again after every hand-out
#: (True), or weighed again when a cheap mark of its growth, this function of the value, changes
Grows = bool | Callable[[object], Hashable]

#: the bytes all the caches of a process hold together, MB (the service sets its own: EPHEM_MODEL_CACHE_MB)
DEFAULT_BUDGET_MB = 64.0

#: objects that are shared by everything and owned by nothing cached: not weighed
_UNWEIGHED = (type, types.ModuleType, types.FunctionType, types.BuiltinFunctionType, types.MethodType,
              str, bytes, int, float, complex, bool, type(None))


#: how :func:`sizeof` treats an object, by its type (:func:`_kind`)
_FREE, _SCALAR, _ARRAY, _MAPPING, _SEQUENCE, _OBJECT = range(6)
#: type -> (kind, the __slots__ names of its classes), filled as types are met (at most _KINDS_MAX types kept)
_KINDS: dict[type, tuple[int, tuple[str, ...]]] = {}
_KINDS_MAX = 4096
_MISSING = object()


def _kind(t: type) -> tuple[int, tuple[str, ...]]:
    """How :func:`sizeof` treats an instance of ``t``, with its slots: worked out once per type (the walk meets the
    same few types thousands of times: a tuple of a ladder's estimates is ~1500 references)."""
    if issubclass(t, np.ndarray):
        kind = _ARRAY
    elif issubclass(t, (str, bytes, float, complex)):
        kind = _SCALAR
    elif issubclass(t, _UNWEIGHED):
        kind = _FREE
    elif issubclass(t, dict):
        kind = _MAPPING
    elif issubclass(t, (list, tuple, set, frozenset)):
        kind = _SEQUENCE
    else:
        kind = _OBJECT
    slots: list[str] = []
    if kind == _OBJECT:
        for cls in t.__mro__:
            names = cls.__dict__.get("__slots__", ())
            for slot in ((names,) if isinstance(names, str) else names):
                if slot not in ("__dict__", "__weakref__") and slot not in slots:
                    slots.append(slot)
    if len(_KINDS) >= _KINDS_MAX:
        _KINDS.clear()
    _KINDS[t] = result = (kind, tuple(slots))
    return result


def sizeof(obj) -> int:
    """Bytes ``obj`` holds: the buffers of the numpy arrays it reaches (each buffer once, a view counted by the
    array that owns its memory), and the Python objects (containers, dataclasses, objects with ``__dict__`` or
    ``__slots__``) on the way, each once. Strings, bytes and floats count their own size once each (often shared:
    interned names); ints, None, types, modules and functions nothing (shared by everything, owned by nothing
    cached)."""
    seen: set[int] = set()
    add = seen.add
    total = 0
    stack = [obj]
    pop, push, extend = stack.pop, stack.append, stack.extend
    getsize = sys.getsizeof
    kinds = _KINDS
    while stack:
        o = pop()
        t = type(o)
        kind, slots = kinds.get(t) or _kind(t)
        if kind == _FREE:
            continue
        i = id(o)
        if i in seen:
            continue
        add(i)
        total += getsize(o)             # an array's: numpy's, the header and the buffer when the array owns it
        if kind == _SCALAR:
            continue
        if kind == _ARRAY:
            if o.base is not None:
                push(o.base)            # a view keeps its base alive: weighed once, whoever reaches it
            if o.dtype == object:
                extend(o.ravel().tolist())
        elif kind == _MAPPING:
            extend(o.keys())
            extend(o.values())
        elif kind == _SEQUENCE:
            extend(o)
        else:
            d = getattr(o, "__dict__", None)
            if d is not None:
                push(d)
            for slot in slots:
                v = getattr(o, slot, _MISSING)
                if v is not _MISSING:
                    push(v)
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
        #: key -> (value, its bytes as last weighed, grows, the growth mark it was weighed at)
        self._entries: OrderedDict[tuple[str, Hashable], tuple[object, int, Grows, Hashable]] = OrderedDict()
        self._nbytes = 0
        self._lent: set = set()        # entries that grow, handed out since they were last weighed
        self._lock = threading.Lock()
        #: entries dropped to keep the budget, and growing entries walked again (since the pool was made)
        self.evictions = 0
        self.reweighs = 0

    def set_budget(self, budget_bytes: int) -> None:
        with self._lock:
            self.budget_bytes = int(budget_bytes)
            self._evict()

    def get(self, key: tuple[str, Hashable]):
        """The value stored at ``key`` (now the most recently used), or a KeyError."""
        with self._lock:
            self._reweigh()
            value, _, grows, _ = self._entries[key]
            self._entries.move_to_end(key)
            if grows:
                self._lent.add(key)
            return value

    def __contains__(self, key) -> bool:
        with self._lock:
            return key in self._entries

    def put(self, key: tuple[str, Hashable], value, grows: Grows = False) -> None:
        """Store ``value`` at ``key`` and evict to the budget. ``grows``: the value fills itself in when used:
        ``True``, weighed again after each time it is handed out; a function of the value giving a cheap hashable
        mark of what it has filled in (the keys of the grids it keeps, say), weighed again after a hand-out only
        if the mark changed. The mark is read before the value is weighed: growth in between shows as a change."""
        mark = grows(value) if callable(grows) else None
        size = sizeof(value)            # outside the lock: a large entry takes a few ms to walk
        with self._lock:
            self._reweigh()
            old = self._entries.pop(key, None)
            if old is not None:
                self._nbytes -= old[1]
            if size > self.budget_bytes:        # kept, it alone would break the bound: the caller uses it once
                return
            self._entries[key] = (value, size, grows, mark)
            self._nbytes += size
            if grows:
                self._lent.add(key)
            self._evict()

    def _reweigh(self) -> None:
        """Weigh again the growing entries handed out since their last weighing (those with a mark only if it
        changed), and evict to the budget."""
        for key in self._lent:
            entry = self._entries.get(key)
            if entry is None:
                continue
            value, old, grows, mark = entry
            if callable(grows):
                mark_now = grows(value)
                if mark_now == mark:
                    continue
                mark = mark_now
            size = sizeof(value)
            self.reweighs += 1
            self._nbytes += size - old
            self._entries[key] = (value, size, grows, mark)
        self._lent.clear()
        self._evict()

    def _evict(self) -> None:
        while self._nbytes > self.budget_bytes and self._entries:
            key, (_, size, _, _) = self._entries.popitem(last=False)
            self._nbytes -= size
            self._lent.discard(key)
            self.evictions += 1

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


def bytes_bounded(func: Callable | None = None, *, name: str | None = None, grows: Grows = False,
                  pool: BytePool = POOL, key: Callable | None = None):
    """Memoise ``func`` (of hashable arguments) in ``pool``: as ``functools.lru_cache``, with ``cache_clear``
    and ``cache_info`` (a :class:`CacheInfo`), but bounded by the pool's bytes rather than a count of entries.
    ``func.cached(*args, **kwargs)`` tells whether a call would find its value stored, ``func.holds(k)`` the same
    by the key ``k`` that ``key`` gives. ``grows``: the values
    fill themselves in as they are used: ``True`` or a function giving a mark of their growth (see
    :meth:`BytePool.put`). ``key``: a function of the call's arguments
    giving the hashable key that stands for them (an array's digest, say), where they are not hashable
    themselves; it must tell apart every two calls whose values differ."""
    if func is None:
        return functools.partial(bytes_bounded, name=name, grows=grows, pool=pool, key=key)
    label = name or f"{func.__module__}.{func.__qualname__}"
    counts = {"hits": 0, "misses": 0}
    signature = inspect.signature(func)
    positional = len(signature.parameters)
    # the parameters' defaults in order, when every parameter can be given by position: a call by position only,
    # with every required argument, is completed from them as binding it would, without binding (a few us a call; a
    # tolerance request makes ~50 such calls, the ladder's model and theory looked up by the body alone)
    params = list(signature.parameters.values())
    plain = all(p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD) for p in params)
    defaults = tuple(p.default for p in params) if plain else None
    required = max((i + 1 for i, p in enumerate(params) if p.default is p.empty), default=0)

    def key_of(args, kwargs):
        if key is not None:
            return (label, key(*args, **kwargs))
        # f(body) and f(body, None) are one entry: the arguments as the function sees them, defaults filled in
        if not kwargs and defaults is not None and required <= len(args) < positional:
            return (label, args + defaults[len(args):])
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
