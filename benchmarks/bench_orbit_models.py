"""What each orbit model of a history costs (issue 39's choice by cost): CPU of one core, in a fresh process (the
first history of a CLI call: the model's one-time work included) and again in the same process (a service's warm
worker), for the catalogue bodies over short and long spans, beside the price :mod:`ephem.longterm.history` predicts
for each.

    python benchmarks/bench_orbit_models.py [-n 3] [--out FILE]     # FILE: the tables alone, as markdown

benchmarks/RESULTS_orbit_models.md holds a run's tables and what they say.

Each case runs in its own subprocess (benchmarks/machine.py's environment: compiled bytecode, a table cache of its
own, warmed by a first run): the imports and the body's theory (its ``secular_spin``) are made first, then the
history along the named orbit model is timed twice (``time.process_time``). The two models share the spin
integration (its steps depend on the orbit only through the orbit normal's turn between samples), so the difference
of their CPU is the difference of their orbits: the secular theory's modes solved and summed and its error against
the N-body orbit, against the shipped N-body file read and its spline. Each figure is the least over ``-n`` runs (the
machine is shared; the models alternate). Last, each piece the price is made of (``SHIPPED_READ_S`` and the others of
:mod:`ephem.longterm.history`, set about twice these) is measured alone in fresh processes.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

from machine import machine_info, tree_env   # benchmarks/machine.py: this directory is first on the path

ROOT = Path(__file__).resolve().parent.parent
CASES = [("earth", -3.0e6, 1.0e6, 1000.0), ("mars", -3.0e6, 1.0e6, 1000.0), ("ceres", -3.0e6, 1.0e6, 1000.0),
         ("vesta", -1.0e5, 1.0e5, 1000.0), ("earth", -2.0e4, 2.0e4, 100.0), ("steins", -1.0e4, 0.0, 100.0),
         ("mars", -5.0e6, 0.0, 5000.0), ("ceres", -5.0e6, 0.0, 5000.0)]
MODELS = ("secular", "nbody")

_CHILD = """
import json, sys, time
from ephem import api
from ephem.answers.requests import _perturbers
from ephem.bodies.catalogue import resolve_body
from ephem.families import theory_for
from ephem.longterm import history as H
name, lo, hi, step, model = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
b = resolve_body(name, "current")
theory = theory_for(b, _perturbers(b, None))
spin = theory.secular_spin()
out = {}
for when in ("cold", "warm"):
    t0 = time.process_time()
    try:
        r = H.spin_axis_history(b, theory, lo, hi, step, orbit_model=model)
        out[when] = time.process_time() - t0
    except api.EphemError as exc:
        out = {"error": str(exc)}
        break
try:
    years = H.history_grid(lo, hi, step)
    choice = {c.name: c for c in H.orbit_choices(b, spin.orbit_body, float(years[0]), float(years[-1]))}[model]
    full = H.history_cost(spin, choice, float(years[0]), float(years[-1]), years.size)
    out["predicted"] = full.cpu_s
    out["orbit_predicted"] = sum(p.cpu_s for p in full.parts[:-1])       # the last part is the spin's
except api.EphemError:
    pass
print(json.dumps(out))
"""


#: each priced piece alone, in a fresh process (the constants of ephem.longterm.history: SHIPPED_READ_S and the rest)
_PIECES = """
import json, time
import numpy as np
from ephem.longterm import history as H, nbody_orbit as N, secular_orbit as S
def cpu(f, *a):
    t0 = time.process_time(); f(*a); return 1e3 * (time.process_time() - t0)
x = np.linspace(-3.0e6, 1.0e6, 80001)
def points(o):
    o.pole_at(x); o.semi_major_axis_at(x); o.eccentricity_at(x)
out = {"secular modes solved (ms)": cpu(S._planets_solution),
       "shipped N-body orbit read, with its spline and noise (ms)": cpu(N.shipped_orbit_history, "Earth")}
