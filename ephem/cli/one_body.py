"""The CLI's answers about one body or a catalogue, printed as JSON, CSV, a table or ECSV.

ECSV is astropy's. The commands: ``ephem bodies |
body | precession | nutation | track | history | free-motion`` (``body``'s record, a unit per value: JSON, CSV or a
table).

Each command imports :mod:`ephem.api` when it runs, not at the top, so that ``--help`` and usage errors answer
without numpy and the theories (tests/cli/test_cli_imports.py).
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional

import typer

from .common import (DatasetOpt, Format, FormatOpt, OrderOpt, RecordFormat, RecordFormatOpt, TimeScale, TimeScaleOpt,
                     ToleranceOpt, app, command_line, emit, fail, flat_answer)
from .usage import HELP_VALUES


def _models_help() -> str:
    """The ``{models}`` of ``--model``'s help: each family's model names and what it is, from the families' registry
    (read when the help is shown, so that a family registered since is listed; it loads numpy for this help only)."""
    from .. import api
    return "; ".join(f"{', '.join(models)} ({summary})" for summary, models in api.model_families())


HELP_VALUES["models"] = _models_help


def _ecsv(api, answer):
    """What ``--format ecsv`` prints: the answer's table written by ephem.api.to_ecsv, the command line its source."""
    return lambda: api.to_ecsv(answer, source=command_line())


@app.command()
def bodies(dataset: str = DatasetOpt, fmt: Format = FormatOpt):
    """List the catalogue's bodies."""
    from .. import api

    try:
        rows = api.list_bodies(dataset=dataset)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    emit(rows, fmt, rows, _ecsv(api, rows))


#: the columns of ``ephem body``'s CSV (every scalar of a value) and table (what fits a terminal's line: the
#: reasons for a missing sigma and the notes are sentences)
BODY_CSV_COLUMNS = ("quantity", "value", "unit", "uncertainty", "no_uncertainty", "source", "note")
BODY_TABLE_COLUMNS = ("quantity", "value", "unit", "uncertainty", "source")


def interior_line(interior: dict) -> str:
    """The record's ``interior`` on one line: the model and form, the parameters with their 1σ and unit, the
    source (or, for a rigid body, why)."""
    params = ", ".join(f"{k} {p['value']:.10g}" + (f" ± {p['uncertainty']:.4g}" if p["uncertainty"] is not None else "")
                       + (f" {p['unit']}" if p["unit"] else "") for k, p in interior["parameters"].items())
    return (f"interior: {interior['model']}" + (f" ({interior['form']})" if interior["form"] else "")
            + (f": {params}" if params else "")
            + (f"; parameters in {interior['parameters_file']}" if interior["parameters_file"] else "")
            + (f"; source {interior['source']}" if interior["source"] else "")
            + (f"; alternatives {', '.join(interior['alternatives'])}" if interior["alternatives"] else "")
            + (f"; why: {interior['why']}" if interior["why"] else ""))


@app.command()
def body(name: str = typer.Argument(..., metavar="BODY"), dataset: str = DatasetOpt,
         fmt: RecordFormat = RecordFormatOpt):
    """Full catalogue record of BODY (name or NAIF id): values, units, uncertainties, sources.

    JSON (the default) is the whole record. CSV and table give one row per value (CSV: quantity, value, unit,
    uncertainty, no_uncertainty, source, note; the table leaves out the reasons and notes); the body's identity,
    H_d and the correlations of the values' errors then go to stderr, and the interior model on a line of its own.
    """
    from .. import api

    try:
        record = api.body_record(name, dataset=dataset)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    if fmt is RecordFormat.json:
        emit(record, fmt)
        return
    corr = "; ".join(f"{a} ~ {b}: {c['value']:.4g}" for c in record["correlations"] for a, b in [c["inputs"]])
    typer.echo(f"{record['name']} (NAIF {record['naif_id']}, {record['kind']}), dataset {record['dataset']}: H_d "
               f"{record['dynamical_ellipticity']:.10g} from {record['dynamical_ellipticity_from']}, perturbers "
               f"{', '.join(record['perturbers'])}" + (f"; correlations {corr}" if corr else ""), err=True)
    typer.echo(interior_line(record["interior"]), err=True)
    columns = BODY_CSV_COLUMNS if fmt is RecordFormat.csv else BODY_TABLE_COLUMNS
    rows = [{c: key if c == "quantity" else value[c] for c in columns} for key, value in record["values"].items()]
    emit(record, fmt, rows)


