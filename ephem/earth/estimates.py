"""The error estimate of the Earth's lunisolar track, and the amplitude cut a tolerance asks of its series.

The estimate (:func:`estimate_terms`) is an upper bound on the angle between the served pole and the real
Earth's, taking IAU 2006/2000A (ERFA) as the real Earth to within its published accuracy:

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

Outside 1900–2100 (where the residual was measured) the track is refused as not applicable. The non-rigid rung's
terms (:func:`nonrigid_terms`) are fewer: it serves IAU 2006's precession on the ecliptic of date, so it has no
``precession`` or ``ecliptic_motion`` term, and its ``nutation_residual`` is its own measured envelope.
"""
from __future__ import annotations

import math
from functools import lru_cache
import numpy as np
from ..bodies.catalogue import Body
from ..base.constants import ARCSEC, J2000_JD, MAS, ROUNDING
from ..base.constants import JULIAN_CENTURY_DAYS as DAYS_PER_CENTURY
from ..base.errors import NotApplicableError
from ..rotation.free_motion import add_free_wobble, free_wobble_bound, wobble_model_bound
from ..orbit.de421 import tdb_date
from ..forced.kinoshita import pole_displacement_sum, pole_displacements
from ..theory.tracks import pole_vectors, with_free_wobble
from ..orbit.lunar import lunisolar_data
from .lunisolar import earth_lunisolar, term_amplitudes
from ..forced.precession_nutation import Track, cached_model
from ..forced.physics_errors import rotation_averaging_bound
from ..theory.choice import Candidates, cheapest
from ..theory.results import Estimate
from ..orbit.lunar import MIN_CUT_MAS
from .model import LunisolarEarth, NonRigidEarth, TRACK_CUT_MAS, check_earth, lunisolar_earth, residual_envelope
from .nonrigid import non_rigid_series
from ..orbit.geometry import unit_vector
from ..forced.integration import angular_separation


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
    d = lunisolar_data()["served_track"]
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
    d, prec = lunisolar_data()["served_track"], lunisolar_data()["iau2006_precession"]
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
    return {**terms, **reference_terms(model, t)}


def reference_terms(model: LunisolarEarth, t: np.ndarray) -> dict:
    """The terms both Earth rungs share (radians): ``iau_reference`` (IAU 2006/2000A against the observed pole, its
    precession part growing as T² from J2000, largest at an end of the epochs or at t0), ``axis_relation`` (the
    angular momentum only), ``rotation_averaging`` and ``rounding``."""
    d = lunisolar_data()["served_track"]
    T = (np.array([float(t.min()), float(t.max()), model.pole_epoch]) - J2000_JD) / DAYS_PER_CENTURY
    terms = {"iau_reference": (d["reference_nutation_mas"]
                               + d["reference_precession_mas_per_century2"] * float(np.max(T * T))) * MAS}
    if model.axis == "angular_momentum":
        terms["axis_relation"] = 2.5 * _oppolzer_sum(model)
    sun = cached_model(model.body)
    if model.body.moments is not None:
        ratio = abs(model.precession_rate / sun.precession_rate)
        terms["rotation_averaging"] = ratio * rotation_averaging_bound(model.body, sun, t, model.axis, "oppolzer")
    terms["rounding"] = ROUNDING
    return terms


@lru_cache(maxsize=16)
def nonrigid_earth(body: Body, axis: str = "figure", perturbers: tuple[str, ...] = ("Moon", "Sun")) -> NonRigidEarth:
    """The non-rigid rung's model of the Earth ``body`` for ``axis`` (:class:`ephem.earth.model.NonRigidEarth`): the
    lunisolar model at the served cut and its series times the IERS 1996 transfer function."""
    rigid = lunisolar_earth(body, axis, TRACK_CUT_MAS, perturbers)
    return NonRigidEarth(rigid, non_rigid_series(rigid.series))


#: The non-rigid rung follows IAU 2006's pole, not the body's: a pole further than this from it at its epoch is not
#: the Earth's (the catalogue's is 2.4 mas from it; a user's Earth with another pole gets the rigid rung only)
NONRIGID_POLE_MISMATCH = ARCSEC


