"""The Earth's tables kept on disk (ephem.base.disk_cache) give what building them gives: the half peak-to-peak
of the nutation answer (ephem.earth.family.half_peak_to_peak), read back in a new process, and never another
series' value (the key hashes the terms)."""
from __future__ import annotations

import ast
import os
import subprocess
import sys

import numpy as np

from ephem.bodies.catalogue import get_body
from ephem.earth import family
from ephem.earth.estimates import window
from ephem.earth.model import lunisolar_earth


def direct(lm) -> tuple[float, float]:
    lo, hi = window()
    dpsi, deps = lm.series.nutation_at(np.arange(lo, hi + 0.25, 0.5))
    return 0.5 * float(np.ptp(dpsi)), 0.5 * float(np.ptp(deps))


def test_the_stored_half_peak_to_peak_is_the_built_one_and_each_series_has_its_own(tmp_path, monkeypatch):
    monkeypatch.setenv("EPHEM_CACHE_DIR", str(tmp_path))
    earth = get_body("earth")
    for cut in (0.1, 5.0):                  # two series under one directory: their keys differ
        lm = lunisolar_earth(earth, "figure", cut)
        family.half_peak_to_peak.cache_clear()
        built = family.half_peak_to_peak(lm)
        # exact: the same sums on the same CPU in one run, and a cache must give back the bits it stored
        assert built == direct(lm)
    assert len(list(tmp_path.glob("earth_half_peak_to_peak_*.npz"))) == 2
    # a new process reads the files (the bits of a float64 survive .npz)
    code = ("from ephem.bodies.catalogue import get_body; from ephem.earth import family; "
            "from ephem.earth.model import lunisolar_earth; "
            "print(repr(family.half_peak_to_peak(lunisolar_earth(get_body('earth'), 'figure', 5.0))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "EPHEM_CACHE_DIR": str(tmp_path)}).stdout
    assert ast.literal_eval(out.strip()) == direct(lunisolar_earth(earth, "figure", 5.0))
    assert direct(lunisolar_earth(earth, "figure", 5.0)) != direct(lunisolar_earth(earth, "figure", 0.1))
