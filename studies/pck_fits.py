"""The measured fit errors of docs/pck.md: each row's kernel written, its fit error and angle count, and the
largest angle between SPICE's own pole (spiceypy's ``tipbod``) and the track at 3000 epochs off the fit grids.

A study, not the library (see :mod:`studies`): run from the project root as ``python -m studies.pck_fits``; it
prints the Markdown table that docs/pck.md carries. The rows' angle counts are the same on every CPU (the fit's
choice is made stable against rounding: tests/theory/test_stable_choices.py), the errors agree to the digits shown.
"""
from __future__ import annotations

import math
import tempfile
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
import typer

from ephem import api
from ephem.answers import kernels as pck
from ephem.exports import pck_kernel
from ephem.base.errors import InvalidInputError

MAS = math.pi / 648_000_000.0
STAMP = datetime(2026, 1, 1, tzinfo=UTC)
#: (label, body, start, stop, keyword arguments of write_pck, check with SPICE)
ROWS = (
    ("Ceres", "ceres", "2020-01-01", "2040-01-01", {}, True),
    ("Vesta", "vesta", "2020-01-01", "2040-01-01", {}, True),
    ("Vesta", "vesta", "1950-01-01", "2150-01-01", {}, False),
    ("Vesta", "vesta", "1500-01-01", "2500-01-01", {}, True),
    ("Eros", "eros", "2020-01-01", "2040-01-01", {}, True),
    ("Steins", "steins", "2020-01-01", "2040-01-01", {}, True),
    ("Itokawa", "itokawa", "2020-01-01", "2040-01-01", {}, True),
    ("Itokawa", "itokawa", "1950-01-01", "2050-01-01", {}, True),
    ("Mars", "mars", "2020-01-01", "2040-01-01", {}, True),
    ("Mars", "mars", "1900-01-01", "2100-01-01", {}, False),
    ('Earth, `perturbers="sun"`', "earth", "2020-01-01", "2040-01-01", {"perturbers": "sun"}, True),
    ("Earth (Moon and Sun)", "earth", "2020-01-01", "2021-01-01", {}, True),
    ("Earth (Moon and Sun)", "earth", "2020-01-01", "2040-01-01", {}, False),
    ("Earth, `max_angles=200`", "earth", "2020-01-01", "2040-01-01", {"max_angles": 200}, True),
    ("Vesta, `tolerance_mas=10`", "vesta", "2020-01-01", "2021-01-01", {"tolerance_mas": 10.0}, False),
    ('Vesta, `model="second_order"`', "vesta", "2020-01-01", "2040-01-01", {"model": "second_order"}, False),
)


def _unit(ra_deg, dec_deg) -> np.ndarray:
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


def spice_error_mas(result: pck_kernel.PckResult, body: str, kwargs: dict, count: int = 3000) -> float:
    """The largest angle (mas) between SPICE's pole of the kernel and the track at ``count`` epochs off the
    fit and check grids."""
    import spiceypy as spice

    fit = result.bodies[0]
    t0, t1 = result.start_jd_tdb, result.stop_jd_tdb
    step = (t1 - t0) / count
    named = {k: v for k, v in kwargs.items() if k in ("perturbers",)}
    tr = api.track_arrays(body, t0 + 0.381966 * step, t1, step, order=fit.model["order"], model=fit.model["name"],
                          max_samples=count + 1, **named)
    ours = _unit(tr["pole_ra_deg"], tr["pole_dec_deg"])
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "fit.tpc"
        path.write_text(result.text, encoding="ascii")
        spice.kclear()
        spice.furnsh(str(path))
        try:
            poles = np.array([spice.tipbod("J2000", fit.naif_id, (jd - 2451545.0) * 86400.0)[2]
                              for jd in tr["jd_tdb"]])
        finally:
            spice.kclear()
    cosang = np.clip(np.sum(poles * ours, axis=-1), -1.0, 1.0)
    sinang = np.linalg.norm(np.cross(poles, ours), axis=-1)
    return float(np.max(np.arctan2(sinang, cosang))) / MAS


def _mas(x: float) -> str:
    return f"{x / 1000:.2g}″" if x >= 1000 else f"{x:.3g} mas"


def row(label, body, start, stop, kwargs, with_spice) -> str:
    span = f"{start[:4]}–{stop[:4]}"
    try:
        result = pck.write_pck([body], start, stop, generated=STAMP, **kwargs)
    except InvalidInputError as exc:
        reason = exc.reason
        best = reason[reason.index("(best ") + 6:reason.index(")", reason.index("(best "))]
        return f"| {label} | {span} | | | refused: {best} | | | |"
    fit = result.bodies[0]
    spice = f"{spice_error_mas(result, body, kwargs):.2g} mas" if with_spice else ""
    return (f"| {label} | {span} | {fit.model['name']} | {_mas(fit.model['estimated_error_mas'])} | "
            f"{fit.fit_error_mas:.2g} mas | {spice} | {len(fit.angles)} | {len(result.text) / 1000:.1f} kB |")


def main() -> None:
    """Print docs/pck.md's table of measured fit errors."""
    typer.echo("| body | span | model | model's estimate | fit error | SPICE | angles | kernel |")
    typer.echo("|---|---|---|---|---|---|---|---|")
    for spec in ROWS:
        typer.echo(row(*spec))


if __name__ == "__main__":
    typer.run(main)
