"""The Moon's orientation beyond the rigid libration theory: what lunar laser ranging observes.

Beyond the rigid degree-2 theory: what lunar laser ranging observes and the theory
cannot give, and the ecliptic's motion the Cassini state lags behind (data/moon_orientation.toml).

* The principal axes against the mean-Earth/rotation frame: a constant rotation (the degree-3 field's constant
  torque), DE421's PA→ME angles from NAIF's frame kernel moon_080317.tf (:func:`me_to_pa`). The rigid degree-2 theory's
  body frame is the mean rotation frame (its principal axes point, on average, along the rotation axis and to the
  mean Earth); the real Moon's principal axes are turned from it by that rotation, the pole by 78.56″ toward the
  mean Earth: a monthly circle in space.
* The mean inclination I of the equator to the ecliptic, the observed one (Eckhardt's, Meeus 1998 ch. 53).
* The free wobble: the principal axes' free motion in the body (8.2″ × 3.3″, 74.6 years), with the period Rambaux &
  Williams (2011) found in DE421 and the amplitude and phase measured in DE421 over the LLR era
  (:func:`free_wobble`).
* The lag behind the moving ecliptic (:func:`ecliptic_lag_vector`): the Laplace pole (the ecliptic pole of date)
  moves at v ≈ 47″/cy; the orbit normal circling it at the node rate Ω̇ lags by v/|Ω̇| (1.4″), and the spin pole,
  whose free precession in space is ω_p, by (1 + (I/i)(1 − ω_p/Ω̇)) Ω̇/ω_p times that (5.3: 7.3″), across the
  ecliptic pole's motion. Derived below; nothing here is fitted.

The lag. In the tangent plane at the Laplace pole K (complex z, K × ↔ multiplication by i), the orbit normal and the
spin pole obey dz_n/dt = iΩ̇ z_n − v and dz_s/dt = iα(z_s − z_n) + iβ z_s − v: the spin precesses about the orbit
normal (α) and about K under the Sun (β), and a pole fixed in space drifts by −v in the frame that follows K. The
forced circles give α/(α + β − Ω̇) = −I/i (Cassini state 2: the spin across K from the orbit normal) and the free
mode ω_p = α + β; the constant parts are δ_n = −iv/Ω̇ and δ_s = (α δ_n − iv)/ω_p = δ_n (1 + α/Ω̇) Ω̇/ω_p. With the
Moon's Ω̇ (18.6 yr) and ω_p (79.8 yr), δ_s ≈ 5.3 δ_n = 7.3″ toward −X of the ecliptic of date, and 0.66″ along +Y
from the ecliptic pole's slower motion in X. DE421's pole lies 7.56″ and 0.65″ from the series' there
(docs/moon.md); its orbit normal 1.35″ (DE421's lunar orbit), the δ_n above.

Radians and days unless a name says otherwise; frames: the mean ecliptic and equinox of date (IAU 2006), body axes
X toward the mean Earth, Z the pole.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..base.constants import ARCSEC
from ..base.disk_cache import read_toml
from ..base.paths import data_dir
from .libration_frames import rodrigues


def frame_rotation(angle, axis: int) -> np.ndarray:
    """SPICE's frame rotation [a]_k (..., 3, 3) about axis k (1, 2, 3): the coordinates of a fixed vector in the frame
    turned by ``angle`` (radians) about that axis."""
    a = np.asarray(angle, dtype=float)
    c, s = np.cos(a), np.sin(a)
    z, o = np.zeros_like(a), np.ones_like(a)
    rows = {3: [[c, s, z], [-s, c, z], [z, z, o]],
            2: [[c, z, -s], [z, o, z], [s, z, c]],
            1: [[o, z, z], [z, c, s], [z, -s, c]]}[axis]
    return np.moveaxis(np.array(rows), [0, 1], [-2, -1])


@lru_cache(maxsize=1)
def orientation_data() -> dict:
    """data/moon_orientation.toml, parsed."""
    return read_toml(data_dir() / "moon_orientation.toml")


@lru_cache(maxsize=1)
def me_to_pa() -> np.ndarray:
    """The matrix taking mean-Earth (ME) coordinates to principal-axis (PA) coordinates, (3, 3): the frame kernel's
    angles as SPICE reads a TKFRAME of ``AXES = (3, 2, 1)``, [a1]_3 [a2]_2 [a3]_1 (data/moon_orientation.toml
    [pa_to_me]). The PA axes in any frame are the ME axes times its transpose: B_PA = B_ME @ me_to_pa().T."""
    d = orientation_data()["pa_to_me"]
    a = [v * ARCSEC for v in d["angles_arcsec"]]
    k = [int(x) for x in d["axes"]]
    return frame_rotation(a[0], k[0]) @ frame_rotation(a[1], k[1]) @ frame_rotation(a[2], k[2])


def pa_offset_angle() -> float:
    """The angle (rad) between the PA and ME poles: 78.56″ for DE421."""
    z = me_to_pa()[2]
    return math.atan2(math.hypot(z[0], z[1]), z[2])


def mean_inclination() -> tuple[float, float]:
    """(I, its uncertainty), radians: the observed mean inclination of the lunar equator to the ecliptic."""
    d = orientation_data()["mean_inclination"]
    return math.radians(d["deg"]), d["uncertainty_arcsec"] * ARCSEC


@dataclass(frozen=True)
class FreeWobble:
    """The free wobble as a small body-frame rotation (radians), its period (days) and phase epoch (JD TDB)."""

    period_days: float
    epoch: float
    x: tuple          # (cos, sin) coefficients of the rotation about body X, rad
    y: tuple          # (cos, sin) about body Y

    @property
    def amplitudes(self) -> tuple[float, float]:
        return math.hypot(*self.x), math.hypot(*self.y)

    def rotation(self, jd_tdb) -> np.ndarray:
        """The rotation vectors (N, 3) taking the forced axes to the wobbling ones, in the body frame."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        ph = 2.0 * math.pi * (t - self.epoch) / self.period_days
        c, s = np.cos(ph), np.sin(ph)
        return np.stack([self.x[0] * c + self.x[1] * s, self.y[0] * c + self.y[1] * s, np.zeros_like(t)], axis=-1)

    def apply(self, axes: np.ndarray, jd_tdb) -> np.ndarray:
        """Body axes (N, 3, 3; columns) turned by the wobble: axes @ exp([w×])."""
        q, _ = rodrigues(self.rotation(jd_tdb).T)
        return np.einsum("nij,jkn->nik", axes, q)


