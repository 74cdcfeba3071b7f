"""The CLI's app, its shared options, and how an answer and a library error are printed.

The shared options: dataset, format, order, tolerance, time scale. An answer is printed as
JSON, CSV, an aligned text table or astropy's ECSV; a library error as ``error: FIELD: why`` with status 2 (3: not
applicable).
"""
from __future__ import annotations

import csv
import io
import json
import sys
from enum import Enum

import typer

try:  # typer >= 0.2x vendors click as typer._click (its context, not click's, is the current one)
    from typer._click.globals import get_current_context
except ImportError:  # pragma: no cover - typer on click
    from click import get_current_context

from .usage import UsageGroup, UsageTyper

app = UsageTyper(cls=UsageGroup, add_completion=False, no_args_is_help=True,
             help="Precession and nutation of the spin axes of asteroids, planets and moons.")


class Format(str, Enum):
    """A table-shaped answer's formats: its JSON, CSV and text table, and its table as astropy's ECSV."""
    json = "json"
    csv = "csv"
    table = "table"
    ecsv = "ecsv"


class RecordFormat(str, Enum):
    """A body's record (a unit per value, not per column): JSON, CSV or a text table."""
    json = "json"
    csv = "csv"
    table = "table"


#: api.CALENDAR_SCALES, spelled here (loading ephem.api for them would load numpy for every `--help`):
#: tests/cli/test_cli_ecsv.py holds them equal
TimeScale = Enum("TimeScale", [(s, s) for s in ("utc", "tt", "tdb")], type=str)


DatasetOpt = typer.Option("current", "--dataset", "-d", help="Catalogue dataset: current, petit2014 or one imported "
                          "with `ephem catalogue import`.")
FormatOpt = typer.Option(Format.json, "--format", "-f", help="Output format: json (the whole answer), csv and "
                         "table (one row per value, term or epoch), or ecsv (astropy's Enhanced CSV: the table with its "
                         "units, descriptions and the answer's metadata, as ephem.api.to_ecsv writes it).")
RecordFormatOpt = typer.Option(RecordFormat.json, "--format", "-f", help="Output format.")
TimeScaleOpt = typer.Option(TimeScale.utc, "--time-scale", help="The scale of the epochs' calendar dates beside "
                            "jd_tdb (ISO 8601 to the millisecond): utc (column utc_iso), tt or tdb.")
OrderOpt = typer.Option(None, "--order", help="Truncate the Hansen coefficients at this power of e "
                        "(the paper: 4). Default: exact.")
# no min=0 here: ephem.answers.requests refuses a tolerance <= 0 (zero too) with the service's message
ToleranceOpt = typer.Option(None, "--tolerance-mas", help="Let the fidelity ladder pick the cheapest "
                            "model estimated within this many milliarcseconds of the truth.")


def fail(exc, not_applicable: type) -> None:
    """Print a library error (an :class:`ephem.api.EphemError`) and exit: 3 if the theory does not apply (the
    command passes ``api.NotApplicableError``: this module does not import the api, one step less between a
    command and the library), else 2."""
    typer.echo(f"error: {exc}", err=True)
    raise typer.Exit(3 if isinstance(exc, not_applicable) else 2)


def _rows_to_csv(rows: list[dict]) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buf.getvalue()


def rows_to_table(rows: list[dict]) -> str:
    def cell(v):
        return f"{v:.10g}" if isinstance(v, float) else "" if v is None else str(v)
    cols = list(rows[0])
    cells = [[cell(r[c]) for c in cols] for r in rows]
    widths = [max(len(c), *(len(r[i]) for r in cells)) for i, c in enumerate(cols)]
    line = lambda vals: "  ".join(v.rjust(w) for v, w in zip(vals, widths))  # noqa: E731
    return "\n".join([line(cols), line(["-" * w for w in widths])] + [line(r) for r in cells]) + "\n"


def _jsonable(value):
    """json.dumps' fallback: some answers carry numpy arrays or scalars (``api.history``'s columns, as the
    service serialises them natively); their ``tolist`` gives the plain lists and numbers JSON takes. Duck-typed
    so that the CLI module itself does not import numpy (see the module docstring)."""
    tolist = getattr(value, "tolist", None)
    if tolist is None:
        raise TypeError(f"Object of type {type(value).__name__} is not JSON serializable")
    return tolist()


def emit(answer, fmt: Format, rows: list[dict] | None = None, ecsv=None) -> None:
    """Print ``answer`` as ``fmt``: JSON, ``rows`` as CSV or a table, or ``ecsv()``'s text (the command passes
    ephem.api.to_ecsv of the answer: this module does not import the api)."""
    if fmt is Format.ecsv:
        sys.stdout.write(ecsv())
        return
    if fmt is Format.json or fmt is RecordFormat.json:
        sys.stdout.write(json.dumps(answer, indent=2, allow_nan=False, default=_jsonable) + "\n")
        return
    rows = rows if rows is not None else [answer]
    notes = lower_bound_notes(answer)
    if fmt in (Format.csv, RecordFormat.csv):
        sys.stdout.write(_rows_to_csv(rows))
        for note in notes:              # beside the data, not in it: a CSV keeps its one header line
            sys.stderr.write(note + "\n")
        return
    # the notes after a blank line: the table's own lines stay aligned, its end plain to a reader and a parser
    sys.stdout.write(rows_to_table(rows) + ("\n" + "".join(note + "\n" for note in notes) if notes else ""))


def lower_bound_notes(answer) -> list[str]:
    """Where an answer's 1-sigma is a lower bound (some input moving the value has no published sigma: the answer's
    ``uncertainty.lower_bounds``), a line per value saying so, for the table and CSV outputs whose columns cannot."""
    uncertainty = answer.get("uncertainty") if isinstance(answer, dict) else None
    bounds = uncertainty.get("lower_bounds") if isinstance(uncertainty, dict) else None
    return [f"note: {key}_uncertainty is a lower bound (>=): {why}" for key, why in (bounds or {}).items()]


def flat_answer(answer: dict) -> dict:
    return {k: v for k, v in answer.items() if not isinstance(v, (dict, list))}


def command_line() -> str:
    """The command being run, as its source in an ECSV header: ``ephem track ceres --start 2040-01-01 ...`` (its
    arguments and the options given or defaulted, flags when set)."""
    ctx = get_current_context()
    words = ["ephem", *ctx.command_path.split()[1:]]      # the program's name, however it was started
    for param in ctx.command.params:
        value = ctx.params.get(param.name)
        if value is None or value is False or value == [] or not getattr(param, "opts", None):
            continue
        value = getattr(value, "value", value)
        if getattr(param, "param_type_name", "") == "argument":
            words.append(str(value))
        else:
            words.append(param.opts[0] if value is True else f"{param.opts[0]} {value}")
    return " ".join(words)
