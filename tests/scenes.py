"""Shared helpers for the tests: synthetic bodies (a pole at a chosen obliquity on a chosen orbit), a cap on the
memory a property sweep may take, and the first-order theory's order-of-magnitude error bound the tests budget with."""
import contextlib
import os

from ephem.bodies.catalogue import Body, Orbit, Pole
from ephem.forced.kinoshita import eccentricity_factor


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


def first_order_error_bound(model, span_days: float) -> float:
    """Estimated upper bound (radians) on the pole error the first-order theory leaves over a span, for a
    :class:`ephem.forced.precession_nutation.PrecessionNutation` ``model``.

    Two second-order effects grow with time: the equinox drifts by ψ̇ T while the nutation phases are held fixed
    (error ≲ 2 A |ψ̇| T, A the largest nutation semi-amplitude), and the nutation feeds back into the torque's
    coefficients (a secular drift ≲ K² f(e)² T / (8 n), f(e) = (1 - e²)^(-3/2)). Order-of-magnitude: the tests
    check that the numerical integration never exceeds it (the library's estimates are the ladder's own bounds,
    ephem.sun.bounds; this one lived on the model, used by nothing but these tests, until issue 43).
    """
    half_psi, half_eps = model.nutation.semi_peak_to_peak()
    amp = max(half_psi, half_eps)
    f = eccentricity_factor(model.eccentricity)
    rate = 2.0 * amp * abs(model.precession_rate) + model.scaling_factor**2 * f * f / (8.0 * model.mean_motion)
    return abs(span_days) * rate
