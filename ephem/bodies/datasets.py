"""Where the datasets of bodies live, and which there are: the shipped ones and a user's own.

The shipped ones are in ``data/catalogue/``; a user's own are imported by ``ephem catalogue import`` into
:func:`user_catalogue_dir` (docs/catalogue_import.md).

A shipped dataset shadows a user's of the same name (in any case); :mod:`ephem.bodies.catalogue` loads either.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

from ..base.paths import data_dir


#: the name a user dataset may take (its file is NAME.toml in :func:`user_catalogue_dir`)
DATASET_NAME = r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}"


def user_catalogue_dir() -> Path | None:
    """Directory of the user's own datasets (``ephem catalogue import``, docs/catalogue_import.md):
    ``$EPHEM_USER_CATALOGUE_DIR``, else ``$XDG_DATA_HOME/ephem/catalogue``, else
    ``~/.local/share/ephem/catalogue``; None when there is no home directory to put it in.

    Returns
    -------
    Path or None
        The directory (it may not exist yet: the first import makes it), or None.
    """
    env = os.environ.get("EPHEM_USER_CATALOGUE_DIR")
    if env:
        return Path(env).expanduser()
    xdg = os.environ.get("XDG_DATA_HOME")
    if xdg and Path(xdg).is_absolute():
        return Path(xdg) / "ephem" / "catalogue"
    try:
        return Path.home() / ".local" / "share" / "ephem" / "catalogue"
    except (RuntimeError, KeyError):
        return None


def shipped_datasets() -> list[str]:
    """The datasets shipped in ``data/catalogue/`` ("current", "petit2014")."""
    return sorted(p.stem for p in (data_dir() / "catalogue").glob("*.toml"))


def _user_dataset_files() -> dict[str, Path]:
    """The user's datasets (name -> file) that no shipped dataset shadows (names compared in any case)."""
    where = user_catalogue_dir()
    if where is None or not where.is_dir():
        return {}
    shipped = {s.lower() for s in shipped_datasets()}
    return {p.stem: p for p in sorted(where.glob("*.toml"))
            if re.fullmatch(DATASET_NAME, p.stem) and p.stem.lower() not in shipped and p.is_file()}


def dataset_file(dataset: str) -> Path | None:
    """The file of ``dataset``: a shipped one first, then the user's (:func:`user_catalogue_dir`)."""
    if not isinstance(dataset, str) or not re.fullmatch(DATASET_NAME, dataset):
        return None
    shipped = data_dir() / "catalogue" / f"{dataset}.toml"
    if shipped.is_file():
        return shipped
    return _user_dataset_files().get(dataset)


def available_datasets() -> list[str]:
    """The shipped datasets (sorted), then the user's imported ones (sorted; docs/catalogue_import.md).

    Returns
    -------
    list of str
        The datasets' names, each one a ``dataset=`` argument takes.
    """
    return shipped_datasets() + sorted(_user_dataset_files())
