"""service/offload.compute: a request's work on the event loop reports to the request's own budget."""
import asyncio
import threading

import pytest

from ephem.base.budget import Cost, Part
from ephem.host import budget, charge
from service.offload import compute


def _charged(memory_mb: float):
    def work():
        charge(Cost((Part("epochs", "a test's work", 1e-6, memory_mb),)), "Vesta")
        return threading.current_thread() is threading.main_thread()
    return work


@pytest.mark.parametrize("memory_mb", [0.5, 12.0])
def test_work_on_the_event_loop_gives_its_peak_memory_to_the_request(memory_mb):
    """The worker returns a large request's freed memory by the request's peak (service/guards.py): work run on
    the loop under its own nested budget must not hide that peak."""
    async def main():
        with budget(1.0, 100.0, 10.0) as outer:
            on_loop = await compute(5.0, _charged(memory_mb))
        return on_loop, outer.peak_memory_mb

    on_loop, peak = asyncio.run(main())
    assert on_loop                                   # it ran inline, not in the thread pool
    assert peak == pytest.approx(memory_mb, rel=1e-12)
