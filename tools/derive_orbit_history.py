"""Derive data/orbit_history/: the catalogue bodies' orbit planes over -3 Myr .. +1 Myr, from REBOUND (WHFast).

One N-body run (the setup lives in :mod:`ephem.longterm.nbody_orbit`, shared with ``nbody_orbit_history``): the Sun
and the eight planetary systems from DE421 at J2000.0 TDB (the Earth-Moon barycentre for the Earth), and the
asteroids Ceres, Vesta, Eros, Steins, Itokawa as test particles from the catalogue's elements (carried from
their epochs to J2000.0 with IAS15), integrated with WHFast (dt = 5.50075 d, corrector 11) backwards to
-3 Myr and forwards to +1 Myr, sampled every 500 Julian years (osculating heliocentric orbit normal,
ecliptic J2000; a; e). Each asteroid has a clone started 1 km further from the Sun; the first times its
orbit normal is 1 arcmin and 1 deg from the nominal one (checked every 10 years) are its horizons. The
planets get a shadow run (the Earth-Moon barycentre moved 1 km) for theirs, and a dt vs dt/2 run over
+-20 kyr measures the integration error.

Outputs: ``data/orbit_history/<body>.npz`` (years, pole (N,3), a_au, e; float64, compressed) and
``data/orbit_history/metadata.toml`` (the run, the sources, each body's horizons).

    python tools/derive_orbit_history.py                 # everything in one process: ~30-40 min
    python tools/derive_orbit_history.py --part backward # or the parts, two at a time on two cores:
    python tools/derive_orbit_history.py --part forward  #   backward 21 min, forward 9 min,
    python tools/derive_orbit_history.py --part dtcheck  #   dtcheck 20 s,
    python tools/derive_orbit_history.py --part shadow   #   shadow (both directions) ~8 min,
    python tools/derive_orbit_history.py --part assemble #   then assemble (seconds)

(times measured on the shared 2-core VM, 2026-11-27, REBOUND 5.2.2, with a third CPU-bound process running
part of the time; the last 1 Myr of the backward part took 5 min alone: ~30 s per 100 kyr with 19 particles.)

Raw parts go to ``--workdir`` (default /tmp/orbit_history_raw).
"""
from __future__ import annotations

import argparse
import datetime
import math
import sys
import time
from pathlib import Path

import numpy as np

from ephem.bodies.catalogue import load_catalogue
from ephem.longterm.nbody_orbit import (DT_DAYS, MASSIVE, SAMPLE_YEARS, SHIPPED_ASTEROIDS, SHIPPED_PLANETS,
                                        STEPS_PER_SAMPLE, add_test_particle, asteroid_state_j2000, osculating,
                                        planet_simulation, run_history)

DATA = Path(__file__).resolve().parent.parent / "data" / "orbit_history"
PAST_YEARS = 3_000_000.0
FUTURE_YEARS = 1_000_000.0
#: clone offset: 1 km, radial (au)
CLONE_OFFSET_AU = 1.0 / 149_597_870.7
#: the clone divergence is checked every this many WHFast steps (664 x 5.50075 d = 10.0 Julian years)
FINE_STEPS = STEPS_PER_SAMPLE // 50
THRESHOLDS_RAD = {"1arcmin": math.radians(1.0 / 60.0), "1deg": math.radians(1.0)}
DTCHECK_YEARS = 20_000.0


def angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle (rad) between unit vectors along the last axis (atan2 form: accurate at small angles)."""
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("...i,...i->...", a, b))


def build(sign: float, dt_days: float = DT_DAYS, clones: bool = True, shadow: bool = False):
    """The run's simulation: planets (+ EMB moved 1 km if ``shadow``), asteroids (+ clones) as test particles."""
    sim = planet_simulation(sign * dt_days)
    if shadow:   # move the EMB 1 km away from the Sun (radially), keep its velocity
        emb, sun = sim.particles[3], sim.particles[0]
        d = np.array([emb.x - sun.x, emb.y - sun.y, emb.z - sun.z])
        d *= CLONE_OFFSET_AU / np.linalg.norm(d)
        emb.x += d[0]
        emb.y += d[1]
        emb.z += d[2]
        sim.move_to_com()
    cat = load_catalogue("current")
    if not shadow:
        states = {n: asteroid_state_j2000(cat.get(n).orbit) for n in SHIPPED_ASTEROIDS}
        for n in SHIPPED_ASTEROIDS:
            add_test_particle(sim, *states[n], n)
        if clones:
            for n in SHIPPED_ASTEROIDS:
                r, v = states[n]
                add_test_particle(sim, r * (1.0 + CLONE_OFFSET_AU / np.linalg.norm(r)), v, n + " clone")
    return sim


