"""The CLI's commands that write files: ``ephem tables | plot | pck | batch | catalogue import``.

Nutation
tables, figures, SPICE text kernels, a catalogue's answers by partition, a user's dataset).

Each command imports :mod:`ephem.api` when it runs, not at the top (see :mod:`ephem.cli.one_body`).
"""
from __future__ import annotations

import sys
from enum import Enum
from pathlib import Path
from typing import Optional

import typer

from .common import DatasetOpt, OrderOpt, ToleranceOpt, app, fail
from .usage import UsageGroup, UsageTyper

# api.FORMATS' and api.LAYOUTS' names, as choices the option parser checks before any body is computed and that
# `--help` reads: spelled here because loading ephem.api for them would load numpy for every `--help` and usage
# error. tests/cli/test_cli_matrix.py::test_the_formats_are_read_from_the_options holds the formats equal to
# api.FORMATS; write_tables refuses a layout outside api.LAYOUTS.
TableFormat = Enum("TableFormat", [(f, f) for f in ("csv", "markdown", "latex", "json")], type=str)
TableLayout = Enum("TableLayout", [(x, x) for x in ("sin-cos", "amp-period")], type=str)


@app.command()
def tables(names: Optional[list[str]] = typer.Argument(None, metavar="[BODY]...",
                                                      help="Bodies (default: the whole catalogue)."),
           dataset: str = DatasetOpt,
           formats: list[TableFormat] = typer.Option(list(TableFormat), "--format",
                                                     help="csv, markdown, latex or json; repeat for several."),
           layouts: list[TableLayout] = typer.Option(list(TableLayout), "--layout",
                                                     help="sin-cos (Petit et al. Tables 5-8) or amp-period (Tables "
                                                     "9-10); repeat for both."),
           order: Optional[int] = OrderOpt,
           out: Path = typer.Option(Path("tables"), "--out", help="Directory for the files.")):
    """Nutation tables in the paper's layouts for BODY... or the whole catalogue: one file per body, layout
    and format (<body>_<dataset>_<layout>.csv|md|tex|json). Bodies no theory applies to
    are skipped with the reason."""
    from .. import api

    try:
        bodies = names or [b["name"] for b in api.list_bodies(dataset=dataset)]
        answers, skipped = [], []
        with typer.progressbar(bodies, label="tables", item_show_func=lambda b: b or "", file=sys.stderr) as bar:
            for name in bar:
                try:
                    answers.append(api.nutation(name, dataset=dataset, order=order))
                except api.NotApplicableError as exc:
                    skipped.append(str(exc))
        written = api.write_tables(answers, out, [f.value for f in formats], [x.value for x in layouts])
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    for why in skipped:
        typer.echo(f"skipped: {why}", err=True)
    typer.echo(f"wrote {len(written)} files for {len(answers)} bodies to {out}/")


@app.command()
def plot(name: str = typer.Argument(..., metavar="BODY"),
         kind: str = typer.Option("precession", "--kind", help="precession (Petit et al. Fig. 4), nutation-loop "
                                  "(Fig. 5), obliquity, free-wobble, or obliquity-history (the obliquity over "
                                  "millennia to millions of years, ephem.answers.requests.history)."),
         start: str = typer.Option(..., "--start", help="ISO 8601 (UTC unless a scale follows) or JD TDB; for "
                                   "--kind obliquity-history, Julian years from J2000.0 TDB (negative: the past, "
                                   "e.g. --start -3e6)."),
         stop: str = typer.Option(..., "--stop", help="ISO 8601 or JD TDB; for --kind obliquity-history, Julian "
                                  "years from J2000.0 TDB."),
         out: Path = typer.Option(..., "--out", help="The figure: FILE.png or FILE.svg."),
         step_days: Optional[float] = typer.Option(None, "--step-days", help="Sampling step (default: chosen "
                                                   "for the kind and span); not for obliquity-history."),
         step_years: Optional[float] = typer.Option(None, "--step-years", help="obliquity-history: sampling step, "
                                                    "Julian years (default: the span over 1000, rounded, at least "
                                                    "100)."),
         orbit_model: Optional[str] = typer.Option(None, "--orbit-model", help="obliquity-history: secular or "
                                                   "nbody (default: the shipped N-body orbit where it covers the "
                                                   "span, else the secular one)."),
         dataset: str = DatasetOpt, order: Optional[int] = OrderOpt, tolerance_mas: Optional[float] = ToleranceOpt,
         model: Optional[str] = typer.Option(None, "--model", help="A rung of the fidelity ladder."),
         j_arcsec: Optional[float] = typer.Option(None, "--J-arcsec", help="Free-wobble amplitude (free-wobble)."),
         dpi: float = typer.Option(150, "--dpi", help="PNG resolution.")):
    """A figure of BODY's track (or free wobble, or obliquity history) as PNG or SVG, axes in units, title with
    body and dataset."""
    from .. import api

    fmt = out.suffix.lower().lstrip(".")
    try:
        if fmt not in api.PLOT_CONTENT_TYPES:
            raise api.InvalidInputError("out", f"the file must end in .png or .svg, got {out.name!r}")
        image = api.render_plot(kind, name, start, stop, step_days, fmt=fmt, dataset=dataset, dpi=dpi,
                                tolerance_mas=tolerance_mas, model=model, order=order, J_arcsec=j_arcsec,
                                step_years=step_years, orbit_model=orbit_model)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_bytes(image)
    typer.echo(f"wrote {out} ({len(image)} bytes)")


