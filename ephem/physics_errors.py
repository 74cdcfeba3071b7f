"""Error terms from physics the fixed-orbit, rotation-averaged theories leave out.

Orbit motion (rungs 1-5). The real orbit is not the fixed Keplerian ellipse of the
osculating elements: its plane turns, the Sun runs ahead of or behind its Keplerian
place, and the mean of (a/r)^3 differs. Three measured quantities per body bound it
(``data/orbit_motion.toml``, derived by ``tools/derive_orbit_motion.py`` from the real
orbit of :mod:`ephem.ephemeris` over DE421's span, 1900-2050):

* the angle δW between the real orbit normal and the Keplerian one, enveloped by
  ``normal_rate`` |t - t_el| + ``normal_wobble`` (t_el the elements' epoch);
* the Sun's in-plane angle δλ from its Keplerian place, enveloped likewise;
* the relative mismatch κ of the mean torque strength <r^-3>.

A tilt δW of the plane changes the pole's speed by at most K f(e) δW (the averaged
torque (K/2) f(e) (s·W)(W×s) has a W-derivative of norm ≤ 2), which integrates from the
pole epoch; a phase error δλ moves the nutation by at most Σ_k k A_k δλ (A_k the pole
displacement of harmonic k) at t and at t0, where both rungs start from the same pole;
κ changes ψ̇ by κ ψ̇. The sum is checked against rung 6 minus rung 5 in the tests.

Rotation averaging (every rung): see :func:`rotation_averaging_bound` and :mod:`ephem.rotation_scale`.

Radians and days.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .catalogue import Body, data_dir
from .constants import ARCSEC
from .kepler import solve_kepler, true_anomaly
from .kinoshita import eccentricity_factor, pole_displacements
from .model import PrecessionNutation
from .rigid import body_moments
from .rotation_scale import error_terms



@dataclass(frozen=True)
class OrbitMotion:
    """Envelopes of the real orbit's departure from the Keplerian one (radians, rad/day)."""

    elements_epoch: float
    normal: tuple[float, float, float]      # (rate, acceleration, wobble) of the tilt envelope
    longitude: tuple[float, float, float]   # the same for the in-plane angle
    torque_mismatch: float
    window: tuple[float, float]

    @staticmethod
    def envelope(coef: tuple[float, float, float], offset_days):
        rate, accel, wobble = coef
        d = np.abs(offset_days)
        return rate * d + accel * d * d + wobble


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
    """Measure the envelopes of :class:`OrbitMotion` against the real orbit over [start, stop] (JD TDB)."""
    from .ephemeris import sun_path

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
    return OrbitMotion(t_el, _envelope(t - t_el, tilt), _envelope(t - t_el, dlam), kappa, (start, stop))


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
        out[(rec["dataset"], rec["name"])] = OrbitMotion(
            rec["elements_epoch_jd_tdb"], coef("normal"), coef("longitude"), rec["torque_mismatch"],
            (rec["window_start_jd_tdb"], rec["window_stop_jd_tdb"]))
    return out


def orbit_motion_for(body: Body) -> OrbitMotion | None:
    """The measured envelopes of a catalogue body (None for a user's body: not measured)."""
    om = _table().get((body.dataset, body.name))
    # the envelopes describe the catalogue's elements: a body with other elements is not covered
    if om is None or om.elements_epoch != body.orbit.epoch_jd_tdb:
        return None
    return om


def phase_sensitivity(model: PrecessionNutation) -> float:
    """Σ_k k A_k: the most the nutation moves the pole per radian of the Sun's phase (radians)."""
    k = model.nutation.multiple.astype(float)
    return float(np.sum(k * pole_displacements(model.nutation, model.obliquity)))


