"""How close each error estimate comes to the truth: estimate over true error, per rung and per term.

A study, not the library (see :mod:`studies`): run from the project root as
``python -m studies.estimate_ratios [--out DIR] [--quick]``. Three groups, each against its own reference:

* the theory terms of the rungs ``secular`` to ``second_order`` (``Estimate.theory_total``) against rung 5
  (``numerical``, the same fixed orbit), over a generated population of bodies and spans
  (:func:`theory_cases`: e to 0.9, obliquities near 0°, 90° and 180° and between, H_d 10⁻³ to 0.3, spans
  from days to a century, both signs);
* ``orbit_motion`` against the gap between ``numerical`` and ``real_orbit`` for the catalogue bodies, over
  random spans inside DE421 (a day to 150 years, either side of the pole epoch, most not reaching it);
* ``rotation_averaging`` (:func:`ephem.forced.rotation_scale.error_terms`) against the full rigid body, read from
  ``rotation_scale_population.csv`` (:mod:`studies.rotation_scale`, which integrates it; a run of its own).

It writes ``estimate_ratios.csv`` (one row per case and rung or term), ``estimate_ratios_summary.csv`` (count,
median, quartiles, worst and best per group) and the chart ``estimate_ratios.png``/``.svg``. Cases whose truth
is below 10⁻¹² rad (0.2 µas, the ladder's rounding term) are kept in the CSV and left out of the ratios: below it
every estimate is the rounding floor.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from ephem.bodies.catalogue import Body, Orbit, Pole, get_body
from ephem.base.constants import JULIAN_YEAR_DAYS, MAS
from ephem.orbit.hansen import LAPLACE_LIMIT
from ephem.base.constants import ROUNDING
from ephem.theory.tracks import pole_vectors
from ephem.sun.ladder import Ladder
from ephem.forced.integration import angular_separation

from ._command import chart_app
from .rotation_scale import write_csv

#: The theory rungs compared with rung 5: (rung, e-order).
THEORY_RUNGS = (("secular", None), ("series", 2), ("series", 4), ("series", 8), ("hansen", None),
                ("second_order", None))
#: Spans of the theory population (days): from a few days to a century.
THEORY_SPANS_DAYS = (3.0, 30.0, JULIAN_YEAR_DAYS, 10 * JULIAN_YEAR_DAYS, 100 * JULIAN_YEAR_DAYS)
ORBIT_BODIES = ("Ceres", "Vesta", "Eros", "Steins", "Itokawa", "Mars", "Earth")
#: Epochs a request of the population asks for (evenly over its span).
EPOCHS = 600
#: Truths below this (radians) are rounding, not error: left out of the ratios.
FLOOR = ROUNDING


def synthetic(e: float, obliquity_deg: float, hd: float, period_hours: float, a_au: float, node_deg: float,
              peri_deg: float, m0_deg: float) -> Body:
    """A body on an orbit in the ecliptic whose pole stands at ``obliquity_deg``."""
    return Body("synthetic", Orbit(a_au, e, 0.0, 0.0, peri_deg, m0_deg, 2451545.0),
                Pole.from_ecliptic(node_deg - 90.0, 90.0 - obliquity_deg), period_hours, dynamical_ellipticity=hd)


def theory_cases(count: int, seed: int = 5) -> list[tuple[Body, np.ndarray]]:
    """``count`` generated (body, epochs) pairs: e in {0.01, 0.1, 0.3, 0.5, 0.7, 0.9}, obliquities near 0.5°, 30°,
    60°, 89.5°, 120° and 179.5°, H_d log-uniform in [10⁻³, 0.3], periods 2-30 h, a 0.8-5 au, a span of
    :data:`THEORY_SPANS_DAYS` (either sign) from the pole epoch, or a window of it that does not reach the epoch."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        e = float(rng.choice([0.01, 0.1, 0.3, 0.5, 0.7, 0.9]))
        obliquity = float(rng.choice([0.5, 30.0, 60.0, 89.5, 120.0, 179.5]) + rng.uniform(-0.2, 0.2))
        hd = float(np.exp(rng.uniform(math.log(1e-3), math.log(0.3))))
        body = synthetic(e, obliquity, hd, float(rng.uniform(2.0, 30.0)), float(rng.uniform(0.8, 5.0)),
                         *(float(x) for x in rng.uniform(0.0, 360.0, 3)))
        span = float(rng.choice(THEORY_SPANS_DAYS)) * float(rng.choice([1.0, -1.0]))
        t0 = 2451545.0
        start = t0 if rng.uniform() < 0.5 else t0 + 0.5 * span        # half the windows do not reach t0
        out.append((body, np.linspace(start, t0 + span, EPOCHS)))
    return out


