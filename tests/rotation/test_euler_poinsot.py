"""The exact torque-free motion (ephem.rotation.euler_poinsot) against numerical integration, classical limits,
Sadov's action-angle variables and published periods."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import ellipj, ellipk, ellipkm1

from ephem.rotation import andoyer as an
from ephem.bodies.catalogue import get_body, load_catalogue
from ephem.base.errors import InvalidInputError
from ephem.base.constants import ARCSEC
from ephem.rotation.elliptic_solution import differences, jacobi_reduced
from ephem.rotation.euler_poinsot import FreeRotation
from ephem.rotation.free_periods import free_motion_periods, sadov_action_angle
from ephem.forced.rigid_body import integrate_states
from ephem.forced.rigid_numerics import quaternion_from_matrix, rotation_matrices

R0 = an.euler_matrix(0.3, 1.1, -0.7)
TRIAXIAL = (0.6, 0.8, 1.0)
BINARY = (0.5, 0.75, 1.0)   # (B−A)/A and (C−B)/C exact in binary: a state exactly on the separatrix exists


def integrate(moments, L0, R_init, t, rtol=1e-13):
    """Euler's equations and the attitude quaternion, torque-free (ephem.forced.rigid_body, DOP853): L_b(t), R(t)."""
    I = np.asarray(moments, dtype=float)
    w = np.asarray(L0, dtype=float) / I
    w0 = float(np.linalg.norm(w))
    y0 = np.concatenate([w / w0, quaternion_from_matrix(R_init.T)])   # ephem.forced.rigid_body's q: body -> inertial
    states, _ = integrate_states(tuple(I), w0, y0, 0.0, t, None, rtol=rtol, atol=1e-16)
    return states[:, :3] * w0 * I, np.transpose(rotation_matrices(states[:, 3:]), (0, 2, 1))


def separatrix_state(L1=0.3, L2=0.1, moments=BINARY):
    """A body momentum with D = M² − 2EB exactly 0 in floating point (found by stepping L1 an ulp at a time)."""
    A, B, C = moments
    for _ in range(2000):
        L3 = math.sqrt(L1 * L1 * (B - A) / A * C / (C - B))
        for cand in (L3, np.nextafter(L3, 0.0), np.nextafter(L3, 9.0)):
            if differences((L1, L2, cand), A, B, C)[3] == 0.0:
                return np.array([L1, L2, cand])
        L1 = float(np.nextafter(L1, 1.0))
    raise AssertionError("no exact separatrix state found")


CASES = {
    # name: (moments, L0, expected mode, span in wobble periods or time units)
    "short-axis": (TRIAXIAL, [0.3, 0.2, 1.0], "short-axis", 3.0),
    "short-axis L3<0": (TRIAXIAL, [-0.4, 0.1, -1.0], "short-axis", 3.0),
    "long-axis": (TRIAXIAL, [1.0, 0.2, 0.3], "long-axis", 3.0),
    "long-axis m=0.74": (TRIAXIAL, [0.5, 0.6, 0.5], "long-axis", 3.0),
    "near separatrix, above": (BINARY, [0.3, 0.1, 0.42426407 * 1.001], "short-axis", 2.0),
    "near separatrix, below": (BINARY, [0.3, 0.1, 0.42426407 * 0.999], "long-axis", 2.0),
    "oblate A=B": ((0.9, 0.9, 1.0), [0.3, 0.2, 1.0], "short-axis", 3.0),
    "prolate B=C": ((0.6, 1.0, 1.0), [1.0, 0.2, 0.3], "long-axis", 3.0),
    "Eros": (get_body("Eros").moments, [0.05, -0.1, 1.0], "short-axis", 3.0),
}


@pytest.mark.parametrize("name", CASES)
def test_exact_solution_matches_integration(name):
    moments, L0, mode, periods = CASES[name]
    fr = FreeRotation.from_body_momentum(moments, L0, 0.0, R0)
    assert fr.mode == mode and not fr.stationary
    t = np.linspace(0.0, periods * fr.wobble_period, 240)
    L_num, R_num = integrate(moments, L0, R0, t)
    # DOP853 at rtol 1e-13 over 2-3 wobble periods: ~1e-14 M and 1e-13-1e-12 on the attitude far from the
    # separatrix (ephem.rotation.euler_poinsot's docstring); the near-separatrix cases (1 − m = 2e-3) amplify an initial
    # ε by ~1/(1 − m) (measured <= 1.4e-12 M): 1e-11 M and 1e-10
    assert np.abs(fr.body_momentum(t) - L_num).max() < 1e-11 * fr.M
    assert np.abs(fr.attitude(t) - R_num).max() < 1e-10


