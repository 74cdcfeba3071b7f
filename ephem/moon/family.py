"""The Moon's family behind the common interface: a synchronous rotator following its Cassini state.

:class:`SynchronousTheory`: a synchronous rotator whose pole
follows its Cassini state (:mod:`ephem.moon.model`).

Models, cheapest first (the two above ``cassini`` need a theory of the orbit's periodic terms, ``orbit.theory``:
the Moon's; a user's satellite has the bare Cassini state only):

* ``cassini``: the bare Cassini state: the mean pole turned with the node;
* ``librations``: plus the forced physical librations (:mod:`ephem.moon.physical_librations`), terms above
  :data:`~ephem.moon.model.LIBRATION_CUT`;
* ``integration``: the full rigid Moon (:mod:`ephem.moon.rigid_integration`) on the real orbit, started at t0 on the
  librations' state (the Moon: with the effective moments, from the ``librations`` model's frame);
* ``de421`` (the Moon, inside 1900-2050, where the package shipping the kernel is installed): JPL's DE421 lunar
  orientation itself, read from its binary PCK (:mod:`ephem.moon.lunar_kernel`), the analogue of a fast rotator's
  ``real_orbit``.

The axes (:data:`AXES`): ``mean_rotation``, the pole of the mean-Earth/rotation frame (the IAU's and DE421's ME pole),
and ``figure``, the principal axis of largest inertia (DE421's PA pole), that frame turned by DE421's constant PA–ME
rotation (:mod:`ephem.moon.orientation`); ``forced_figure``, the figure axis without its free wobble, which is then
not an error (no ``de421`` there: DE421's axes carry it). For the Moon every model's mean pole is the Cassini state at the observed
inclination, lagging behind the moving ecliptic (:mod:`ephem.moon.orientation`); a user's satellite keeps the
catalogue pole with the libration series' displacement at t0 removed, and its two axes coincide. The Moon's
estimates, by term (docs/moon.md; each checked against DE421 in tests/moon/test_against_de421_moon.py):

* ``librations`` (``cassini``): every forced libration left out, the sum of the series' pole amplitudes;
* ``free_modes``: the free wobble (``cassini``: its amplitude, left out; ``librations``: its measurement) and the free
  libration in latitude (0.025″, left out by all);
* ``truncation`` (``librations``): the terms below the cut, the sum of their amplitudes;
* ``inclination``: the observed mean inclination's distance from DE421's (data/moon_orientation.toml);
* ``ecliptic_motion``: the lag behind the moving ecliptic, modelled to first order in the small tilts: a twentieth of
  it (DE421's is 3 % from the model's);
* ``start`` (``integration``): it starts on the ``librations`` state and carries that state's error terms; the free
  modes that error excites turn it in space, 2δ sin(ωΔt/2) ≤ min(2, ωΔt) δ over Δt from t0 (ω the faster of the
  free wobble and the free precession, ~74 years);
* ``moments`` (``librations``, ``integration``): the series with the catalogue's moments against those that give
  the observed I and free longitude period (:data:`ephem.moon.physical_librations.EFFECTIVE_BETA_GAMMA`);
* ``physics``: what a rigid degree-2 body leaves out, the degree-3 field's periodic pole terms (1.15″) and the
  dissipation's offset (0.26″, Williams et al. 2001) (a user's satellite: twice, at t and in its catalogue pole);
* ``pa_offset`` (``figure``): the rounding of DE421's PA–ME angles to 0.01″;
* ``ephemeris`` (``de421``): DE421's own accuracy, the change from DE418 the frame kernel measures (0.45 µrad in the
  principal axes, 0.27 µrad in the ME frame, over 2000-2020).

Here too: the Cassini state carried over millennia (:class:`CassiniHistory`), the precession and nutation results,
the spectrum the kernel writer fits. Radians and days unless a name says otherwise.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..bodies.interior import interior_of
from ..theory import cost
from ..base.budget import Cost, charge
from ..base.memo import bytes_bounded
from ..forced.cassini import free_librations, moment_ratios
from ..bodies.catalogue import Body, is_synchronous
from ..base.constants import ARCSEC, J2000_JD, JULIAN_CENTURY_DAYS, JULIAN_YEAR_DAYS, MAS, ROUNDING
from ..base.errors import InvalidInputError, NotApplicableError
from ..orbit.lunar import MIN_CUT_MAS, check_cut, lunisolar_data
from ..orbit.relativity import geodesic_precession_rate
from ..orbit.geometry import carry
from ..orbit.kepler import mean_motion_rad_per_day
from ..forced.precession_nutation import Track
from ..theory.choice import Candidates, cheapest
from ..theory.interface import SpinAxisTheory, Spectrum, SpectrumExport
from ..theory.requests import Epochs, ModelChoice
from ..theory.results import (COVERS_ALL_TERMS, COVERS_NOTHING_TRUNCATED, COVERS_TRUNCATION, Estimate,
                              NutationResult, NutationTerm, PrecessionResult, RateSigmas, selection)
from ..forced.catalogue_sigmas import dynamical_ellipticity_sigma, moments_function_sigma, no_uncertainty_reasons
from ..forced.uncertainty import SCALAR_KEYS
from ..longterm.averaged_spin import history_arrays
from ..orbit.lunar import delaunay_arguments, delaunay_rates
from ..base.units import in_unit
from .model import (CIRCLE_SIDEBANDS, INTEGRATION_ERROR, LIBRATION_CUT, PHYSICS_OMITTED, SynchronousModel, check_body,
                    ecliptic_lag, integrate_axes, integrate_track, libration_series, moments_bound, series_built,
                    synchronous_model)
from . import costs, lunar_kernel
from .results import CassiniSummary
from .kernel_rung import PA_ROUNDING, kernel_estimate, kernel_track
from .orientation import ecliptic_lag_vector, mean_inclination, orientation_data, pa_offset_angle


THEORY = ("Cassini state of a synchronous rotator (ephem.forced.cassini): the spin axis, the orbit normal and the Laplace "
          "pole coplanar, the pole at fixed inclination to the Laplace plane turning with the orbit's node")
DESCRIPTIONS = {
    "cassini": "the bare Cassini state: the catalogue's mean pole turned with the node (Cassini's laws); the "
               "forced physical librations are left out and counted in the estimate",
    "librations": "the Cassini state with the forced physical librations of the pole (ephem.moon.physical_librations: "
                  "the rigid Moon's response to its orbit's periodic terms, terms above 0.01″)",
    "integration": "the full rigid Moon integrated on the real orbit (ephem.moon.rigid_integration: Euler's equations, "
                   "the Earth's and the Sun's torques), started on the librations' state at the pole epoch",
    "de421": "JPL's DE421 lunar orientation, fitted to lunar laser ranging, read from its binary PCK "
             "(moon_pa_de421_1900-2050.bpc; the mean-Earth frame by the frame kernel moon_080317.tf's constant "
             "rotation): the Moon inside 1900-2050 only",
}
#: the axes a synchronous rotator's track follows (:data:`ephem.base.constants.AXES`)
AXES = ("figure", "forced_figure", "mean_rotation")
AXIS_ASSUMPTIONS = {
    "figure": "axis figure: the principal axis of largest inertia (DE421's PA frame +Z for the Moon): the mean-Earth/"
              "rotation frame turned by DE421's constant PA-to-ME rotation (frame kernel moon_080317.tf: 67.92, 78.56, "
              "0.30 arcsec about Z, Y, X), which puts it 78.56 arcsec from the mean rotation axis, toward the mean Earth "
              "(a monthly circle in space)",
    "mean_rotation": "axis mean_rotation: the pole of the mean-Earth/mean-rotation frame (the IAU's and DE421's ME "
                     "frame +Z): the rotation axis the libration theory follows, with the free wobble as DE421's ME "
                     "frame has it (a constant rotation of its principal axes)",
    "forced_figure": "axis forced_figure: the figure axis's forced motion, without the free wobble (8.2 x 3.3 arcsec, "
                     "74.6 years), which is then not an error",
}
#: the free libration in latitude, rad (Yang et al. 2017: 0.025″ in DE430), which no model carries
FREE_LATITUDE = 0.025 * ARCSEC
#: the free wobble's measurement: its fit over 1970-2010 against one over 1900-2050 (0.03″; tools/
#: derive_moon_free_wobble.py), rounded up
WOBBLE_MEASUREMENT = 0.05 * ARCSEC
#: the wobble period's uncertainty, days: DE430's (Yang et al. 2017, 27262.99 d) against DE421's (Rambaux & Williams
#: 2011, 27257.27 d) stands for it; the phase it loses grows with the distance from the fit
WOBBLE_PERIOD_SIGMA_DAYS = 5.72
#: the lag behind the moving ecliptic is first order in the tilts and folds the Sun into ω_p: a twentieth of it stands
#: for what is left out (DE421: 7.56″ against 7.33″ modelled, 3 %)
LAG_MODEL_SHARE = 0.05

ASSUMPTIONS = [
    "rigid synchronous body, rotation locked to the orbit (long axis toward the primary)",
    "the orbit's node regresses uniformly on the Laplace plane (the Moon: the mean node of Meeus 1998 eq. 47.7 on "
    "the mean ecliptic of date, the ecliptic's motion from IAU 2006, erfa.ecm06)",
    "the pole keeps the catalogue's inclination to the Laplace plane and its longitude from the node + 90° at the "
    "pole epoch (Cassini's third law up to the librations there)",
]

# ----------------------------------------------------------------------------- the theory's interface


#: Meeus (1998) eq. 47.7's T² coefficient of the lunar node, deg per century²: the node's acceleration (tides
#: and the Earth's eccentricity) that a linear node leaves out; over millennia it is the phase's error
NODE_ACCELERATION_DEG_PER_CENTURY2 = 0.0020708


@dataclass(frozen=True, eq=False)
class CassiniHistory:
    """A synchronous rotator's pole over long spans: the Cassini state carried along the moving Laplace plane.

    The plane is the primary's orbit plane (the Moon's Laplace plane is the ecliptic of date, to the 8″ of the
    Earth's J2 left out), taken from the primary's orbit history; the pole keeps its inclination I to it and
    turns with the node, whose inertial rate (``SynchronousOrbit.node_rate``) is driven by the Sun and scales with
    the Earth's orbit as (1 − e²)^(−3/2) (the solar tide's mean strength). The node's acceleration of Meeus' T²
    term (tides, left out) is the estimate's ``node_phase`` term, I times the node's phase error; the libration and
    the other terms of the ``cassini`` model's estimate are the ``librations`` term."""

    model: SynchronousModel
    librations: float
    orbit_body: str = "Earth"
    source: str = "the Cassini state (ephem.forced.cassini) turned with the node along the primary's orbit plane"

    def cost(self, span_years: float, epochs: int):
        """The Cassini pole at ``epochs`` epochs and the node's quadrature (:func:`ephem.moon.costs.cassini_history`)."""
        return costs.cassini_history(epochs)

    def orbit_points(self, span_years: float, epochs: int) -> int:
        """The orbit's points a history reads beside :meth:`cost`: none, its price was measured with the orbit's
        spline read at its quadrature's points and its epochs (:func:`ephem.longterm.history.history_cost`)."""
        return 0

    def history(self, orbit, years, progress=None):
        m = self.model
        years = np.asarray(years, dtype=float)
        t0 = (m.pole_epoch - J2000_JD) / JULIAN_YEAR_DAYS
        e0 = float(orbit.eccentricity_at(t0))
        fine = np.unique(np.concatenate([np.linspace(min(years.min(), t0), max(years.max(), t0), 4001), years, [t0]]))
        rate = m.orbit.node_rate * JULIAN_YEAR_DAYS * ((1.0 - e0**2) / (1.0 - orbit.eccentricity_at(fine) ** 2)) ** 1.5
        turned = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(fine))])
        turned -= np.interp(t0, fine, turned)
        node = m.node_at_pole_epoch + np.interp(years, fine, turned)
        plane = orbit.pole_at(years)
        z = np.array([0.0, 0.0, 1.0])
        i, incl = m.orbit.inclination, m.inclination
        lon = node + 0.5 * math.pi + m.longitude_offset
        orbit_pole = carry(z, plane, np.stack([math.sin(i) * np.sin(node), -math.sin(i) * np.cos(node),
                                               np.full(node.shape, math.cos(i))], axis=-1))
        spin = carry(z, plane, np.stack([math.sin(incl) * np.cos(lon), math.sin(incl) * np.sin(lon),
                                         np.full(node.shape, math.cos(incl))], axis=-1))
        centuries = (years - t0) / 100.0
        phase = np.minimum(np.radians(NODE_ACCELERATION_DEG_PER_CENTURY2) * centuries**2, math.pi)
        terms = {"librations": np.full(years.shape, self.librations),
                 "node_phase": 2.0 * math.sin(incl) * np.sin(0.5 * phase)}
        # the obliquity i + I does not depend on the node's phase: only the librations move it
        obliquity_terms = {"librations": np.full(years.shape, self.librations)}
        return history_arrays(years, spin, orbit_pole, -(node - m.node_at_pole_epoch), terms, obliquity_terms, (),
                              t0, np.zeros(years.shape), 0)


