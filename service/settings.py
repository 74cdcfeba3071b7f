"""Service limits, from environment variables (read once when the app is created)."""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from urllib.parse import urlsplit


def _int_env(name: str, default: int, minimum: int = 1) -> int:
    raw = os.environ.get(name)
    if raw is None or raw.strip() == "":
        return default
    try:
        value = int(raw)
    except ValueError:
        raise SystemExit(f"{name} must be an integer, got {raw!r}") from None
    if value < minimum:
        raise SystemExit(f"{name} must be positive, got {value}" if minimum == 1 else
                         f"{name} must be at least {minimum}, got {value}")
    return value


def _float_env(name: str, default: float | None, zero: bool = False) -> float | None:
    """A number from the environment: positive and finite (``zero``: or 0); ``default`` when unset."""
    raw = os.environ.get(name)
    if raw is None or raw.strip() == "":
        return default
    try:
        value = float(raw)
    except ValueError:
        raise SystemExit(f"{name} must be a number, got {raw!r}") from None
    if not math.isfinite(value) or value < 0 or (value == 0 and not zero):
        raise SystemExit(f"{name} must be a {'non-negative' if zero else 'positive'} finite number, got {raw!r}")
    return value


def _bool_env(name: str, default: bool) -> bool:
    raw = os.environ.get(name)
    if raw is None or raw.strip() == "":
        return default
    value = raw.strip().lower()
    if value in ("1", "true", "yes", "on"):
        return True
    if value in ("0", "false", "no", "off"):
        return False
    raise SystemExit(f"{name} must be one of 1/0, true/false, yes/no, on/off; got {raw!r}")


def _url_env(name: str) -> str | None:
    """An absolute http(s) URL without query or fragment (its trailing slash dropped), or None when unset."""
    raw = (os.environ.get(name) or "").strip()
    if not raw:
        return None
    parts = urlsplit(raw)
    if parts.scheme not in ("http", "https") or not parts.netloc or parts.query or parts.fragment:
        raise SystemExit(f"{name} must be an absolute http(s) URL without query or fragment "
                         f"(https://ephem.example.org), got {raw!r}")
    return raw.rstrip("/")


#: what a worker keeps after its requests besides its per-body caches, MB: code, tables, the libraries imported on
#: first use (matplotlib, scipy), Python's pools and the allocator's kept pages. Measured idle through the memory
#: soak's 4,000-8,000 requests: 288-320 MB with the caches full at 64 MB, so 224-256 MB; the largest is taken
KEPT_FIXED_MB = 256.0
#: what a worker's RSS held beyond that, its caches and its requests' predicted peaks, MB: the memory the requests
#: below service.guards.TRIM_AFTER_REQUEST_MB (4 MB) freed and the once-a-second trim has not yet returned (less
#: than 4 MB each and reused by the next, up to 4 requests at once: < 16 MB), the requests with no checkpoint, which
#: are not counted (measured under 3.3 MB each), and the allocator's fragments. The memory soak with these defaults
#: (benchmarks/RESULTS_memory_soak.md, 4,000 requests) still had 0.4-1.0 % of its RSS samples above 400 MB, the
#: largest 429 MB, ~80 MB beyond the idle RSS and the whole allowance: the free wobble drawn as PNG, which took 68-246
#: MB against a charge of 69 (now charged for its loops: benchmarks/RESULTS_request_memory.md); each request alone is
#: now within its charge but for a few MB (a new body's cache entries, the Moon's nutation: 3-6 MB; a posted history's
#: secular spin, made before its charge: 9-15 MB, rare), which this covers for the few in flight at once
RSS_SLACK_MB = 32.0
#: the share of the room (the bound less KEPT_FIXED_MB and RSS_SLACK_MB) the requests in flight get by default; the
#: per-body caches get the rest: 80 and 32 MB of 112 at 400
REQUESTS_SHARE = 5.0 / 7.0


