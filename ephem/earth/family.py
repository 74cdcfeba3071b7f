"""The Earth under the Moon and the Sun, as the library serves it: :mod:`ephem.earth.lunisolar` wired to the
catalogue's pole and orbit, a pole track with an error estimate against the real Earth.

The series (precession rate and nutation in the Delaunay arguments l, l′, F, D, Ω) are
:func:`ephem.earth.lunisolar.earth_lunisolar` with the body's H_d and spin rate. The track follows
:mod:`ephem.forced.precession_nutation`'s definition in the frame of the catalogue's orbit and the mean equinox at the pole
epoch t0:

    ψ(t) = ψ̇ (t − t0) + Δψ(t),    ε(t) = ε̄ + Δε(t),

with the catalogue pole the instantaneous axis at t0: ε̄ and the mean equinox are the catalogue's
obliquity and equinox with the series' own Δε(t0), Δψ(t0) removed (exactly, not by iteration: the
lunisolar series depend on time only). ``axis="figure"`` serves the figure-axis series (the Oppolzer
terms included: the analogue of the IAU's CIP), ``axis="angular_momentum"`` the angular-momentum one.

The error estimate (:func:`estimate_terms`) is an upper bound on the angle between the served pole and
the real Earth's, taking IAU 2006/2000A (ERFA) as the real Earth to within its published accuracy:

* ``nutation_residual``: our series minus ``erfa.nut00a`` moves the pole by at most E (the
  envelope of sin ε|Δψ| + |Δε| measured over 1900–2100, ``data/lunisolar.toml [served_track]``)
  at t, plus what it moves it at t0 (computed exactly: the mean pole inherits it);
* ``hd_scaling``: an H_d other than the one E was measured with scales every term (0 at that H_d);
* ``precession``: our linear ψ̇ (t − t0) at fixed ε̄ (the torque's rate with the geodesic precession,
  :mod:`ephem.orbit.relativity`) against IAU 2006's ψ_A and ω_A (the planetary and second-order parts of ψ_A that a
  first-order theory lacks, the ecliptic's motion), plus the catalogue orbit normal's tilt from the J2000
  ecliptic times the angle precessed;
* ``ecliptic_motion``: IAU 2000A applies the nutation on the ecliptic of date, we on the fixed one;
* ``iau_reference``: IAU 2006/2000A against the observed pole;
* ``axis_relation`` (angular-momentum axis only): IAU 2000A gives the CIP, the figure axis's forced
  motion; the real angular momentum differs from it by the Earth's own Oppolzer offsets, taken no
  larger than 1.5 times the rigid ones, to which ours are added (2.5 times the rigid sum);
* ``rotation_averaging``: what averaging over the rotation leaves out for the Sun alone
  (:func:`ephem.forced.physics_errors.rotation_averaging_bound` with the Oppolzer offset modelled: the semi-diurnal
  terms, the start, the second-order drift and the next order), scaled by the lunisolar-to-solar torque (the
  Oppolzer offsets are in the figure series or in ``axis_relation``);
* ``free_wobble`` / ``free_wobble_model`` (figure axis) as the ladder's; ``rounding``.

Outside 1900–2100 (where the residual was measured) the track is refused as not applicable.
Radians and days unless a name says otherwise.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..theory import cost
from ..base.budget import Cost, charge
from ..bodies.catalogue import Body, is_earth
from ..base.constants import ARCSEC, J2000_JD, JULIAN_YEAR_DAYS, MAS
from ..base.constants import JULIAN_CENTURY_DAYS as DAYS_PER_CENTURY
from ..base.errors import InvalidInputError, NotApplicableError
from ..rotation.free_motion import add_free_wobble, free_wobble_bound, wobble_model_bound
from ..orbit.geometry import icrf_to_ecliptic_matrix, spin_geometry, unit_vector
from ..orbit.de421 import tdb_date
from ..orbit.kepler import mean_motion_rad_per_day
from ..forced.kinoshita import eccentricity_factor, mean_pole, pole_displacement_sum, pole_displacements, scaling_factor
from ..theory.tracks import ROUNDING, pole_vectors, with_free_wobble
from ..forced.describe import model_info
from ..orbit.lunar import delaunay_arguments, delaunay_rates, lunisolar_data, obliquity_arcsec
from .lunisolar import earth_lunisolar, term_amplitudes
from ..forced.precession_nutation import Track, cached_model, model_for
from ..forced.physics_errors import rotation_averaging_bound
from ..orbit.relativity import geodesic_precession_rate
from ..longterm.averaged_spin import SpinConstants, spin_constants
from ..theory.interface import Estimate, SpectrumExport, SpinAxisTheory, Spectrum, cheapest_within
from ..theory.results import (COVERS_NOTHING_TRUNCATED, COVERS_TRUNCATION, NutationResult, NutationTerm,
                              PrecessionResult, RateSigmas, selection)
from ..forced.catalogue_sigmas import dynamical_ellipticity_sigma, no_uncertainty_reasons
from ..forced.uncertainty import SCALAR_KEYS
from ..base.units import in_unit
from ..orbit.lunar import MIN_CUT_MAS, check_cut

#: Sidebands ±j ψ̇ a track carries about each lunisolar term (the Earth's precession is slow, its terms many)
TRACK_SIDEBANDS = 1
#: Amplitude cut of the served track's series (mas): the cut the residual envelope was measured with.
TRACK_CUT_MAS = 0.1
#: The series are built at IAU 2006's ε_A; a pole whose mean obliquity departs by more is refused.
MAX_OBLIQUITY_MISMATCH = 60.0 * ARCSEC
#: The tides' secular change of the precession constant, which the averaged spin equation leaves out (relative per
#: year; the long-term estimate's α neighbour drifts at it). The Moon's share of α goes as a⁻³ with the Moon receding
#: at 3.82 ± 0.07 cm/yr (lunar laser ranging: Dickey et al. 1994, Science 265, 482) from 3.844e8 m; the whole of α
#: as H_d/ω with H_d ∝ ω² (the figure follows the spin over such spans), i.e. as ω, which tidal braking slows at
#: 6.39 ± 0.03e-22 rad/s² (the predicted tidal deceleration of Morrison, Stephenson, Hohenkerk & Zawilski 2021,
#: "Addendum 2020 to 'Measurement of the Earth's rotation: 720 BC to AD 2015'", Proc. R. Soc. A 477) from
#: 7.292115e-5 rad/s: 2.77e-10 per year. Both lower α towards the future; the magnitudes add (about 4.8e-10 per
#: year with the Moon's 69 % share), a sign-blind bound, as La2004's own tidal parameters are not ours.
MOON_RECESSION_PER_YEAR = 0.0382 / 3.844e8
SPIN_BRAKING_PER_YEAR = 6.39e-22 / 7.292115e-5 * 86400.0 * JULIAN_YEAR_DAYS


def tidal_constant_drift(moon_share: float) -> float:
    """The relative change of the precession constant per year that tides cause (:data:`MOON_RECESSION_PER_YEAR`,
    :data:`SPIN_BRAKING_PER_YEAR`), for the Moon's share ``moon_share`` of it."""
    return 3.0 * MOON_RECESSION_PER_YEAR * moon_share + SPIN_BRAKING_PER_YEAR


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
AXIS_ASSUMPTIONS = {
    "figure": "the pole served is the figure axis's forced motion (Oppolzer terms included: the analogue of "
              "the IAU's CIP); the free wobble is left out and counted in the estimate (free_wobble)",
    "figure+wobble": "the pole served is the figure axis: the forced motion (Oppolzer terms included) plus the "
                     "torque-free rigid-body wobble (given J and phase)",
    "angular_momentum": "the pole served is the angular momentum (the series without the Oppolzer terms), "
                        "which the free wobble does not move",
}