@app.command()
def precession(name: str = typer.Argument(..., metavar="BODY"), dataset: str = DatasetOpt,
               fmt: Format = FormatOpt, order: Optional[int] = OrderOpt,
               tolerance_mas: Optional[float] = ToleranceOpt,
               perturbers: Optional[str] = typer.Option(None, "--perturbers", help="The torquing bodies, comma-separated: default the "
                                          "catalogue's (the Earth: moon,sun, the lunisolar theory); sun for the "
                                          "single-perturber answer.")):
    """Obliquity, dynamical ellipticity, scaling factor K and precession rate of BODY."""
    from .. import api

    try:
        ans = api.precession(name, dataset=dataset, order=order, tolerance_mas=tolerance_mas, perturbers=perturbers)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    emit(ans, fmt, [flat_answer(ans)], _ecsv(api, ans))


@app.command()
def nutation(name: str = typer.Argument(..., metavar="BODY"), dataset: str = DatasetOpt,
             fmt: Format = FormatOpt, order: Optional[int] = OrderOpt,
             tolerance_mas: Optional[float] = ToleranceOpt,
             perturbers: Optional[str] = typer.Option(None, "--perturbers", help="The torquing bodies, comma-separated: default the "
                                          "catalogue's (the Earth: moon,sun, the lunisolar theory); sun for the "
                                          "single-perturber answer."),
             cut_mas: Optional[float] = typer.Option(None, "--cut-mas", help="The lunisolar series (the Earth "
                                                     "with the Moon): keep the terms whose amplitude reaches this "
                                                     "many mas (default 0.1)."),
             nonrigid: bool = typer.Option(False, "--nonrigid", help="Apply the body's interior model to the "
                                           "terms (data/interiors.toml): Mars' liquid core, the Earth's IERS 1996 "
                                           "transfer function; a rigid body is refused with the reason.")):
    """Nutation series of BODY in longitude and obliquity (harmonics of the mean anomaly; for the Earth with
    the Moon, integer combinations of the Delaunay arguments l, l', F, D, Omega)."""
    from .. import api

    try:
        ans = api.nutation(name, dataset=dataset, order=order, tolerance_mas=tolerance_mas, perturbers=perturbers,
                           cut_mas=cut_mas,
                           nonrigid=nonrigid)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    rows = []
    for term in ans["terms"]:       # the Delaunay multipliers as five columns in CSV and tables
        row = {k: v for k, v in term.items() if k != "delaunay_multipliers"}
        if term.get("delaunay_multipliers") is not None:
            row = {"multiple": None, **dict(zip(api.DELAUNAY_NAMES, term["delaunay_multipliers"])), **row}
        rows.append(row)
    emit(ans, fmt, rows, _ecsv(api, ans))


