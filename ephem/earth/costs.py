"""What the Earth's lunisolar theory will cost before it runs: its predictors, with its own unit costs.

The units are in ``data/earth_costs.toml``, measured by ``benchmarks/bench_cost.py`` as the shared ones of
``data/cost_model.toml`` (:mod:`ephem.theory.cost`, whose units every family's answers share: a track's answer, the
serialisation); each family keeps its own predictors and table, so a new family adds its own beside them (issue 43).
"""
from __future__ import annotations

from ..base.budget import Part
from ..theory.cost import MB, unit, unit_table

#: the Earth's table of unit costs, in data/
TABLE = "earth_costs.toml"


def _u(key: str) -> float:
    return float(unit_table(TABLE)[key])


def lunisolar_estimates(models: int = 1) -> Part:
    """The Earth's track estimates (:func:`ephem.earth.estimates.estimates`) of ``models`` models: each its terms
    against IAU 2006/2000A over the span from the kept series (a fixed part: the epochs enter through their span)."""
    return Part("step_days", f"the error estimates of {models} model{'s' if models != 1 else ''}",
                models * _u("lunisolar_estimates_s"), 1.0)


def lunisolar_sum(epochs: int) -> Part:
    """The Earth's lunisolar series at ``epochs`` epochs (the Delaunay arguments, the term products)."""
    return Part("step_days", f"the lunisolar series at {epochs} epochs", epochs * _u("lunisolar_epoch_s"),
                epochs * unit("track_bytes_per_epoch") / MB)


def nonrigid_sum(epochs: int) -> Part:
    """The non-rigid Earth's track beyond the lunisolar series' sum: the transfer function's series (built once per
    process, as the rigid one) and ERFA's IAU 2006 precession and rotation matrix at every epoch."""
    return Part("step_days", f"the IAU 2006 precession (ERFA) at {epochs} epochs", epochs * _u("nonrigid_epoch_s"),
                epochs * unit("track_bytes_per_epoch") / MB)


def lunisolar_answer() -> Part:
    """The Earth under the Moon and the Sun: the lunisolar series are built once per process (at the
    service's start-up, ``EPHEM_WARM_UP``); an answer reads them."""
    return Part("perturbers", "the lunisolar series (built at start-up)", _u("lunisolar_answer_s"), 5.0)