def nonrigid_unavailable(model: NonRigidEarth, jd_tdb: np.ndarray) -> str | None:
    """Why the non-rigid rung cannot serve these epochs, or None."""
    why = unavailable(model.rigid, jd_tdb)
    if why is not None:
        return why
    b = model.body
    given = unit_vector(math.radians(b.pole.ra_deg), math.radians(b.pole.dec_deg))
    offset = float(angular_separation(model.pole(np.array([b.pole.epoch_jd_tdb]))[0][0], given))
    if offset > NONRIGID_POLE_MISMATCH:
        return (f"the non-rigid rung serves IAU 2006's pole, {offset / ARCSEC:.3g} arcsec from this body's at its "
                f"epoch (accepted within {NONRIGID_POLE_MISMATCH / ARCSEC:g} arcsec): the rigid rung follows the "
                "body's own pole")
    return None


def nonrigid_terms(model: NonRigidEarth, jd_tdb) -> dict:
    """The non-rigid rung's named error terms (radians) at the epochs, against the real Earth as IAU 2006/2000A
    gives it (:class:`ephem.earth.model.NonRigidEarth`):

    * ``nutation_residual``: the non-rigid series minus ``erfa.nut00a`` moves the pole by at most the measured
      envelope (``data/lunisolar.toml [nonrigid_track]``): MHB2000's anelastic and ocean corrections, the
      planetary nutation, the terms under the cut; the precession is IAU 2006's own, applied as ERFA does;
    * ``hd_scaling``: an H_d other than the measured one scales the nutation, and the precession it implies departs
      from IAU 2006's (which the rung serves) by ψ̇'s relative change over the span;
    * ``iau_reference``, ``axis_relation``, ``rotation_averaging``, ``rounding``: as the rigid rung's."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    rigid = model.rigid
    why = unavailable(rigid, t)
    if why is not None:
        raise NotApplicableError(model.body.name, why)
    d = lunisolar_data()["served_track"]
    se = abs(math.sin(model.obliquity))
    span = float(np.max(np.abs(t - rigid.pole_epoch)))
    terms = {"nutation_residual": residual_envelope() * MAS,
             "hd_scaling": abs(model.hd / d["hd"] - 1.0) * (displacement_sum(model.series, model.obliquity)
                                                          + se * abs(rigid.precession_rate) * span)}
    return {**terms, **reference_terms(rigid, t)}


def estimates(model: LunisolarEarth | NonRigidEarth, jd_tdb, wobble=None, counts_free_wobble: bool = True) -> list:
    """A rung's estimates (:class:`ephem.theory.results.Estimate`), ``lunisolar`` for the rigid model and
    ``nonrigid`` for the non-rigid one: without the free wobble and, for the figure axis with a wobble phase, with
    it. The non-rigid rung outside its domain is one unavailable estimate saying why. ``counts_free_wobble`` False:
    the figure axis's forced motion (the CIP's analogue), whose free wobble is polar motion, not an error."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    rung = "nonrigid" if isinstance(model, NonRigidEarth) else "lunisolar"
    if rung == "nonrigid":
        why = nonrigid_unavailable(model, t)
        if why is not None:
            return [Estimate(rung, None, {}, available=False, why_not=why)]
        terms = nonrigid_terms(model, t)
    else:
        terms = estimate_terms(model, t)
    unestimated = () if model.body.moments is not None else ("rotation_averaging",)
    if model.axis != "figure" or not counts_free_wobble:
        return [Estimate(rung, None, terms, unestimated=unestimated)]
    left_out = free_wobble_bound(model.body) if wobble is None else wobble.J_arcsec * ARCSEC
    out = [Estimate(rung, None, terms if left_out is None else {**terms, "free_wobble": left_out},
                    unestimated=unestimated + (("free_wobble",) if left_out is None else ()))]
    if wobble is not None:
        modelled = wobble_model_bound(model.body, wobble, t, pole_vectors(model.track(t)),
                                      pole_at(model, wobble.epoch_jd_tdb)) + ROUNDING
        out.append(Estimate(rung, None, {**terms, "free_wobble_model": modelled}, unestimated=unestimated,
                            free_wobble=True))
    return out


