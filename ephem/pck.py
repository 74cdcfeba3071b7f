"""NAIF SPICE text PCK kernels (``KPL/PCK``) fitted to the spin-axis track.

A text PCK gives a body's orientation as three angles of time (NAIF, *PCK Required Reading*,
pck.req, "Models for the Sun, Planets, and Asteroids" and "Models for Satellites in Text PCK
Kernels"; SPICELIB TISBOD, toolkit N0067):

    RA  = RA0  + RA1  T + RA2  T² + Σ_i a_i sin θ_i          (degrees)
    DEC = DEC0 + DEC1 T + DEC2 T² + Σ_i d_i cos θ_i          (degrees)
    W   = W0   + W1   d + W2   d²                            (degrees)
    θ_i = θ0_i + θ1_i T                                      (degrees, degrees per Julian century)

T in Julian centuries and d in days of TDB from J2000 (JD 2451545.0 TDB). The kernel variables are
``BODYnnn_POLE_RA``, ``BODYnnn_POLE_DEC``, ``BODYnnn_PM`` (each [c0, c1, c2]), ``BODYnnn_NUT_PREC_RA``
(the a_i), ``BODYnnn_NUT_PREC_DEC`` (the d_i) and ``BODYbbb_NUT_PREC_ANGLES`` (the pairs θ0_i, θ1_i).
bbb is SPICELIB ZZBODBRY's "barycenter code" of nnn: nnn // 100 for a planet or satellite code
100-999, nnn // 10000 for 10000-99999, and nnn itself for any other body, so that an asteroid such as
Vesta (2000004) carries its own ``BODY2000004_NUT_PREC_ANGLES`` while the Earth's angles are the
Earth-Moon system's ``BODY3_NUT_PREC_ANGLES``. The same code names ``BODYbbb_CONSTANTS_REF_FRAME``
(the inertial frame of RA and DEC, an IRFNUM code; default J2000) and ``BODYbbb_MAX_PHASE_DEGREE``
(the angles' polynomial degree, default 1), which the kernels written here state explicitly. TISBOD
signals SPICE(INSUFFICIENTANGLES) when a coefficient list is longer than the angle list and holds
at most 200 angles per body (N0067); older toolkits hold 100 (MAXANG in TISBOD and BODEUL), the
default cap here.

The fit. The track (:func:`ephem.api.track_arrays`) is quasi-periodic in two frequencies: the
orbital mean motion n (the nutation's argument is the mean anomaly M) and the precession rate ψ̇
(the pole turns about the orbit normal, and the nutation's displacement turns with it). Its right
ascension and declination are therefore sums of terms at k n + j ψ̇ (k >= 0, any j), which SPICE's
angles, linear in T, represent exactly; one frequency takes two angles (θ and θ + 90°) because RA
takes only sines and DEC only cosines. The quadratic polynomials carry the secular motion. The
frequencies (0 <= k <= 2 k_max of the nutation series, |j| <= :data:`ephem.ladder.TRACK_SIDEBANDS`; for the Earth with
the Moon, the ``lunisolar`` model, the lunisolar series' terms instead, their phases in the Delaunay
arguments linearised at the span's middle, |j| <= :data:`ephem.earth.TRACK_SIDEBANDS`) are chosen one at a time
by orthogonal least squares (the one that lowers the residual most), the coefficients by linear least
squares over a dense grid of the span, RA weighted by cos DEC so that both residuals are angles on
the sky. The fit error is the largest angle between the kernel's pole, evaluated as SPICE does, and
the track over the fit grid and a grid :data:`CHECK_DENSITY` times denser offset from it, raised by
:data:`CHECK_MARGIN` for the maxima between epochs, plus :func:`rounding_bound` for SPICE's
double-precision arithmetic. Terms are added until that error is below the
aim (:data:`FIT_AIM_MAS`); if the angle budget runs out first the kernel is written only if the
error is below the limit (:data:`FIT_LIMIT_MAS`; both default to a tenth of the model's estimated
error where that is smaller, and both are ``fit_tolerance_mas`` when given), and otherwise refused
(:class:`~ephem.errors.InvalidInputError` on ``stop``).

Frames. The track's poles are ICRF; SPICE's J2000 frame differs from the ICRF by the frame bias
(~20 mas). Like the IAU WGCCRE models in NAIF's generic PCKs, the kernel gives ICRF coordinates as
J2000 ones. A pole within 10° of the J2000 pole (the Earth's) makes RA a poor coordinate (it swings
through 180° as the pole passes near the frame's pole); such a body's RA and DEC are ecliptic
longitude and latitude in SPICE's ECLIPJ2000 (``BODYbbb_CONSTANTS_REF_FRAME = 17``), and SPICE
rotates them back.

The prime meridian. The catalogue has the rotation period P but no W0: W1 = 360° / P (days) and, for
the bodies :func:`iau_orientation` knows (the catalogue's asteroids, Mars, the Earth), W0 puts the
prime meridian where the IAU WGCCRE model puts it at the middle of the span: the IAU model's body x
axis there, projected on our kernel's equator, measured from our node. Our pole and the IAU's differ
(the IAU asteroid poles are fixed, ours precess), so this is the nearest meridian to the IAU's, not the
IAU's W; over the span the two drift apart by the difference of the node motions and of W1. For
other bodies W0 = 0. The pole does not depend on W.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from .catalogue import DEFAULT_DATASET, Body
from .constants import ARCSEC, J2000_JD, MAS
from .constants import JULIAN_CENTURY_DAYS as CENTURY_DAYS
from .errors import InvalidInputError
from .registry import theory_for
from .theory import Spectrum

#: Terms are added until the fit error is below this (mas) ...
FIT_AIM_MAS = 0.1
#: ... and, when the angle budget runs out first, the kernel is written if its error is below this (mas);
#: both are lowered to a tenth of the model's estimated error where that is smaller.
FIT_LIMIT_MAS = 1.0
#: Default cap on the nutation-precession angles per body (TISBOD's MAXANG before N0067).
DEFAULT_MAX_ANGLES = 100
#: Hard cap (TISBOD N0067 buffers 200 angles per body).
SPICE_MAX_ANGLES = 200
#: Fit epochs per period of the fastest candidate term, and bounds on the fit grid.
SAMPLES_PER_PERIOD = 8
MIN_FIT_SAMPLES = 1500
MAX_FIT_SAMPLES = 40_000
#: The check grid is this many times denser than the fit grid, offset from it by half its step.
CHECK_DENSITY = 4
#: The largest error on the two grids is raised by this factor to bound the maxima between their epochs:
#: with >= 32 epochs per period of the fastest term, a sinusoid's peak exceeds its sampled maximum by at
#: most 1/cos(π/32) - 1 = 0.5%.
CHECK_MARGIN = 1.02
#: A candidate column whose part outside the basis is below this fraction of its norm is neither scored nor
#: added: a nearly dependent column is fitted with large coefficients that cancel, which costs the kernel
#: digits (see rounding_bound), and its updated inner products have lost their precision.
SCORED = DEPENDENT = 1e-6
#: A track that comes nearer than this to the J2000 pole (degrees of declination) is fitted in ECLIPJ2000.
MAX_J2000_DEC_DEG = 80.0
#: SPICE's ECLIPJ2000 is J2000 turned about its x axis by the IAU 1976 obliquity of J2000 (SPICELIB
#: CHGIRF); IRFNUM codes of the two frames, for BODY#_CONSTANTS_REF_FRAME.
ECLIPJ2000_OBLIQUITY_ARCSEC = 84381.448
FRAME_CODES = {"J2000": 1, "ECLIPJ2000": 17}

# The IAU WGCCRE orientation models, used only to place our W0 (module docstring). Asteroids and Mars:
# Archinal et al. (2018), the WGCCRE 2015 report, as in NAIF's pck00011.tpc, read in NAIF's test utility
# T_PCKANG (which checks that kernel's models) and cross-checked for Ceres, Vesta and Eros against
# independent transcriptions; the asteroids' W1 give the catalogue's rotation periods, and the Mars
# series at J2000 gives the catalogue's J2000 pole (317.68085, 52.88644). Earth: the WGCCRE 2009 model
# (Archinal et al. 2011; the 2015 report gives none), as in NAIF's pck00010.tpc.
_WGCCRE_2015 = "IAU WGCCRE 2015 (Archinal et al. 2018, Celest. Mech. Dyn. Astr. 130:22), as in NAIF pck00011.tpc"
_WGCCRE_2009 = "IAU WGCCRE 2009 (Archinal et al. 2011, Celest. Mech. Dyn. Astr. 109:101), as in NAIF pck00010.tpc"
#: Constant poles: NAIF id -> (RA deg, DEC deg, W0 deg, W1 deg/day).
_IAU_CONSTANT_POLE = {
    2000001: (291.418, 66.764, 170.65, 952.1532),            # Ceres
    2000004: (309.031, 42.235, 285.39, 1617.3329428),        # Vesta
    2000433: (11.35, 17.22, 326.07, 1639.38864745),          # Eros
    2002867: (91.0, -62.0, 321.76, 1428.09917),              # Steins
    2025143: (90.53, -66.30, 0.0, 712.143),                  # Itokawa
}
#: Mars (WGCCRE 2015): constant, rate (per century or per day), then (amplitude, phase0, phase rate per century).
_MARS_RA = (317.269202, -0.10927547, ((0.000068, 198.991226, 19139.4819985), (0.000238, 226.292679, 38280.8511281),
                                      (0.000052, 249.663391, 57420.7251593), (0.000009, 266.183510, 76560.6367950),
                                      (0.419057, 79.398797, 0.5042615)))
_MARS_DEC = (54.432516, -0.05827105, ((0.000051, 122.433576, 19139.9407476), (0.000141, 43.058401, 38280.8753272),
                                      (0.000031, 57.663379, 57420.7517205), (0.000005, 79.476401, 76560.6495004),
                                      (1.591274, 166.325722, 0.5042615)))
_MARS_W = (176.049863, 350.891982443297, ((0.000145, 129.071773, 19140.0328244), (0.000157, 36.352167, 38281.0473591),
                                          (0.000040, 56.668646, 57420.9295360), (0.000001, 67.364003, 76560.2552215),
                                          (0.000001, 104.792680, 95700.4387578), (0.584542, 95.391654, 0.5042615)))


def iau_orientation(naif_id: int, jd_tdb: float) -> tuple[float, float, float, str] | None:
    """The IAU WGCCRE model's pole RA, DEC and prime meridian W (degrees, J2000 frame) at ``jd_tdb``, and its
    source; None for a body without one here."""
    d = jd_tdb - J2000_JD
    T = d / CENTURY_DAYS
    if naif_id in _IAU_CONSTANT_POLE:
        ra, dec, w0, w1 = _IAU_CONSTANT_POLE[naif_id]
        return ra, dec, w0 + w1 * d, _WGCCRE_2015
    if naif_id == 499:
        def series(c, rate_t, periodic, trig):
            return c + rate_t + sum(a * trig(math.radians(p0 + p1 * T)) for a, p0, p1 in periodic)
        return (series(_MARS_RA[0], _MARS_RA[1] * T, _MARS_RA[2], math.sin),
                series(_MARS_DEC[0], _MARS_DEC[1] * T, _MARS_DEC[2], math.cos),
                series(_MARS_W[0], _MARS_W[1] * d, _MARS_W[2], math.sin), _WGCCRE_2015)
    if naif_id == 399:
        return -0.641 * T, 90.0 - 0.557 * T, 190.147 + 360.9856235 * d, _WGCCRE_2009
    return None


def angles_owner(naif_id: int) -> int:
    """The ID naming ``BODY#_NUT_PREC_ANGLES`` and ``BODY#_CONSTANTS_REF_FRAME`` for ``naif_id`` (ZZBODBRY)."""
    if 100 <= naif_id <= 999:
        return naif_id // 100
    if 10000 <= naif_id <= 99999:
        return naif_id // 10000
    return naif_id


