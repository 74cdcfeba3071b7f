"""Second order in the torque: the equinox drifts under the precession, and the nutation feeds back.

The first-order theory (:mod:`ephem.kinoshita`) holds the equinox fixed: the
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
ẋ = f(x, M) the rotation-averaged equations of :mod:`ephem.kinoshita` and
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
third-order drift; it is estimated in :mod:`ephem.ladder`.

Measured against the numerical integration of the averaged torque (rung 5),
over 20 years: Vesta 6.7 → 0.21 mas, Eros 176 → 5.3 mas, Itokawa 252 → 3.7 mas;
over 200 years Itokawa 2435 → 3.9 mas.

Radians, days, rad/day.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .kepler import solve_kepler, true_anomaly
from .kinoshita import NutationComponents, eccentricity_factor, nutation_components

#: Samples of φ over its period π: the G's hold harmonics 0, ±2φ, ±4φ, which 8 samples resolve.
_PHI_SAMPLES = 8


def _phi_harmonics(values: np.ndarray) -> np.ndarray:
    """Real coefficients (c0, c1, s1, c2, s2) of Σ c_j cos 2jφ + s_j sin 2jφ from samples on the φ grid."""
    spec = np.fft.rfft(values, axis=-1) / _PHI_SAMPLES
    return np.stack([spec[..., 0].real, 2 * spec[..., 1].real, -2 * spec[..., 1].imag,
                     2 * spec[..., 2].real, -2 * spec[..., 2].imag], axis=-1)


def _eval_phi(coef: np.ndarray, phi):
    c2, s2 = np.cos(2.0 * phi), np.sin(2.0 * phi)
    c4, s4 = c2 * c2 - s2 * s2, 2.0 * s2 * c2
    return coef[..., 0] + coef[..., 1] * c2 + coef[..., 2] * s2 + coef[..., 3] * c4 + coef[..., 4] * s4


def second_order_coefficients(K: float, e: float, components: NutationComponents) -> np.ndarray:
    """Harmonics in φ of G1, G2, G3 (rad/day): array (3, 5) of (c0, c1, s1, c2, s2).

    Quadrature of <Df · w> over M on an even grid (the trapezoidal rule, spectrally
    accurate for periodic integrands) with enough points to resolve every harmonic
    of (a/r)^3 e^{2iν} and of the nutation.
    """
    kmax = int(components.multiple.max()) if components.multiple.size else 1
    count = max(512, 8 * kmax)
    m = 2.0 * math.pi * np.arange(count) / count
    nu = true_anomaly(m, e)
    rho = (1.0 / (1.0 - e * np.cos(solve_kepler(m, e)))) ** 3
    a, b, c = components.evaluate(m)
    phi = (math.pi / _PHI_SAMPLES) * np.arange(_PHI_SAMPLES)[:, None]
    lam2 = 2.0 * (phi + nu)
    c2l, s2l = np.cos(lam2), np.sin(lam2)
    cp, sp = np.cos(2.0 * phi), np.sin(2.0 * phi)
    w_psi = a - cp * b - sp * c          # Δψ = cos ε w_psi
    w_eps = cp * c - sp * b              # Δε = sin ε w_eps
    half_k_rho = 0.5 * K * rho
    g1 = np.mean(half_k_rho * 2.0 * s2l * w_psi, axis=1)                 # ∂f_ψ/∂ψ Δψ / cos²ε
    g2 = np.mean(-half_k_rho * (1.0 - c2l) * w_eps, axis=1)             # ∂f_ψ/∂ε Δε / sin²ε
    g3 = np.mean(-half_k_rho * (2.0 * c2l * w_psi + s2l * w_eps), axis=1)  # (∂f_ε/∂ψ Δψ + ∂f_ε/∂ε Δε) / (sin ε cos ε)
    return _phi_harmonics(np.stack([g1, g2, g3]))


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
    plus the second-order mean rates. Built from a :class:`~ephem.model.PrecessionNutation`."""

    components: NutationComponents
    coefficients: np.ndarray      # (3, 5), see second_order_coefficients
    first_order_rate: float       # (K/2)(1-e²)^(-3/2), rad/day: ψ̇ = this × cos ε̄
    equinox_to_pericentre: float  # θ̄0 at the pole epoch
    obliquity: float              # ε̄0
    pole_epoch: float

    def mean_rates(self, psi_bar, eps_bar):
        """dψ̄/dt and dε̄/dt (rad/day), first plus second order."""
        g = _eval_phi(self.coefficients, np.asarray(self.equinox_to_pericentre + psi_bar)[..., None])
        ce, se = np.cos(eps_bar), np.sin(eps_bar)
        return (self.first_order_rate * ce + ce * ce * g[..., 0] + se * se * g[..., 1],
                se * ce * g[..., 2])

    def second_order_rate_bound(self) -> float:
        """Upper bound (rad/day) on the pole's speed from the second-order mean rates at ε̄0."""
        phi = np.linspace(0.0, math.pi, 64, endpoint=False)
        ce, se = math.cos(self.obliquity), math.sin(self.obliquity)
        g = _eval_phi(self.coefficients, phi[:, None])
        speed = np.abs(se * (ce * ce * g[:, 0] + se * se * g[:, 1])) + np.abs(se * ce * g[:, 2])
        # the grid misses the peak of a degree-2 polynomial in 2φ by at most (1 - cos(2π/64))
        return float(speed.max()) * 1.01

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
    """Rung 4 for a first-order ``model`` (:class:`~ephem.model.PrecessionNutation`)."""
    comp = nutation_components(model.scaling_factor, model.mean_motion, model.eccentricity, order)
    coef = second_order_coefficients(model.scaling_factor, model.eccentricity, comp)
    rate = 0.5 * model.scaling_factor * eccentricity_factor(model.eccentricity, order)
    return SecondOrderTheory(comp, coef, rate, model.equinox_to_pericentre, model.obliquity, model.pole_epoch)