def pole_at(model: LunisolarEarth, jd_tdb: float) -> np.ndarray:
    return pole_vectors(model.track(np.array([float(jd_tdb)])))[0]


def add_wobble(model: LunisolarEarth, track: Track, wobble) -> Track:
    """The figure axis: the forced track with the free wobble added about it (:mod:`ephem.rotation.free_motion`)."""
    figure = add_free_wobble(model.body, wobble, track.jd_tdb, pole_vectors(track), pole_at(model, wobble.epoch_jd_tdb))
    return with_free_wobble(model, track, figure)


# ----------------------------------------------------------------------------- the nutation answer's cut

@lru_cache(maxsize=32)
def _all_terms(body: Body, axis: str, perturbers: tuple[str, ...]):
    """The cut-free series of the Earth ``body``: the coefficients only, as :func:`lunisolar_earth` builds them, but
    without its mean pole (which would evaluate all 17 000 terms at the pole epoch: 0.3 s no caller here needs)."""
    check_earth(body)
    return earth_lunisolar(cut_mas=0.0, perturbers=tuple(p.lower() for p in perturbers), hd=float(body.hd), axis=axis,
                           spin_rate=body.spin_rate_rad_per_day)


def omitted_bound(model: LunisolarEarth, cut_mas: float) -> float:
    """Σ of the pole displacements (radians) of the terms the cut leaves out (against the cut-free series) of the
    Earth's lunisolar ``model`` at the track's cut (its body, axis and perturbers; its mean obliquity)."""
    full = _all_terms(model.body, model.axis, model.perturbers)
    c = full.coefficients
    amp = term_amplitudes(c)
    dropped = amp < cut_mas
    return pole_displacement_sum(c[dropped], model.obliquity) * MAS


def cut_candidates(model: LunisolarEarth) -> Candidates:
    """The amplitude cuts (mas) a tolerance may choose for the nutation terms of the Earth's lunisolar ``model`` at
    the track's cut (its body, axis and perturbers): the n-th drops the n smallest terms (n = 0 ... all, the last cut
    twice the largest amplitude), priced by the terms it keeps and bounded by the sum of the pole displacements of
    those it drops (radians, against the cut-free series). Arrays: 17 000 candidates."""
    full = _all_terms(model.body, model.axis, model.perturbers)
    c = full.coefficients
    amp = term_amplitudes(c)
    eps = model.obliquity
    disp = pole_displacements(c, eps) * MAS
    order = np.argsort(amp)                       # drop the smallest terms first
    cuts = np.append(amp[order], float(amp.max()) * 2.0 if amp.size else 0.0)
    return Candidates(cuts, np.arange(amp.size, -1, -1, dtype=float),
                      np.concatenate(([0.0], np.cumsum(disp[order]))), tie=0.0, what="amplitude cut")


def cut_for_tolerance(model: LunisolarEarth, tolerance: float) -> float:
    """The largest amplitude cut (mas, at least :data:`MIN_CUT_MAS`) whose omitted terms move the pole of the
    Earth's lunisolar ``model`` (at the track's cut) by no more than ``tolerance`` (radians) in all
    (:func:`ephem.theory.choice.cheapest` of :func:`cut_candidates`: the fewest terms kept);
    :class:`NotApplicableError` when even the smallest cut does not."""
    cut = float(cheapest(cut_candidates(model), tolerance, default=0.0))
    if cut < MIN_CUT_MAS:
        if omitted_bound(model, MIN_CUT_MAS) > tolerance:
            raise NotApplicableError(model.body.name, (
                f"no amplitude cut meets the tolerance of {tolerance / MAS:.6g} mas: the smallest served "
                f"({MIN_CUT_MAS:g} mas) leaves out terms moving the pole by "
                f"{omitted_bound(model, MIN_CUT_MAS) / MAS:.6g} mas in all"))
        cut = MIN_CUT_MAS
    return cut