def theory_rows(count: int) -> list[dict]:
    rows = []
    for i, (body, t) in enumerate(theory_cases(count)):
        ladder = Ladder(body, "angular_momentum")
        est = {(e.rung, e.order): e for e in ladder.estimates(t) if e.available and e.rotation_scale is None}
        if ("numerical", None) not in est:
            continue
        ref = pole_vectors(ladder.track("numerical", t))
        own = est[("numerical", None)].theory_total
        m = ladder.model
        for rung, order in THEORY_RUNGS:
            if (rung, order) not in est or (order is not None and m.eccentricity >= LAPLACE_LIMIT):
                continue
            true = float(np.max(angular_separation(pole_vectors(ladder.track(rung, t, order)), ref)))
            rows.append({"group": "theory", "case": i, "label": rung if order is None else f"series N={order}",
                         "e": m.eccentricity, "obliquity_deg": math.degrees(m.obliquity), "hd": m.hd,
                         "span_days": float(t[-1] - t[0]), "true_mas": true / MAS,
                         "estimate_mas": est[(rung, order)].theory_total / MAS, "reference_mas": own / MAS})
    return rows


def orbit_rows(count_per_body: int, seed: int = 7, bodies=ORBIT_BODIES) -> list[dict]:
    """``orbit_motion`` against the gap between rungs 5 and 6, random spans inside DE421 per catalogue body."""
    from ephem.orbit.de421 import de421_span

    lo, hi = de421_span()
    lo, hi = lo + 60.0, hi - 60.0
    rng = np.random.default_rng(seed)
    rows = []
    for name in bodies:
        ladder = Ladder(get_body(name), "angular_momentum")
        t0 = ladder.model.pole_epoch
        for i in range(count_per_body):
            length = float(np.exp(rng.uniform(math.log(1.0), math.log(150 * JULIAN_YEAR_DAYS))))
            start = float(rng.uniform(lo, max(lo, hi - length)))
            t = np.linspace(start, min(start + length, hi), 400)
            est = next(e for e in ladder.estimates(t) if e.rung == "numerical" and e.rotation_scale is None)
            gap = float(np.max(angular_separation(pole_vectors(ladder.track("numerical", t)),
                                                  pole_vectors(ladder.track("real_orbit", t)))))
            rows.append({"group": "orbit_motion", "case": i, "label": name, "e": ladder.model.eccentricity,
                         "obliquity_deg": math.degrees(ladder.model.obliquity), "hd": ladder.model.hd,
                         "span_days": float(t[-1] - t[0]), "true_mas": gap / MAS,
                         "estimate_mas": est.terms["orbit_motion"] / MAS,
                         "reference_mas": 2.0 * est.theory_total / MAS,
                         "reaches_pole_epoch": bool(t[0] <= t0 <= t[-1])})
    return rows


def rotation_rows(path: Path) -> list[dict]:
    """The rotation-scale population's rows (studies.rotation_scale), as ratios per variant and axis."""
    if not path.exists():
        return []
    with open(path, newline="") as fh:
        src = list(csv.DictReader(fh))
    return [{"group": "rotation_averaging", "case": int(r["case"]),
             "label": f"{r['variant']}, {'figure' if r['axis'] == 'figure' else 'L'}", "e": float(r["e"]),
             "obliquity_deg": float(r["obliquity_deg"]), "hd": "", "span_days": "",
             "true_mas": float(r["true_mas"]), "estimate_mas": float(r["estimate_mas"]),
             "reference_mas": FLOOR / MAS} for r in src]


