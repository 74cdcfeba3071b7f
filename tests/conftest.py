"""Settings every test process shares, and shared fixtures.

* One BLAS/OpenMP thread per process, set before numpy loads its BLAS. The suite runs under
  ``pytest -n 2`` (one process per core): a multi-threaded BLAS in each worker oversubscribes the
  cores, and on a many-core host given two CPUs (a container, a CI runner) OpenBLAS starts one
  thread per *host* core in each worker. Measured on two shared cores: the IAU 2000A fit of
  tests/earth/test_against_erfa.py (a 34786 x 190 least-squares problem) takes 2.8 s with one thread and
  8.1 s with 16, and it grows with the thread count. Single-threaded
  BLAS also fixes the order of its sums. An explicit setting in the environment wins.
* Hypothesis is derandomized (the same examples on every machine and every run), keeps no example
  database (nothing written, nothing replayed from an earlier run) and has no deadline (timings
  differ between machines; the tests that care measure their own cost). Tests set their own
  ``max_examples``. ``HYPOTHESIS_PROFILE=explore`` draws fresh random examples for a local hunt.
* The user catalogue directory (``ephem catalogue import``'s datasets) is an empty one of each test process's
  own: the datasets a user imported on this machine must not enter the tests (tests that import set their own).
* So is the disk cache of built tables (``EPHEM_CACHE_DIR``, :mod:`ephem.base.disk_cache`): a table built by another
  run (another numpy, or numpy held to its baseline SIMD path) must not be read here.
"""
import os
import tempfile

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
             "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
os.environ["EPHEM_USER_CATALOGUE_DIR"] = tempfile.mkdtemp(prefix="ephem-test-user-catalogue-")
os.environ["EPHEM_CACHE_DIR"] = tempfile.mkdtemp(prefix="ephem-test-cache-")

import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

from ephem.bodies.catalogue import Body, Orbit, Pole  # noqa: E402



def pytest_report_header(config):
    """Which of numpy's SIMD paths this run takes: .ci/run runs the suite on the CPU's and on the baseline's."""
    from numpy._core._multiarray_umath import __cpu_baseline__, __cpu_dispatch__, __cpu_features__

    on = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]
    held = os.environ.get("NPY_DISABLE_CPU_FEATURES", "")
    return (f"numpy SIMD: baseline {' '.join(__cpu_baseline__)}; dispatching to {' '.join(on) or 'nothing above it'}"
            + (f" (NPY_DISABLE_CPU_FEATURES={held!r})" if held else ""))


settings.register_profile("ephem", derandomize=True, database=None, deadline=None)
settings.register_profile("explore", derandomize=False, database=None, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ephem"))


@pytest.fixture
def vesta_like():
    """A Vesta-like body built in code (independent of the catalogue files)."""
    return Body("Vesta-like", Orbit(2.3615413, 0.0901676, 7.14406, 103.70232, 151.53711, 26.80969, 2461000.5),
                Pole(309.031, 42.2264), 5.3421, moments=(0.3433, 0.3546, 0.42))


# --- fixtures several suites share (one definition each; the library caches the objects as well)

@pytest.fixture(scope="session")
def nf():
    """Lara's normal form of the free rigid body at the order the Lie-series suites use."""
    from ephem.rotation.lie_series import sam_normal_form
    from tests.rotation.test_lie_series import ORDER

    return sam_normal_form(ORDER)


@pytest.fixture(scope="session")
def generated(nf):
    """Lara (2014) Tables 2-5 as our normal form generates them."""
    return nf.lara2014_tables()


@pytest.fixture(scope="session")
def moderate_reference():
    """β = 1/2, J = 35° (δ = 0.139), two polhode periods: quaternion route (m and g)."""
    import math

    import numpy as np

    from ephem.rotation.sam_series import SamParameters
    from tests.rotation.test_lie_series import MODERATE, _initial_m, _reference_quaternion

    p = SamParameters(*MODERATE)
    t = np.linspace(0.0, 2 * 2 * math.pi / p.kappa, 400)
    m0 = _initial_m(math.radians(35.0), 0.3)
    m, g = _reference_quaternion(MODERATE, m0, t)
    return m0, t, m, g


def run_quick_charts(tasks, out, count: int):
    """Run a study's ``tasks(out, quick=True)`` into ``out``: ``count`` labelled jobs, each run once."""
    jobs = tasks(out, quick=True)
    assert len(jobs) == count
    for label, job in jobs:
        assert isinstance(label, str) and label
        job()
    return out


@pytest.fixture(scope="session")
def rigid():
    """The Earth's rigid lunisolar series: figure axis, IERS 2010 H_d, 0.1 mas cut (compared with IAU 2000A)."""
    from ephem.earth import lunisolar

    return lunisolar.earth_lunisolar(cut_mas=0.1, hd="iers2010")