class SynchronousTheory(SpinAxisTheory, SpectrumExport):
    """A synchronous rotator (the Moon) under its primary: the Cassini state and its ladder."""

    summary = "the Cassini-state theory of a synchronous rotator (the Moon)"
    models = ("cassini", "librations", "integration", "de421")
    descriptions = DESCRIPTIONS
    axes = AXES

    @classmethod
    def serves(cls, body: Body, perturbers: tuple[str, ...]) -> bool:
        return is_synchronous(body, perturbers)

    @property
    def model(self) -> SynchronousModel:
        return synchronous_model(self.body)

    @classmethod
    def how_to_reach(cls, body: Body) -> str:
        return "it models synchronous rotators (spin period = orbital period), such as the Moon"

    def default_model(self, choice: ModelChoice) -> str:
        return "cassini" if self.body.orbit.theory is None else "librations"

    def check_request(self, choice: ModelChoice) -> None:
        model = choice.model
        check_body(self.body)
        no_order(self.body, choice.order)
        if self.requested_axis not in AXES:
            raise NotApplicableError(self.body.name, refused_axis(self.requested_axis))
        if model in ("librations", "integration") and self.body.orbit.theory is None:
            raise NotApplicableError(self.body.name, no_orbit_theory(model))
        if model == "de421" and not self.model.llr:
            raise NotApplicableError(self.body.name, NOT_THE_MOON)

    @property
    def figure(self) -> bool:
        """Whether the principal axis is asked for (else the mean rotation axis)."""
        return self.axis == "figure"

    # --- cost: known before the work (ephem.moon.costs and its table, benchmarks/bench_cost.py)

    def _setup_cost(self) -> tuple:
        return (costs.synchronous_estimates(),) + (() if series_built(self.body) else (costs.libration_series(),))

    def choice_cost(self, start: float, stop: float, count: int) -> Cost:
        """The request and its answer, the estimates, and the libration series while it is not kept."""
        return Cost((cost.track_answer(count),) + self._setup_cost())

    def track_cost(self, choice, start, stop, count) -> Cost:
        """The model's own track (the estimates and the series are the choice's): the Cassini pole at every epoch,
        with the libration terms (``librations``), or integrated (``integration``)."""
        model = self.resolved(choice).model
        if model == "de421":
            return Cost((costs.lunar_kernel(count, lunar_kernel.kept()),))
        terms = self._terms_kept() if model == "librations" else 0
        parts = (costs.synchronous_track(count, terms),)
        if model == "integration":
            t0 = self.body.pole.epoch_jd_tdb
            parts += (costs.synchronous_integration(max(stop, t0) - min(start, t0), count),)
        return Cost(parts)

    def _terms_kept(self) -> int:
        """Terms of the cut series (the Moon's: 57); before the series is built, that count."""
        if series_built(self.body) and self.body.orbit.theory is not None:
            return len(libration_series(self.body).truncated(LIBRATION_CUT))
        return LIBRATION_TERMS_KEPT

    def answer_cost(self, order: int | None, nutation: bool = False, tolerance: bool = False) -> Cost:
        return Cost(self._setup_cost())

    # --- estimates

    def estimates(self, jd_tdb) -> list[Estimate]:
        m = self.model
        if m.series is None:
            why = no_orbit_theory("librations")
            return [Estimate("cassini", None, {"rounding": ROUNDING}, unestimated=("librations",)),
                    Estimate("librations", None, {}, available=False, why_not=why),
                    Estimate("integration", None, {}, available=False, why_not=no_orbit_theory("integration")),
                    Estimate("de421", None, {}, available=False, why_not=NOT_THE_MOON)]
        if m.llr:
            return self._llr_estimates(jd_tdb)
        physics, ecliptic = 2.0 * PHYSICS_OMITTED, 2.0 * ecliptic_lag(m)
        moments = moments_bound(self.body)
        return [
            Estimate("cassini", None, {"librations": float(m.series.pole_amplitudes.sum()),
                                       "ecliptic_motion": ecliptic, "physics": physics, "rounding": ROUNDING}),
            Estimate("librations", None, {"truncation": m.series.omitted_bound(LIBRATION_CUT)[0], "moments": moments,
                                          "ecliptic_motion": ecliptic, "physics": physics, "rounding": ROUNDING}),
            Estimate("integration", None, {"start": 2.0 * abs(m.inclination - m.series.equator_inclination),
                                           "moments": moments, "integration": INTEGRATION_ERROR, "physics": physics,
                                           "rounding": ROUNDING}),
            Estimate("de421", None, {}, available=False, why_not=NOT_THE_MOON),
        ]

    def _llr_estimates(self, jd_tdb) -> list[Estimate]:
        """The Moon's estimates (module docstring): the mean pole's terms (the observed I, the lag's model, the free
        latitude libration, the degree-3 field and dissipation), the librations' and the free wobble's."""
        m = self.model
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        ends = np.array([t.min(), t.max()]) if t.size else np.array([m.pole_epoch])
        lag = float(np.max(np.linalg.norm(ecliptic_lag_vector(ends, m.orbit.node_rate, m.lag_ratio), axis=1)))
        common = {"inclination": mean_inclination()[1], "ecliptic_motion": LAG_MODEL_SHARE * lag,
                  "physics": PHYSICS_OMITTED}
        if self.figure:
            common["pa_offset"] = PA_ROUNDING
        common["rounding"] = ROUNDING
        # the free modes: left out (cassini) or measured (librations); not errors of the forced figure axis
        free_modes = self.counts_free_wobble
        wobble = max(m.wobble.amplitudes) + FREE_LATITUDE if free_modes else 0.0
        moments = moments_bound(self.body)
        librations = {"truncation": m.series.omitted_bound(LIBRATION_CUT)[0], "moments": moments}
        if free_modes:
            librations["free_modes"] = wobble_measurement(m, ends) + FREE_LATITUDE
        # the integration starts on the librations' state: its error there, and the free modes it excites, which turn
        # it in space (the free wobble and the free precession, the faster ~74 years): 2δ sin(ωΔt/2) ≤ min(2, ωΔt) δ
        delta = sum(librations.values()) + common["inclination"] + common["ecliptic_motion"]
        far = float(np.max(np.abs(ends - m.pole_epoch)))
        free = free_librations(m.orbit, m.body.moments, m.state)
        swing = min(2.0, 2.0 * math.pi * far / min(free.wobble_days, free.precession_space_days))
        return [
            Estimate("cassini", None, {"librations": float(m.series.pole_amplitudes.sum()),
                                       **({"free_modes": wobble} if free_modes else {}), **common}),
            Estimate("librations", None, {**librations, **common}),
            Estimate("integration", None, {**librations, **common, "start": swing * delta,
                                           "integration": INTEGRATION_ERROR}),
            kernel_estimate(t, self.figure) if free_modes else
            Estimate("de421", None, {}, available=False, why_not=KERNEL_WOBBLES),
        ]

    def named(self, jd_tdb, choice):
        name = self.resolved(choice).model
        return next(e for e in self.estimates(jd_tdb) if e.rung == name)

    def track(self, choice: ModelChoice, epochs: Epochs) -> Track:
        m = self.model
        model = self.resolved(choice).model
        t = epochs.jd_tdb
        if model == "de421":
            if not self.counts_free_wobble:
                raise NotApplicableError(self.body.name, KERNEL_WOBBLES)
            return kernel_track(m, t, self.figure)
        if m.llr:
            if model == "integration":
                axes = integrate_axes(m, t, self.figure, self.counts_free_wobble)
            else:
                lib = model == "librations"
                return m.track_of_poles(t, m.poles(t, librations=lib, wobble=lib and self.counts_free_wobble,
                                                   figure=self.figure))
            return m.track_of_poles(t, axes[:, :, 2])
        if model == "cassini":
            return m.track(t)
        if model == "librations":
            rho, sigma, _ = m.series.truncated(LIBRATION_CUT).angles(t)
            return m.track(t, sigma, rho)
        return integrate_track(m, t)

    def describe(self, choice: ModelChoice) -> dict:
        m = self.model
        b = self.body
        warnings = []
        if m.series is None:
            warnings.append(no_orbit_theory("librations"))
        assumptions = list(ASSUMPTIONS)
        if m.llr:
            assumptions[2] = MOON_MEAN_POLE
            assumptions.append(AXIS_ASSUMPTIONS[self.requested_axis])
        elif self.axis == "figure" or self.axis == "mean_rotation":
            assumptions.append("the figure and mean rotation axes coincide: no offset of the principal axes from the "
                               "mean rotation frame (a degree-3 field) is known for this body")
        return {
            "theory": THEORY, "eccentricity_order": None, "assumptions": assumptions, "warnings": warnings,
            "spin_orbit_ratio": b.spin_rate_rad_per_day / mean_motion_rad_per_day(b.orbit.a_au, b.orbit.center),
            "min_spin_orbit_ratio": 0.0, "pole_epoch_jd_tdb": m.pole_epoch, "orbit_epoch_jd_tdb": b.orbit.epoch_jd_tdb,
        }

    def secular_spin(self) -> CassiniHistory:
        """The Cassini state along the primary's moving orbit plane (:class:`CassiniHistory`); the primary's orbit
        history must be known (the Moon's: the Earth's)."""
        self.check_request(ModelChoice())
        if self.body.orbit.center != "Earth":
            raise NotApplicableError(self.body.name, "the long-term Cassini state follows the primary's orbit plane, "
                                     "whose history is shipped for the Earth only (the Moon's primary)")
        cassini = next(e for e in self.estimates(np.array([self.model.pole_epoch])) if e.rung == "cassini")
        # the history carries the mean rotation axis: the figure axis's monthly circle about it is an error there
        circle = pa_offset_angle() if self.figure and self.model.llr else 0.0
        return CassiniHistory(self.model, cassini.total + circle)

    def spectrum(self, aim_mas: float, mid_centuries: float, jd_tdb=None, psi=None) -> Spectrum:
        """The node's circle (a base at 0 with the precession's sidebands: the circle's projection on RA and Dec,
        :data:`CIRCLE_SIDEBANDS`) and, with a libration series, its terms above a hundredth of ``aim_mas`` as
        bases, their Delaunay phases linear about ``mid_centuries``."""
        m = self.model
        rate = m.precession_rate
        labels, theta0, theta1, amp = [None], [0.0], [0.0], [0.0]
        if m.series is not None:
            s = m.series.truncated(LIBRATION_CUT)
            keep = np.nonzero(s.pole_amplitudes > 0.01 * aim_mas * MAS)[0]
            mult = s.multipliers[keep].astype(float)
            jd_m = J2000_JD + mid_centuries * JULIAN_CENTURY_DAYS
            phase = np.degrees(mult @ delaunay_arguments(np.array(jd_m)))
            freq = np.degrees(mult @ delaunay_rates(mid_centuries)) * JULIAN_CENTURY_DAYS
            sign = np.where(freq < 0.0, -1.0, 1.0)
            labels += [tuple(int(v) for v in row) for row in s.multipliers[keep]]
            theta1 += list(sign * freq)
            theta0 += list((sign * phase - sign * freq * mid_centuries) % 360.0)
            amp += list(s.pole_amplitudes[keep] / MAS)
        return Spectrum(tuple(labels), np.array(theta0), np.array(theta1), np.array(amp),
                        math.degrees(rate * (J2000_JD - m.pole_epoch)) % 360.0,
                        math.degrees(rate) * JULIAN_CENTURY_DAYS, CIRCLE_SIDEBANDS,
                        "Delaunay multipliers (l, l', F, D, Omega) of a physical libration term; none: the node's circle")

    # --- the precession and nutation answers

    def precession(self, order: int | None, tolerance: float | None, start: float) -> PrecessionResult:
        b = self.body
        check_body(b)
        no_order(b, order)
        charge(self.answer_cost(order), b.name)
        m = self.model
        info = self.describe(ModelChoice("cassini"))
        info["assumptions"].append(
            "precession_rate_arcsec_per_year: the node's inertial regression (the pole turns with it about the "
            "Laplace pole); obliquity_deg: the mean pole's θ = i + I to the orbit; scaling_factor_arcsec_per_year: "
            "2 P(0), twice the synchronous torque's precession constant (ephem.forced.cassini)")
        info["assumptions"].append(
            "the node's regression is an observed rate (the lunar theory's, fitted to observations), so it already "
            "contains the geodesic (de Sitter) precession of the Earth-Moon system about the Sun "
            "(geodesic_precession_rate_arcsec_per_year, ephem.orbit.relativity; lunar laser ranging confirms it, "
            "Williams, Newhall & Dickey 1996): observable_precession_rate_arcsec_per_year is the rate itself, and "
            "nothing is subtracted")
        # the rate and the mean obliquity are the bare Cassini state's: nothing truncated
        return PrecessionResult(b, m.obliquity, m.hd, m.scaling_factor, m.precession_rate, rate_sigmas(b, m),
                                uncertainty_summary(b), info,
                                selection(self, "cassini", None, None, 1e3 * (time.perf_counter() - start),
                                          tolerance, covers=COVERS_NOTHING_TRUNCATED),
                                derived_cassini_state(m), geodesic_rate=earth_moon_geodesic_rate(),
                                geodesic_in_rate=True)

    def nutation(self, order: int | None, tolerance: float | None, cut_mas, start: float,
                 nonrigid: bool = False) -> NutationResult:
        if nonrigid:
            raise NotApplicableError(self.body.name, "non-rigid terms do not apply: the body is rigid in this "
                                     f"project: {interior_of(self.body.name).why}")
        b = self.body
        check_body(b)
        no_order(b, order)
        if tolerance is not None and cut_mas is not None:
            raise InvalidInputError("cut_mas", "give either cut_mas or tolerance_mas, not both", b.name)
        m = self.model
        if m.series is None:
            if cut_mas is not None:
                raise NotApplicableError(b.name, no_orbit_theory("librations"))
            cut = None
        elif cut_mas is not None:
            cut = check_cut(in_unit(cut_mas, "mas", "cut_mas")) * MAS
        elif tolerance is not None:
            cut = cut_for_tolerance(m.series, tolerance, b.name)
        else:
            cut = LIBRATION_CUT
        extremes = () if m.series is None or _extremes.cached(b, cut) else (
            costs.libration_extremes(len(m.series.truncated(cut)), EXTREMES_EPOCHS, HALF_PEAK_BLOCK),)
        charge(self.answer_cost(order, nutation=True) + Cost(extremes), b.name)
        name = "cassini" if m.series is None else "librations"
        info = self.describe(ModelChoice(name))
        terms, omitted = (), None
        if m.series is not None:
            series = m.series.truncated(cut)
            omitted = m.series.omitted_bound(cut)[0]
            terms = nutation_terms(series)
            info["assumptions"].append(
                "terms: the forced physical librations of the pole, Δψ = σ (the pole's displacement across its "
                "meridian, toward increasing ecliptic longitude of date: sin I times the equator's node shift) and "
                "Δε = ρ (the equator's inclination less its mean), each Σ S sin φ + C cos φ with φ the multipliers · "
                "(l, l′, F, D, Ω) (IERS 2010 eq. 5.43); Eckhardt's (1981) variables, ephem.moon.physical_librations")
        if omitted is not None and not omitted > 0.0:
            omitted = None          # every term kept: nothing truncated here (issue 29: an estimate of 0 is no bound)
        chosen = selection(self, name, None, omitted, 1e3 * (time.perf_counter() - start), tolerance,
                           None if omitted is None else {"truncation": omitted},
                           covers=COVERS_TRUNCATION if omitted is not None else COVERS_ALL_TERMS,
                           cut_mas=None if cut is None else cut / MAS)
        half = (0.0, 0.0) if m.series is None else _extremes(b, cut)
        # Δψ = σ is already the pole's displacement: its amplitude is not scaled by sin ε
        return NutationResult(b, "Delaunay arguments l, l′, F, D, Ω (IERS 2010 eq. 5.43)",
                              math.radians(b.orbit.mean_anomaly_deg), b.orbit.epoch_jd_tdb, m.orbit.mean_motion,
                              m.obliquity, terms, 1.0, half, (None, None), uncertainty_summary(b), info, chosen)