def summary_rows(rows: list[dict]) -> list[dict]:
    out = []
    for group in dict.fromkeys(r["group"] for r in rows):
        for label in dict.fromkeys(r["label"] for r in rows if r["group"] == group):
            sel = [r for r in rows if r["group"] == group and r["label"] == label
                   and float(r["true_mas"]) * MAS > FLOOR]
            if not sel:
                continue
            q = np.array([float(r["estimate_mas"]) / float(r["true_mas"]) for r in sel])
            # the truth may exceed the estimate by the reference's own error (rung 5's estimate, rung 6's)
            exceeded = sum(float(r["true_mas"]) > float(r["estimate_mas"]) + float(r["reference_mas"]) for r in sel)
            out.append({"group": group, "label": label, "cases": len(sel), "median": float(np.median(q)),
                        "p25": float(np.percentile(q, 25)), "p75": float(np.percentile(q, 75)),
                        "worst": float(q.max()), "best": float(q.min()), "exceeded": int(exceeded)})
    return out


def draw(rows: list[dict], out_dir: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = [g for g in ("theory", "orbit_motion", "rotation_averaging") if any(r["group"] == g for r in rows)]
    titles = {"theory": "theory terms against rung 5 (numerical)",
              "orbit_motion": "orbit_motion against rung 6 (real orbit)",
              "rotation_averaging": "rotation_averaging against the rigid body"}
    fig, axes = plt.subplots(1, len(groups), figsize=(5.0 * len(groups), 4.6), layout="constrained", sharey=True,
                             squeeze=False)
    for ax, group in zip(axes[0], groups):
        labels = list(dict.fromkeys(r["label"] for r in rows if r["group"] == group))
        for i, label in enumerate(labels):
            sel = [r for r in rows if r["group"] == group and r["label"] == label and float(r["true_mas"]) * MAS > FLOOR]
            q = np.array([float(r["estimate_mas"]) / float(r["true_mas"]) for r in sel])
            if not q.size:
                continue
            x = i + np.random.default_rng(i).uniform(-0.28, 0.28, q.size)
            ax.scatter(x, q, s=7, alpha=0.45, color="tab:blue", lw=0)
            ax.plot([i - 0.38, i + 0.38], [np.median(q)] * 2, color="black", lw=2)
        ax.axhline(1.0, color="tab:red", lw=1.0)
        ax.axhline(3.0, color="0.45", ls="--", lw=0.8)
        ax.axhline(10.0, color="0.45", ls=":", lw=0.8)
        ax.set_yscale("log")
        ax.set_xticks(range(len(labels)), labels, rotation=45, ha="right", fontsize=8)
        ax.set_title(titles[group], fontsize=9)
        ax.grid(True, axis="y", which="major", alpha=0.3)
    axes[0][0].set_ylabel("estimate / true error\n(bar: median; red: the truth; dashed 3×, dotted 10×)")
    fig.suptitle("How close the error estimates come to the truth", fontsize=11)
    fig.savefig(out_dir / "estimate_ratios.png", dpi=150)
    fig.savefig(out_dir / "estimate_ratios.svg", metadata={"Date": None})
    plt.close(fig)


def chart(out_dir: Path, quick: bool = False) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    # quick: the planets only (DE421 gives their orbits at once; an asteroid's is integrated over 150 years first)
    rows = theory_rows(6 if quick else 120) + orbit_rows(2 if quick else 30, bodies=ORBIT_BODIES[-2:] if quick
                                                         else ORBIT_BODIES) \
        + rotation_rows(out_dir / "rotation_scale_population.csv")
    write_csv(out_dir / "estimate_ratios.csv", rows)
    write_csv(out_dir / "estimate_ratios_summary.csv", summary_rows(rows))
    draw(rows, out_dir)


def tasks(out_dir: Path, quick: bool = False):
    return [("estimate_ratios", lambda: chart(out_dir, quick))]


app = chart_app(lambda out, quick=False: tasks(out, quick), "docs/accuracy.md",
                help="Estimate over true error per rung and term (theory, orbit motion, rotation averaging).",
                quick_help="A small population (for the tests).")

if __name__ == "__main__":
    app()