@app.command()
def track(name: str = typer.Argument(..., metavar="BODY"),
          start: str = typer.Option(..., "--start", help="ISO 8601 (UTC unless a scale follows) or JD TDB."),
          stop: str = typer.Option(..., "--stop", help="ISO 8601 or JD TDB."),
          step_days: float = typer.Option(..., "--step-days", help="Sampling step in days."),
          dataset: str = DatasetOpt, fmt: Format = FormatOpt, order: Optional[int] = OrderOpt,
          tolerance_mas: Optional[float] = ToleranceOpt,
          model: Optional[str] = typer.Option(None, "--model", help="The model to compute with, "
                                              "one of the family serving BODY (omitted: its default): {models}."),
          axis: str = typer.Option("figure", "--axis", help="The pole to follow: figure (the axis of largest "
                                   "inertia, which circles the angular momentum by the free wobble, counted as "
                                   "an error), angular_momentum, forced_figure (the figure axis's forced "
                                   "motion, as the IAU's CIP: the free wobble is polar motion, not an error), or "
                                   "mean_rotation (a synchronous body's mean rotation axis: the Moon's mean-Earth "
                                   "pole, the IAU's; its figure axis is 78.56\" from it)."),
          wobble_phase: Optional[float] = typer.Option(None, "--free-wobble-phase-deg", help="Position angle of "
                                                       "the figure axis about the angular momentum at the wobble "
                                                       "epoch (north through east): lets the track add the free "
                                                       "wobble when the tolerance needs it."),
          wobble_j: Optional[float] = typer.Option(None, "--free-wobble-J-arcsec", help="The wobble's amplitude "
                                                   "(default: the published one)."),
          wobble_epoch: Optional[str] = typer.Option(None, "--free-wobble-epoch", help="Epoch of the phase "
                                                     "(default: the pole epoch)."),
          rotation_phase: Optional[float] = typer.Option(None, "--rotation-phase-deg", help="Angle of the long "
                                                         "(least-inertia) axis in the equator from the orbit's "
                                                         "ascending node on it at the pole epoch: lets the track add "
                                                         "the semi-diurnal terms of the rotation scale."),
          perturbers: Optional[str] = typer.Option(None, "--perturbers", help="The torquing bodies, comma-separated: default the "
                                          "catalogue's (the Earth: moon,sun, the lunisolar theory); sun for the "
                                          "single-perturber answer."),
          time_scale: TimeScale = TimeScaleOpt,
          models: bool = typer.Option(False, "--models", help="Instead of the track, compare every model serving "
                                      "BODY over these epochs: its estimated error (mas), predicted cost (CPU ms, "
                                      "MB), whether it is eligible and which one --tolerance-mas picks."),
          out: Optional[str] = typer.Option(None, "--out", help="With --models: also write the chart of the "
                                            "comparison (error against cost), FILE.svg or FILE.png.")):
    """Spin-axis track of BODY: ψ, Δψ, Δε, obliquity and pole RA/Dec over time, each epoch as JD TDB and as a calendar
    date (--time-scale: utc, tt or tdb).

    The model used (rung, order, estimated error, cost) goes to stderr with --format csv, table or ecsv. With --models,
    the comparison of every model instead (JSON: ephem.api.track_models' answer; CSV and table: one row per model,
    the chosen one on stderr), and with --out its chart.
    """
    from .. import api

    if models:
        if fmt is Format.ecsv:
            fail(api.InvalidInputError("format", "ecsv writes the track's table: the comparison of the models "
                                       "prints as json, csv or table"), api.NotApplicableError)
        try:
            chart = _models_chart(out, {"order": order, "model": model, "free_wobble_phase_deg": wobble_phase,
                                        "free_wobble_J_arcsec": wobble_j, "free_wobble_epoch": wobble_epoch,
                                        "rotation_phase_deg": rotation_phase,
                                        "time_scale": None if time_scale is TimeScale.utc else time_scale.value})
            # the request, checked once where every track's is (ephem.api.track_request), its models then compared
            request = api.track_request(name, start, stop, step_days, tolerance_mas=tolerance_mas, axis=axis,
                                        dataset=dataset, perturbers=perturbers)
        except api.EphemError as exc:
            fail(exc, api.NotApplicableError)
        _track_models(request, fmt, out, chart)
        return
    if out is not None:
        fail(api.InvalidInputError("out", "writes the chart of the models' comparison: give --models too"),
             api.NotApplicableError)
    try:
        ans = api.track(name, start, stop, step_days, dataset=dataset, order=order, tolerance_mas=tolerance_mas,
                        model=model,
                        axis=axis, free_wobble_phase_deg=wobble_phase, free_wobble_J_arcsec=wobble_j,
                        free_wobble_epoch=wobble_epoch, perturbers=perturbers, rotation_phase_deg=rotation_phase,
                        time_scale=time_scale.value)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    if fmt is not Format.json:
        info = ans["model"]
        err = info["estimated_error_mas"]
        typer.echo(f"model: {info['name']}" + (f" (order {info['order']})" if info["order"] is not None else "")
                   + (f", estimated error {err:.4g} mas" if err is not None else "")
                   + (", with the free wobble" if info["free_wobble"] else "")
                   + (f", with the rotation-scale terms ({info['rotation_scale']['modelled']})"
                      if info["rotation_scale"] else "")
                   + f", {info['cost_ms']:.1f} ms", err=True)
    keys = ["jd_tdb", f"{time_scale.value}_iso", "psi_arcsec", "delta_psi_arcsec", "delta_epsilon_arcsec",
            "obliquity_deg", "pole_ra_deg", "pole_dec_deg"]
    rows = [dict(zip(keys, vals)) for vals in zip(*(ans[k] for k in keys))]
    if not rows:
        rows = [dict.fromkeys(keys, "")]
    emit(ans, fmt, rows, _ecsv(api, ans))


