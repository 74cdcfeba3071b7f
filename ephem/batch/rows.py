"""A bad row marked in a batch core's output columns: its reason in ``error``, NaN or "" in the rest.

Apart from the core (:mod:`ephem.batch.population`, which re-exports it) so that the engine's task
(:mod:`ephem.batch.task`) takes it without importing the theory: the engine's imports stay shallow.
"""
from __future__ import annotations

from collections.abc import Mapping

import numpy as np


def spoil_rows(result: Mapping, bad: Mapping[int, str]) -> dict:
    """``result`` (output columns of :func:`ephem.batch.population.evaluate`, or of another batch core) with the rows in ``bad`` marked
    as the core marks a row it cannot take: ``bad[j]`` in ``error``, NaN or "" elsewhere (``name`` kept). For the
    rows whose input the reader could not parse (a cell that is not a number): ``ephem batch`` and the service's
    POST /v1/batch both mark them here."""
    if not bad:
        return {key: np.asarray(value) for key, value in result.items()}
    rows = np.fromiter(bad, dtype=np.intp)
    out = {}
    for key, value in result.items():
        value = np.asarray(value)
        if key != "name":
            text = value.dtype.kind not in "fiub"
            value = value.astype(object if text else np.float64)    # a copy; fixed-width text would cut a reason
            value[rows] = "" if text else np.nan
            if key == "error":
                for j, reason in bad.items():
                    value[j] = reason
        out[key] = value
    return out
