"""What a request will cost, known before it runs: CPU seconds of one core and peak memory.

Every model states its cost from the request's parameters alone (epochs, harmonics, orbits,
integration span), before any work: :class:`Cost` is a sum of named :class:`Part` s, each
tied to the request parameter that drives it, so a refusal can say which parameter to change.
:mod:`ephem.base.budget` charges these costs against a request's budget.

A prediction is the work this request will do: what a process keeps after the first request (a body's model,
second-order theory, estimate tables, the pole's stepped models, a real orbit) is charged only while it is not
kept, so that a worker's first request for a body (cold) and the next ones (warm) are each predicted as they run;
the families ask the caches (``tables_built``, ``cached(...)``, :func:`kept`) before pricing.

The unit costs in ``data/cost_model.toml`` are what they measure on the project's reference machine (2 cores,
CPython 3.11, numpy 2.4, one BLAS thread), each with its measurement in a comment: the goal is a prediction within
0.5-2x of the measured CPU, warm and cold, for every model and size from 10 to 10^6 epochs.
``benchmarks/bench_calibration.py`` holds the requests to that goal over a grid of bodies, spans, sizes and models
(``benchmarks/RESULTS_calibration.md``); ``benchmarks/bench_cost.py`` prints each predictor against the library call
it stands for, with the memory (``benchmarks/RESULTS_cost.md``). They are predictions, not bounds: the deadline of
:mod:`ephem.base.budget` is the backstop when a machine or an input is slower than predicted.
"""
from __future__ import annotations

import math
from functools import lru_cache

from ..base import memo
from ..base.budget import FREE, Cost, Part  # noqa: F401  (FREE, Cost: re-exported with the predictors)
from ..base.paths import data_dir
from ..orbit.hansen import decay_rate, fft_length
from ..orbit.kepler import mean_motion_rad_per_day
from ..base.disk_cache import read_toml

MB = 1024.0 * 1024.0
#: The numerical rungs integrate through every orbit (~5 ms each); beyond this many orbits from the pole epoch a
#: request would tie up a worker for seconds, so they are not offered (the service states it in its OpenAPI text).
MAX_NUMERICAL_ORBITS = 1000




@lru_cache(maxsize=None)
def unit_table(name: str) -> dict:
    """The measured unit costs of one table of data/: ``cost_model.toml``, the shared ones (:func:`unit_costs`), or a
    family's own (``earth_costs.toml``, read by :mod:`ephem.earth.costs`: each family prices its own work)."""
    return read_toml(data_dir() / name)["unit"]


def unit_costs() -> dict:
    """The shared measured unit costs (``data/cost_model.toml``): every family's answers, the forced model's work."""
    return unit_table("cost_model.toml")


def _u(key: str) -> float:
    return float(unit_costs()[key])


def unit(key: str) -> float:
    """One shared unit cost, for a family's predictors (which read their own table for the rest)."""
    return float(unit_costs()[key])


def kept(function: str, *args) -> bool:
    """Whether the per-body cache ``function`` (the module and name of a :func:`ephem.base.memo.bytes_bounded`
    function, e.g. ``ephem.forced.pole_uncertainty.cached_pole_sensitivity``) holds its value for ``args`` (its key:
    all its arguments, in order): how a predictor asks whether a request will build it without importing the layer that
    keeps it (``tests/theory/test_cost_model.py`` holds the names to the caches). A cache with a ``key`` function
    is asked with what that function gives (the σ caches: ``body.with_sigmas(order)``)."""
    return (function, tuple(args)) in memo.POOL


#: the caches :func:`pole_uncertainty` asks (see :func:`kept`)
POLE_SENSITIVITY = "ephem.forced.pole_uncertainty.cached_pole_sensitivity"
PROPAGATED = "ephem.forced.uncertainty.propagated"


# --- what every track answer costs beside its models ----------------------------------------------