def _models_chart(out: Optional[str], track_only: dict) -> Optional[str]:
    """``ephem track --models``' own checks, before the request is made: no option of the track alone
    (``track_only``, the command's), and ``out`` a chart's file; the chart's format (its suffix), or None."""
    from .. import api

    given = [k for k, v in track_only.items() if v is not None]
    if given:
        raise api.InvalidInputError(given[0], "applies to the track, not to --models (the comparison takes "
                                    "--tolerance-mas, --axis, --perturbers and --dataset)")
    chart = None if out is None else Path(out).suffix.lower().lstrip(".")
    if chart is not None and chart not in api.PLOT_CONTENT_TYPES:
        raise api.InvalidInputError("out", f"the chart's file must end in .svg or .png, got {Path(out).name!r}")
    return chart


def _track_models(request, fmt: Format, out: Optional[str], chart: Optional[str]) -> None:
    """``ephem track --models``: every model over the request's epochs (ephem.api.track_models_of, the request an
    ``ephem.api.TrackRequest``), printed, and with ``out`` its work-precision chart written (ephem.api.models_chart,
    as the suffix ``chart`` says)."""
    from .. import api

    image = None
    try:
        ans = api.track_models_of(request)
        if chart is not None:
            image = api.models_chart(ans, fmt=chart)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    if image is not None:
        Path(out).parent.mkdir(parents=True, exist_ok=True)
        Path(out).write_bytes(image)
        typer.echo(f"wrote {out} ({len(image)} bytes)", err=True)
    if fmt is not Format.json:
        pick = next((m for m in ans["models"] if m["chosen"]), None)
        chosen = ("none chosen" + (": none within the tolerance" if ans["tolerance_mas"] is not None else
                                   ": no tolerance given") if pick is None else
                  f"chosen: {pick['name']}" + (f" (order {pick['order']})" if pick["order"] is not None else "")
                  + f", estimated error {pick['estimated_error_mas']:.4g} mas, {pick['estimated_cpu_ms']:.4g} ms")
        typer.echo(f"{len(ans['models'])} models over {ans['epochs']} epochs; {chosen}", err=True)
    emit(ans, fmt, api.track_models_rows(ans, reasons=fmt is Format.csv))