def run_part(sign: float, span_years: float, out: Path, dt_days: float = DT_DAYS, clones: bool = True,
             shadow: bool = False) -> None:
    """Integrate one direction and save the raw samples (and the clones' crossing times) to ``out``."""
    sim = build(sign, dt_days, clones, shadow)
    steps_per_sample = round(SAMPLE_YEARS * 365.25 / dt_days)
    fine = round(steps_per_sample / 50)
    n_samples = int(round(span_years / SAMPLE_YEARS))
    nb = len(SHIPPED_ASTEROIDS)
    i0 = len(MASSIVE) - 1                 # index of the first asteroid among the non-Sun particles
    crossing = {k: np.full(nb, np.nan) for k in THRESHOLDS_RAD}
    worst_fine = np.zeros(nb)

    def on_fine(s):
        p, _, _ = osculating(s)
        ang = angle(p[i0:i0 + nb], p[i0 + nb:i0 + 2 * nb])
        np.maximum(worst_fine, np.nan_to_num(ang, nan=np.pi), out=worst_fine)
        for key, thr in THRESHOLDS_RAD.items():
            new = np.isnan(crossing[key]) & ~(ang <= thr)     # NaN angle (runaway) counts as diverged
            crossing[key][new] = s.t / 365.25

    t0 = time.perf_counter()

    def on_sample(k, s):
        if k % 200 == 0:
            print(f"{out.name}: {k * SAMPLE_YEARS:.0f} yr, {time.perf_counter() - t0:.0f} s", flush=True)

    fine_kw = dict(fine_every=fine, on_fine=on_fine, fine_until_steps=n_samples * steps_per_sample) \
        if clones and not shadow else {}
    years, poles, a, e, worst = run_history(sim, n_samples, steps_per_sample, on_sample=on_sample, **fine_kw)
    wall = time.perf_counter() - t0
    np.savez(out, years=years, poles=poles, a=a, e=e, energy_error=worst, wall_seconds=wall,
             dt_days=dt_days, **{f"crossing_{k}": v for k, v in crossing.items()})
    print(f"{out.name}: done in {wall:.0f} s, max relative energy error {worst:.3g}", flush=True)


def part(name: str, work: Path) -> None:
    work.mkdir(parents=True, exist_ok=True)
    if name == "backward":
        run_part(-1.0, PAST_YEARS, work / "backward.npz")
    elif name == "forward":
        run_part(1.0, FUTURE_YEARS, work / "forward.npz")
    elif name == "shadow":
        run_part(1.0, FUTURE_YEARS, work / "shadow_forward.npz", clones=False, shadow=True)
        run_part(-1.0, PAST_YEARS, work / "shadow_backward.npz", clones=False, shadow=True)
    elif name == "dtcheck":
        for sign, tag in ((1.0, "forward"), (-1.0, "backward")):
            run_part(sign, DTCHECK_YEARS, work / f"dt_{tag}.npz", clones=False)
            run_part(sign, DTCHECK_YEARS, work / f"dt2_{tag}.npz", dt_days=DT_DAYS / 2.0, clones=False)
    elif name == "assemble":
        assemble(work)
    else:
        raise SystemExit(f"unknown part {name!r}")


