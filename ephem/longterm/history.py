"""A body's history over millennia and millions of years: the orbit chosen, the cost charged, the result typed.

Every family of :mod:`ephem.families` gives its body's spin averaged over the rotation and the orbit
(:meth:`~ephem.theory.interface.SpinAxisTheory.secular_spin`: the averaged spin equation of :mod:`ephem.longterm.averaged_spin`
with the theory's precession constant, or the Moon's Cassini state carried along the ecliptic); this module
chooses the orbit it moves along, charges the cost before the work, and returns a :class:`HistoryResult`
(rendered by :func:`ephem.answers.render.history`).

Two models of the orbit (:data:`ORBIT_MODELS`):

- ``secular``: first-order Laplace–Lagrange theory (:mod:`ephem.longterm.secular_orbit`): the planets' modes, and a small
  body's forced and free elements in them; milliseconds, good for the slow modes, blind to resonances and
  close encounters;
- ``nbody``: a REBOUND (WHFast) integration from DE421 (:mod:`ephem.longterm.nbody_orbit`): shipped for the catalogue's
  bodies over :data:`~ephem.longterm.nbody_orbit` 's span (so their history costs only the file's read and the spin
  integration), run on request for a body of the user's own within the request's budget.

Each is priced for the request (:func:`history_cost`: the spin integration both share, and the orbit's own work,
measured by benchmarks/bench_orbit_models.py). With a tolerance the answer is the model predicted cheapest among those
whose estimate meets it (:func:`ephem.theory.choice.choose`, the rule of every track's choice: each estimate is a run,
made in order of predicted cost); without one, the shipped N-body orbit where it covers the span, else the cheapest
available; the answer says which models were examined and why the chosen one won
(:mod:`ephem.longterm.orbit_selection`).

The estimate of a history, per epoch, is the sum of named terms (radians): ``nutation`` (the periodic terms the
averaged equation leaves out), ``precession_constant`` and ``pole`` (the divergence of neighbouring solutions
started with the constant and the pole displaced by their 1σ, or by a probe where no σ is published), and
``orbit``, the orbit model's own error taken as the pole's: for ``nbody`` the divergence of clone orbits
(recorded with the shipped histories), for ``secular`` its measured distance from the N-body orbits. Where the
neighbours or the orbit's clones part by more than a degree the answer says the history stops meaning anything
(``meaningful_from_year``, ``meaningful_to_year``): Mars' obliquity is chaotic (Laskar & Robutel 1993).

Times are Julian years (365.25 d) from J2000.0 TDB, negative in the past.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..theory import cost
from ..theory.choice import RULE, Deferred, choose
from ..theory.results import Estimate
from ..base.budget import charge, checkpoint
from ..bodies.catalogue import DEFAULT_DATASET, Body, load_catalogue
from ..base.constants import JULIAN_YEAR_DAYS, MAS
from ..base.errors import InvalidInputError, NotApplicableError, count_text
from ..base.extras import DISTRIBUTION, missing
from ..base.grids import check_step
from ..orbit.geometry import angle_between
from .averaged_spin import MEANINGFUL_LIMIT, ORBIT_SAMPLE_YEARS, SpinConstants, SpinHistory, outward_max
from .nbody_orbit import (DT_DAYS, SHIPPED_ASTEROIDS, SHIPPED_BODIES, SHIPPED_PLANETS, load_metadata,
                          nbody_cost_seconds, nbody_orbit_history, shipped_loaded, shipped_orbit_history,
                          shipped_sample_noise)
from .orbit_selection import (DEFAULT_RULE, NAMED_RULE, OrbitCandidate, OrbitSelection, RunEstimate, ms_text,
                              why_chosen)
from .secular_orbit import planet_secular_history, secular_orbit_history

ORBIT_MODELS = ("secular", "nbody")
DESCRIPTIONS = {
    "secular": "the spin equation averaged over the rotation and the orbit, integrated (a 4th-order splitting) "
               "along the first-order Laplace-Lagrange secular orbit (the planets' modes; a small body's forced and free "
               "elements); no nutation, no resonance of the orbit",
    "nbody": "the spin equation averaged over the rotation and the orbit, integrated (a 4th-order splitting) "
             "along a REBOUND WHFast N-body orbit started from DE421 (shipped for the catalogue's bodies); no nutation",
}
#: the most epochs one history answers (a 4 Myr history at a 40-year step)
MAX_HISTORY_SAMPLES = 100_001
#: the longest span one request may ask for (years): beyond ~20 Myr no orbit of the inner solar system is
#: known (Laskar et al. 2004's Mars solution is "precise over 10 to 20 Myr")
MAX_SPAN_YEARS = 2.0e7
#: the planets the secular theory knows by name (the rest are test particles in their field)
PLANETS = ("Mercury", "Venus", "Earth", "Mars", "Jupiter", "Saturn", "Uranus", "Neptune")


def history_grid(start_year, stop_year, step_years, max_samples: int = MAX_HISTORY_SAMPLES) -> np.ndarray:
    """The requested epochs (Julian years from J2000.0), validated: each field named in its error.

    Any span after start_year within :data:`MAX_SPAN_YEARS` is served, however short (a span shorter than the step
    is its one epoch, start_year); a step finer than float64 years resolve there is refused
    (:func:`ephem.base.grids.check_step`)."""
    values = {}
    for name, v in (("start_year", start_year), ("stop_year", stop_year), ("step_years", step_years)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InvalidInputError(name, f"must be a finite number of Julian years, got {v!r}")
        values[name] = float(v)
    start, stop, step = values["start_year"], values["stop_year"], values["step_years"]
    if stop <= start:
        raise InvalidInputError("stop_year", f"must be after start_year ({stop:g} <= {start:g})")
    if stop - start > MAX_SPAN_YEARS:
        raise InvalidInputError("stop_year", f"the span {stop - start:.4g} years exceeds {MAX_SPAN_YEARS:.3g} years: "
                                "no orbit of the solar system is known beyond ~20 Myr")
    if not step > 0.0:
        raise InvalidInputError("step_years", f"must be positive, got {step:g}")
    steps = (stop - start) / step * (1.0 + 1e-12)          # inf for a subnormal step: compared before int()
    if not steps < max_samples:        # floor(steps) + 1 > the cap (steps + 1 > it would refuse a part step)
        raise InvalidInputError("step_years", f"gives {count_text(steps + 1)} epochs over [{start:g}, {stop:g}]; at "
                                f"most {max_samples} (a step of at least {(stop - start) / (max_samples - 1):.4g} "
                                "years)")
    count = int(math.floor(steps)) + 1
    check_step("step_years", start, stop, step, count, "years", "years from J2000.0")
    return start + step * np.arange(count)


# ----------------------------------------------------------------------------- the orbit models

@dataclass(frozen=True)
class OrbitChoice:
    """One orbit model for a request: the orbit (``pole_at``, ``eccentricity_at``, ``semi_major_axis_at``), what
    it costs to get, and its error (radians) at the requested epochs, or why it is unavailable."""

    name: str
    orbit: object = None
    cost: cost.Cost = cost.FREE
    why_not: str | None = None
    shipped: bool = False


def _is_planet(b: Body, orbit_body: str) -> bool:
    return orbit_body in PLANETS and b.dataset != "user"


def _shipped(b: Body, orbit_body: str):
    """The shipped N-body history of a catalogue body's orbit, or None."""
    if b.dataset == "user" or orbit_body not in SHIPPED_BODIES:
        return None
    if b.dataset != "current" and not _is_planet(b, orbit_body):
        return None     # another dataset's elements: not the orbit the shipped run started from
    return shipped_orbit_history(orbit_body)


