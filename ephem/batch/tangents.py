"""Forward-mode derivatives of the population core's values (:mod:`ephem.batch.population`) for its σ columns.

The core's values of a row (the mean obliquity ε̄, H_d, K and ψ̇) depend on an input through a few leaves: H_d,
the mean motion n, the spin rate ω, the catalogue pole's obliquity ε and equinox-to-pericentre angle θ
(:func:`ephem.orbit.geometry.spin_angles`) and the mean anomaly M(t0) at the pole's epoch. The tangent of each leaf
is written down here (exact formulas, below), then carried through K = 3 n² H_d / ω (Petit et al. 2014,
eq. 10), c = K/(2n), the mean pole's fixed-point passes (:func:`ephem.forced.kinoshita.mean_pole`:
ε̄ ← ε - Δε(ε̄, θ̄), θ̄ ← θ - Δψ(ε̄, θ̄), :data:`~ephem.forced.kinoshita.MEAN_POLE_PASSES` of them, the nutation
at t0 from its θ-free sums, :func:`nutation_sums`) and ψ̇ = (K/2) cos ε̄ (1 - e²)^(-3/2) (eq. 25). The Hansen
coefficients are held: the eccentricity, which moves them, is the core's to difference. Exact derivatives of
the same arithmetic as the core's: no step, so no truncation error; the core compares them with central
differences in its tests (tests/batch/test_population_sigmas.py). With them, two helpers of the core's
arithmetic on (rows, harmonics) arrays: :func:`rowdot`, :func:`hypot`.

Units: angles in radians inside, inputs per their column's unit (degrees, AU, hours, km); rates in rad/day.
"""
from __future__ import annotations

import math

import numpy as np

from ..bodies.catalogue import spin_rate_rad_per_day
from ..forced.kinoshita import MEAN_POLE_PASSES, scaling_factor
from ..orbit.geometry import icrf_to_ecliptic_matrix, spin_angles, unit_vector
from ..orbit.kepler import mean_motion_rad_per_day, orbit_basis

#: the inputs that give H_d, in the core's order of preference (the first form a row gives is the one it takes)
INERTIA_INPUTS = ("dynamical_ellipticity", "moment_a", "moment_b", "moment_c", "axis_a_km", "axis_b_km", "axis_c_km")
#: the inputs that move M(t0) = M + n (t0 - epoch): their derivatives need the sums' derivatives in M
MEAN_ANOMALY_INPUTS = ("a_au", "mean_anomaly_deg")


