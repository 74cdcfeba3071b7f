"""The Earth's family behind the common interface (:class:`LunisolarTheory`): the Earth under the Moon and the Sun.

One model, ``lunisolar``: Kinoshita's first-order rigid-Earth theory with the series of
:mod:`ephem.earth.lunisolar` (the precession rate and the nutation in the Delaunay arguments l, l′, F, D, Ω, with
the body's H_d and spin rate), wired to the catalogue's pole and orbit in :mod:`ephem.earth.model`, its track's
error estimate against the real Earth in :mod:`ephem.earth.estimates`. Here: the family's texts, its costs, its
precession and nutation results with their 1σ (H_d's, the one input with a published σ), the spectrum the
kernel writer fits, the secular spin for histories. Radians and days unless a name says otherwise.
"""
from __future__ import annotations

import hashlib
import math
import time
from dataclasses import replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..theory import cost
from ..base.budget import Cost, charge
from ..base.disk_cache import cached_arrays, fingerprint
from ..bodies.catalogue import Body, is_lunisolar
from ..base.constants import ARCSEC, J2000_JD, JULIAN_YEAR_DAYS, MAS
from ..base.constants import JULIAN_CENTURY_DAYS as DAYS_PER_CENTURY
from ..base.errors import InvalidInputError, NotApplicableError
from ..orbit.kepler import mean_motion_rad_per_day
from ..forced.kinoshita import eccentricity_factor, pole_displacements, scaling_factor
from ..forced.describe import model_info
from ..orbit.lunar import delaunay_arguments, delaunay_rates, lunisolar_data
from ..forced.precession_nutation import Track, cached_model, model_for
from ..longterm.averaged_spin import SpinConstants, spin_constants
from ..theory.interface import SpectrumExport, SpinAxisTheory, Spectrum
from ..theory.requests import Epochs, ModelChoice
from ..theory.results import (COVERS_INTERIOR, COVERS_NOTHING_TRUNCATED, COVERS_TRUNCATION, Estimate, NutationResult, NutationTerm,
                              OBSERVABLE_RATE, PrecessionResult, RateSigmas, selection)
from ..forced.catalogue_sigmas import dynamical_ellipticity_sigma, no_uncertainty_reasons
from ..forced.uncertainty import SCALAR_KEYS
from ..base.units import in_unit
from ..orbit.lunar import check_cut
from . import costs
from .model import LunisolarEarth, TRACK_CUT_MAS, TRACK_SIDEBANDS, lunisolar_earth, tidal_constant_drift
from .estimates import add_wobble, cut_for_tolerance, estimates, nonrigid_earth, omitted_bound, window
from .model import NonRigidEarth, residual_envelope
from .nonrigid import non_rigid_series


ARGUMENT = "Delaunay arguments l, l′, F, D, Ω (IERS 2010 eq. 5.43)"
THEORY = ("Kinoshita (1977) lunisolar precession-nutation, first order, rigid Earth (ephem.earth.lunisolar): the Moon "
          "(Meeus 1998 / ELP-2000/82) and the Sun (Simon et al. 1994) on their moving mean orbits, nutation "
          "in the Delaunay arguments l, l′, F, D, Ω")
DESCRIPTION = ("Kinoshita's first-order rigid-Earth theory under the Moon and the Sun: ψ = ψ̇ (t − t0) + Δψ, "
               "ε = ε̄ + Δε with the lunisolar series (amplitude cut 0.1 mas)")
#: the answer's ``model.description``
SELECTION_DESCRIPTION = ("Kinoshita's first-order rigid-Earth theory under the Moon and the Sun (ephem.earth.lunisolar): "
                         "precession rate and nutation in the Delaunay arguments, amplitude cut 0.1 mas (ephem.earth.family)")