def derived_memory(worker_rss_mb: float, worker_request_memory_mb: float | None = None,
                   model_cache_mb: float | None = None) -> tuple[float, float]:
    """The worker's allowance for its requests in flight and its per-body caches' budget, MB, each as set or, unset,
    from the bound ``worker_rss_mb``: the room ``worker_rss_mb - KEPT_FIXED_MB - RSS_SLACK_MB``, REQUESTS_SHARE of it
    to the requests and the rest to the caches (at 400 MB: 112, so 80 and 32); one set, the other is the rest of the
    room. May be negative for a bound too small: :meth:`Settings.check` says so."""
    room = worker_rss_mb - KEPT_FIXED_MB - RSS_SLACK_MB
    # rounded down to 0.1 MB, so that the derived parts never sum above the room
    if worker_request_memory_mb is not None:
        requests = worker_request_memory_mb
    elif model_cache_mb is not None:
        requests = math.floor(10.0 * (room - model_cache_mb)) / 10.0
    else:
        requests = math.floor(10.0 * room * REQUESTS_SHARE) / 10.0
    caches = model_cache_mb if model_cache_mb is not None else math.floor(10.0 * (room - requests)) / 10.0
    return requests, caches


@dataclass(frozen=True)
class Settings:
    #: largest number of epochs in one track (422 beyond): 10^5 is 12 MB of JSON, ~0.05 s of one core; at
    #: 10^6 (122 MB, ~0.3 s holding the worker) one such answer stalled every request of its worker
    #: (benchmarks/RESULTS_load.md). The library and the CLI allow 10^6 (ephem.api.MAX_TRACK_SAMPLES).
    max_track_samples: int = 100_000
    #: largest request body in bytes (413 beyond)
    max_body_bytes: int = 65_536
    #: largest request head (the request line and the headers) in bytes, as received: 431 beyond (service/server.py;
    #: nginx's default is four 8 KiB buffers). Read by the server (gunicorn's worker), not by the app
    max_header_bytes: int = 32_768
    #: the address the pages' API links and curl lines start with (``https://ephem.example.org``, a path prefix
    #: allowed), for a service behind a proxy; None: the links are relative and the curl lines use the address the
    #: connection reached (the server's own socket, never the client's Host header)
    public_base_url: str | None = None
    #: build the Earth's lunisolar series at start-up (~2 s) rather than in the first Earth request
    warm_up: bool = True
    #: a request's predicted CPU time, seconds of one core (422 beyond, before any work)
    max_request_cpu_s: float = 5.0
    #: a request's predicted peak memory above the worker's baseline, MB (422 over-budget beyond, before any work).
    #: At most worker_request_memory_mb (checked at start-up, :meth:`check`): a request over what a worker may hold
    #: for all its requests could never run; unset, it is worker_request_memory_mb (was 500 MB, which let one
    #: request alone take a worker past its 400-MB bound)
    max_request_memory_mb: float | None = None
    #: the predicted peak memory of the requests running at once in one worker, summed, MB (service/guards.py,
    #: MemoryAllowance): a request that does not fit waits up to memory_wait_s for others to finish, then gets 503
    #: busy with Retry-After. Unset, it follows worker_rss_mb: 5/7 of what the bound leaves beyond the worker's own
    #: memory and the slack, ``(worker_rss_mb - KEPT_FIXED_MB - RSS_SLACK_MB) * 5/7``, 80 MB at 400
    #: (:func:`derived_memory`; the predictions are upper values, about twice what the requests take:
    #: benchmarks/RESULTS_memory_soak.md)
    worker_request_memory_mb: float | None = None
    #: how long a request waits for the worker's memory before 503 busy, seconds (a request holds a thread of the
    #: worker's pool while it waits; one on the event loop never waits)
    memory_wait_s: float = 2.0
    #: a request estimated above this many seconds of one core is large: only heavy_slots of them run at once
    #: (the usual requests are estimated at 2-50 ms; a track of 10^5 epochs at 0.18 s)
    heavy_request_cpu_s: float = 0.1
    #: how many large requests run at once, across all the workers (503 busy with Retry-After beyond)
    heavy_slots: int = 1
    #: where the workers' shared slot locks live (service/gunicorn_conf.py sets one per service; None: a
    #: fresh temporary directory, shared by nothing but this process)
    lock_dir: str | None = None
    #: wall-clock deadline of a request, seconds: the long loops stop past it (503)
    request_deadline_s: float = 20.0
    #: a request still running this long past its deadline ends its worker (under a supervisor only)
    hard_kill_after_s: float = 10.0
    #: each worker's address-space ceiling, MB (set by service/gunicorn_conf.py; MemoryError beyond: 503)
    worker_memory_mb: float = 3072.0
    #: the bound on a worker's resident memory (RSS), MB, at any time, its requests in flight included: the one
    #: memory setting, which the others follow unless set (:func:`derived_memory`): a worker keeps its own memory
    #: (KEPT_FIXED_MB) and its per-body caches (model_cache_mb), its requests in flight hold at most
    #: worker_request_memory_mb by their predictions, and RSS_SLACK_MB is what the samples held beyond these; the
    #: four sum within this (checked at start-up, :meth:`check`). What a worker may keep after its requests is the
    #: rest, :attr:`worker_keep_mb` (288 MB at 400): above it, when idle, the watchdog returns the allocator's freed
    #: memory to the system and, if the worker still holds more, recycles it gracefully, one worker at a time (under a
    #: supervisor only; service/guards.py). Before the bound: a worker grew to 500-770 MB over 8,000 requests
    #: (benchmarks/RESULTS_memory_soak.md)
    worker_rss_mb: float = 400.0
    #: the requests one keep-alive connection carries: the last is answered with ``Connection: close`` and the
    #: connection closed after it (make serve's httptools protocol, service/server.py), so that the client reconnects
    #: and the kernel spreads the connections over the workers again
    keepalive_max_requests: int = 1000
    #: a keep-alive connection's age, seconds, after which its next answer closes it (as above): after a worker was
    #: killed its clients all went to the survivor and stayed there while the replacement served nothing; with
    #: this, both workers serve again within a few seconds of the replacement's start (RESULTS_kill_rebalance.md)
    keepalive_max_s: float = 2.0
    #: running under a supervisor that restarts workers (gunicorn): arms the watchdog
    supervised: bool = False
    #: the most bodies one POST /v1/batch takes (422 beyond, pointing to `ephem batch`); the body size limit
    #: (max_body_bytes: about 300 bytes a row of JSON) and the CPU budget bound it too
    max_batch_rows: int = 200
    #: the bytes a worker's per-body caches (models, theories, the ladder's tables, uncertainties: ephem.base.memo) hold
    #: together, MB: the bodies are the clients', and one eccentric body's entries weigh megabytes (a cache
    #: counted in entries let 512 of them walk a worker to its recycle threshold). Unset, it follows worker_rss_mb:
    #: what the bound leaves beyond the worker's own memory, the slack and worker_request_memory_mb, 32 MB at 400
    #: (it was 64 MB, with the 400-MB bound then unmet under load)
    model_cache_mb: float | None = None
    #: how long a client or a shared cache (a reverse proxy, a CDN) may keep a GET answer without asking again,
    #: seconds: ``Cache-Control: public, max-age=N`` (0: ``no-cache``, every reuse revalidated with the ETag, a
    #: 304 when unchanged; service/caching.py). An answer is a pure function of the request, the version and
    #: the data, so a day is safe: a new version or new data change every ETag
    cache_max_age_s: int = 86_400
    #: a request predicted to need at most this much CPU, ms, is answered on the worker's event loop, without the hop
    #: to the thread pool and back (~0.1 ms of CPU each way); beyond, the thread pool (service/offload.py). The
    #: loop is held at most about this long by one request. 0: every request in the thread pool
    inline_cpu_ms: float = 5.0

    def __post_init__(self):
        # the memory settings left unset follow the bound (worker_rss_mb): one setting the others derive from
        requests, caches = derived_memory(self.worker_rss_mb, self.worker_request_memory_mb, self.model_cache_mb)
        object.__setattr__(self, "worker_request_memory_mb", requests)
        object.__setattr__(self, "model_cache_mb", caches)
        if self.max_request_memory_mb is None:
            object.__setattr__(self, "max_request_memory_mb", requests)

    @property
    def worker_keep_mb(self) -> float:
        """What a worker may keep after its requests, MB: the bound less its requests' allowance and the slack (288 MB
        at the defaults); the watchdog recycles an idle worker above it (service/guards.py, Watchdog)."""
        return self.worker_rss_mb - self.worker_request_memory_mb - RSS_SLACK_MB

    def check(self) -> "Settings":
        """The settings that must agree, checked at start-up (:func:`service.guards.install`): raises ``SystemExit``
        with what to change."""
        if self.max_request_memory_mb > self.worker_request_memory_mb:
            raise SystemExit(f"EPHEM_MAX_REQUEST_MEMORY_MB ({self.max_request_memory_mb:g} MB, one request's predicted "
                             f"peak) must not exceed EPHEM_WORKER_REQUEST_MEMORY_MB ({self.worker_request_memory_mb:g} MB, "
                             "what the requests running in a worker may hold together): a request between the two would "
                             "pass its own budget and never be admitted. Lower the first or raise the second")
        if self.worker_request_memory_mb >= self.worker_memory_mb:
            raise SystemExit(f"EPHEM_WORKER_REQUEST_MEMORY_MB ({self.worker_request_memory_mb:g} MB) must be below the "
                             f"worker's address-space ceiling EPHEM_WORKER_MEMORY_MB ({self.worker_memory_mb:g} MB)")
        if self.worker_request_memory_mb <= 0 or self.model_cache_mb <= 0 or (
                KEPT_FIXED_MB + self.model_cache_mb + self.worker_request_memory_mb + RSS_SLACK_MB
                > self.worker_rss_mb * (1.0 + 1e-12)):
            raise SystemExit(f"EPHEM_WORKER_RSS_MB ({self.worker_rss_mb:g} MB, the bound on a worker's resident memory) "
                             f"must hold what a worker keeps ({KEPT_FIXED_MB:g} MB), its per-body caches "
                             f"(EPHEM_MODEL_CACHE_MB, {self.model_cache_mb:g} MB), its requests in flight "
                             f"(EPHEM_WORKER_REQUEST_MEMORY_MB, {self.worker_request_memory_mb:g} MB) and a slack of "
                             f"{RSS_SLACK_MB:g} MB, each positive: raise the bound or lower the others (unset, they "
                             f"follow the bound, which must then exceed {KEPT_FIXED_MB + RSS_SLACK_MB:g} MB)")
        return self

    @classmethod
    def from_env(cls) -> "Settings":
        worker_rss_mb = _float_env("EPHEM_WORKER_RSS_MB", cls.worker_rss_mb)
        worker_request_memory_mb, model_cache_mb = derived_memory(
            worker_rss_mb, _float_env("EPHEM_WORKER_REQUEST_MEMORY_MB", None),
            _float_env("EPHEM_MODEL_CACHE_MB", None))
        return cls(max_track_samples=_int_env("EPHEM_MAX_TRACK_SAMPLES", cls.max_track_samples),
                   max_body_bytes=_int_env("EPHEM_MAX_BODY_BYTES", cls.max_body_bytes),
                   max_header_bytes=_int_env("EPHEM_MAX_HEADER_BYTES", cls.max_header_bytes, minimum=1024),
                   public_base_url=_url_env("EPHEM_PUBLIC_BASE_URL"),
                   warm_up=_bool_env("EPHEM_WARM_UP", cls.warm_up),
                   max_request_cpu_s=_float_env("EPHEM_MAX_REQUEST_CPU_S", cls.max_request_cpu_s),
                   max_request_memory_mb=_float_env("EPHEM_MAX_REQUEST_MEMORY_MB", worker_request_memory_mb),
                   worker_request_memory_mb=worker_request_memory_mb,
                   memory_wait_s=_float_env("EPHEM_MEMORY_WAIT_S", cls.memory_wait_s, zero=True),
                   heavy_request_cpu_s=_float_env("EPHEM_HEAVY_REQUEST_CPU_S", cls.heavy_request_cpu_s),
                   heavy_slots=_int_env("EPHEM_HEAVY_SLOTS", cls.heavy_slots),
                   lock_dir=os.environ.get("EPHEM_LOCK_DIR") or None,
                   request_deadline_s=_float_env("EPHEM_REQUEST_DEADLINE_S", cls.request_deadline_s),
                   hard_kill_after_s=_float_env("EPHEM_HARD_KILL_AFTER_S", cls.hard_kill_after_s),
                   worker_memory_mb=_float_env("EPHEM_WORKER_MEMORY_MB", cls.worker_memory_mb),
                   worker_rss_mb=worker_rss_mb,
                   keepalive_max_requests=_int_env("EPHEM_KEEPALIVE_MAX_REQUESTS", cls.keepalive_max_requests),
                   keepalive_max_s=_float_env("EPHEM_KEEPALIVE_MAX_S", cls.keepalive_max_s),
                   supervised=_bool_env("EPHEM_SUPERVISED", cls.supervised),
                   max_batch_rows=_int_env("EPHEM_MAX_BATCH_ROWS", cls.max_batch_rows),
                   model_cache_mb=model_cache_mb,
                   cache_max_age_s=_int_env("EPHEM_CACHE_MAX_AGE_S", cls.cache_max_age_s, minimum=0),
                   inline_cpu_ms=_float_env("EPHEM_INLINE_CPU_MS", cls.inline_cpu_ms, zero=True)).check()