def secular_orbit(b: Body, orbit_body: str):
    """The secular orbit of the body whose orbit drives ``b``'s spin (the Moon's: the Earth's)."""
    if orbit_body != b.name:
        return planet_secular_history(orbit_body)
    if _is_planet(b, orbit_body):
        return planet_secular_history(orbit_body)
    if b.orbit.center != "Sun":
        raise NotApplicableError(b.name, f"the secular orbit theory is heliocentric; {b.name} orbits "
                                 f"{b.orbit.center}")
    return secular_orbit_history(b.orbit)


def orbit_choices(b: Body, orbit_body: str, lo: float, hi: float, on_demand: bool = True) -> list[OrbitChoice]:
    """The orbit models for ``b`` over [lo, hi] years in :data:`ORBIT_MODELS`' order, each priced (its own part:
    :func:`history_cost` adds the spin's); unavailable ones say why. ``on_demand``: whether a body without a
    shipped N-body orbit may have one run for it (a history may; the ``long_term`` model of a track may not)."""
    return [secular_choice(b, orbit_body, lo, hi), nbody_choice(b, orbit_body, lo, hi, on_demand)]


#: CPU of an orbit model's own work in a history, beyond the spin integration the models share: the one-time work of
#: a process priced with the request (the first history of a CLI call pays it), each about twice its measurement
#: (benchmarks/bench_orbit_models.py, benchmarks/RESULTS_orbit_models.md; the measured ms in fresh processes)
SHIPPED_READ_S = 0.01           # the shipped N-body file with its spline and noise from the table cache: 4.4-5.6
SECULAR_SOLVE_S = 0.03          # the planets' eight modes (Laplace-Lagrange), once per process: 15-16
ENVELOPE_S = {"planet": 0.02, "small body": 0.05}    # the secular error's envelope, once per process: 8-10, 18-26
SPLINE_POINT_S = 4.0e-7         # the shipped orbit's spline at one epoch (the pole, a and e): 0.17-0.19 us
SECULAR_POINT_S = 1.2e-6        # the secular orbit at one epoch (its modes summed for the pole, a and e): 0.56-0.58 us