def track_answer(epochs: int) -> Part:
    """A track request's own work beside its models': the checks of its inputs, the family's description of the
    model and the answer's arrays in their units at every epoch (:func:`ephem.answers.render.track`): a fixed part
    (``request_base_s``) and a part per epoch (``answer_epoch_s``)."""
    return Part("step_days", f"the request and its answer's {epochs} epochs in their units",
                _u("request_base_s") + epochs * _u("answer_epoch_s"), epochs * _u("track_bytes_per_epoch") / MB)


# --- the pieces every model is made of ------------------------------------------------------------

def pole_epoch_sides(pole_epoch: float, first: float, last: float) -> int:
    """The sides of the pole epoch t₀ (any time unit, as ``first`` and ``last``) that epochs spanning [first, last]
    reach: 1, or 2 for a span across t₀. The models that integrate or sum from t₀ outward (the second-order mean
    track, :meth:`ephem.forced.second_order.SecondOrderTheory.mean_track`; the averaged spin,
    :func:`ephem.longterm.averaged_spin.integrate`; the rotation averaging's bound,
    :func:`ephem.forced.physics_errors.rotation_averaging_bound`) do their fixed work once on each side; a span
    at t₀ alone or on one side of it counts one, the side the fixed units were measured on."""
    return max(1, int(last > pole_epoch) + int(first < pole_epoch))



