"""The Moon's forced physical librations about its Cassini state: the pole and the prime meridian.

The principal axes of the Moon (a toward the Earth, c the pole; A < B < C) turn uniformly on average: c precesses
with the orbit's node about the ecliptic pole at the inclination I (Cassini's laws, :mod:`ephem.forced.cassini`), a
follows the mean Earth. The orbit's periodic departures from a uniformly precessing circle (the equation of
centre, evection, variation, the annual equation, the latitude's periodic terms, the Sun) drive the axes about
that state: the physical librations. This module derives them from the rigid body's equations, the Moon's orbit
series of :mod:`ephem.earth.lunisolar` (Meeus 1998 ch. 47, a truncation of ELP-2000/82) and the Sun, without fitting.
Radians and days throughout; JD TDB.

This module holds the fixed point (the equations' residual, the iteration) and the public entry; beside it are the
torque and the coefficients (:mod:`ephem.moon.libration_forcing`, eqs. (4)–(6)), the linear solve chain by chain
(:mod:`ephem.moon.libration_chains`), the frame (R) and the angles (E) (:mod:`ephem.moon.libration_angles`), the
series returned (:mod:`ephem.moon.libration_series`) and the free modes (:mod:`ephem.moon.libration_modes`).

Frames and angles (all signs stated)
------------------------------------
E: the mean ecliptic and equinox of date (x to the equinox, z the ecliptic pole K). Ω, F = L − Ω, l, l', D: the
Delaunay arguments of IERS Conventions (2010) eq. 5.43 (Meeus's M' = l, M = l'); L = F + Ω the Moon's mean
longitude. The reference frame, turning uniformly,

    R(t) = Rz(Ω + π) Rx(I) Rz(F)                                                                        (R)

has z the Cassini pole (colatitude I, ecliptic longitude Ω + 90°: the ecliptic pole between it and the orbit
pole, Cassini state 2) and x toward the mean Earth (along the equator, F from the equator's ascending node at
Ω + π). Its angular velocity in space is ω_R = (Ω̇ − p_A) K + Ḟ c, in R's axes

    w = (ν sin F, ν cos F, w3),   ν = (Ω̇ − p_A) sin I,   w3 = Ḟ + (Ω̇ − p_A) cos I,

p_A the general precession (:data:`ephem.moon.libration_frames.GENERAL_PRECESSION_RATE`: the frame of date turns at −p_A about K). The
principal axes are B = R exp([θ×]): θ (rad, in R's axes) is the unknown, θ1 a roll about the mean Earth
direction, θ2 a pitch about the along-track axis, θ3 a yaw about the pole. The published variables (Eckhardt
1981, Moon and Planets 25, 3; Meeus 1998 ch. 53) are the principal axes' 3-1-3 Euler angles from E,

    B = Rz(φ) Rx(ϑ) Rz(ψ),   φ = Ω + π + σ / sin I,   ϑ = I + ρ,   ψ = F + τ − σ / sin I,              (E)

so ρ is the equator's inclination less I (positive: the pole away from K), σ = sin I × the node's advance
(the pole's displacement across its meridian, toward increasing longitude), τ the libration in longitude (the
long axis ahead of the mean Earth, measured along the node and then the equator). The pole is at colatitude
I + ρ, longitude Ω + 90° + σ / sin I: Meeus's eq. (53.2) and his position-angle formula use exactly this. The
Euler angles are exact functions of θ (signed, from atan2); to first order ρ + iσ = (θ1 + iθ2) e^{iF} and
τ = θ3 + (1 − cos I) σ / sin I. That last term is first order (I/2 × σ, 1.4″ for σ's 100″ l-term): a library that
takes τ = θ3 disagrees with Eckhardt's τ at the 1″ level; the second-order terms of (E) make Meeus's σ term
−0.00025° sin 2l exactly (σ_E = σ − ρσ / sin I).

Equations
---------
Euler's equations in the principal axes (the inertia Λ = diag(A, B, C), normalised C = 1),

    Λ ω̇ + ω × Λ ω = Σ_j 3 (GM_j / r_j³) u_j × Λ u_j,                                                   (1)
    ω = Q^T w + J_r(θ) θ̇,   Q = exp([θ×]),   u_j = Q^T R^T r̂_j,                                          (2)

r̂_j the Earth and the Sun seen from the Moon (the Sun: its geocentric position less the Moon's), GM_j DE421's, J_r
the right Jacobian of the rotation (J_r θ̇ = θ̇ + O(θ θ̇)). Linearised in θ (u the unit vector in R):

    Λ θ̈ + M1 θ̇ + M0 θ = f,                                                                             (3)
    f  = Σ 3K u × Λ u − Λ ẇ − w × Λ w,                                                                  (4)
    M1 = Λ [w×] − [(Λw)×] + [w×] Λ,                                                                      (5)
    M0 = Λ [ẇ×] − [(Λw)×][w×] + [w×] Λ [w×] + Σ 3K ([(Λu)×][u×] − [u×] Λ [u×]),                          (6)

K = GM/r³. f is the torque the reference attitude leaves unbalanced: what drives the librations. On a circular
orbit in the equator (u = x, w = (0, 0, n)) (5) and (6) reduce to the classical gravity-gradient roll-yaw-pitch
equations of a synchronous satellite: M1 = n(A + B − C)(e_y e_x^T − e_x e_y^T), M0 = diag(n²(C − B),
(n² + 3g)(C − A), 3g(B − A)), i.e. A θ̈1 − n(A + B − C) θ̇2 + n²(C − B) θ1 = f1, B θ̈2 + n(A + B − C) θ̇1 +
(n² + 3g)(C − A) θ2 = f2, C θ̈3 + 3g(B − A) θ3 = f3, with α = (C − B)/A, β = (C − A)/B, γ = (B − A)/C: the
longitude mode ω² = 3gγ and the roll-pitch pair of :func:`ephem.forced.cassini.free_librations`. Here u and w are the
real ones: u carries the orbit's inclination to the equator (i + I, the latitude at F), its eccentricity, the
Sun's perturbations; w the node's regression (ν: the term that holds the Cassini state against the torque).

Solution
--------
Every coefficient is a function on the torus of (l, l', F, D, Ω) (the orbit series are Delaunay series; R turns
with F and Ω): f, M0 are sampled on a regular grid of it (:data:`DEFAULT_GRID`) and Fourier analysed by FFT (no
least squares, no leakage; the grid's convergence is tested), M1 depends on F alone. θ = Σ_k c_k e^{ik·φ}.

* "constant" model: M0 replaced by its average over (l, l', D, Ω), a function of F alone. The harmonic balance
  then splits into independent chains k = (b, m) over the F multiplier m (b = the other four): one small linear
  solve per chain, [−ν_m² Λ + i ν_m M1 + M0]_{m,m'} c_{m'} = f_m with ν_m = k·φ̇. This is the response of the
  linear system at each forcing frequency, resonances included: nothing is fitted; the free modes
  (:func:`ephem.moon.libration_modes.free_modes`, the same operator's Floquet exponents) sit where the chain
  matrix is singular.
* "linear": (3) with all its coefficients: the fixed point θ ← θ − L_F⁻¹ r(θ), r = Λ θ̈ + M1 θ̇ + M0 θ − f on the
  grid (time derivatives spectral), L_F the chain operator above. Contracts by ~3e-3 a step.
* "full" (default): r the residual of (1)–(2) themselves, all orders in θ. The second-order terms matter where
  they fall near a free mode: θ1, θ2 carry the l and l − 2F pole terms (100″ and 25″) at the same R-frequency
  F − l, one prograde and one retrograde; the elliptical motion makes ω3 = ... − n(θ1² + θ2²)/2 vary at 2(F − l),
  1095 d, beside the free longitude mode (1056 d): 4.6″ of τ's 2(l − F) term (with the catalogue moments).

At each step I takes up the constant of the first-order ρ (I is the mean inclination, solved with the librations,
not assumed); an ``offset`` (a constant θ the degree-2 torque does not give, below) is held by a constant torque
corrected at each step. The series (:class:`PhysicalLibrations`) are the FFT of the exact Euler angles (E) of the
converged θ on the grid.

Checks (tests/moon/test_physical_librations.py)
------------------------------------------
(4)–(6) against central differences of (1)–(2) (2e-6 relative); the "linear" series against a numerical
integration of (3) itself (2 years, < 0.001″); the "full" series against a numerical integration of the rigid Moon
(1)–(2), in the frame of date with the same Earth and Sun, started on the series: 0.0005″ over 4 years (the
"linear" series is then 4.6″ off in τ and 0.07″ in the pole, the "constant" one 10.6″ and 0.27″); against
:mod:`ephem.moon.rigid_integration`'s rigid Moon in the J2000 frame, which differs by the ecliptic's own motion only (the
series' pole follows the ecliptic of date; the integrated one lags behind it: 1.9″ after 4 years, the ecliptic
pole's displacement, bounded by v/ω_lat ≈ 2″ in steady state). Against Eckhardt (1981) as printed by Meeus (1998,
ch. 53), with the moments that give the observed I and free longitude period (:data:`EFFECTIVE_BETA_GAMMA`) and
DE421's constant offset: every even-F term of ρ, σ within 0.13″, of τ within 0.03″ but 2(l − F) (0.51″, the most
γ-sensitive term: the resonance gain is ~17); the odd-F terms the offset reaches within 0.02″. The σ term
−0.00025° sin 2l is the Euler angles' second order; Eckhardt's τ l term (−0.00467°) needs the (1 − cos I) σ / sin I
term of τ (without it: −0.00429°).

What the series leave out
-------------------------
* The degree-3 (and higher) gravity field. Its main effect is a constant torque in the body, which tilts the
  principal axes from the mean frame by θ ≈ (0.30″, 78.56″, 67.92″) (DE421's PA→ME rotation,
  :data:`DE421_PA_OFFSET`): without it the pole lacks Eckhardt's ρ = −0.02245° sin F, σ = +0.02244° cos F (81″,
  a monthly circle in space). With ``offset=DE421_PA_OFFSET`` the full model reproduces those (to 2.2″: DE421's
  78.56″ against Eckhardt's 80.8″), the asymmetry of the 2F terms (ρ −0.00293°, σ −0.00279°) and the odd-F terms
  sin(l + F), cos(l + F), cos(l − 3F) to 0.02″; the degree-3 terms that vary with the distance and latitude
  (arguments l ± F: ρ −0.0002° cos(l − F), σ 0.0002° cos(l − F), 0.00019° sin(l − F), τ −0.00183° cos(l − F),
  −0.00039° sin(l − F)) stay out: up to 1.15″ in the pole, 8.4″ in τ.
* The degree-3 field's share of the mean inclination: with LLR's β = (C − A)/B ≈ 631.0e-6 the rigid degree-2 I is
  1.5457°, 12″ above the observed 1.5424°; the moments :data:`EFFECTIVE_MOMENTS` give the observed I (and the
  observed free longitude period).
* A fluid core, elasticity and tidal dissipation: Eckhardt's τ has 0.00014° cos 2(l − F) (0.5″, a phase lag near
  the free mode); none here.
* The planetary terms of the orbit and its terms below Meeus's cut (1e-6° printing, ~1″ smallest longitude term):
  τ's 0.00396° sin K1 and 0.00023° sin K2 (Venus, 270 yr and 1800 yr), 0.00011° sin 2(l − l' − D).
* The ecliptic's own motion (π_A, 47″/cy): the series put the pole on the ecliptic of date; the Moon lags behind
  the moving plane, a slowly varying offset of the mean pole, not a periodic term: 7.3″ in steady state
  (:mod:`ephem.moon.orientation`, which the Moon's model adds; DE421: 7.56″), where a start on the series grows by
  the ecliptic pole's displacement (1.9″ after 4 years, below).
* The secular change of the Delaunay rates (the series' frequencies are J2000's): Ω̇'s 2 × 7.47″/cy² moves I by
  ~1.3 I ΔΩ̇/Ω̇, 0.0006″ in 4 years.

The pole also carries what Eckhardt's does not: a constant offset of 8.09″ toward ecliptic longitude 90° (terms
in Ω: ρ 0.00235° cos Ω, σ −0.00232° sin Ω), the Cassini state following the Moon's Laplace plane, tilted by the
Earth's flattening (Meeus's latitude term −0.002235° sin L', which the series take from :mod:`ephem.earth.lunisolar`).
Units: radians, rad/day; amplitudes in radians.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..base.constants import ARCSEC
from ..base.errors import InvalidInputError
from ..bodies.catalogue import get_body
from ..orbit.lunar import delaunay_arguments, delaunay_rates
from .libration_angles import euler_angles, remove_rho_constant, rho_constant
from .libration_chains import chain_operator, dc_response, grid_frequencies, scatter, solve_chains
from .libration_forcing import (frame_rates, linearised_equations, perturber_directions, perturber_directions_at,
                                torus_fields)
from .libration_frames import rodrigues
from .libration_series import PhysicalLibrations, canonical_sign, pole_amplitude

#: θ's constant (rad) in DE421: the principal axes (PA) from the mean-Earth/rotation (ME) frame, the rotation of
#: NAIF's moon_080317.tf (TKFRAME_31007: 67.92″, 78.56″, 0.30″ about z, y, x, from Williams et al. 2008, JPL IOM
#: 335-JW,DB,WF-20080314-001), as (x, y, z); mostly the degree-3 field's constant torque (module docstring). Sign:
#: v_ME = exp([θ×]) v_PA, checked on the kernel's own example (tests/moon/test_physical_librations.py).
DE421_PA_OFFSET = (0.30 * ARCSEC, 78.56 * ARCSEC, 67.92 * ARCSEC)
#: β = (C − A)/B and γ = (B − A)/C of a rigid degree-2 Moon that has the observed mean inclination, I = 1.54242°
#: (the IAU value, Meeus 1998 p. 372), and free libration in longitude, 1056.16 d (Yang et al. 2017, RAA 17, 127,
#: from DE430), in this module's full model with the Sun and :data:`DE421_PA_OFFSET` (solved by Newton's method on
#: (β, γ); tests/moon/test_physical_librations.py re-checks both). LLR's β (631.0e-6) gives I 12″ too large here (the
#: degree-3 field's share of the precession torque, left out); the catalogue's Lara (2014) ratios give γ =
#: 233.0e-6 and a free period of 1046 d.
EFFECTIVE_BETA_GAMMA = (629.9834e-6, 228.5628e-6)
#: The FFT grid on the torus (l, l', F, D, Ω) of the forcing and of the operator's coefficients: against grids
#: finer on each axis the series move by < 1e-5″ (tests/moon/test_physical_librations.py, test_grid_converges); Ω needs
#: 6 points (|k_Ω| = 2 from the products of the Laplace plane's Ω terms: 4 points were 0.007″ off).
DEFAULT_GRID = (16, 8, 16, 16, 6)
#: Forcing harmonics kept: those above this fraction of the largest (the F term that holds the Cassini state);
#: 1e-11 or 1e-13 instead moves the series by < 1e-5″ over 8 years (measured).
FORCING_FLOOR = 1e-9
#: Terms kept in a series (rad): far below any cut a caller would take (1e-6 arcsec).
TERM_FLOOR = 1e-6 * ARCSEC
#: The Moon's Cassini inclination the iteration starts from (rad); it converges to its own from any start within
#: a few tenths of a degree (one step moves by the constant ρ it finds).
_I_START = math.radians(1.54)


def moments_from_beta_gamma(beta: float, gamma: float) -> tuple[float, float, float]:
    """(A, B, C) with C = 1 from β = (C − A)/B and γ = (B − A)/C."""
    b = (1.0 + gamma) / (1.0 + beta)
    return (b - gamma, b, 1.0)


#: (A, B, C) of :data:`EFFECTIVE_BETA_GAMMA`, C = 1.
EFFECTIVE_MOMENTS = moments_from_beta_gamma(*EFFECTIVE_BETA_GAMMA)


# ----------------------------------------------------------------------------- the equations at epochs; chains on the torus

def linearised_terms(jd_tdb, equator_inclination: float, moments, sun: bool = True):
    """f, M0, M1 of the linearised equations Λ θ̈ + M1 θ̇ + M0 θ = f (module docstring) at JD TDB epochs
    (shape (N,)): (3, N), (3, 3, N), (3, 3, N); moments normalised to C = 1. For checks (a numerical integration
    of the linear system, a numerical Jacobian of the full one)."""
    args = delaunay_arguments(np.atleast_1d(np.asarray(jd_tdb, dtype=float)))
    directions = perturber_directions_at(tuple(args[:, i] for i in range(5)), sun)
    return linearised_equations(directions, args[:, 2], float(equator_inclination), moments_over_c(moments))


def _pole_longitude_terms(bases: np.ndarray, ms: np.ndarray, theta: np.ndarray):
    """ρ, σ, τ from θ chain by chain: ρ + iσ = (θ1 + iθ2) e^{iF} (module docstring), so each ρ, σ harmonic (b, m)
    takes θ's (b, m ∓ 1). Returns real terms: multipliers (n, 5), cos and sin coefficients (n, 3) of (ρ, σ, τ), and
    the constant (3,)."""
    nb, nm, _ = theta.shape
    pad = np.zeros((nb, nm + 4, 3), dtype=complex)
    pad[:, 2:-2] = theta
    lo, mid, hi = pad[:, :-2], pad[:, 1:-1], pad[:, 2:]      # θ at m' − 1, m', m' + 1 for m' = ms[0]−1 .. ms[-1]+1
    rho = 0.5 * (lo[..., 0] + hi[..., 0]) - (lo[..., 1] - hi[..., 1]) / 2j
    sig = (lo[..., 0] - hi[..., 0]) / 2j + 0.5 * (lo[..., 1] + hi[..., 1])
    coef = np.stack([rho, sig, mid[..., 2]], axis=-1)          # (nb, nm + 2, 3)
    mm = np.arange(ms[0] - 1, ms[-1] + 2)
    k = np.empty((nb, mm.size, 5), dtype=int)
    k[:, :, [0, 1, 3, 4]] = bases[:, None, :]
    k[:, :, 2] = mm[None, :]
    k, coef = k.reshape(-1, 5), coef.reshape(-1, 3)
    zero_base = ~np.any(k[:, [0, 1, 3, 4]], axis=1)
    constant = coef[zero_base & (k[:, 2] == 0)].real.sum(axis=0)
    keep = ~zero_base | (k[:, 2] > 0)
    k, coef = k[keep], coef[keep]
    sign = canonical_sign(k)
    cos_, sin_ = 2.0 * coef.real, -2.0 * coef.imag * sign[:, None]
    return k * sign[:, None], cos_, sin_, constant


# ----------------------------------------------------------------------------- solving

def _zero_chain_rho(grid: tuple, sun: bool, I: float, moments: np.ndarray) -> tuple[float, float]:
    """The constant ρ and σ the b = 0 chain (the F harmonics of the torus-averaged equations) gives at I."""
    f, m0, m1 = torus_fields(grid, sun, I, moments)
    nf = grid[2]
    f_f = f.mean(axis=(1, 2, 4, 5))                         # (3, NF): averaged over l, l', D, Ω
    m0_f = m0.mean(axis=(2, 3, 5, 6))
    ms, T0, T1 = chain_operator(m0_f, m1, moments, nf)
    spec = np.fft.fft(f_f, axis=1) / nf                     # (3, NF)
    nu = np.repeat(ms * delaunay_rates(0.0)[2], 3)
    mat = T0 + 1j * T1 * nu[None, :]
    mat[np.arange(nu.size), np.arange(nu.size)] -= nu**2 * np.tile(moments, ms.size)
    rhs = spec[:, ms % nf].T.reshape(-1)
    theta = np.linalg.solve(mat, rhs).reshape(ms.size, 3)
    _, cos_, sin_, const = _pole_longitude_terms(np.zeros((1, 4), dtype=int), ms, theta[None])
    return float(const[0]), float(const[1])


def moments_over_c(moments) -> np.ndarray:
    m = np.asarray(moments, dtype=float).reshape(-1)
    if m.size != 3 or not np.all(np.isfinite(m)) or not 0.0 < m[0] <= m[1] < m[2]:
        raise InvalidInputError("moments", f"principal moments A <= B < C, all positive, got {moments!r}")
    return m / m[2]


def _series_terms(values: np.ndarray, grid: tuple, floor: float):
    """Real terms of functions (3, grid) on the torus: multipliers (n, 5) (canonical sign), cos and sin
    coefficients (n, 3) of the rows whose largest coefficient exceeds ``floor``, and the constants (3,)."""
    n = float(np.prod(grid))
    spec = np.fft.fftn(values, axes=(1, 2, 3, 4, 5)) / n
    constant = spec[(slice(None),) + (0,) * 5].real.copy()
    gsize = np.array(grid)
    idx = np.argwhere(np.abs(spec).max(axis=0) > 0.5 * floor)
    k = np.where(idx > gsize // 2, idx - gsize, idx)
    ok = np.all(2 * np.abs(k) < gsize, axis=1) & np.any(k, axis=1) & (canonical_sign(k) == 1)
    idx, k = idx[ok], k[ok]
    c = spec[(slice(None),) + tuple(idx.T)].T                     # (n, 3)
    return k, 2.0 * c.real, -2.0 * c.imag, constant


def _residual(spec: np.ndarray, nu: np.ndarray, grid: tuple, sun: bool, I: float, mom: np.ndarray,
              model: str, torque: np.ndarray) -> np.ndarray:
    """The equations' residual on the grid (3, grid) at θ of spectrum ``spec``: "full", the rigid body's
    Λ ω̇ + ω × Λω − T in the principal axes (eqs. (1)–(2)), ω = Q^T w + J_r(θ) θ̇, T from u = Q^T u_R; or
    "linear", Λ θ̈ + M1 θ̇ + M0 θ − f (eq. (3)). Time derivatives are spectral (ν_k on each harmonic). ``torque``
    (3,): a constant torque in the principal axes (the offset's, :func:`moon_physical_librations`), subtracted."""
    axes = (1, 2, 3, 4, 5)
    n = float(np.prod(grid))
    th = np.fft.ifftn(spec, axes=axes).real * n
    thd = np.fft.ifftn(1j * nu * spec, axes=axes).real * n
    mv = mom.reshape((3,) + (1,) * 5)
    if model == "linear":
        f, m0, m1 = torus_fields(grid, sun, I, mom)
        thdd = np.fft.ifftn(-nu * nu * spec, axes=axes).real * n
        m1 = m1.reshape((3, 3, 1, 1, grid[2], 1, 1))
        return (mv * thdd + np.einsum("ij...,j...->i...", m1, thd) + np.einsum("ij...,j...->i...", m0, th) - f
                - torque.reshape((3,) + (1,) * 5))
    q, jr = rodrigues(th)
    nf = grid[2]
    F = (2.0 * math.pi * np.arange(nf) / nf).reshape(1, 1, nf, 1, 1)
    nu_r, w3, _ = frame_rates(I)
    w = np.stack(np.broadcast_arrays(nu_r * np.sin(F), nu_r * np.cos(F), np.full(F.shape, w3)))
    omega = np.einsum("ji...,j...->i...", q, w) + np.einsum("ij...,j...->i...", jr, thd)
    omega_dot = np.fft.ifftn(1j * nu * np.fft.fftn(omega, axes=axes), axes=axes).real
    res = mv * omega_dot + np.cross(omega, mv * omega, axis=0)
    ci, si = math.cos(I), math.sin(I)
    cF, sF = np.cos(F), np.sin(F)
    for gm_r3, v in perturber_directions(grid, sun):
        y, z = ci * v[1] + si * v[2], -si * v[1] + ci * v[2]
        u_r = np.stack(np.broadcast_arrays(cF * v[0] + sF * y, -sF * v[0] + cF * y, z))
        u = np.einsum("ji...,j...->i...", q, u_r)
        res -= 3.0 * gm_r3 * np.cross(u, mv * u, axis=0)
    return res - torque.reshape((3,) + (1,) * 5)


#: The models :func:`moon_physical_librations` solves (module docstring, "Solution").
MODELS = ("constant", "linear", "full")
#: The fixed-point iteration stops when no harmonic of θ (and neither I) moves by more than this (rad): 1e-10 rad =
#: 0.02 mas, above what the forcing floor leaves unsolved at the slowest mode (~1e-14 rad/day² × 3e4 day² ~ 3e-10
#: at DC is the worst; typical harmonics far less).
CONVERGENCE = 1e-10
MAX_STEPS = 30


def _solve(grid: tuple, sun: bool, mom: np.ndarray, model: str, inclination: float | None, offset):
    """θ's spectrum (3, grid), I and the number of fixed-point steps: θ = L_F⁻¹ f, then (models "linear" and
    "full") θ ← θ − L_F⁻¹ r(θ) with r the model's residual, I absorbing θ's constant ρ at each step (unless given)
    and, with an ``offset``, the constant torque being corrected until θ's constant is the offset."""
    if inclination is None:
        I = _I_START
        for _ in range(20):
            rho0, _sigma0 = _zero_chain_rho(grid, sun, I, mom)
            I += rho0
            if abs(rho0) < CONVERGENCE:
                break
    else:
        I = float(inclination)
    nf = grid[2]
    n = float(np.prod(grid))
    f, m0, m1 = torus_fields(grid, sun, I, mom)
    ms, T0, T1 = chain_operator(m0.mean(axis=(2, 3, 5, 6)), m1, mom, nf)
    fspec = np.fft.fftn(f, axes=(1, 2, 3, 4, 5)) / n
    floor = FORCING_FLOOR * float(np.abs(fspec).max())
    torque = np.zeros(3)
    if offset is not None:
        gain = dc_response(ms, T0, T1, mom)
        torque = np.linalg.solve(gain, np.asarray(offset, dtype=float))
        fspec[(slice(None),) + (0,) * 5] += torque
    bases, theta = solve_chains(fspec, grid, ms, T0, T1, mom, FORCING_FLOOR)
    spec = scatter(bases, theta, ms, grid)
    if model == "constant":
        return spec, I, 0
    nu = grid_frequencies(grid)
    for step in range(1, MAX_STEPS + 1):
        r = _residual(spec, nu, grid, sun, I, mom, model, torque)
        rspec = np.fft.fftn(r, axes=(1, 2, 3, 4, 5)) / n
        top = float(np.abs(rspec).max())
        if top == 0.0:
            return spec, I, step
        bases, theta = solve_chains(rspec, grid, ms, T0, T1, mom, floor / top)
        delta = scatter(bases, theta, ms, grid)
        spec -= delta
        moved = float(np.abs(delta).max())
        if inclination is None:
            rho0 = rho_constant(spec)
            I += rho0
            remove_rho_constant(spec, rho0)
            moved = max(moved, abs(rho0))
        if offset is not None:
            miss = np.asarray(offset, dtype=float) - spec[(slice(None),) + (0,) * 5].real
            torque = torque + np.linalg.solve(gain, miss)
            moved = max(moved, float(np.abs(miss).max()))
        if moved < CONVERGENCE:
            return spec, I, step
    raise RuntimeError(f"the librations did not converge in {MAX_STEPS} steps (last move {moved:.3g} rad)")


@lru_cache(maxsize=8)
def _build(moments: tuple, sun: bool, grid: tuple, model: str, inclination: float | None,
           offset: tuple | None) -> PhysicalLibrations:
    mom = moments_over_c(moments)
    spec, I, steps = _solve(grid, sun, mom, model, inclination, offset)
    theta_grid = np.fft.ifftn(spec, axes=(1, 2, 3, 4, 5)).real * float(np.prod(grid))
    rotation = _series_terms(theta_grid, grid, TERM_FLOOR)
    k, cos_, sin_, const = _series_terms(euler_angles(theta_grid, I, grid), grid, TERM_FLOOR)
    rho, sigma, tau = (np.stack([cos_[:, j], sin_[:, j]], axis=1) for j in range(3))
    amp = np.maximum(pole_amplitude(rho, sigma), np.hypot(tau[:, 0], tau[:, 1]))
    order = np.argsort(-amp, kind="stable")
    return PhysicalLibrations(k[order], rho[order], sigma[order], tau[order], const, I,
                              tuple(float(x) for x in moments), sun, grid, model, steps, rotation, offset)


def moon_physical_librations(moments=None, *, sun: bool = True, grid: tuple = DEFAULT_GRID, model: str = "full",
                             equator_inclination: float | None = None, offset=None) -> PhysicalLibrations:
    """The Moon's forced physical librations (module docstring), all terms above :data:`TERM_FLOOR`.

    ``moments``: (A, B, C) in any common unit, by default the catalogue's Moon (Lara 2014). ``sun``: the Sun's
    torque on the lunar figure (its effect through the orbit is always in, by the Moon's series). ``model``: one of
    :data:`MODELS`: "constant", the linear equations with their torus-averaged (F-only) coefficients; "linear",
    the linear equations with all the orbit's harmonics in their coefficients; "full", the rigid body's equations
    themselves (all orders in θ). ``equator_inclination``: I (rad) to linearise about; by default the series' own
    (the constant of its first-order ρ driven to zero). ``offset``: a constant rotation θ (rad, 3) of the principal
    axes from the mean frame R, imposed by the constant torque that gives it (the degree-3 field's main effect,
    left out of the torque: :data:`DE421_PA_OFFSET`); None: none. With an offset the series are the principal
    axes' (a lunar PA frame); ``mean_frame=True`` in :meth:`PhysicalLibrations.attitude` and
    :meth:`PhysicalLibrations.pole` gives the mean-Earth/rotation axes (ME, the IAU WGCCRE's), B_ME = B_PA
    exp(−[θ_off×]). These differ from the series without the offset by the offset's couplings with the
    librations (terms in l ± F, l − 3F: 1.3″ in the pole, 1.9″ in the long axis for DE421's offset): a body
    without its degree-3 field is another body."""
    if moments is None:
        moments = get_body("Moon").moments
    grid = tuple(int(g) for g in grid)
    if len(grid) != 5 or min(grid) < 4 or any(g % 2 for g in grid):
        raise InvalidInputError("grid", f"five even sizes of at least 4, got {grid!r}")
    if model not in MODELS:
        raise InvalidInputError("model", f"one of {', '.join(MODELS)}, got {model!r}")
    if offset is not None:
        offset = tuple(float(x) for x in np.asarray(offset, dtype=float).reshape(-1))
        if len(offset) != 3 or not all(math.isfinite(x) and abs(x) < 0.01 for x in offset):
            raise InvalidInputError("offset", f"three small angles (rad, |θ| < 0.01), got {offset!r}")
    return _build(tuple(float(x) for x in np.asarray(moments, dtype=float).reshape(-1)), bool(sun), grid, model,
                  None if equator_inclination is None else float(equator_inclination), offset)