def _join(back: dict, fwd: dict, key: str) -> np.ndarray:
    return np.concatenate([back[key][::-1], fwd[key][1:]])


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(float(v)) if isinstance(v, float) else str(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return '"' + str(v).replace("\\", "\\\\").replace('"', '\\"') + '"'


def assemble(work: Path) -> None:
    """Join the parts into the shipped files and the metadata."""
    import rebound

    load = lambda n: dict(np.load(work / n)) if (work / n).exists() else None  # noqa: E731
    back, fwd = load("backward.npz"), load("forward.npz")
    sback, sfwd = load("shadow_backward.npz"), load("shadow_forward.npz")
    dt = {f"{a}_{b}": load(f"{a}_{b}.npz") for a in ("dt", "dt2") for b in ("forward", "backward")}
    years = _join(back, fwd, "years")
    # sample k is k x 33200 WHFast steps of dt = 500 yr / 33200: exactly k x 500 yr. REBOUND's sim.t is a running
    # float sum (1e9 days, 2e8 additions) that drifts by 0.02 yr over 3 Myr; no force depends on t, so the
    # trajectory does not see it. Store the exact grid.
    grid = np.round(years / SAMPLE_YEARS) * SAMPLE_YEARS
    assert np.abs(grid - years).max() < 0.1
    names = [m[0] for m in MASSIVE[1:]] + list(SHIPPED_ASTEROIDS)
    cat = load_catalogue("current")
    DATA.mkdir(parents=True, exist_ok=True)
    lines = [
        "# Orbit-plane histories of the catalogue bodies: an N-body run with REBOUND (WHFast).",
        "# Generated by tools/derive_orbit_history.py (do not edit); read by ephem/longterm/nbody_orbit.py.",
        "# Per body: <body>.npz holds years (Julian years of 365.25 d from J2000.0 TDB), pole (N, 3: the",
        "# osculating heliocentric orbit normal, unit vector, mean ecliptic and equinox J2000), a_au, e.",
        "# Horizons: Julian years from J2000.0 where a clone (started 1 km further from the Sun) has its orbit",
        "# normal 1 arcmin / 1 deg from the nominal (asteroids: checked every 10 years; planets: a shadow run",
        "# with the Earth-Moon barycentre moved 1 km, compared every 500 years). A horizon equal to the span's",
        "# end means: not reached within the run (reached_* = false).",
        "",
        "[run]",
        f"generated = {_toml_value(datetime.date.today().isoformat())}",
        f"rebound_version = {_toml_value(rebound.__version__)}",
        'integrator = "WHFast (Rein & Tamayo 2015), Jacobi coordinates, symplectic corrector 11, '
        'keep_unsynchronized"',
        f"dt_days = {DT_DAYS!r}",
        f"sample_years = {SAMPLE_YEARS!r}",
        f"span_years = [{-PAST_YEARS!r}, {FUTURE_YEARS!r}]",
        'units = "au, day, solar mass; G = GM_SUN_DE421 = k^2 (au^3/day^2)"',
        'frame = "mean ecliptic and equinox J2000 (erfa.ecm06 at J2000, ephem.orbit.geometry.icrf_to_ecliptic_matrix)"',
        'massive_bodies = "Sun and the barycentres of Mercury..Neptune (Earth: Earth-Moon barycentre) from DE421 '
        'at J2000.0 TDB (Folkner, Williams & Boggs 2009) via skyfield + skyfield-data; GMs DE421 header '
        '(ephem.orbit.de421_header.GM_DE421, GM_SUN_DE421); moved to the centre of mass"',
        'test_particles = "Ceres, Vesta, Eros, Steins, Itokawa: catalogue \'current\' osculating heliocentric '
        'elements (ecliptic J2000, own epochs), placed among the DE421 planets of their epoch and carried to '
        'J2000.0 with IAS15; massless; plus one clone each, 1 km further from the Sun"',
        'left_out = "general relativity (Mercury perihelion 43 arcsec/cy), the Moon as a separate body, '
        'asteroid masses, Pluto, the Sun\'s J2 and mass loss, Yarkovsky"',
        f"max_relative_energy_error_past = {float(back['energy_error']):.3g}",
        f"max_relative_energy_error_future = {float(fwd['energy_error']):.3g}",
        f"wall_seconds_past = {float(back['wall_seconds']):.0f}",
        f"wall_seconds_future = {float(fwd['wall_seconds']):.0f}",
        'planets_horizon_literature = "inner solar system Lyapunov time ~5 Myr (Laskar 1989, Nature 338, 237; '
        'Laskar & Gastineau 2009, Nature 459, 817): a solution is good over a few tens of Myr at most"',
    ]
    if all(v is not None for v in dt.values()):
        lines.append(f"dtcheck_years = {DTCHECK_YEARS!r}")
        lines.append('dtcheck = "largest angle (arcsec) between the orbit normals of runs at dt and dt/2 over '
                     '+-dtcheck_years, sampled every 500 yr, per body below (dtcheck_arcsec)"')
    body_lines = []
    shipped = list(SHIPPED_PLANETS) + list(SHIPPED_ASTEROIDS)
    for name in shipped:
        j = names.index(name)
        pole = _join(back, fwd, "poles")[:, j]
        a = _join(back, fwd, "a")[:, j]
        e = _join(back, fwd, "e")[:, j]
        ok = np.isfinite(pole).all(axis=1) & np.isfinite(a) & (e < 1.0) & (a > 0.0)
        # the data kept: the contiguous run of good samples around J2000
        i0 = int(np.argmin(np.abs(grid)))
        lo = i0
        while lo > 0 and ok[lo - 1]:
            lo -= 1
        hi = i0
        while hi < len(grid) - 1 and ok[hi + 1]:
            hi += 1
        sl = slice(lo, hi + 1)
        fname = f"{name.lower()}.npz"
        np.savez_compressed(DATA / fname, years=grid[sl], pole=pole[sl] / np.linalg.norm(pole[sl], axis=1,
                                                                                           keepdims=True),
                            a_au=a[sl], e=e[sl])
        entry = {"file": fname, "data_span_years": [float(grid[lo]), float(grid[hi])]}
        if lo > 0 or hi < len(grid) - 1:
            entry["data_span_note"] = ("the nominal orbit became unbound (e >= 1) just outside this span in the WHFast "
                                       "run: an unresolved close encounter; nothing is shipped beyond")
        if name in SHIPPED_ASTEROIDS:
            k = list(SHIPPED_ASTEROIDS).index(name)
            o = cat.get(name).orbit
            entry["initial_conditions"] = (f"catalogue 'current' elements at JD {o.epoch_jd_tdb} TDB, IAS15 to "
                                           "J2000.0")
            for key in THRESHOLDS_RAD:
                for tag, part_, end in (("past", back, -PAST_YEARS), ("future", fwd, FUTURE_YEARS)):
                    c = float(part_[f"crossing_{key}"][k])
                    entry[f"reached_{key}_{tag}"] = not math.isnan(c)
                    if not math.isnan(c):
                        entry[f"clone_divergence_{key}_{tag}_years"] = round(c, 1)
                    entry[f"horizon_{key}_{tag}_years"] = round(c, 1) if not math.isnan(c) else end
        else:
            entry["initial_conditions"] = "DE421 barycentre at J2000.0 TDB" + (
                " (Earth-Moon barycentre)" if name == "Earth" else "")
            for key, thr in THRESHOLDS_RAD.items():
                for tag, part_, spart, end in (("past", back, sback, -PAST_YEARS), ("future", fwd, sfwd,
                                                                                       FUTURE_YEARS)):
                    if spart is None:
                        entry[f"reached_{key}_{tag}"] = False
                        entry[f"horizon_{key}_{tag}_years"] = end
                        entry["horizon_method"] = "literature Lyapunov time (run.planets_horizon_literature)"
                        continue
                    ang = angle(part_["poles"][:, j], spart["poles"][:, j])
                    over = np.nonzero(~(ang <= thr))[0]
                    entry[f"reached_{key}_{tag}"] = bool(over.size)
                    entry[f"horizon_{key}_{tag}_years"] = float(part_["years"][over[0]]) if over.size else end
                    entry[f"shadow_max_arcsec_{tag}"] = float(np.degrees(np.nanmax(ang)) * 3600.0)
                    entry["horizon_method"] = "shadow run, Earth-Moon barycentre moved 1 km"
        # horizons cannot lie outside the shipped data
        for key in THRESHOLDS_RAD:
            entry[f"horizon_{key}_past_years"] = max(entry[f"horizon_{key}_past_years"], float(grid[lo]))
            entry[f"horizon_{key}_future_years"] = min(entry[f"horizon_{key}_future_years"], float(grid[hi]))
        if all(v is not None for v in dt.values()):
            worst = 0.0
            for tag in ("forward", "backward"):
                p1, p2 = dt[f"dt_{tag}"]["poles"][:, j], dt[f"dt2_{tag}"]["poles"][:, j]
                worst = max(worst, float(np.nanmax(np.nan_to_num(angle(p1, p2), nan=np.pi))))
            entry["dtcheck_arcsec"] = float(f"{math.degrees(worst) * 3600.0:.3g}")
        body_lines += ["", f"[body.{name}]"] + [f"{k} = {_toml_value(v)}" for k, v in entry.items()]
    (DATA / "metadata.toml").write_text("\n".join(lines + body_lines) + "\n", encoding="utf-8")
    print("wrote", DATA)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--part", default="all",
                    choices=["all", "backward", "forward", "shadow", "dtcheck", "assemble"])
    ap.add_argument("--workdir", default="/tmp/orbit_history_raw", type=Path)
    args = ap.parse_args(argv)
    parts = ["forward", "backward", "shadow", "dtcheck", "assemble"] if args.part == "all" else [args.part]
    for p in parts:
        part(p, args.workdir)


if __name__ == "__main__":
    sys.exit(main())