def _data() -> dict:
    return lunisolar_data()


def _lower(perturbers) -> tuple[str, ...]:
    return tuple(p.lower() for p in perturbers)


@dataclass(frozen=True, eq=False)
class LunisolarEarth:
    """The Earth's lunisolar precession-nutation from the catalogue's pole and orbit (radians, days)."""

    body: Body
    series: object                       # ephem.earth.lunisolar.LunisolarSeries
    axis: str
    perturbers: tuple[str, ...]          # canonical names ("Moon", "Sun")
    obliquity: float                     # ε̄: mean obliquity on the catalogue orbit at t0
    pole_epoch: float                    # t0
    nutation_at_pole_epoch: tuple[float, float]
    icrf_from_orbit: np.ndarray = field(repr=False)   # columns: mean equinox at t0, W × it, W (ICRF)
    orbit_tilt: float = 0.0              # the catalogue orbit normal from the J2000 ecliptic pole
    geodesic_rate: float = 0.0           # Ω_gp (rad/day): the geodesic precession the track adds (ephem.orbit.relativity)

    @property
    def precession_rate(self) -> float:
        """ψ̇ of the torque (rad/day): the first-order lunisolar rate (the precession answer's)."""
        return float(self.series.precession_rate)

    @property
    def track_rate(self) -> float:
        """The track's ψ̇ (rad/day): the torque's less the geodesic precession, which turns the axis about the
        orbit normal in the orbital (prograde) sense."""
        return self.precession_rate - self.geodesic_rate

    @property
    def hd(self) -> float:
        return self.series.hd

    @property
    def spin_rate(self) -> float:
        return self.series.spin_rate

    @property
    def scaling_factor(self) -> float:
        """2 ψ̇ / cos ε̄: the K of one perturber on a circular orbit in the ecliptic giving the same rate."""
        return 2.0 * self.precession_rate / math.cos(self.obliquity)

    def angles(self, jd_tdb):
        """ψ, Δψ, Δε, ε (radians) at JD TDB."""
        t = np.asarray(jd_tdb, dtype=float)
        dpsi, deps = self.series.nutation_at(t)
        return self.track_rate * (t - self.pole_epoch) + dpsi, dpsi, deps, self.obliquity + deps

    def track(self, jd_tdb) -> Track:
        t = np.asarray(jd_tdb, dtype=float)
        psi, dpsi, deps, eps = self.angles(t)
        se = np.sin(eps)
        v = np.stack([se * np.sin(psi), se * np.cos(psi), np.cos(eps)], axis=-1) @ self.icrf_from_orbit.T
        ra = np.remainder(np.arctan2(v[..., 1], v[..., 0]), 2.0 * math.pi)
        dec = np.arctan2(v[..., 2], np.hypot(v[..., 0], v[..., 1]))
        return Track(t, psi, dpsi, deps, eps, ra, dec)