ASSUMPTIONS = [
    "rigid Earth: IAU 2000A (non-rigid, MHB2000) differs term by term by up to 77 mas (18.6-yr term in "
    "longitude) and 40 mas (semi-annual): the published non-rigid correction of each term (IERS 1996 "
    "transfer function, ephem.earth.nonrigid) accounts for it to 0.12 mas on terms of a year or shorter and 2.6 mas "
    "on the 18.6-yr term; see docs/earth.md",
    "first order in the torque; rotation-averaged degree-2 potential; no planetary or second-order "
    "contributions to the precession (the geodesic precession, relativistic, is added to the track)",
    "the Moon's orbit from Meeus (1998) ch. 47 (ELP-2000/82 truncated), the Sun on the Earth-Moon barycentre's "
    "mean Kepler ellipse (Simon et al. 1994); GM of both from DE421",
    "the track turns about the catalogue orbit's normal at fixed mean obliquity (the ecliptic's own motion "
    "is in the error estimate, not in the track)",
]
NONRIGID_THEORY = ("IAU 2006 precession (P03, erfa.pfw06) with our lunisolar nutation times the IERS 1996 transfer "
                   "function of the non-rigid Earth (ephem.earth.model.NonRigidEarth)")
#: the non-rigid rung's ``model.description``
NONRIGID_DESCRIPTION = ("the non-rigid Earth: Kinoshita's lunisolar nutation (amplitude cut 0.1 mas) with the "
                        "precession-nutation coupling, every circular component times the IERS 1996 transfer function "
                        "(elastic mantle, fluid core, oceans), on the IAU 2006 precession and the ecliptic of date "
                        "(ephem.earth.model.NonRigidEarth)")
NONRIGID_ASSUMPTIONS = [
    "non-rigid Earth: the IERS 1996 transfer function (Mathews et al. 1991's resonance form, KSV_1996_3's "
    "coefficients) multiplies every circular nutation component (ephem.earth.nonrigid)",
    "left out and in the estimate's nutation_residual (measured against erfa.nut00a over 1900-2100): MHB2000's "
    "anelastic and ocean corrections beyond the 1996 transfer function, the planetary nutation, the terms under "
    "0.1 mas; the free core nutation's free mode, which IAU 2000A leaves out too, is in iau_reference",
    "precession: IAU 2006 (P03, Capitaine et al. 2003) through ERFA's Fukushima-Williams angles, frame bias "
    "included, the geodesic precession in it; the nutation applied on the ecliptic and equinox of date as IAU "
    "2000A's is; the rung serves IAU 2006's pole, not the body's (refused for a pole 1 arcsec or more from it)",
    "TT taken for TDB in ERFA's arguments (they differ by under 2 ms)",
]
AXIS_ASSUMPTIONS = {
    "figure": "the pole served is the figure axis's forced motion (Oppolzer terms included: the analogue of "
              "the IAU's CIP); the free wobble is left out and counted in the estimate (free_wobble)",
    "figure+wobble": "the pole served is the figure axis: the forced motion (Oppolzer terms included) plus the "
                     "torque-free rigid-body wobble (given J and phase)",
    "angular_momentum": "the pole served is the angular momentum (the series without the Oppolzer terms), "
                        "which the free wobble does not move",
    "forced_figure": "the pole served is the figure axis's forced motion (Oppolzer terms included), as the IAU's "
                     "CIP: the free wobble is polar motion, neither added nor counted as an error",
}

# ----------------------------------------------------------------------------- the theory's interface (ephem.theory.interface)

def describe_model(b: Body, per: tuple[str, ...], lm) -> dict:
    """``model`` of a lunisolar answer: model_info's keys (the spin-orbit ratio and epochs are the Earth's
    about the Sun) with the lunisolar theory, its assumptions and the H_d it used, and why."""
    info = model_info(cached_model(b), b, list(ASSUMPTIONS))
    rate = lm.precession_rate * JULIAN_YEAR_DAYS / ARCSEC
    track = lm.track_rate * JULIAN_YEAR_DAYS / ARCSEC
    iau = lunisolar_data()["precession_reference"]["psi_a_rate_arcsec_per_century"] / 100.0
    given = b.values.get("inertia.dynamical_ellipticity")
    if b.hd_from == "dynamical_ellipticity":
        src = f"the catalogue's explicit dynamical ellipticity (source {given.source})" if given is not None \
            else "the body's explicit dynamical ellipticity"
    else:
        src = "the catalogue's moments of inertia"
    info["theory"] = THEORY
    info["eccentricity_order"] = None
    info["assumptions"] = list(ASSUMPTIONS) + [
        f"H_d = {lm.hd:.10g} from {src}",
        f"precession rate {rate:.6f}″/yr of the torque; the track adds the geodesic precession "
        f"({track - rate:+.6f}″/yr, ephem.orbit.relativity): {track:.6f}″/yr against IAU 2006's ψ_A rate {iau:.6f}″/yr "
        f"({track - iau:+.4f}″/yr: P03's second-order and planetary contributions, not in a first-order theory; "
        "docs/earth.md)"]
    info["perturbers"] = list(per)
    return info


