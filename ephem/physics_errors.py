"""Error terms from physics the fixed-orbit, rotation-averaged theories leave out.

* orbit motion: the real orbit is not the fixed Keplerian ellipse of the osculating
  elements; its plane turns and its mean motion differs from the osculating one.
* rotation averaging: the torque is averaged over the body's rotation; the full rigid
  body (:mod:`ephem.rigid`) keeps what that drops.

Radians and days.
"""
from __future__ import annotations

import numpy as np

from .catalogue import Body
from .model import PrecessionNutation


def orbit_motion_bound(body: Body, model: PrecessionNutation, jd_tdb: np.ndarray) -> float:
    return 0.0  # filled from data/orbit_motion.toml


def rotation_averaging_bound(model: PrecessionNutation, span_days: float) -> float:
    return 0.0  # filled from the rigid-body study


def real_orbit_unavailable(body: Body, jd_tdb: np.ndarray) -> str | None:
    return "not yet"


def ephemeris_bound(body: Body, model: PrecessionNutation, span_days: float) -> float:
    return 0.0


def sun_path_for(body: Body, jd_tdb: np.ndarray):
    raise NotImplementedError