def test_exact_separatrix():
    # D = 0 exactly: the sech/tanh closed form (never K(1) = ∞, never NaN), heteroclinic towards ±B
    L0 = separatrix_state()
    fr = FreeRotation.from_body_momentum(BINARY, L0, 0.0, R0)
    assert fr.mode == "separatrix" and fr.wobble_period == math.inf and fr.elliptic_parameter == 1.0
    t = np.linspace(0.0, 12.0 / fr.elliptic_rate, 200)
    L_num, R_num = integrate(BINARY, L0, R0, t)
    L = fr.body_momentum(t)
    # The separatrix is unstable: the B axis it tends to is a saddle whose unstable eigenvalue is the
    # elliptic rate λ = |p|, so an error δ off the separatrix grows as δ e^{λt} (e^12 = 1.6e5 here). The
    # integration starts δ ~ ε|L| off it (the state rounded into y0 = ω/|ω|, a few roundings) and
    # DOP853 at rtol 1e-13 adds less: measured 0.3 ε M e^{λt} at the end, and 1.0 ε M e^{λt} for one
    # ulp moved in any component of L0. Budget per epoch: 4 ε M e^{λt} (4 ulp) on top of the
    # integrator's own 1e-13 M (attitude: 1e-12, ephem.rotation.euler_poinsot's docstring). A flat 1e-12 M
    # failed at 6e-12 M on the last epochs, on this and other machines: the conditioning, not the
    # formulas.
    grow = np.exp(fr.elliptic_rate * t)
    eps = np.finfo(float).eps
    assert np.all(np.abs(L - L_num).max(axis=1) < (1e-13 + 4 * eps * grow) * fr.M)
    assert np.all(np.abs(fr.attitude(t) - R_num).max(axis=(1, 2)) < 1e-12 + 4 * eps * grow)
    # the well-conditioned component: L_B = ±√(M² − L_A² − L_C²) moves by (L_A δL_A + L_C δL_C)/M,
    # the growing error times the decaying sech u, so it stays at the integrator's level (measured 6e-15 M)
    assert np.abs(L[:, 1] - L_num[:, 1]).max() < 1e-13 * fr.M
    assert abs(abs(L[-1, 1]) - fr.M) < 1e-8 * fr.M          # L -> the B axis
    far = fr.body_momentum([-1e6, 1e6])
    assert np.all(np.isfinite(far)) and np.all(np.isfinite(fr.attitude([1e6])))
    # the precession rate tends to M/B (the limit of n_μ from both sides)
    mu = np.unwrap(fr.andoyer(np.array([1000.0, 1000.001]) / fr.elliptic_rate)[1])
    assert (mu[1] - mu[0]) / (0.001 / fr.elliptic_rate) == pytest.approx(fr.M / BINARY[1], rel=1e-6)
    assert fr.precession_frequency == fr.M / BINARY[1]


def test_separatrix_is_the_limit_of_both_modes():
    """Approaching D = 0 from above (short-axis) and below (long-axis), L(t) tends to the sech/tanh solution
    and n_μ to M/B, slowly: (n_μ − M/B) K(m) -> M (I3 − I1)/(I1 I3) √f arctan √f/(1 + f) (from
    Π(−f|m) − K/(1 + f) -> √f arctan √f/(1 + f) as m -> 1), with (I1, I3, f) = (A, C, f) above and
    (C, A, 1/f) below."""
    A, B, C = BINARY
    L0 = separatrix_state()
    sep = FreeRotation.from_body_momentum(BINARY, L0, 0.0, R0)
    t = np.linspace(0.0, 3.0 / sep.elliptic_rate, 50)
    f = C * (B - A) / (A * (C - B))
    for sign, (I1, I3, ff) in ((1.0, (A, C, f)), (-1.0, (C, A, 1.0 / f))):
        limit = sep.M * (I3 - I1) / (I1 * I3) * math.sqrt(ff) * math.atan(math.sqrt(ff)) / (1.0 + ff)
        for scale in (1e-3, 1e-6, 1e-9):
            near = FreeRotation.from_body_momentum(BINARY, L0 * [1.0, 1.0, 1.0 + sign * scale], 0.0, R0)
            assert near.mode == ("short-axis" if sign > 0 else "long-axis")
            assert near.complementary_parameter == pytest.approx(1.9286 * scale, rel=3e-3)
            assert np.abs(near.body_momentum(t) - sep.body_momentum(t)).max() < 20 * scale * sep.M
            gap_k = (near.precession_frequency - sep.M / B) * ellipk(near.elliptic_parameter)
            assert gap_k == pytest.approx(limit, rel=3e-2 if scale > 1e-4 else 1e-4)


