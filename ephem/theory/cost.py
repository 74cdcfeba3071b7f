"""What a request will cost, known before it runs: CPU seconds of one core and peak memory.

Every model states its cost from the request's parameters alone (epochs, harmonics, orbits,
integration span), before any work: :class:`Cost` is a sum of named :class:`Part` s, each
tied to the request parameter that drives it, so a refusal can say which parameter to change.
:mod:`ephem.base.budget` charges these costs against a request's budget.

The unit costs in ``data/cost_model.toml`` were measured on the project's reference machine
(2 cores, CPython 3.11, numpy 2.4, one BLAS thread) and set about twice the measurement;
``benchmarks/bench_cost.py`` prints each prediction against the measured time and memory
(``benchmarks/RESULTS_cost.md``). They are upper estimates there, some by much more than 2x
(the integrations' dense output, the second-order theory), not promises: the deadline of
:mod:`ephem.base.budget` is the backstop when a machine or an input is slower than predicted.
"""
from __future__ import annotations

import math
from functools import lru_cache

from ..base.budget import FREE, Cost, Part  # noqa: F401  (FREE, Cost: re-exported with the predictors)
from ..base.paths import data_dir
from ..orbit.hansen import decay_rate, fft_length
from ..orbit.kepler import mean_motion_rad_per_day
from ..base.disk_cache import read_toml

MB = 1024.0 * 1024.0
#: The numerical rungs integrate through every orbit (~5 ms each); beyond this many orbits from the pole epoch a
#: request would tie up a worker for seconds, so they are not offered (the service states it in its OpenAPI text).
MAX_NUMERICAL_ORBITS = 1000




@lru_cache(maxsize=1)
def unit_costs() -> dict:
    """The measured unit costs (``data/cost_model.toml``)."""
    return read_toml(data_dir() / "cost_model.toml")["unit"]


def _u(key: str) -> float:
    return float(unit_costs()[key])


# --- the pieces every model is made of ------------------------------------------------------------

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
    if order is not None:
        return Part("order", f"the e^{order} Hansen series", _u("series_s") * (1 + order) ** 2, 1.0)
    return Part("orbit.e", f"exact Hansen coefficients (a {n}-point FFT, e = {e:.4g})",
                _u("base_s") + hansen_fft_s(n), _u("fft_bytes_per_sample") * n / MB)


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
                _u("harmonic_s") * 64.0 * k * k, 0.5 + harmonic_work_mb(64 * k, k))


def harmonic_sum(epochs: int, k: int, parameter: str, what: str) -> Part:
    """A nutation series of ``k`` harmonics summed at ``epochs`` epochs (Chebyshev blocks)."""
    return Part(parameter, f"{what}: {epochs} epochs x {k} harmonics",
                epochs * (_u("epoch_s") + _u("harmonic_s") * k),
                epochs * _u("track_bytes_per_epoch") / MB + harmonic_work_mb(epochs, k))


def estimate_tables(e: float) -> Part:
    """The tables the ladder's span-aware estimates read (:func:`ephem.sun.ladder.theory_tables`: the nutation, the
    truncated series' differences and the second-order remainder over one orbit), built once per body and process:
    measured 9-33 ms for the catalogue bodies, 40 ms at e = 0.9 (K = 1580) and 0.195 s, 74 MB at e = 0.95
    (K = 4806)."""
    k = harmonics(e, None)[1]
    return Part("orbit.e", f"the estimates' tables over one orbit ({k} harmonics, e = {e:.4g}; once per body)",
                _u("tables_base_s") + _u("tables_s_per_harmonic") * k,
                _u("tables_base_mb") + _u("tables_mb_per_harmonic") * k)


def second_order(epochs: int, k: int) -> Part:
    return Part("step_days", f"the second-order theory at {epochs} epochs x {k} harmonics",
                _u("base_s") + epochs * (_u("second_order_epoch_s") + _u("second_order_harmonic_s") * k),
                epochs * _u("track_bytes_per_epoch") / MB + harmonic_work_mb(epochs, k))


def spin_integration(orbits: float, e: float, epochs: int) -> Part:
    """DOP853 through every orbit from the pole epoch (:mod:`ephem.forced.integration`): the steps per
    orbit grow toward pericentre, measured as (1 - e)^(-1/2)."""
    per_orbit = _u("spin_orbit_s") / math.sqrt(1.0 - e)
    return Part("stop", f"the spin axis integrated through {orbits:.4g} orbits",
                _u("base_s") + orbits * per_orbit + epochs * _u("dense_output_s"),
                epochs * _u("track_bytes_per_epoch") / MB + orbits * _u("spin_bytes_per_orbit") / MB)


def orbit_integration(span_days: float) -> Part:
    """The real orbit (:mod:`ephem.orbit.de421`): the body integrated under the DE421 planets."""
    years = span_days / 365.25
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


def lunisolar_sum(epochs: int) -> Part:
    return Part("step_days", f"the lunisolar series at {epochs} epochs", epochs * _u("lunisolar_epoch_s"),
                epochs * _u("track_bytes_per_epoch") / MB)


def nonrigid_sum(epochs: int) -> Part:
    """The non-rigid Earth's track beyond the lunisolar series' sum: the transfer function's series (built once per
    process, as the rigid one) and ERFA's IAU 2006 precession and rotation matrix at every epoch."""
    return Part("step_days", f"the IAU 2006 precession (ERFA) at {epochs} epochs", epochs * _u("nonrigid_epoch_s"),
                epochs * _u("track_bytes_per_epoch") / MB)


