"""The gunicorn settings of the service (``make serve``, the Dockerfile): a supervisor over uvicorn workers.

gunicorn's master restarts a worker that dies (``kill -9``, a crash) or stops answering its heartbeat
for ``timeout`` seconds (stuck in compiled code holding the interpreter). Each worker gets an
address-space ceiling (``EPHEM_WORKER_MEMORY_MB``): an allocation beyond it raises ``MemoryError``,
answered 503, instead of the kernel's OOM killer taking the machine's memory first. The service's
own watchdog (``service/guards.py``, armed here by ``EPHEM_SUPERVISED``) ends a worker whose request
overstays its deadline, hands the allocator's freed memory back, and recycles a worker that keeps more
after its requests than ``EPHEM_WORKER_RSS_MB`` (the bound with its requests in flight) less their allowance and
the slack (one at a time).

Bind address and worker count come from the command line (``--bind``, ``--workers``).
"""
import os
import resource
import shutil
import tempfile

from service.settings import Settings

# the app reads this when each worker imports it: the watchdog may end a worker, the master replaces it
os.environ.setdefault("EPHEM_SUPERVISED", "1")
# One BLAS thread per worker: a worker is one core's worth of work, which the cost predictions and the
# turns of large requests count on. With BLAS's own threads an e = 0.95 track took 2.2-13.6 s of CPU
# in three runs against a steady 1.3 s on one thread (benchmarks/RESULTS_cost.md). Set before the
# workers import numpy; an operator's own setting is kept.
for _blas in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_blas, "1")
# the workers share the slots of large requests (service/guards.py) through lock files here
_own_lock_dir = "EPHEM_LOCK_DIR" not in os.environ
os.environ.setdefault("EPHEM_LOCK_DIR", tempfile.mkdtemp(prefix="ephem-service-"))
_settings = Settings.from_env()

# uvicorn's worker with the request head capped at EPHEM_MAX_HEADER_BYTES (431 beyond: service/server.py)
worker_class = "service.server.Worker"
# a worker silent this long is killed and replaced: the deadline plus the watchdog's grace, plus slack
timeout = int(_settings.request_deadline_s + _settings.hard_kill_after_s + 15)
graceful_timeout = 20
# the app is imported by each worker after the fork (no preload): the memory ceiling below then covers
# everything a worker allocates, and a worker's crash cannot take the master's copy with it
preload_app = False
# No recycling after a count of requests by default: under steady load the workers reach the count
# together, and a new worker takes seconds to import and warm up, so the service stopped answering
# for 7-10 s and dropped keep-alive requests (benchmarks/RESULTS_load.md). Memory is bounded by the
# watchdog instead (EPHEM_WORKER_RSS_MB), which recycles one worker at a time, spaced apart.
# EPHEM_MAX_REQUESTS turns the count on (with a jitter of half of it, so workers recycle apart).
max_requests = int(os.environ.get("EPHEM_MAX_REQUESTS") or 0)
max_requests_jitter = max_requests // 2
keepalive = 5
# gunicorn 27 shares one control socket per user (~/.gunicorn): two services of one user would collide
control_socket_disable = True
accesslog = "-"


def post_fork(server, worker):
    ceiling = int(_settings.worker_memory_mb * 2**20)
    resource.setrlimit(resource.RLIMIT_AS, (ceiling, ceiling))
    server.log.info("worker %s: address-space ceiling %d MB", worker.pid, _settings.worker_memory_mb)


def on_exit(server):
    if _own_lock_dir:
        shutil.rmtree(os.environ["EPHEM_LOCK_DIR"], ignore_errors=True)