def test_near_separatrix_conditioning():
    # 1 − m = 2e-6: the motion is sensitive (phase error ~ ε/(1 − m)); exact and numerical agree to 1e-8 over
    # two periods, and each agrees with a 40-digit mpmath integration to ~5e-11 over one (report, not here)
    L0 = np.array([0.3, 0.1, 0.42426406871192857 * (1 + 1e-6)])
    fr = FreeRotation.from_body_momentum(BINARY, L0, 0.0, R0)
    assert fr.complementary_parameter < 3e-6
    t = np.linspace(0.0, 2 * fr.wobble_period, 300)
    L_num, _ = integrate(BINARY, L0, R0, t)
    assert np.abs(fr.body_momentum(t) - L_num).max() < 1e-8 * fr.M


@pytest.mark.parametrize("L0, axis", [([0.0, 0.0, 2.0], 2), ([0.0, 0.0, -2.0], 2), ([1.0, 0.0, 0.0], 0),
                                      ([0.0, 1.0, 0.0], 1)])
def test_stationary_rotation(L0, axis):
    fr = FreeRotation.from_body_momentum(TRIAXIAL, L0, 0.0, R0)
    assert fr.stationary
    t = np.linspace(0.0, 30.0, 40)
    _L_num, R_num = integrate(TRIAXIAL, L0, R0, t)
    assert np.abs(fr.body_momentum(t) - L0).max() == 0.0    # stationary: L0 itself, copied to every epoch
    assert np.abs(fr.attitude(t) - R_num).max() < 1e-11
    if axis == 2:   # about C: the J -> 0 limits of the wobble and precession frequencies
        A, B, C = TRIAXIAL
        kappa = math.sqrt((C / A - 1) * (C / B - 1))
        assert fr.wobble_frequency == pytest.approx(fr.M / C * kappa, rel=1e-15)
        assert fr.precession_frequency == pytest.approx(fr.M / C * (1 + kappa), rel=1e-15)
    if axis == 1:
        assert fr.wobble_period == math.inf


@pytest.mark.parametrize("moments, L0", [((0.8, 0.8, 1.0), [0.3, 0.4, 0.0]), ((0.6, 1.0, 1.0), [0.0, 0.4, 0.3])])
def test_degenerate_planes_are_stationary(moments, L0):
    # an axisymmetric body turning about any axis of its degenerate plane: every such axis is principal
    fr = FreeRotation.from_body_momentum(moments, L0, 0.0, R0)
    t = np.linspace(0.0, 20.0, 30)
    _, R_num = integrate(moments, L0, R0, t)
    assert fr.stationary and np.abs(fr.attitude(t) - R_num).max() < 1e-11


# --------------------------------------------------------------------------- classical limits and integrals