def _shipped_read(orbit_body: str) -> float:
    """CPU of reading the shipped N-body history of ``orbit_body``: :data:`SHIPPED_READ_S` the first time in a
    process, nothing once it is held (every request of a worker priced it before)."""
    return 0.0 if shipped_loaded(orbit_body) else SHIPPED_READ_S


def _part(what: str, seconds: float) -> cost.Part:
    """A part of an orbit model's price (its memory: small arrays, 1 MB)."""
    return cost.Part("orbit_model", what, seconds, 1.0)


def secular_choice(b: Body, orbit_body: str, lo: float, hi: float) -> OrbitChoice:
    """The ``secular`` model of :func:`orbit_choices` (the theory solved: the planets' modes once per process),
    priced with its error term over [lo, hi] years: its distance from the shipped N-body orbit where that covers
    the span, else the envelope of the shipped bodies of its kind (:func:`secular_orbit_error`)."""
    try:
        orbit = secular_orbit(b, orbit_body)
    except NotApplicableError as exc:
        return OrbitChoice("secular", why_not=exc.reason)
    read = _shipped_read(orbit_body)
    shipped = _shipped(b, orbit_body)
    if shipped is not None and shipped.span_years[0] <= lo and hi <= shipped.span_years[1]:
        error = _part("its error: the shipped N-body orbit read", read)
    else:
        kind = "planet" if _is_planet(b, orbit_body) else "small body"
        error = _part(f"its error: the envelope of the shipped {kind} orbits' (once per process)", ENVELOPE_S[kind])
    return OrbitChoice("secular", orbit, cost.Cost((_part("the secular theory's modes (once per process)",
                                                          SECULAR_SOLVE_S), error)))


#: the shortest N-body run made on request (years): eight WHFast steps (5.5 d each), the samples its spline needs; a
#: shorter span (a history within days of J2000) is read from a run this long, which costs ~1 s like any other
MIN_NBODY_RUN_YEARS = 8.0 * DT_DAYS / JULIAN_YEAR_DAYS