class LunisolarTheory(SpinAxisTheory, SpectrumExport):
    """The Earth under the Moon and the Sun (:func:`lunisolar_earth`) behind the common interface: one
    model, ``lunisolar``, whose track is the series at the served amplitude cut."""

    summary = "the Earth's lunisolar theory (the Earth under the Moon and the Sun)"
    models = ("lunisolar", "nonrigid")
    descriptions = {"lunisolar": SELECTION_DESCRIPTION, "nonrigid": NONRIGID_DESCRIPTION}
    track_cut_mas = TRACK_CUT_MAS

    @classmethod
    def serves(cls, body: Body, perturbers: tuple[str, ...]) -> bool:
        return is_lunisolar(body, perturbers)

    @property
    def model(self) -> LunisolarEarth:
        return lunisolar_earth(self.body, self.axis, TRACK_CUT_MAS, self.perturbers)

    @property
    def nonrigid(self) -> NonRigidEarth:
        return nonrigid_earth(self.body, self.axis, self.perturbers)

    def _model_named(self, choice: ModelChoice):
        return self.nonrigid if choice.model == "nonrigid" else self.model

    @classmethod
    def how_to_reach(cls, body: Body) -> str:
        return "it models the Earth with the Moon among the perturbers (perturbers=moon,sun, the Earth's default)"

    def default_model(self, choice: ModelChoice) -> str:
        return "lunisolar"

    def check_request(self, choice: ModelChoice) -> None:
        model_for(self.body, self.body.dataset)              # applicability (the Moon: synchronous)
        no_order(self.body, choice.order)

    def choice_cost(self, start: float, stop: float, count: int) -> Cost:
        """The request and its answer, the estimates of both models (the series kept since start-up) and, while the
        process does not keep it, the body's first-order model its description reads."""
        built = () if cached_model.cached(self.body, None) else (cost.model_build(self.body.orbit.e),)
        return Cost((cost.track_answer(count), costs.lunisolar_estimates(len(self.models))) + built)

    def track_cost(self, choice, start, stop, count) -> Cost:
        parts = (costs.lunisolar_sum(count),) + ((costs.nonrigid_sum(count),) if choice.model == "nonrigid" else ())
        return Cost(parts + ((cost.free_rotation("exact", count, 0.0),) if choice.free_wobble else ()))

    def estimates(self, jd_tdb) -> list[Estimate]:
        # cheapest first: the rigid rung, then the non-rigid one (the same series, times T(σ), on ERFA's precession)
        return estimates(self.model, jd_tdb, self.wobble, self.counts_free_wobble) \
            + estimates(self.nonrigid, jd_tdb, self.wobble, self.counts_free_wobble)

    def named(self, jd_tdb, choice):
        # the model follows the wobble whenever its phase is given
        candidates = estimates(self._model_named(choice), jd_tdb, self.wobble, self.counts_free_wobble)
        if not candidates[0].available:
            raise NotApplicableError(self.body.name, candidates[0].why_not)
        return candidates[-1] if self.wobble is not None else candidates[0]

    def track(self, choice: ModelChoice, epochs: Epochs) -> Track:
        m = self._model_named(choice)
        tr = m.track(epochs.jd_tdb)
        return add_wobble(m, tr, self.wobble) if self.adds_wobble(choice) else tr

    def describe(self, choice: ModelChoice) -> dict:
        info = describe_model(self.body, self.perturbers, self.model)
        with_wobble = self.adds_wobble(choice)
        if choice.model == "nonrigid":
            info["theory"] = NONRIGID_THEORY
            rigid_only = ("rigid Earth", "first order in the torque", "the track turns about", "precession rate")
            info["assumptions"] = NONRIGID_ASSUMPTIONS + [a for a in info["assumptions"]
                                                          if not a.startswith(rigid_only)]
        info["assumptions"] = [AXIS_ASSUMPTIONS["figure+wobble" if with_wobble else self.requested_axis]] \
            + info["assumptions"]
        return info

    def secular_spin(self) -> SpinConstants:
        """The lunisolar theory's mean pole and precession constant ψ̇ / cos ε̄, split into the Sun's part (which
        follows the Earth's orbit) and the Moon's (held fixed: the Moon's orbit precesses about the ecliptic in
        18.6 years, so its mean torque is about the ecliptic's normal too; its tidal recession and the slowing spin
        are left out of the equation and counted in the estimate: :func:`tidal_constant_drift`)."""
        lm = self.model
        total = lm.precession_rate / math.cos(lm.obliquity)
        o = self.body.orbit
        # the Sun's share: Kinoshita's (K/2)(1 - e²)^(-3/2) on the Earth's orbit, the first-order term the
        # lunisolar series has for it (Petit et al. eq. 25)
        sun = 0.0 if "Sun" not in lm.perturbers else 0.5 * eccentricity_factor(o.e) * scaling_factor(
            mean_motion_rad_per_day(o.a_au, o.center), lm.spin_rate, lm.hd)
        half_psi, half_eps = half_peak_to_peak(lm)
        return spin_constants(self.body, lm.pole_epoch, lm.icrf_from_orbit, lm.obliquity, sun, total - sun,
                              math.hypot(half_psi * math.sin(lm.obliquity), half_eps),
                              "the lunisolar theory's precession rate (ephem.earth.lunisolar) over cos(obliquity): the "
                              "Sun's part scaled with the Earth's orbit, the Moon's held fixed; the tides' change "
                              "of it in the estimate",
                              constant_drift=tidal_constant_drift((total - sun) / total))

    def spectrum(self, aim_mas: float, mid_centuries: float, jd_tdb=None, psi=None) -> Spectrum:
        """The lunisolar series' terms: phases in the Delaunay arguments, their polynomials linearised at
        ``mid_centuries``; plus a base at 0 for the precession alone. The track's rate is the series' own."""
        lm = self.model
        s = lm.series
        amp = pole_displacements(s.coefficients, lm.obliquity) * MAS      # coefficients in mas
        keep = np.nonzero(amp > 0.01 * aim_mas * MAS)[0]
        mult = s.multipliers[keep].astype(float)
        jd_m = J2000_JD + mid_centuries * DAYS_PER_CENTURY
        phase_m = np.degrees(mult @ delaunay_arguments(np.array(jd_m)))            # deg at the middle
        rate = np.degrees(mult @ delaunay_rates(mid_centuries)) * DAYS_PER_CENTURY  # deg/century there
        sign = np.where(rate < 0.0, -1.0, 1.0)    # positive frequencies: sin(-x) and cos(-x) span the same pair
        theta1 = sign * rate
        theta0 = sign * phase_m - theta1 * mid_centuries
        labels = (None,) + tuple(tuple(int(v) for v in row) for row in s.multipliers[keep])
        psi_dot = lm.track_rate
        return Spectrum(labels, np.concatenate([[0.0], theta0 % 360.0]), np.concatenate([[0.0], theta1]),
                        np.concatenate([[0.0], amp[keep]]),
                        math.degrees(psi_dot * (J2000_JD - lm.pole_epoch)) % 360.0,
                        math.degrees(psi_dot) * DAYS_PER_CENTURY, TRACK_SIDEBANDS,
                        "Delaunay multipliers (l, l', F, D, Omega) of a lunisolar nutation term")

    # --- the precession and nutation answers

    def answer_cost(self, order: int | None, nutation: bool = False, tolerance: bool = False) -> Cost:
        return Cost((costs.lunisolar_answer(),))

    def _check_answer(self, order) -> None:
        model_for(self.body, self.body.dataset)           # applicability (the Moon)
        no_order(self.body, order)

    def precession(self, order: int | None, tolerance: float | None, start: float) -> PrecessionResult:
        b = self.body
        self._check_answer(order)
        charge(self.answer_cost(order), b.name)
        lm = lunisolar_earth(b, "figure", TRACK_CUT_MAS, self.perturbers)
        info = describe_model(b, self.perturbers, lm)
        info["assumptions"].append("scaling_factor_arcsec_per_year: with several perturbers, 2ψ̇/cos ε̄ (the K of one "
                                   "perturber on a circular orbit in the ecliptic giving the same rate)")
        # the rate does not depend on the nutation's amplitude cut: nothing truncated
        info["assumptions"].append(OBSERVABLE_RATE)
        return PrecessionResult(b, lm.obliquity, lm.hd, lm.scaling_factor, lm.precession_rate,
                                rate_sigmas(b, lm), uncertainty_summary(b), info,
                                selection(self, "lunisolar", None, None, 1e3 * (time.perf_counter() - start),
                                          tolerance, covers=COVERS_NOTHING_TRUNCATED), geodesic_rate=lm.geodesic_rate)

    def nutation(self, order: int | None, tolerance: float | None, cut_mas, start: float,
                 nonrigid: bool = False) -> NutationResult:
        b, per = self.body, self.perturbers
        self._check_answer(order)
        if tolerance is not None and cut_mas is not None:
            raise InvalidInputError("cut_mas", "give either cut_mas or tolerance_mas, not both", b.name)
        if cut_mas is not None:
            cut = check_cut(in_unit(cut_mas, "mas", "cut_mas"))
        elif tolerance is not None:
            cut = cut_for_tolerance(lunisolar_earth(b, "figure", TRACK_CUT_MAS, per), tolerance)
        else:
            cut = TRACK_CUT_MAS
        charge(self.answer_cost(order, nutation=True), b.name)
        lm = lunisolar_earth(b, "figure", cut, per)
        if nonrigid:    # the served terms with the precession-nutation coupling, times the IERS 1996 T(σ)
            lm = replace(lm, series=non_rigid_series(lm.series))
        eps = lunisolar_earth(b, "figure", TRACK_CUT_MAS, per).obliquity   # the track's, any cut
        sin_eps = abs(math.sin(eps))
        rel = hd_relative_sigma(b)
        terms = []
        for t in lm.series.terms:
            coef = [t[f"{comp}_{part}_mas"] * MAS for comp in ("longitude", "obliquity") for part in ("sin", "cos")]
            amplitudes = (math.hypot(coef[0], coef[1]) * sin_eps, math.hypot(coef[2], coef[3]))
            terms.append(NutationTerm(
                None, tuple(t["delaunay_multipliers"]), t["period_days"], *coef,
                None,                           # the lunar theory's rates: published without a σ
                *(_scaled(c, rel) for c in coef), *(_scaled(a, rel) for a in amplitudes),
                rates=tuple(t[f"{comp}_{part}_rate_mas_per_century"] * MAS for comp in ("longitude", "obliquity")
                            for part in ("sin", "cos"))))
        half = half_peak_to_peak(lm)
        orbit_epoch = b.orbit.epoch_jd_tdb
        omitted = omitted_bound(lunisolar_earth(b, "figure", TRACK_CUT_MAS, per), cut)
        info = describe_model(b, per, lm)
        info["assumptions"].append("terms: Δψ = Σ (S + Ṡ T) sin φ + (C + Ċ T) cos φ (likewise Δε), φ = the "
                                   "multipliers · (l, l′, F, D, Ω), T Julian centuries TDB from J2000; `multiple` is "
                                   "null (no single mean anomaly), periods are signed (negative: the argument "
                                   "decreases); half peak-to-peak over 1900-2100")
        bound = {"truncation": omitted}
        if nonrigid:
            # the measured envelope of the served non-rigid series against erfa.nut00a (data/lunisolar.toml)
            bound["nutation_residual"] = residual_envelope() * MAS
            info["assumptions"].append(
                "nonrigid terms: the lunisolar series with the precession-nutation coupling, each circular "
                "component times the IERS 1996 transfer function (ephem.earth.nonrigid, data/nonrigid.toml); the "
                "Poisson rates stay rigid; nutation_residual: their measured envelope against IAU 2000A (erfa.nut00a) "
                "over 1900-2100")
        chosen = selection(self, "nonrigid" if nonrigid else "lunisolar", None, sum(bound.values()),
                           1e3 * (time.perf_counter() - start), tolerance, bound,
                           covers=COVERS_INTERIOR if nonrigid else COVERS_TRUNCATION, cut_mas=cut)
        return NutationResult(
            # the Earth's orbital mean anomaly is l′ (the Sun's mean anomaly seen from the Earth)
            b, ARGUMENT, float(delaunay_arguments(orbit_epoch)[1]), orbit_epoch,
            float(delaunay_rates((orbit_epoch - J2000_JD) / DAYS_PER_CENTURY)[1]), eps, tuple(terms), sin_eps,
            half, (_scaled(half[0], rel), _scaled(half[1], rel)), uncertainty_summary(b), info, chosen)


