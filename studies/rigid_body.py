"""The rigid-body study: the rotation-averaged pole (rung 5) against the full rigid body (rung 7) as ω/n
falls, and rung 7's cost. The numbers of docs/rigid_body_study.md.

A study, not the library (see :mod:`studies`): run from the project root as ``python -m studies.rigid_body``
(prints the study's tables, then rung 7's CPU cost for Vesta and Itokawa). The library's side is the rigid body,
:func:`ephem.forced.rigid_body.integrate_rigid_body`; the study's own are here: the synthetic rotators
(:func:`synthetic_model`), rung 5 against rung 7 (:func:`compare_with_averaged`), the epochs (:func:`study_epochs`)
and the threshold the study sets (:data:`RECOMMENDED_MIN_SPIN_ORBIT_RATIO`, which the library's
``ephem.forced.precession_nutation.MIN_SPIN_ORBIT_RATIO`` follows); chart 4 of :mod:`studies.accuracy` draws this
study. The error estimate of what averaging leaves out (:func:`ephem.forced.rotation_scale.error_terms`) is checked
against the rigid body by :mod:`studies.rotation_scale`, from the forced start this study does not use.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from ephem.forced.integration import angular_separation, integrate_spin_axis
from ephem.forced.kinoshita import nutation_series, precession_rate, scaling_factor
from ephem.forced.precession_nutation import PrecessionNutation
from ephem.forced.rigid_body import RigidTrack, integrate_rigid_body
from ephem.forced.rigid_numerics import model_moments

# --------------------------------------------------------------------------- rung 5 against rung 7
# (moved here from ephem.forced.rigid_body: the study's synthetic rotators and comparison, which the library
# never calls; the rigid body itself, rung 7, stays there)


def synthetic_model(model: PrecessionNutation, spin_orbit_ratio: float, hd: float | None = None) -> PrecessionNutation:
    """``model`` spun at ω = ratio × n (and with H_d replaced if given): a synthetic rotator for the study.

    K, ψ̇ and the nutation series are recomputed; the initial pole, the frame and
    (Δψ, Δε) at the pole epoch are kept, so every ratio starts from the same
    pole in the same frame. Bypasses ``MIN_SPIN_ORBIT_RATIO`` on purpose.
    """
    hd = model.hd if hd is None else hd
    omega = spin_orbit_ratio * model.mean_motion
    K = scaling_factor(model.mean_motion, omega, hd)
    return replace(model, hd=hd, spin_rate=omega, scaling_factor=K,
                   precession_rate=precession_rate(K, model.obliquity, model.eccentricity, model.order),
                   nutation=nutation_series(K, model.mean_motion, model.obliquity, model.eccentricity,
                                            model.equinox_to_pericentre, model.order))


@dataclass(frozen=True)
class AveragingComparison:
    """Rung 5 against rung 7 at epochs (radians): the averaged theory's errors and the forced motion."""

    jd_tdb: np.ndarray
    momentum_error: np.ndarray   # angle between rung 5's axis and rung 7's L
    figure_error: np.ndarray     # angle between rung 5's axis and rung 7's C axis
    displacement: np.ndarray     # angle of rung 5's axis from its initial position
    rigid: RigidTrack

    def relative(self) -> tuple[float, float]:
        """Max errors of L and of the figure axis over the max displacement."""
        d = float(self.displacement.max())
        return float(self.momentum_error.max()) / d, float(self.figure_error.max()) / d


def compare_with_averaged(model: PrecessionNutation, jd_tdb, moments=None, initial_angle: float = 0.0,
                          rtol: float = 1e-12) -> AveragingComparison:
    """Run rung 7 and rung 5 (:func:`ephem.forced.integration.integrate_spin_axis`) from the same pole and compare.

    Both start with L on the pole (rung 7 with ``start="aligned"``), the comparison the averaged theory's
    convergence as ω/n falls is about; the forced start, the rotation-scale terms and their error estimate are
    compared in :mod:`studies.rotation_scale` and tests/forced/test_rotation_scale.py."""
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    rig = integrate_rigid_body(model, t, moments, initial_angle, rtol=rtol, start="aligned")
    model = replace(model, geodesic_rate=0.0)     # the torque alone, as rung 7 integrates it
    avg = integrate_spin_axis(model, t, rtol=rtol)
    s0 = integrate_spin_axis(model, [model.pole_epoch])[0]
    return AveragingComparison(t, angular_separation(rig.angular_momentum, avg),
                               angular_separation(rig.figure_axis, avg), angular_separation(avg, s0), rig)


def study_epochs(model: PrecessionNutation, span_days: float, per_rotation: int = 12,
                 minimum: int = 400) -> np.ndarray:
    """Evenly spaced epochs over [t0, t0 + span], dense enough to catch the short-period terms' peaks."""
    rotations = abs(span_days) * model.spin_rate / (2.0 * math.pi)
    count = max(minimum, int(per_rotation * rotations) + 1)
    return model.pole_epoch + np.linspace(0.0, span_days, count)


# --------------------------------------------------------------------------- the recommended threshold

#: Recommended ω/n threshold for the averaged theory (see docs/rigid_body_study.md): below it the
#: figure axis of an Eros-like body (extreme triaxiality, obliquity ~90°) departs from rung 5 by
#: more than 10% of the pole's largest displacement over one orbit.
RECOMMENDED_MIN_SPIN_ORBIT_RATIO = 30.0


# --------------------------------------------------------------------------- the study

STUDY_RATIOS = (1.2, 1.5, 2.0, 3.0, 5.0, 10.0, 20.0, 50.0, 100.0, 300.0, 1000.0)