#: terms of the Moon's series above :data:`LIBRATION_CUT` (the cost before it is built)
LIBRATION_TERMS_KEPT = 60
KERNEL_WOBBLES = ("DE421's principal axes carry the free wobble, which the forced figure axis leaves out: ask for "
                  "axis=figure")
NOT_THE_MOON = ("DE421's lunar orientation is the Moon's: a user's synchronous satellite has the Cassini state "
                "(model=cassini)")
MOON_MEAN_POLE = ("the Moon's mean pole: the Cassini state at the observed mean inclination I = 1.54242 deg (Eckhardt "
                  "1981, Meeus 1998 ch. 53; not the catalogue's IAU pole), its node at the Delaunay node + 90 deg, "
                  "displaced by its lag behind the moving ecliptic (ephem.moon.orientation: 7.3 arcsec) and, with the "
                  "librations, by the free wobble measured in DE421")


def wobble_measurement(m: SynchronousModel, ends: np.ndarray) -> float:
    """The free wobble's error (rad) at epochs reaching ``ends``: its fit (:data:`WOBBLE_MEASUREMENT`) and the phase
    its period's uncertainty loses from the fit's middle, 2 A sin(Δφ/2) ≤ A min(2, Δφ), Δφ = 2π Δt σ_P / P²: 0.01″ a
    century, growing with the span as the theory's other terms do not."""
    w = m.wobble
    span = orientation_data()["free_wobble"]["fit_span_jd_tdb"]
    far = float(np.max(np.abs(np.asarray(ends, dtype=float) - 0.5 * (span[0] + span[1]))))
    drift = 2.0 * math.pi * far * WOBBLE_PERIOD_SIGMA_DAYS / w.period_days**2
    return WOBBLE_MEASUREMENT + max(w.amplitudes) * min(2.0, drift)