@app.command()
def pck(names: list[str] = typer.Argument(..., metavar="BODY..."),
        start: str = typer.Option(..., "--start", help="ISO 8601 (UTC unless a scale follows) or JD TDB."),
        stop: str = typer.Option(..., "--stop", help="ISO 8601 or JD TDB."),
        out: Path = typer.Option(..., "--out", help="The kernel, FILE.tpc."),
        dataset: str = DatasetOpt, tolerance_mas: Optional[float] = ToleranceOpt,
        model: Optional[str] = typer.Option(None, "--model", help="A rung of the fidelity ladder."),
        max_angles: int = typer.Option(100, "--max-angles", help="Most nutation angles per body (the fit adds "
                                       "them until it is under 0.1 mas).")):
    """A NAIF text PCK (KPL/PCK) whose pole reproduces BODY...'s track over the span, with a comment block
    stating the model, dataset, validity span and fitting error (docs/pck.md)."""
    from .. import api

    try:
        result = api.write_pck_file(out, names, start, stop, dataset=dataset, tolerance_mas=tolerance_mas,
                                    model=model, max_angles=max_angles)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    for f in result.bodies:
        est = f.model.get("estimated_error_mas")
        typer.echo(f"{f.name}: fitting error {f.fit_error_mas:.4g} mas with {len(f.angles)} angles (model "
                   f"{f.model['name']}" + (f", estimated {est:.4g} mas" if est is not None else "") + ")")
    typer.echo(f"wrote {out}")


class BatchFormat(str, Enum):
    parquet = "parquet"
    csv = "csv"
    ecsv = "ecsv"