def orbit_motion_bound(body: Body, model: PrecessionNutation, jd_tdb: np.ndarray) -> float | None:
    """Largest pole error (radians) the fixed orbit makes at the epochs; None if not measured."""
    om = orbit_motion_for(body)
    if om is None:
        return None
    t = np.asarray(jd_tdb, dtype=float)
    if t.size == 0:
        return 0.0
    t0, t_el = model.pole_epoch, om.elements_epoch

    rate, accel, wobble = om.normal

    def antiderivative(x):  # of the tilt envelope, rate |τ - t_el| + accel (τ - t_el)² + wobble
        d = x - t_el
        return rate * np.sign(d) * d * d / 2.0 + accel * d**3 / 3.0 + wobble * x

    ends = np.array([t.min(), t.max()])
    tilt_integral = np.abs(antiderivative(ends) - antiderivative(t0))
    plane = model.scaling_factor * eccentricity_factor(model.eccentricity) * tilt_integral
    # the phase error cannot exceed π: beyond, the nutation is simply out of phase (2 A at most)
    dlam = lambda x: np.minimum(OrbitMotion.envelope(om.longitude, x - t_el), math.pi)  # noqa: E731
    phase = phase_sensitivity(model) * (dlam(ends) + dlam(t0))
    rate = abs(math.sin(model.obliquity) * model.precession_rate) * om.torque_mismatch * np.abs(ends - t0)
    return float(np.max(plane + phase + rate))


def rotation_averaging_bound(body: Body, model: PrecessionNutation, span_days: float, axis: str = "figure",
                             modelled: str = "none", pole: str = "figure") -> float:
    """What averaging over the rotation leaves out (radians) for the pole ``axis`` ("figure" or
    "angular_momentum") when a track includes ``modelled`` of the rotation-scale terms
    (:data:`ephem.rotation_scale.MODELLED`), the catalogue pole being ``pole`` at t₀: the sum of
    :func:`ephem.rotation_scale.error_terms` over ±span.

    A body known only by H_d gets the worst triaxiality its H_d allows (:func:`ephem.rigid.worst_case_moments`).
    """
    if model.hd == 0.0:  # a sphere: no torque to average
        return 0.0
    moments = body_moments(body, model)
    which = "figure" if axis == "figure" else "momentum"
    return max(sum(error_terms(model, moments, s, which, modelled, pole).values()) for s in (span_days, -span_days))


def real_orbit_unavailable(body: Body, jd_tdb: np.ndarray) -> str | None:
    """Why rung 6 cannot serve these epochs, or None if it can."""
    from .ephemeris import DE421_BODIES, de421_span, tdb_date

    if body.orbit.center != "Sun":
        return (f"the orbit is centred on the {body.orbit.center}: the real-orbit rung follows heliocentric "
                "orbits only")
    lo, hi = de421_span()
    t = np.asarray(jd_tdb, dtype=float)
    need = [body.pole.epoch_jd_tdb] + ([float(t.min()), float(t.max())] if t.size else [])
    if body.naif_id not in DE421_BODIES:
        need.append(body.orbit.epoch_jd_tdb)
    if min(need) < lo or max(need) > hi:
        return (f"the real orbit comes from DE421, which spans {tdb_date(lo)} to {tdb_date(hi)} TDB; these epochs "
                f"(with the pole epoch{'' if body.naif_id in DE421_BODIES else ' and the elements epoch'}) "
                f"need JD {min(need):.1f} to {max(need):.1f}")
    return None


def ephemeris_bound(body: Body, model: PrecessionNutation, span_days: float) -> float:
    """Error of rung 6's orbit: the fit (< 1e-11 relative) and the integrated asteroid orbit (6e-7 au after
    100 years for Mars against DE421) move the Sun's direction by < 1e-9 rad per century; through the
    nutation's phase sensitivity and the precession that is far below a micro-arcsecond, so a floor of
    1e-10 rad per century of span stands for it."""
    return 1e-10 * (1.0 + abs(span_days) / 36525.0)


def sun_path_for(body: Body, jd_tdb: np.ndarray):
    """The real Sun path covering the epochs and the pole epoch (where the integration starts)."""
    from .ephemeris import sun_path

    t = np.asarray(jd_tdb, dtype=float)
    t0 = body.pole.epoch_jd_tdb
    return sun_path(body, min(t0, float(t.min())), max(t0, float(t.max())))