def check_earth(body: Body) -> None:
    if not is_earth(body) or body.orbit.center != "Sun":
        raise NotApplicableError(body.name, "the lunisolar theory (the Moon as a perturber) is modelled for the "
                                 "Earth only")


@lru_cache(maxsize=64)
def lunisolar_earth(body: Body, axis: str = "figure", cut_mas: float = TRACK_CUT_MAS,
                    perturbers: tuple[str, ...] = ("Moon", "Sun")) -> LunisolarEarth:
    """The lunisolar model of the Earth ``body`` (its H_d, spin rate, pole and orbit)."""
    check_earth(body)
    series = earth_lunisolar(cut_mas=cut_mas, perturbers=_lower(perturbers), hd=float(body.hd), axis=axis,
                             spin_rate=body.spin_rate_rad_per_day)
    ecl_from_icrf = icrf_to_ecliptic_matrix()
    s_ecl = ecl_from_icrf @ unit_vector(math.radians(body.pole.ra_deg), math.radians(body.pole.dec_deg))
    o = body.orbit
    geo = spin_geometry(s_ecl, *(math.radians(x) for x in (o.i_deg, o.node_deg, o.peri_deg)), body.name)
    t0 = body.pole.epoch_jd_tdb
    # the lunisolar series does not depend on the mean pole: one pass of the fixed point is exact
    eps_mean, _, dpsi0, deps0 = mean_pole(geo.obliquity, geo.equinox_to_pericentre,
                                          lambda *_: series.nutation_at(np.array(t0)), passes=1)
    eps_a = obliquity_arcsec((t0 - J2000_JD) / DAYS_PER_CENTURY) * ARCSEC
    if abs(eps_mean - eps_a) > MAX_OBLIQUITY_MISMATCH:
        raise NotApplicableError(body.name, (
            f"the pole gives a mean obliquity of {math.degrees(eps_mean):.6f} deg on the orbit, "
            f"{abs(eps_mean - eps_a) / ARCSEC:.1f} arcsec from IAU 2006's {math.degrees(eps_a):.6f} deg at its "
            f"epoch; the lunisolar series are built at the latter (accepted within "
            f"{MAX_OBLIQUITY_MISMATCH / ARCSEC:g} arcsec)"))
    gamma, y_true, w = geo.orbit_frame
    x_mean = math.cos(dpsi0) * gamma + math.sin(dpsi0) * y_true
    icrf_from_orbit = ecl_from_icrf.T @ np.vstack([x_mean, np.cross(w, x_mean), w]).T
    tilt = math.atan2(float(np.linalg.norm(w[:2])), float(w[2]))
    return LunisolarEarth(body, series, axis, tuple(perturbers), eps_mean, t0, (dpsi0, deps0), icrf_from_orbit, tilt,
                          geodesic_precession_rate(o.a_au, o.e, o.center))