@app.command()
def batch(input_path: str = typer.Argument(..., metavar="INPUT", help="The bodies: a CSV or Parquet file, one row "
                                           "per body (columns: docs/batch_input.md)."),
          out: Path = typer.Option(..., "--out", help="Output directory: part-NNNNN.parquet|csv|ecsv, one per partition "
                                   "(a rerun resumes in it)."),
          scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Address of a running dask scheduler, "
                                                  "tcp://HOST:PORT (default: a local cluster on 127.0.0.1)."),
          workers: Optional[int] = typer.Option(None, "--workers", min=1, help="Local worker processes (default: "
                                                "the cores); with --scheduler, wait for this many workers."),
          partition_rows: int = typer.Option(50_000, "--partition-rows", min=1, help="Bodies per partition (one "
                                             "task; bounds a worker's memory)."),
          fmt: BatchFormat = typer.Option(BatchFormat.parquet, "--format", help="Output format (ecsv: "
                                                "astropy's, with units, as POST /v1/batch's)."),
          history: bool = typer.Option(False, "--history", help="Add each body's obliquity history (with "
                                       "--start-year, --stop-year, --step-years)."),
          start_year: Optional[float] = typer.Option(None, "--start-year", help="--history: Julian years from "
                                                     "J2000.0 TDB (negative: the past)."),
          stop_year: Optional[float] = typer.Option(None, "--stop-year", help="--history: Julian years from "
                                                    "J2000.0 TDB."),
          step_years: Optional[float] = typer.Option(None, "--step-years", help="--history: sampling step, Julian "
                                                     "years."),
          fresh: bool = typer.Option(False, "--fresh", help="Delete an earlier batch's partitions and outputs in "
                                     "--out and start again (a rerun with the same input and settings resumes)."),
          quiet: bool = typer.Option(False, "--quiet", help="No progress bar and no notes on stderr.")):
    """Answer a catalogue of bodies, partition by partition, on a local or remote dask cluster (docs/batch.md).

    Each partition's answers go to --out as one file; a body the theory cannot take gets its reason in the
    ``error`` column. A rerun of the same command resumes: finished partitions are skipped. Notes and a
    progress bar go to stderr; the summary line to stdout.
    """
    from .. import api

    years = {"start_year": start_year, "stop_year": stop_year, "step_years": step_years}
    try:
        if history and None in years.values():
            missing = next(k for k, v in years.items() if v is None)
            raise api.InvalidInputError(missing, f"missing; give --{missing.replace('_', '-')} with --history")
        if not history and any(v is not None for v in years.values()):
            given = next(k for k, v in years.items() if v is not None)
            raise api.InvalidInputError(given, "only with --history")
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    spec = None
    if history:
        spec = api.HistorySpec(start_year, stop_year, step_years)
    bar, shown = [None], [0]

    def progress(done: int, total: int) -> None:
        if quiet or total == 0:
            return
        if bar[0] is None:
            bar[0] = typer.progressbar(length=total, label="partitions", file=sys.stderr)
            bar[0].__enter__()
        if done > shown[0]:
            bar[0].update(done - shown[0])
            shown[0] = done

    def note(message: str) -> None:
        if not quiet:
            typer.echo(message, err=True)

    failed = None
    try:
        try:
            result = api.run_batch(input_path, out, scheduler=scheduler, workers=workers,
                                   partition_rows=partition_rows, output_format=fmt.value, history=spec,
                                   progress=progress, fresh=fresh, log=note)
        finally:
            if bar[0] is not None:
                bar[0].__exit__(None, None, None)
    except api.BatchFailed as exc:
        failed, result = exc, exc.result
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    rate = f", {result.rows_computed / result.seconds:.4g} bodies/s" if result.rows_computed else ""
    resumed = f", {result.partitions_skipped} resumed" if result.partitions_skipped else ""
    typer.echo(f"{result.rows} rows ({result.rows_failed} failed) in {result.partitions} partitions{resumed} to "
               f"{result.out_path}/, {result.seconds:.1f} s{rate}")
    if failed is not None:
        typer.echo(f"error: {failed}", err=True)
        raise typer.Exit(1)


# ------------------------------------------------------------------ ephem catalogue import

catalogue_app = UsageTyper(cls=UsageGroup, no_args_is_help=True,
                       help="Your own datasets: import an orbit file and a pole/period table (docs/catalogue_import.md).")
app.add_typer(catalogue_app, name="catalogue")


class OrbitFormat(str, Enum):
    mpcorb = "mpcorb"
    sbdb_json = "sbdb-json"
    sbdb_csv = "sbdb-csv"


@catalogue_app.command("import")
def catalogue_import(orbits: str = typer.Option(..., "--orbits", help="Orbit file: MPCORB layout, SBDB API JSON or "
                                                "SBDB query CSV (full_name,e,a,i,om,w,ma,epoch)."),
                     poles: str = typer.Option(..., "--poles", help="Pole/period table (CSV: name, pole_ra_deg, "
                                               "pole_dec_deg, rotation_period_hours, dynamical_ellipticity or "
                                               "moment_a/b/c, optional *_sigma)."),
                     name: str = typer.Option(..., "--name", help="Name of the new dataset (select it with "
                                              "--dataset NAME)."),
                     orbit_format: Optional[OrbitFormat] = typer.Option(None, "--format", help="Format of the orbit "
                                                                        "file (default: detected from its content)."),
                     skip_unmatched: bool = typer.Option(False, "--skip-unmatched", help="Leave out the bodies found "
                                                         "in one file only (default: an error naming them)."),
                     force: bool = typer.Option(False, "--force", help="Replace an imported dataset of that name.")):
    """Write a dataset from your own orbit file and pole/period table, into $EPHEM_USER_CATALOGUE_DIR (default
    ~/.local/share/ephem/catalogue); nothing is fetched from the network."""
    from .. import api

    try:
        result = api.import_catalogue(orbits, poles, name, orbit_format.value if orbit_format else None,
                                  skip_unmatched=skip_unmatched, force=force)
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    for skipped in result.skipped:
        typer.echo(f"note: skipped {skipped}", err=True)
    names = result.catalogue.names
    typer.echo(f"{'replaced' if result.replaced else 'wrote'} {result.path}: dataset {name!r}, {len(names)} "
               f"bod{'y' if len(names) == 1 else 'ies'} ({', '.join(names)}); select it with --dataset {name}")
