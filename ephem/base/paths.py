"""Where the shipped data live (the catalogue, the references, the reference tables, the lunar series)."""
from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path


def data_dir() -> Path:
    """Directory of the shipped data (catalogue, references, reference tables).

    ``$EPHEM_DATA_DIR`` overrides; otherwise the copy inside an installed wheel
    (``ephem/_data``) or the repository's ``data/``.

    Returns
    -------
    Path
        The data directory (read only: the user's own datasets go to
        :func:`ephem.bodies.datasets.user_catalogue_dir`).
    """
    env = os.environ.get("EPHEM_DATA_DIR")
    if env:
        return Path(env)
    return _shipped_data_dir()


@lru_cache(maxsize=1)
def _shipped_data_dir() -> Path:
    """The package's own data directory, found once per process (every answer asks for it)."""
    here = Path(__file__).resolve().parent.parent
    for candidate in (here / "_data", here.parent / "data"):
        if (candidate / "catalogue").is_dir():
            return candidate
    raise FileNotFoundError("ephem data directory not found (set EPHEM_DATA_DIR)")