def hd_relative_sigma(b: Body) -> float | None:
    """σ(H_d)/H_d from the catalogue (IERS 2010's 1e-9 for the Earth), or None where H_d has no σ."""
    sigma = dynamical_ellipticity_sigma(b)
    return None if sigma is None else sigma / b.hd


def _scaled(value: float, rel: float | None) -> float | None:
    return None if rel is None else abs(value) * rel


def rate_sigmas(b: Body, lm: LunisolarEarth) -> RateSigmas | None:
    """The precession answer's 1σ: every term of Kinoshita's first-order theory is proportional to H_d (the
    rate, K, the nutation), so each carries H_d's relative σ; the mean obliquity, the pole's less the nutation
    at the pole epoch, moves by that nutation's Δε times it. The other inputs have no published σ."""
    rel = hd_relative_sigma(b)
    if rel is None:
        return None
    return RateSigmas(abs(lm.nutation_at_pole_epoch[1]) * rel, rel * lm.hd, abs(lm.scaling_factor) * rel,
                      abs(lm.precession_rate) * rel)


def uncertainty_summary(b: Body) -> dict:
    """The answers' ``uncertainty`` object: H_d's relative σ scales every value (:func:`rate_sigmas`); the
    inputs without a σ are listed with the record's reasons."""
    inputs = sorted(k for k in b.values if k.split(".")[0] in ("orbit", "pole", "rotation", "inertia"))
    unpropagated = [k for k in inputs if b.values[k].uncertainty is None and not k.endswith(".epoch")]
    dominant = "inertia.dynamical_ellipticity" if hd_relative_sigma(b) is not None else None
    return {"method": "linear: every value of Kinoshita's first-order lunisolar theory is proportional to H_d, so "
                      "each carries H_d's relative 1-sigma (the mean obliquity through the nutation at the pole "
                      "epoch); the other inputs have no published sigma, and the lunisolar theory's own series "
                      "(the Moon's and the Sun's orbits) none either: their uncertainty is unknown, not zero",
            "complete": not unpropagated,
            "dominant_input": {k: dominant for k in SCALAR_KEYS},
            "unpropagated_inputs": unpropagated,
            "no_uncertainty_reasons": no_uncertainty_reasons(b, unpropagated),
            "assumptions": ["the lunisolar theory's inputs (the Moon's and the Sun's orbits, GMs) are published "
                            "series without a stated 1-sigma (data/lunisolar.toml)",
                            "first order in H_d: the values scale with it exactly"]}