def nbody_choice(b: Body, orbit_body: str, lo: float, hi: float, on_demand: bool = True) -> OrbitChoice:
    """The ``nbody`` model of :func:`orbit_choices`: the shipped orbit where it covers [lo, hi] years, else one run on
    request (``on_demand``), else unavailable with the reason."""
    read = _shipped_read(orbit_body)
    shipped = _shipped(b, orbit_body)
    if shipped is not None:
        first, last = shipped.span_years
        if first <= lo and hi <= last:
            return OrbitChoice("nbody", shipped, cost.Cost((_part("the shipped N-body orbit read", read),)),
                               shipped=True)
        return OrbitChoice("nbody", why_not=f"the shipped N-body orbit of {orbit_body} covers "
                           f"[{first:g}, {last:g}] years from J2000.0, not [{lo:g}, {hi:g}]")
    if b.orbit.center != "Sun":
        return OrbitChoice("nbody", why_not=f"the N-body orbits are heliocentric; {b.name} orbits {b.orbit.center}")
    if not on_demand:
        return OrbitChoice("nbody", why_not=f"no N-body orbit is shipped for {b.name} ({b.dataset} dataset); "
                           "a history (GET .../history, orbit_model=nbody) runs one on request")
    if missing("nbody") is not None:
        return OrbitChoice("nbody", why_not=f"no N-body orbit is shipped for {b.name} ({b.dataset} dataset), and "
                           f"one run on request needs REBOUND, which is not installed: install {DISTRIBUTION}[nbody]")
    span = (min(lo, 0.0), max(hi, 0.0))
    if span[1] - span[0] < MIN_NBODY_RUN_YEARS:     # a span within days of J2000: the run reaches past it
        span = (span[0], span[0] + MIN_NBODY_RUN_YEARS)
    seconds = nbody_cost_seconds(*span)
    return OrbitChoice("nbody", _LazyNbody(b, span), cost.Cost((cost.Part(
        "stop_year", f"a REBOUND N-body orbit over {span[1] - span[0]:.4g} years", seconds, 30.0),)))


class _LazyNbody:
    """A user's N-body orbit, run on first use (after its cost was charged)."""

    def __init__(self, b: Body, span: tuple[float, float]):
        self.body, self.span = b, span

    @property
    def orbit(self):
        return _nbody(self.body.orbit, self.span)

    def pole_at(self, years):
        return self.orbit.pole_at(years)

    def eccentricity_at(self, years):
        return self.orbit.eccentricity_at(years)

    def semi_major_axis_at(self, years):
        return self.orbit.semi_major_axis_at(years)


@lru_cache(maxsize=8)
def _nbody(orbit, span: tuple[float, float]):
    # the shipped step, or finer on a short span (the run needs three samples a side)
    return nbody_orbit_history(orbit, span[0], span[1], min(500.0, max(span[1] - span[0], 1e-3) / 8.0))


# ----------------------------------------------------------------------------- orbit errors

ARCMIN = math.radians(1.0 / 60.0)


def nbody_orbit_error(orbit_body: str, years: np.ndarray) -> np.ndarray:
    """The shipped N-body orbit normal's error (radians) at ``years``, read as the pole's: the larger of

    - its short-period noise (the samples are osculating, aliased by the 500-year step: :func:`sample_noise`),
    - the integrator's (the dt / dt/2 comparison recorded with the run over ±20 kyr, grown linearly), and
    - the divergence of a clone started 1 km away (``data/orbit_history/metadata.toml``): linear up to the
      epoch where it reached 1′, then exponential through the epoch where it reached 1° (a regular orbit's
      clones part linearly, a chaotic one's exponentially); where the run never reached 1′, the largest
      recorded gap grown linearly to the span's end.
    """
    entry = load_metadata()["body"][orbit_body]
    t = np.asarray(years, dtype=float)
    out = np.full(t.shape, sample_noise(orbit_body))
    dt_years = float(load_metadata()["run"]["dtcheck_years"])
    out = np.maximum(out, math.radians(entry["dtcheck_arcsec"] / 3600.0) * np.abs(t) / dt_years)
    for side, mask in (("past", t < 0.0), ("future", t >= 0.0)):
        if not mask.any():
            continue
        a = np.abs(t[mask])
        t1 = abs(float(entry[f"horizon_1arcmin_{side}_years"]))
        if entry.get(f"reached_1arcmin_{side}", False):
            grow = ARCMIN * a / max(t1, 1.0)
            if entry.get(f"reached_1deg_{side}", False):
                t2 = abs(float(entry[f"horizon_1deg_{side}_years"]))
                tau = max(t2 - t1, 1.0) / math.log(60.0)
                beyond = a > t1
                grow[beyond] = ARCMIN * np.exp(np.minimum((a[beyond] - t1) / tau, 50.0))
        else:
            gap = math.radians(float(entry.get(f"shadow_max_arcsec_{side}", 60.0)) / 3600.0)
            grow = gap * a / max(t1, 1.0)
        out[mask] = np.maximum(out[mask], np.minimum(grow, math.pi))
    return out