def refused_axis(axis: str) -> str:
    """Why a synchronous rotator's track does not follow ``axis``."""
    return (f"the Cassini-state theory follows the figure axis (the principal axis of largest inertia) and the mean "
            f"rotation axis (axis=mean_rotation, the mean-Earth frame's pole), not {axis}: a synchronous body's "
            "angular momentum differs from its rotation axis by the precession's own angular velocity, not modelled, "
            "and its free wobble is part of both axes")




def no_orbit_theory(model: str) -> str:
    return (f"the '{model}' model follows the orbit's periodic terms, which the library has for the Moon only (its "
            "catalogue orbit's theory, Meeus 1998 ch. 47); a user's satellite gets the bare Cassini state "
            "(model=cassini)")


def cut_candidates(series) -> Candidates:
    """The amplitude cuts (rad) a tolerance may choose for the libration terms: each term's larger amplitude (pole or
    τ), largest first, priced by the terms the cut keeps (those above it) and bounded by what the terms at or below it
    can move the pole (radians, made only when the choice reaches it)."""
    rising = np.sort(np.maximum(series.pole_amplitudes, series.tau_amplitudes))
    amp = rising[::-1]
    return Candidates(amp, (amp.size - np.searchsorted(rising, amp, side="right")).astype(float).tolist(),
                      lambda i: series.omitted_bound(float(amp[i]))[0], tie=0.0, what="amplitude cut")


