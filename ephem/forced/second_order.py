"""Second order in the torque: the equinox drifts under the precession, and the nutation feeds back.

The first-order theory (:mod:`ephem.forced.kinoshita`) holds the equinox fixed: the
constants C' = cos 2θ and S' = sin 2θ of Petit et al. (2014, eqs. 20-22) use the
angle θ from the equinox to the pericentre at the pole epoch. But the equinox
moves with the precession, so the Sun's longitude from it is λ = θ̄0 + ψ̄ + ν
(ψ̄ the mean precession since the epoch). Two effects of relative size K/n
follow, both growing with time:

* the phases of the θ-dependent nutation terms drift (re-phasing);
* the nutation correlates with the torque it modulates, which adds a slow
  secular drift to ψ̄ and ε̄ (the second-order mean rates).

Both come from second-order averaging (e.g. Sanders, Verhulst & Murdock,
*Averaging Methods in Nonlinear Dynamical Systems*, 2007, ch. 2). With x = (ψ, ε),
ẋ = f(x, M) the rotation-averaged equations of :mod:`ephem.forced.kinoshita` and
x = x̄ + w(x̄, M) with w the first-order (zero-mean) nutation,

    dx̄/dt = <f>(x̄) + <Df · w>(x̄)

where <·> averages over the mean anomaly M at fixed x̄. <f> = ((K/2) cos ε̄ (1-e²)^(-3/2), 0),
since the Hansen coefficient X_0^{-3,2}(e) vanishes. The second-order rates are

    <Df · w> = (cos²ε̄ G1(φ) + sin²ε̄ G2(φ),  sin ε̄ cos ε̄ G3(φ)),    φ = θ̄0 + ψ̄,

with G1, G2, G3 trigonometric polynomials in 2φ of degree 2, computed here by
quadrature over M (exact up to rounding: the integrands are band-limited in φ).
The mean equations are integrated numerically (they are slow and smooth: a few
steps per precession period) and the nutation is evaluated with the current
mean ε̄ and φ. The remaining error is periodic, of relative size (K/n)², plus a
third-order drift; it is estimated in :mod:`ephem.sun.ladder`.

Measured against the numerical integration of the averaged torque (rung 5),
over 20 years: Vesta 6.7 → 0.21 mas, Eros 176 → 5.3 mas, Itokawa 252 → 3.7 mas;
over 200 years Itokawa 2435 → 3.9 mas.

Radians, days, rad/day.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..orbit.harmonics import evaluate_harmonics_periodic
from ..orbit.kepler import solve_kepler, true_anomaly
from .kinoshita import NutationComponents, eccentricity_factor, nutation_components

#: Samples of φ over its period π: the G's hold harmonics 0, ±2φ, ±4φ, which 8 samples resolve (and the
#: third-order rates of :class:`Remainder`, up to ±6φ).
_PHI_SAMPLES = 8


def _phi_harmonics(values: np.ndarray, degree: int = 2) -> np.ndarray:
    """Real coefficients (c0, c1, s1, c2, s2, …) of Σ_j c_j cos 2jφ + s_j sin 2jφ, j <= ``degree`` (at most 3),
    from samples on the φ grid (last axis)."""
    spec = np.fft.rfft(values, axis=-1) / _PHI_SAMPLES
    out = [spec[..., 0].real]
    for j in range(1, degree + 1):
        out += [2 * spec[..., j].real, -2 * spec[..., j].imag]
    return np.stack(out, axis=-1)


def eval_phi(coef: np.ndarray, phi):
    """Σ_j c_j cos 2jφ + s_j sin 2jφ from coefficients (…, 2 degree + 1) of :func:`_phi_harmonics`."""
    c2, s2 = np.cos(2.0 * phi), np.sin(2.0 * phi)
    c4, s4 = c2 * c2 - s2 * s2, 2.0 * s2 * c2
    out = coef[..., 0] + coef[..., 1] * c2 + coef[..., 2] * s2 + coef[..., 3] * c4 + coef[..., 4] * s4
    if coef.shape[-1] > 5:
        out = out + coef[..., 5] * (c4 * c2 - s4 * s2) + coef[..., 6] * (s4 * c2 + c4 * s2)
    return out


def _quadrature(e: float, components: NutationComponents, count: int, start: float = 0.0, fft: bool = False):
    """The mean anomalies M_j = start + 2πj/count, the true anomaly, (a/r)^3 and the nutation's a, b, c there
    (``fft``: the nutation by one inverse FFT, :func:`ephem.orbit.harmonics.evaluate_harmonics_periodic`)."""
    m = start + 2.0 * math.pi * np.arange(count) / count
    nu = true_anomaly(m, e)
    rho = (1.0 / (1.0 - e * np.cos(solve_kepler(m, e)))) ** 3
    if fft and components.multiple.size:
        abc = evaluate_harmonics_periodic(start, count, components.sin_coef, components.cos_coef)
        return m, nu, rho, (abc[:, 0], abc[:, 1], abc[:, 2])
    return m, nu, rho, components.evaluate(m)


def _integrands(K: float, nu, rho, a, b, c):
    """On the φ grid (rows) and the M samples (columns): the nutation's parts w_ψ, w_ε (Δψ = cos ε w_ψ,
    Δε = sin ε w_ε), cos 2λ, sin 2λ (λ = φ + ν) and the integrands I1, I2, I3 of :func:`second_order_coefficients`,
    the ε-free factors of Df · w (the torque's derivative along the nutation)."""
    phi = (math.pi / _PHI_SAMPLES) * np.arange(_PHI_SAMPLES)[:, None]
    lam2 = 2.0 * (phi + nu)
    c2l, s2l = np.cos(lam2), np.sin(lam2)
    cp, sp = np.cos(2.0 * phi), np.sin(2.0 * phi)
    w_psi = a - cp * b - sp * c          # Δψ = cos ε w_psi
    w_eps = cp * c - sp * b              # Δε = sin ε w_eps
    half_k_rho = 0.5 * K * rho
    i1 = half_k_rho * 2.0 * s2l * w_psi                      # ∂f_ψ/∂ψ Δψ / cos²ε
    i2 = -half_k_rho * (1.0 - c2l) * w_eps                   # ∂f_ψ/∂ε Δε / sin²ε
    i3 = -half_k_rho * (2.0 * c2l * w_psi + s2l * w_eps)     # (∂f_ε/∂ψ Δψ + ∂f_ε/∂ε Δε) / (sin ε cos ε)
    return dict(cp=cp, sp=sp, c2l=c2l, s2l=s2l, w_psi=w_psi, w_eps=w_eps, half_k_rho=half_k_rho, i1=i1, i2=i2, i3=i3)


def second_order_coefficients(K: float, e: float, components: NutationComponents) -> np.ndarray:
    """Harmonics in φ of G1, G2, G3 (rad/day): array (3, 5) of (c0, c1, s1, c2, s2).

    Quadrature of <Df · w> over M on an even grid (the trapezoidal rule, spectrally
    accurate for periodic integrands) with enough points to resolve every harmonic
    of (a/r)^3 e^{2iν} and of the nutation.
    """
    kmax = int(components.multiple.max()) if components.multiple.size else 1
    _, nu, rho, (a, b, c) = _quadrature(e, components, max(512, 8 * kmax))
    f = _integrands(K, nu, rho, a, b, c)
    return _phi_harmonics(np.stack([np.mean(f[key], axis=1) for key in ("i1", "i2", "i3")]))


@dataclass(frozen=True)
class MeanTrack:
    """Mean precession ψ̄ and obliquity ε̄ (radians) as functions of time, either side of the epoch."""

    epoch: float
    forward: object | None
    backward: object | None
    start: tuple[float, float]

    def __call__(self, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
        t = np.asarray(jd_tdb, dtype=float)
        psi = np.full(t.shape, self.start[0])
        eps = np.full(t.shape, self.start[1])
        for sol, mask in ((self.forward, t > self.epoch), (self.backward, t < self.epoch)):
            if sol is not None and mask.any():
                y = sol(t[mask])
                psi[mask], eps[mask] = y[0], y[1]
        return psi, eps


@dataclass(frozen=True)
class SecondOrderTheory:
    """Rung 4 of the ladder: the first-order series re-phased with the moving equinox,
    plus the second-order mean rates. Built from a :class:`~ephem.forced.precession_nutation.PrecessionNutation`."""

    components: NutationComponents
    coefficients: np.ndarray      # (3, 5), see second_order_coefficients
    first_order_rate: float       # (K/2)(1-e²)^(-3/2), rad/day: ψ̇ = this × cos ε̄
    equinox_to_pericentre: float  # θ̄0 at the pole epoch
    obliquity: float              # ε̄0
    pole_epoch: float

    def mean_rates(self, psi_bar, eps_bar):
        """dψ̄/dt and dε̄/dt (rad/day), first plus second order."""
        g = eval_phi(self.coefficients, np.asarray(self.equinox_to_pericentre + psi_bar)[..., None])
        ce, se = np.cos(eps_bar), np.sin(eps_bar)
        return (self.first_order_rate * ce + ce * ce * g[..., 0] + se * se * g[..., 1],
                se * ce * g[..., 2])

    def mean_track(self, jd_tdb) -> MeanTrack:
        """Integrate the mean equations over the epochs' span (DOP853, dense output)."""
        from scipy.integrate import solve_ivp  # imported on first use: 0.35 s

        t = np.asarray(jd_tdb, dtype=float)
        y0 = [0.0, self.obliquity]

        def rhs(_, y):
            dpsi, deps = self.mean_rates(y[0], y[1])
            return [float(dpsi), float(deps)]

        sols = []
        for end in ((t.max() if t.size else self.pole_epoch), (t.min() if t.size else self.pole_epoch)):
            if (end - self.pole_epoch) == 0.0 or (end > self.pole_epoch) != (len(sols) == 0):
                sols.append(None)
                continue
            sol = solve_ivp(rhs, (self.pole_epoch, end), y0, method="DOP853", rtol=1e-12, atol=1e-15,
                            dense_output=True)
            if not sol.success:  # pragma: no cover - smooth two-variable system
                raise RuntimeError(f"mean equations failed: {sol.message}")
            sols.append(sol.sol)
        return MeanTrack(self.pole_epoch, sols[0], sols[1], (0.0, self.obliquity))

    def angles(self, mean_anomaly, jd_tdb):
        """ψ (from the mean equinox at the epoch), Δψ, Δε and ε (radians) at the epochs."""
        psi_bar, eps_bar = self.mean_track(jd_tdb)(jd_tdb)
        a, b, c = self.components.evaluate(mean_anomaly)
        dpsi, deps = NutationComponents.combine(a, b, c, eps_bar, self.equinox_to_pericentre + psi_bar)
        return psi_bar + dpsi, dpsi, deps, eps_bar + deps


def second_order_theory(model, order: int | None = None) -> SecondOrderTheory:
    """Rung 4 for a first-order ``model`` (:class:`~ephem.forced.precession_nutation.PrecessionNutation`)."""
    comp = nutation_components(model.scaling_factor, model.mean_motion, model.eccentricity, order)
    coef = second_order_coefficients(model.scaling_factor, model.eccentricity, comp)
    rate = 0.5 * model.scaling_factor * eccentricity_factor(model.eccentricity, order)
    return SecondOrderTheory(comp, coef, rate, model.equinox_to_pericentre, model.obliquity, model.pole_epoch)


#: A :class:`PhasedSeries` keeps the harmonics of M until those left out sum to at most this fraction of all.
SERIES_TAIL = 1e-9


@dataclass(frozen=True)
class PhasedSeries:
    """A pair (ψ, ε) of periodic functions of the mean anomaly M and of the phase φ (radians, or rad/day for
    rates), at most degree 2 in (cos 2φ, sin 2φ): ``values`` (N, 2, 5) at M_j = ``start`` + 2πj/N and ``sin_coef``,
    ``cos_coef`` (K, 2, 5) of sin k(M - start), cos k(M - start), k = 1..K, each as φ-harmonics (c0, c1, s1, c2,
    s2). The harmonics above K (up to N/2) are left out of the coefficients (not of the values): ``tail`` (5,)
    holds Σ_{k>K} k^p sup_φ |c_k| for p = 0..4, what they can add to the function and its first four derivatives
    in M."""

    start: float
    values: np.ndarray
    sin_coef: np.ndarray
    cos_coef: np.ndarray
    tail: np.ndarray

    @classmethod
    def from_samples(cls, samples: np.ndarray, start: float, integrate_over: float | None = None) -> PhasedSeries:
        """From samples (2, φ grid, N) of functions of zero mean over M on the M grid from ``start``;
        ``integrate_over`` n: their integral over time (∫ dt = ∫ dM / n, of zero mean) instead."""
        count = samples.shape[-1]
        spec = np.fft.rfft(samples, axis=-1)
        spec[..., 0] = 0.0
        if integrate_over is not None:
            spec[..., 1:] /= 1j * np.arange(1.0, spec.shape[-1]) * integrate_over
        values = np.fft.irfft(spec, n=count, axis=-1)
        # X_k e^{ikx} and its conjugate give 2 Re X_k / N cos kx - 2 Im X_k / N sin kx; the Nyquist term once
        cos_c, sin_c = 2.0 * spec[..., 1:].real / count, -2.0 * spec[..., 1:].imag / count
        cos_c[..., -1] *= 0.5
        sin_c[..., -1] = 0.0
        values, sin_c, cos_c = (_phi_harmonics(np.moveaxis(x, 1, -1)).transpose(1, 0, 2) for x in (values, sin_c, cos_c))
        # sup over φ of a harmonic's size: the sum over the φ-harmonics of its norm over ψ, ε and sin, cos
        size = np.sum(np.sqrt(np.sum(sin_c ** 2 + cos_c ** 2, axis=1)), axis=-1)
        left = np.cumsum(size[::-1])[::-1]                        # Σ_{k' >= k} size
        small = np.nonzero(left <= SERIES_TAIL * (left[0] if left.size else 0.0))[0]
        keep = int(small[0]) if small.size else size.size
        k = np.arange(1.0, size.size + 1.0)
        tail = np.array([float(np.sum(k[keep:] ** p * size[keep:])) for p in range(5)])
        return cls(float(start), values, sin_c[:keep], cos_c[:keep], tail)

    def at(self, phi: float):
        """At the phase φ: values (N, 2) on the grid, and the coefficients (K, 2) of sin k(M - start), cos k(M - start)."""
        return eval_phi(self.values, phi), eval_phi(self.sin_coef, phi), eval_phi(self.cos_coef, phi)


@dataclass(frozen=True)
class Remainder:
    """What rungs 3 and 4 leave at second and third order (radians, rad/day).

    Third-order averaging of ẋ = f(x, M) (x = (ψ, ε); Sanders, Verhulst & Murdock 2007, ch. 2): with the
    near-identity change x = y + u1 + u2 + …, u1 = w the first-order nutation and ẏ = g1 + g2 + g3 + …,
    order by order in the torque

        g1 + ∂_t u1 = f,    g2 + Du1 · g1 + ∂_t u2 = Df · u1,    g3 + Du1 · g2 + Du2 · g1 + ∂_t u3 = Df · u2 + ½ D²f(u1, u1)

    so, with u1 and u2 of zero mean over M, g2 = <Df · w> (the G's of :func:`second_order_coefficients`),

        u2 = P2 = ∫ (Df · w - V ψ̇ - g2) dt,    g3 = <Df · P2 + ½ D²f(w, w)>,    V = ∂w/∂φ

    (ψ̇ = g1 moves φ = θ̄0 + ψ̄, on which w depends through λ = φ + ν: ∂Δψ/∂φ = 2 cos ε (S' b - C' c),
    ∂Δε/∂φ = -2 sin ε (C' b + S' c) in the notation of :class:`~ephem.forced.kinoshita.NutationComponents`). Rung 4
    follows y to second order and adds w, so against the integrated torque it misses P2(t) - P2(t0) (both start
    from the catalogue pole) and drifts at g3, plus the drift its first-order mean pole causes: its ε̄0 differs
    from the mean obliquity by -P2_ε(t0), which changes ψ̇ = (K/2) f(e) cos ε̄ by (K/2) f(e) sin ε̄ P2_ε(t0)
    (:meth:`drift_harmonics`). Rung 3 holds φ at θ̄0 and ψ̇ at first order: it misses also ψ̇ (t - t0) V(t)
    and ∫ g2.

    Computed at the theory's ε̄0 on the φ grid of :func:`second_order_coefficients` (P2 holds harmonics up to
    ±4φ, g3 up to ±6φ, which 8 samples resolve) and on an even grid of M starting at the pole epoch's
    ``mean_anomaly0`` (4 samples per harmonic of the nutation, a power of two, for the FFT that integrates over
    M: the products of two series hold harmonics up to twice theirs; 8 per harmonic change P2 and g3 by < 4e-15 of
    their size at e = 0.3-0.95). ``periodic``: P2 (:class:`PhasedSeries`); ``rephasing``: V + ∂P2/∂φ, what turning the mean pole by δφ
    changes in w + P2 per radian; ``third_order`` (2, 7): g3 as φ-harmonics
    up to ±6φ; ``start``: P2 at the pole epoch (M0, φ0 = θ̄0).
    """

    mean_anomaly0: float
    periodic: PhasedSeries
    rephasing: PhasedSeries
    third_order: np.ndarray
    first_order_rate: float     # (K/2) f(e), rad/day
    obliquity: float            # ε̄0
    start: np.ndarray

    def drift_harmonics(self) -> np.ndarray:
        """Rung 4's drift against the torque as φ-harmonics (2, 7) (rad/day; rows ψ, ε): g3 plus what its
        first-order mean obliquity changes in ψ̇, (K/2) f(e) sin ε̄0 P2_ε(t0)."""
        coef = self.third_order.copy()
        coef[0, 0] += self.first_order_rate * math.sin(self.obliquity) * self.start[1]
        return coef


def second_order_remainder(K: float, n: float, e: float, theory: SecondOrderTheory,
                           mean_anomaly0: float) -> Remainder:
    """The :class:`Remainder` of ``theory`` for torque scale K and mean motion n (rad/day), eccentricity e, on a
    grid of M starting at ``mean_anomaly0`` (the pole epoch's mean anomaly)."""
    comp = theory.components
    kmax = int(comp.multiple.max()) if comp.multiple.size else 1
    count = 1 << int(math.ceil(math.log2(max(512, 4 * kmax))))
    _, nu, rho, (a, b, c) = _quadrature(e, comp, count, mean_anomaly0, fft=True)
    f = _integrands(K, nu, rho, a, b, c)
    ce, se = math.cos(theory.obliquity), math.sin(theory.obliquity)
    rate = theory.first_order_rate
    cp, sp = f["cp"], f["sp"]
    v = np.stack([2.0 * ce * (sp * b - cp * c), -2.0 * se * (cp * b + sp * c)])              # (2, φ, M)
    psi_dot = rate * ce
    df_w = np.stack([ce * ce * f["i1"] + se * se * f["i2"], se * ce * f["i3"]])             # Df · w
    periodic = PhasedSeries.from_samples(df_w - psi_dot * v, mean_anomaly0, integrate_over=n)
    p2 = np.moveaxis(eval_phi(periodic.values[:, :, None, :], (math.pi / _PHI_SAMPLES) * np.arange(_PHI_SAMPLES)),
                     0, -1)                                                                  # (2, φ, M)
    # third order: <Df · P2 + ½ D²f(w, w)> at ε̄0, per φ sample
    h, c2l, s2l = f["half_k_rho"], f["c2l"], f["s2l"]
    dpsi, deps = ce * f["w_psi"], se * f["w_eps"]
    f_pp, f_pe = h * ce * 2.0 * s2l, -h * se * (1.0 - c2l)
    f_ep, f_ee = -h * se * 2.0 * c2l, -h * ce * s2l
    second_psi = 0.5 * (4.0 * h * ce * c2l * dpsi ** 2 - 4.0 * h * se * s2l * dpsi * deps
                        - h * ce * (1.0 - c2l) * deps ** 2)
    second_eps = 0.5 * (4.0 * h * se * s2l * dpsi ** 2 - 4.0 * h * ce * c2l * dpsi * deps + h * se * s2l * deps ** 2)
    g3 = np.stack([np.mean(f_pp * p2[0] + f_pe * p2[1] + second_psi, axis=-1),
                   np.mean(f_ep * p2[0] + f_ee * p2[1] + second_eps, axis=-1)])             # (2, φ)
    # ∂P2/∂φ on the φ grid: harmonic j of (c_j cos 2jφ + s_j sin 2jφ) turns into 2j (s_j cos 2jφ - c_j sin 2jφ)
    d_phi = np.zeros_like(periodic.values)
    for j in (1, 2):
        d_phi[..., 2 * j - 1], d_phi[..., 2 * j] = 2 * j * periodic.values[..., 2 * j], -2 * j * periodic.values[..., 2 * j - 1]
    d_phi = np.moveaxis(eval_phi(d_phi[:, :, None, :], (math.pi / _PHI_SAMPLES) * np.arange(_PHI_SAMPLES)), 0, -1)
    return Remainder(float(mean_anomaly0), periodic, PhasedSeries.from_samples(v + d_phi, mean_anomaly0),
                     _phi_harmonics(g3, degree=3), rate, theory.obliquity,
                     eval_phi(periodic.values[0], theory.equinox_to_pericentre))
