"""What the Moon's family (a synchronous rotator) will cost before it runs: its predictors, with its own unit costs.

The units are in ``data/moon_costs.toml``, measured by ``benchmarks/bench_cost.py`` and ``bench_calibration.py`` as the
shared ones of ``data/cost_model.toml`` (:mod:`ephem.theory.cost`: a track's answer, the serialisation, the fixed part
of a call); each family keeps its own predictors and table, so a new family adds its own beside them (issue 43).
"""
from __future__ import annotations

from ..base.budget import Part
from ..theory.cost import MB, unit, unit_table

#: the Moon's table of unit costs, in data/
TABLE = "moon_costs.toml"


def _u(key: str) -> float:
    return float(unit_table(TABLE)[key])


def synchronous_estimates() -> Part:
    """A synchronous rotator's estimates from its Cassini state, free modes and libration series' bounds (kept once
    per body: the Moon's at start-up, :mod:`ephem.moon.family`)."""
    return Part("body", "the Cassini state's estimates", _u("synchronous_base_s"), 2.0)


def synchronous_track(epochs: int, terms: int = 0) -> Part:
    """The Cassini pole (and ``terms`` libration terms) at ``epochs`` epochs, with the ecliptic of date's
    rotation to the ICRF (erfa.ecm06) at each."""
    return Part("step_days", f"the Cassini-state pole at {epochs} epochs"
                + (f" with {terms} libration terms" if terms else ""),
                (unit("base_s") if terms else 0.0)
                + epochs * (_u("synchronous_epoch_s") + terms * _u("libration_term_epoch_s")),
                epochs * (unit("track_bytes_per_epoch") + terms * _u("libration_bytes_per_term_epoch")) / MB)


def libration_extremes(terms: int, epochs: int, block: int) -> Part:
    """The nutation answer's half peak-to-peak σ and ρ of a series of ``terms`` terms (:func:`ephem.moon.family.
    half_peak_to_peak`): the terms summed at ``epochs`` epochs, ``block`` at a time (kept per body and cut once
    computed)."""
    return Part("cut_mas", f"the librations' extremes: {terms} terms at {epochs} epochs",
                unit("base_s") + epochs * terms * _u("libration_term_epoch_s"),
                min(block, epochs) * terms * _u("libration_bytes_per_term_epoch") / MB)


def libration_series() -> Part:
    """The Moon's forced physical librations (:func:`ephem.moon.physical_librations.moon_physical_librations`), with the
    catalogue's and the effective moments: built once per process (at the service's start-up)."""
    return Part("body", "the Moon's libration series (built once per process, at start-up)",
                2.0 * _u("libration_series_s"), 2.0 * _u("libration_series_mb"))


def synchronous_integration(span_days: float, epochs: int) -> Part:
    """The rigid Moon on its real orbit (:func:`ephem.moon.rigid_integration.integrate_synchronous`) over ``span_days``
    (from the pole epoch to the farthest epoch, both sides): the orbit's table and the integration per year, and the
    integrated pole at every epoch (dense output, the ecliptic of date)."""
    years = span_days / 365.25
    return Part("stop", f"the rigid Moon integrated over {years:.4g} years",
                unit("base_s") + years * (_u("moon_table_s_per_year") + _u("moon_integration_s_per_year"))
                + epochs * _u("moon_epoch_s"),
                years * _u("moon_mb_per_year") + epochs * unit("track_bytes_per_epoch") / MB)


def lunar_kernel(epochs: int, kept: bool) -> Part:
    """DE421's lunar orientation read from its binary PCK (:mod:`ephem.moon.lunar_kernel`) at ``epochs`` epochs: the
    Chebyshev pieces and the axes at each, the ecliptic of date's rotation, and the file's first mapping while the
    process does not keep it open (``kept``)."""
    return Part("step_days", f"DE421's lunar orientation at {epochs} epochs",
                (0.0 if kept else _u("lunar_kernel_open_s")) + epochs * (_u("lunar_kernel_epoch_s")
                                                                          + _u("synchronous_epoch_s")),
                epochs * unit("track_bytes_per_epoch") / MB)


def cassini_history(epochs: int) -> Part:
    """A synchronous rotator's Cassini state carried along its primary's orbit history (:class:`ephem.moon.family.
    CassiniHistory`): a fixed part (the node's quadrature on 4001 points of the orbit's spline, vectorised) and the
    pole carried to each epoch."""
    return Part("step_years", f"the Cassini state along the orbit at {epochs} epochs",
                unit("base_s") + _u("cassini_history_base_s") + epochs * _u("cassini_history_point_s"),
                unit("spin_history_base_mb") + (epochs + 4001) * unit("history_bytes_per_epoch") / MB)
