"""Write the Moon's forced physical librations (ephem.moon.physical_librations) for the moments the library uses: the
catalogues' (Lara 2014 Table 1, both datasets) and the effective ones (EFFECTIVE_BETA_GAMMA), to
data/moon_librations/*.csv, so that a request reads them instead of building them (about 2 s each).

    python -m tools.derive_moon_librations

tests/moon/test_physical_librations.py checks the shipped files against a fresh build.
"""
from __future__ import annotations

from ephem.bodies.catalogue import get_body
from ephem.bodies.datasets import available_datasets
from ephem.base.paths import data_dir
from ephem.moon.libration_series import SHIPPED_DIR, write_series_csv
from ephem.moon.physical_librations import EFFECTIVE_MOMENTS, moon_physical_librations


def main() -> None:
    sets = {"effective": EFFECTIVE_MOMENTS}
    sets.update({f"catalogue_{ds}": get_body("moon", ds).moments for ds in available_datasets()})
    seen = set()
    out = data_dir() / SHIPPED_DIR
    out.mkdir(exist_ok=True)
    for name, moments in sets.items():
        key = tuple(float(x) for x in moments)
        if key in seen:
            continue
        seen.add(key)
        path = out / f"{name}.csv"         # a moment set two datasets share is written once, under the first
        write_series_csv(moon_physical_librations(key), path)
        print(f"wrote {path} ({len(moon_physical_librations(key))} terms)")


if __name__ == "__main__":
    main()
