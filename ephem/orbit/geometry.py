"""Spin-pole and orbit geometry: obliquity, the body's equinox, the angle to pericentre.

References: Petit, Souchay & Lhotka (2014), A&A 565, A79, sect. 4.2-4.3, eqs. 26-29.
The printed equations have sign slips (eq. 26's second component, eq. 27's
second component) and eq. 29 takes an arccos, which loses the sign of the
angle. Here everything is done with vectors and signed angles (atan2).

Frames: poles are given in the ICRF (RA, Dec); orbits in the ecliptic and
equinox J2000. The ICRF -> ecliptic rotation is astropy's
``BarycentricMeanEcliptic(equinox="J2000")``, taken from ERFA ``ecm06`` as
astropy does (IAU 2006 obliquity at J2000 and the ICRS frame bias); it is
computed once and cached.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..base.errors import InvalidInputError
from .kepler import orbit_basis


@lru_cache(maxsize=1)
def icrf_to_ecliptic_matrix() -> np.ndarray:
    """3x3 rotation taking ICRF unit vectors to the mean ecliptic and equinox J2000.

    Returns
    -------
    numpy.ndarray
        The (3, 3) rotation matrix (dimensionless): ``M @ v_icrf`` is the vector in the J2000 ecliptic frame (ERFA's
        ``ecm06`` at J2000.0 TT: the frame bias and the IAU 2006 obliquity, 84381.406 arcsec). Kept and shared by
        every caller: do not change it in place.
    """
    # erfa, not astropy.coordinates (0.1-0.2 s to import and build the frame graph): astropy's
    # ICRS -> BarycentricMeanEcliptic(equinox="J2000") is this same call at J2000.0 TT (agree to 1e-16)
    import erfa

    return erfa.ecm06(2451545.0, 0.0)


def unit_vector(lon, lat) -> np.ndarray:
    """Unit vector(s) from longitude and latitude in radians; last axis is xyz."""
    lon = np.asarray(lon, dtype=float)
    lat = np.asarray(lat, dtype=float)
    return np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=-1)


def lon_lat(vec) -> tuple[np.ndarray, np.ndarray]:
    """Longitude in [0, 2π) and latitude (radians) of vector(s) along the last axis."""
    vec = np.asarray(vec, dtype=float)
    x, y, z = vec[..., 0], vec[..., 1], vec[..., 2]
    lon = np.remainder(np.arctan2(y, x), 2.0 * math.pi)
    lat = np.arctan2(z, np.hypot(x, y))
    return lon, lat


def angle_between(u, v) -> np.ndarray:
    """Angles (radians) between unit vectors along the last axis, accurate at small angles (atan2 of |u×v| and
    u·v, where an arccos loses half the digits)."""
    u, v = np.asarray(u, dtype=float), np.asarray(v, dtype=float)
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), np.sum(u * v, axis=-1))


def carry(a, b, v) -> np.ndarray:
    """Vectors ``v`` (..., 3) turned by the rotation taking the unit vector ``a`` to ``b`` about a × b (Rodrigues;
    the identity where b = a). ``a``, ``b`` and ``v`` broadcast along their leading axes."""
    a, b, v = (np.asarray(x, dtype=float) for x in (a, b, v))
    axis = np.cross(a, b)
    s = np.linalg.norm(axis, axis=-1, keepdims=True)
    c = np.sum(a * b, axis=-1, keepdims=True)
    k = np.divide(axis, s, out=np.zeros_like(axis), where=s > 0.0)
    return v * c + np.cross(k, v) * s + k * (np.sum(k * v, axis=-1, keepdims=True) * (1.0 - c))


def icrf_to_ecliptic(ra: float, dec: float) -> np.ndarray:
    """Ecliptic-J2000 unit vector of an ICRF direction (ra, dec in radians)."""
    return icrf_to_ecliptic_matrix() @ unit_vector(ra, dec)


def ecliptic_to_icrf(lon: float, lat: float) -> np.ndarray:
    """ICRF unit vector of an ecliptic-J2000 direction (lon, lat in radians)."""
    return icrf_to_ecliptic_matrix().T @ unit_vector(lon, lat)


@dataclass(frozen=True)
class SpinGeometry:
    """Where the spin axis stands relative to the orbit.

    Attributes
    ----------
    obliquity : angle between the orbit normal and the spin axis, radians in [0, π].
    equinox : unit vector (ecliptic J2000) of the body's equinox γ, the
        ascending node of the orbit on the body's equator: s × W / |s × W|.
        The Sun, seen from the body, crosses the equator northward there.
    equinox_to_pericentre : signed angle from γ to the pericentre, measured in
        the orbit plane in the direction of motion (radians). The Sun's
        longitude from γ is then λ = this + ν (+π, which drops out of 2λ).
        Petit et al.'s ω + 180° − Λ.
    orbit_frame : 3x3 matrix whose rows are (γ, W × γ, W) in ecliptic J2000: it
        takes ecliptic vectors to the frame of the orbit and the equinox.
    """

    obliquity: float
    equinox: np.ndarray
    equinox_to_pericentre: float
    orbit_frame: np.ndarray


#: Below this sin(obliquity) the node of the equator on the orbit is undefined.
MIN_SIN_OBLIQUITY = 1e-10


def spin_geometry(pole_ecliptic: np.ndarray, i: float, node: float, peri: float,
                  body: str | None = None) -> SpinGeometry:
    """Obliquity, equinox and equinox-to-pericentre angle of a spin axis.

    ``pole_ecliptic`` is the spin-axis unit vector in ecliptic J2000; the orbit
    angles are in radians (ecliptic and equinox J2000).
    """
    obliquity, theta, gamma, w = spin_angles(pole_ecliptic, i, node, peri)
    if not np.isfinite(theta):
        raise InvalidInputError(
            "pole", "the spin axis is normal to the orbit (obliquity 0 or 180 deg): "
            "the equinox and the longitude of the node are undefined", body)
    frame = np.vstack([gamma, np.cross(w, gamma), w])
    return SpinGeometry(float(obliquity), gamma, float(theta), frame)


def spin_angles(pole_ecliptic, i, node, peri):
    """(obliquity, θ, equinox γ, orbit normal W) of spin axes (..., 3) in ecliptic J2000 on orbits of angles i, node,
    peri (radians, arrays broadcast over the leading axes): the obliquity from atan2(|s × W|, s · W), γ = s × W /
    |s × W| and θ the signed angle from γ to the pericentre P about W. θ and γ are NaN where the spin axis is
    normal to the orbit (|s × W| below :data:`MIN_SIN_OBLIQUITY`: no equinox)."""
    s = np.asarray(pole_ecliptic, dtype=float)
    s = s / np.linalg.norm(s, axis=-1, keepdims=True)
    basis = orbit_basis(i, node, peri)
    p, w = basis[..., 0, :], basis[..., 2, :]
    cross = np.cross(s, w)
    sin_eps = np.linalg.norm(cross, axis=-1)
    obliquity = np.arctan2(sin_eps, np.sum(s * w, axis=-1))
    with np.errstate(invalid="ignore", divide="ignore"):
        gamma = np.where((sin_eps >= MIN_SIN_OBLIQUITY)[..., None], cross / sin_eps[..., None], np.nan)
    theta = np.arctan2(np.sum(np.cross(gamma, p) * w, axis=-1), np.sum(gamma * p, axis=-1))
    return obliquity, theta, gamma, w
