"""The pole's 1-σ along a track, propagated from the catalogue's 1-σ uncertainties.

Radians: the RMS angle between the
served and the true pole at each epoch).

The inputs, their steps and correlations are those of :mod:`ephem.forced.uncertainty` (its docstring says which
inputs and why): each input with a σ is stepped by :data:`~ephem.forced.uncertainty.STEP_FRACTION` of it both ways,
the 2m first-order models are built once per body and order (:func:`cached_pole_sensitivity`), and a request
evaluates their tracks together at its epochs (:meth:`PoleSensitivity.sigma`); the σ of a track's epochs is kept
per body, order and epochs (:func:`_cached_sigma`), so the same track asked again does not evaluate them again.
"""
from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..base.errors import NotApplicableError
from ..base.memo import bytes_bounded, epochs_digest
from ..bodies.catalogue import Body
from .catalogue_sigmas import CatalogueInput, catalogue_inputs, correlation_matrix
from .precession_nutation import build_model
from .uncertainty import difference_step

def _perturbed_body(b: Body, inputs: list[CatalogueInput], x: np.ndarray) -> Body:
    """``b`` with its inputs set to ``x`` (model units, in the order of ``inputs``)."""
    v = {i.key: float(xi) for i, xi in zip(inputs, x)}
    if "pole.lon" in v:
        raise NotApplicableError(b.name, "the pole's uncertainty along a track is propagated for poles given in "
                                 "RA and Dec only")
    orbit = dataclasses.replace(b.orbit, a_au=v["orbit.a"], e=v["orbit.e"], i_deg=v["orbit.i"],
                                node_deg=v["orbit.node"], peri_deg=v["orbit.peri"],
                                mean_anomaly_deg=v["orbit.mean_anomaly"])
    pole = dataclasses.replace(b.pole, ra_deg=v["pole.ra"], dec_deg=v["pole.dec"])
    if "inertia.dynamical_ellipticity" in v:
        inertia = {"dynamical_ellipticity": v["inertia.dynamical_ellipticity"], "moments": None}
    else:
        inertia = {"moments": (v["inertia.A"], v["inertia.B"], v["inertia.C"]), "dynamical_ellipticity": None}
    return dataclasses.replace(b, orbit=orbit, pole=pole, rotation_period_hours=v["rotation.period"],
                               values={}, **inertia)


#: epochs per block of :meth:`PoleSensitivity.sigma`: its work arrays are (2 inputs, harmonics, epochs), ~2 MB a
#: block for the catalogue's (14 rows, ~20 harmonics)
_SIGMA_BLOCK = 1024


