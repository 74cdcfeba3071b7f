"""The single-perturber family: the fidelity ladder behind the common interface.

:class:`SunLadder`: the fidelity ladder (:class:`~ephem.sun.ladder.Ladder`) behind
the common interface of :mod:`ephem.theory.interface`, a body torqued by the centre of its orbit alone."""
from __future__ import annotations

import math
import time
from dataclasses import replace
from functools import cached_property

import numpy as np

from ..base.budget import charge
from ..base.memo import bytes_bounded
from ..base.constants import ARCSEC, JULIAN_YEAR_DAYS, MAS
from ..base.errors import InvalidInputError, NotApplicableError
from ..bodies.catalogue import Body, is_centre_alone
from ..forced import interior_response
from ..forced.describe import ASSUMPTIONS, model_info
from ..forced.kinoshita import eccentricity_factor, exact_series_floor, pole_displacement_sum
from ..forced.precession_nutation import MAX_ORDER, Track, cached_model, check_domain, model_for
from ..forced.catalogue_sigmas import input_sigmas
from ..forced.uncertainty import propagated, summary
from ..longterm.averaged_spin import SpinConstants, spin_constants
from ..orbit.hansen import LAPLACE_LIMIT
from ..orbit.relativity import geodesic_precession_rate
from ..theory import cost
from ..base.budget import Cost
from ..theory.choice import Candidates, cheapest
from ..theory.interface import Spectrum, SpectrumExport, SpinAxisTheory
from ..theory.requests import Epochs, ModelChoice
from ..theory.results import (COVERS_INTERIOR, COVERS_TRUNCATION, Estimate, NutationResult, NutationTerm, OBSERVABLE_RATE,
                              PrecessionResult, RateSigmas, Selection, selection)
from .bounds import truncation_bound
from .ladder import Ladder
from .rungs import RUNG_NAMES, RUNGS, rung_named
from .spectrum import mean_anomaly_spectrum, semi_amplitudes

def forced_model_info(m, b: Body) -> dict:
    """:func:`ephem.forced.describe.model_info` with what the exact or the truncated series (``m.order``) assumes."""
    return model_info(m, b, ASSUMPTIONS + list(rung_named("hansen" if m.order is None else "series").assumptions))


AXIS_ASSUMPTIONS = {
    "angular_momentum": "the pole served is the angular momentum, which the free wobble does not move",
    "figure": "the pole served is the figure axis, taken as the angular momentum: the free wobble is left "
              "out and counted in the estimate (free_wobble)",
    "figure+wobble": "the pole served is the figure axis: the torque-free rigid-body wobble (given J and phase) "
                     "added about the forced angular momentum",
    "forced_figure": "the pole served is the figure axis's forced motion (the analogue of the IERS's celestial "
                     "intermediate pole): its free wobble is left to polar motion, neither added nor counted as an "
                     "error",
}


