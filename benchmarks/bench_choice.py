"""The choice by tolerance before and after it became one rule for every decision (issue 43a): ``choose`` timed on the
plans of real tracks, the ``ephem/theory/choice.py`` of a given commit against the working tree's, in one process.

Each family's estimates for a 37-epoch track in 2040 (the long-term model, a run of a history, left out: both versions
make it the same way), priced 1 ms, 2 ms, ... in the family's order, chosen at a tolerance just above the median
estimate; both versions must choose the same model with the same reason. Best of 15 rounds of 200 calls each (the machine is shared: the least disturbed round),
alternated. Writes nothing: the numbers go to benchmarks/RESULTS_choice.md by hand.

    .venv/bin/python benchmarks/bench_choice.py [--before 9b66c41]
"""
from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from ephem.base.budget import Cost, Part  # noqa: E402
from ephem.bodies.catalogue import get_body  # noqa: E402
from ephem.families import theory_for  # noqa: E402
from ephem.theory import choice as after  # noqa: E402

ROUNDS = 15
CASES = [("Ceres", ("Sun",)), ("Itokawa", ("Sun",)), ("Earth", ("Moon", "Sun")), ("Moon", ("Earth", "Sun"))]


def choice_at(commit: str):
    """``ephem/theory/choice.py`` as it was at ``commit``, loaded as a module of the package (its relative imports
    resolve against the working tree's ``ephem.base`` and ``ephem.theory.results``)."""
    text = subprocess.run(["git", "show", f"{commit}:ephem/theory/choice.py"], cwd=ROOT, capture_output=True,
                          text=True, check=True).stdout
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "choice_before.py"
        path.write_text(text, encoding="utf-8")
        spec = importlib.util.spec_from_file_location("ephem.theory.choice_before", path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = module          # its dataclasses look their module up
        spec.loader.exec_module(module)
    return module


def refuse(made):
    raise RuntimeError("no model within the tolerance")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default="9b66c41", help="the commit whose choice.py is 'before'")
    args = parser.parse_args()
    before = choice_at(args.before)
    jd = np.linspace(2466154.5, 2466519.5, 37)
    print(f"choose(), best of 15 x 200 calls (us): before = {args.before}, after = the working tree")
    for name, perturbers in CASES:
        theory = theory_for(get_body(name), perturbers).inner
        plan = [p for p in theory.estimate_plan(jd) if not isinstance(p, after.Deferred)]
        costs = [None if not p.available else Cost((Part("x", "x", 1e-3 * (1 + i), 1.0),)) for i, p in enumerate(plan)]
        tolerance = sorted(p.total for p in plan if p.available)[len(plan) // 2] * 1.0001
        got = [(c.chosen.rung, c.chosen.order, c.reason) for c in
               (m.choose(plan, list(costs), tolerance, refuse) for m in (before, after))]
        assert got[0] == got[1], got
        times = {"before": [], "after": []}
        for _ in range(ROUNDS):
            for label, module in (("before", before), ("after", after)):
                t0 = time.perf_counter()
                for _ in range(200):
                    module.choose(plan, list(costs), tolerance, refuse)
                times[label].append((time.perf_counter() - t0) / 200 * 1e6)
        b, a = min(times["before"]), min(times["after"])
        print(f"{name:8s} {len(plan):3d} models: {b:7.1f} before, {a:7.1f} after (x{a / b:.2f}); same choice, "
              f"same reason")


if __name__ == "__main__":
    main()