# ----------------------------------------------------------------------------- the error estimate

def _poly(coef, T):
    T = np.asarray(T, dtype=float)
    out = np.zeros_like(T)
    for c in reversed(coef):
        out = out * T + c
    return out * ARCSEC


def displacement_sum(series, obliquity: float) -> float:
    """The most a lunisolar series' nutation moves the pole (radians; its coefficients are in mas)."""
    return pole_displacement_sum(series.coefficients, obliquity) * MAS


@lru_cache(maxsize=64)
def _residual_at_pole_epoch(model: LunisolarEarth) -> float:
    """sin ε|Δψ| + |Δε| of the served series minus ``erfa.nut00a`` at the pole epoch (radians): the mean
    pole is the catalogue pole with our nutation removed, so it inherits this."""
    import erfa

    t0 = np.array([model.pole_epoch])
    dpsi, deps = model.series.nutation_at(t0)
    ref_psi, ref_eps = erfa.nut00a(t0, 0.0)
    return float(abs(math.sin(model.obliquity)) * abs(dpsi[0] - ref_psi[0]) + abs(deps[0] - ref_eps[0]))


@lru_cache(maxsize=64)
def _oppolzer_sum(model: LunisolarEarth) -> float:
    """Σ_k of the pole displacement between the figure-axis and angular-momentum series (radians)."""
    kw = dict(cut_mas=model.series.cut_mas, perturbers=model.series.perturbers, hd=model.hd,
              spin_rate=model.spin_rate)
    fig, mom = earth_lunisolar(axis="figure", **kw), earth_lunisolar(axis="angular_momentum", **kw)
    lookup = {tuple(k): i for i, k in enumerate(mom.multipliers)}
    rows = [c - (mom.coefficients[lookup[tuple(k)]] if tuple(k) in lookup else 0.0)
            for k, c in zip(fig.multipliers, fig.coefficients)]
    on_figure = {tuple(k) for k in fig.multipliers}
    rows += [c for k, c in zip(mom.multipliers, mom.coefficients) if tuple(k) not in on_figure]  # one axis only
    return pole_displacement_sum(np.array(rows).reshape(-1, 4), model.obliquity) * MAS


def window() -> tuple[float, float]:
    d = _data()["served_track"]
    return float(d["window_start_jd_tdb"]), float(d["window_stop_jd_tdb"])


def unavailable(model: LunisolarEarth, jd_tdb: np.ndarray) -> str | None:
    """Why the track cannot be served with an estimate at these epochs, or None."""
    lo, hi = window()
    t = np.asarray(jd_tdb, dtype=float)
    need = [model.pole_epoch] + ([float(t.min()), float(t.max())] if t.size else [])
    if min(need) < lo or max(need) > hi:
        return (f"the lunisolar track's error was measured against IAU 2006/2000A from {tdb_date(lo)} to {tdb_date(hi)} "
                f"only; these epochs (with the pole epoch) need JD {min(need):.1f} to {max(need):.1f}. The Sun-only "
                "theory (perturbers=sun) serves any epoch, but leaves out the Moon's two thirds of the Earth's "
                "precession")
    if set(model.perturbers) != {"Moon", "Sun"}:
        return ("the lunisolar track's error was measured with both the Moon and the Sun; a track under "
                f"{' and '.join(model.perturbers)} alone is no model of the real Earth")
    return None


