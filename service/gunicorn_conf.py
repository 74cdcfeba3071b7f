"""gunicorn settings for the service (``make serve``, the Dockerfile): a supervisor over uvicorn workers.

gunicorn's master restarts a worker that dies (``kill -9``, a crash) or stops answering its heartbeat
for ``timeout`` seconds (stuck in compiled code holding the interpreter). Each worker gets an
address-space ceiling (``EPHEM_WORKER_MEMORY_MB``): an allocation beyond it raises ``MemoryError``,
answered 503, instead of the kernel's OOM killer taking the machine's memory first. The service's
own watchdog (``service/guards.py``, armed here by ``EPHEM_SUPERVISED``) ends a worker whose request
overstays its deadline, and recycles one that keeps too much memory after its requests.

Bind address and worker count come from the command line (``--bind``, ``--workers``).
"""
import os
import resource

from service.settings import Settings

# the app reads this when each worker imports it: the watchdog may end a worker, the master replaces it
os.environ.setdefault("EPHEM_SUPERVISED", "1")
_settings = Settings.from_env()

worker_class = "uvicorn_worker.UvicornWorker"
# a worker silent this long is killed and replaced: the deadline plus the watchdog's grace, plus slack
timeout = int(_settings.request_deadline_s + _settings.hard_kill_after_s + 15)
graceful_timeout = 20
# the app is imported by each worker after the fork (no preload): the memory ceiling below then covers
# everything a worker allocates, and a worker's crash cannot take the master's copy with it
preload_app = False
# recycle workers now and then: numpy's freed arenas are not always returned to the system
max_requests = 5000
max_requests_jitter = 500
keepalive = 5
# gunicorn 27 shares one control socket per user (~/.gunicorn): two services of one user would collide
control_socket_disable = True
accesslog = "-"


def post_fork(server, worker):
    ceiling = int(_settings.worker_memory_mb * 2**20)
    resource.setrlimit(resource.RLIMIT_AS, (ceiling, ceiling))
    server.log.info("worker %s: address-space ceiling %d MB", worker.pid, _settings.worker_memory_mb)
