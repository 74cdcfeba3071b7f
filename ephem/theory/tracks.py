"""What every family's track shares: pole vectors, the free wobble, the checks of axis and tolerance.

The free wobble is carried into the track's angles; the checks are of a request's axis, wobble and tolerance."""
from __future__ import annotations

import math

import numpy as np

from ..base.constants import AXES
from ..base.errors import InvalidInputError
from ..forced.precession_nutation import PrecessionNutation, Track


def pole_vectors(track: Track) -> np.ndarray:
    """ICRF unit vectors (N, 3) of a track's pole."""
    cd = np.cos(track.pole_dec)
    return np.stack([cd * np.cos(track.pole_ra), cd * np.sin(track.pole_ra), np.sin(track.pole_dec)], axis=-1)


def with_free_wobble(model: PrecessionNutation, track: Track, figure_icrf: np.ndarray) -> Track:
    """The track of the figure axis: ``track`` (of the angular momentum) moved to the vectors ``figure_icrf``;
    the wobble's share of ψ and ε goes into Δψ and Δε."""
    s = figure_icrf @ model.icrf_from_orbit
    raw = np.arctan2(s[:, 0], s[:, 1])
    psi = track.psi + np.remainder(raw - track.psi + math.pi, 2.0 * math.pi) - math.pi
    eps = np.arctan2(np.hypot(s[:, 0], s[:, 1]), s[:, 2])
    ra = np.arctan2(figure_icrf[:, 1], figure_icrf[:, 0])
    ra += (ra < 0.0) * (2.0 * math.pi)
    dec = np.arctan2(figure_icrf[:, 2], np.hypot(figure_icrf[:, 0], figure_icrf[:, 1]))
    return Track(track.jd_tdb, psi, track.delta_psi + (psi - track.psi), track.delta_epsilon + (eps - track.obliquity),
                 eps, ra, dec)


def check_axis(axis: str, body: str | None = None) -> None:
    """Refuse a pole that is not one of :data:`ephem.base.constants.AXES`."""
    if axis not in AXES:
        raise InvalidInputError("axis", f"must be one of {', '.join(AXES)}, got {axis!r}", body)


def check_wobble_axis(axis: str, body: str | None = None) -> None:
    """Refuse a free wobble asked for a pole it does not move (it moves the figure axis only)."""
    if axis != "figure":
        raise InvalidInputError("free_wobble_phase_deg", f"the free wobble moves the figure axis, and axis={axis} "
                                "does not follow it (the angular momentum is not moved by it; the forced figure axis "
                                "leaves it to polar motion): ask for axis=figure", body)


def check_tolerance(tolerance, body: str | None = None, unit: str = "") -> None:
    """Refuse a tolerance that is not a positive finite number (``unit``: words naming its unit in the message)."""
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or not math.isfinite(tolerance) \
            or tolerance <= 0.0:
        raise InvalidInputError("tolerance_mas", f"must be a positive finite number{unit}, got {tolerance!r}", body)