def cut_for_tolerance(series, tolerance: float, name: str) -> float:
    """The largest amplitude cut (rad) whose omitted terms move the pole by no more than ``tolerance``
    (:func:`ephem.theory.choice.cheapest` of :func:`cut_candidates`: the fewest terms kept)."""
    return float(cheapest(cut_candidates(series), tolerance, default=MIN_CUT_MAS * MAS))


def nutation_terms(series) -> tuple[NutationTerm, ...]:
    """The nutation terms of a libration series (radians; Δψ = σ, Δε = ρ; no 1σ: the librations are not
    propagated), largest pole amplitude first."""
    out = []
    order = np.argsort(-series.pole_amplitudes, kind="stable")
    for i in order:
        freq = float(series.frequencies[i])
        sigma, rho = series.sigma[i], series.rho[i]           # (cos, sin) coefficients
        out.append(NutationTerm(None, tuple(int(x) for x in series.multipliers[i]),
                                2.0 * math.pi / freq if freq else math.inf,
                                float(sigma[1]), float(sigma[0]), float(rho[1]), float(rho[0])))
    return tuple(out)


#: epochs of :func:`half_peak_to_peak` summed at a time: its 27,200 epochs at once took 37 MB of work arrays (57
#: terms), more than the answer's charged peak; 2,000 at a time take ~3 MB, the extremes the same numbers
HALF_PEAK_BLOCK = 2000


