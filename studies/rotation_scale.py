"""The rotation-scale study: what averaging over the rotation leaves out, against the full rigid body, and how
close the error estimate of :func:`ephem.forced.rotation_scale.error_terms` comes to it.

A study, not the library (see :mod:`studies`): run from the project root as
``python -m studies.rotation_scale [--out DIR] [--quick]``. For a population of generated bodies (e to 0.95,
obliquities near 0°, 30°, 60°, 90°, 120° and 180°, ω/n from 30 up, A + B - C from near 0 to near 1, spans
from a fraction of an orbit to tens of orbits) it integrates the full rigid body (:mod:`ephem.forced.rigid_body`, DOP853 at
1e-12, started in the forced state: no free wobble) and the rotation-averaged pole (rung 5) without and with the
closed-form rotation-scale terms, and writes ``rotation_scale_population.csv``: per case, variant (what the
track includes: "none", "oppolzer", "all") and axis (figure or angular momentum), the true largest error, the
estimate and its pieces. :func:`ratio_rows` and the chart summarise it (estimate over truth per variant).

The comparison :func:`compare` is also the reference of tests/forced/test_rotation_scale.py.
"""
from __future__ import annotations

import csv
import dataclasses
import math
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ephem.forced import rotation_scale as rs
from ephem.bodies.catalogue import Body, Pole, get_body
from ephem.base.constants import MAS
from ephem.orbit.geometry import lon_lat
from ephem.base.constants import ROUNDING
from ephem.forced.precession_nutation import cached_model
from ephem.forced.integration import angular_separation, integrate_spin_axis
from ephem.forced.rigid_body import integrate_rigid_body
from ephem.forced.rigid_numerics import normalised_moments, rotation_matrices

from ._command import chart_app
from .rigid_body import study_epochs

#: The tracks compared: what of the rotation-scale terms each includes (the "none" track is every rung as it was).
VARIANTS = rs.MODELLED
AXES = ("figure", "momentum")


def torque_only(b: Body):
    """The body's model without the geodesic precession (what the rigid body integrates)."""
    return replace(cached_model(b), geodesic_rate=0.0)


def initial_pole(m):
    """The model's instantaneous pole at its epoch (orbit frame): the catalogue pole, the figure axis there."""
    dpsi0, deps0 = m.nutation_at_pole_epoch
    return m.pole_orbit_frame(dpsi0, m.obliquity + deps0)


def from_pole(b: Body, m, s_orbit) -> Body:
    """``b`` with its pole moved to the orbit-frame vector ``s_orbit`` of model ``m``."""
    ra, dec = lon_lat(m.icrf_from_orbit @ s_orbit)
    return replace(b, pole=Pole(math.degrees(float(ra)), math.degrees(float(dec)), b.pole.epoch_jd_tdb))


def compare(b: Body, span: float, phase0: float, start: str = "forced", per_rotation: int = 16) -> dict:
    """The rigid body against rung 5 over [t0, t0 + span] (days) with the A axis at ``phase0`` (rad) from the
    orbit's node on the equator at t0: max errors (rad) ``{axis}_{variant}`` for the figure axis and L, the
    track without the terms ("bare"), with the Oppolzer offset, and with all the terms; also the rigid run, the
    epochs, the bare track's terms and its rotation phase. Both sides follow the torque alone: the rigid body
    integrates no geodesic precession, a rotation about the orbit normal that averaging does not touch."""
    m = torque_only(b)
    mom = normalised_moments(b.moments)
    t = study_epochs(m, span, per_rotation=per_rotation)
    s0 = initial_pole(m)
    rig = integrate_rigid_body(m, t, moments=b.moments, initial_angle=phase0, start=start)
    first = rs.rotation_terms(mom, m.spin_rate, s0[None], rs.SunGeometry.at(m, [m.pole_epoch]), np.array([phase0]))
    sun = rs.SunGeometry.at(m, t)
    out = {"rigid": rig, "t": t}
    for label, start_offset in (("bare", None), ("oppolzer", first.oppolzer), ("all", first.figure_offset())):
        body = b if start_offset is None else from_pole(b, m, rs.apply(s0[None], -start_offset)[0])
        mean_icrf = integrate_spin_axis(torque_only(body), t, rtol=1e-12)
        mean = mean_icrf @ m.icrf_from_orbit
        psi = np.unwrap(np.arctan2(mean[:, 0], mean[:, 1]))
        phase = rs.rotation_phase(m, t, phase0, psi) if label == "all" else None
        terms = rs.rotation_terms(mom, m.spin_rate, mean, sun, phase)
        if label == "bare":
            L = F = mean_icrf
            out["terms"], out["phase"] = terms, rs.rotation_phase(m, t, phase0, psi)
        else:
            L = rs.apply(mean, terms.momentum_offset()) @ m.icrf_from_orbit.T
            F = rs.apply(mean, terms.figure_offset()) @ m.icrf_from_orbit.T
        out[f"momentum_{label}"] = float(angular_separation(rig.angular_momentum, L).max())
        out[f"figure_{label}"] = float(angular_separation(rig.figure_axis, F).max())
    # the rotation phase model against the integrated A axis's angle from the node (what "all" needs)
    e1, e2 = rs.equator_basis(rig.figure_axis_orbit)
    a_axis = rotation_matrices(rig.quaternion)[:, :, 0]
    measured = np.arctan2(np.sum(a_axis * e2, axis=1), np.sum(a_axis * e1, axis=1))
    out["phase_error"] = float(np.abs(np.remainder(measured - out["phase"] + math.pi, 2 * math.pi) - math.pi).max())
    return out