@lru_cache(maxsize=1)
def free_wobble() -> FreeWobble:
    """The Moon's free wobble (data/moon_orientation.toml [free_wobble])."""
    d = orientation_data()["free_wobble"]
    return FreeWobble(float(d["period_days"]), float(d["epoch_jd_tdb"]),
                      (d["x_cos_arcsec"] * ARCSEC, d["x_sin_arcsec"] * ARCSEC),
                      (d["y_cos_arcsec"] * ARCSEC, d["y_sin_arcsec"] * ARCSEC))


def lag_ratio(inclination: float, orbit_inclination: float, node_rate: float, free_precession_days: float) -> float:
    """δ_s / δ_n = (1 + (I/i)(1 − ω_p/Ω̇)) Ω̇/ω_p (module docstring): how much farther than the orbit normal the spin
    pole lags the moving Laplace pole. ``node_rate`` Ω̇ (rad/day, signed, inertial), ``free_precession_days`` the
    free precession of the pole in space (same sense as the node's)."""
    w_p = math.copysign(2.0 * math.pi / free_precession_days, node_rate)
    r = w_p / node_rate
    return (1.0 + inclination / orbit_inclination * (1.0 - r)) / r


def ecliptic_pole_velocity(jd_tdb) -> np.ndarray:
    """v (N, 3): the ecliptic pole of date's velocity (rad/day) in the mean ecliptic and equinox of date, from IAU
    2006's ecliptic (erfa.ecm06) by central differences over ±1 day (its curvature, ~1e-9 of v, is far below use)."""
    import erfa

    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    h = 1.0

    def pole(x):
        return erfa.ecm06(x, np.zeros_like(x))[:, 2, :]          # the ecliptic pole in the ICRS (ecm06's 3rd row)

    return np.einsum("nij,nj->ni", erfa.ecm06(t, np.zeros_like(t)), (pole(t + h) - pole(t - h)) / (2.0 * h))


#: epochs at which the lag is evaluated over a track, linear between: v turns with the equinox (p_A, 1.4° a century)
#: and changes its speed by parts in 1e3 a century, so 33 nodes over even 150 years leave < 1e-6 of the lag
LAG_NODES = 33


def ecliptic_lag_vector(jd_tdb, node_rate: float, ratio: float) -> np.ndarray:
    """δ_s (N, 3), radians, in the ecliptic of date: the spin pole's steady lag behind the moving ecliptic pole,
    ``ratio`` (:func:`lag_ratio`) times the orbit normal's δ_n = K × v / |Ω̇| (v at :data:`LAG_NODES` epochs across
    the span, linear between, when there are more epochs)."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    if t.size > LAG_NODES and t.max() > t.min():
        nodes = np.linspace(t.min(), t.max(), LAG_NODES)
        vn = ecliptic_pole_velocity(nodes)
        v = np.stack([np.interp(t, nodes, vn[:, k]) for k in range(2)], axis=-1)
    else:
        v = ecliptic_pole_velocity(t)
    dn = np.stack([-v[:, 1], v[:, 0], np.zeros(v.shape[0])], axis=-1) / abs(node_rate)
    return ratio * dn


def lag_rotation(delta: np.ndarray) -> np.ndarray:
    """The space-frame rotations (N, 3, 3) that move the pole of date (+Z) by the small vectors ``delta`` (N, 3)."""
    q, _ = rodrigues(np.cross(np.array([0.0, 0.0, 1.0]), delta).T)
    return np.moveaxis(q, -1, 0)
