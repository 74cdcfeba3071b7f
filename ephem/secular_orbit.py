"""The planets' orbit planes over long spans: Laplace–Lagrange secular theory of the inclinations.

The first rung of the long-term orbit (the spin axis over millennia): averaged over the orbits, the mutual
perturbations of the planets turn their orbit planes slowly. To first order in the masses and second in the
inclinations (Murray & Dermott 1999, Solar System Dynamics, ch. 7, eqs. 7.9-7.11, 7.25-7.28), with
p_j = I_j sin Ω_j, q_j = I_j cos Ω_j of planet j (I_j its inclination, Ω_j its node, on a fixed reference
plane: here the ecliptic of J2000),

    dp_j/dt = Σ_k B_jk q_k,    dq_j/dt = −Σ_k B_jk p_k,
    B_jk = n_j/4 (m_k / (M + m_j)) α_jk ᾱ_jk b_{3/2}^{(1)}(α_jk),    B_jj = −Σ_{k≠j} B_jk,

α_jk the ratio of the smaller to the larger semi-major axis, ᾱ_jk = α_jk for an outer perturber and 1 for an
inner one, b_{3/2}^{(1)} the Laplace coefficient (:func:`laplace_coefficient`). B's eigenvalues f_i (rad/day,
one zero: the invariable plane) and eigenvectors give

    p_j(t) = Σ_i I_ji sin(f_i t + γ_i),    q_j(t) = Σ_i I_ji cos(f_i t + γ_i),

the amplitudes and phases fixed by the planets' (p, q) at J2000. Those come from the mean planetary theory of
Simon et al. (1994) (``erfa.plan94``: Mercury to Neptune, the Earth-Moon barycentre for the Earth); the masses
are DE421's (:data:`ephem.ephemeris.GM_DE421`, the planetary systems). Good for the slow modes over millennia;
what it leaves out (second order in the masses, the Jupiter-Saturn near-resonance, the inclination's higher
powers, the eccentricities' coupling) grows with the span and is measured against the long-term ecliptic of
Vondrák et al. (2011) in tests/test_secular_orbit.py. Radians and days unless a name says otherwise.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .constants import J2000_JD
from .ephemeris import GM_DE421, GM_SUN_DE421
from .geometry import icrf_to_ecliptic_matrix

#: the planets of the theory: (name, erfa.plan94 index, DE421 GM key)
PLANETS = (("Mercury", 1, 1), ("Venus", 2, 2), ("Earth", 3, 399), ("Mars", 4, 4), ("Jupiter", 5, 5),
           ("Saturn", 6, 6), ("Uranus", 7, 7), ("Neptune", 8, 8))
#: the trapezoid rule's points for the Laplace coefficients: geometric convergence, 1e-15 relative at α = 0.73
#: (Venus-Earth, the closest pair) with 2048
_LAPLACE_POINTS = 2048


def laplace_coefficient(alpha: float, s: float = 1.5, j: int = 1) -> float:
    """b_s^(j)(α) = (1/π) ∫_0^{2π} cos jψ / (1 − 2α cos ψ + α²)^s dψ (Murray & Dermott eq. 6.67)."""
    psi = np.linspace(0.0, 2.0 * math.pi, _LAPLACE_POINTS, endpoint=False)
    return float(2.0 * np.mean(np.cos(j * psi) / (1.0 - 2.0 * alpha * np.cos(psi) + alpha * alpha) ** s))


@dataclass(frozen=True)
class SecularInclinations:
    """The Laplace–Lagrange solution for the planets' orbit planes (radians, rad/day, JD TDB)."""

    names: tuple
    frequencies: np.ndarray      # f_i, rad/day (one ~0: the invariable plane)
    amplitudes: np.ndarray       # I_ji, (planet j, mode i)
    phases: np.ndarray           # γ_i, rad at J2000

    def pq(self, name: str, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """(p, q) = (I sin Ω, I cos Ω) of planet ``name`` at JD TDB (any shape)."""
        j = self.names.index(name)
        t = np.asarray(jd_tdb, dtype=float)[..., None] - J2000_JD
        arg = self.frequencies * t + self.phases
        return (np.sum(self.amplitudes[j] * np.sin(arg), axis=-1), np.sum(self.amplitudes[j] * np.cos(arg), axis=-1))

    def orbit_pole(self, name: str, jd_tdb) -> np.ndarray:
        """The planet's orbit normal, unit vectors (..., 3) in the ecliptic and equinox of J2000: (sin I sin Ω,
        −sin I cos Ω, cos I) with I = √(p² + q²) (the theory's variables are small angles)."""
        p, q = self.pq(name, jd_tdb)
        inc = np.hypot(p, q)
        s = np.where(inc > 0.0, np.sin(inc) / np.where(inc > 0.0, inc, 1.0), 1.0)
        return np.stack([s * p, -s * q, np.cos(inc)], axis=-1)


def secular_matrix(a_au: np.ndarray, mass_ratio: np.ndarray) -> np.ndarray:
    """B (rad/day): Murray & Dermott eqs. 7.10-7.11 for planets of semi-major axes ``a_au`` and masses
    ``mass_ratio`` (over the Sun's)."""
    n_planets = a_au.size
    n = np.sqrt(GM_SUN_DE421 * (1.0 + mass_ratio) / a_au**3)
    B = np.zeros((n_planets, n_planets))
    for j in range(n_planets):
        for k in range(n_planets):
            if j == k:
                continue
            alpha = min(a_au[j], a_au[k]) / max(a_au[j], a_au[k])
            alpha_bar = alpha if a_au[j] < a_au[k] else 1.0
            B[j, k] = 0.25 * n[j] * mass_ratio[k] / (1.0 + mass_ratio[j]) * alpha * alpha_bar \
                * laplace_coefficient(alpha)
        B[j, j] = -B[j].sum()
    return B


def planet_elements_j2000() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(a AU, I, Ω) of the planets at J2000 on the ecliptic of J2000, from Simon et al. (1994) (erfa.plan94)."""
    import erfa

    ecl = icrf_to_ecliptic_matrix()
    out = []
    for _, index, key in PLANETS:
        position, velocity = erfa.plan94(J2000_JD, 0.0, index)        # AU, AU/day, J2000 equatorial
        r, v = ecl @ np.asarray(position), ecl @ np.asarray(velocity)
        h = np.cross(r, v)
        inc = math.atan2(math.hypot(h[0], h[1]), h[2])
        node = math.atan2(h[0], -h[1])
        mu = GM_SUN_DE421 * (1.0 + GM_DE421[key] / GM_SUN_DE421)
        a = 1.0 / (2.0 / float(np.linalg.norm(r)) - float(v @ v) / mu)
        out.append((a, inc, node))
    a, inc, node = (np.array(x) for x in zip(*out))
    return a, inc, node


@lru_cache(maxsize=1)
def laplace_lagrange() -> SecularInclinations:
    """The solution for the eight planets (module docstring)."""
    a, inc, node = planet_elements_j2000()
    mass = np.array([GM_DE421[key] / GM_SUN_DE421 for _, _, key in PLANETS])
    B = secular_matrix(a, mass)
    f, vec = np.linalg.eig(B)
    f, vec = f.real, vec.real
    # p_j(0) = Σ_i S_i e_ji sin γ_i, q_j(0) = Σ_i S_i e_ji cos γ_i: solve for S_i sin γ_i, S_i cos γ_i
    ssin = np.linalg.solve(vec, inc * np.sin(node))
    scos = np.linalg.solve(vec, inc * np.cos(node))
    scale, phase = np.hypot(ssin, scos), np.arctan2(ssin, scos)
    return SecularInclinations(tuple(p[0] for p in PLANETS), f, vec * scale[None, :], phase)
