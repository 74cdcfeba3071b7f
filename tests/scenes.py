"""Shared helpers for the tests: synthetic bodies (a pole at a chosen obliquity on a chosen orbit), and a
cap on the memory a property sweep may take."""
import contextlib
import os

from ephem.bodies.catalogue import Body, Orbit, Pole


def synthetic_body(e=0.1, obliquity_deg=30.0, hd=0.1, period_hours=5.0, a_au=2.0, node_of_equator_deg=40.0,
                   peri_deg=70.0, mean_anomaly_deg=0.0, name="synthetic", moments=None) -> Body:
    """A body on an orbit in the ecliptic whose pole stands at a chosen obliquity."""
    return Body(name, Orbit(a_au, e, 0.0, 0.0, peri_deg, mean_anomaly_deg, 2451545.0),
                Pole.from_ecliptic(node_of_equator_deg - 90.0, 90.0 - obliquity_deg),
                period_hours, dynamical_ellipticity=None if moments else hd, moments=moments)


@contextlib.contextmanager
def address_space_cap(extra: int):
    """Cap this process's address space (Linux RLIMIT_AS) at its present size plus ``extra`` bytes.

    For sweeps over the whole valid domain (Hypothesis): a runaway allocation then fails as a MemoryError
    that names the example, instead of the OOM killer taking the worker (or the machine). Elsewhere, or
    when a tighter cap is already set, it does nothing.
    """
    try:
        import resource
        with open("/proc/self/statm") as fh:
            size = int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (ImportError, OSError, ValueError):
        yield
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    cap = size + extra if hard == resource.RLIM_INFINITY else min(size + extra, hard)
    if soft != resource.RLIM_INFINITY and soft <= cap:
        yield
        return
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