@app.command()
def history(name: str = typer.Argument(..., metavar="BODY"),
            start_year: float = typer.Option(..., "--start-year", help="Julian years from J2000.0 TDB (negative: the "
                                             "past)."),
            stop_year: float = typer.Option(..., "--stop-year", help="Julian years from J2000.0 TDB."),
            step_years: float = typer.Option(..., "--step-years", help="Sampling step, Julian years."),
            dataset: str = DatasetOpt, fmt: Format = FormatOpt, tolerance_mas: Optional[float] = ToleranceOpt,
            orbit_model: Optional[str] = typer.Option(None, "--orbit-model", help="secular (Laplace-Lagrange) or "
                                                      "nbody (REBOUND from DE421, shipped for the catalogue's "
                                                      "bodies); default: the shipped N-body orbit where it covers "
                                                      "the span, else the secular one."),
            perturbers: Optional[str] = typer.Option(None, "--perturbers", help="The torquing bodies (default the "
                                                     "catalogue's)."),
            quiet: bool = typer.Option(False, "--quiet", help="No progress bar.")):
    """BODY's spin axis over millennia and millions of years: obliquity, precession angle, pole and orbit
    inclination, with the estimated error at each epoch.

    The model (orbit, estimate, where the history stops meaning anything, cost) goes to stderr with --format csv,
    table or ecsv. A progress bar shows on stderr while the spin is integrated (not with --quiet). The epochs are
    Julian years from J2000.0 TDB (column year), not calendar dates.
    """
    from .. import api

    bar = None if quiet else typer.progressbar(length=1000, label="integrating", file=sys.stderr)
    shown = [0]

    def progress(fraction: float) -> None:
        if bar is not None:
            step = int(1000 * fraction) - shown[0]
            if step > 0:
                bar.update(step)
                shown[0] += step

    try:
        if bar is not None:
            bar.__enter__()
        try:
            ans = api.history(name, start_year, stop_year, step_years, dataset=dataset, tolerance_mas=tolerance_mas,
                              orbit_model=orbit_model,
                              perturbers=perturbers, progress=progress)
        finally:
            if bar is not None:
                bar.__exit__(None, None, None)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    if fmt is not Format.json:
        info = ans["model"]
        span = (ans["meaningful_from_year"], ans["meaningful_to_year"])
        typer.echo(f"model: {info['name']} orbit, estimated error {info['estimated_error_mas'] / 3.6e6:.4g} deg"
                   + ("" if span == (None, None) else
                      f", meaningful from {span[0] if span[0] is not None else '-inf'} to "
                      f"{span[1] if span[1] is not None else 'inf'} years")
                   + f", {info['cost_ms']:.0f} ms", err=True)
    keys = ["year", "obliquity_deg", "precession_angle_deg", "pole_ra_deg", "pole_dec_deg", "orbit_inclination_deg",
            "estimated_error_deg", "obliquity_error_deg"]
    rows = [dict(zip(keys, vals)) for vals in zip(*(ans[k] for k in keys))]
    emit(ans, fmt, rows, _ecsv(api, ans))


@app.command("free-motion")
def free_motion(name: str = typer.Argument(..., metavar="BODY"),
                start: str = typer.Option(..., "--start", help="ISO 8601 (UTC unless a scale follows) or JD TDB."),
                stop: str = typer.Option(..., "--stop", help="ISO 8601 or JD TDB."),
                step_days: float = typer.Option(..., "--step-days", help="Sampling step in days."),
                j_arcsec: Optional[float] = typer.Option(None, "--J-arcsec", help="Wobble amplitude J at start "
                                                         "(default: the published one, Lara 2014 Table 1)."),
                method: str = typer.Option("auto", "--method", help="auto, exact, series or numeric."),
                dataset: str = DatasetOpt, fmt: Format = FormatOpt, time_scale: TimeScale = TimeScaleOpt):
    """Torque-free wobble of BODY: the figure axis about the angular momentum, and its periods."""
    from .. import api

    try:
        ans = api.free_motion_answer(name, start, stop, step_days, J_arcsec=j_arcsec, method=method, dataset=dataset,
                                     time_scale=time_scale.value)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    keys = [api.FREE_MOTION_KEYS[0], f"{time_scale.value}_iso", *api.FREE_MOTION_KEYS[1:]]
    rows = [dict(zip(keys, vals)) for vals in zip(*(ans[k] for k in keys))]
    if fmt is not Format.json:
        typer.echo(f"{ans['mode']} mode, method {ans['method']}: wobble period {ans['wobble_period_days']:.6g} d, "
                   f"precession period {ans['precession_period_days']:.6g} d", err=True)
    emit(ans, fmt, rows or [dict.fromkeys(keys, "")], _ecsv(api, ans))