def sample_noise(orbit_body: str) -> float:
    """The shipped orbit normal's short-period noise (radians): half the largest miss of a spline through every
    other sample at the samples between (the osculating normal's terms of synodic periods, aliased;
    :func:`ephem.longterm.nbody_orbit.shipped_sample_noise`)."""
    return shipped_sample_noise(orbit_body)


@lru_cache(maxsize=4)
def secular_envelope(kind: str) -> tuple[np.ndarray, np.ndarray]:
    """How far the secular orbit normal strays from the N-body one, as the largest over the shipped bodies of
    ``kind`` ("planet" or "small body") within |t| (years; radians), for an orbit with no N-body history."""
    names = SHIPPED_PLANETS if kind == "planet" else SHIPPED_ASTEROIDS
    cat = load_catalogue(DEFAULT_DATASET)
    grid = np.linspace(0.0, 1.0e6, 2001)
    worst = np.zeros(grid.size)
    for name in names:
        try:
            sec = planet_secular_history(name) if kind == "planet" else secular_orbit_history(cat.get(name).orbit)
        except NotApplicableError:
            continue    # out of the theory's domain (a planet-crosser): not part of its envelope
        nb = shipped_orbit_history(name)
        lo, hi = nb.span_years
        for sign in (-1.0, 1.0):
            t = np.clip(sign * grid, lo, hi)
            d = angle_between(sec.pole_at(t), nb.pole_at(t))
            worst = np.maximum(worst, np.maximum.accumulate(d))
    return grid, worst


def secular_orbit_error(b: Body, orbit_body: str, years: np.ndarray) -> np.ndarray:
    """The secular orbit normal's error (radians): its distance from the shipped N-body orbit where there is
    one (growing only: the running largest from J2000 outward), else the envelope of the shipped bodies of its
    kind."""
    shipped = _shipped(b, orbit_body)
    if shipped is not None:
        lo, hi = shipped.span_years
        inside = (years >= lo) & (years <= hi)
        if inside.all():
            d = angle_between(secular_orbit(b, orbit_body).pole_at(years), shipped.pole_at(years))
            return outward_max(years, 0.0, d)
    grid, worst = secular_envelope("planet" if _is_planet(b, orbit_body) else "small body")
    return np.interp(np.abs(years), grid, worst, right=math.pi)


# ----------------------------------------------------------------------------- the answer

def history_cost(spin, choice: OrbitChoice, lo: float, hi: float, count: int) -> cost.Cost:
    """The orbit's and the spin integration's cost over [lo, hi] years at ``count`` epochs, known before the
    work: the integration runs from the spin's epoch to the farthest epoch on each side, sampling the orbit every
    500 years (its pole, a and e) and at the epochs (twice: the spin's frame and the orbit's error)."""
    t0 = getattr(spin, "epoch_years", 0.0)
    span = float(max(lo, hi, t0) - min(lo, hi, t0))
    own = getattr(spin, "orbit_points", None)      # a spin whose own price counts its reads of the orbit says how many
    points = own(span, count) if own is not None else 2 * (int(math.ceil(span / ORBIT_SAMPLE_YEARS)) + 1 + count)
    per = SECULAR_POINT_S if choice.name == "secular" else SPLINE_POINT_S
    # the averaged spin (SpinConstants) integrates from its epoch outward, its fixed work once on each side reached
    sides = cost.pole_epoch_sides(t0, min(lo, hi), max(lo, hi))
    spin_cost = spin.cost(span, count, sides) if isinstance(spin, SpinConstants) else spin.cost(span, count)
    return choice.cost + cost.Cost((cost.Part("step_years", f"the {choice.name} orbit at {points} epochs",
                                              points * per, points * 56.0 / cost.MB),     # 7 float64 a point
                                    spin_cost))