@lru_cache(maxsize=32)
def half_peak_to_peak(lm: LunisolarEarth) -> tuple[float, float]:
    """Half the peak-to-peak Δψ, Δε (radians) of a lunisolar series over 1900-2100, sampled every 0.5 d.

    146 000 epochs of the series (0.12 s): a pure function of its terms and the code that sums them, so it is kept
    on disk (:mod:`ephem.base.disk_cache`) under a key hashing the terms' bytes, the window and that code."""
    lo, hi = window()
    s = lm.series
    terms = hashlib.sha256()
    for a in (s.multipliers, s.coefficients, s.rates):
        terms.update(np.ascontiguousarray(a).tobytes())
    here = Path(__file__).resolve()
    key = fingerprint([here, here.parent / "lunisolar.py", here.parent.parent / "orbit" / "lunar.py"],
                      terms.hexdigest(), float(lo), float(hi))

    def build() -> dict:
        dpsi, deps = s.nutation_at(np.arange(lo, hi + 0.25, 0.5))
        return {"half": np.array([0.5 * float(np.ptp(dpsi)), 0.5 * float(np.ptp(deps))])}

    # one file per kind of series (a new key replaces the file of its name: see cached_arrays)
    name = f"earth_half_peak_to_peak_{s.axis}_{'_'.join(s.perturbers)}_cut{float(s.cut_mas):g}"
    half = cached_arrays(name, key, build)["half"]
    return float(half[0]), float(half[1])


def no_order(body: Body, order) -> None:
    """An e-order does not apply to the lunisolar series (cut by amplitude instead)."""
    if order is not None:
        raise NotApplicableError(body.name, f"an e-order (order={order!r}) truncates the single-perturber theory's "
                                 "Hansen coefficients; the lunisolar series is cut by amplitude instead (cut_mas, or "
                                 "tolerance_mas). Pass perturbers=sun for the Sun-only theory")