def test_axisymmetric_limit_is_the_classical_solution():
    """A = B (Goldstein, Classical Mechanics §5.6; Lara 2014 §1): J constant, ν̇ = −N (C − A)/(AC) (L circles the
    figure axis in the body at ω3 (C − A)/A), μ̇ = M/A (the figure axis circles L in space), the wobble period
    2π A/(ω3 (C − A)) with ω3 = N/C."""
    A, C = 0.9, 1.0
    M, J, nu0, mu0 = 2.0, 0.4, 0.3, -1.0
    fr = FreeRotation.from_andoyer((A, A, C), M, J, nu0, mu=mu0, lam=0.5, inc=0.7)
    t = np.linspace(0.0, 100.0, 501)
    lam, mu, nu, Lam, _MM, N = fr.andoyer(t)
    N0 = M * math.cos(J)
    assert np.allclose(N, N0, rtol=1e-15, atol=0)
    # the angles grow linearly to |ν| = 20 and |μ| = 223 rad and are rounded to their ulp (3.6e-15 and
    # 2.8e-14) on each side, by products taken in different orders: 8 ulp of the largest angle
    nu_lin, mu_lin = nu0 - N0 * (C - A) / (A * C) * t, mu0 + M / A * t
    assert np.abs(an.wrap_angle(nu - nu_lin)).max() < 8 * np.spacing(np.abs(nu_lin).max())
    assert np.abs(an.wrap_angle(mu - mu_lin)).max() < 8 * np.spacing(np.abs(mu_lin).max())
    # λ and Λ are constants of the motion, returned as computed once at t0: to a few ulp (4.5 ε)
    assert np.allclose(lam, 0.5, rtol=1e-15, atol=0) and np.allclose(Lam, M * math.cos(0.7), rtol=1e-15, atol=0)
    assert fr.wobble_period == pytest.approx(2 * math.pi * A / ((N0 / C) * (C - A)), rel=1e-15)
    assert fr.precession_period == pytest.approx(2 * math.pi * A / M, rel=1e-15)
    # and the attitude is R3(ν) R1(J) R3(μ) R1(I) R3(λ) with those angles
    classic = an.andoyer_matrix(0.5, mu0 + M / A * t, nu0 - N0 * (C - A) / (A * C) * t, M * math.cos(0.7), M, N0)
    assert np.abs(fr.attitude(t) - classic).max() < 1e-13
    fig = fr.figure_axis(t)
    assert np.allclose(fig.opening_arcsec, J / ARCSEC, rtol=1e-14)


def test_integrals_are_conserved():
    for moments, L0 in ((TRIAXIAL, [0.3, 0.2, 1.0]), (TRIAXIAL, [1.0, 0.2, 0.3]), (BINARY, separatrix_state())):
        fr = FreeRotation.from_body_momentum(moments, L0)
        t = np.linspace(-500.0, 500.0, 20001)
        L = fr.body_momentum(t)
        assert np.abs(an.energy(L, moments) / fr.energy - 1).max() < 1e-14
        assert np.abs(an.momentum(L) / fr.M - 1).max() < 1e-14
        # and the inertial angular momentum Rᵀ L_b stays put
        G = np.einsum("nji,nj->ni", fr.attitude(t[::500]), L[::500])
        assert np.abs(G - G[0]).max() < 1e-12 * fr.M


def test_andoyer_hamilton_equations():
    # μ̇ = ∂H/∂M, ν̇ = ∂H/∂N, Ṅ = −∂H/∂ν with H = Lara's eq. 1; λ, Λ, M constant
    for L0 in ([0.3, 0.2, 1.0], [1.0, 0.2, 0.3]):
        fr = FreeRotation.from_body_momentum(TRIAXIAL, L0, 0.0, R0)
        t, h = np.linspace(0.0, 20.0, 15), 1e-5
        lam, _mu, nu, Lam, M, N = fr.andoyer(t)
        plus, minus = fr.andoyer(t + h), fr.andoyer(t - h)
        rate = [an.wrap_angle(p - m) / (2 * h) for p, m in zip(plus, minus)]
        d = 1e-6

        def H(nu_, M_, N_):
            return an.hamiltonian(nu_, M_, N_, TRIAXIAL)
        assert np.allclose(rate[1], (H(nu, M + d, N) - H(nu, M - d, N)) / (2 * d), atol=1e-7)
        assert np.allclose(rate[2], (H(nu, M, N + d) - H(nu, M, N - d)) / (2 * d), atol=1e-7)
        assert np.allclose((plus[5] - minus[5]) / (2 * h), -(H(nu + d, M, N) - H(nu - d, M, N)) / (2 * d), atol=1e-7)
        assert np.ptp(lam) < 1e-14 and np.ptp(Lam) < 1e-14 and np.ptp(M) < 1e-14


# --------------------------------------------------------------------------- Sadov's action-angle variables