def estimate_terms(model: LunisolarEarth, jd_tdb) -> dict:
    """The named error terms (radians) of the track at the epochs: see the module docstring. Raises
    :class:`NotApplicableError` outside the window the residual was measured over."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    why = unavailable(model, t)
    if why is not None:
        raise NotApplicableError(model.body.name, why)
    d, prec = _data()["served_track"], _data()["iau2006_precession"]
    t0, eps = model.pole_epoch, model.obliquity
    se = abs(math.sin(eps))
    disp = displacement_sum(model.series, eps)
    envelope = d["residual_envelope_mas"] * MAS
    terms = {"nutation_residual": envelope + _residual_at_pole_epoch(model)}
    # always named (0 at the measured H_d): a key that appeared only when H_d != the measured one would
    # come and go with the last bit of H_d (issue 29)
    terms["hd_scaling"] = abs(model.hd / d["hd"] - 1.0) * disp
    # the mean pole's drift against IAU 2006, on a grid spanning the epochs (a smooth function of t)
    lo, hi = float(t.min()), float(t.max())
    grid = np.unique(np.concatenate([np.linspace(lo, hi, 65), [t0]])) if hi > lo else np.array([lo])
    T, T0 = (grid - J2000_JD) / DAYS_PER_CENTURY, (t0 - J2000_JD) / DAYS_PER_CENTURY
    precessed = model.track_rate * (grid - t0)
    dpsi = precessed - (_poly(prec["psi_a"], T) - _poly(prec["psi_a"], T0))
    domega = _poly(prec["omega_a"], T) - _poly(prec["omega_a"], T0)
    terms["precession"] = float(np.max(se * np.abs(dpsi) + np.abs(domega) + model.orbit_tilt * np.abs(precessed)))
    pi_t, pi_0 = np.abs(_poly(prec["pi_a"], T)), abs(float(_poly(prec["pi_a"], T0)))
    terms["ecliptic_motion"] = float(disp * np.max(2.0 * model.orbit_tilt + pi_t + pi_0) / se)
    terms["iau_reference"] = (d["reference_nutation_mas"]
                              + d["reference_precession_mas_per_century2"] * float(np.max(T * T))) * MAS
    if model.axis == "angular_momentum":
        terms["axis_relation"] = 2.5 * _oppolzer_sum(model)
    sun = cached_model(model.body)
    if model.body.moments is not None:
        ratio = abs(model.precession_rate / sun.precession_rate)
        terms["rotation_averaging"] = ratio * rotation_averaging_bound(model.body, sun, t, model.axis, "oppolzer")
    terms["rounding"] = ROUNDING
    return terms


def estimates(model: LunisolarEarth, jd_tdb, wobble=None) -> list:
    """The lunisolar rung's estimates (:class:`ephem.sun.ladder.Estimate`): without the free wobble and, for the
    figure axis with a wobble phase, with it."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    terms = estimate_terms(model, t)
    unestimated = () if model.body.moments is not None else ("rotation_averaging",)
    if model.axis != "figure":
        return [Estimate("lunisolar", None, terms, unestimated=unestimated)]
    left_out = free_wobble_bound(model.body) if wobble is None else wobble.J_arcsec * ARCSEC
    out = [Estimate("lunisolar", None, terms if left_out is None else {**terms, "free_wobble": left_out},
                    unestimated=unestimated + (("free_wobble",) if left_out is None else ()))]
    if wobble is not None:
        modelled = wobble_model_bound(model.body, wobble, t, pole_vectors(model.track(t)),
                                      pole_at(model, wobble.epoch_jd_tdb)) + ROUNDING
        out.append(Estimate("lunisolar", None, {**terms, "free_wobble_model": modelled}, unestimated=unestimated,
                            free_wobble=True))
    return out


def pole_at(model: LunisolarEarth, jd_tdb: float) -> np.ndarray:
    return pole_vectors(model.track(np.array([float(jd_tdb)])))[0]


def choose(model: LunisolarEarth, candidates: list, tolerance: float, wobble=None):
    """The cheapest candidate within ``tolerance`` (radians), else :class:`NotApplicableError` naming the best
    (:func:`ephem.sun.ladder.cheapest_within`)."""
    return cheapest_within(candidates, tolerance, model.body.name, wobble is not None)