class SunLadder(SpinAxisTheory, SpectrumExport):
    """The single-perturber ladder (:class:`Ladder`) behind the common interface: a body torqued by the
    centre of its orbit alone, its rungs cheapest first."""

    summary = "the single-perturber ladder (a body torqued by the centre of its orbit)"
    models = RUNG_NAMES
    descriptions = {rung.name: rung.description for rung in RUNGS}
    propagates_uncertainty = True
    models_rotation_scale = True

    @classmethod
    def serves(cls, body: Body, perturbers: tuple[str, ...]) -> bool:
        return is_centre_alone(body, perturbers)

    @cached_property
    def ladder(self) -> Ladder:
        return Ladder(self.body, self.axis, self.wobble, self.rotation_phase,   # one per request
                      counts_free_wobble=self.counts_free_wobble)

    @classmethod
    def how_to_reach(cls, body: Body) -> str:
        return f"pass perturbers={body.orbit.center.lower()} for it (the centre of {body.name}'s orbit alone)"

    def default_model(self, choice: ModelChoice) -> str:
        return "hansen" if choice.order is None else "series"

    def check_request(self, choice: ModelChoice) -> None:
        rung, order = self.resolved(choice).model, choice.order
        if rung == "series" and order is None:
            raise InvalidInputError("order", "the 'series' model needs an e-order")
        if order is not None and rung != "series":
            raise InvalidInputError("order", f"an e-order applies to the 'series' model, not to {rung!r}")
        if order is not None and self.body.orbit.e > LAPLACE_LIMIT:
            model_for(self.body, self.body.dataset, order)     # refuses the diverging series, before any cost

    def choice_cost(self, start: float, stop: float, count: int) -> Cost:
        return self.ladder.cost(None, start, stop, count, free_wobble=self.wobble is not None)

    def track_cost(self, choice, start, stop, count) -> Cost:
        return self.ladder.cost(self.resolved(choice).model, start, stop, count, choice.order, choice.free_wobble,
                                choice.rotation_scale)

    def estimates(self, jd_tdb) -> list[Estimate]:
        return self.ladder.estimates(jd_tdb)

    def plan_costs(self, plan, start, stop, count) -> list:
        """Every rung and variant priced at once (:meth:`Ladder.plan_costs`: one look-up for a question asked
        before)."""
        return self.ladder.plan_costs(plan, start, stop, count)

    def named(self, jd_tdb, choice):
        rung, order = self.resolved(choice).model, choice.order
        # a named rung adds the rotation-scale terms when the request gave the rotation phase
        scale = None if self.rotation_phase is None else self.ladder.rotation_modelled
        return next((e for e in self.estimates(jd_tdb) if e.rung == rung and e.order == order
                     and e.free_wobble == (self.wobble is not None) and e.rotation_scale == scale), None)

    def track(self, choice: ModelChoice, epochs: Epochs) -> Track:
        model, order = self.resolved(choice).model, choice.order
        if epochs.is_grid and model in ("hansen", "series") and not choice.rotation_scale:
            tr = cached_model(self.body, order).track_grid(epochs.start, epochs.step, epochs.count)  # the fast path
        else:
            tr = self.ladder.track(model, epochs.jd_tdb, order, rotation_scale=choice.rotation_scale)
        if self.adds_wobble(choice):
            tr = self.ladder.add_wobble(tr)
        return tr

    def describe(self, choice: ModelChoice) -> dict:
        info = forced_model_info(cached_model(self.body, choice.order), self.body)
        axis = "figure+wobble" if self.adds_wobble(choice) else self.requested_axis
        info["assumptions"] = [AXIS_ASSUMPTIONS[axis]] + ASSUMPTIONS[1:] \
            + list(rung_named(self.resolved(choice).model).assumptions)
        return info

    def secular_spin(self) -> SpinConstants:
        """The first-order theory's mean pole and precession constant (K/2) f(e) (Petit et al. eq. 25), kept per
        body (:func:`cached_secular_spin`)."""
        return cached_secular_spin(self.body)

    def spectrum(self, aim_mas: float, mid_centuries: float, jd_tdb=None, psi=None) -> Spectrum:
        m = cached_model(self.body)
        if jd_tdb is None:
            return mean_anomaly_spectrum(m, aim_mas, m.track_rate)
        # ψ̇ as the track has it (the rungs above 'hansen' change the mean rates): ψ = a + ψ̇ t + nutation
        t = np.asarray(jd_tdb, dtype=float)
        mt = m.mean_anomaly(t)
        cols = [np.ones_like(t), t - 0.5 * (t[0] + t[-1])]
        for k in np.unique(m.nutation.multiple):
            cols += [np.sin(k * mt), np.cos(k * mt)]
        psi_dot = float(np.linalg.lstsq(np.array(cols).T, np.asarray(psi, dtype=float), rcond=None)[0][1])
        return mean_anomaly_spectrum(m, aim_mas, psi_dot)

    # --- the precession and nutation answers

    def answer_cost(self, order: int | None, nutation: bool = False, tolerance: bool = False) -> Cost:
        """The body's models (while the process does not keep them), the nutation's extremes, and the propagation
        of the inputs' σ (once per body and order: kept); ``tolerance``: the truncation bounds of the e-orders."""
        b = self.body
        check_domain(b, order)                   # not applicable (too slow a rotation, e -> 1): before any cost
        e = b.orbit.e
        if order is not None and e > LAPLACE_LIMIT:
            return cost.FREE      # refused by model_for before any work
        parts = [cost.hansen_build(e, o) for o in ((None,) if order is None else (None, order))
                 if not cached_model.cached(b, o)]
        if nutation:
            parts.append(cost.half_peak_to_peak(e, order, cost.body_harmonics(b, order)))
        if tolerance:
            parts.append(cost.truncation_bounds(e))
        with_sigma = sum(1 for v in input_sigmas(b).values() if v is not None)
        if with_sigma and not propagated.cached(b, order):
            parts.append(cost.propagation(with_sigma))
        return Cost(tuple(parts))

    def order_candidates(self) -> Candidates:
        """The e-orders a tolerance may choose for the rate and the nutation terms, priced by their e-power (the
        series' order: the lower, the simpler the answer's series; its CPU hardly differs, the exact coefficients
        being built for the floor anyway) and bounded by their truncation alone (no time span; radians); the exact
        coefficients (None) last, at no truncation. Past the Laplace limit the exact ones alone."""
        m = cached_model(self.body)
        orders: list[int | None] = []
        if m.eccentricity < LAPLACE_LIMIT:
            kmax = int(m.nutation.multiple.max()) if m.nutation.multiple.size else 0
            orders = list(range(0, min(kmax, MAX_ORDER)))
        return Candidates(orders + [None], [float(n) for n in orders] + [math.inf],
                          lambda i: 0.0 if i == len(orders) else truncation_bound(m, orders[i], 0.0),
                          tie=0.0, what="e-order")

    def order_for_tolerance(self, tolerance: float | None, order: int | None) -> int | None:
        """The e-order a tolerance chooses (:func:`ephem.theory.choice.cheapest` of :meth:`order_candidates`: the
        lowest whose truncation bound is within it; None: the exact coefficients, whose floor the selection checks)."""
        if tolerance is None:
            return order
        if order is not None:
            raise InvalidInputError("order", "give either order or tolerance_mas, not both")
        return cheapest(self.order_candidates(), tolerance)

    def _selection(self, order: int | None, tol: float | None, start: float, interior=None) -> Selection:
        m = cached_model(self.body)
        # never 0 (issue 29): the exact coefficients' own floor, the harmonics dropped under their amplitude cut
        # (twice: they also move the mean pole) and the rounding of every coefficient kept, is part of both
        floor = exact_series_floor(m.nutation.dropped, pole_displacement_sum(m.nutation, m.obliquity))
        truncation = floor + (0.0 if order is None else truncation_bound(m, order, 0.0))
        terms = None
        if interior is not None:    # what the interior's parameters and its left-out mantle can move
            terms = {"truncation": truncation,
                     "interior_parameters": interior_response.parameter_bound(m.nutation, m.obliquity, interior),
                     "interior_mantle": interior_response.mantle_bound(m.nutation, m.obliquity, interior,
                                                                       m.spin_rate)}
        estimate = truncation if terms is None else sum(terms.values())
        if tol is not None and estimate > tol:
            raise NotApplicableError(self.body.name, (
                f"no e-order meets the tolerance of {tol / MAS:.6g} mas: the exact Hansen coefficients are good to "
                f"{truncation / MAS:.3g} mas (the harmonics under their amplitude cut and the coefficients' rounding)"
                + ("" if terms is None else f", and with the core to {estimate / MAS:.3g} mas (its parameters' "
                   "2 sigma and the mantle)")))
        chosen = selection(self, "hansen" if order is None else "series", order, estimate,
                           1e3 * (time.perf_counter() - start), tol, terms,
                           covers=COVERS_TRUNCATION if terms is None else COVERS_INTERIOR)
        if interior is None:
            return chosen
        return replace(chosen, name="nonrigid", description=(
            f"{chosen.description}, with the body's liquid core: each circular component times its interior "
            "model's transfer function (data/interiors.toml)"))

    def precession(self, order: int | None, tolerance: float | None, start: float) -> PrecessionResult:
        b = self.body
        charge(self.answer_cost(order, tolerance=tolerance is not None), b.name)
        order = self.order_for_tolerance(tolerance, order)
        m = model_for(b, b.dataset, order)
        unc = propagated(b, order)
        info = forced_model_info(m, b)
        info["assumptions"].append(OBSERVABLE_RATE)
        o = b.orbit
        return PrecessionResult(b, m.obliquity, m.hd, m.scaling_factor, m.precession_rate, rate_sigmas(unc),
                                summary(unc), info, self._selection(order, tolerance, start),
                                geodesic_rate=geodesic_precession_rate(o.a_au, o.e, o.center))

    def nutation(self, order: int | None, tolerance: float | None, cut_mas, start: float,
                 nonrigid: bool = False) -> NutationResult:
        b = self.body
        if cut_mas is not None:
            raise InvalidInputError("cut_mas", "an amplitude cut applies to the lunisolar series (the Earth with the "
                                    "Moon); this series is truncated by e-order (order, tolerance_mas)", b.name)
        interior = self._interior(nonrigid)
        charge(self.answer_cost(order, nutation=True, tolerance=tolerance is not None), b.name)
        order = self.order_for_tolerance(tolerance, order)
        m = model_for(b, b.dataset, order)
        rigid = m.nutation
        s = rigid if interior is None else interior_response.nonrigid_series(rigid, m.obliquity, interior)
        core = None if interior is None else interior_response.term_sigmas(rigid, m.obliquity, interior)
        unc = propagated(b, order)
        terms = []
        for j, (k, p, a, c, d, f, sigma) in enumerate(zip(s.multiple, s.period_days, s.lon_sin, s.lon_cos,
                                                           s.obl_sin, s.obl_cos, unc["terms"])):
            if sigma["multiple"] != k:  # pragma: no cover - both come from the same series
                raise RuntimeError("uncertainty terms out of step with the nutation terms")
            sigmas = [_radians(sigma[f"{comp}_{part}_arcsec_uncertainty"]) for comp in ("longitude", "obliquity")
                      for part in ("sin", "cos")]
            sigmas += [_radians(sigma["amplitude_longitude_arcsec_uncertainty"]),
                       _radians(sigma["amplitude_obliquity_arcsec_uncertainty"])]
            if core is not None:    # the core's parameters' σ, independent of the inputs'
                sigmas = [None if x is None else math.hypot(x, float(core[i, j])) for i, x in enumerate(sigmas)]
            terms.append(NutationTerm(int(k), None, float(p), float(a), float(c), float(d), float(f),
                                      sigma["period_days_uncertainty"], *sigmas))
        # the selection's cost_ms is measured here, after the terms and their 1σ, as the answer is ready
        chosen = self._selection(order, tolerance, start, interior)
        info = forced_model_info(m, b)
        if interior is not None:
            info["assumptions"] += list(rung_named("nonrigid").assumptions[2:]) + [
                "nonrigid terms: each harmonic kM's prograde circular component times T(+k n), its retrograde one "
                "times T(-k n); each 1-sigma combines the inputs' (rigid) with the core parameters' (linear; near "
                "the resonance an order of magnitude)"]
        return NutationResult(
            b, "mean anomaly M", m.mean_anomaly_at_epoch, m.orbit_epoch, m.mean_motion, m.obliquity, tuple(terms),
            abs(math.sin(m.obliquity)), semi_amplitudes(b, m.order) if interior is None else s.semi_peak_to_peak(),
            (_radians(unc["delta_psi_half_peak_to_peak_arcsec_uncertainty"]),
             _radians(unc["delta_epsilon_half_peak_to_peak_arcsec_uncertainty"])),
            summary(unc), info, chosen)

    def _interior(self, nonrigid: bool):
        """The fluid core the non-rigid terms apply (None for the rigid answer); refused for a rigid body."""
        if not nonrigid:
            return None
        why = interior_response.not_applicable(self.body)
        if why is not None:
            raise NotApplicableError(self.body.name, f"non-rigid terms do not apply: {why}")
        return interior_response.fluid_core(self.body)


