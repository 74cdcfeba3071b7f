"""The orbits over long spans by Laplace–Lagrange secular theory: the planets' and a small body's.

The planets' orbit planes and eccentricities,
and a small body's orbit in the planets' field.

The first rung of the long-term orbit (the spin axis over millennia): averaged over the orbits, the mutual
perturbations of the planets turn their orbit planes and their perihelia slowly. To first order in the masses
and second in the eccentricities and inclinations (Murray & Dermott 1999, Solar System Dynamics, ch. 7), with
h_j = e_j sin ϖ_j, k_j = e_j cos ϖ_j and p_j = I_j sin Ω_j, q_j = I_j cos Ω_j of planet j (e_j its eccentricity,
ϖ_j = Ω_j + ω_j its longitude of perihelion, I_j its inclination, Ω_j its node, on a fixed reference plane: here
the ecliptic and equinox of J2000),

    dh_j/dt = Σ_k A_jk k_k,    dk_j/dt = −Σ_k A_jk h_k,      dp_j/dt = Σ_k B_jk q_k,    dq_j/dt = −Σ_k B_jk p_k,
    A_jj = n_j/4 Σ_{k≠j} (m_k / (M + m_j)) α_jk ᾱ_jk b_{3/2}^{(1)}(α_jk),
    A_jk = −n_j/4 (m_k / (M + m_j)) α_jk ᾱ_jk b_{3/2}^{(2)}(α_jk)                    (M&D eqs. 7.9-7.10)
    B_jk = n_j/4 (m_k / (M + m_j)) α_jk ᾱ_jk b_{3/2}^{(1)}(α_jk),    B_jj = −Σ_{k≠j} B_jk,

α_jk the ratio of the smaller to the larger semi-major axis, ᾱ_jk = α_jk for an outer perturber and 1 for an
inner one, b_{3/2}^{(j)} the Laplace coefficients (:func:`laplace_coefficient`). The eigenvalues g_i of A and f_i
of B (rad/day; one f is zero: the invariable plane) and their eigenvectors give

    h_j(t) = Σ_i e_ji sin(g_i t + β_i),    k_j(t) = Σ_i e_ji cos(g_i t + β_i),    (p_j, q_j) likewise (I_ji, f_i, γ_i),

the amplitudes and phases fixed by the planets' elements at J2000. Those come from the mean planetary theory of
Simon et al. (1994) (``erfa.plan94``: Mercury to Neptune, the Earth-Moon barycentre for the Earth); the masses
are DE421's (:data:`ephem.orbit.de421_header.GM_DE421`, the planetary systems). Each mode is named after the planet that
carries the largest share of its angular momentum (g_1 … g_8, s_1 … s_8; s_5 = 0 is the invariable plane's).

A massless body of semi-major axis a in that field (M&D §7.7) has the free frequencies

    A = n/4 Σ_j μ_j α_j ᾱ_j b_{3/2}^{(1)}(α_j),    B = −A    (μ_j = m_j / M, n the body's mean motion),

and is driven by each planetary mode: its forced elements are h_0 = −Σ_i ν_i / (A − g_i) sin(g_i t + β_i), with
ν_i = Σ_j A_j e_ji, A_j = −n/4 μ_j α_j ᾱ_j b_{3/2}^{(2)}(α_j), and p_0 = −Σ_i μ_i / (B − f_i) sin(f_i t + γ_i),
μ_i = Σ_j B_j I_ji, B_j = n/4 μ_j α_j ᾱ_j b_{3/2}^{(1)}(α_j) (k_0, q_0 with cosines). Its free elements (amplitude and
phase of the terms at A and B: the proper elements of the linear theory) are what is left of its osculating
elements at their epoch once the forced ones are taken away. The forced amplitudes diverge at a secular resonance
(A = g_i: ν_i; B = f_i: ν_1i), and the expansion in e and α fails for an orbit that crosses a planet's: both are
refused (:class:`~ephem.base.errors.NotApplicableError`) rather than answered with a huge number.

Good for the slow modes over millennia; what it leaves out (second order in the masses, the Jupiter-Saturn
near-resonance, the mean-motion near-resonances of the asteroids with Jupiter, the higher powers of e and I)
shows as an error in the frequencies: 1.3 % for the ecliptic's motion against Vondrák et al. (2011), 0.7-2.3 %
for Ceres' and Vesta's s and 5-9 % for their g against AstDyS's synthetic proper frequencies
(tests/longterm/test_secular_orbit.py). :class:`SecularOrbit` turns that into a horizon. Radians and days unless a name
says otherwise; the :class:`SecularOrbit` methods take Julian years from J2000.0 TDB.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..base.constants import ARCSEC, J2000_JD, JULIAN_YEAR_DAYS
from ..orbit.de421_header import GM_DE421, GM_SUN_DE421
from ..base.errors import NotApplicableError
from ..orbit.geometry import icrf_to_ecliptic_matrix

#: the planets of the theory: (name, erfa.plan94 index, DE421 GM key)
PLANETS = (("Mercury", 1, 1), ("Venus", 2, 2), ("Earth", 3, 399), ("Mars", 4, 4), ("Jupiter", 5, 5),
           ("Saturn", 6, 6), ("Uranus", 7, 7), ("Neptune", 8, 8))
#: the trapezoid rule's points for the Laplace coefficients: geometric convergence, 1e-15 relative at α = 0.73
#: (Venus-Earth, the closest pair) with 2048
_LAPLACE_POINTS = 2048
#: first-order theory's error in the inclinations' frequencies, as a fraction: measured 1.3 % for the ecliptic's
#: motion (Vondrák et al. 2011), 0.7 % and 2.3 % for Ceres' and Vesta's s (AstDyS); 3 % bounds them. The horizon
#: of a :class:`SecularOrbit` is the span over which that error turns its orbit pole by :data:`HORIZON_ANGLE`.
FREQUENCY_ERROR = 0.03
#: the pole error that ends a :class:`SecularOrbit`'s horizon (radians): one arcminute
HORIZON_ANGLE = 60.0 * ARCSEC
#: a secular resonance is refused when the body's free frequency lies nearer a planetary mode than this fraction
#: of itself (first-order theory cannot tell on which side of the resonance the body is: its g is off by up to
#: 9 % in the main belt) ...
RESONANCE_FRACTION = 0.1
#: ... or when a single mode forces an eccentricity (or an inclination, radians) above this: the theory is the
#: first term of an expansion in e and I
FORCED_LIMIT = 0.1
#: the largest inclination to the ecliptic (degrees) taken: beyond the Lidov-Kozai critical 39.2° the terms of
#: fourth degree in e and I that the theory leaves out couple e and I and change the motion's kind
MAX_INCLINATION_DEG = 39.2

def laplace_coefficient(alpha: float, s: float = 1.5, j: int = 1) -> float:
    """b_s^(j)(α) = (1/π) ∫_0^{2π} cos jψ / (1 − 2α cos ψ + α²)^s dψ (Murray & Dermott eq. 6.67)."""
    psi = np.linspace(0.0, 2.0 * math.pi, _LAPLACE_POINTS, endpoint=False)
    return float(2.0 * np.mean(np.cos(j * psi) / (1.0 - 2.0 * alpha * np.cos(psi) + alpha * alpha) ** s))


def _alpha(a_in: float, a_other: float) -> tuple[float, float]:
    """(α, ᾱ) of a body at ``a_in`` perturbed by one at ``a_other``: α the smaller over the larger semi-major axis,
    ᾱ = α for an outer perturber, 1 for an inner one (Murray & Dermott §7.2)."""
    alpha = min(a_in, a_other) / max(a_in, a_other)
    return alpha, (alpha if a_in < a_other else 1.0)


def _mean_motion(a_au, mass_ratio=0.0):
    """n = √(GM_sun (1 + m/M) / a³), rad/day."""
    return np.sqrt(GM_SUN_DE421 * (1.0 + np.asarray(mass_ratio, dtype=float)) / np.asarray(a_au, dtype=float) ** 3)


def _couplings(a_au: np.ndarray, mass_ratio: np.ndarray, order: int) -> np.ndarray:
    """C_jk = n_j/4 (m_k / (M + m_j)) α_jk ᾱ_jk b_{3/2}^{(order)}(α_jk) (rad/day), zero on the diagonal: the
    common factor of A's and B's entries."""
    n = _mean_motion(a_au, mass_ratio)
    C = np.zeros((a_au.size, a_au.size))
    for j in range(a_au.size):
        for k in range(a_au.size):
            if j != k:
                alpha, alpha_bar = _alpha(a_au[j], a_au[k])
                C[j, k] = 0.25 * n[j] * mass_ratio[k] / (1.0 + mass_ratio[j]) * alpha * alpha_bar \
                    * laplace_coefficient(alpha, 1.5, order)
    return C


def secular_matrix(a_au: np.ndarray, mass_ratio: np.ndarray) -> np.ndarray:
    """B (rad/day), the inclinations' matrix (Murray & Dermott §7.2, the B_jj, B_jk beside A's eqs. 7.9-7.10), for
    planets of semi-major axes ``a_au`` and masses ``mass_ratio`` (over the Sun's)."""
    B = _couplings(a_au, mass_ratio, 1)
    B[np.diag_indices(a_au.size)] = -B.sum(axis=1)
    return B


def eccentricity_matrix(a_au: np.ndarray, mass_ratio: np.ndarray) -> np.ndarray:
    """A (rad/day): Murray & Dermott eqs. 7.9-7.10 for planets of semi-major axes ``a_au`` and masses
    ``mass_ratio`` (over the Sun's). The eccentricities' matrix: A_jj = Σ_k C¹_jk, A_jk = −C²_jk."""
    A = -_couplings(a_au, mass_ratio, 2)
    A[np.diag_indices(a_au.size)] = _couplings(a_au, mass_ratio, 1).sum(axis=1)
    return A


@dataclass(frozen=True)
class SecularModes:
    """One Laplace–Lagrange solution of the planets (radians, rad/day, JD TDB): x_j = Σ_i amp_ji sin(ω_i t + φ_i),
    y_j = Σ_i amp_ji cos(ω_i t + φ_i), t = JD − J2000; (x, y) = (h, k) or (p, q)."""

    names: tuple
    frequencies: np.ndarray      # ω_i, rad/day
    amplitudes: np.ndarray       # amp_ji, (planet j, mode i)
    phases: np.ndarray           # φ_i, rad at J2000
    labels: tuple                # labels[i]: the index of the planet whose mode i is (the largest share of it)

    def series(self, name: str, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """(x, y) of planet ``name`` at JD TDB (any shape)."""
        j = self.names.index(name)
        arg = self.frequencies * (np.asarray(jd_tdb, dtype=float)[..., None] - J2000_JD) + self.phases
        return (np.sum(self.amplitudes[j] * np.sin(arg), axis=-1), np.sum(self.amplitudes[j] * np.cos(arg), axis=-1))

    def mode_of(self, name: str) -> int:
        """The index of planet ``name``'s own mode (g_j or s_j)."""
        return self.labels.index(self.names.index(name))


class SecularInclinations(SecularModes):
    """The planets' orbit planes: (p, q) = (I sin Ω, I cos Ω), frequencies f_i (one ~0: the invariable plane)."""

    def pq(self, name: str, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """(p, q) = (I sin Ω, I cos Ω) of planet ``name`` at JD TDB (any shape)."""
        return self.series(name, jd_tdb)

    def orbit_pole(self, name: str, jd_tdb) -> np.ndarray:
        """The planet's orbit normal, unit vectors (..., 3) in the ecliptic and equinox of J2000 (:func:`pole`)."""
        return pole(*self.pq(name, jd_tdb))


class SecularEccentricities(SecularModes):
    """The planets' eccentricity vectors: (h, k) = (e sin ϖ, e cos ϖ), frequencies g_i."""

    def hk(self, name: str, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        """(h, k) = (e sin ϖ, e cos ϖ) of planet ``name`` at JD TDB (any shape)."""
        return self.series(name, jd_tdb)

    def eccentricity(self, name: str, jd_tdb) -> np.ndarray:
        """e = √(h² + k²) of planet ``name`` at JD TDB (any shape)."""
        return np.hypot(*self.hk(name, jd_tdb))


def pole(p, q) -> np.ndarray:
    """The orbit normal of (p, q) = (I sin Ω, I cos Ω): (sin I sin Ω, −sin I cos Ω, cos I), unit vectors (..., 3) in
    the frame of the reference plane, with I = √(p² + q²) (the theory's variables are small angles)."""
    p, q = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    inc = np.hypot(p, q)
    s = np.where(inc > 0.0, np.sin(inc) / np.where(inc > 0.0, inc, 1.0), 1.0)
    return np.stack([s * p, -s * q, np.cos(inc)], axis=-1)


def _modes(matrix: np.ndarray, x0: np.ndarray, y0: np.ndarray, weight: np.ndarray):
    """Eigen-solution of dx/dt = M y, dy/dt = −M x fixed by (x0, y0) at J2000: (ω_i, amp_ji, φ_i, labels). The
    labels come from the symmetric form of M (weights Λ_j = m_j n_j a_j², the planets' angular momenta, make
    Λ_j M_jk symmetric): mode i belongs to the planet of the largest share Λ_j v_ji² / Σ_j Λ_j v_ji², taken
    greedily, largest first."""
    freq, vec = np.linalg.eig(matrix)
    freq, vec = freq.real, vec.real
    # x_j(0) = Σ_i S_i v_ji sin φ_i, y_j(0) = Σ_i S_i v_ji cos φ_i: solve for S_i sin φ_i, S_i cos φ_i
    ssin, scos = np.linalg.solve(vec, x0), np.linalg.solve(vec, y0)
    share = weight[:, None] * vec**2
    share = share / share.sum(axis=0)
    labels = [-1] * freq.size
    free_planets, free_modes = set(range(freq.size)), set(range(freq.size))
    for flat in np.argsort(share, axis=None)[::-1]:
        j, i = divmod(int(flat), freq.size)
        if j in free_planets and i in free_modes:
            labels[i] = j
            free_planets.discard(j)
            free_modes.discard(i)
    return freq, vec * np.hypot(ssin, scos)[None, :], np.arctan2(ssin, scos), tuple(labels)


def solve_planets(names, a_au, mass_ratio, e, varpi, inc, node) -> tuple[SecularEccentricities, SecularInclinations]:
    """The Laplace–Lagrange solution of planets ``names`` (semi-major axes AU, masses over the Sun's, and at J2000
    their eccentricities, longitudes of perihelion, inclinations and nodes, radians): (eccentricities,
    inclinations)."""
    a_au, mass_ratio = np.asarray(a_au, dtype=float), np.asarray(mass_ratio, dtype=float)
    e, varpi, inc, node = (np.asarray(x, dtype=float) for x in (e, varpi, inc, node))
    weight = mass_ratio * _mean_motion(a_au, mass_ratio) * a_au**2
    names = tuple(names)
    ecc = SecularEccentricities(names, *_modes(eccentricity_matrix(a_au, mass_ratio), e * np.sin(varpi),
                                               e * np.cos(varpi), weight))
    incl = SecularInclinations(names, *_modes(secular_matrix(a_au, mass_ratio), inc * np.sin(node),
                                              inc * np.cos(node), weight))
    return ecc, incl


@lru_cache(maxsize=1)
def planet_orbits_j2000() -> tuple[np.ndarray, ...]:
    """(a AU, e, ϖ, I, Ω) of the planets at J2000 on the ecliptic and equinox of J2000 (radians), from Simon et
    al. (1994) (erfa.plan94; the Earth-Moon barycentre for the Earth)."""
    import erfa

    ecl = icrf_to_ecliptic_matrix()
    out = []
    for _, index, key in PLANETS:
        position, velocity = erfa.plan94(J2000_JD, 0.0, index)        # AU, AU/day, J2000 equatorial
        r, v = ecl @ np.asarray(position), ecl @ np.asarray(velocity)
        mu = GM_SUN_DE421 * (1.0 + GM_DE421[key] / GM_SUN_DE421)
        h = np.cross(r, v)
        inc = math.atan2(math.hypot(h[0], h[1]), h[2])
        node = math.atan2(h[0], -h[1])
        a = 1.0 / (2.0 / float(np.linalg.norm(r)) - float(v @ v) / mu)
        ecc = np.cross(v, h) / mu - r / np.linalg.norm(r)
        n_hat = np.array([math.cos(node), math.sin(node), 0.0])
        omega = math.atan2(float(np.cross(n_hat, ecc) @ h) / float(np.linalg.norm(h)), float(n_hat @ ecc))
        out.append((a, float(np.linalg.norm(ecc)), (node + omega) % (2.0 * math.pi), inc, node))
    return tuple(np.array(x) for x in zip(*out))


def planet_masses() -> np.ndarray:
    """The planets' masses over the Sun's (DE421; the Earth-Moon system for the Earth)."""
    return np.array([GM_DE421[key] / GM_SUN_DE421 for _, _, key in PLANETS])


@lru_cache(maxsize=1)
def _planets_solution() -> tuple[SecularEccentricities, SecularInclinations]:
    a, e, varpi, inc, node = planet_orbits_j2000()
    return solve_planets(tuple(p[0] for p in PLANETS), a, planet_masses(), e, varpi, inc, node)


def laplace_lagrange() -> SecularInclinations:
    """The solution for the eight planets' inclinations (module docstring)."""
    return _planets_solution()[1]


def laplace_lagrange_eccentricities() -> SecularEccentricities:
    """The solution for the eight planets' eccentricities (module docstring)."""
    return _planets_solution()[0]


@dataclass(frozen=True)
class SecularOrbit:
    """An orbit by secular theory: its plane, eccentricity and semi-major axis over long spans.

    (h, k) = Σ_m E_m (sin, cos)(g_m t + β_m) and (p, q) = Σ_m I_m (sin, cos)(s_m t + γ_m), t the days from J2000.0
    TDB; term 0 of each is the orbit's own (free) mode: a small body's free elements at its frequencies A and B
    (the proper elements of the linear theory), or a planet's own mode g_j, s_j. The methods take ``years``, Julian
    years of 365.25 days from J2000.0 TDB, any shape. The interface the spin integrations take (``pole_at``,
    ``eccentricity_at``, ``semi_major_axis_at``, ``horizon_years``, ``source``) is shared with
    :mod:`ephem.longterm.nbody_orbit`.

    ``horizon_years``: (past, future), Julian years from J2000.0 (past negative), as :class:`ephem.longterm.nbody_orbit.
    OrbitHistory` has it: the elements' epoch ± the span H over which first-order theory's frequency error
    (:data:`FREQUENCY_ERROR` of each term's frequency) can turn the orbit pole by :data:`HORIZON_ANGLE` (1′),
    Σ_m |I_m s_m| FREQUENCY_ERROR H = 1′. This is the secular drift only: the osculating pole also carries the
    short-period terms no secular theory has (up to 2′ for Ceres, 1′ for Vesta, measured against the integrated
    orbit over 1925-2025). The eccentricity is less good over the same span: the g are off by up to 9 % in the
    main belt.
    """

    name: str
    a_au: float
    ecc_frequencies: np.ndarray     # g_m, rad/day
    ecc_amplitudes: np.ndarray      # E_m (signed)
    ecc_phases: np.ndarray          # β_m, rad at J2000
    inc_frequencies: np.ndarray     # s_m, rad/day
    inc_amplitudes: np.ndarray      # I_m, radians (signed)
    inc_phases: np.ndarray          # γ_m, rad at J2000
    horizon_years: tuple[float, float]
    source: str
    #: the epoch the solution was fixed at, Julian years from J2000.0 (0 for the planets)
    epoch_years: float = 0.0

    @property
    def g(self) -> float:
        """The free eccentricity frequency (rad/day): the body's A, or the planet's own g_j."""
        return float(self.ecc_frequencies[0])

    @property
    def s(self) -> float:
        """The free inclination frequency (rad/day): the body's B, or the planet's own s_j."""
        return float(self.inc_frequencies[0])

    @property
    def g_arcsec_per_year(self) -> float:
        return self.g * JULIAN_YEAR_DAYS / ARCSEC

    @property
    def s_arcsec_per_year(self) -> float:
        return self.s * JULIAN_YEAR_DAYS / ARCSEC

    @property
    def free_eccentricity(self) -> float:
        """The free (proper) eccentricity: the amplitude of the own mode."""
        return abs(float(self.ecc_amplitudes[0]))

    @property
    def free_inclination(self) -> float:
        """The free (proper) inclination, radians: to the forced plane, which moves."""
        return abs(float(self.inc_amplitudes[0]))

    @staticmethod
    def _sum(freq, amp, phase, years):
        arg = freq * (np.asarray(years, dtype=float)[..., None] * JULIAN_YEAR_DAYS) + phase
        return np.sum(amp * np.sin(arg), axis=-1), np.sum(amp * np.cos(arg), axis=-1)

    def hk_at(self, years) -> tuple[np.ndarray, np.ndarray]:
        """(h, k) = (e sin ϖ, e cos ϖ) at ``years`` (any shape)."""
        return self._sum(self.ecc_frequencies, self.ecc_amplitudes, self.ecc_phases, years)

    def pq_at(self, years) -> tuple[np.ndarray, np.ndarray]:
        """(p, q) = (I sin Ω, I cos Ω) at ``years`` (any shape), ecliptic and equinox of J2000, radians."""
        return self._sum(self.inc_frequencies, self.inc_amplitudes, self.inc_phases, years)

    def pole_at(self, years) -> np.ndarray:
        """The orbit normal at ``years``: unit vectors (..., 3) in the ecliptic and equinox of J2000."""
        return pole(*self.pq_at(years))

    def eccentricity_at(self, years) -> np.ndarray:
        """The eccentricity at ``years`` (any shape)."""
        return np.hypot(*self.hk_at(years))

    def semi_major_axis_at(self, years) -> np.ndarray:
        """The semi-major axis (AU) at ``years``: constant in secular theory."""
        return np.full(np.shape(years), self.a_au, dtype=float)

    def covers(self, start_years: float, stop_years: float) -> bool:
        """Whether [start, stop] (Julian years from J2000.0) lies inside the 1′ horizon."""
        return self.horizon_years[0] <= start_years and stop_years <= self.horizon_years[1]


def _horizon_years(inc_frequencies, inc_amplitudes, epoch_years: float = 0.0) -> tuple[float, float]:
    """(past, future), years from J2000: the epoch ± the span over which :data:`FREQUENCY_ERROR` of each term's
    frequency turns the pole by :data:`HORIZON_ANGLE` (class docstring)."""
    rate = FREQUENCY_ERROR * float(np.sum(np.abs(inc_frequencies * inc_amplitudes)))     # rad/day
    span = HORIZON_ANGLE / rate / JULIAN_YEAR_DAYS if rate > 0.0 else math.inf
    return epoch_years - span, epoch_years + span


def _mode_name(kind: str, label: int) -> str:
    return f"{kind}{label + 1}"


def planet_secular_history(name: str) -> SecularOrbit:
    """Planet ``name``'s orbit (Mercury … Neptune; the Earth-Moon barycentre for "Earth") by Laplace–Lagrange
    theory, its own modes g_j, s_j first."""
    ecc, incl = _planets_solution()
    if name not in ecc.names:
        raise NotApplicableError(name, f"not a planet of the secular theory ({', '.join(ecc.names)})")
    j = ecc.names.index(name)

    def ordered(modes):
        own = modes.mode_of(name)
        order = [own] + [i for i in range(modes.frequencies.size) if i != own]
        return modes.frequencies[order], modes.amplitudes[j, order], modes.phases[order]

    (gf, ga, gp), (sf, sa, sp) = ordered(ecc), ordered(incl)
    a = float(planet_orbits_j2000()[0][j])
    source = (f"Laplace–Lagrange secular theory, first order (Murray & Dermott 1999 ch. 7), of the eight planets "
              f"from Simon et al. (1994) J2000 elements (erfa.plan94) and DE421 masses: {name}")
    return SecularOrbit(name, a, gf, ga, gp, sf, sa, sp, _horizon_years(sf, sa), source)


def test_particle_coefficients(a_au: float, planets_a_au, planets_mass_ratio) -> tuple:
    """(A, A_j, B, B_j), rad/day, of a massless body at ``a_au`` in the field of planets at ``planets_a_au`` of
    masses ``planets_mass_ratio`` (over the Sun's) (Murray & Dermott §7.7; module docstring)."""
    n = float(_mean_motion(a_au))
    c1, c2 = [], []
    for a_j, mu_j in zip(np.asarray(planets_a_au, dtype=float), np.asarray(planets_mass_ratio, dtype=float)):
        alpha, alpha_bar = _alpha(a_au, a_j)
        factor = 0.25 * n * mu_j * alpha * alpha_bar
        c1.append(factor * laplace_coefficient(alpha, 1.5, 1))
        c2.append(factor * laplace_coefficient(alpha, 1.5, 2))
    c1, c2 = np.array(c1), np.array(c2)
    return float(c1.sum()), -c2, -float(c1.sum()), c1


def _refuse_crossing(body: str, a: float, e_lo: float, e_hi: float, planets_a, planets_e_max, names, when: str):
    """Refuse an orbit whose perihelion-aphelion band meets a planet's (over the planet's secular cycle): there
    the expansion of the disturbing function in e and α does not converge."""
    q, Q = a * (1.0 - e_hi), a * (1.0 + e_hi)
    for a_j, e_j, planet in zip(planets_a, planets_e_max, names):
        q_j, Q_j = a_j * (1.0 - e_j), a_j * (1.0 + e_j)
        if q < Q_j and Q > q_j:
            raise NotApplicableError(
                body, f"its orbit ({when}: perihelion {q:.3f} AU, aphelion {Q:.3f} AU) meets {planet}'s (perihelion "
                      f"{q_j:.3f} AU, aphelion {Q_j:.3f} AU at its largest secular eccentricity {e_j:.3f}): secular "
                      "theory's expansion in the eccentricities and the ratio of the semi-major axes fails for "
                      "crossing orbits", ratio=a / a_j, threshold=None)


def secular_orbit_history(orbit, planets: tuple[SecularEccentricities, SecularInclinations] | None = None,
                          planets_a_au=None, planets_mass_ratio=None, name: str | None = None) -> SecularOrbit:
    """A small body's orbit by first-order secular theory in the planets' field (Murray & Dermott §7.7), its free
    elements fixed by its osculating elements (``orbit``: an :class:`ephem.bodies.catalogue.Orbit`, heliocentric, on the
    ecliptic and equinox of J2000) at their epoch.

    ``planets`` (with ``planets_a_au``, ``planets_mass_ratio``): another planetary solution (:func:`solve_planets`),
    by default the eight planets'. Raises :class:`~ephem.base.errors.NotApplicableError` for an orbit not about the Sun,
    one inclined beyond :data:`MAX_INCLINATION_DEG`, one that crosses a planet's, or one near a secular resonance
    (:data:`RESONANCE_FRACTION`, :data:`FORCED_LIMIT`)."""
    body = name or getattr(orbit, "body", None) or "the body"
    if planets is None:
        planets = _planets_solution()
        planets_a_au, planets_mass_ratio = planet_orbits_j2000()[0], planet_masses()
    ecc_p, inc_p = planets
    planets_a_au, planets_mass_ratio = np.asarray(planets_a_au, dtype=float), np.asarray(planets_mass_ratio, float)
    if orbit.center != "Sun":
        raise NotApplicableError(body, f"its orbit is about the {orbit.center}: the secular theory is of orbits about "
                                       "the Sun in the planets' field")
    if orbit.frame != "ecliptic_j2000":
        raise NotApplicableError(body, f"its elements are on the {orbit.frame} frame: the secular theory takes "
                                       "osculating elements on the ecliptic and equinox of J2000")
    if orbit.i_deg > MAX_INCLINATION_DEG:
        raise NotApplicableError(body, f"its inclination {orbit.i_deg:.2f}° exceeds {MAX_INCLINATION_DEG}°: "
                                       "first-order secular theory (second degree in e and I) leaves out the "
                                       "Lidov-Kozai coupling of e and I", ratio=orbit.i_deg,
                                 threshold=MAX_INCLINATION_DEG)
    planet_e_max = np.sum(np.abs(ecc_p.amplitudes), axis=1)
    _refuse_crossing(body, orbit.a_au, orbit.e, orbit.e, planets_a_au, planet_e_max, ecc_p.names, "osculating")

    A, A_j, B, B_j = test_particle_coefficients(orbit.a_au, planets_a_au, planets_mass_ratio)
    year = JULIAN_YEAR_DAYS / ARCSEC      # rad/day -> arcsec/yr
    forced = []
    for kind, modes, free, coupling in (("ν", ecc_p, A, A_j), ("ν1", inc_p, B, B_j)):
        drive = coupling @ modes.amplitudes          # ν_i or μ_i
        distance = free - modes.frequencies
        for i in range(distance.size):
            amplitude = abs(drive[i] / distance[i]) if distance[i] != 0.0 else math.inf
            if abs(distance[i]) < RESONANCE_FRACTION * abs(free) or amplitude > FORCED_LIMIT:
                resonance = _mode_name(kind, modes.labels[i])
                which = "g" if kind == "ν" else "s"
                raise NotApplicableError(
                    body, f"near the secular resonance {resonance}: its free frequency {free * year:.3f}″/yr lies "
                          f"{distance[i] * year:+.3f}″/yr from the mode {_mode_name(which, modes.labels[i])} = "
                          f"{modes.frequencies[i] * year:.3f}″/yr (refused within {RESONANCE_FRACTION:.0%} of the "
                          f"free frequency, or a forced amplitude above {FORCED_LIMIT}: here {amplitude:.3g}); the "
                          "forced terms of linear secular theory diverge there",
                    ratio=abs(distance[i] / free), threshold=RESONANCE_FRACTION)
        forced.append((modes.frequencies, -drive / distance, modes.phases))

    # the free terms: the osculating elements at the epoch less the forced ones
    t_epoch = orbit.epoch_jd_tdb - J2000_JD
    epoch_years = t_epoch / JULIAN_YEAR_DAYS
    inc, node = math.radians(orbit.i_deg), math.radians(orbit.node_deg)
    varpi = math.radians(orbit.node_deg + orbit.peri_deg)
    terms = []
    for (freq, amp, phase), free, (x, y) in zip(forced, (A, B), ((orbit.e * math.sin(varpi), orbit.e * math.cos(varpi)),
                                                               (inc * math.sin(node), inc * math.cos(node)))):
        arg = freq * t_epoch + phase
        x_free, y_free = x - float(np.sum(amp * np.sin(arg))), y - float(np.sum(amp * np.cos(arg)))
        terms.append((np.concatenate([[free], freq]), np.concatenate([[math.hypot(x_free, y_free)], amp]),
                      np.concatenate([[math.atan2(x_free, y_free) - free * t_epoch], phase])))
    (gf, ga, gp), (sf, sa, sp) = terms
    e_hi = float(np.sum(np.abs(ga)))
    _refuse_crossing(body, orbit.a_au, 0.0, e_hi, planets_a_au, planet_e_max, ecc_p.names,
                     "at its largest secular eccentricity")
    source = (f"Laplace–Lagrange secular theory, first order (Murray & Dermott 1999 §7.7), of {body} in the "
              f"planets' field ({', '.join(ecc_p.names)}), free elements fixed by its osculating elements of JD "
              f"{orbit.epoch_jd_tdb:.1f} TDB")
    return SecularOrbit(body, float(orbit.a_au), gf, ga, gp, sf, sa, sp, _horizon_years(sf, sa, epoch_years), source,
                        epoch_years)
