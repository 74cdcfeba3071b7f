"""Andoyer, Poincaré-type and complex variables (ephem.rotation.andoyer) against independent routes.

Every seed formula is checked by a route that does not share its algebra:
rotation matrices against the printed entries and the kinematics, Hamiltonians
against the kinetic energy ½ Σ L_i²/I_i, canonicity by numerical Jacobians
(Jᵀ Ω J = Ω) and round trips to rounding. Lara (2014)'s printed δ values: tests/rotation/test_against_lara2014.py.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ephem.rotation import andoyer as an
from ephem.rotation import poincare as pc
from ephem.base.errors import InvalidInputError

EPS = np.finfo(float).eps
MOMENTS = [(0.6, 0.8, 1.0), (0.9, 0.9, 1.0), (0.55, 0.95, 1.0), (0.229427, 0.963754, 1.0), (0.99672, 0.9967222, 1.0)]

angle = st.floats(-math.pi, math.pi, allow_nan=False)
# J from the poles inwards on a log scale as well as uniformly: the singular ends are where bugs live
small = st.floats(1e-12, 1.0).map(lambda e: e * e)
theta_any = st.one_of(st.floats(0.0, math.pi), small, small.map(lambda e: math.pi - e))


def random_states(n=400, seed=1, moments=(0.6, 0.8, 1.0)):
    rng = np.random.default_rng(seed)
    R = an.euler_matrix(rng.uniform(-np.pi, np.pi, n), rng.uniform(0, np.pi, n), rng.uniform(-np.pi, np.pi, n))
    L = rng.normal(size=(n, 3))
    return R, L


# --------------------------------------------------------------------------- Euler angles


def test_euler_matrix_is_gurfil_eq2():
    # the printed matrix of Gurfil et al. (2007) eq. 2, entry by entry
    phi, th, psi = 0.3, 1.1, -0.7
    cf, sf, ct, s_t, cp, sp = math.cos(phi), math.sin(phi), math.cos(th), math.sin(th), math.cos(psi), math.sin(psi)
    printed = np.array([
        [cp * cf - sp * ct * sf, cp * sf + sp * ct * cf, sp * s_t],
        [-sp * cf - cp * ct * sf, -sp * sf + cp * ct * cf, cp * s_t],
        [s_t * sf, -s_t * cf, ct]])
    # each entry: products of up to three sines/cosines (≤ 1 ulp each) and a sum: ≲ 4 ε on values ≤ 1
    assert np.abs(an.euler_matrix(phi, th, psi) - printed).max() < 4 * EPS


def test_euler_kinematics_gurfil_eqs_5_to_7():
    # ω̂ = −Ṙ Rᵀ (Gurfil eq. 3) by central differences against ω1 = φ̇ sθ sψ + θ̇ cψ, ω2 = φ̇ sθ cψ − θ̇ sψ,
    # ω3 = ψ̇ + φ̇ cθ (eqs. 5-7, whose dots the seed's extraction lost)
    ang, rate, h = np.array([0.4, 0.9, -1.3]), np.array([0.7, -0.2, 1.9]), 1e-6
    R = an.euler_matrix(*ang)
    Rdot = (an.euler_matrix(*(ang + h * rate)) - an.euler_matrix(*(ang - h * rate))) / (2 * h)
    W = -Rdot @ R.T
    w = np.array([W[2, 1], W[0, 2], W[1, 0]])
    (_phi, th, psi), (dphi, dth, dpsi) = ang, rate
    expected = [dphi * math.sin(th) * math.sin(psi) + dth * math.cos(psi),
                dphi * math.sin(th) * math.cos(psi) - dth * math.sin(psi),
                dpsi + dphi * math.cos(th)]
    assert np.allclose(w, expected, atol=1e-9)
    assert np.abs(W + W.T).max() < 1e-9


@settings(max_examples=300, deadline=None)
@given(angle, theta_any, angle)
def test_euler_angles_round_trip(phi, theta, psi):
    R = an.euler_matrix(phi, theta, psi)
    back = an.euler_from_matrix(R)
    assert np.abs(an.euler_matrix(*back) - R).max() < 8 * EPS
    assert 0.0 <= back[1] <= math.pi


# --------------------------------------------------------------------------- Andoyer variables


@settings(max_examples=300, deadline=None)
@given(angle, theta_any, angle, angle, theta_any, st.floats(0.1, 10.0))
def test_andoyer_euler_round_trip(phi, theta, psi, nu, J, M):
    L = an.body_momentum_from_j(M, J, nu)
    A = an.andoyer_from_euler(phi, theta, psi, L)
    phi2, th2, psi2, L2 = an.euler_from_andoyer(*A)
    # sin J and sin I come back from the momenta N = M cos J, Λ = M cos I: their rounding costs
    # ε / sin J (at most √(2ε) as J -> 0), the Andoyer chart's own singularity, not an implementation error
    sI = math.sqrt(max(1.0 - (A[3] / A[4]) ** 2, 0.0))
    lost = 4 * EPS * (2.0 + 1.0 / max(math.sin(J), math.sqrt(EPS)) + 1.0 / max(sI, math.sqrt(EPS)))
    assert np.abs(an.euler_matrix(phi2, th2, psi2) - an.euler_matrix(phi, theta, psi)).max() < lost
    # L1, L2 come back through √((M − N)(M + N)): its rounding is ε M / sin J
    tol = 4 * EPS * M * (1.0 + 1.0 / max(math.sin(J), 1e-300))
    assert np.abs(L2 - L).max() <= min(tol, 2.0 * M)
    assert A[4] == pytest.approx(M, rel=4 * EPS)
    assert A[5] == L[2]


def test_andoyer_variables_are_the_defining_geometry():
    # Λ = L·ẑ, N = L·b3, cos I = Λ/M, cos J = N/M, and R = R3(ν) R1(J) R3(μ) R1(I) R3(λ) (Lara 2018 eq. 34)
    R, L = random_states()
    lam, mu, nu, Lam, M, N = an.andoyer_from_attitude(R, L)
    G = np.einsum("nji,nj->ni", R, L)
    # Λ = (Rᵀ L)_z against the same dot product by einsum: 3 products and 2 sums of |L| ~ 2 (1e-14 = 20 ulp
    # of 2); N is L₃ itself, so equal; M = |L| by two routes to a few ulp (rtol 1e-15 = 4.5 ε)
    assert np.allclose(Lam, G[:, 2], rtol=0, atol=1e-14) and np.array_equal(N, L[:, 2])
    assert np.allclose(M, np.linalg.norm(L, axis=1), rtol=1e-15, atol=0)
    J, I = np.arccos(N / M), np.arccos(Lam / M)
    direct = an.rot3(nu) @ an.rot1(J) @ an.rot3(mu) @ an.rot1(I) @ an.rot3(lam)
    assert np.abs(direct - R).max() < 1e-13
    # the node of the invariable plane: ẑ × L direction at longitude λ
    node = np.cross([0.0, 0.0, 1.0], G)
    assert np.allclose(np.arctan2(node[:, 1], node[:, 0]), lam, atol=1e-13)


def test_gurfil_euler_momenta_eqs_40_42_and_83():
    # Φ = Λ and Ψ = N (eq. 83: H = Φ, L = Ψ); eqs. 25-27 invert eqs. 40-42 where sin θ ≠ 0
    rng = np.random.default_rng(5)
    phi, th, psi = rng.uniform(-3, 3, 200), rng.uniform(0.05, 3.09, 200), rng.uniform(-3, 3, 200)
    L = rng.normal(size=(200, 3))
    Phi, Theta, Psi = an.euler_momenta(th, psi, L)
    A = an.andoyer_from_euler(phi, th, psi, L)
    # Φ = Λ by two orders of the same products (|L| ~ 2: 1e-14 = 20 ulp); Ψ and N are both L₃, copied
    assert np.allclose(Phi, A[3], rtol=0, atol=1e-14) and np.array_equal(Psi, A[5])
    s_t, c_t, sp, cp = np.sin(th), np.cos(th), np.sin(psi), np.cos(psi)
    g1 = (Phi * sp + Theta * s_t * cp - Psi * sp * c_t) / s_t      # Gurfil eq. 25
    g2 = (Phi * cp - Theta * sp * s_t - Psi * cp * c_t) / s_t      # eq. 26
    assert np.allclose(np.stack([g1, g2, Psi], 1), L, atol=1e-12)


def test_energy_and_hamiltonians_agree():
    for mom in MOMENTS:
        R, L = random_states(moments=mom)
        _lam, _mu, nu, _Lam, M, N = an.andoyer_from_attitude(R, L)
        T = an.energy(L, mom)
        p = an.inertia_parameters(mom)
        assert np.allclose(an.hamiltonian(nu, M, N, mom), T, rtol=4e-15, atol=0)                  # Lara eq. 1
        assert np.allclose(an.hamiltonian_alpha_beta(nu, M, N, p.C, p.alpha, p.beta), T, rtol=4e-15, atol=0)
        # the SAM split (Lara 2014 eqs. 5-7) is exact
        assert np.allclose(an.sam_main_problem(nu, M, N, mom) + an.sam_perturbation(nu, M, N, mom), T, rtol=1e-14)


@pytest.mark.parametrize("mom", [m for m in MOMENTS if m[1] < m[2]])
def test_poincare_and_complex_hamiltonians(mom):
    # Lara 2018 eqs. 15 and 19 (Poincaré) and 25 and 26 (complex) equal eqs. 5 and 6 term by term
    R, L = random_states(moments=mom)
    L[:, 2] = np.abs(L[:, 2])
    _lam, mu, nu, _Lam, M, N = an.andoyer_from_attitude(R, L)
    x, g, X, G = pc.poincare_from_andoyer(mu, nu, M, N)
    main, pert = an.sam_main_problem(nu, M, N, mom), an.sam_perturbation(nu, M, N, mom)
    assert np.allclose(pc.sam_main_problem_poincare(x, X, G, mom), main, rtol=1e-13)
    assert np.allclose(pc.sam_perturbation_poincare(x, X, mom), pert, rtol=1e-12, atol=1e-15 * np.abs(main).max())
    assert np.allclose(pc.hamiltonian_poincare(x, X, G, mom), an.energy(L, mom), rtol=1e-14)
    u, _v, U, V = pc.complex_from_poincare(x, g, X, G, mom)
    assert np.allclose(U, 1j * np.conj(u), atol=1e-15)          # real states: U = i ū
    hm, hp = pc.sam_main_problem_complex(u, U, V, mom), pc.sam_perturbation_complex(u, U, mom)
    assert np.allclose(hm, main, rtol=1e-13) and np.abs(hm.imag).max() < 1e-14 * np.abs(main).max()
    assert np.allclose(hp, pert, rtol=1e-11, atol=1e-15 * np.abs(main).max())


# --------------------------------------------------------------------------- canonicity


OMEGA = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.eye(2), np.zeros((2, 2))]])


def jacobian(fn, z, h=1e-6):
    """Central-difference Jacobian of fn: R⁴ -> R⁴ (angles unwrapped against the centre value)."""
    cols = []
    for k in range(4):
        dz = np.zeros(4)
        dz[k] = h
        fp, fm = np.array(fn(z + dz)), np.array(fn(z - dz))
        d = fp - fm
        d = np.where(np.abs(d) > 3.0, an.wrap_angle(d), d)   # angles crossing ±π
        cols.append(d / (2 * h))
    return np.stack(cols, axis=1)


def assert_symplectic(fn, z, tol=1e-7):
    Jm = jacobian(fn, z)
    assert np.abs(Jm.T @ OMEGA @ Jm - OMEGA).max() < tol


@pytest.mark.parametrize("hemisphere", [1, -1])
def test_poincare_transformation_is_canonical(hemisphere):
    # (μ, ν; M, N) -> (x, g; X, G): Lara 2018 Proposition 1 (and its mirror for J near 180°)
    def fn(z):
        x, g, X, G = pc.poincare_from_andoyer(z[0], z[1], z[2], z[3], hemisphere)
        return [float(x), float(g), float(X), float(G)]

    for z in ([0.3, 1.2, 2.0, 1.7 * hemisphere], [-2.0, -0.4, 1.0, 0.2], [1.0, 2.9, 3.0, -2.5 * hemisphere]):
        assert_symplectic(fn, np.array(z, dtype=float))


def test_sam_action_angle_is_canonical_and_oscillator():
    # Lara 2014 eqs. 18-25 ("a Mathieu transformation": M dμ + N dν = L dℓ + G dg)
    mom = (0.6, 0.8, 1.0)

    def fn(z):
        return [float(v) for v in pc.sam_action_angle_from_andoyer(z[0], z[1], z[2], z[3], mom)]

    for z in ([0.3, 1.2, 2.0, 1.7], [-2.0, -0.4, 1.0, 0.2], [1.0, 2.9, 3.0, -2.5]):
        assert_symplectic(fn, np.array(z))
    # and it is the oscillator form of Lara 2018 eq. 17: x = √(2L/ω) sin ℓ, X = √(2ωL) cos ℓ
    R, L = random_states()
    _, mu, nu, _, M, N = an.andoyer_from_attitude(R, L)
    ell, g, Lac, G = pc.sam_action_angle_from_andoyer(mu, nu, M, N, mom)
    x, _g2, X, _ = pc.poincare_from_andoyer(mu, nu, M, N)
    w = an.inertia_parameters(mom).omega
    assert np.allclose(np.sqrt(2 * Lac / w) * np.sin(ell), x, atol=1e-13)
    assert np.allclose(np.sqrt(2 * Lac * w) * np.cos(ell), X, atol=1e-13)
    back = pc.andoyer_from_sam_action_angle(ell, g, Lac, G, mom)
    assert np.abs(an.wrap_angle(back[0] - mu)).max() < 1e-13 and np.abs(back[3] - N).max() < 1e-13


def test_complex_transformation_is_canonical():
    # {u, U} = 1 in (x, X) and dg ∧ dG = dv ∧ dV (Lara 2018 Proposition 2, with Ω = ω, κ of eq. 24)
    mom = (0.6, 0.8, 1.0)
    x, X, h = 0.3, -0.7, 1e-6
    du_dx = (pc.complex_from_poincare(x + h, 0, X, 1, mom)[0] - pc.complex_from_poincare(x - h, 0, X, 1, mom)[0]) / (2 * h)
    du_dX = (pc.complex_from_poincare(x, 0, X + h, 1, mom)[0] - pc.complex_from_poincare(x, 0, X - h, 1, mom)[0]) / (2 * h)
    dU_dx = (pc.complex_from_poincare(x + h, 0, X, 1, mom)[2] - pc.complex_from_poincare(x - h, 0, X, 1, mom)[2]) / (2 * h)
    dU_dX = (pc.complex_from_poincare(x, 0, X + h, 1, mom)[2] - pc.complex_from_poincare(x, 0, X - h, 1, mom)[2]) / (2 * h)
    assert abs(du_dx * dU_dX - du_dX * dU_dx - 1.0) < 1e-9
    _, v, _, V = pc.complex_from_poincare(x, 0.4, X, 2.0, mom)
    assert v * V == pytest.approx(0.4 * 2.0, rel=1e-15)
    p = an.inertia_parameters(mom)
    assert p.kappa == pytest.approx(p.alpha * math.sqrt(1 - p.beta**2), rel=1e-14)   # eq. 24, both forms


@settings(max_examples=200, deadline=None)
@given(angle, angle, st.floats(0.1, 10.0), st.floats(-1.0, 1.0), st.sampled_from([1, -1]))
def test_poincare_andoyer_round_trip(mu, nu, M, c, s):
    N = c * M
    x, g, X, G = pc.poincare_from_andoyer(mu, nu, M, N, s)
    mu2, nu2, M2, N2 = pc.andoyer_from_poincare(x, g, X, G, s)
    assert abs(N2 - N) <= 8 * EPS * M and M2 == M
    if abs(M - s * N) > 1e-6 * M:   # ν (and μ) are defined away from the hemisphere's pole
        assert abs(an.wrap_angle(nu2 - nu)) < 1e-7 and abs(an.wrap_angle(mu2 - mu)) < 1e-7


@pytest.mark.parametrize("mom", [m for m in MOMENTS if m[1] < m[2]])
def test_complex_round_trip(mom):
    R, L = random_states(moments=mom)
    _, x, g, _, X, G = pc.poincare_from_attitude(R, L)
    u, v, U, V = pc.complex_from_poincare(x, g, X, G, mom)
    x2, g2, X2, G2 = pc.poincare_from_complex(u, v, U, V, mom)
    assert np.abs(x2 - x).max() < 1e-14 * np.abs(x).max() and np.abs(X2 - X).max() < 1e-14 * np.abs(X).max()
    assert np.allclose(g2, g, atol=1e-15) and np.allclose(G2, G, rtol=1e-15)


# --------------------------------------------------------------------------- the singularities


@pytest.mark.parametrize("J, s", [(1e-10, 1), (1e-13, 1), (math.pi - 1e-10, -1), (math.pi - 1e-13, -1)])
def test_andoyer_loses_small_j_poincare_does_not(J, s):
    """At J ~ 1e-10 the Andoyer momentum N = M cos J cannot hold J (M − N = M J²/2 < ε M): the body momentum
    rebuilt from (ν, M, N) loses L1, L2 entirely. The Poincaré-type variables carry x ~ L1, X ~ L2 and
    rebuild them to rounding (Lara 2018 §2.3); the mirror set does the same at J = 180°."""
    M, nu = 3.0, 0.7
    L = an.body_momentum_from_j(M, J, nu)
    R = an.euler_matrix(0.2, 0.9, -1.1)
    perp = math.hypot(L[0], L[1])
    nu_a, M_a, N_a = an.andoyer_from_body_momentum(L)
    via_andoyer = an.body_momentum_from_andoyer(nu_a, M_a, N_a)
    assert math.hypot(*(via_andoyer[:2] - L[:2])) > 0.5 * perp          # the singular chart fails
    P = pc.poincare_from_attitude(R, L, s)
    R2, L2 = pc.attitude_from_poincare(*P, hemisphere=s)
    assert math.hypot(*(L2[:2] - L[:2])) < 4 * EPS * perp               # the regular chart does not
    assert np.abs(R2 - R).max() < 8 * EPS
    # and the other hemisphere's chart is the singular one there
    Pw = pc.poincare_from_attitude(R, L, -s)
    assert np.isfinite(Pw[1]) and np.isfinite(Pw[4])


def test_wrong_hemisphere_pole_is_finite():
    # each chart is singular at the other pole (J = 180° for s = 1): there it returns finite values
    # (ν = 0 by convention), without warnings, but cannot carry the attitude
    R = an.euler_matrix(0.2, 0.9, -1.1)
    for L3, s in ((-2.0, 1), (2.0, -1)):
        P = pc.poincare_from_attitude(R, [0.0, 0.0, L3], s)
        R2, L2 = pc.attitude_from_poincare(*P, hemisphere=s)
        assert all(np.all(np.isfinite(v)) for v in P) and np.all(np.isfinite(R2))
        # L comes back through a few roundings of values of size |L| = 2: 4 ulp of |L| (the atol=1e-15 this
        # replaces was 2.25 ulp of 2, and the trip measured 2 ulp)
        assert np.allclose(L2, [0.0, 0.0, L3], atol=4 * EPS * abs(L3), rtol=0)
        # det of a rotation built from ~3 roundings per entry, by LU (LAPACK): ≲ 10 ε; 16 ε (measured 3 ε)
        assert abs(np.linalg.det(R2) - 1.0) < 16 * EPS


def test_poincare_variables_are_smooth_through_the_pole():
    # L's tip crosses the C axis along L1 (J through 0): ν jumps by π, x and X stay linear in the path parameter
    eps = np.linspace(-1e-6, 1e-6, 201)
    L = np.stack([eps, 0.3 * eps, np.full_like(eps, 2.0)], axis=1)
    R = an.euler_matrix(np.zeros_like(eps) + 0.1, np.zeros_like(eps) + 0.5, np.zeros_like(eps) - 0.2)
    nu, _, _ = an.andoyer_from_body_momentum(L)
    assert abs(nu[-1] - nu[0]) == pytest.approx(math.pi, abs=1e-12)     # ν flips across the pole
    _, x, g, _, X, _G = pc.poincare_from_attitude(R, L)
    for v in (x, X):
        second = np.diff(v, 2)
        assert np.abs(second).max() < 1e-20 + 1e-9 * np.abs(np.diff(v)).max()
    assert np.abs(np.diff(g, 2)).max() < 1e-15        # g = μ + ν moves smoothly (linearly) through the pole


def test_andoyer_attitude_at_the_poles():
    # at J = 0 and J = π exactly (N = ±M), ν = 0 by convention and μ takes the whole angle μ ± ν; the
    # attitude rebuilds to rounding. Just off the pole N can no longer hold J and the chart loses ~J.
    R = an.euler_matrix(0.3, 1.0, -0.5)
    for L3 in (2.0, -2.0):
        A = an.andoyer_from_attitude(R, [0.0, 0.0, L3])
        assert A[2] == 0.0
        assert np.abs(an.andoyer_matrix(*A) - R).max() < 8 * EPS
    A = an.andoyer_from_attitude(R, an.body_momentum_from_j(2.0, 1e-9, 0.4))
    assert abs(A[5] - A[4]) <= 2 * EPS * A[4]             # N = M to rounding: J = 1e-9 is gone
    assert 0.5e-9 < np.abs(an.andoyer_matrix(*A) - R).max() < 2e-9


# --------------------------------------------------------------------------- bad input


def test_bad_moments():
    with pytest.raises(InvalidInputError, match="A <= B <= C"):
        an.inertia_parameters((1.0, 0.8, 0.9))
    with pytest.raises(InvalidInputError, match="C > A \\+ B"):
        an.check_moments((0.1, 0.2, 1.0))
    with pytest.raises(InvalidInputError, match="finite"):
        an.check_moments((0.5, float("nan"), 1.0))
    with pytest.raises(InvalidInputError, match="no free motion"):
        an.check_moments((1.0, 1.0, 1.0), allow_spherical=False)
    with pytest.raises(InvalidInputError, match="three principal moments"):
        an.check_moments((1.0, 1.0))
    with pytest.raises(InvalidInputError, match="infinite"):
        pc.complex_from_poincare(0.1, 0.0, 0.1, 1.0, (0.5, 1.0, 1.0))


def test_bad_states():
    with pytest.raises(InvalidInputError, match=r"\[0°, 180°\]"):
        an.body_momentum_from_j(1.0, -0.1, 0.0)
    with pytest.raises(InvalidInputError, match=r"\[0°, 180°\]"):
        an.body_momentum_from_j(1.0, math.pi + 1e-9, 0.0)
    with pytest.raises(InvalidInputError, match=r"\|N\| <= M"):
        an.body_momentum_from_andoyer(0.0, 1.0, 1.01)
    with pytest.raises(InvalidInputError, match="finite"):
        an.hamiltonian(float("inf"), 1.0, 0.5, (0.6, 0.8, 1.0))
    with pytest.raises(InvalidInputError, match="finite"):
        an.andoyer_from_euler(0.0, float("nan"), 0.0, [0.0, 0.0, 1.0])
    with pytest.raises(InvalidInputError, match="must not vanish"):
        an.andoyer_from_body_momentum([0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="hemisphere"):
        pc.poincare_from_andoyer(0.0, 0.0, 1.0, 0.5, hemisphere=0)
    with pytest.raises(InvalidInputError, match="positive"):
        pc.andoyer_from_poincare(0.1, 0.0, 0.1, -1.0)
    # N within rounding of ±M is clipped, not rejected (M = |L| is itself rounded)
    assert np.all(np.isfinite(an.body_momentum_from_andoyer(0.3, 1.0, 1.0 + 2 * EPS)))