@pytest.mark.parametrize("L0", [[0.3, 0.2, 1.0], [0.3, 0.2, -1.0], [1e-7, -2e-7, 1.0], [0.2, 0.9, 0.6]])
def test_sadov_variables_along_the_motion(L0):
    """Lara 2018 Appendix: L and G constant, ℓ and g advance uniformly. The fitted rates are n_ℓ = −πp/(2K)
    (negative: eq. A6 as printed has the opposite sign, see the erratum test in tests/rotation/test_against_lara2018.py)
    and n_g of eq. A7, which also equals n_μ derived here independently from Andoyer's μ̇ = ∂H/∂M."""
    fr = FreeRotation.from_body_momentum(TRIAXIAL, L0)
    t = np.linspace(0.0, 2 * fr.wobble_period, 300)
    _, mu, nu, _, M, N = fr.andoyer(t)
    sv = sadov_action_angle(mu, nu, M, N, TRIAXIAL)
    ell, g = np.unwrap(sv.ell), np.unwrap(sv.g)
    fit_l, fit_g = np.polyfit(t, ell, 1), np.polyfit(t, g, 1)
    assert np.abs(ell - np.polyval(fit_l, t)).max() < 1e-12
    assert np.abs(g - np.polyval(fit_g, t)).max() < 1e-12
    assert np.ptp(sv.L) < 1e-14 and np.ptp(sv.m) < 1e-14
    assert fit_l[0] == pytest.approx(sv.n_ell[0], rel=1e-12) and sv.n_ell[0] == pytest.approx(-fr.wobble_frequency)
    assert fit_g[0] == pytest.approx(sv.n_g[0], rel=1e-12)
    assert sv.n_g[0] == pytest.approx(fr.precession_frequency, rel=1e-13)


def test_sadov_transformation_is_canonical():
    def fn(z):
        sv = sadov_action_angle(z[0], z[1], z[2], z[3], TRIAXIAL)
        return [float(sv.ell), float(sv.g), float(sv.L), float(sv.G)]

    omega = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.eye(2), np.zeros((2, 2))]])
    for z in ([0.3, 1.2, 2.0, 1.8], [-2.0, -0.4, 1.0, 0.9], [1.0, 2.9, 3.0, -2.7]):
        z = np.array(z)
        cols = []
        for k in range(4):
            dz = np.zeros(4)
            dz[k] = 1e-6
            d = np.array(fn(z + dz)) - np.array(fn(z - dz))
            cols.append(np.where(np.abs(d) > 3, an.wrap_angle(d), d) / 2e-6)
        Jm = np.stack(cols, axis=1)
        assert np.abs(Jm.T @ omega @ Jm - omega).max() < 1e-7


def test_sadov_axisymmetric_limit():
    # f = 0: Sadov's L is N and g is μ (Andoyer variables are action-angle variables of the oblate body)
    sv = sadov_action_angle(0.4, 1.1, 2.0, 1.5, (0.9, 0.9, 1.0))
    assert float(sv.L) == pytest.approx(1.5, rel=1e-15) and float(sv.g) == pytest.approx(0.4, rel=1e-15)
    assert float(sv.n_g) == pytest.approx(2.0 / 0.9, rel=1e-15)


# --------------------------------------------------------------------------- periods


def catalogue_bodies():
    cat = load_catalogue()
    return [n for n in cat.names if cat.get(n).moments is not None]


def test_earth_rigid_euler_period():
    """Lara (2014) Table 1 Earth (A/C = 0.99672, B/C = 0.9967222) spinning once a sidereal day.

    Published: "the theoretical eigenperiod of a rigid body having the same composition and geometry as the
    Earth is about 305 days" (M. L. Smith, "A normal mode study of wobble and nutation", IAU Symp. 78,
    Nutation and the Earth's Rotation, 1980, p. 195), i.e. A/(C − A) sidereal days with H = 0.00327.
    We get 303.98 sidereal days = 303.15 days of 86400 s: 0.3 % short of 305 because Table 1 rounds A/C to
    five digits (1 − A/C = 0.00328 against 0.0032749 from IERS H_d = 0.0032737949); with IERS-consistent
    moments the same code gives 304.45 sidereal days.
    """
    A, B, C = get_body("Earth").moments
    sidereal_day = get_body("Earth").rotation_period_hours / 24.0
    fp = free_motion_periods((A, B, C), sidereal_day, wobble_arcsec=1.0)      # J0 = 1" (Table 1)
    rotations = fp.wobble_period / sidereal_day
    assert rotations == pytest.approx(303.98, abs=0.01)
    assert abs(rotations / 305.0 - 1.0) < 0.005
    assert fp.wobble_period == pytest.approx(303.15, abs=0.01)
    # the axisymmetric formula 2π/(ω (C−A)/A) differs by the triaxiality, (B − A)/(2(C − A)) ~ 3e-4
    assert abs(fp.wobble_period / fp.euler_period - 1.0) < 0.6 * (B - A) / (C - A)
    hd, dba = 0.0032737949, (B - A) / C                     # IERS 2010 H_d; Table 1's (B − A)/C
    iers = (1.0 - hd - dba / 2, 1.0 - hd + dba / 2, 1.0)
    assert free_motion_periods(iers, 1.0).wobble_period == pytest.approx(304.45, abs=0.01)
    # the rigid period is shorter than the observed Chandler wobble (433 d): elasticity lengthens it
    assert fp.wobble_period < 433.0


