"""The geodesic (de Sitter) precession: the relativistic turning of a spinning body's axis as it orbits a mass.

A gyroscope carried on an orbit about a mass M turns, relative to the distant stars (the kinematically
non-rotating barycentric frame of the ICRS), about the orbit normal in the orbital sense, at the orbit-averaged
rate (de Sitter 1916; Fukushima 1991, A&A 244, L11; Soffel et al. 2003, the IAU 2000 resolutions' framework)

    Ω_gp = (3/2) (G M / (c² a (1 − e²))) n,

first post-Newtonian order (the next is ~G M/(c² a) ~ 1e-8 smaller). For the Earth it is the −1.919883″ per
century of IAU 2006's ψ_A (Capitaine et al. 2003, P03, after Fukushima's value for the Earth-Moon barycentre);
for Mars about 6.75 mas per year. In the precession angle ψ (positive retrograde, the Earth's sense) it enters
as −Ω_gp, whatever the obliquity: it is a rotation about the orbit normal. Radians and days.
"""
from __future__ import annotations

import numpy as np

from ..base.centres import GM_CENTER
from ..base.constants import AU_M, SPEED_OF_LIGHT_M_S
from .kepler import mean_motion_rad_per_day, true_anomaly


def geodesic_precession_rate(a_au: float, e: float, center: str = "Sun") -> float:
    """Ω_gp (rad/day) of a body on an orbit of semi-major axis ``a_au`` and eccentricity ``e`` about ``center``
    (module docstring): the rate at which its spin axis turns about the orbit normal, in the orbital sense."""
    gm_over_c2 = GM_CENTER[center] / SPEED_OF_LIGHT_M_S**2            # m
    return 1.5 * gm_over_c2 / (a_au * AU_M * (1.0 - e * e)) * mean_motion_rad_per_day(a_au, center)


def geodesic_angle(rate: float, mean_motion: float, e: float, mean_anomaly, mean_anomaly_start: float):
    """The angle (radians) the axis turns about the orbit normal at the *instantaneous* geodesic rate
    (3/2)(G M / c²) h / r³ along a Keplerian orbit, from mean anomaly ``mean_anomaly_start`` to ``mean_anomaly``
    (unwrapped, radians; ``rate`` Ω_gp and ``mean_motion`` n in rad/day).

    With h/r² = ν̇ and 1/r = (1 + e cos ν)/p the angle since pericentre is (Ω_gp / n)(ν + e sin ν): the mean rate
    Ω_gp times the time plus the periodic g(M) = (Ω_gp / n)(ν + e sin ν − M), whose largest value is what the
    orbit-averaged rate leaves (a "geodesic nutation" of 0.35 mas for Vesta, 2 mas for Itokawa).
    """
    m = np.asarray(mean_anomaly, dtype=float)
    return rate / mean_motion * (m - mean_anomaly_start + geodesic_periodic(e, m) - geodesic_periodic(
        e, np.asarray(mean_anomaly_start, dtype=float)))


def geodesic_periodic(e: float, mean_anomaly) -> np.ndarray:
    """ν + e sin ν − M (radians) wrapped to (−π, π]: the periodic part of the geodesic angle per unit Ω_gp / n
    (:func:`geodesic_angle`)."""
    m = np.asarray(mean_anomaly, dtype=float)
    nu = true_anomaly(m, e)
    return np.remainder(nu + e * np.sin(nu) - m + np.pi, 2.0 * np.pi) - np.pi
