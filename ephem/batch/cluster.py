"""The Dask cluster of a batch: an existing one at a scheduler's address, or a local one, and its dashboard.

A local cluster is one single-threaded worker process per core, every socket on 127.0.0.1. The engine is
:mod:`ephem.batch.distributed`.
"""
from __future__ import annotations

import contextlib
import logging
import os

from ..base.errors import InvalidInputError


def _bokeh() -> bool:
    try:
        import bokeh  # noqa: F401
    except ImportError:
        return False
    return True


@contextlib.contextmanager
def dask_client(scheduler: str | None, workers: int | None):
    """A dask.distributed Client: on an existing cluster at ``scheduler``, or on a LocalCluster of ``workers``
    single-threaded processes, all bound to 127.0.0.1 (closed on exit)."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="20s", set_as_default=True)
        except (OSError, ValueError, TypeError) as exc:
            raise InvalidInputError("scheduler", f"cannot reach a dask scheduler at {scheduler!r}: {exc}") from None
        try:
            if workers is not None:
                try:
                    client.wait_for_workers(workers, timeout=120)
                except TimeoutError:
                    have = len(client.scheduler_info().get("workers", {}))
                    raise InvalidInputError("workers", f"{have} workers joined {scheduler} in 120 s, "
                                            f"{workers} asked for") from None
            yield client
        finally:
            client.close()
        return
    # The scheduler always serves HTTP (its health and metrics routes; with bokeh, the dashboard): on
    # dashboard_address=None it still takes 127.0.0.1:8787, where two runs at once would collide. Port 0:
    # a free loopback port, and the dashboard's familiar 8787 only when there is a dashboard to serve.
    # dask's nannies set MALLOC_TRIM_THRESHOLD_=65536 in a worker's environment (and in this process's): glibc
    # then maps and unmaps every array above 64 KiB afresh, and the core's numpy temporaries of a partition
    # make it 2.4 times slower (20 000 rows: 3.5 s -> 8.5 s, 9.6 s of it in the kernel). None unsets it.
    with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}):
        cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address="127.0.0.1:8787" if _bokeh() else "127.0.0.1:0",
                               silence_logs=logging.ERROR)
    try:
        with Client(cluster, set_as_default=True) as client:
            yield client
    finally:
        cluster.close()


def dashboard(client) -> str | None:
    """The dashboard's address, if the scheduler serves one: its HTTP port serves the dashboard only where
    bokeh is installed (else just health and metrics routes). Asked of the scheduler itself, by a function
    sent by value: a remote scheduler need not have ephem."""
    try:
        if not client.run_on_scheduler(lambda: __import__("importlib.util").util.find_spec("bokeh") is not None):
            return None
        return client.dashboard_link or None
    except Exception:  # noqa: BLE001 - no link is no reason to stop the batch
        return None