def test_earth_period_by_integration():
    # one predicted wobble period later, the integrated body momentum is back where it started
    A, B, C = get_body("Earth").moments
    w = 2 * math.pi / (get_body("Earth").rotation_period_hours / 24.0)
    fr = FreeRotation.from_andoyer((A, B, C), C * w, math.radians(0.5), 0.2)
    L_num, _ = integrate((A, B, C), fr.L0, np.eye(3), np.array([0.0, 0.5, 1.0]) * fr.wobble_period, rtol=1e-12)
    perp = np.hypot(fr.L0[0], fr.L0[1])
    assert np.abs(L_num[2] - fr.L0).max() < 1e-7 * perp
    assert np.abs(L_num[1, :2] + fr.L0[:2]).max() < 0.05 * perp       # half a period: roughly opposite


@pytest.mark.parametrize("name", catalogue_bodies())
def test_catalogue_periods(name):
    body = get_body(name)
    A, B, C = body.moments
    P = body.rotation_period_hours / 24.0
    fp = free_motion_periods((A, B, C), P)
    kappa = math.sqrt((C - A) * (C - B) / (A * B))
    # J -> 0: Euler's triaxial period 2π/(ω κ) and precession 2π/(ω (1 + κ)), ω = M/C = 2π/P
    assert fp.mode == "short-axis"
    assert fp.wobble_period == pytest.approx(P / kappa, rel=1e-13)
    assert fp.precession_period == pytest.approx(P / (1 + kappa), rel=1e-13)
    # the figure axis circles L faster than the nominal spin M/C and slower than M/A
    assert P * A / C < fp.precession_period < P
    # the wobble period lengthens monotonically towards the separatrix, which a path through the B-C plane
    # (ν = 0, where J is largest on its orbit) reaches at J = 90°: L on the B axis
    periods = [free_motion_periods((A, B, C), P, J_deg * 3600).wobble_period for J_deg in np.linspace(0, 89, 12)]
    assert np.all(np.diff(periods) > 0)
    assert FreeRotation.from_body_momentum((A, B, C), [0.0, 1.0, 0.0]).wobble_period == math.inf


def test_mars_rigid_period_below_observed_chandler():
    # Konopliv et al. (2020, GRL) measured Mars' Chandler wobble at ~207 d; a rigid Mars must wobble faster
    body = get_body("Mars")
    fp = free_motion_periods(body.moments, body.rotation_period_hours / 24.0, wobble_arcsec=0.1)
    assert 185.0 < fp.wobble_period < 207.0


def test_figure_axis_path_units():
    fr = FreeRotation.from_andoyer(TRIAXIAL, 2.0, math.radians(1.0), 0.0)
    t = np.linspace(0.0, fr.wobble_period, 50)
    fig = fr.figure_axis(t)
    J = an.inclination_j(fr.body_momentum(t))
    assert np.allclose(fig.opening_arcsec, J * 206264.80624709636, rtol=1e-14)
    assert np.allclose(np.hypot(*fig.offset_arcsec.T), fig.opening_arcsec, rtol=1e-14)
    assert fig.opening_arcsec[0] == pytest.approx(3600.0, rel=1e-12)
    assert np.all(np.abs(fig.azimuth_deg) <= 180.0)


# --------------------------------------------------------------------------- elliptic functions, robustness