def true_error(result: dict, axis: str, variant: str) -> float:
    """The largest angle (rad) between the rigid body's ``axis`` and the track including ``variant``."""
    return result[f"{axis}_{'bare' if variant == 'none' else variant}"]


@dataclass(frozen=True)
class Case:
    """One generated body and span: the orbit (a in au, e), the pole's obliquity (deg), ω/n, the moments
    (A/C, B/C), the span in orbits (signed) and the A axis's phase (rad)."""

    a_au: float
    e: float
    obliquity_deg: float
    pole_longitude_deg: float
    spin_orbit_ratio: float
    A: float
    B: float
    orbits: float
    phase: float

    def body(self, name: str = "generated") -> Body:
        ito = get_body("itokawa")
        n = 0.01720209895 / self.a_au**1.5          # Gauss's constant: rad/day at 1 au, the planet's mass dropped
        return Body(name=name, orbit=replace(ito.orbit, a_au=self.a_au, e=self.e, i_deg=0.0, node_deg=0.0),
                    pole=Pole.from_ecliptic(self.pole_longitude_deg, 90.0 - self.obliquity_deg, ito.pole.epoch_jd_tdb),
                    rotation_period_hours=2.0 * math.pi / (self.spin_orbit_ratio * n) * 24.0,
                    moments=(self.A, self.B, 1.0))

    def span_days(self) -> float:
        return self.orbits * 2.0 * math.pi * self.a_au**1.5 / 0.01720209895


def generated_population(count: int, seed: int, max_rotations: float = 400.0,
                         orbit_range: tuple[float, float] = (0.01, 3.0)) -> list[Case]:
    """Bodies across the extremes: e to 0.9 (+0.04), obliquities near 0°, 45°, 90°, 135° and 180°, ω/n where the
    Sun's peak rate is at most 5% of the spin (and at least 30), A + B - C from 0 to 1, spans of
    ``orbit_range`` orbits (log-uniform, either sign) capped at ``max_rotations`` rotations."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        e = float(rng.choice([0.0, 0.3, 0.6, 0.9]) + rng.uniform(0, 0.04))
        obliquity = float(rng.choice([0.5, 45.0, 89.6, 135.0, 179.5]) + rng.uniform(-0.3, 0.3))
        a = float(rng.uniform(0.8, 3.0))
        peak = (1 + e) ** 2 / (1 - e * e) ** 1.5
        ratio = max(30.0, peak / 0.05) * float(np.exp(rng.uniform(0, 1.5)))
        A = float(rng.uniform(0.45, 0.95))
        B = float(rng.uniform(max(A, 1.0 - A), 1.0))
        orbits = float(np.exp(rng.uniform(math.log(orbit_range[0]), math.log(orbit_range[1]))))
        orbits = min(orbits, max_rotations / ratio) * float(rng.choice([1, -1]))
        out.append(Case(a, e, obliquity, float(rng.uniform(0, 360)), ratio, A, B, orbits,
                        float(rng.uniform(0, 2 * math.pi))))
    return out


def case_rows(case: Case, index: int) -> list[dict]:
    """The rigid body against the three tracks for one case: a row per (variant, axis) with the truth, the
    estimate and its pieces (mas), and the rigid run's CPU seconds."""
    b = case.body(f"case{index}")
    m = cached_model(b)
    span = case.span_days()
    cpu = time.process_time()
    r = compare(b, span, case.phase)
    cpu = time.process_time() - cpu
    rows = []
    for variant in VARIANTS:
        for axis in AXES:
            pieces = rs.error_terms(m, b.moments, span, axis, variant)
            truth = true_error(r, axis, variant)
            row = {"case": index, "variant": variant, "axis": axis, **dataclasses.asdict(case),
                   "true_mas": truth / MAS, "estimate_mas": sum(pieces.values()) / MAS, "cpu_s": cpu,
                   "phase_error_rad": r["phase_error"]}
            row.update({f"{k}_mas": v / MAS for k, v in pieces.items()})
            rows.append(row)
    return rows


def re_estimate(rows: list[dict]) -> list[dict]:
    """The rows with the estimate and its pieces recomputed by today's :func:`ephem.forced.rotation_scale.error_terms`
    (the truth kept): a change of the estimate is judged on the stored population without integrating again."""
    fields = [f.name for f in dataclasses.fields(Case)]
    out = []
    for r in rows:
        case = Case(**{k: float(r[k]) for k in fields})
        b = case.body()
        pieces = rs.error_terms(cached_model(b), b.moments, case.span_days(), r["axis"], r["variant"])
        new = {k: v for k, v in r.items() if not k.endswith("_mas") or k == "true_mas"}
        new.update(estimate_mas=sum(pieces.values()) / MAS, **{f"{k}_mas": v / MAS for k, v in pieces.items()})
        out.append(new)
    return out


