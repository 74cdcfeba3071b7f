"""What every family's track shares: the poles it may follow, the rounding of its numbers, its pole vectors and
the free wobble carried into its angles."""
from __future__ import annotations

import math

import numpy as np

from ..forced.precession_nutation import PrecessionNutation, Track

#: The poles a track can follow (see the module docstring).
AXES = ("figure", "angular_momentum")

#: Rounding floor of any pole computed in double precision through a few rotations (radians, 0.2 µas).
ROUNDING = 1e-12


def pole_vectors(track: Track) -> np.ndarray:
    """ICRF unit vectors (N, 3) of a track's pole."""
    cd = np.cos(track.pole_dec)
    return np.stack([cd * np.cos(track.pole_ra), cd * np.sin(track.pole_ra), np.sin(track.pole_dec)], axis=-1)


#: What to tell a user when the largest term of the best estimate is one no rung removes.
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