def add_wobble(model: LunisolarEarth, track: Track, wobble) -> Track:
    """The figure axis: the forced track with the free wobble added about it (:mod:`ephem.rotation.free_motion`)."""
    figure = add_free_wobble(model.body, wobble, track.jd_tdb, pole_vectors(track), pole_at(model, wobble.epoch_jd_tdb))
    return with_free_wobble(model, track, figure)


# ----------------------------------------------------------------------------- the nutation answer's cut

@lru_cache(maxsize=32)
def _all_terms(body: Body, axis: str, perturbers: tuple[str, ...]):
    return lunisolar_earth(body, axis, 0.0, perturbers).series


def omitted_bound(body: Body, cut_mas: float, axis: str = "figure", perturbers=("Moon", "Sun")) -> float:
    """Σ of the pole displacements (radians) of the terms the cut leaves out (against the cut-free series)."""
    full = _all_terms(body, axis, tuple(perturbers))
    c = full.coefficients
    amp = term_amplitudes(c)
    dropped = amp < cut_mas
    eps = lunisolar_earth(body, axis, TRACK_CUT_MAS, tuple(perturbers)).obliquity
    return pole_displacement_sum(c[dropped], eps) * MAS


def cut_for_tolerance(body: Body, tolerance: float, axis: str = "figure", perturbers=("Moon", "Sun")) -> float:
    """The largest amplitude cut (mas, at least :data:`MIN_CUT_MAS`) whose omitted terms move the pole by no
    more than ``tolerance`` (radians) in all; :class:`NotApplicableError` when even the smallest cut does not."""
    full = _all_terms(body, axis, tuple(perturbers))
    c = full.coefficients
    amp = term_amplitudes(c)
    eps = lunisolar_earth(body, axis, TRACK_CUT_MAS, tuple(perturbers)).obliquity
    disp = pole_displacements(c, eps) * MAS
    order = np.argsort(amp)                       # drop the smallest terms first
    dropped = np.cumsum(disp[order])
    n = int(np.searchsorted(dropped, tolerance, side="right"))   # the n smallest may go
    cut = float(amp[order[n]]) if n < amp.size else float(amp.max()) * 2.0
    if cut < MIN_CUT_MAS:
        if omitted_bound(body, MIN_CUT_MAS, axis, perturbers) > tolerance:
            raise NotApplicableError(body.name, (
                f"no amplitude cut meets the tolerance of {tolerance / MAS:.6g} mas: the smallest served "
                f"({MIN_CUT_MAS:g} mas) leaves out terms moving the pole by "
                f"{omitted_bound(body, MIN_CUT_MAS, axis, perturbers) / MAS:.6g} mas in all"))
        cut = MIN_CUT_MAS
    return cut


# ----------------------------------------------------------------------------- the theory's interface (ephem.theory.interface)