#: Truths below this (mas; 1e-12 rad, the ladder's rounding term) are rounding, not error: counted apart from the
#: ratios. The rigid reference itself is good to ~1e-14 rad (rtol 1e-12 against 1e-13).
FLOOR_MAS = ROUNDING / MAS


def _measurable(rows: list[dict], variant: str, axis: str) -> list[dict]:
    return [r for r in rows if r["variant"] == variant and r["axis"] == axis and float(r["true_mas"]) > FLOOR_MAS]


def ratio_rows(rows: list[dict]) -> list[dict]:
    """Estimate over truth per (variant, axis): count, median, the quartiles, max and min, how many times the truth
    exceeded the estimate (with the rounding floor), and how many truths were below the floor (left out)."""
    out = []
    for variant in VARIANTS:
        for axis in AXES:
            every = [r for r in rows if r["variant"] == variant and r["axis"] == axis]
            sel = _measurable(rows, variant, axis)
            if not sel:
                continue
            q = np.array([float(r["estimate_mas"]) / float(r["true_mas"]) for r in sel])
            exceeded = sum(float(r["true_mas"]) > float(r["estimate_mas"]) + FLOOR_MAS for r in every)
            out.append({"variant": variant, "axis": axis, "cases": len(sel), "median": float(np.median(q)),
                        "p25": float(np.percentile(q, 25)), "p75": float(np.percentile(q, 75)),
                        "max": float(q.max()), "min": float(q.min()), "exceeded": int(exceeded),
                        "below_floor": len(every) - len(sel)})
    return out


def write_csv(path: Path, rows: list[dict]) -> None:
    keys = list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, keys)
        w.writeheader()
        w.writerows(rows)


def read_csv(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def population_rows(count: int, seeds=(1, 2), max_rotations: float = 2000.0,
                    orbit_range=(0.01, 20.0), progress=None) -> list[dict]:
    rows = []
    per_seed = max(1, count // len(seeds))
    for seed in seeds:
        for i, case in enumerate(generated_population(per_seed, seed, max_rotations, orbit_range)):
            rows += case_rows(case, len(rows) // (len(VARIANTS) * len(AXES)))
            if progress is not None:
                progress()
    return rows


def draw(rows: list[dict], out_dir: Path) -> None:
    """Estimate over truth for each variant and axis: every case as a dot, the median as a bar."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.2), layout="constrained")
    labels = []
    for i, (variant, axis) in enumerate((v, a) for v in VARIANTS for a in AXES):
        sel = _measurable(rows, variant, axis)
        q = np.array([float(r["estimate_mas"]) / float(r["true_mas"]) for r in sel])
        x = i + np.random.default_rng(i).uniform(-0.25, 0.25, q.size)
        ax.scatter(x, q, s=8, alpha=0.5, color="tab:blue" if axis == "figure" else "tab:orange")
        ax.plot([i - 0.35, i + 0.35], [np.median(q)] * 2, color="black", lw=2)
        labels.append(f"{variant}\n{'figure' if axis == 'figure' else 'L'}")
    ax.axhline(1.0, color="tab:red", lw=1)
    ax.axhline(3.0, color="0.5", ls="--", lw=0.8)
    ax.axhline(10.0, color="0.5", ls=":", lw=0.8)
    ax.set_yscale("log")
    ax.set_xticks(range(len(labels)), labels)
    ax.set_ylabel("estimate / true error")
    ax.set_title("Rotation averaging: error_terms against the rigid body (bar: median; red: the truth)")
    out_dir.mkdir(parents=True, exist_ok=True)
    fig.savefig(out_dir / "rotation_scale_ratios.png", dpi=150)
    fig.savefig(out_dir / "rotation_scale_ratios.svg", metadata={"Date": None})
    plt.close(fig)


def population_chart(out_dir: Path, quick: bool = False) -> None:
    count = 4 if quick else 160
    rows = population_rows(count, max_rotations=100.0 if quick else 2000.0,
                           orbit_range=(0.01, 1.0) if quick else (0.01, 20.0))
    out_dir.mkdir(parents=True, exist_ok=True)
    write_csv(out_dir / "rotation_scale_population.csv", rows)
    write_csv(out_dir / "rotation_scale_ratios.csv", ratio_rows(rows))
    draw(rows, out_dir)


def tasks(out_dir: Path, quick: bool = False):
    return [("rotation_scale_ratios", lambda: population_chart(out_dir, quick))]


app = chart_app(lambda out, quick=False: tasks(out, quick), "docs/accuracy.md",
                help="The rotation-scale terms' error estimate against the full rigid body, over a generated population.",
                quick_help="A small population (for the tests).")

if __name__ == "__main__":
    app()
