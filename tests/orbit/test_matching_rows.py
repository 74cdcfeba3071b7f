"""ephem.orbit.harmonics.matching_rows against the dict of tuples it replaces (the Earth's spectrum a century on,
matched to today's harmonics, in ephem.earth.lunisolar._build): the same index, the last of repeated rows, -1 where
the row is absent."""
from __future__ import annotations

import numpy as np
import pytest

from ephem.orbit.harmonics import matching_rows


def dict_lookup(k, table):
    index = {tuple(row): i for i, row in enumerate(np.asarray(table).tolist())}
    return [index.get(tuple(row), -1) for row in np.asarray(k).tolist()]


@pytest.mark.parametrize("seed", range(5))
def test_matching_rows_finds_what_a_dict_of_tuples_finds(seed):
    rng = np.random.default_rng(seed)
    for _ in range(60):
        k = rng.integers(-4, 5, size=(int(rng.integers(0, 50)), 5))
        table = rng.integers(-4, 5, size=(int(rng.integers(0, 50)), 5))
        table = np.concatenate([table, k[: len(k) // 2], table[: len(table) // 3]])   # hits and repeats
        assert matching_rows(k, table).tolist() == dict_lookup(k, table)


def test_the_earths_spectrum_rows_match_a_century_on():
    from ephem.earth.lunisolar import DEFAULT_GRID, orbital_spectrum
    now, later = orbital_spectrum(("moon", "sun"), 0.0, DEFAULT_GRID), orbital_spectrum(("moon", "sun"), 1.0, DEFAULT_GRID)
    rows = matching_rows(now.multipliers, later.multipliers)
    assert rows.tolist() == dict_lookup(now.multipliers, later.multipliers)
    assert (rows >= 0).mean() > 0.9       # the spectrum barely changes in a century: nearly every harmonic is there