def rowdot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Σ_k a[:, k] b[:, k] for each row (no (rows, k) temporary)."""
    return np.einsum("ij,ij->i", a, b)


def hypot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """np.hypot to an ulp, at a quarter of its cost: (x² + y²)^½, but np.hypot itself where x² + y² would lose
    digits (below 1e-290, subnormal or zero: an H_d of 1e-300 makes such coefficients) or overflow."""
    sq = x * x + y * y
    out = np.sqrt(sq)
    edge = ~((sq >= 1e-290) & (sq < np.inf))
    if edge.any():
        out[edge] = np.hypot(x[edge], y[edge])
    return out


def nutation_sums(c, eps, theta, A, B, C):
    """(Δψ, Δε) at the pole's epoch, radians, from the θ-free sums of the nutation (Petit et al. 2014, eqs. 20 and
    22 regrouped as :class:`ephem.forced.kinoshita.NutationComponents`): with c = K/(2n), C' = cos 2θ, S' = sin 2θ,
    Δψ = c cos ε (A - C' B - S' C) and Δε = -c sin ε (S' B - C' C), where A = Σ C0_k sin kM / k,
    B = Σ C2_k sin kM / k and C = Σ S2_k cos kM / k at M = M(t0)."""
    cp, sp = np.cos(2.0 * theta), np.sin(2.0 * theta)
    return c * np.cos(eps) * (A - cp * B - sp * C), -c * np.sin(eps) * (sp * B - cp * C)


def geometry(x: dict):
    """(ε, θ, the pole s, the orbit's P, Q, W as rows of (..., 3, 3)) of the rows ``x`` (the core's columns),
    ecliptic J2000 (:func:`ephem.orbit.geometry.spin_angles`, :func:`ephem.orbit.kepler.orbit_basis`)."""
    s = unit_vector(np.radians(x["pole_ra_deg"]), np.radians(x["pole_dec_deg"])) @ icrf_to_ecliptic_matrix().T
    angles = np.radians(x["i_deg"]), np.radians(x["node_deg"]), np.radians(x["peri_deg"])
    eps, theta, _, _ = spin_angles(s, *angles)
    return eps, theta, s, orbit_basis(*angles)


def forward(x: dict, sums: np.ndarray, dsums: np.ndarray, key: str) -> tuple[np.ndarray, ...]:
    """The derivatives in ``key`` (per the input's unit) of the rows ``x`` (the core's columns, with ``_hd``) of
    (ε̄ in degrees, H_d, K in rad/day, ψ̇ in rad/day). ``sums``: (rows, 3) the sums A, B, C of :func:`nutation_sums`
    at M(t0); ``dsums``: their derivatives in M (read only for :data:`MEAN_ANOMALY_INPUTS`). The values are
    recomputed as the core computes them (the same functions on the same columns)."""
    zero = np.zeros(x["a_au"].size)
    dhd = dn = domega = deps0 = dtheta0 = dm = zero
    n, omega, hd = mean_motion_rad_per_day(x["a_au"]), spin_rate_rad_per_day(x["rotation_period_hours"]), x["_hd"]
    K = scaling_factor(n, omega, hd)
    c = 0.5 * K / n
    eps0, theta0, s, basis = geometry(x)
    if key == "a_au":                                       # n ∝ a^(-3/2); M(t0) = M + n (t0 - epoch)
        dn = -1.5 * n / x["a_au"]
        dm = dn * (x["pole_epoch_jd_tdb"] - x["epoch_jd_tdb"])
    elif key == "mean_anomaly_deg":
        dm = zero + math.pi / 180.0
    elif key == "rotation_period_hours":                    # ω = 2π / P
        domega = -omega / x["rotation_period_hours"]
    elif key in INERTIA_INPUTS:
        dhd = hd_tangent(x, key)
    else:
        deps0, dtheta0 = pole_tangent(x, s, basis, key)
    dK = (6.0 * n * hd * dn + 3.0 * n * n * dhd) / omega - K * domega / omega
    dc = dK / (2.0 * n) - c * dn / n
    A, B, C = sums.T
    dA, dB, dC = dsums.T * dm if key in MEAN_ANOMALY_INPUTS else (zero, zero, zero)
    eb, tb, deb, dtb = eps0, theta0, deps0, dtheta0
    for _ in range(MEAN_POLE_PASSES):        # kinoshita.mean_pole from ε̄ = ε, θ̄ = θ, with the tangents
        cp, sp, ce, se = np.cos(2.0 * tb), np.sin(2.0 * tb), np.cos(eb), np.sin(eb)
        G, H = A - cp * B - sp * C, sp * B - cp * C          # Δψ = c cos ε̄ G, Δε = -c sin ε̄ H
        dG = 2.0 * H * dtb + dA - cp * dB - sp * dC          # ∂G/∂θ̄ = 2H, ∂H/∂θ̄ = 2 (C' B + S' C)
        dH = 2.0 * (cp * B + sp * C) * dtb + sp * dB - cp * dC
        dpsi = dc * ce * G - c * se * G * deb + c * ce * dG
        deps = -dc * se * H - c * ce * H * deb - c * se * dH
        eb, tb, deb, dtb = eps0 + c * se * H, theta0 - c * ce * G, deps0 - deps, dtheta0 - dpsi
    rate = 0.5 * (1.0 - x["e"] ** 2) ** -1.5 * (dK * np.cos(eb) - K * np.sin(eb) * deb)
    return np.degrees(deb), dhd, dK, rate


def hd_tangent(x: dict, key: str) -> np.ndarray:
    """∂H_d/∂``key`` where the row's inertia form (the first it gives, as the core takes it) has ``key``, else 0:
    H_d = (C - (A+B)/2)/C (Petit et al. 2014, eq. 11); of the ellipsoid's semi-axes (eq. 30),
    H_d = 1/2 - c²/(a² + b²)."""
    given = np.isfinite(x["dynamical_ellipticity"])
    A, B, C, a, b, c = (x[k] for k in INERTIA_INPUTS[1:])
    moments = ~given & np.isfinite(A) & np.isfinite(B) & np.isfinite(C)
    axes = ~given & ~moments & np.isfinite(a) & np.isfinite(b) & np.isfinite(c)
    s = a * a + b * b
    form, value = {"dynamical_ellipticity": (given, 1.0), "moment_a": (moments, -0.5 / C),
                   "moment_b": (moments, -0.5 / C), "moment_c": (moments, 0.5 * (A + B) / (C * C)),
                   "axis_a_km": (axes, 2.0 * a * c * c / (s * s)), "axis_b_km": (axes, 2.0 * b * c * c / (s * s)),
                   "axis_c_km": (axes, -2.0 * c / s)}[key]
    return np.where(form, value, 0.0)


def pole_tangent(x: dict, s: np.ndarray, basis: np.ndarray, key: str) -> tuple[np.ndarray, np.ndarray]:
    """(∂ε, ∂θ) in radians per degree of the pole's RA or Dec or the orbit's i, node or peri. In the orbit's frame
    (P, Q, W) the pole s is (s_x, s_y, s_z): ε = atan2(ρ, s_z) with ρ = (s_x² + s_y²)^½, and θ = atan2(s_x, s_y)
    (spin_angles' equinox γ = s × W / ρ = (s_y P - s_x Q)/ρ, θ the angle from γ to P about W). Turning the frame
    by dφ about a unit vector u moves the pole by -u × s dφ in it (u: the ecliptic pole for the node, the line of
    nodes for i, W for peri)."""
    ra, dec, node = np.radians(x["pole_ra_deg"]), np.radians(x["pole_dec_deg"]), np.radians(x["node_deg"])
    zero = np.zeros_like(ra)
    if key in ("pole_ra_deg", "pole_dec_deg"):              # ∂/∂α, ∂/∂δ of (cos δ cos α, cos δ sin α, sin δ)
        ds = np.stack([-np.cos(dec) * np.sin(ra), np.cos(dec) * np.cos(ra), zero] if key == "pole_ra_deg" else
                      [-np.sin(dec) * np.cos(ra), -np.sin(dec) * np.sin(ra), np.cos(dec)], axis=-1)
        ds = ds @ icrf_to_ecliptic_matrix().T
    else:
        u = {"node_deg": np.stack([zero, zero, zero + 1.0], axis=-1),
             "i_deg": np.stack([np.cos(node), np.sin(node), zero], axis=-1), "peri_deg": basis[:, 2]}[key]
        ds = -np.cross(u, s)
    (sx, dx), (sy, dy), (sz, dz) = ((np.sum(s * basis[:, j], axis=-1), np.sum(ds * basis[:, j], axis=-1))
                                    for j in range(3))
    rho2 = sx * sx + sy * sy
    rho = np.sqrt(rho2)
    deg = math.pi / 180.0
    deps = (sz * (sx * dx + sy * dy) / rho - rho * dz) / (rho2 + sz * sz)
    return deg * deps, deg * (sy * dx - sx * dy) / rho2