def study_cases() -> list[tuple[str, PrecessionNutation, tuple[float, float, float]]]:
    """(label, catalogue model, normalised moments): each geometry axisymmetric (same H_d) and as catalogued."""
    from ephem.bodies.catalogue import get_body
    from ephem.forced.precession_nutation import build_model

    cases = []
    for name in ("Vesta", "Eros", "Itokawa", "Earth"):
        model = build_model(get_body(name))
        A, B, C = model_moments(model)
        mean = 0.5 * (A + B)
        if name in ("Vesta", "Eros"):
            cases.append((f"{name}, axisymmetric", model, (mean, mean, C)))
        cases.append((f"{name}, (B-A)/C = {B - A:.3g}", model, (A, B, C)))
    return cases


@dataclass(frozen=True)
class StudyRow:
    """One (case, ω/n) of the averaging-error study; angles in radians, CPU in seconds."""

    case: str
    ratio: float
    k_over_n: float
    displacement: float      # max angle of rung 5's pole from its start over the span
    momentum_error: float    # max angle rung 5 - rung 7 L
    figure_error: float      # max angle rung 5 - rung 7 C axis
    cpu: float

    @property
    def relative(self) -> tuple[float, float]:
        return self.momentum_error / self.displacement, self.figure_error / self.displacement


def averaging_error_study(ratios=STUDY_RATIOS, span_orbits: float = 1.0, cases=None,
                          per_rotation: int = 12) -> list[StudyRow]:
    """Rung 5 against rung 7 as ω/n falls, over ``span_orbits`` orbits from the pole epoch.

    Each case keeps its geometry (orbit, pole) and moments; ω = ratio × n sets K = 3 n² H_d/ω
    (:func:`synthetic_model`). Epochs: ``per_rotation`` a rotation, at least 400.
    """
    rows = []
    for label, base, mom in (study_cases() if cases is None else cases):
        hd = 1.0 - 0.5 * (mom[0] + mom[1]) / mom[2]
        for ratio in ratios:
            model = synthetic_model(base, ratio, hd)
            span = span_orbits * 2.0 * math.pi / model.mean_motion
            t = study_epochs(model, span, per_rotation)
            start = time.process_time()
            cmp = compare_with_averaged(model, t, mom)
            cpu = time.process_time() - start
            rows.append(StudyRow(label, ratio, model.scaling_factor / model.mean_motion,
                                 float(cmp.displacement.max()), float(cmp.momentum_error.max()),
                                 float(cmp.figure_error.max()), cpu))
    return rows


def threshold_ratio(rows: list[StudyRow], level: float = 0.1, axis: int = 1) -> float:
    """Smallest ω/n above which the relative error (axis 0: L, 1: figure) stays below ``level``.

    Interpolated log-log between the study's ratios (rows of one case, any order).
    """
    pts = sorted((r.ratio, r.relative[axis]) for r in rows)
    above = [i for i, (_, rel) in enumerate(pts) if rel >= level]
    if not above:
        return pts[0][0]
    i = above[-1]
    if i == len(pts) - 1:
        return math.inf
    (r0, e0), (r1, e1) = pts[i], pts[i + 1]
    x = math.log(level / e0) / math.log(e1 / e0)
    return math.exp(math.log(r0) + x * math.log(r1 / r0))


def rigid_cost(model: PrecessionNutation, rotations: float, repeats: int = 3) -> dict[str, float]:
    """CPU seconds of rung 7 per rotation and per orbit (best of ``repeats`` runs over ``rotations``)."""
    span = rotations * 2.0 * math.pi / model.spin_rate
    t = model.pole_epoch + np.linspace(0.0, span, 11)
    best, nfev = math.inf, 0
    for _ in range(repeats):
        start = time.process_time()
        nfev = integrate_rigid_body(model, t).nfev
        best = min(best, time.process_time() - start)
    per_rotation = best / rotations
    return {"per_rotation": per_rotation, "per_orbit": per_rotation * model.spin_orbit_ratio,
            "calls_per_rotation": nfev / rotations, "us_per_call": 1e6 * best / nfev}


def _print_study(rows: list[StudyRow]) -> None:
    print("| case | ω/n | K/n | max displacement (rad) | L error (rad) | C error (rad) | L rel. | C rel. | CPU s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        rel_l, rel_c = r.relative
        print(f"| {r.case} | {r.ratio:g} | {r.k_over_n:.3g} | {r.displacement:.3e} | {r.momentum_error:.2e} "
              f"| {r.figure_error:.2e} | {rel_l:.2e} | {rel_c:.2e} | {r.cpu:.2f} |")
    print()
    print("| case | ω/n where L error = 10% | ω/n where C error = 10% |")
    print("|---|---:|---:|")
    for case in dict.fromkeys(r.case for r in rows):
        sub = [r for r in rows if r.case == case]
        cells = []
        for axis in (0, 1):
            never = all(r.relative[axis] < 0.1 for r in sub)
            cells.append(f"below 10% from {min(r.ratio for r in sub):g}" if never else f"{threshold_ratio(sub, axis=axis):.3g}")
        print(f"| {case} | {cells[0]} | {cells[1]} |")


def main() -> None:
    """The study's tables (markdown), then rung 7's CPU cost for Vesta and Itokawa (300 rotations each)."""
    from ephem.bodies.catalogue import get_body
    from ephem.forced.precession_nutation import build_model

    _print_study(averaging_error_study())
    print()
    for name in ("Vesta", "Itokawa"):
        cost = rigid_cost(build_model(get_body(name)), 300)
        print(f"{name}: {1e3 * cost['per_rotation']:.2f} ms CPU per rotation, {cost['per_orbit']:.1f} s per orbit, "
              f"{cost['calls_per_rotation']:.0f} calls per rotation, {cost['us_per_call']:.1f} µs per call")


if __name__ == "__main__":  # python -m studies.rigid_body: the numbers of docs/rigid_body_study.md
    main()