def _radians(arcsec: float | None) -> float | None:
    return None if arcsec is None else arcsec * ARCSEC


def rate_sigmas(unc: dict) -> RateSigmas:
    """The precession answer's 1σ from :func:`ephem.forced.uncertainty.propagated` (which gives them in the
    answer's units), in radians and rad/day."""
    per_day = ARCSEC / JULIAN_YEAR_DAYS
    obliquity, k, rate = (unc["obliquity_deg_uncertainty"], unc["scaling_factor_arcsec_per_year_uncertainty"],
                          unc["precession_rate_arcsec_per_year_uncertainty"])
    return RateSigmas(None if obliquity is None else math.radians(obliquity), unc["dynamical_ellipticity_uncertainty"],
                      None if k is None else k * per_day, None if rate is None else rate * per_day)


@bytes_bounded      # a pure function of the body; its nutation's extremes take ~0.5 ms, and a long-term track asks 3 times
def cached_secular_spin(body: Body) -> SpinConstants:
    """:meth:`SunLadder.secular_spin` of ``body``: the first-order model's mean pole, its precession constant and the
    half amplitude of its nutation (the long-term model's inputs)."""
    m = cached_model(body)
    half_psi, half_eps = m.nutation.semi_peak_to_peak()
    return spin_constants(body, m.pole_epoch, m.icrf_from_orbit, m.obliquity,
                          0.5 * m.scaling_factor * eccentricity_factor(m.eccentricity), 0.0,
                          math.hypot(half_psi * math.sin(m.obliquity), half_eps),
                          "Kinoshita's first-order theory (Petit et al. 2014 eq. 25): the precession constant "
                          "(K/2)(1 - e^2)^(-3/2), K = 3 n^2 H_d / omega")
