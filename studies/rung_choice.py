"""Which model a tolerance picks, and what it costs: the product's choice over a fixed set of scenes.

A study, not the library (see :mod:`studies`): run from the project root as
``python -m studies.rung_choice [--out DIR] [--label NAME]``. For the catalogue bodies and the three fast
precessors of issue 15 (:func:`issue_bodies`), over four spans, four tolerances and both axes, it asks
:func:`ephem.api.track` for the track by tolerance and writes ``rung_choice_{label}.csv``: the model served (rung,
e-order, the rotation-scale terms), its estimate and its cost, or the refusal with the best estimate. It imports
only the API, so the same file runs on an older checkout: the committed ``rung_choice_before.csv`` was made with it
on commit 93e801e (before issue 15's tighter estimates), ``rung_choice_after.csv`` on today's code;
:func:`compare_rows` sets them side by side (docs/accuracy.md).
"""
from __future__ import annotations

import csv
import re
import time
from dataclasses import replace
from pathlib import Path

import typer

from ephem import api
from ephem.bodies.catalogue import Body, get_body
from ephem.base.errors import NotApplicableError

#: (label, start, stop, step in days)
SPANS = (("30 days", "2020-01-01", "2020-01-31", 1.0), ("1 year", "2020-01-01", "2021-01-01", 5.0),
         ("20 years", "2000-01-01", "2020-01-01", 30.0), ("100 years", "1950-01-01", "2050-01-01", 365.25))
TOLERANCES_MAS = (1.0, 10.0, 100.0, 1000.0)
AXES = ("angular_momentum", "figure")
CATALOGUE = ("Ceres", "Vesta", "Eros", "Steins", "Itokawa", "Mars", "Earth")


def issue_bodies() -> dict[str, Body]:
    """The three fast precessors of issue 15, as users' bodies (no measured orbit motion: a comparison with the
    rigid body, which follows the same Keplerian orbit, is about rotation averaging alone):

    * an Itokawa-like body: a = 1.3241 au, e = 0.2801, P = 12.132 h, H_d = 0.38 and no moments (the worst
      triaxiality its H_d allows), Itokawa's pole (obliquity 178.7°);
    * an Eros-like body near 90° obliquity: Eros' orbit, pole (obliquity 89.0°), period and moments;
    * a 4-hour rotator on an e = 0.75 orbit: the Itokawa-like body spun at P = 4 h with e = 0.75.
    """
    ito, eros = get_body("itokawa"), get_body("eros")
    return {
        "itokawa-like": Body(name="itokawa-like", orbit=replace(ito.orbit, a_au=1.3241, e=0.2801), pole=ito.pole,
                             rotation_period_hours=12.132, dynamical_ellipticity=0.38),
        "eros-like": Body(name="eros-like", orbit=eros.orbit, pole=eros.pole,
                          rotation_period_hours=eros.rotation_period_hours, moments=eros.moments),
        "4h-e0.75": Body(name="4h-e0.75", orbit=replace(ito.orbit, a_au=1.3241, e=0.75), pole=ito.pole,
                         rotation_period_hours=4.0, dynamical_ellipticity=0.38),
    }


def scenes():
    bodies = [(name, name.lower()) for name in CATALOGUE] + list(issue_bodies().items())
    for label, body in bodies:
        for span in SPANS:
            for axis in AXES:
                for tol in TOLERANCES_MAS:
                    yield label, body, span, axis, tol


_BEST = re.compile(r"the best, '([a-z_]+)', is estimated good to ([0-9.eE+-]+) mas")


def choice_row(label: str, body, span, axis: str, tol: float) -> dict:
    """One request by tolerance: what was served (or why not) and its wall-clock cost."""
    name, start, stop, step = span
    row = {"body": label, "span": name, "axis": axis, "tolerance_mas": tol}
    t = time.perf_counter()
    try:
        ans = api.track(body, start, stop, step, tolerance_mas=tol, axis=axis)
    except NotApplicableError as exc:
        best = _BEST.search(str(exc))
        row.update(served=False, model="", order="", rotation_scale="", estimated_error_mas=float(best.group(2))
                   if best else "", best_model=best.group(1) if best else "", reason=str(exc)[:160])
    else:
        m = ans["model"]
        row.update(served=True, model=m["name"], order="" if m.get("order") is None else m["order"],
                   rotation_scale=(m.get("rotation_scale") or {}).get("modelled", ""),
                   estimated_error_mas=m["estimated_error_mas"], best_model="", reason="")
    row["wall_ms"] = 1e3 * (time.perf_counter() - t)
    return row


def write_csv(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def read_csv(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def compare_rows(before: list[dict], after: list[dict]) -> list[dict]:
    """Before and after side by side, per scene: the model, served or not, and the wall time."""
    key = ("body", "span", "axis", "tolerance_mas")
    old = {tuple(r[k] for k in key): r for r in before}
    out = []
    for r in after:
        b = old.get(tuple(r[k] for k in key))
        if b is None:
            continue

        def what(x):
            if x["served"] != "True":
                return f"refused ({float(x['estimated_error_mas']):.3g})" if x["estimated_error_mas"] else "refused"
            order = f" N={x['order']}" if x["order"] else ""
            extra = f" +{x['rotation_scale']}" if x["rotation_scale"] else ""
            return f"{x['model']}{order}{extra}"

        out.append({**{k: r[k] for k in key}, "before": what(b), "after": what(r),
                    "before_ms": float(b["wall_ms"]), "after_ms": float(r["wall_ms"])})
    return out


app = typer.Typer(add_completion=False)


@app.command()
def main(out: Path = typer.Option(Path("docs/charts"), "--out"), label: str = typer.Option("after", "--label")):
    """Run every scene twice and write the CSV: the second call's time (the caches the first built: the model, the
    Sun's real path) as ``wall_ms``, the first's as ``first_wall_ms``."""
    rows = []
    for label_, body, span, axis, tol in scenes():
        first = choice_row(label_, body, span, axis, tol)
        row = choice_row(label_, body, span, axis, tol)
        rows.append({**row, "first_wall_ms": first["wall_ms"]})
    out.mkdir(parents=True, exist_ok=True)
    write_csv(out / f"rung_choice_{label}.csv", rows)
    typer.echo(f"wrote {len(rows)} rows to {out / f'rung_choice_{label}.csv'}")


if __name__ == "__main__":
    app()
