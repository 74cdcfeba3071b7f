"""Error terms from physics the fixed-orbit, rotation-averaged theories leave out.

Orbit motion (rungs 1-5). The real orbit is not the fixed Keplerian ellipse of the osculating
elements: its plane turns, the Sun runs ahead of or behind its Keplerian place, and the mean of
(a/r)^3 differs. Rung 5 (``numerical``) integrates the averaged torque along the fixed ellipse, rung 6
(``real_orbit``) along the real orbit, both from the catalogue pole at the pole epoch t0; every
fixed-orbit rung is as far from rung 6 as from rung 5 plus the angle between those two. For a
catalogue body that angle, the *pole gap* g(t), is a fixed function of t (the pole, elements and
pole epoch are the catalogue's). ``tools/derive_orbit_motion.py`` measures it daily over DE421's span
less a margin (1899-2053) and ships, per dataset and body, the largest gap in bins of
τ = t - t0 (:class:`PoleGap`, ``data/orbit_motion/``); the ``orbit_motion`` estimate for a set of
epochs is the largest over the bins their span touches (:func:`orbit_motion_bound`).

Three measured envelopes per body (``data/orbit_motion.toml``, from the real orbit over the same
window) describe the orbit itself:

* the angle δW between the real orbit normal and the Keplerian one, enveloped by
  ``normal_rate`` |t - t_el| + ``normal_acceleration`` (t - t_el)² + ``normal_wobble`` (t_el the
  elements' epoch);
* the Sun's in-plane angle δλ from its Keplerian place, enveloped likewise;
* the relative mismatch κ of the mean torque strength <r^-3>.

A tilt δW of the plane changes the pole's speed by at most K f(e) δW (the averaged torque
(K/2) f(e) (s·W)(W×s) has a W-derivative of norm ≤ 2), which integrates over time; a phase error
δλ moves the nutation by at most Σ_k k A_k δλ (A_k the pole displacement of harmonic k) at each
end of an interval; κ changes ψ̇ by κ ψ̇. Summed from t0, where both rungs start from the same
pole, they bound the gap of a body whose gap was not measured (:func:`envelope_bound`: a catalogue
body given other parameters); summed from the edge of the measured window, they bound how far the
gap can grow beyond it (:func:`growth_beyond`).

Rotation averaging (every rung): see :func:`rotation_averaging_bound` and :mod:`ephem.forced.rotation_scale`.

Radians and days.
"""
from __future__ import annotations

import csv
import math
import tomllib
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..bodies.catalogue import Body
from ..base.paths import data_dir
from ..base.constants import ARCSEC, MAS
from ..orbit.kepler import mean_motion_rad_per_day, solve_kepler, true_anomaly
from .kinoshita import eccentricity_factor, pole_displacements
from .precession_nutation import PrecessionNutation, cached_model
from .rigid_numerics import body_moments
from .rotation_scale import error_terms, sampled_epochs
from ..orbit.de421 import sun_path
from .integration import integrate_spin_axis

#: The gap is sampled at t0 + k days (k whole): the bins' ends are samples.
GAP_STEP_DAYS = 1.0
#: Bins of |τ|: 20 per decade from 1 day (a step of 12%, what the estimate can lose on a span that
#: reaches from t0 into a bin) ...
GAP_BINS_PER_DECADE = 20
#: ... at most 90 days wide: a quarter of the Earth's orbit, an eighth of Mars's or less. A short span
#: far from t0 is charged the largest gap of its bin, and the gap dips towards zero on the orbit's time
#: scale. Worst estimate/gap over every daily start in the window, for spans of 1, 15 and 30 days
#: (rows per body): 30-day bins 22, 7.2, 3.8 (1936); 60-day 55, 9.7, 5.9 (1010); 90-day 87, 9.8, 7.0
#: (705); 120-day 95, 12, 8.4 (554); 180-day 97, 17, 13 (405). 90 days is the widest that keeps every
#: span of 15 days or more within 10; no width bounds the shortest spans.
GAP_BIN_MAX_DAYS = 90
#: Significant digits of the shipped gaps (mas, rounded up).
GAP_DIGITS = 3
#: Relative allowance on the tabulated gap for a rotation-scale variant started from a pole moved by the
#: semi-diurnal term (phase-dependent, not sampled; measured effect ≤ 1.2e-6 of the gap: measure_pole_gap).
START_ALLOWANCE = 1e-5
#: The catalogue values a table was measured for are printed exactly (repr); this admits only the
#: rounding of how they are computed (K from H_d: a few ulp), which moves the gap by as little.
SAME_VALUE_REL = 1e-12