out["secular envelope, planets (ms)"] = cpu(H.secular_envelope, "planet")
out["secular envelope, small bodies (ms)"] = cpu(H.secular_envelope, "small body")
for name, orbit in (("N-body spline", N.shipped_orbit_history("Earth")), ("secular modes", S.planet_secular_history("Earth"))):
    out[f"{name} at one epoch: pole, a, e (us)"] = min(cpu(points, orbit) for _ in range(3)) / x.size * 1e3
print(json.dumps(out))
"""


def pieces() -> dict:
    """Each priced piece's CPU in a fresh process (the table cache warm, as on a CLI user's second call)."""
    proc = subprocess.run([sys.executable, "-c", _PIECES], cwd=ROOT, env=tree_env(ROOT), capture_output=True,
                          text=True, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def run_case(body: str, lo: float, hi: float, step: float, model: str) -> dict:
    proc = subprocess.run([sys.executable, "-c", _CHILD, body, repr(lo), repr(hi), repr(step), model], cwd=ROOT,
                          env=tree_env(ROOT), capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{body} {model} failed:\n{proc.stderr}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=3, help="runs per case and model (default 3); the least is kept")
    ap.add_argument("--out", type=Path, help="write the table (markdown) here too")
    opts = ap.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    lines = [f"- {line}" for line in machine_info()]
    run_case("earth", -1.0e3, 1.0e3, 100.0, "nbody")          # the table cache written, the bytecode compiled
    lines += ["", "| body | years from J2000 | step (yr) | model | CPU cold (ms) | CPU warm (ms) | predicted (ms) | "
              "its orbit's part, predicted (ms) |", "|---|---|---:|---|---:|---:|---:|---:|"]
    diffs = ["", "The secular model's CPU less the N-body model's (the orbits' difference: the spin integration is the "
             "same):", "", "| body | years from J2000 | measured cold (ms) | measured warm (ms) | predicted (ms) |",
             "|---|---|---:|---:|---:|"]
    for body, lo, hi, step in CASES:
        by_model = {m: [] for m in MODELS}
        for _ in range(opts.n):                     # the models alternate: the machine's load falls on both alike
            for model in MODELS:
                by_model[model].append(run_case(body, lo, hi, step, model))
        for model, runs in by_model.items():
            if "error" in runs[0]:
                lines.append(f"| {body} | {lo:g} .. {hi:g} | {step:g} | {model} | – | – | – | {runs[0]['error'][:90]}… |")
                continue
            cold = 1e3 * min(r["cold"] for r in runs)
            warm = 1e3 * min(r["warm"] for r in runs)
            lines.append(f"| {body} | {lo:g} .. {hi:g} | {step:g} | {model} | {cold:.1f} | {warm:.1f} | "
                         f"{1e3 * runs[0]['predicted']:.1f} | {1e3 * runs[0]['orbit_predicted']:.1f} |")
            print(lines[-1], flush=True)
        if all("error" not in runs[0] for runs in by_model.values()):
            sec, nb = by_model["secular"], by_model["nbody"]
            diffs.append(f"| {body} | {lo:g} .. {hi:g} | "
                         + " | ".join(f"{1e3 * (min(r[k] for r in sec) - min(r[k] for r in nb)):.1f}"
                                      for k in ("cold", "warm"))
                         + f" | {1e3 * (sec[0]['predicted'] - nb[0]['predicted']):.1f} |")
    measured = [pieces() for _ in range(opts.n)]
    diffs += ["", "Each priced piece alone, in a fresh process (least and largest of the runs):", "",
              "| piece | measured |", "|---|---:|"]
    diffs += [f"| {k} | {min(m[k] for m in measured):.3g}-{max(m[k] for m in measured):.3g} |" for k in measured[0]]
    text = "\n".join(lines + diffs) + "\n"
    print(text)
    if opts.out:
        opts.out.write_text(text)


if __name__ == "__main__":
    main()