def spin_axis_history(b: Body, theory, start_year, stop_year, step_years, tolerance: float | None = None,
                      orbit_model: str | None = None, max_samples: int = MAX_HISTORY_SAMPLES,
                      progress=None) -> HistoryResult:
    """The history of ``b`` served by ``theory`` (a :class:`~ephem.theory.interface.SpinAxisTheory`): the spin
    at each epoch of the grid, its error by named term, where it stops meaning anything and the orbit model
    used (:class:`HistoryResult`). ``tolerance`` (radians) or ``orbit_model`` ("secular" or "nbody"), not
    both; by default the shipped N-body orbit where it covers the span, else the cheapest available; with a
    tolerance, the one predicted cheapest whose estimate meets it. ``progress``: called with the fraction
    integrated (a console's progress bar)."""
    t_start = time.perf_counter()
    years = history_grid(start_year, stop_year, step_years, min(max_samples, MAX_HISTORY_SAMPLES))
    if orbit_model is not None and orbit_model not in ORBIT_MODELS:
        raise InvalidInputError("orbit_model", f"must be one of {', '.join(ORBIT_MODELS)}, got {orbit_model!r}")
    if orbit_model is not None and tolerance is not None:
        raise InvalidInputError("orbit_model", "give either an orbit model or a tolerance, not both")
    spin = theory.secular_spin()
    chosen, result, estimates, selection = _choose(b, spin, years, tolerance, orbit_model, progress)
    return _result(b, theory, spin, chosen, result, estimates, years, tolerance, t_start, selection)


@dataclass(frozen=True)
class LongTermRun:
    """One history along the default orbit model: the spin history, its terms with the orbit's (radians), the
    orbit model used."""

    history: SpinHistory
    terms: dict
    choice: OrbitChoice


def default_choice(choices: list[OrbitChoice], b: Body) -> OrbitChoice:
    """The shipped N-body orbit where it covers the span (it costs nothing more), else the cheapest available."""
    available = [c for c in choices if c.why_not is None]
    if not available:
        raise NotApplicableError(b.name, "no orbit model serves this span: " +
                                 "; ".join(f"{c.name}: {c.why_not}" for c in choices))
    return next((c for c in available if c.shipped), available[0])


def default_orbit(b: Body, orbit_body: str, lo: float, hi: float, on_demand: bool = False) -> OrbitChoice:
    """:func:`default_choice` of :func:`orbit_choices`, the secular theory solved only when no shipped N-body orbit
    covers [lo, hi] years (the planets' modes: 15-20 ms of a fresh process)."""
    nbody = nbody_choice(b, orbit_body, lo, hi, on_demand)
    return nbody if nbody.shipped else default_choice([secular_choice(b, orbit_body, lo, hi), nbody], b)


def long_term_cost(b: Body, spin, lo: float, hi: float, count: int) -> cost.Cost:
    """What :func:`long_term_run` costs over [lo, hi] years at ``count`` epochs."""
    choice = default_orbit(b, spin.orbit_body, min(lo, hi), max(lo, hi))
    return history_cost(spin, choice, lo, hi, count)


def long_term_run(b: Body, spin, years: np.ndarray, progress=None, on_demand: bool = False) -> LongTermRun:
    """The history of ``spin`` at ``years`` along the default orbit model (:func:`default_choice`), charged
    first; ``on_demand``: as :func:`orbit_choices`."""
    years = np.asarray(years, dtype=float)
    choice = default_orbit(b, spin.orbit_body, float(years.min()), float(years.max()), on_demand)
    h, terms = _run(b, spin, choice, years, progress)
    return LongTermRun(h, terms, choice)


def _run(b: Body, spin, choice: OrbitChoice, years: np.ndarray, progress=None) -> tuple[SpinHistory, dict]:
    """The history along one orbit model, and its terms with the orbit's error added (radians, per epoch; the
    obliquity's with it too, in ``history.obliquity_terms``): an orbit normal off by δ moves both by up to δ."""
    charge(history_cost(spin, choice, float(years.min()), float(years.max()), years.size), b.name)
    checkpoint()
    h = spin.history(choice.orbit, years, progress)
    terms = dict(h.terms)
    if choice.name == "nbody" and choice.shipped:
        terms["orbit"] = nbody_orbit_error(spin.orbit_body, years)
    elif choice.name == "secular":
        terms["orbit"] = secular_orbit_error(b, spin.orbit_body, years)
    if "orbit" in terms:
        h.obliquity_terms["orbit"] = terms["orbit"]
    return h, terms


