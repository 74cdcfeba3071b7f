"""A NAIF text PCK as SPICE reads it: a kernel's records, its frames, its pole as SPICE evaluates it.

The records of a kernel (:class:`BodyFit`, one body's entry and its fit;
:class:`PckResult`, the kernel), its frames (J2000, ECLIPJ2000) and their IRFNUM codes, the ID that owns a
body's angles, and the kernel's pole evaluated as SPICE evaluates it. :mod:`ephem.exports.pck_fit` fits the
entries, :mod:`ephem.exports.pck_text` writes them."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base.constants import ARCSEC, J2000_JD
from ..base.constants import JULIAN_CENTURY_DAYS as CENTURY_DAYS


#: SPICE's ECLIPJ2000 is J2000 turned about its x axis by the IAU 1976 obliquity of J2000 (SPICELIB
#: CHGIRF); IRFNUM codes of the two frames, for BODY#_CONSTANTS_REF_FRAME.
ECLIPJ2000_OBLIQUITY_ARCSEC = 84381.448
FRAME_CODES = {"J2000": 1, "ECLIPJ2000": 17}


def angles_owner(naif_id: int) -> int:
    """The ID naming ``BODY#_NUT_PREC_ANGLES`` and ``BODY#_CONSTANTS_REF_FRAME`` for ``naif_id`` (ZZBODBRY)."""
    if 100 <= naif_id <= 999:
        return naif_id // 100
    if 10000 <= naif_id <= 99999:
        return naif_id // 10000
    return naif_id


def jd_text(jd: float) -> str:
    """A Julian date TDB as the kernel's texts and messages write it."""
    return f"JD {jd:.6f} TDB"


def rotation_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])


#: Vectors from J2000 to each kernel frame (rows: the frame's axes in J2000).
FRAME_FROM_J2000 = {"J2000": np.eye(3), "ECLIPJ2000": rotation_x(ECLIPJ2000_OBLIQUITY_ARCSEC * ARCSEC)}


@dataclass(frozen=True)
class BodyFit:
    """One body's kernel entry as written (degrees; T in Julian centuries, d in days of TDB from J2000;
    RA and DEC in ``frame``) and the quality of its fit to the track."""

    name: str
    naif_id: int
    dataset: str
    model: dict                      # the track's model: name, order, estimated_error_mas, description, ...
    frame: str                       # "J2000" or "ECLIPJ2000"
    fit_error_mas: float             # largest angle between the kernel's pole and the track over the span
    fit_rms_mas: float
    fit_aim_mas: float
    fit_limit_mas: float
    check_epochs: int
    pole_ra: tuple[float, float, float]
    pole_dec: tuple[float, float, float]
    pm: tuple[float, float, float]
    pm_source: str
    angles: tuple[tuple[float, float], ...]      # (θ0 deg, θ1 deg/century)
    nut_prec_ra: tuple[float, ...]
    nut_prec_dec: tuple[float, ...]
    terms: tuple                                 # (label, j) of each pair of angles: see term_label
    term_label: str                              # what a term's label is (k: θ = k M + j Ψ; or Delaunay multipliers)
    precession_rate_deg_per_day: float           # ψ̇: the sidebands' step

    @property
    def angles_owner(self) -> int:
        return angles_owner(self.naif_id)

    def pole_radec(self, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """The kernel's RA and DEC (degrees, in :attr:`frame`) at epochs (JD TDB), as SPICE evaluates them."""
        return kernel_radec(self, np.asarray(jd_tdb, dtype=float))

    def pole_j2000(self, jd_tdb) -> np.ndarray:
        """The kernel's pole as unit vectors (..., 3) in J2000 at epochs (JD TDB)."""
        return unit_vectors(*self.pole_radec(jd_tdb)) @ FRAME_FROM_J2000[self.frame]


@dataclass(frozen=True)
class PckResult:
    """A kernel: its ``text`` and, per body (``bodies``), the fit; the validity span (JD TDB and UTC)."""

    text: str
    bodies: tuple[BodyFit, ...]
    start_jd_tdb: float
    stop_jd_tdb: float
    start_utc: str
    stop_utc: str
    generated_utc: str

    @property
    def fit_error_mas(self) -> dict[str, float]:
        """Largest angle between the kernel's pole and the track over the span, per body (mas)."""
        return {b.name: b.fit_error_mas for b in self.bodies}

    @property
    def models(self) -> dict[str, dict]:
        """The model each body's track used (rung name, order, estimated error, ...)."""
        return {b.name: b.model for b in self.bodies}


# --------------------------------------------------------------------------- evaluation

def theta_rad(angles: np.ndarray, T: np.ndarray) -> np.ndarray:
    """θ_i(T) in radians, shape (N, m), computed as TISBOD does: θ0 + θ1 T in degrees, then radians."""
    angles = np.asarray(angles, dtype=float).reshape(-1, 2)
    return np.radians(angles[:, 0][None, :] + T[:, None] * angles[:, 1][None, :])


def kernel_radec(fit: BodyFit, jd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    T = (np.atleast_1d(jd) - J2000_JD) / CENTURY_DAYS
    ra = fit.pole_ra[0] + T * (fit.pole_ra[1] + T * fit.pole_ra[2])
    dec = fit.pole_dec[0] + T * (fit.pole_dec[1] + T * fit.pole_dec[2])
    if fit.angles:
        theta = theta_rad(fit.angles, T)
        ra = ra + np.sin(theta[:, :len(fit.nut_prec_ra)]) @ np.asarray(fit.nut_prec_ra)
        dec = dec + np.cos(theta[:, :len(fit.nut_prec_dec)]) @ np.asarray(fit.nut_prec_dec)
    return ra, dec


def rounding_bound(fit: BodyFit, jd: np.ndarray) -> float:
    """A bound (radians) on what double-precision rounding in SPICE's evaluation of the kernel can move its
    pole over the epochs: a few units in the last place of every term summed, in RA (times cos DEC) and DEC,
    and of each angle θ = θ0 + θ1 T times its coefficients."""
    T = (np.atleast_1d(jd) - J2000_JD) / CENTURY_DAYS
    eps = 4.0 * np.finfo(float).eps
    ang = np.asarray(fit.angles, dtype=float).reshape(-1, 2)
    theta_err = eps * (np.abs(ang[:, 0])[None, :] + np.abs(T)[:, None] * np.abs(ang[:, 1])[None, :])   # deg

    def part(poly, coef):
        c = np.abs(np.asarray(coef, dtype=float))
        terms = abs(poly[0]) + np.abs(T) * (abs(poly[1]) + np.abs(T) * abs(poly[2])) + float(c.sum())
        return eps * terms + np.radians(theta_err[:, :c.size]) @ c

    dec = np.radians(fit.pole_radec(jd)[1])
    return float(np.max(np.hypot(np.cos(dec) * part(fit.pole_ra, fit.nut_prec_ra),
                                 part(fit.pole_dec, fit.nut_prec_dec)))) * math.pi / 180.0


def unit_vectors(ra_deg, dec_deg) -> np.ndarray:
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    cd = np.cos(dec)
    return np.stack([cd * np.cos(ra), cd * np.sin(ra), np.sin(dec)], axis=-1)


def radec_of_units(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """RA (unwrapped along the rows, degrees) and DEC (degrees) of unit vectors (N, 3)."""
    ra = np.unwrap(np.arctan2(v[:, 1], v[:, 0]))
    return np.degrees(ra), np.degrees(np.arctan2(v[:, 2], np.hypot(v[:, 0], v[:, 1])))