def describe_model(b: Body, per: tuple[str, ...], lm) -> dict:
    """``model`` of a lunisolar answer: model_info's keys (the spin-orbit ratio and epochs are the Earth's
    about the Sun) with the lunisolar theory, its assumptions and the H_d it used, and why."""
    info = model_info(cached_model(b), b, list(ASSUMPTIONS))
    rate = lm.precession_rate * JULIAN_YEAR_DAYS / ARCSEC
    track = lm.track_rate * JULIAN_YEAR_DAYS / ARCSEC
    iau = _data()["precession_reference"]["psi_a_rate_arcsec_per_century"] / 100.0
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
    models = ("lunisolar",)
    descriptions = {"lunisolar": SELECTION_DESCRIPTION}
    track_cut_mas = TRACK_CUT_MAS

    @classmethod
    def serves(cls, body: Body, perturbers: tuple[str, ...]) -> bool:
        return "Moon" in perturbers

    @property
    def model(self) -> LunisolarEarth:
        return lunisolar_earth(self.body, self.axis, TRACK_CUT_MAS, self.perturbers)

    @classmethod
    def how_to_reach(cls, body: Body) -> str:
        return "it models the Earth with the Moon among the perturbers (perturbers=moon,sun, the Earth's default)"

    def default_model(self, order: int | None) -> str:
        return "lunisolar"

    def check_request(self, model: str | None, order: int | None) -> None:
        model_for(self.body, self.body.dataset)              # applicability (the Moon: synchronous)
        no_order(self.body, order)

    def choice_cost(self, start: float, stop: float, count: int) -> Cost:
        return Cost((cost.lunisolar_answer(),))

    def track_cost(self, model, order, start, stop, count, free_wobble, rotation_scale=False) -> Cost:
        return Cost((cost.lunisolar_sum(count),) + ((cost.free_rotation("exact", count, 0.0),) if free_wobble else ()))

    def estimates(self, jd_tdb) -> list[Estimate]:
        return estimates(self.model, jd_tdb, self.wobble)

    def named(self, jd_tdb, model, order):
        # the model follows the wobble whenever its phase is given
        candidates = self.estimates(jd_tdb)
        return candidates[-1] if self.wobble is not None else candidates[0]

    def track(self, est, model, order, t0, step, count) -> Track:
        return self.track_at(model, order, self.grid(t0, step, count), est is not None and est.free_wobble)

    def track_at(self, model, order, jd_tdb, free_wobble=False) -> Track:
        tr = self.model.track(np.asarray(jd_tdb, dtype=float))
        return add_wobble(self.model, tr, self.wobble) if free_wobble else tr

    def describe(self, est, model, order, with_wobble) -> dict:
        info = describe_model(self.body, self.perturbers, self.model)
        info["assumptions"] = [AXIS_ASSUMPTIONS["figure+wobble" if with_wobble else self.axis]] + info["assumptions"]
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
        return Cost((cost.lunisolar_answer(),))

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
        return PrecessionResult(b, lm.obliquity, lm.hd, lm.scaling_factor, lm.precession_rate,
                                rate_sigmas(b, lm), uncertainty_summary(b), info,
                                selection(self, "lunisolar", None, None, 1e3 * (time.perf_counter() - start),
                                          tolerance, covers=COVERS_NOTHING_TRUNCATED))

    def nutation(self, order: int | None, tolerance: float | None, cut_mas, start: float) -> NutationResult:
        b, per = self.body, self.perturbers
        self._check_answer(order)
        if tolerance is not None and cut_mas is not None:
            raise InvalidInputError("cut_mas", "give either cut_mas or tolerance_mas, not both", b.name)
        if cut_mas is not None:
            cut = check_cut(in_unit(cut_mas, "mas", "cut_mas"))
        elif tolerance is not None:
            cut = cut_for_tolerance(b, tolerance, "figure", per)
        else:
            cut = TRACK_CUT_MAS
        charge(self.answer_cost(order, nutation=True), b.name)
        lm = lunisolar_earth(b, "figure", cut, per)
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
        omitted = omitted_bound(b, cut, "figure", per)
        info = describe_model(b, per, lm)
        info["assumptions"].append("terms: Δψ = Σ (S + Ṡ T) sin φ + (C + Ċ T) cos φ (likewise Δε), φ = the "
                                   "multipliers · (l, l′, F, D, Ω), T Julian centuries TDB from J2000; `multiple` is "
                                   "null (no single mean anomaly), periods are signed (negative: the argument "
                                   "decreases); half peak-to-peak over 1900-2100")
        chosen = selection(self, "lunisolar", None, omitted, 1e3 * (time.perf_counter() - start), tolerance,
                           {"truncation": omitted}, covers=COVERS_TRUNCATION, cut_mas=cut)
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
    """Half the peak-to-peak Δψ, Δε (radians) of a lunisolar series over 1900-2100, sampled every 0.5 d."""
    lo, hi = window()
    dpsi, deps = lm.series.nutation_at(np.arange(lo, hi + 0.25, 0.5))
    return 0.5 * float(np.ptp(dpsi)), 0.5 * float(np.ptp(deps))


def no_order(body: Body, order) -> None:
    """An e-order does not apply to the lunisolar series (cut by amplitude instead)."""
    if order is not None:
        raise NotApplicableError(body.name, f"an e-order (order={order!r}) truncates the single-perturber theory's "
                                 "Hansen coefficients; the lunisolar series is cut by amplitude instead (cut_mas, or "
                                 "tolerance_mas). Pass perturbers=sun for the Sun-only theory")