@pytest.mark.parametrize("m1, tol", [(0.7, 4e-15), (1e-3, 4e-15), (1e-8, 1e-12), (3e-9, 1e-12), (1e-10, 4e-15),
                                     (1e-14, 4e-15)])
def test_reduced_jacobi_functions(m1, tol):
    """sn² + cn² = 1, dn² + m sn² = 1 and d sn/du = cn dn over seven half-periods. scipy's ellipj (Cephes,
    AGM) is good to ~2e-13 relative for 1e-9 < 1 − m < 1e-6 (against mpmath at 30 digits, scratch check), far
    below the motion's own sensitivity ε/(1 − m) there; hence the looser tol. Below 1e-9 the module's own
    m -> 1 expansion with the exact 1 − m takes over. K comes from 1 − m (ellipkm1), as in the module."""
    m = 1.0 - m1
    K = float(ellipkm1(m1))
    u = np.linspace(-7 * K, 7 * K, 2001)
    sn, cn, dn, *_ = jacobi_reduced(u, m, m1, K)
    assert np.abs(sn * sn + cn * cn - 1).max() < tol
    assert np.abs(dn * dn + m * sn * sn - 1).max() < tol
    h = 1e-6 * K
    sp, *_ = jacobi_reduced(u + h, m, m1, K)
    sm, *_ = jacobi_reduced(u - h, m, m1, K)
    assert np.abs((sp - sm) / (2 * h) - cn * dn).max() < 1e-6
    inside = np.abs(u) < 0.5 * K
    # within half a quarter period: ellipj itself, or the m -> 1 expansion against it, to a few ulp of |sn| <= 1
    # (measured <= 2.2e-16)
    assert np.allclose(sn[inside], ellipj(u[inside], m)[0], rtol=0, atol=1e-15)


@settings(max_examples=150, deadline=None)
@given(st.tuples(*[st.floats(-1.0, 1.0) for _ in range(3)]), st.sampled_from([TRIAXIAL, BINARY, (0.9, 0.9, 1.0),
                                                                               (0.6, 1.0, 1.0)]))
def test_never_nan(L0, moments):
    if not any(L0):
        return
    fr = FreeRotation.from_body_momentum(moments, L0)
    t = np.array([-1e4, -3.0, 0.0, 0.7, 1e4])
    for out in (fr.body_momentum(t), fr.attitude(t), np.stack(fr.andoyer(t)), fr.figure_axis(t).offset_arcsec):
        assert np.all(np.isfinite(out))
    assert fr.precession_period > 0 and fr.wobble_period > 0     # finite, or inf for |L| ~ 1e-313


def test_bad_input():
    with pytest.raises(InvalidInputError, match="no free motion to compute"):
        FreeRotation.from_body_momentum((1.0, 1.0, 1.0), [0.1, 0.2, 1.0])
    with pytest.raises(InvalidInputError, match="A <= B <= C"):
        FreeRotation.from_body_momentum((1.0, 0.8, 0.9), [0.1, 0.2, 1.0])
    with pytest.raises(InvalidInputError, match="finite"):
        FreeRotation.from_body_momentum(TRIAXIAL, [0.1, float("nan"), 1.0])
    with pytest.raises(InvalidInputError, match="must not vanish"):
        FreeRotation.from_body_momentum(TRIAXIAL, [0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="proper rotation"):
        FreeRotation.from_body_momentum(TRIAXIAL, [0.1, 0.2, 1.0], attitude=np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InvalidInputError, match=r"\[0°, 180°\]"):
        FreeRotation.from_andoyer(TRIAXIAL, 1.0, 3.2, 0.0)
    with pytest.raises(InvalidInputError, match=r"\[0°, 180°\]"):
        free_motion_periods(TRIAXIAL, 1.0, wobble_arcsec=-1.0)
    with pytest.raises(InvalidInputError, match="positive"):
        free_motion_periods(TRIAXIAL, 0.0)
    with pytest.raises(InvalidInputError, match="short-axis-mode"):
        sadov_action_angle(0.0, 0.3, 1.0, 0.1, TRIAXIAL)
    fr = FreeRotation.from_body_momentum(TRIAXIAL, [0.1, 0.2, 1.0])
    with pytest.raises(InvalidInputError, match="finite"):
        fr.body_momentum([0.0, float("inf")])
