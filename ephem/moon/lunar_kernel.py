"""JPL's DE421 lunar orientation, read where the install put it: its Euler angles and frame kernel.

The principal-axis frame's Euler angles (binary PCK
``moon_pa_de421_1900-2050.bpc``) and the frame kernel defining the mean-Earth frame (``moon_080317.tf``), both shipped
in the wheel of the registry package ``lunarsky`` (pyproject.toml's ``lunar`` extra; data/moon_orientation.toml [kernel]).

The files are found through the installed distribution's file list (:func:`importlib.metadata.files`): the package is
never imported (it would load astropy's frame machinery and its own dependencies for two data files). The binary
PCK is read with jplephem (already a dependency, through skyfield): its type-2 segments are Chebyshev pieces of the
3-1-3 Euler angles (φ, θ, ψ) of the PA frame from the ICRF, the rotation ICRF → PA being [ψ]_3 [θ]_1 [φ]_3 (SPICE's
frame rotations; tests/moon/test_against_de421_moon.py checks it against CSPICE). Without the package the kernel is
unavailable, with the reason (:func:`unavailable`). Radians, JD TDB.
"""
from __future__ import annotations

import hashlib
import threading
from functools import lru_cache
from importlib import metadata
from pathlib import Path

import numpy as np

from ..base.paths import data_dir
from ..base.disk_cache import read_toml
from .orientation import frame_rotation


@lru_cache(maxsize=1)
def kernel_data() -> dict:
    """data/moon_orientation.toml [kernel]: the package, the files' paths in it, their hashes and DE421's accuracy."""
    return read_toml(data_dir() / "moon_orientation.toml")["kernel"]


@lru_cache(maxsize=1)
def _located() -> tuple[Path | None, Path | None, str | None]:
    """(binary PCK, frame kernel, None) where the package's files are installed, else (None, None, why)."""
    k = kernel_data()
    try:
        listed = metadata.files(k["package"]) or []
    except metadata.PackageNotFoundError:
        return None, None, (f"DE421's lunar orientation ships in the package '{k['package']}' (the lunar extra: "
                            f"pip install 'ephem-asteroid-pn[lunar]'), which is not installed")
    found = {str(f).replace("\\", "/"): f for f in listed}
    paths = []
    for key in ("pck", "frame_kernel"):
        entry = found.get(k[key])
        path = None if entry is None else Path(entry.locate())
        if path is None or not path.is_file():
            return None, None, f"the package '{k['package']}' is installed without its file {k[key]}"
        paths.append(path)
    return paths[0], paths[1], None


def unavailable() -> str | None:
    """Why DE421's lunar orientation cannot be read here (the package or a file missing), or None."""
    return _located()[2]


def kernel_paths() -> tuple[Path, Path]:
    """(binary PCK, frame kernel) paths; :class:`FileNotFoundError` with the reason when not installed."""
    pck, fk, why = _located()
    if why is not None:
        raise FileNotFoundError(why)
    return pck, fk


def file_sha256(path: Path) -> str:
    """The SHA-256 of a file (hex): the tests check the installed kernels are the ones data/moon_orientation.toml
    names."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


_lock = threading.Lock()


@lru_cache(maxsize=1)
def _segment():
    """The PCK's one segment (body 31006, MOON_PA_DE421, relative to the ICRF), opened once per process."""
    from jplephem.pck import PCK      # jplephem: skyfield's dependency, loaded only when the kernel is read

    pck = PCK.open(str(kernel_paths()[0]))
    body = int(kernel_data()["body"])
    segments = [s for s in pck.segments if s.body == body and s.frame == 1 and s.data_type == 2]
    if len(segments) != 1:
        raise ValueError(f"expected one type-2 segment of body {body} relative to the ICRF, found {len(segments)}")
    return segments[0]


#: whether this process has read the kernel's coefficients (jplephem maps them on the first evaluation)
_read = [False]


def kept() -> bool:
    """Whether this process has read the kernel's coefficients once (the first read maps the file and loads its
    segment: the cost model charges it until then; opening it for its span, as the estimates do, reads only the
    summary)."""
    return _read[0]


@lru_cache(maxsize=1)
def span() -> tuple[float, float]:
    """(first, last) JD TDB of the kernel's segment (JD 2415020.5 to 2470172.5: 1900-01-01 to 2051-01-01)."""
    s = _segment()
    return float(s.initial_jd), float(s.final_jd)


def euler_angles(jd_tdb) -> np.ndarray:
    """DE421's (φ, θ, ψ) of the PA frame from the ICRF at JD TDB (3, N), radians; the epochs must lie in :func:`span`."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    day = np.floor(t)
    with _lock:               # jplephem loads the segment's coefficients on first use
        out = np.asarray(_segment().compute(day, t - day, False), dtype=float).reshape(3, -1)
        _read[0] = True
        return out


def pa_axes_icrf(jd_tdb) -> np.ndarray:
    """DE421's principal axes in the ICRF, (N, 3, 3), columns X (toward the mean Earth, least inertia), Y, Z (the
    axis of largest inertia): the transpose of ICRF → PA = [ψ]_3 [θ]_1 [φ]_3."""
    phi, theta, psi = euler_angles(jd_tdb)
    to_pa = frame_rotation(psi, 3) @ frame_rotation(theta, 1) @ frame_rotation(phi, 3)
    return np.swapaxes(to_pa, -1, -2)