@dataclass(frozen=True)
class PoleGap:
    """The measured gap between rungs 5 and 6 of one catalogue body (radians).

    ``after`` (t ≥ t0) and ``before`` (t ≤ t0) are (ends, gaps): bin i covers |τ| = |t - t0| from
    ends[i-1] (0 for the first) to ends[i] days, both included, and gaps[i] bounds the gap there
    (sampling allowance and both integrations' error included). ``pole`` (RA, Dec in degrees, epoch
    JD TDB) and ``scaling_factor`` (K, rad/day) are what it was measured for; the orbit's elements
    are in :class:`OrbitMotion`.
    """

    pole: tuple[float, float, float]
    scaling_factor: float
    after: tuple[tuple[float, ...], tuple[float, ...]]
    before: tuple[tuple[float, ...], tuple[float, ...]]

    @property
    def pole_epoch(self) -> float:
        return self.pole[2]

    def sides(self):
        """(sign of t - t0, bin ends in days, gaps in radians) for each side."""
        for sign, (ends, gaps) in ((1.0, self.after), (-1.0, self.before)):
            yield sign, np.asarray(ends, dtype=float), np.asarray(gaps, dtype=float)

    def describes(self, body: Body, model: PrecessionNutation) -> bool:
        mine = (*self.pole, self.scaling_factor)
        theirs = (body.pole.ra_deg, body.pole.dec_deg, body.pole.epoch_jd_tdb, model.scaling_factor)
        return all(_same(a, b) for a, b in zip(mine, theirs))


def _same(a: float, b: float) -> bool:
    return abs(a - b) <= SAME_VALUE_REL * max(abs(a), abs(b))


@dataclass(frozen=True)
class OrbitMotion:
    """Envelopes of the real orbit's departure from the Keplerian one (radians, rad/day), and the
    measured pole gap (None where it was not measured)."""

    elements: tuple[float, ...]             # a (au), e, i, node, peri, mean anomaly (deg), epoch (JD TDB)
    normal: tuple[float, float, float]      # (rate, acceleration, wobble) of the tilt envelope
    longitude: tuple[float, float, float]   # the same for the in-plane angle
    torque_mismatch: float
    window: tuple[float, float]
    real_perihelion_au: float               # the real orbit's smallest distance from the Sun in the window
    gap: PoleGap | None = None

    @property
    def elements_epoch(self) -> float:
        return self.elements[-1]

    @staticmethod
    def envelope(coef: tuple[float, float, float], offset_days):
        rate, accel, wobble = coef
        d = np.abs(offset_days)
        return rate * d + accel * d * d + wobble


def orbit_elements(body: Body) -> tuple[float, ...]:
    o = body.orbit
    return (o.a_au, o.e, o.i_deg, o.node_deg, o.peri_deg, o.mean_anomaly_deg, o.epoch_jd_tdb)


def _envelope(offset_days: np.ndarray, angle: np.ndarray) -> tuple[float, float, float]:
    """(rate, acceleration, wobble) with angle <= rate |Δ| + acceleration Δ² + wobble at every sample:
    non-negative least squares for the first two, the wobble what they leave."""
    from scipy.optimize import nnls

    d = np.abs(offset_days) / 36525.0          # centuries: a well-scaled fit
    coef, _ = nnls(np.column_stack([d, d * d]), angle)
    wobble = float(np.max(angle - coef[0] * d - coef[1] * d * d))
    return float(coef[0]) / 36525.0, float(coef[1]) / 36525.0**2, max(wobble, 0.0)