def _rx(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])


def _rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


#: Vectors from J2000 to each kernel frame (rows: the frame's axes in J2000).
FRAME_FROM_J2000 = {"J2000": np.eye(3), "ECLIPJ2000": _rx(ECLIPJ2000_OBLIQUITY_ARCSEC * ARCSEC)}


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
        return _kernel_radec(self, np.asarray(jd_tdb, dtype=float))

    def pole_j2000(self, jd_tdb) -> np.ndarray:
        """The kernel's pole as unit vectors (..., 3) in J2000 at epochs (JD TDB)."""
        return _unit(*self.pole_radec(jd_tdb)) @ FRAME_FROM_J2000[self.frame]


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

def _theta_rad(angles: np.ndarray, T: np.ndarray) -> np.ndarray:
    """θ_i(T) in radians, shape (N, m), computed as TISBOD does: θ0 + θ1 T in degrees, then radians."""
    angles = np.asarray(angles, dtype=float).reshape(-1, 2)
    return np.radians(angles[:, 0][None, :] + T[:, None] * angles[:, 1][None, :])


def _kernel_radec(fit: BodyFit, jd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    T = (np.atleast_1d(jd) - J2000_JD) / CENTURY_DAYS
    ra = fit.pole_ra[0] + T * (fit.pole_ra[1] + T * fit.pole_ra[2])
    dec = fit.pole_dec[0] + T * (fit.pole_dec[1] + T * fit.pole_dec[2])
    if fit.angles:
        theta = _theta_rad(fit.angles, T)
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


def _unit(ra_deg, dec_deg) -> np.ndarray:
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    cd = np.cos(dec)
    return np.stack([cd * np.cos(ra), cd * np.sin(ra), np.sin(dec)], axis=-1)


def _radec(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """RA (unwrapped along the rows, degrees) and DEC (degrees) of unit vectors (N, 3)."""
    ra = np.unwrap(np.arctan2(v[:, 1], v[:, 0]))
    return np.degrees(ra), np.degrees(np.arctan2(v[:, 2], np.hypot(v[:, 0], v[:, 1])))


def angle_between(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Angles (radians) between rows of unit vectors, accurate at small angles (atan2 of |u×v| and u·v)."""
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), np.sum(u * v, axis=-1))


# --------------------------------------------------------------------------- fitting

class _Ols:
    """Orthogonal least squares for one coordinate (Chen, Billings & Luo 1989, Int. J. Control 50:1873): an
    orthonormal basis (modified Gram-Schmidt, orthogonalised twice) of weighted columns, the residual of
    the weighted data, and for every candidate column c the inner products of its part c' orthogonal to
    the basis, from which a candidate's score, the exact drop in the residual's energy it would bring,
    follows. They are updated as each basis vector q joins (q is orthogonal to the earlier ones, so
    q·c' = q·c): |c'|² -= (q·c)², s'·c' -= (q·s)(q·c), r·c' -= (q·r)(q·c). A candidate whose part outside
    the basis is below SCORED of its norm is not scored (its products have lost their precision), and a
    column whose part is below DEPENDENT is not added (its coefficient is zero)."""

    def __init__(self, weight: np.ndarray, data: np.ndarray, candidates: np.ndarray):
        self.w = weight
        self.data = weight * data
        self.residual = self.data.copy()
        self.cand = weight[:, None] * candidates               # weighted candidate columns (never changed)
        s, c = self.cand[:, 0::2], self.cand[:, 1::2]
        self.ss0 = np.einsum("ij,ij->j", s, s)
        self.cc0 = np.einsum("ij,ij->j", c, c)
        self.ss, self.cc, self.sc = self.ss0.copy(), self.cc0.copy(), np.einsum("ij,ij->j", s, c)
        self.bs, self.bc = self.residual @ s, self.residual @ c
        self.Q = np.empty((16, data.size))                      # rows: the orthonormal basis (grown by doubling)
        self.m = 0
        self.r: list[np.ndarray] = []                           # column j of R, length j + 1
        self.keys: list = []                                    # what each basis column is

    def add(self, column: np.ndarray, key) -> bool:
        v = self.w * column
        norm0 = float(np.linalg.norm(v))
        coeffs = np.zeros(self.m + 1)
        if self.m:
            Q = self.Q[: self.m]
            for _ in range(2):
                c = Q @ v
                coeffs[:-1] += c
                v = v - c @ Q
        norm = float(np.linalg.norm(v))
        if norm0 == 0.0 or norm <= DEPENDENT * norm0:          # numerically dependent on the basis
            return False
        q = v / norm
        coeffs[-1] = norm
        if self.m == self.Q.shape[0]:
            self.Q = np.concatenate([self.Q, np.empty_like(self.Q)])
        self.Q[self.m] = q
        self.m += 1
        self.r.append(coeffs)
        self.keys.append(key)
        qr = float(q @ self.residual)
        self.residual -= q * qr
        if self.cand.shape[1]:
            y = q @ self.cand
            ys, yc = y[0::2], y[1::2]
            self.ss -= ys * ys
            self.cc -= yc * yc
            self.sc -= ys * yc
            self.bs -= qr * ys
            self.bc -= qr * yc
        return True

    def scores(self) -> np.ndarray:
        """The residual's energy drop for each candidate pair of columns (sin, cos), or for the one of them
        that is scored; -1 where neither is."""
        ss, cc, sc, bs, bc = self.ss, self.cc, self.sc, self.bs, self.bc
        s_ok = ss > SCORED ** 2 * self.ss0
        c_ok = cc > SCORED ** 2 * self.cc0
        det = ss * cc - sc * sc
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.maximum(np.where(s_ok, bs * bs / np.where(s_ok, ss, 1.0), -1.0),
                             np.where(c_ok, bc * bc / np.where(c_ok, cc, 1.0), -1.0))
            both = s_ok & c_ok & (det > 1e-6 * ss * cc)
            out[both] = (cc[both] * bs[both] ** 2 - 2.0 * sc[both] * bs[both] * bc[both]
                         + ss[both] * bc[both] ** 2) / det[both]
        return out

    def coefficients(self) -> dict:
        """Least-squares coefficient of each column added, by key (back substitution in R)."""
        m = self.m
        R = np.zeros((m, m))
        for j, col in enumerate(self.r):
            R[: j + 1, j] = col
        return dict(zip(self.keys, np.linalg.solve(R, self.Q[:m] @ self.data)))


def _candidates(spec: Spectrum, span: float, fit_step: float) -> list[tuple[int, int]]:
    """(base, j) of the frequencies worth trying: positive, resolved by the fit grid (at least
    SAMPLES_PER_PERIOD / 2 epochs per period), and, for the precession alone, not a mere polynomial."""
    fastest = 2.0 * math.pi / (0.5 * SAMPLES_PER_PERIOD * fit_step)
    out = []
    for i in range(len(spec.labels)):
        for j in range(-spec.max_sideband, spec.max_sideband + 1):
            f = spec.frequency(i, j)
            if f <= 0.0 or f > fastest or (spec.theta1[i] == 0.0 and f * span < 1e-3):
                continue
            out.append((i, j))
    return out


def _fit_body(b: Body, t0: float, t1: float, dataset: str, tolerance_mas, model, order, axis: str, perturbers,
              fit_tolerance_mas: float | None, max_angles: int) -> BodyFit:
    from . import api

    span = t1 - t0
    # the model: chosen once (by tolerance, name or default) for the span's two ends, then named for both
    # grids, so that a tolerance cannot pick another one for other epochs
    probe = api.track_arrays(b, t0, t1, span, dataset, order=order, tolerance_mas=tolerance_mas, model=model,
                             axis=axis, perturbers=perturbers)
    info = probe["model"]
    estimate = info.get("estimated_error_mas")
    if fit_tolerance_mas is not None:
        aim = limit = float(fit_tolerance_mas)
    else:
        tenth = math.inf if estimate is None else 0.1 * estimate
        aim, limit = min(FIT_AIM_MAS, tenth), min(FIT_LIMIT_MAS, tenth)

    T0, T1 = (t0 - J2000_JD) / CENTURY_DAYS, (t1 - J2000_JD) / CENTURY_DAYS
    Tm, Th = 0.5 * (T0 + T1), 0.5 * (T1 - T0)
    theory = theory_for(b, tuple(info["perturbers"]), axis)
    spec = theory.spectrum(aim, Tm)            # refined below from the track (the rates the higher rungs change)
    fastest = max(spec.frequency(i, spec.max_sideband) for i in range(len(spec.labels)))
    count = int(min(MAX_FIT_SAMPLES, max(MIN_FIT_SAMPLES,
                                         math.ceil(SAMPLES_PER_PERIOD * fastest * span / (2.0 * math.pi)) + 1)))
    step = span / (count - 1)
    named = {"order": info["order"], "model": info["name"], "axis": axis, "perturbers": perturbers}
    ans = api.track_arrays(b, t0, t1, step, dataset, max_samples=count + 1, **named)
    t = ans["jd_tdb"]
    check_count = CHECK_DENSITY * (t.size - 1)
    check_step = span / check_count
    chk = api.track_arrays(b, t0 + 0.5 * check_step, t1, check_step, dataset, max_samples=check_count + 1, **named)
    t_chk = chk["jd_tdb"]
    spec = theory.spectrum(aim, Tm, t, ans["psi_arcsec"] * ARCSEC)

    # the frame: J2000 unless the pole comes near its pole
    frame = "J2000" if float(np.max(np.abs(ans["pole_dec_deg"]))) <= MAX_J2000_DEC_DEG else "ECLIPJ2000"
    rot = FRAME_FROM_J2000[frame]
    u_fit = _unit(ans["pole_ra_deg"], ans["pole_dec_deg"]) @ rot.T
    u_chk = _unit(chk["pole_ra_deg"], chk["pole_dec_deg"]) @ rot.T
    ra_deg, dec_deg = _radec(u_fit)
    ra_deg -= 360.0 * math.floor(ra_deg[ra_deg.size // 2] / 360.0)      # RA in [0°, 360°) mid-span

    T = (t - J2000_JD) / CENTURY_DAYS
    u = (T - Tm) / Th
    cands = _candidates(spec, span, step)
    cand_cols = np.empty((t.size, 2 * len(cands)))
    if cands:
        theta = _theta_rad(np.array([spec.angle(i, j) for i, j in cands]), T)
        cand_cols[:, 0::2], cand_cols[:, 1::2] = np.sin(theta), np.cos(theta)
    ra = _Ols(np.cos(np.radians(dec_deg)), ra_deg, cand_cols)        # RA weighted by cos DEC: an angle
    dec = _Ols(np.ones_like(t), dec_deg, cand_cols)
    for key, c in (("p0", np.ones_like(u)), ("p1", u), ("p2", u * u)):
        if not (ra.add(c, key) and dec.add(c, key)):
            raise RuntimeError("polynomial columns dependent")  # pragma: no cover - >= 1500 distinct epochs

    def assemble(chosen) -> BodyFit:
        return _assemble(b, info, dataset, frame, chosen, spec, ra.coefficients(), dec.coefficients(), Tm, Th,
                         aim, limit)

    def measure(fit: BodyFit) -> tuple[float, float, int]:
        e1 = angle_between(_unit(*_kernel_radec(fit, t)), u_fit)
        e2 = angle_between(_unit(*_kernel_radec(fit, t_chk)), u_chk)
        worst = (max(float(e1.max()), float(e2.max())) * CHECK_MARGIN + rounding_bound(fit, t_chk)) / MAS
        return worst, math.sqrt(float(np.mean(np.concatenate([e1, e2]) ** 2))) / MAS, e1.size + e2.size

    chosen: list[tuple[int, int]] = []
    available = np.ones(len(cands), dtype=bool)
    result = None
    while True:
        # the weighted residuals are the angles on the sky to first order: a cheap test on the fit grid first
        approx = float(np.max(np.hypot(ra.residual, dec.residual))) * 3.6e6 * CHECK_MARGIN       # deg -> mas
        if approx <= aim:
            fit = assemble(chosen)
            worst, rms, epochs = measure(fit)
            if worst <= aim:
                result = (fit, worst, rms, epochs)
                break
        if 2 * (len(chosen) + 1) > max_angles or not available.any():
            break
        s_ra, s_dec = ra.scores(), dec.scores()
        score = np.where((s_ra < 0.0) & (s_dec < 0.0), -1.0, np.maximum(s_ra, 0.0) + np.maximum(s_dec, 0.0))
        score[~available] = -1.0
        i = int(np.argmax(score))
        if score[i] <= 0.0:
            break
        available[i] = False
        took = [basis.add(cand_cols[:, 2 * i + p], (cands[i], p)) for basis in (ra, dec) for p in (0, 1)]
        if any(took):
            chosen.append(cands[i])
    if result is None:          # the aim was not reached: all the terms the budget allows
        fit = assemble(chosen)
        worst, rms, epochs = measure(fit)
        if not worst <= limit:
            raise InvalidInputError(
                "stop", f"the span {_jd_text(t0)} to {_jd_text(t1)} cannot be fitted within {limit:.4g} mas "
                f"with at most {max_angles} nutation-precession angles (best {worst:.4g} mas with "
                f"{2 * len(chosen)} angles); shorten the span (or write several kernels), raise max_angles "
                f"(up to {SPICE_MAX_ANGLES}, SPICE N0067) or fit_tolerance_mas", b.name)
        result = (fit, worst, rms, epochs)
    fit, worst, rms, epochs = result
    return replace(fit, fit_error_mas=worst, fit_rms_mas=rms, check_epochs=epochs,
                   **dict(zip(("pm", "pm_source"), _prime_meridian(b, fit, 0.5 * (t0 + t1)))))


def _assemble(b: Body, info: dict, dataset: str, frame: str, chosen, spec: Spectrum, ra_coef, dec_coef, Tm: float,
              Th: float, aim: float, limit: float) -> BodyFit:
    """Kernel coefficients from the fitted ones: the polynomial in u = (T - Tm)/Th re-expanded in T, and each
    frequency's (sin, cos) pair as the coefficients of the angles θ and θ + 90°."""
    def poly(c) -> tuple[float, float, float]:
        a0, a1, a2 = (float(c[key]) for key in ("p0", "p1", "p2"))
        return (a0 - a1 * Tm / Th + a2 * Tm * Tm / (Th * Th), a1 / Th - 2.0 * a2 * Tm / (Th * Th), a2 / (Th * Th))

    angles, ra_terms, dec_terms = [], [], []
    for kj in chosen:
        theta0, theta1 = spec.angle(*kj)
        angles += [(theta0, theta1), ((theta0 + 90.0) % 360.0, theta1)]
        ra_s, ra_c = (float(ra_coef.get((kj, p), 0.0)) for p in (0, 1))
        dec_s, dec_c = (float(dec_coef.get((kj, p), 0.0)) for p in (0, 1))
        ra_terms += [ra_s, ra_c]            # sin θ, sin(θ + 90°) = cos θ
        dec_terms += [dec_c, -dec_s]        # cos θ, cos(θ + 90°) = -sin θ
    return BodyFit(
        name=b.name, naif_id=int(b.naif_id), dataset=dataset, model=dict(info), frame=frame,
        fit_error_mas=math.nan, fit_rms_mas=math.nan, fit_aim_mas=aim, fit_limit_mas=limit, check_epochs=0,
        pole_ra=poly(ra_coef), pole_dec=poly(dec_coef), pm=(0.0, 0.0, 0.0), pm_source="",
        angles=tuple(angles), nut_prec_ra=tuple(ra_terms), nut_prec_dec=tuple(dec_terms),
        terms=tuple((spec.labels[i], j) for i, j in chosen), term_label=spec.describe,
        precession_rate_deg_per_day=spec.psi_theta1 / CENTURY_DAYS)


def _frame_axes(ra_deg: float, dec_deg: float, w_deg: float) -> np.ndarray:
    """Rows: the body-fixed axes, in the reference frame, of the PCK Euler angles: [W]3 [90° - DEC]1 [90° + RA]3
    (pck.req, "Orientation Models used by PCK Software")."""
    a, d, w = (math.radians(x) for x in (ra_deg, dec_deg, w_deg))
    return _rz(w) @ _rx(math.pi / 2 - d) @ _rz(math.pi / 2 + a)


def _prime_meridian(b: Body, fit: BodyFit, jd_anchor: float) -> tuple[tuple[float, float, float], str]:
    """((W0 deg, W1 deg/day, 0), statement): W1 from the catalogue period; W0 such that at ``jd_anchor`` (the
    span's middle) the prime meridian lies where the IAU model puts it (its x axis projected on our equator)."""
    w1 = 360.0 / (b.rotation_period_hours / 24.0)
    iau = iau_orientation(int(b.naif_id), jd_anchor)
    if iau is None:
        return (0.0, w1, 0.0), ("W0 = 0: no IAU prime meridian is known here for this body, so the origin of "
                                "longitude is arbitrary (the pole does not depend on W); W1 = 360 deg / the "
                                "catalogue's rotation period")
    ra_i, dec_i, w_i, source = iau
    x_iau = _frame_axes(ra_i, dec_i, w_i)[0] @ FRAME_FROM_J2000[fit.frame].T     # the IAU x axis, kernel frame
    ra_k, dec_k = (float(x[0]) for x in fit.pole_radec(jd_anchor))
    axes = _frame_axes(ra_k, dec_k, 0.0)                    # W = 0: x along the kernel's node
    w_anchor = math.degrees(math.atan2(float(x_iau @ axes[1]), float(x_iau @ axes[0])))
    w0 = (w_anchor - w1 * (jd_anchor - J2000_JD)) % 360.0
    j2000 = iau_orientation(int(b.naif_id), J2000_JD)
    return (w0, w1, 0.0), (
        f"W0 = {w0:.6f} deg puts the prime meridian where the IAU model does ({source}; its W at J2000 "
        f"{j2000[2] % 360.0:.6f} deg about its pole RA {j2000[0]:.6f}, DEC {j2000[1]:.6f} deg) at the span's "
        f"middle, {_jd_text(jd_anchor)}; W1 = 360 deg / the catalogue's rotation period")


# --------------------------------------------------------------------------- text

def _num(x: float) -> str:
    """A kernel number: the shortest repr that reads back to the same double, exponent in upper case."""
    if isinstance(x, int):
        return str(x)
    if not math.isfinite(x):
        raise InvalidInputError("kernel", f"non-finite coefficient {x!r}")  # pragma: no cover - fits are finite
    return repr(float(x)).upper()


def _assign(name: str, values, per_line: int = 2) -> list[str]:
    vals = [_num(v) for v in values]
    head = f"   {name:<27} = ( "
    pad = " " * len(head)
    lines = [(head if i == 0 else pad) + "  ".join(vals[i:i + per_line]) for i in range(0, len(vals), per_line)]
    lines[-1] += " )"
    return lines


def _jd_text(jd: float) -> str:
    return f"JD {jd:.6f} TDB"


def _time_text(jd: float, scale: str) -> str:
    from astropy.time import Time
    from erfa import ErfaWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ErfaWarning)     # "dubious year": UTC beyond the leap-second table
        return getattr(Time(jd, format="jd", scale="tdb"), scale).isot + " " + scale.upper()


#: ASCII for the symbols our texts use (a text kernel is ASCII: NAIF, Kernel Required Reading).
_ASCII = {"ψ": "psi", "ε": "eps", "θ": "theta", "Ω": "Omega", "ω": "omega", "Δ": "Delta", "Ψ": "Psi", "φ": "phi",
          "ν": "nu", "μ": "mu", "µ": "u", "π": "pi", "∝": "propto", "″": '"', "′": "'", "°": " deg", "·": "*",
          "×": "x", "−": "-", "–": "-", "—": "--", "≤": "<=", "≥": ">=", "≈": "~", "±": "+-", "²": "^2",
          "³": "^3", "√": "sqrt", "∞": "inf", "…": "...", "‘": "'", "’": "'", "“": '"', "”": '"', "̇": "dot"}


def _ascii(text: str) -> str:
    """``text`` in printable ASCII and newlines: known symbols spelt out, accents dropped, anything else '?'."""
    import unicodedata

    out = []
    for ch in text:
        if 32 <= ord(ch) < 127 or ch == "\n":
            out.append(ch)
        elif ch in _ASCII:
            out.append(_ASCII[ch])
        else:
            base = unicodedata.normalize("NFKD", ch).encode("ascii", "ignore").decode("ascii")
            out.append(base if base.isprintable() and base else "?")
    return "".join(out)


def _wrap(text: str, width: int, indent: str) -> list[str]:
    import textwrap

    return textwrap.wrap(_ascii(text), width=width, initial_indent=indent, subsequent_indent=indent)


def _comment(fits: list[BodyFit], t0: float, t1: float, generated: str, max_angles: int) -> list[str]:
    L = [
        "Spin-axis orientation from ephem (ephem-asteroid-pn): forced precession and nutation",
        "===========================================================================",
        "",
        f"   Generated:      {generated}",
        f"   Validity span:  {_time_text(t0, 'utc')}  to  {_time_text(t1, 'utc')}",
        f"                   {_time_text(t0, 'tdb')}  to  {_time_text(t1, 'tdb')}",
        f"                   {_jd_text(t0)}  to  {_jd_text(t1)}",
        "",
        "   Outside the span the fit is extrapolated: do not use the kernel there.",
        "",
        "Bodies",
        "--------------------------------------------------------",
        "",
    ]
    for f in fits:
        info = f.model
        est = info.get("estimated_error_mas")
        order = "" if info.get("order") is None else f", e-order {info['order']}"
        L.append(f"   {f.name} (NAIF ID {f.naif_id}), dataset '{f.dataset}'")
        L += _wrap(f"Model: rung '{info.get('name')}'{order} of ephem's fidelity ladder, "
                   f"{info.get('description')}; estimated error "
                   + ("not estimated" if est is None else f"{est:.6g} mas") + " (the model against the truth, "
                   "over the span; see ephem's docs/accuracy.md).", 92, "      ")
        L += _wrap(f"Fit error: {f.fit_error_mas:.4g} mas, the largest angle between this kernel's pole and "
                   f"ephem's track over the span ({f.check_epochs} epochs; rms {f.fit_rms_mas:.3g} mas; aim "
                   f"{f.fit_aim_mas:.4g} mas, limit {f.fit_limit_mas:.4g} mas).", 92, "      ")
        L += _wrap(f"Terms: RA and DEC in {f.frame}; {len(f.angles)} nutation-precession angles in "
                   f"BODY{f.angles_owner}_NUT_PREC_ANGLES: {len(f.terms)} frequencies, each as a pair of angles "
                   f"theta, theta + 90 deg, with theta = (the phase of a nutation term: {f.term_label}) + j Psi, "
                   f"Psi the precession angle (rate psidot = {f.precession_rate_deg_per_day:.6g} deg/day).",
                   92, "      ")
        L += _wrap(f"Prime meridian: {f.pm_source}.", 92, "      ")
        for w in info.get("warnings") or []:
            L += _wrap(f"Note: {w}.", 92, "      ")
        if f.angles_owner != f.naif_id:
            L += _wrap(f"WARNING: SPICE takes this planet's angles (and its reference frame) from the system "
                       f"barycentre's BODY{f.angles_owner}_... variables, which its satellites share in NAIF's "
                       "generic PCKs: loaded after such a PCK this kernel replaces the satellites' angles, and "
                       "loaded before it, its own are replaced. Do not load both.", 92, "      ")
        L.append("")
    L += [
        "Model and conventions",
        "--------------------------------------------------------",
        "",
        "   The pole is ephem's forced precession-nutation track (Kinoshita's theory on ephem's",
        "   fidelity ladder), fitted by linear least squares in the form SPICE evaluates (PCK",
        "   Required Reading; SPICELIB TISBOD):",
        "",
        "      RA  = RA0  + RA1  T + RA2  T**2 + SUM a_i sin(theta_i)     (deg)",
        "      DEC = DEC0 + DEC1 T + DEC2 T**2 + SUM d_i cos(theta_i)     (deg)",
        "      W   = W0   + W1   d                                        (deg)",
        "      theta_i = theta0_i + theta1_i T                            (deg, deg/century)",
        "",
        "   T: Julian centuries of TDB, d: days of TDB, both from J2000 (JD 2451545.0 TDB).",
        "   The pole's frequencies are those of the nutation terms (multiples of the orbital mean",
        "   motion: the argument is the mean anomaly; for the Earth with the Moon, the lunisolar",
        "   series' arguments) offset by multiples of the precession rate psidot: the nutation's",
        "   displacement turns with the pole about the orbit normal.",
        "",
        "   Frame: ephem's poles are ICRF. As in the IAU WGCCRE models of NAIF's generic PCKs, they",
        "   are given as if in SPICE's J2000 frame, which differs from the ICRF by the frame bias",
        "   (about 20 mas, more than the fit error). A pole within 10 deg of the J2000 pole is given",
        "   in ECLIPJ2000 (BODY#_CONSTANTS_REF_FRAME = 17) instead: near a frame's pole RA is a poor",
        "   coordinate. SPICE turns the constants into J2000 itself.",
        "",
        "   Prime meridian: the catalogue gives the rotation period P, not W0; W1 = 360 deg / P (days).",
        "   Each body's entry above says where W0 comes from; the pole does not depend on W.",
        "",
        f"   Angles: at most {max_angles} per body (SPICE toolkits before N0067 hold 100, N0067 200).",
        "   BODY#_MAX_PHASE_DEGREE = 1 states that they are linear in T.",
        "",
        "   Use: furnsh this file; then pxform('J2000', 'IAU_<BODY>', et) or tipbod('J2000', id, et)",
        "   (whose third row is the pole) give the orientation, et = (JD TDB - 2451545.0) * 86400.",
        "",
    ]
    return L


def _data_block(f: BodyFit) -> list[str]:
    nid, own = f.naif_id, f.angles_owner
    out = [f"   {f.name}: pole RA, DEC in {f.frame} (deg, deg/century, deg/century**2); prime meridian",
           "   (deg, deg/day, deg/day**2); nutation-precession angles (deg, deg/century).", "",
           "\\begindata", ""]
    out += _assign(f"BODY{own}_CONSTANTS_REF_FRAME", [FRAME_CODES[f.frame]])
    out += _assign(f"BODY{nid}_POLE_RA", f.pole_ra)
    out += _assign(f"BODY{nid}_POLE_DEC", f.pole_dec)
    out += _assign(f"BODY{nid}_PM", f.pm)
    if f.angles:
        out.append("")
        out += _assign(f"BODY{nid}_NUT_PREC_RA", f.nut_prec_ra)
        out += _assign(f"BODY{nid}_NUT_PREC_DEC", f.nut_prec_dec)
        out.append("")
        out += _assign(f"BODY{own}_MAX_PHASE_DEGREE", [1])
        out += _assign(f"BODY{own}_NUT_PREC_ANGLES", [x for pair in f.angles for x in pair])
    out += ["", "\\begintext", ""]
    return out


# --------------------------------------------------------------------------- public

def write_pck(bodies, start, stop, dataset: str = DEFAULT_DATASET, tolerance_mas: float | None = None,
              model: str | None = None, order: int | None = None, axis: str = "figure", perturbers=None,
              fit_tolerance_mas: float | None = None, max_angles: int = DEFAULT_MAX_ANGLES,
              generated: datetime | None = None) -> PckResult:
    """A NAIF text PCK (``KPL/PCK``) of the bodies' poles over [start, stop], fitted to ephem's track.

    ``bodies``: one or a list of names, NAIF ids or :class:`~ephem.catalogue.Body` (with a ``naif_id``).
    ``start``, ``stop``: ISO 8601 (UTC unless a scale is named) or JD TDB. ``dataset``,
    ``tolerance_mas``, ``model``, ``order``, ``axis``, ``perturbers``: the track's model, as in
    :func:`ephem.api.track` (the Earth with the Moon: the lunisolar series' terms are the frequencies).
    ``fit_tolerance_mas``: the largest angle (mas) allowed between the kernel's pole and the track
    anywhere in the span; by default the fit aims at :data:`FIT_AIM_MAS` and accepts up to
    :data:`FIT_LIMIT_MAS` (each at most a tenth of the model's estimated error). ``max_angles``: the
    nutation-precession angles allowed per body (default 100, the limit of SPICE toolkits before N0067;
    at most 200). ``generated``: the time stamped in the comments (default now).

    Returns a :class:`PckResult`: ``text``, per-body fits (``fit_error_mas``, ``models``), the span.
    Raises :class:`~ephem.errors.UnknownBodyError` for an unknown body,
    :class:`~ephem.errors.NotApplicableError` where the theory does not hold (the Moon), and
    :class:`~ephem.errors.InvalidInputError` naming the field for bad inputs, and ``stop`` for a span
    the fit cannot follow within the limit.
    """
    from .api import resolve_body
    from .timeparse import to_jd_tdb
    from .units import in_unit

    t0 = to_jd_tdb(start, "start")
    t1 = to_jd_tdb(stop, "stop")
    if not t1 > t0:
        raise InvalidInputError("stop", f"stop (JD {t1} TDB) must be after start (JD {t0} TDB)")
    if isinstance(bodies, (str, int, Body)):
        bodies = [bodies]
    try:
        bodies = list(bodies)
    except TypeError:
        raise InvalidInputError("bodies", f"expected body names or NAIF ids, got {bodies!r}") from None
    if not bodies:
        raise InvalidInputError("bodies", "give at least one body")
    if isinstance(max_angles, bool) or not isinstance(max_angles, int) or not 0 <= max_angles <= SPICE_MAX_ANGLES:
        raise InvalidInputError("max_angles", f"must be an integer in [0, {SPICE_MAX_ANGLES}], got {max_angles!r}")
    if fit_tolerance_mas is not None:
        fit_tolerance_mas = in_unit(fit_tolerance_mas, "mas", "fit_tolerance_mas")
        if isinstance(fit_tolerance_mas, bool) or not isinstance(fit_tolerance_mas, (int, float)) \
                or not math.isfinite(fit_tolerance_mas) or fit_tolerance_mas <= 0.0:
            raise InvalidInputError("fit_tolerance_mas", "must be a positive finite number of milliarcseconds, "
                                    f"got {fit_tolerance_mas!r}")
    resolved = [resolve_body(b, dataset) for b in bodies]
    seen, owners = set(), {}
    for b in resolved:
        if b.naif_id is None:
            raise InvalidInputError("naif_id", "a body needs a NAIF id to name its kernel variables", b.name)
        if b.naif_id in seen:
            raise InvalidInputError("bodies", f"{b.name} (NAIF ID {b.naif_id}) is listed twice")
        seen.add(b.naif_id)
        own = angles_owner(b.naif_id)
        if own in owners:
            raise InvalidInputError("bodies", f"{b.name} and {owners[own]} would share BODY{own}_NUT_PREC_ANGLES "
                                    "(one planetary system): write them to separate kernels")
        owners[own] = b.name
    fits = [_fit_body(b, t0, t1, dataset, tolerance_mas, model, order, axis, perturbers, fit_tolerance_mas,
                      max_angles) for b in resolved]
    when = generated or datetime.now(UTC)
    stamp = (when.astimezone(UTC) if when.tzinfo else when).strftime("%Y-%m-%dT%H:%M:%S UTC")
    lines = ["KPL/PCK", "", "\\begintext", ""]
    lines += _comment(fits, t0, t1, stamp, max_angles)
    for f in fits:
        lines += _data_block(f)
    lines += ["End of kernel", ""]
    return PckResult(text=_ascii("\n".join(lines)), bodies=tuple(fits), start_jd_tdb=t0, stop_jd_tdb=t1,
                     start_utc=_time_text(t0, "utc"), stop_utc=_time_text(t1, "utc"), generated_utc=stamp)


def write_pck_file(path, bodies, start, stop, **kwargs) -> PckResult:
    """:func:`write_pck` with the text written to ``path`` (conventionally ``*.tpc``, ASCII); returns the result."""
    result = write_pck(bodies, start, stop, **kwargs)
    Path(path).write_text(result.text, encoding="ascii")
    return result
