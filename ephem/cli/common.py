"""The CLI's app, its shared options, and how an answer and a library error are printed.

The shared options: dataset, format, order, tolerance. An answer is printed as JSON, CSV or an aligned text table;
a library error as ``error: FIELD: why`` with status 2 (3: not applicable).
"""
from __future__ import annotations

import csv
import io
import json
import sys
from enum import Enum

import typer

from .usage import UsageGroup, UsageTyper

app = UsageTyper(cls=UsageGroup, add_completion=False, no_args_is_help=True,
             help="Precession and nutation of the spin axes of asteroids, planets and moons.")


class Format(str, Enum):
    json = "json"
    csv = "csv"
    table = "table"


DatasetOpt = typer.Option("current", "--dataset", "-d", help="Catalogue dataset: current, petit2014 or one imported "
                          "with `ephem catalogue import`.")
FormatOpt = typer.Option(Format.json, "--format", "-f", help="Output format.")
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


def emit(answer, fmt: Format, rows: list[dict] | None = None) -> None:
    if fmt is Format.json:
        sys.stdout.write(json.dumps(answer, indent=2, allow_nan=False, default=_jsonable) + "\n")
        return
    rows = rows if rows is not None else [answer]
    sys.stdout.write(_rows_to_csv(rows) if fmt is Format.csv else rows_to_table(rows))


def flat_answer(answer: dict) -> dict:
    return {k: v for k, v in answer.items() if not isinstance(v, (dict, list))}