def keplerian_sun_orbit_frame(model: PrecessionNutation, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
    """The Sun's longitude λ from the mean equinox at t0 and its distance r/a on the model's fixed
    ellipse (the same Sun the analytic and numerical rungs use)."""
    m = model.mean_anomaly(jd_tdb)
    e = model.eccentricity
    lam = model.equinox_to_pericentre + true_anomaly(m, e)
    return lam, 1.0 - e * np.cos(solve_kepler(m, e))


def measure_orbit_motion(body: Body, model: PrecessionNutation, start: float, stop: float,
                         step_days: float = 1.0) -> OrbitMotion:
    """Measure the envelopes of :class:`OrbitMotion` against the real orbit over [start, stop] (JD TDB)
    (without the gap: :func:`measure_pole_gap`)."""
    t = np.arange(start, stop, step_days)
    path = sun_path(body, start, stop)
    to_orbit = model.icrf_from_orbit          # orbit frame -> ICRF; rows @ it: ICRF -> orbit
    real = path.position(t) @ to_orbit
    normal = path.orbit_normal(t) @ to_orbit
    tilt = np.arctan2(np.hypot(normal[:, 0], normal[:, 1]), normal[:, 2])
    lam_k, r_over_a = keplerian_sun_orbit_frame(model, t)
    lam_r = np.arctan2(real[:, 1], real[:, 0])
    # the model's λ = θ + ν is the body's longitude seen from the Sun; the Sun seen from the body is λ + π
    dlam = np.abs(np.remainder(lam_r - lam_k, 2.0 * math.pi) - math.pi)
    r_real = np.linalg.norm(real, axis=1)
    a = body.orbit.a_au
    kappa = abs(float(np.mean(r_real ** -3.0) / np.mean((a * r_over_a) ** -3.0)) - 1.0)
    t_el = body.orbit.epoch_jd_tdb
    return OrbitMotion(orbit_elements(body), _envelope(t - t_el, tilt), _envelope(t - t_el, dlam), kappa,
                       (start, stop), float(r_real.min()))


def gap_bin_ends(extent_days: float) -> np.ndarray:
    """Outer ends (whole days from t0) of the bins of |τ| up to ``extent_days`` (its whole days): 1, 2, …
    growing by 10^(1/GAP_BINS_PER_DECADE) (at least a day), at most GAP_BIN_MAX_DAYS apart."""
    top = math.floor(extent_days / GAP_STEP_DAYS) * GAP_STEP_DAYS
    ratio = 10.0 ** (1.0 / GAP_BINS_PER_DECADE)
    ends, e = [], 0.0
    while e < top:
        e = min(top, max(e + GAP_STEP_DAYS, min(round(e * ratio), e + GAP_BIN_MAX_DAYS)))
        ends.append(e)
    return np.array(ends)


def measure_pole_gap(body: Body, start: float, stop: float, starts, rtol: float, integration_error
                     ) -> tuple[PoleGap, float]:
    """Measure the :class:`PoleGap` of a catalogue body over [start, stop] (JD TDB, inside DE421 and
    around the pole epoch t0), and how well its sampling allowance holds (below).

    The ladder's pieces are the caller's (``tools/derive_orbit_motion.py``; this module sits below
    :mod:`ephem.sun.ladder`): ``starts``, the bodies whose poles both rungs start from (the body itself and
    the rotation-scale variants' mean-pole body); ``rtol``, the rungs' ODE tolerance; and
    ``integration_error(model, span_days)``, the rungs' integration error (radians).

    Both rungs are integrated as the ladder does (DOP853 at ``rtol``, the real Sun path of
    :func:`ephem.orbit.de421.sun_path`) from the pole at t0 and sampled at t0 + k days. Between two
    samples the gap can peak above both: with d(t) the difference of the two pole vectors, smooth
    where the gap (its norm) is not, d departs from its chord by at most h²/8 max|d̈|, h²|d̈| being
    the second difference |d(t+h) - 2 d(t) + d(t-h)|; the allowance is a quarter of the larger second
    difference at the interval's two samples (twice that). The check returned is the largest ratio
    of the gap's excess over its two samples to that allowance, found on 1/16-day samples over three
    orbits (the first from t0, where the gap is smallest, and the last at each end of the window,
    where it is largest): at most 1 when the allowance covers the sampling (measured: see the table).

    Each bin adds both integrations' error (``integration_error`` twice; the ladder's is 1e-12 rad and
    up) at its outer end. The real orbit's own error is not added. The real-orbit rung's ``ephemeris`` term
    (:func:`ephem.sun.rungs.ephemeris_bound`: 1e-10 rad, 0.02 mas, plus as much per century) is below the asteroids' gap
    from the first day (0.05-2.6 mas one day from t0) and 100 times below it beyond 2-50 days (Itokawa
    from the start). The gap of the Earth and Mars, whose real orbit is DE421's own (fitted to 1e-11),
    stays under that floor for the first 5 months (0.003 mas after a day, at most 0.02 mas to 151 days)
    and passes 2 mas only after 13-33 years; the floor there stands for far less, a fitted Sun direction
    good to 1e-11 rad.

    The rungs' rotation-scale variants run from the mean pole (:meth:`ephem.sun.ladder.Ladder.mean_pole_body`,
    the catalogue pole less the Oppolzer offset: 0.03-69 mas away): the tool starts from both, and the
    bins hold the larger gap. The start's move changes the gap only at second order (the move times the difference of
    the two rungs' flows): by at most 0.11 mas over the window for petit2014 Itokawa (69 mas moved;
    1e-5 of its gap there), and the running maximum of the gap from t0 by at most 2e-5 of itself for
    Mars, 1.4e-6 for petit2014 Itokawa, but 0.56% for the Earth (0.001 mas at 3.5 years, where its gap
    is 0.17 mas): not always below the table's rounding, hence the second start. With the rotation
    phase given the start moves further by the semi-diurnal term, which depends on the phase and is not
    sampled: up to 29 mas for petit2014 Itokawa, 2.4 mas for Eros, 0.12 mas for Mars, 0.001 mas for the
    Earth; with the sensitivities above (per mas moved, of the gap: 2.0e-8 for petit2014 Itokawa, 5e-7
    for Eros, 5.4e-6 for Mars, 1e-3 for the Earth) that is at most 1.2e-6 of the gap (Eros), and
    :data:`START_ALLOWANCE` is added for it.
    """
    model = cached_model(body)
    t0, h = model.pole_epoch, GAP_STEP_DAYS
    if not start <= t0 <= stop:
        raise ValueError(f"the pole epoch {t0} is outside [{start}, {stop}]")
    k = np.arange(math.ceil((start - t0) / h), math.floor((stop - t0) / h) + 1.0)
    samples = t0 + k * h
    period = 2.0 * math.pi / model.mean_motion
    checks = [(t0, t0 + period), (samples[0], samples[0] + period), (samples[-1] - period, samples[-1])]
    fine = np.concatenate([np.arange(a, b, h / 16.0) for a, b in checks])
    t = np.unique(np.concatenate([samples, fine]))
    at_sample = np.searchsorted(t, samples)
    path = sun_path(body, start, stop)

    chord = np.zeros(k.size - 1)        # per interval between samples: the most |d| reaches in it
    check = 0.0
    for start_body in starts:
        m = cached_model(start_body)
        d = integrate_spin_axis(m, t, rtol=rtol) - integrate_spin_axis(m, t, rtol=rtol, sun=path.position_scalar)
        ds = d[at_sample]
        size = np.linalg.norm(ds, axis=1)
        second = np.linalg.norm(ds[2:] - 2.0 * ds[1:-1] + ds[:-2], axis=1)
        second = np.concatenate([second[:1], second, second[-1:]])       # the end samples take their neighbour's
        allowance = 0.25 * np.maximum(second[:-1], second[1:])
        top = np.maximum(size[:-1], size[1:])
        chord = np.maximum(chord, top + allowance)
        between = np.setdiff1d(np.arange(t.size), at_sample)
        j = np.searchsorted(samples, t[between]) - 1
        excess = np.linalg.norm(d[between], axis=1) - top[j]
        check = max(check, float(np.max(excess / np.maximum(allowance[j], 1e-300))))
    gap = 2.0 * np.arcsin(np.minimum(chord / 2.0, 1.0))     # the chord of two unit vectors -> their angle

    sides = []
    for sign in (1.0, -1.0):
        outer = np.maximum(sign * k[:-1], sign * k[1:]) * h    # each interval's end farther from t0
        mine = (sign * k[:-1] >= 0.0) & (sign * k[1:] >= 0.0)
        ends = gap_bin_ends(float(outer[mine].max()))
        worst = np.zeros(ends.size)
        np.maximum.at(worst, np.searchsorted(ends, outer[mine]), gap[mine])
        worst = worst * (1.0 + START_ALLOWANCE) + 2.0 * np.array([integration_error(model, e) for e in ends])
        sides.append((tuple(float(x) for x in ends), tuple(float(x) for x in worst)))
    pole = (body.pole.ra_deg, body.pole.dec_deg, body.pole.epoch_jd_tdb)
    return PoleGap(pole, model.scaling_factor, *sides), check


def _read_gap(path, pole, scaling_factor) -> PoleGap:
    """A table written by tools/derive_orbit_motion.py: rows τ (days, signed), gap (mas)."""
    rows = {1.0: ([], []), -1.0: ([], [])}
    with open(path, newline="") as fh:
        for row in csv.DictReader(line for line in fh if not line.startswith("#")):
            tau = float(row["tau_days"])
            ends, gaps = rows[1.0 if tau > 0.0 else -1.0]
            ends.append(abs(tau))
            gaps.append(float(row["max_gap_mas"]) * MAS)
    return PoleGap(tuple(pole), scaling_factor, *((tuple(e), tuple(g)) for e, g in rows.values()))


@lru_cache(maxsize=1)
def _table() -> dict:
    path = data_dir() / "orbit_motion.toml"
    if not path.exists():
        return {}
    with open(path, "rb") as fh:
        raw = tomllib.load(fh)
    out = {}
    for rec in raw.get("body", []):
        def coef(prefix):
            return (rec[f"{prefix}_rate_arcsec_per_year"] * ARCSEC / 365.25,
                    rec[f"{prefix}_acceleration_arcsec_per_year2"] * ARCSEC / 365.25**2,
                    rec[f"{prefix}_wobble_arcsec"] * ARCSEC)
        gap = None
        if "gap_file" in rec:
            gap = _read_gap(data_dir() / rec["gap_file"], rec["gap_pole"], rec["gap_scaling_factor_rad_per_day"])
        out[(rec["dataset"], rec["name"])] = OrbitMotion(
            tuple(rec["elements"]), coef("normal"), coef("longitude"), rec["torque_mismatch"],
            (rec["window_start_jd_tdb"], rec["window_stop_jd_tdb"]), rec["real_perihelion_au"], gap)
    return out


def orbit_motion_for(body: Body) -> OrbitMotion | None:
    """The measurements of a catalogue body (None for a user's body: not measured)."""
    om = _table().get((body.dataset, body.name))
    # the envelopes describe the catalogue's elements: a body with other elements is not covered
    if om is None or not all(_same(a, b) for a, b in zip(om.elements, orbit_elements(body))):
        return None
    return om


def phase_sensitivity(model: PrecessionNutation) -> float:
    """Σ_k k A_k: the most the nutation moves the pole per radian of the Sun's phase (radians)."""
    k = model.nutation.multiple.astype(float)
    return float(np.sum(k * pole_displacements(model.nutation, model.obliquity)))


def _drift(om: OrbitMotion, model: PrecessionNutation, a, b):
    """What the plane's tilt and the torque mismatch add to the gap from epoch a to epoch b (radians)."""
    rate, accel, wobble = om.normal
    t_el = om.elements_epoch

    def antiderivative(x):  # of the tilt envelope, rate |τ - t_el| + accel (τ - t_el)² + wobble
        d = x - t_el
        return rate * np.sign(d) * d * d / 2.0 + accel * d**3 / 3.0 + wobble * x

    plane = model.scaling_factor * eccentricity_factor(model.eccentricity) * np.abs(
        antiderivative(b) - antiderivative(a))
    torque = abs(math.sin(model.obliquity) * model.precession_rate) * om.torque_mismatch * np.abs(b - a)
    return plane + torque


def _phase(om: OrbitMotion, model: PrecessionNutation, x):
    """The most the Sun's phase error moves the nutation at epoch x (radians)."""
    # the phase error cannot exceed π: beyond, the nutation is simply out of phase (2 A at most)
    return phase_sensitivity(model) * np.minimum(OrbitMotion.envelope(om.longitude, x - om.elements_epoch), math.pi)


def envelope_bound(om: OrbitMotion, model: PrecessionNutation, t: np.ndarray) -> float:
    """The gap bounded from t0 by the envelopes alone (radians): for a body whose gap was not measured.
    Each part is largest at the first or the last epoch (monotone, or convex, in t)."""
    ends, t0 = np.array([t.min(), t.max()]), model.pole_epoch
    return float(np.max(_drift(om, model, t0, ends) + _phase(om, model, ends) + _phase(om, model, t0)))


def growth_beyond(om: OrbitMotion, model: PrecessionNutation, edge: float, t) -> np.ndarray:
    """The most the gap can grow from epoch ``edge`` to ``t`` (radians), for epochs beyond the measured window.

    The tilt and the torque mismatch add their drift from the edge on; the nutation's phase error at t and at
    the edge add at most Σ k A_k (δλ(t) + δλ(edge)). Neither pole moves faster than K (a/r)³/2 (the torque
    (s·r̂)(r̂×s) has norm ≤ 1/2), so the gap grows by at most the sum of their speeds times |t - edge|: at the
    fixed orbit's perihelion q and the real orbit's smallest distance in the window (the growth reaches the
    phase term within a few days, too soon for that distance to change). That keeps the estimate continuous
    at the window's edge. Increasing in |t - edge|."""
    t = np.asarray(t, dtype=float)
    a, e = om.elements[0], om.elements[1]
    speeds = 0.5 * model.scaling_factor * ((1.0 / (1.0 - e)) ** 3 + (a / om.real_perihelion_au) ** 3)
    phase = np.minimum(_phase(om, model, t) + _phase(om, model, edge), speeds * np.abs(t - edge))
    return _drift(om, model, edge, t) + phase


def gap_bound(om: OrbitMotion, model: PrecessionNutation, t: np.ndarray) -> float:
    """The measured gap over the epochs (radians): on each side of t0, the largest gap of the bins the epochs'
    span touches; past the window's edge, the gap at the edge (its last bin) plus :func:`growth_beyond`.

    A span that does not reach t0 (2040-2050 for t0 = 2000) is charged only its own bins, not the gap's
    running maximum from t0."""
    t0, out = om.gap.pole_epoch, 0.0
    for sign, ends, gaps in om.gap.sides():
        tau = sign * (t - t0)
        tau = tau[tau >= 0.0]
        if tau.size == 0:
            continue
        lo, hi = float(tau.min()), float(tau.max())
        edge = float(ends[-1])
        if lo <= edge:      # bin i holds [ends[i-1], ends[i]]: the first whose end reaches lo, to the one holding hi
            first, last = np.searchsorted(ends, [lo, min(hi, edge)], side="left")
            out = max(out, float(gaps[first:last + 1].max()))
        if hi > edge:
            out = max(out, float(gaps[-1] + growth_beyond(om, model, t0 + sign * edge, t0 + sign * hi)))
    return out


def orbit_motion_bound(body: Body, model: PrecessionNutation, jd_tdb: np.ndarray) -> float | None:
    """Largest pole error (radians) the fixed orbit makes at the epochs: the measured gap between rungs 5 and 6
    (:func:`gap_bound`) for a catalogue body, the envelopes' bound (:func:`envelope_bound`) for a catalogue body
    given another pole or H_d; None for a body never measured.

    The rotation-scale variants reuse it: they run from a pole moved by the Oppolzer offset, whose gap the table
    includes (:func:`measure_pole_gap`)."""
    om = orbit_motion_for(body)
    if om is None:
        return None
    t = np.asarray(jd_tdb, dtype=float).ravel()
    if t.size == 0:
        return 0.0
    if om.gap is not None and om.gap.describes(body, model):
        return gap_bound(om, model, t)
    return envelope_bound(om, model, t)


def rotation_averaging_bound(body: Body, model: PrecessionNutation, jd_tdb, axis: str = "figure",
                             modelled: str = "none", pole: str = "figure") -> float:
    """What averaging over the rotation leaves out (radians) at the epochs ``jd_tdb`` for the pole ``axis``
    ("figure" or "angular_momentum") when a track includes ``modelled`` of the rotation-scale terms
    (:data:`ephem.forced.rotation_scale.MODELLED`), the catalogue pole being ``pole`` at t₀: the sum of
    :func:`ephem.forced.rotation_scale.error_terms` from t₀ to the farthest epoch on each side of it the epochs reach
    (every track starts at t₀, so a span that does not include it is bounded by the span from t₀).

    A body known only by H_d gets the worst triaxiality its H_d allows (:func:`ephem.forced.rigid_numerics.worst_case_moments`).
    """
    if model.hd == 0.0:  # a sphere: no torque to average
        return 0.0
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    if t.size == 0:
        return 0.0
    moments = body_moments(body, model)
    which = "figure" if axis == "figure" else "momentum"
    return max(sum(error_terms(model, moments, s, which, modelled, pole).values())
               for s in _averaging_sides(model.pole_epoch, float(t.min()), float(t.max())))


def _averaging_sides(pole_epoch: float, first: float, last: float) -> list[float]:
    """The spans (days, signed) from t₀ (``pole_epoch``) to the farthest epoch on each side of it that [first, last]
    reaches."""
    after, before = last - pole_epoch, first - pole_epoch
    return ([after] if after > 0.0 else []) + ([before] if before < 0.0 else []) or [0.0]


def rotation_averaging_samples(body: Body, first: float, last: float) -> int:
    """The epochs :func:`rotation_averaging_bound` samples for epochs spanning [first, last] (JD TDB)
    (:func:`ephem.forced.rotation_scale.sampled_epochs` on each side of t₀), once for all its calls of a request:
    the axis, what is modelled and the catalogue pole's meaning share one sampling of a span
    (:func:`ephem.forced.rotation_scale.span_samples`). What its cost grows with, from the body's parameters alone
    (a price made before its model is built)."""
    if body.hd == 0.0:
        return 0
    n = mean_motion_rad_per_day(body.orbit.a_au, body.orbit.center)
    return sum(sampled_epochs(body.orbit.e, abs(s) * n / (2.0 * math.pi))
               for s in _averaging_sides(body.pole.epoch_jd_tdb, first, last))


def rotation_averaging_sides(body: Body, first: float, last: float) -> int:
    """The sides of t₀ on which :func:`rotation_averaging_bound` bounds epochs spanning [first, last] (JD TDB), each
    with its own fixed work (:func:`ephem.forced.rotation_scale.span_samples`, once a request; each call's terms from
    it are a few float operations): 2 for a span across t₀, else 1; 0 for a sphere (no torque to average). From the
    body's parameters alone, for its price."""
    if body.hd == 0.0:
        return 0
    return len(_averaging_sides(body.pole.epoch_jd_tdb, first, last))