#: the epochs of :func:`half_peak_to_peak`: one node period (6,800 d) from J2000 every 0.25 d
EXTREMES_EPOCHS = 27200


def half_peak_to_peak(series) -> tuple[float, float]:
    """Half the peak-to-peak σ and ρ (radians) over one node period from J2000, sampled every 0.25 d."""
    jd = J2000_JD + 0.25 * np.arange(EXTREMES_EPOCHS)
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for i in range(0, jd.size, HALF_PEAK_BLOCK):
        rho, sigma, _ = series.angles(jd[i:i + HALF_PEAK_BLOCK])
        lo = np.minimum(lo, [sigma.min(), rho.min()])
        hi = np.maximum(hi, [sigma.max(), rho.max()])
    return 0.5 * float(hi[0] - lo[0]), 0.5 * float(hi[1] - lo[1])


@bytes_bounded
def _extremes(b: Body, cut: float | None) -> tuple[float, float]:
    """:func:`half_peak_to_peak` of ``b``'s libration series cut at ``cut`` (rad): a pure function of the body and
    the cut, kept per both (0.06 s for the Moon's 57 terms, 0.8 s for 795, asked by every nutation answer)."""
    return half_peak_to_peak(synchronous_model(b).series.truncated(cut))


def derived_cassini_state(m: SynchronousModel) -> CassiniSummary:
    """The Cassini state the theory derives (the answer's ``cassini`` object), beside the served mean pole."""
    alpha, beta, gamma = moment_ratios(m.body.moments)
    free = free_librations(m.orbit, m.body.moments, m.state)
    return CassiniSummary(m.inclination, m.state.equator_inclination, m.state.obliquity, m.orbit.inclination,
                        m.orbit.node_rate, beta, gamma, free.longitude_days, free.latitude_days,
                        free.precession_space_days, free.wobble_days)