@dataclass(frozen=True)
class PoleSensitivity:
    """The first-order tracks of a body with each input with a σ stepped up and down by :data:`STEP_FRACTION` of its
    σ (:func:`pole_sensitivity`): their parameters stacked, rows ``2 j`` (+h) and ``2 j + 1`` (-h) for the j-th
    input, so that the pole's 1-σ at any epochs is one vectorised evaluation of the 2m tracks
    (:meth:`sigma`) instead of 2m models built per request.

    Each row is the track of :meth:`ephem.forced.precession_nutation.PrecessionNutation.angles` on the plain path:
    ψ = r (t - t0) + Δψ(M), ε = ε̄ + Δε(M), M = M0 + n (t - t_orbit), the pole R · (sin ε sin ψ, sin ε cos ψ,
    cos ε), with Δψ, Δε the model's own harmonics (padded with zeros to the union of the rows' multiples)."""

    steps: np.ndarray            # (m,) the central differences' 2h, model units
    covariance: np.ndarray       # (m, m) σ_i ρ_ij σ_j, model units
    rate: np.ndarray             # (2m,) the track's ψ̇, rad/day
    pole_epoch: np.ndarray       # (2m,) JD TDB
    obliquity: np.ndarray        # (2m,) ε̄, rad
    mean_anomaly: np.ndarray     # (2m,) M at ``orbit_epoch``, rad
    mean_motion: np.ndarray      # (2m,) rad/day
    orbit_epoch: np.ndarray      # (2m,) JD TDB
    multiple: np.ndarray         # (K,) the harmonics' k, increasing
    coefficients: np.ndarray     # (4, 2m, K): Δψ sin, Δψ cos, Δε sin, Δε cos (radians)
    frames: np.ndarray           # (2m, 3, 3) ICRF from the orbit frame

    @classmethod
    def of_models(cls, models: list, steps: np.ndarray, covariance: np.ndarray) -> "PoleSensitivity":
        multiple = np.unique(np.concatenate([m.nutation.multiple for m in models])).astype(float)
        coef = np.zeros((4, len(models), multiple.size))
        for row, m in enumerate(models):
            at = np.searchsorted(multiple, m.nutation.multiple)
            nut = m.nutation
            for c, values in enumerate((nut.lon_sin, nut.lon_cos, nut.obl_sin, nut.obl_cos)):
                coef[c, row, at] = values
        column = lambda f: np.array([f(m) for m in models], dtype=float)       # noqa: E731
        return cls(steps, covariance, column(lambda m: m.track_rate), column(lambda m: m.pole_epoch),
                   column(lambda m: m.obliquity), column(lambda m: m.mean_anomaly_at_epoch),
                   column(lambda m: m.mean_motion), column(lambda m: m.orbit_epoch), multiple, coef,
                   np.stack([m.icrf_from_orbit for m in models]))

    def poles(self, t: np.ndarray) -> np.ndarray:
        """The 2m tracks' ICRF pole vectors at the epochs ``t`` (1-D): (2m, epochs, 3), the harmonics summed at once
        over rows, multiples and epochs (sin and cos of k M, as the models' plain path takes them)."""
        m = self.mean_anomaly[:, None] + self.mean_motion[:, None] * (t[None, :] - self.orbit_epoch[:, None])
        km = self.multiple[None, :, None] * m[:, None, :]                               # (2m, K, epochs)
        sk, ck = np.sin(km), np.cos(km)
        lon_s, lon_c, obl_s, obl_c = self.coefficients
        dpsi = np.einsum("rk,rke->re", lon_s, sk) + np.einsum("rk,rke->re", lon_c, ck)
        deps = np.einsum("rk,rke->re", obl_s, sk) + np.einsum("rk,rke->re", obl_c, ck)
        psi = self.rate[:, None] * (t[None, :] - self.pole_epoch[:, None]) + dpsi
        eps = self.obliquity[:, None] + deps
        se = np.sin(eps)
        s = np.stack([se * np.sin(psi), se * np.cos(psi), np.cos(eps)], axis=-1)       # (2m, epochs, 3)
        return np.einsum("rij,rej->rei", self.frames, s)

    def sigma(self, jd_tdb) -> np.ndarray:
        """The pole's 1-σ (radians, the RMS angle) at the epochs: J Σ Jᵀ's trace per epoch, J the central
        differences of the pole vector (:func:`pole_uncertainty`)."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        if t.ndim != 1:
            raise ValueError("the epochs must be one-dimensional")
        out = np.empty(t.size)
        for lo in range(0, t.size, _SIGMA_BLOCK):
            v = self.poles(t[lo:lo + _SIGMA_BLOCK])
            jac = (v[0::2] - v[1::2]) / self.steps[:, None, None]          # (inputs, epochs, 3)
            out[lo:lo + _SIGMA_BLOCK] = np.sqrt(np.einsum("iea,ij,jea->e", jac, self.covariance, jac))
        return out


def pole_sensitivity(b: Body, order: int | None, uncertainties=None, correlations=None) -> PoleSensitivity | None:
    """The perturbed tracks behind :func:`pole_uncertainty` (None where no input has a σ): 2 models per input with
    a σ, built once per body, order and dataset by :func:`cached_pole_sensitivity` (~1 ms a model)."""
    inputs = catalogue_inputs(b, uncertainties)
    which = [j for j, i in enumerate(inputs) if i.sigma]
    if not which:
        return None
    x0 = np.array([i.value * i.factor for i in inputs])
    rho = correlation_matrix(inputs, correlations, b)
    models, steps = [], []
    for j in which:
        h = difference_step(inputs[j], x0[j])
        for sign in (1.0, -1.0):
            x = x0.copy()
            x[j] += sign * h
            models.append(build_model(_perturbed_body(b, inputs, x), order))
        steps.append(2.0 * h)
    s = np.array([inputs[j].sigma * inputs[j].factor for j in which])
    return PoleSensitivity.of_models(models, np.array(steps), s[:, None] * rho[np.ix_(which, which)] * s[None, :])


@bytes_bounded(key=lambda b, order=None: b.with_sigmas(order))     # the σ too: a body's equality leaves them out
def cached_pole_sensitivity(b: Body, order: int | None) -> PoleSensitivity | None:
    """:func:`pole_sensitivity` with the catalogue's σ and correlations, memoised per body and order in the
    byte-bounded per-body caches (:mod:`ephem.base.memo`: ~1 kB a harmonic and input)."""
    return pole_sensitivity(b, order)


def pole_uncertainty(b: Body, jd_tdb, order: int | None = None, *,
                     uncertainties: Mapping[str, float | None] | None = None,
                     correlations: Mapping[tuple[str, str], float] | None = None) -> np.ndarray | None:
    """The 1-σ of the angle between the served and the true pole (radians, the RMS of that angle) at each epoch
    of a first-order track (:meth:`ephem.forced.precession_nutation.PrecessionNutation.track`), from the inputs' 1-σ and correlations:
    the pole vector's derivatives by central differences (each input stepped by :data:`STEP_FRACTION` of its σ),
    its 3×3 covariance J Σ Jᵀ per epoch, σ² its trace (the pole is a unit vector: its errors lie across it).

    The stepped models are built once per body and order (:func:`cached_pole_sensitivity`, when the catalogue's σ
    and correlations are used) and evaluated together at the epochs (:meth:`PoleSensitivity.sigma`): a request
    pays for the evaluation alone, and up to :data:`SIGMA_MEMO_EPOCHS` epochs asked again (the same track) for a
    look-up (:func:`_cached_sigma`).

    It grows from the catalogue pole's own σ at the pole epoch as the precession rate's σ accumulates. None
    where no input has a σ (a user's body); the inputs without one do not count (their σ is unknown, not zero).
    ``b``: the body (its dataset with it).
    """
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    if uncertainties is None and correlations is None:
        if t.ndim == 1 and t.size <= SIGMA_MEMO_EPOCHS:
            sigma = _cached_sigma(b, order, t)
            return None if sigma is None else sigma.copy()      # the caller's own: the kept one stays as computed
        sens = cached_pole_sensitivity(b, order)
    else:
        sens = pole_sensitivity(b, order, uncertainties, correlations)
    return None if sens is None else sens.sigma(t)


#: the most epochs whose σ :func:`pole_uncertainty` keeps (:func:`_cached_sigma`): 32 kB an entry at most, where the
#: evaluation (~0.1 ms for a few dozen epochs, numpy's per-call overhead) is a warm small track's largest part
SIGMA_MEMO_EPOCHS = 4096


@bytes_bounded(key=lambda b, order, t: b.with_sigmas(order, epochs_digest(t)))
def _cached_sigma(b: Body, order: int | None, t: np.ndarray) -> np.ndarray | None:
    """The pole's 1-σ at the epochs ``t`` with the catalogue's σ and correlations (:meth:`PoleSensitivity.sigma`):
    a pure function of the body (its dataset with it), the order and the epochs, kept per body, order and the epochs'
    digest in the byte-bounded caches (:mod:`ephem.base.memo`, 8 bytes an epoch weighed), so that the same track asked
    again (the same grid) looks its σ up instead of evaluating the 2m stepped tracks again."""
    sens = cached_pole_sensitivity(b, order)
    return None if sens is None else sens.sigma(t)