def _choose(b: Body, spin, years, tolerance, orbit_model, progress=None):
    """(the orbit model, (history, terms), every tried model's terms, :class:`OrbitSelection`): the named one, the
    default, or with ``tolerance`` the one predicted cheapest among those estimated within it
    (:func:`ephem.theory.choice.choose`: estimated in order of predicted cost, each estimate a run)."""
    lo, hi = float(years[0]), float(years[-1])

    def price(c: OrbitChoice) -> float:
        return history_cost(spin, c, lo, hi, years.size).cpu_s

    def alone(choices, c, result, rule, reason):
        est = float(np.max(total(result[1])))
        return c, result, {c.name: result[1]}, OrbitSelection(rule, reason, tuple(
            OrbitCandidate(x.name, x.why_not, None if x.why_not else price(x), est if x is c else None,
                           None, x is c) for x in choices))

    if orbit_model is not None:
        c = secular_choice(b, spin.orbit_body, lo, hi) if orbit_model == "secular" else \
            nbody_choice(b, spin.orbit_body, lo, hi)
        if c.why_not is not None:
            raise NotApplicableError(b.name, f"the {orbit_model} orbit: {c.why_not}")
        return alone([c], c, _run(b, spin, c, years, progress), NAMED_RULE, f"named: orbit_model={orbit_model}")
    if tolerance is None:
        nbody = nbody_choice(b, spin.orbit_body, lo, hi, on_demand=True)
        choices = [nbody] if nbody.shipped else [secular_choice(b, spin.orbit_body, lo, hi), nbody]
        c = default_choice(choices, b)
        reason = ("the shipped N-body orbit covers the span (the secular theory is not examined)" if nbody.shipped
                  else f"no shipped N-body orbit covers the span: {c.name}, the cheapest available "
                       f"({ms_text(price(c))})")
        return alone(choices, c, _run(b, spin, c, years, progress), DEFAULT_RULE, reason)
    choices = orbit_choices(b, spin.orbit_body, lo, hi)
    by_name = {c.name: c for c in choices}
    runs = {}

    def deferred(c: OrbitChoice) -> Deferred:
        def make() -> Estimate:
            if c.why_not is not None:
                return Estimate(c.name, None, {}, available=False, why_not=c.why_not)
            if c.name not in runs:          # made once: the refusal asks for every estimate again
                runs[c.name] = _run(b, spin, c, years, progress)
            terms = runs[c.name][1]
            return RunEstimate(c.name, None, {k: float(np.max(v)) for k, v in terms.items()},
                               largest=float(np.max(total(terms))))
        return Deferred(c.name, None, make, available=c.why_not is None)

    def refuse(made: list) -> None:
        if not made:
            default_choice(choices, b)          # raises, saying why each is unavailable
        best = min(made, key=lambda e: e.total).rung
        terms = runs[best][1]
        raise NotApplicableError(b.name, f"no orbit model meets tolerance_mas={tolerance / MAS:.6g} over "
                                 f"[{lo:g}, {hi:g}] years: the best, {best}, is estimated at "
                                 f"{float(np.max(total(terms))) / MAS:.4g} mas (largest terms: "
                                 + ", ".join(f"{k} {float(np.max(v)) / MAS:.4g}" for k, v in
                                             sorted(terms.items(), key=lambda kv: -float(np.max(kv[1])))[:2])
                                 + "); the history has no nutation: for a few centuries ask for the track")

    pick = choose([deferred(c) for c in choices], lambda p: history_cost(spin, by_name[p.rung], lo, hi, years.size),
                  tolerance, refuse)
    candidates = tuple(OrbitCandidate(k.rung, by_name[k.rung].why_not, None if k.cost is None else k.cost.cpu_s,
                                      None if k.estimate is None or not k.estimate.available else k.estimate.total,
                                      k.eligible, k.estimate is pick.chosen) for k in pick.candidates)
    c = by_name[pick.chosen.rung]
    return c, runs[c.name], {k: v[1] for k, v in runs.items()}, OrbitSelection(
        RULE, why_chosen(candidates, tolerance), candidates)