def rate_sigmas(b: Body, m: SynchronousModel) -> RateSigmas:
    """The precession answer's 1σ where the inputs have one: H_d and K = 2 P(0) ∝ (C − A)/C from the moments' σ
    and correlation (the Moon's: lunar laser ranging's β and γ); the rate is the orbit node's and the mean
    obliquity the catalogue pole's, neither with a published σ (None)."""
    A, B, C = b.moments
    polar = (C - A) / C
    sigma_polar = moments_function_sigma(b, lambda a, _b, c: (c - a) / c)
    return RateSigmas(None, dynamical_ellipticity_sigma(b),
                      None if sigma_polar is None else abs(m.scaling_factor) * sigma_polar / polar, None)


def uncertainty_summary(b: Body) -> dict:
    inputs = sorted(k for k in b.values if k.split(".")[0] in ("orbit", "pole", "rotation", "inertia")
                    and not k.endswith(".epoch"))
    unpropagated = [k for k in inputs if b.values[k].uncertainty is None]
    with_sigma = [k for k in ("inertia.A", "inertia.B", "inertia.C") if k in b.values
                  and b.values[k].uncertainty]
    dominant = {k: None for k in SCALAR_KEYS}
    if with_sigma:
        dominant["dynamical_ellipticity"] = dominant["scaling_factor_arcsec_per_year"] = "inertia.A"
    return {"method": "linear over the moments (their 1-sigma and correlation, for the Moon from lunar laser "
                      "ranging) for H_d and K; the rate is the orbit node's and the mean obliquity the catalogue "
                      "pole's, neither with a published sigma, and the physical librations are not propagated "
                      "(each build of their series costs seconds): those are unknown (null), not zero",
            "complete": not unpropagated, "dominant_input": dominant, "unpropagated_inputs": unpropagated,
            "no_uncertainty_reasons": no_uncertainty_reasons(b, unpropagated),
            "assumptions": ["the moments' errors as their derivation gives them (ephem.bodies.inertia)"]}


def no_order(body: Body, order) -> None:
    if order is not None:
        raise NotApplicableError(body.name, f"an e-order (order={order!r}) truncates the fast-rotator theory's "
                                 "Hansen coefficients; the Cassini-state theory of a synchronous rotator has none")


def earth_moon_geodesic_rate() -> float:
    """Ω_gp (rad/day) of the Earth-Moon barycentre's orbit about the Sun (the Kepler ellipse of
    ``data/lunisolar.toml [sun]`` at J2000, :func:`ephem.orbit.relativity.geodesic_precession_rate`): 19.2 mas/yr,
    the de Sitter precession of the lunar orbit and spin axis, which the observed node rate contains."""
    s = lunisolar_data()["sun"]
    return geodesic_precession_rate(s["semi_major_axis_au"], s["eccentricity"][0], "Sun")