def synchronous_estimates() -> Part:
    """A synchronous rotator's Cassini state, its free modes and its libration series' bounds: a root, a few
    closed forms and a small table, once per body (:mod:`ephem.moon.family`)."""
    return Part("body", "the Cassini state and its estimates", _u("synchronous_base_s"), 2.0)


def synchronous_track(epochs: int, terms: int = 0) -> Part:
    """The Cassini pole (and ``terms`` libration terms) at ``epochs`` epochs, with the ecliptic of date's
    rotation to the ICRF (erfa.ecm06) at each."""
    return Part("step_days", f"the Cassini-state pole at {epochs} epochs"
                + (f" with {terms} libration terms" if terms else ""),
                _u("base_s") + epochs * (_u("synchronous_epoch_s") + terms * _u("libration_term_epoch_s")),
                epochs * (_u("track_bytes_per_epoch") + terms * _u("libration_bytes_per_term_epoch")) / MB)


def libration_series() -> Part:
    """The Moon's forced physical librations (:func:`ephem.moon.physical_librations.moon_physical_librations`), with the
    catalogue's and the effective moments: built once per process (at the service's start-up)."""
    return Part("body", "the Moon's libration series (built once per process, at start-up)",
                2.0 * _u("libration_series_s"), 2.0 * _u("libration_series_mb"))


def synchronous_integration(span_days: float, epochs: int) -> Part:
    """The rigid Moon on its real orbit (:func:`ephem.moon.rigid_integration.integrate_synchronous`) over ``span_days``
    (from the pole epoch to the farthest epoch, both sides): the orbit's table and the integration per year."""
    years = span_days / 365.25
    return Part("stop", f"the rigid Moon integrated over {years:.4g} years",
                _u("base_s") + years * (_u("moon_table_s_per_year") + _u("moon_integration_s_per_year"))
                + epochs * _u("dense_output_s"), years * _u("moon_mb_per_year") + epochs * _u("track_bytes_per_epoch") / MB)


def spin_history(span_years: float, epochs: int, steps_per_sample: int = 1) -> Part:
    """The averaged spin equation integrated over ``span_years`` (both sides of the epoch together) with its
    neighbours (:func:`ephem.longterm.averaged_spin.integrate`'s splitting), then the requested epochs. The steps
    cut the orbit's 500-year samples in ``steps_per_sample`` (a power of two, :func:`ephem.longterm.averaged_spin.
    split_steps` on the body's own orbit): the work is per year of span and per step. The unit is the shipped
    catalogue's slowest per year at one step per sample (Eros, whose noisy orbit asks for 1.8 on average)."""
    return Part("stop_year", f"the averaged spin integrated over {span_years:.4g} years",
                _u("base_s") + _u("spin_history_base_s")
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


def cassini_history(epochs: int) -> Part:
    """A synchronous rotator's Cassini state carried along its primary's orbit history (:class:`ephem.moon.family.
    CassiniHistory`): the orbit's spline, the node's quadrature on 4001 points and the pole at each epoch."""
    return Part("step_years", f"the Cassini state along the orbit at {epochs} epochs",
                _u("base_s") + _u("spin_history_base_s") + (epochs + 4001) * _u("cassini_history_point_s"),
                _u("spin_history_base_mb") + (epochs + 4001) * _u("history_bytes_per_epoch") / MB)


def pole_uncertainty(body, inputs_with_sigma: int, epochs: int, order: int | None = None) -> Cost:
    """The pole's 1-σ along a track (:func:`ephem.forced.uncertainty.pole_uncertainty`): two first-order models and
    tracks per input with a σ."""
    if inputs_with_sigma == 0:
        return FREE
    k = body_harmonics(body, order)
    one = (hansen_build(body.orbit.e, order), harmonic_sum(epochs, k, "step_days", "a perturbed track"))
    return Cost(one * (2 * inputs_with_sigma))


#: how an answer is written out: the unit cost of one value
SERIALISATIONS = {"json": "serialise_s_per_value", "csv": "serialise_csv_s_per_value"}


def serialised(epochs: int, columns: int, output: str = "json") -> Part:
    """An answer of ``epochs`` rows of ``columns`` floats, serialised as JSON (orjson, or a figure's
    points) or CSV (a float's exact repr per value: ~20x the cost of JSON)."""
    return Part("step_days", f"{epochs} epochs serialised as {output}",
                epochs * columns * _u(SERIALISATIONS[output]), epochs * columns * _u("serialised_bytes_per_value") / MB)


def truncation_bounds(e: float) -> Part:
    """The truncation bound of each e-order the choice by tolerance tries (:func:`ephem.sun.ladder.truncation_bound`):
    the coefficient differences of up to 20 orders, each a small rational series evaluated once."""
    _, k = harmonics(e, None)
    return Part("tolerance_mas", "the truncation bounds of the e-orders", _u("base_s") + 20 * _u("harmonic_s") * k * 40,
                1.0)


def lunisolar_answer() -> Part:
    """The Earth under the Moon and the Sun: the lunisolar series are built once per process (at the
    service's start-up, ``EPHEM_WARM_UP``); an answer reads them."""
    return Part("perturbers", "the lunisolar series (built at start-up)", _u("lunisolar_answer_s"), 5.0)


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