def total(terms: dict) -> np.ndarray:
    return np.minimum(sum(terms.values()), math.pi)


#: what every history assumes (the answer's ``model.assumptions``)
HISTORY_ASSUMPTIONS = (
    "averaged over the rotation and the orbit: no nutation (its size is the nutation term)",
    "the precession constant follows the orbit's a and e; the body's moments and spin rate are fixed "
    "(no tidal or YORP evolution)",
    "an orbit error is taken as the pole's error",
    "the precession_constant and pole terms are the divergence of neighbouring solutions; where no 1-sigma "
    "is published they are probes (listed in probed_terms)",
)


@dataclass(frozen=True)
class HistoryResult:
    """A history: the spin at ``years`` (radians: the obliquity to the moving orbit, the precession angle, the
    ICRF pole, the orbit's inclination to the J2000 ecliptic), its error by named term per epoch (radians;
    ``obliquity_terms`` the obliquity's own), every tried orbit model's terms (``estimates``), the span where it
    means something (``meaningful``: years, infinite where not limited; equal ends: nowhere), the orbit model
    chosen and what it is, and the warnings. :func:`ephem.answers.render.history` renders it."""

    body: Body
    years: np.ndarray
    history: SpinHistory
    terms: dict
    estimates: dict
    meaningful: tuple[float, float]
    orbit_model: str
    orbit_source: str | None
    orbit_horizon_years: tuple[float, float] | None
    theory: str
    spin: str
    tolerance: float | None
    cost_ms: float
    warnings: tuple[str, ...]
    #: how the orbit model was chosen (None: a result made without the choice)
    selection: OrbitSelection | None = None

    @property
    def error(self) -> np.ndarray:
        """The estimate at each epoch (radians): the sum of the terms."""
        return total(self.terms)

    @property
    def obliquity_error(self) -> np.ndarray:
        return total(self.history.obliquity_terms)


def _result(b, theory, spin, chosen: OrbitChoice, result, estimates, years, tolerance, t_start,
            selection: OrbitSelection) -> HistoryResult:
    h, terms = result
    meaningful = _meaningful(years, spin, h, terms)
    horizon = getattr(chosen.orbit, "horizon_years", None)
    warnings = []
    if meaningful[0] == meaningful[1]:
        warnings.append(f"the history means nothing anywhere in the span: its orbit's error is "
                        f"{math.degrees(float(np.min(terms['orbit']))):.3g} deg or more at every epoch (more than "
                        f"{math.degrees(MEANINGFUL_LIMIT):g} deg: the osculating orbit's short-period scatter or its "
                        f"clones' divergence)")
    elif meaningful[0] > years[0] or meaningful[1] < years[-1]:
        warnings.append(f"the history stops meaning anything outside [{meaningful[0]:g}, {meaningful[1]:g}] years "
                        f"from J2000.0: neighbouring solutions or orbits part by more than "
                        f"{math.degrees(MEANINGFUL_LIMIT):g} deg there")
    return HistoryResult(b, years, h, terms, estimates, meaningful, chosen.name,
                         getattr(chosen.orbit, "source", None),
                         None if horizon is None else tuple(float(x) for x in horizon), theory.summary, spin.source,
                         tolerance, (time.perf_counter() - t_start) * 1e3, tuple(warnings), selection)


def _meaningful(years, spin, h: SpinHistory, terms: dict) -> tuple[float, float]:
    """The span over which neither the neighbours' obliquities nor the orbit's clones part by more than a
    degree."""
    past, future = h.meaningful_years
    orbit = terms.get("orbit")
    if orbit is not None:
        bad = orbit > MEANINGFUL_LIMIT
        t0 = getattr(spin, "epoch_years", 0.0)
        if bad[int(np.argmin(np.abs(years - t0)))]:
            return t0, t0                    # the orbit is too uncertain already at the epoch: nowhere
        if (bad & (years < t0)).any():
            past = max(past, float(years[bad & (years < t0)].max()))
        if (bad & (years >= t0)).any():
            future = min(future, float(years[bad & (years >= t0)].min()))
    return past, future
