"""The cost predictors (ephem.theory.cost) against what the work they predict does: the harmonic work table the cost
model allows is the one ephem.orbit.harmonics caps. Moved from tests/service/test_bounded_work.py (issue 43: the
tests mirror the packages); the corrections are measured in benchmarks/RESULTS_cost.md."""
from __future__ import annotations

import pytest

from ephem.orbit import harmonics
from ephem.theory import cost


def test_the_harmonic_work_table_the_cost_model_allows_is_the_one_harmonics_caps():
    assert cost.unit_costs()["harmonic_block_mb"] * 2**20 == pytest.approx(harmonics.BLOCK_BYTES, rel=0, abs=0.5)
    assert cost.harmonic_work_mb(10**6, 40_000) == pytest.approx(32.0, rel=1e-12)
    assert cost.harmonic_work_mb(100, 10) < 0.1