def harmonics(e: float, order: int | None, relative_floor: float = 1e-16) -> tuple[int, int]:
    """(FFT samples N, harmonics K) of the nutation series at eccentricity ``e``.

    ``order`` None: the exact coefficients of :func:`ephem.orbit.hansen.hansen_exact`, whose harmonics
    decay like k^(3/2) exp(-σk) (σ of :func:`ephem.orbit.hansen.decay_rate`, ~(1-e²)^(3/2)/3 as e -> 1):
    K solves σK - 1.5 ln K = ln(1/relative_floor), the last harmonic above that fraction of the
    largest (1e-16: the Hansen coefficients themselves; the nutation series cuts at an absolute
    amplitude, a larger fraction, see :func:`nutation_harmonics`). An e-power series to e^order has
    order + 2.
    """
    if order is not None:
        return 0, order + 2
    n = fft_length(e, None)
    sigma = decay_rate(e)
    if math.isinf(sigma):
        return n, 2
    target = math.log(1.0 / relative_floor)
    k = target / sigma
    while sigma * k - 1.5 * math.log(k) < target:
        k *= 1.05
    return n, max(2, min(n // 2, math.ceil(k)))


def nutation_harmonics(e: float, order: int | None, torque_over_motion: float) -> int:
    """Harmonics kept in the nutation series: :func:`ephem.forced.kinoshita.nutation_series` drops those below
    1e-14 rad, and its amplitudes scale with K/n (``torque_over_motion``)."""
    floor = min(1e-2, max(1e-16, 1e-14 / max(0.5 * torque_over_motion, 1e-300)))
    return harmonics(e, order, floor)[1]


def hansen_fft_s(n: int) -> float:
    """CPU seconds of one body's exact Hansen coefficients on ``n`` samples (Kepler's equation solved at each,
    then the FFTs): the one formula for it, whether a body is answered alone (:func:`hansen_build`) or in a
    population (:func:`population`)."""
    return _u("fft_s_per_n_log_n") * n * math.log2(n)


def hansen_build(e: float, order: int | None) -> Part:
    """The Hansen coefficients: an N-point FFT (exact) or the rational series (order)."""
    n, k = harmonics(e, order)
    if order is not None:      # the rational series, built once (above SHARED_SERIES_ORDER: the lower are cut from it)
        return Part("order", f"the e^{order} Hansen series", _u("series_s") * (1 + order) ** 4, 1.0)
    return Part("orbit.e", f"exact Hansen coefficients (a {n}-point FFT, e = {e:.4g})",
                _u("base_s") + hansen_fft_s(n), _u("fft_bytes_per_sample") * n / MB)


#: the rational e-power series are built at start-up up to this order (``ephem.host.warm_up``), the lower orders cut
#: from it; a higher order is built on its first use (``series_s``), then kept
#: (:func:`ephem.orbit.hansen.hansen_series`)
SHARED_SERIES_ORDER = 20


def model_build(e: float, order: int | None = None) -> Part:
    """A body's first-order model (:func:`ephem.forced.precession_nutation.build_model`): the exact Hansen
    coefficients (an N-point FFT, recomputed by the passes that settle the nutation at the pole epoch) or the
    e-power series cut at ``order`` (from the rational series of :func:`ephem.orbit.hansen.hansen_series`, kept once
    built: :data:`SHARED_SERIES_ORDER`), and the nutation series over their harmonics."""
    if order is not None:
        return Part("order", f"the body's model with the e^{order} Hansen series",
                    _u("model_base_s") + _u("series_term_s") * (order + 2) ** 2, 1.0)
    n, _ = harmonics(e, None)
    return Part("orbit.e", f"the body's model (exact Hansen coefficients: a {n}-point FFT, e = {e:.4g})",
                _u("model_base_s") + _u("model_s_per_n_log_n") * n * math.log2(n), _u("fft_bytes_per_sample") * n / MB)


def theory_build(k: int) -> Part:
    """The body's second-order theory (:func:`ephem.forced.second_order.second_order_theory`, which every rung's
    estimate reads): products of the nutation's ``k`` harmonics, ~k^2."""
    return Part("orbit.e", f"the body's second-order theory ({k} harmonics)",
                _u("theory_base_s") + _u("theory_harmonic2_s") * k * k, 0.5 + 16.0 * k * k / MB)


def ladder_estimates(epochs: int, k: int, averaging_samples: int = 0, averaging_sides: int = 1,
                     weighed: bool = True) -> Part:
    """Every rung's error estimate over the epochs (:meth:`ephem.sun.ladder.Ladder.estimates`): a fixed part (the
    theory terms from the body's tables, the truncation bound of each e-order, the geodesic and interior terms), a
    pass over the epochs (the orbit's motion: Kepler's equation at each, slower as the eccentricity, and with it the
    ``k`` harmonics, grows) and the rotation averaging's samples of the span from the pole epoch
    (``averaging_samples``: :func:`ephem.forced.physics_errors.rotation_averaging_samples`, up to ~4000 for 20
    orbits; none beyond, where its bounds take no samples). The bound works from the pole epoch to each side the
    epochs reach (``averaging_sides``, :func:`pole_epoch_sides`; the fixed part holds one): each further side costs
    its fixed work (``estimates_averaging_side_s``; the span is sampled once a request, every bound of it reading
    those samples: :func:`ephem.forced.rotation_scale.span_samples`). ``weighed``: the new
    estimates are kept (:func:`ephem.sun.ladder._cached_estimates`, up to its epochs' limit), weighed first against
    the per-body caches' byte budget (:mod:`ephem.base.memo`): ``estimates_weighed_s``, whatever the epochs."""
    extra_sides = max(0, averaging_sides - 1)
    return Part("step_days", f"the error estimates of every model at {epochs} epochs"
                + (f" ({averaging_samples} samples of the span for the rotation averaging)" if averaging_samples else "")
                + (" (the rotation averaging on both sides of the pole epoch)" if extra_sides else ""),
                _u("estimates_base_s") + epochs * (_u("estimates_epoch_s") + k * _u("estimates_harmonic_s"))
                + averaging_samples * _u("estimates_averaging_sample_s")
                + extra_sides * _u("estimates_averaging_side_s") + (_u("estimates_weighed_s") if weighed else 0.0),
                max(epochs, averaging_samples) * _u("track_bytes_per_epoch") / MB)


def ladder_estimates_kept(epochs: int) -> Part:
    """Every rung's error estimate over epochs whose estimates the ladder keeps from the same question asked before
    (:func:`ephem.sun.ladder._cached_estimates`): the epochs' digest and a look-up."""
    return Part("step_days", f"the error estimates of every model at {epochs} epochs, kept from the same question",
                _u("estimates_kept_s"), 0.0)


def harmonic_work_mb(epochs: int, k: int) -> float:
    """The work table of a harmonic sum: two float64 rows per harmonic over a block of at most 16 384 epochs (the
    track kernel's, :mod:`ephem.forced.precession_nutation`; :func:`ephem.orbit.harmonics.evaluate_harmonics`
    takes 8192), capped at ``harmonic_block_mb``."""
    return min(_u("harmonic_block_mb"), 16.0 * max(k, 1) * min(epochs, 16384) / MB)


def half_peak_to_peak(e: float, order: int | None, k: int | None = None) -> Part:
    """Half the peak-to-peak nutation (Petit Table 4's Δψ, Δε): a grid of 64 points per harmonic
    (``k`` harmonics; default all the Hansen coefficients')."""
    k = harmonics(e, order)[1] if k is None else k
    return Part("orbit.e", f"the nutation's extremes over one orbit ({k} harmonics on a {64 * k}-point grid)",
                _u("extrema_harmonic_s") * 64.0 * k * k, 0.5 + harmonic_work_mb(64 * k, k))


#: the most harmonics a track sums by one matrix product per block (:data:`ephem.orbit.harmonics.MAX_POWER_BASIS_TERMS`,
#: every catalogue body's series); more are summed by Chebyshev recurrences, at ``harmonic_s`` each
POWER_BASIS_HARMONICS = 48


def harmonic_sum(epochs: int, k: int, parameter: str, what: str) -> Part:
    """A nutation series of ``k`` harmonics summed at ``epochs`` epochs, and the track's angles from it (the blocked
    kernel of :mod:`ephem.forced.precession_nutation`): up to :data:`POWER_BASIS_HARMONICS` one matrix product per
    block (``harmonic_grid_s`` a harmonic), beyond it Chebyshev recurrences (``harmonic_s``)."""
    per = _u("harmonic_grid_s") if k <= POWER_BASIS_HARMONICS else _u("harmonic_s")
    return Part(parameter, f"{what}: {epochs} epochs x {k} harmonics",
                _u("base_s") + epochs * (_u("epoch_s") + per * k),
                epochs * _u("track_bytes_per_epoch") / MB + harmonic_work_mb(epochs, k))


def secular_track(epochs: int) -> Part:
    """The secular rung's track (:func:`ephem.sun.rungs.secular_track`): the precessing mean pole's angles at every
    epoch, no nutation."""
    return Part("step_days", f"the secular track at {epochs} epochs", epochs * _u("secular_epoch_s"),
                epochs * _u("track_bytes_per_epoch") / MB)


def estimate_tables(e: float) -> Part:
    """The tables the ladder's span-aware estimates read (:func:`ephem.sun.ladder.theory_tables`: the nutation, the
    truncated series' differences and the second-order remainder over one orbit), built once per body and process:
    measured 9-33 ms for the catalogue bodies, 40 ms at e = 0.9 (K = 1580) and 0.195 s, 74 MB at e = 0.95
    (K = 4806)."""
    k = harmonics(e, None)[1]
    return Part("orbit.e", f"the estimates' tables over one orbit ({k} harmonics, e = {e:.4g}; once per body)",
                _u("tables_base_s") + _u("tables_s_per_harmonic") * k,
                _u("tables_base_mb") + _u("tables_mb_per_harmonic") * k)


def mean_track(sides: int = 1) -> float:
    """CPU seconds of the second-order mean track (:meth:`ephem.forced.second_order.SecondOrderTheory.mean_track`:
    DOP853 from the pole epoch to the farthest epoch on each of the ``sides`` it reaches, :func:`pole_epoch_sides`):
    ``second_order_base_s`` for the first side, ``second_order_side_s`` for the other."""
    return _u("second_order_base_s") + max(0, sides - 1) * _u("second_order_side_s")


def second_order(epochs: int, k: int, sides: int = 1) -> Part:
    """The second-order theory's track (:func:`ephem.sun.rungs.second_order_track`): its mean track (a fixed part
    for each side of the pole epoch the epochs reach, :func:`mean_track`) and the re-phased nutation of ``k``
    harmonics at every epoch."""
    return Part("step_days", f"the second-order theory at {epochs} epochs x {k} harmonics"
                + (" (its mean track integrated to both sides of the pole epoch)" if sides > 1 else ""),
                mean_track(sides) + epochs * (_u("second_order_epoch_s") + _u("second_order_harmonic_s") * k),
                epochs * _u("track_bytes_per_epoch") / MB + harmonic_work_mb(epochs, k))


def integrated_track(epochs: int, sides: int = 1) -> Part:
    """The numerical rungs' track from the integrated pole vectors (:func:`ephem.sun.rungs.track_from_vectors`):
    the second-order mean track to read the nutation off (a fixed part for each side of the pole epoch the epochs
    reach, :func:`mean_track`) and the angles at every epoch."""
    return Part("step_days", f"the track from the integrated pole at {epochs} epochs",
                mean_track(sides) + epochs * _u("vectors_epoch_s"), epochs * _u("track_bytes_per_epoch") / MB)


def spin_integration(orbits: float, e: float, epochs: int, real_orbit: bool = False) -> Part:
    """DOP853 through every orbit from the pole epoch to the epochs, both sides of it counted
    (:mod:`ephem.forced.integration`): the steps per orbit grow toward pericentre, measured as (1 - e)^(-1/2);
    ``real_orbit``: along the real Sun path, whose interpolation each step reads (``spin_orbit_real_s``)."""
    per_orbit = _u("spin_orbit_real_s" if real_orbit else "spin_orbit_s") / math.sqrt(1.0 - e)
    return Part("stop", f"the spin axis integrated through {orbits:.4g} orbits",
                _u("base_s") + orbits * per_orbit + epochs * _u("dense_output_s"),
                epochs * _u("track_bytes_per_epoch") / MB + orbits * _u("spin_bytes_per_orbit") / MB)


def orbit_integration(span_days: float, integrated: bool = True) -> Part:
    """The real orbit (:mod:`ephem.orbit.de421`): the body integrated under the DE421 planets over ``span_days``, or,
    not ``integrated`` (a planet DE421 gives), its path read from the kernel's pieces."""
    years = span_days / 365.25
    if not integrated:
        return Part("start", f"the real orbit read from DE421 over {years:.4g} years", _u("path_de421_s"), 5.0)
    return Part("start", f"the real orbit integrated over {years:.4g} years",
                _u("path_base_s") + years * _u("path_s_per_year"), _u("path_mb_per_year") * years + 5.0)


def free_rotation(method: str, epochs: int, rotations: float) -> Part:
    """The torque-free motion (:mod:`ephem.rotation.free_motion`): closed form, Lie series or DOP853."""
    if method == "numeric":
        return Part("stop", f"Euler's equations integrated through {rotations:.4g} rotations",
                    _u("base_s") + rotations * _u("rigid_s_per_rotation") + epochs * _u("dense_output_s"),
                    epochs * _u("track_bytes_per_epoch") / MB)
    if method == "series":
        fixed, per, per_bytes = _u("free_series_build_s"), _u("free_series_epoch_s"), _u("free_series_bytes_per_epoch")
    else:
        fixed, per, per_bytes = _u("base_s"), _u("free_exact_epoch_s"), _u("track_bytes_per_epoch")
    return Part("step_days", f"the free motion ({method}) at {epochs} epochs", fixed + epochs * per,
                epochs * per_bytes / MB)


def spin_history(span_years: float, epochs: int, steps_per_sample: int = 1, sides: int = 1) -> Part:
    """The averaged spin equation integrated over ``span_years`` (both sides of the epoch together) with its
    neighbours (:func:`ephem.longterm.averaged_spin.integrate`'s splitting), then the requested epochs. The steps
    cut the orbit's 500-year samples in ``steps_per_sample`` (a power of two, :func:`ephem.longterm.averaged_spin.
    split_steps` on the body's own orbit): the work is per year of span and per step. The unit is the shipped
    catalogue's slowest per year at one step per sample (Eros, whose noisy orbit asks for 1.8 on average). The
    integration runs from the epoch outward on each of the ``sides`` of it the span reaches (:func:`pole_epoch_sides`),
    each with its own start, splitting and read-out: ``spin_history_side_s`` for the second."""
    return Part("stop_year", f"the averaged spin integrated over {span_years:.4g} years"
                + (" on both sides of its epoch" if sides > 1 else ""),
                _u("base_s") + _u("spin_history_base_s") + max(0, sides - 1) * _u("spin_history_side_s")
                + span_years * steps_per_sample * _u("spin_history_s_per_year")
                + epochs * _u("history_epoch_s"),
                _u("spin_history_base_mb") + epochs * _u("history_bytes_per_epoch") / MB
                + span_years / 500.0 * steps_per_sample * _u("history_bytes_per_orbit_sample") / MB)


def population(rows: int, sigma_inputs: int = 0, groups=(), differenced: int | None = None) -> Cost:
    """A partition of ``rows`` bodies through the population core (:func:`ephem.batch.population.evaluate`).

    Every body costs a fixed part (the parsing, the checks, the geometry on columns). ``groups``: the rows that
    reach the Hansen coefficients, as :func:`ephem.orbit.hansen.hansen_exact_many` groups them by FFT length, each
    ``(count, N, K, parameter)``: each row pays the FFT of its own eccentricity (:func:`hansen_fft_s`, the
    single-body formula: the large step, 0.19 s a row at e = 0.99) and the theory over its group's ``K``
    harmonics (the sines of the mean anomaly, the last pass's series, the leading terms). Of the ``sigma_inputs``
    inputs with a sigma column, the ``differenced`` ones (the eccentricity's: central differences,
    :data:`ephem.batch.population.DIFFERENCED_INPUTS`; None: all of them, when the columns are unknown) evaluate
    the rows twice more; the others cost a part per row (forward-mode derivatives, :mod:`ephem.batch.tangents`,
    and the checks of the steps). The groups' coefficients stay in memory until the theory ends, so each group's
    part carries the memory of those before it: the last one is the peak. Without ``groups`` (the eccentricities
    unknown) the estimate is that of the low eccentricities of a main-belt population, which the fixed part
    covers.
    """
    differenced = sigma_inputs if differenced is None else min(differenced, sigma_inputs)
    evaluations = 1 + 2 * differenced
    per_row = evaluations * _u("population_row_s") + (sigma_inputs - differenced) * _u("population_sigma_row_s")
    fixed = Part("rows", f"{rows} bodies through the theory on columns"
                 + (f", {sigma_inputs} inputs with a sigma" if sigma_inputs else ""),
                 _u("population_base_s") + rows * per_row, rows * _u("population_row_bytes") / MB)
    parts, held = [fixed], fixed.memory_mb
    for count, n, k, parameter in groups:
        held += count * n * _u("population_bytes_per_sample") / MB
        parts.append(Part(parameter, f"the exact Hansen coefficients of {count} bod{'y' if count == 1 else 'ies'} "
                          f"(a {n}-point FFT each) and the theory over {k} harmonics"
                          + (f", {evaluations} evaluations (the sigmas)" if evaluations > 1 else ""),
                          evaluations * count * (hansen_fft_s(n) + k * _u("population_harmonic_s")), held))
    return Cost(tuple(parts))


def pole_uncertainty(body, inputs_with_sigma: int, epochs: int, order: int | None = None) -> Cost:
    """The pole's 1-σ along a track (:func:`ephem.forced.pole_uncertainty.pole_uncertainty`): the 2m first-order
    models stepped by each of the m inputs with a σ, built once per body and order (while
    :func:`~ephem.forced.pole_uncertainty.cached_pole_sensitivity` does not keep them), evaluated together at every
    epoch over their harmonics; and the catalogue's σ propagated to the mean obliquity (once per body and order:
    :func:`ephem.forced.uncertainty.propagated`, which a track reports beside it)."""
    if inputs_with_sigma == 0:
        return FREE
    rows, k = 2 * inputs_with_sigma, body_harmonics(body, order)
    parts = [Part("step_days", f"the pole's 1-sigma at {epochs} epochs ({rows} stepped models x {k} harmonics)",
                  _u("pole_sigma_base_s") + epochs * rows * (_u("pole_sigma_row_epoch_s")
                                                             + k * _u("pole_sigma_row_harmonic_s")),
                  epochs * rows * 48.0 / MB)]
    if not kept(POLE_SENSITIVITY, *body.with_sigmas(order)):     # the caches' key (Body.with_sigmas)
        build = model_build(body.orbit.e, order)
        parts.append(Part("body", f"the pole's {rows} stepped models (once per body and order)",
                          rows * (build.cpu_s + _u("pole_sigma_model_s")), build.memory_mb))
    if not kept(PROPAGATED, *body.with_sigmas(order)):
        parts.append(propagation(inputs_with_sigma))
    return Cost(tuple(parts))


def propagation(inputs_with_sigma: int) -> Part:
    """The catalogue's σ propagated to the answers' values (:func:`ephem.forced.uncertainty.propagated`: central
    differences of the model over every input with a σ, once per body and order, kept after)."""
    return Part("body", f"the catalogue's {inputs_with_sigma} input uncertainties propagated (once per body and "
                        "order)", _u("propagation_s"), 1.0)


#: how an answer is written out: the unit cost of one value
SERIALISATIONS = {"json": "serialise_s_per_value", "csv": "serialise_csv_s_per_value",
                  "ecsv": "serialise_ecsv_s_per_value"}


def serialised(epochs: int, columns: int, output: str = "json") -> Part:
    """An answer of ``epochs`` rows of ``columns`` floats, serialised as JSON (orjson, or a figure's
    points), CSV (a float's exact repr per value: ~20x the cost of JSON) or ECSV (astropy's writer, through a
    QTable: ~50x JSON's, benchmarks/RESULTS_calendar.md)."""
    return Part("step_days", f"{epochs} epochs serialised as {output}",
                epochs * columns * _u(SERIALISATIONS[output]), epochs * columns * _u("serialised_bytes_per_value") / MB)


def calendar_dates(epochs: int) -> Part:
    """The epochs' calendar dates beside ``jd_tdb`` (:func:`ephem.base.times.calendar_dates`: TDB to UTC through
    ERFA and the ISO text; benchmarks/bench_calendar.py)."""
    return Part("step_days", f"the calendar dates of {epochs} epochs",
                (_u("calendar_base_s") if epochs else 0.0) + epochs * _u("calendar_epoch_s"),
                epochs * _u("calendar_bytes_per_epoch") / MB)


def truncation_bounds(e: float) -> Part:
    """The truncation bound of each e-order the choice by tolerance tries (:func:`ephem.sun.ladder.truncation_bound`):
    the coefficient differences of up to 20 orders, each a small rational series evaluated once."""
    _, k = harmonics(e, None)
    return Part("tolerance_mas", "the truncation bounds of the e-orders", _u("base_s") + 20 * _u("harmonic_s") * k * 40,
                1.0)


@memo.bytes_bounded     # a function of the body alone, priced by every track of it (~14 us): kept per body and order
def body_harmonics(body, order: int | None = None) -> int:
    """:func:`nutation_harmonics` of a :class:`~ephem.bodies.catalogue.Body`, from its parameters alone
    (:func:`spin_harmonics`)."""
    return spin_harmonics(body.orbit.e, body.orbit.a_au, body.hd, body.spin_rate_rad_per_day, body.orbit.center,
                          order)


def spin_harmonics(e: float, a_au: float, hd: float, spin_rate_rad_per_day: float, center: str = "Sun",
                   order: int | None = None) -> int:
    """:func:`nutation_harmonics` of a body given by its values (a population's row): K/n = 3 n H_d / ω (Petit
    et al. eq. 10)."""
    n = mean_motion_rad_per_day(a_au, center)
    return nutation_harmonics(e, order, 3.0 * n * hd / spin_rate_rad_per_day)
