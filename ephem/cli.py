"""Command-line interface: ``ephem bodies | body | precession | nutation | track | history | free-motion | tables |
plot | pck | batch | demo | catalogue import``.

``bodies``, ``body``, ``precession``, ``nutation``, ``track``, ``history`` and ``free-motion`` print JSON (the
default), CSV or an aligned text table (``--format json|csv|table``); ``tables`` writes csv, markdown, latex or json
files, ``plot`` PNG or SVG (``--out``'s suffix), ``pck`` a text kernel, ``batch`` parquet or csv partitions, ``demo``
text tables; ``catalogue import``'s ``--format`` is its orbit file's. tests/test_cli_matrix.py runs every command in
every format for a body of every theory family. Errors go to stderr as ``error: FIELD: why``
with exit status 2 (bad input, unknown body, and what the option parser refuses: a malformed
number, an unknown option or command, a missing one), 3 (theory not applicable) or 1 (``ephem batch``:
partitions that still failed after their retries; the others are written and a rerun resumes).

Start-up is kept short for one-body answers: :mod:`ephem.answers.requests` (numpy, the catalogue, the models)
is imported by each command rather than here, so ``--help`` and usage errors never load it, and
option values are parsed here rather than by typer's pydantic adapters (see :func:`_plain_values`).
"""
from __future__ import annotations

import csv
import difflib
import io
import json
import math
import re
import sys
from contextlib import contextmanager
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any, Optional

import typer
from typer.core import TyperCommand, TyperGroup

from .exports import tables as _tables
from .base.errors import EphemError, NotApplicableError

try:  # typer >= 0.2x vendors click as typer._click
    from typer._click import exceptions as _usage
except ImportError:  # pragma: no cover - typer on click
    from click import exceptions as _usage
try:  # typer >= 0.2x coerces each value through a pydantic adapter built on first use (0.05-0.1 s)
    from typer._coercion import RuntimeParam as _RuntimeParam
except ImportError:  # pragma: no cover - typer on click: click's own types, no pydantic
    _RuntimeParam = None


# ------------------------------------------------------------------ usage errors read like the library's

class _UsageFailure(_usage.UsageError):
    """A usage error of ours, with the field it concerns (``error: FIELD: why``, status 2)."""

    def __init__(self, field: str, reason: str, ctx=None):
        super().__init__(f"{field}: {reason}", ctx)
        self.field, self.reason = field, reason


def _field(param) -> str:
    """The name the API gives a parameter: ``--step-days`` -> step_days, ``--format`` -> format, BODY -> body."""
    if param is None:
        return "arguments"
    if getattr(param, "param_type_name", "") == "argument":
        return (param.metavar or param.name or "arguments").strip("[].").lower()
    longs = [o for o in param.opts if o.startswith("--")] or list(param.opts)
    return longs[0].lstrip("-").replace("-", "_")


def _hint(param) -> str:
    return param.opts[0] if getattr(param, "param_type_name", "") == "option" else (param.metavar or param.name)


def _usage_message(exc) -> str:
    """``FIELD: why`` for a usage error of the option parser (typer/click's classes) or of ours."""
    if isinstance(exc, _UsageFailure):
        return exc.message
    ctx = getattr(exc, "ctx", None)
    where = f"see '{ctx.command_path} --help'" if ctx is not None else "see --help"
    if isinstance(exc, _usage.NoSuchOption):
        close = sorted(exc.possibilities or ())
        return f"{exc.option_name}: no such option" + (f"; did you mean {' or '.join(close)}?" if close else
                                                         f"; {where}")
    if isinstance(exc, _usage.MissingParameter):
        return f"{_field(exc.param)}: missing; give {_hint(exc.param)}" if exc.param is not None else \
            f"arguments: {exc.format_message()}"
    if isinstance(exc, _usage.BadParameter):
        return f"{_field(exc.param)}: {exc.message}" if exc.param is not None else f"arguments: {exc.message}"
    if isinstance(exc, _usage.BadOptionUsage):
        params = ctx.command.params if ctx is not None else []
        param = next((p for p in params if exc.option_name in getattr(p, "opts", ())), None)
        field = _field(param) if param is not None else exc.option_name
        needs = re.fullmatch(r"Option '(.+)' (requires (an argument|\d+ arguments)|does not take a value)\.",
                             exc.message)
        return f"{field}: " + (exc.message if needs is None else f"{needs.group(1)} needs a value"
                               if needs.group(2).startswith("requires") else f"{needs.group(1)} takes no value")
    # the rest (extra arguments are ours, see _Command): "Missing command." and the like
    field = "command" if ctx is not None and isinstance(ctx.command, TyperGroup) else "arguments"
    return f"{field}: {exc.format_message().rstrip('.')}; {where}"


@contextmanager
def _usage_errors():
    """Print a usage error as ``error: FIELD: why`` on stderr and exit 2 (no usage page, no rich box);
    the help that a bare ``ephem`` prints is left alone."""
    try:
        yield
    except _usage.UsageError as exc:
        if isinstance(exc, getattr(_usage, "NoArgsIsHelpError", ())):
            raise
        typer.echo(f"error: {_usage_message(exc)}", err=True)
        raise typer.Exit(2) from None


# ------------------------------------------------------------------ option values parsed without pydantic

def _number(text: str, kind: type, info) -> int | float:
    try:
        value = kind(text.strip())
    except ValueError:
        raise ValueError(f"must be {'an integer' if kind is int else 'a number'}, got {text!r}") from None
    if kind is float and math.isnan(value):
        raise ValueError(f"must be a number, got {text!r} (NaN is not a number)")
    if kind is float and math.isinf(value):
        raise ValueError(f"must be a finite number, got {text!r}")
    if info.min is not None and value < info.min:
        raise ValueError(f"must be >= {info.min}, got {text!r}")
    if info.max is not None and value > info.max:
        raise ValueError(f"must be <= {info.max}, got {text!r}")
    return value


def _plain_value(annotation, value, info):
    """``value`` (the command line's text, or a default) as ``annotation``; ValueError says why not."""
    if isinstance(annotation, type) and issubclass(annotation, Enum):
        if isinstance(value, annotation):
            return value
        for choice in annotation:
            if (choice.value == value) if info.case_sensitive else (str(choice.value).lower() == str(value).lower()):
                return choice
        raise ValueError(f"must be one of {', '.join(str(c.value) for c in annotation)}, got {value!r}")
    if annotation is str:
        return value if isinstance(value, str) else str(value)
    if annotation is bool:  # a flag's value is already one; text from elsewhere (an envvar) is parsed
        if isinstance(value, bool):
            return value
        word = str(value).strip().lower()
        if word in _BOOL_WORDS:
            return _BOOL_WORDS[word]
        raise ValueError(f"must be true or false, got {value!r}")
    if annotation in (int, float):
        if isinstance(value, str):
            return _number(value, annotation, info)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"must be a number, got {value!r}")
        return annotation(value)
    raise TypeError(annotation)  # pragma: no cover - _plain_values only installs the types above


_BOOL_WORDS = {**dict.fromkeys(("1", "true", "t", "yes", "y", "on"), True),
               **dict.fromkeys(("0", "false", "f", "no", "n", "off", ""), False)}


def _plain_type(annotation, info) -> bool:
    if info.parser is not None or info.clamp:
        return False
    if getattr(annotation, "__origin__", None) is list:
        return len(annotation.__args__) == 1 and _plain_type(annotation.__args__[0], info)
    return annotation in (str, int, float, bool) or (isinstance(annotation, type) and issubclass(annotation, Enum))


if _RuntimeParam is not None:
    @dataclass(frozen=True)
    class _PlainParam(_RuntimeParam):
        """Typer's coercion contract (None and multiple values are handled by the base class), without pydantic."""

        def _coerce_value(self, value: Any, param, ctx) -> Any:
            ann, info = self.annotation, self.parameter_info
            try:
                if getattr(ann, "__origin__", None) is list:
                    items = value if isinstance(value, (list, tuple)) else [value]
                    return [_plain_value(ann.__args__[0], v, info) for v in items]
                return _plain_value(ann, value, info)
            except ValueError as exc:
                raise _UsageFailure(_field(param), str(exc), ctx) from None


def _plain_param(param):
    """Give a str, int, float, bool or Enum (or list of these) parameter the plain parser above instead of
    typer's pydantic adapter: importing pydantic and building the adapters cost more than the answer to
    ``ephem precession BODY``, and the messages are ours (``step_days: must be a number, got 'abc'``;
    NaN and infinity are refused for every float). Other types (paths) keep typer's coercion."""
    desc = getattr(param, "type_descriptor", None)
    if (_RuntimeParam is not None and desc is not None and getattr(param, "_runtime_param", True) is None
            and desc.file_annotation is None and _plain_type(desc.annotation, desc.parameter_info)):
        param._runtime_param = _PlainParam(parameter_info=desc.parameter_info, annotation=desc.annotation)
    return param


def _plain_values(command) -> None:
    """:func:`_plain_param` for every parameter of ``command`` and of its subcommands."""
    for sub in getattr(command, "commands", {}).values():
        _plain_values(sub)
    for param in command.params:
        _plain_param(param)


class _Command(TyperCommand):
    """A command whose extra arguments are a usage error naming them."""

    def get_help_option(self, ctx):  # made on first use, after _plain_values
        option = super().get_help_option(ctx)
        return option if option is None else _plain_param(option)

    def parse_args(self, ctx, args):
        allow = ctx.allow_extra_args
        ctx.allow_extra_args = True
        try:
            rest = super().parse_args(ctx, args)
        except _usage.UsageError as exc:
            exc.ctx = exc.ctx or ctx  # the parser raises some without it: the message needs the command
            raise
        finally:
            ctx.allow_extra_args = allow
        if rest and not allow and not ctx.resilient_parsing:
            raise _UsageFailure("arguments", f"unexpected extra argument{'s' if len(rest) > 1 else ''} "
                                f"{' '.join(map(repr, rest))}; see '{ctx.command_path} --help'", ctx)
        return rest


class _Group(TyperGroup):
    """The command group: usage errors as ``error: FIELD: why`` with status 2, plain option parsing."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        _plain_values(self)

    def get_help_option(self, ctx):  # made on first use, after _plain_values
        option = super().get_help_option(ctx)
        return option if option is None else _plain_param(option)

    def make_context(self, info_name, args, parent=None, **extra):
        with _usage_errors():
            return super().make_context(info_name, args, parent=parent, **extra)

    def invoke(self, ctx):
        with _usage_errors():
            return super().invoke(ctx)

    def resolve_command(self, ctx, args):
        name = args[0] if args else ""
        if name and not name.startswith("-") and self.get_command(ctx, name) is None and not ctx.resilient_parsing:
            known = [n for n, c in self.commands.items() if not c.hidden]
            close = difflib.get_close_matches(name, known)
            raise _UsageFailure("command", f"no such command {name!r}; "
                                + (f"did you mean {' or '.join(close)}?" if close else f"one of {', '.join(known)}"),
                                ctx)
        return super().resolve_command(ctx, args)


class _Typer(typer.Typer):
    """typer.Typer whose commands are :class:`_Command` (the group class is given as ``cls``)."""

    def command(self, name: str | None = None, *, cls=None, **kwargs):
        return super().command(name, cls=cls or _Command, **kwargs)


app = _Typer(cls=_Group, add_completion=False, no_args_is_help=True,
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


def _fail(exc: EphemError) -> None:
    typer.echo(f"error: {exc}", err=True)
    raise typer.Exit(3 if isinstance(exc, NotApplicableError) else 2)


def _rows_to_csv(rows: list[dict]) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buf.getvalue()


def _rows_to_table(rows: list[dict]) -> str:
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


def _emit(answer, fmt: Format, rows: list[dict] | None = None) -> None:
    if fmt is Format.json:
        sys.stdout.write(json.dumps(answer, indent=2, allow_nan=False, default=_jsonable) + "\n")
        return
    rows = rows if rows is not None else [answer]
    sys.stdout.write(_rows_to_csv(rows) if fmt is Format.csv else _rows_to_table(rows))


def _flat(answer: dict) -> dict:
    return {k: v for k, v in answer.items() if not isinstance(v, (dict, list))}


@app.command()
def bodies(dataset: str = DatasetOpt, fmt: Format = FormatOpt):
    """List the catalogue's bodies."""
    from .answers import requests as api

    try:
        rows = api.list_bodies(dataset)
    except EphemError as exc:
        _fail(exc)
    _emit(rows, fmt, rows)


#: the columns of ``ephem body``'s CSV (every scalar of a value) and table (what fits a terminal's line: the
#: reasons for a missing sigma and the notes are sentences)
BODY_CSV_COLUMNS = ("quantity", "value", "unit", "uncertainty", "no_uncertainty", "source", "note")
BODY_TABLE_COLUMNS = ("quantity", "value", "unit", "uncertainty", "source")


@app.command()
def body(name: str = typer.Argument(..., metavar="BODY"), dataset: str = DatasetOpt, fmt: Format = FormatOpt):
    """Full catalogue record of BODY (name or NAIF id): values, units, uncertainties, sources.

    JSON (the default) is the whole record. CSV and table give one row per value (CSV: quantity, value, unit,
    uncertainty, no_uncertainty, source, note; the table leaves out the reasons and notes); the body's identity,
    H_d and the correlations of the values' errors then go to stderr.
    """
    from .answers import requests as api

    try:
        record = api.body_record(name, dataset)
    except EphemError as exc:
        _fail(exc)
    if fmt is Format.json:
        _emit(record, fmt)
        return
    corr = "; ".join(f"{a} ~ {b}: {c['value']:.4g}" for c in record["correlations"] for a, b in [c["inputs"]])
    typer.echo(f"{record['name']} (NAIF {record['naif_id']}, {record['kind']}), dataset {record['dataset']}: H_d "
               f"{record['dynamical_ellipticity']:.10g} from {record['dynamical_ellipticity_from']}, perturbers "
               f"{', '.join(record['perturbers'])}" + (f"; correlations {corr}" if corr else ""), err=True)
    columns = BODY_CSV_COLUMNS if fmt is Format.csv else BODY_TABLE_COLUMNS
    rows = [{c: key if c == "quantity" else value[c] for c in columns} for key, value in record["values"].items()]
    _emit(record, fmt, rows)


@app.command()
def precession(name: str = typer.Argument(..., metavar="BODY"), dataset: str = DatasetOpt,
               fmt: Format = FormatOpt, order: Optional[int] = OrderOpt,
               tolerance_mas: Optional[float] = ToleranceOpt,
               perturbers: Optional[str] = typer.Option(None, "--perturbers", help="The torquing bodies, comma-separated: default the "
                                          "catalogue's (the Earth: moon,sun, the lunisolar theory); sun for the "
                                          "single-perturber answer.")):
    """Obliquity, dynamical ellipticity, scaling factor K and precession rate of BODY."""
    from .answers import requests as api

    try:
        ans = api.precession(name, dataset, order, tolerance_mas, perturbers=perturbers)
    except EphemError as exc:
        _fail(exc)
    _emit(ans, fmt, [_flat(ans)])


@app.command()
def nutation(name: str = typer.Argument(..., metavar="BODY"), dataset: str = DatasetOpt,
             fmt: Format = FormatOpt, order: Optional[int] = OrderOpt,
             tolerance_mas: Optional[float] = ToleranceOpt,
             perturbers: Optional[str] = typer.Option(None, "--perturbers", help="The torquing bodies, comma-separated: default the "
                                          "catalogue's (the Earth: moon,sun, the lunisolar theory); sun for the "
                                          "single-perturber answer."),
             cut_mas: Optional[float] = typer.Option(None, "--cut-mas", help="The lunisolar series (the Earth "
                                                     "with the Moon): keep the terms whose amplitude reaches this "
                                                     "many mas (default 0.1).")):
    """Nutation series of BODY in longitude and obliquity (harmonics of the mean anomaly; for the Earth with
    the Moon, integer combinations of the Delaunay arguments l, l', F, D, Omega)."""
    from .answers import requests as api
    from .exports.tables import DELAUNAY_COLUMNS

    try:
        ans = api.nutation(name, dataset, order, tolerance_mas, perturbers=perturbers, cut_mas=cut_mas)
    except EphemError as exc:
        _fail(exc)
    rows = []
    for term in ans["terms"]:       # the Delaunay multipliers as five columns in CSV and tables
        row = {k: v for k, v in term.items() if k != "delaunay_multipliers"}
        if term.get("delaunay_multipliers") is not None:
            row = {"multiple": None, **dict(zip(DELAUNAY_COLUMNS, term["delaunay_multipliers"])), **row}
        rows.append(row)
    _emit(ans, fmt, rows)


@app.command()
def track(name: str = typer.Argument(..., metavar="BODY"),
          start: str = typer.Option(..., "--start", help="ISO 8601 (UTC unless a scale follows) or JD TDB."),
          stop: str = typer.Option(..., "--stop", help="ISO 8601 or JD TDB."),
          step_days: float = typer.Option(..., "--step-days", help="Sampling step in days."),
          dataset: str = DatasetOpt, fmt: Format = FormatOpt, order: Optional[int] = OrderOpt,
          tolerance_mas: Optional[float] = ToleranceOpt,
          model: Optional[str] = typer.Option(None, "--model", help="A rung of the fidelity ladder: "
                                              "secular, series, hansen, second_order, numerical, real_orbit; "
                                              "lunisolar for the Earth with the Moon (its default)."),
          axis: str = typer.Option("figure", "--axis", help="The pole to follow: figure (the axis of largest "
                                   "inertia, which circles the angular momentum by the free wobble) or "
                                   "angular_momentum."),
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
                                          "single-perturber answer.")):
    """Spin-axis track of BODY: ψ, Δψ, Δε, obliquity and pole RA/Dec over time.

    The model used (rung, order, estimated error, cost) goes to stderr with --format csv or table.
    """
    from .answers import requests as api

    try:
        ans = api.track(name, start, stop, step_days, dataset, order, tolerance_mas=tolerance_mas, model=model,
                        axis=axis, free_wobble_phase_deg=wobble_phase, free_wobble_J_arcsec=wobble_j,
                        free_wobble_epoch=wobble_epoch, perturbers=perturbers, rotation_phase_deg=rotation_phase)
    except EphemError as exc:
        _fail(exc)
    if fmt is not Format.json:
        info = ans["model"]
        err = info["estimated_error_mas"]
        typer.echo(f"model: {info['name']}" + (f" (order {info['order']})" if info["order"] is not None else "")
                   + (f", estimated error {err:.4g} mas" if err is not None else "")
                   + (", with the free wobble" if info["free_wobble"] else "")
                   + (f", with the rotation-scale terms ({info['rotation_scale']['modelled']})"
                      if info["rotation_scale"] else "")
                   + f", {info['cost_ms']:.1f} ms", err=True)
    keys = ["jd_tdb", "psi_arcsec", "delta_psi_arcsec", "delta_epsilon_arcsec", "obliquity_deg",
            "pole_ra_deg", "pole_dec_deg"]
    rows = [dict(zip(keys, vals)) for vals in zip(*(ans[k] for k in keys))]
    if not rows:
        rows = [dict.fromkeys(keys, "")]
    _emit(ans, fmt, rows)


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

    The model (orbit, estimate, where the history stops meaning anything, cost) goes to stderr with --format csv
    or table. A progress bar shows on stderr while the spin is integrated (not with --quiet).
    """
    from .answers import requests as api

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
            ans = api.history(name, start_year, stop_year, step_years, dataset, tolerance_mas, orbit_model,
                              perturbers, progress=progress)
        finally:
            if bar is not None:
                bar.__exit__(None, None, None)
    except EphemError as exc:
        _fail(exc)
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
    _emit(ans, fmt, rows)


@app.command("free-motion")
def free_motion(name: str = typer.Argument(..., metavar="BODY"),
                start: str = typer.Option(..., "--start", help="ISO 8601 (UTC unless a scale follows) or JD TDB."),
                stop: str = typer.Option(..., "--stop", help="ISO 8601 or JD TDB."),
                step_days: float = typer.Option(..., "--step-days", help="Sampling step in days."),
                j_arcsec: Optional[float] = typer.Option(None, "--J-arcsec", help="Wobble amplitude J at start "
                                                         "(default: the published one, Lara 2014 Table 1)."),
                method: str = typer.Option("auto", "--method", help="auto, exact, series or numeric."),
                dataset: str = DatasetOpt, fmt: Format = FormatOpt):
    """Torque-free wobble of BODY: the figure axis about the angular momentum, and its periods."""
    from .answers import requests as api

    try:
        ans = api.free_motion_answer(name, start, stop, step_days, j_arcsec, method, dataset)
    except EphemError as exc:
        _fail(exc)
    rows = [dict(zip(api.FREE_MOTION_KEYS, vals)) for vals in zip(*(ans[k] for k in api.FREE_MOTION_KEYS))]
    if fmt is not Format.json:
        typer.echo(f"{ans['mode']} mode, method {ans['method']}: wobble period {ans['wobble_period_days']:.6g} d, "
                   f"precession period {ans['precession_period_days']:.6g} d", err=True)
    _emit(ans, fmt, rows or [dict.fromkeys(api.FREE_MOTION_KEYS, "")])


# ephem.exports.tables' own lists (a light module: csv, io, json, math), as choices the option parser checks before any
# body is computed and that `--help` and the tests read
TableFormat = Enum("TableFormat", [(f, f) for f in _tables.FORMATS], type=str)
TableLayout = Enum("TableLayout", [(x, x) for x in _tables.LAYOUTS], type=str)


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
    from .answers import requests as api
    from .exports.tables import write_tables

    try:
        bodies = names or [b["name"] for b in api.list_bodies(dataset)]
        answers, skipped = [], []
        with typer.progressbar(bodies, label="tables", item_show_func=lambda b: b or "", file=sys.stderr) as bar:
            for name in bar:
                try:
                    answers.append(api.nutation(name, dataset, order))
                except NotApplicableError as exc:
                    skipped.append(str(exc))
        written = write_tables(answers, out, [f.value for f in formats], [x.value for x in layouts])
    except EphemError as exc:
        _fail(exc)
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
    from .exports import plots

    fmt = out.suffix.lower().lstrip(".")
    try:
        if fmt not in plots.CONTENT_TYPES:
            from .base.errors import InvalidInputError

            raise InvalidInputError("out", f"the file must end in .png or .svg, got {out.name!r}")
        image = plots.render(kind, name, start, stop, step_days, fmt, dataset, dpi=dpi, tolerance_mas=tolerance_mas,
                             model=model, order=order, J_arcsec=j_arcsec, step_years=step_years,
                             orbit_model=orbit_model)
    except EphemError as exc:
        _fail(exc)
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
    from .exports.pck import write_pck_file

    try:
        result = write_pck_file(out, names, start, stop, dataset=dataset, tolerance_mas=tolerance_mas, model=model,
                                max_angles=max_angles)
    except EphemError as exc:
        _fail(exc)
    for f in result.bodies:
        est = f.model.get("estimated_error_mas")
        typer.echo(f"{f.name}: fitting error {f.fit_error_mas:.4g} mas with {len(f.angles)} angles (model "
                   f"{f.model['name']}" + (f", estimated {est:.4g} mas" if est is not None else "") + ")")
    typer.echo(f"wrote {out}")


class BatchFormat(str, Enum):
    parquet = "parquet"
    csv = "csv"


@app.command()
def batch(input_path: str = typer.Argument(..., metavar="INPUT", help="The bodies: a CSV or Parquet file, one row "
                                           "per body (columns: docs/batch_input.md)."),
          out: Path = typer.Option(..., "--out", help="Output directory: part-NNNNN.parquet|csv, one per partition "
                                   "(a rerun resumes in it)."),
          scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Address of a running dask scheduler, "
                                                  "tcp://HOST:PORT (default: a local cluster on 127.0.0.1)."),
          workers: Optional[int] = typer.Option(None, "--workers", min=1, help="Local worker processes (default: "
                                                "the cores); with --scheduler, wait for this many workers."),
          partition_rows: int = typer.Option(50_000, "--partition-rows", min=1, help="Bodies per partition (one "
                                             "task; bounds a worker's memory)."),
          fmt: BatchFormat = typer.Option(BatchFormat.parquet, "--format", help="Output format."),
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
    from .base.errors import InvalidInputError

    years = {"start_year": start_year, "stop_year": stop_year, "step_years": step_years}
    try:
        if history and None in years.values():
            missing = next(k for k, v in years.items() if v is None)
            raise InvalidInputError(missing, f"missing; give --{missing.replace('_', '-')} with --history")
        if not history and any(v is not None for v in years.values()):
            given = next(k for k, v in years.items() if v is not None)
            raise InvalidInputError(given, "only with --history")
    except EphemError as exc:
        _fail(exc)
    from .batch import distributed as engine

    spec = None
    if history:
        from .batch.population import HistorySpec

        spec = HistorySpec(start_year, stop_year, step_years)
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
            result = engine.run(input_path, out, scheduler=scheduler, workers=workers, partition_rows=partition_rows,
                                output_format=fmt.value, history=spec, progress=progress, fresh=fresh, log=note)
        finally:
            if bar[0] is not None:
                bar[0].__exit__(None, None, None)
    except engine.BatchFailed as exc:
        failed, result = exc, exc.result
    except EphemError as exc:
        _fail(exc)
    rate = f", {result.rows_computed / result.seconds:.4g} bodies/s" if result.rows_computed else ""
    resumed = f", {result.partitions_skipped} resumed" if result.partitions_skipped else ""
    typer.echo(f"{result.rows} rows ({result.rows_failed} failed) in {result.partitions} partitions{resumed} to "
               f"{result.out_path}/, {result.seconds:.1f} s{rate}")
    if failed is not None:
        typer.echo(f"error: {failed}", err=True)
        raise typer.Exit(1)


#: the columns of the demo's nutation table: the paper's (Petit et al. Tables 5-8) and the amplitudes; the sigmas,
#: ~1e-5 arcsec, would print as 0 at its four decimals (``ephem nutation BODY --format table`` gives them)
DEMO_NUTATION_COLUMNS = ("multiple", "period_days", "period_years", "longitude_sin_arcsec", "longitude_cos_arcsec",
                         "obliquity_sin_arcsec", "obliquity_cos_arcsec", "longitude_amplitude_arcsec",
                         "obliquity_amplitude_arcsec")


@app.command()
def demo(dataset: str = DatasetOpt):
    """A short tour: precession of every body of the dataset (the Moon: its Cassini state), and Vesta's
    nutation (in a dataset without Vesta, its first body whose series is in harmonics of the mean anomaly)."""
    from .answers import requests as api

    try:
        bodies = [b["name"] for b in api.list_bodies(dataset)]
    except EphemError as exc:
        _fail(exc)
    typer.echo(f"Precession rates ({dataset} dataset)")
    rows = []
    for name in bodies:
        try:
            p = api.precession(name, dataset)
            rows.append({"body": name, "obliquity_deg": round(p["obliquity_deg"], 4),
                         "H_d": round(p["dynamical_ellipticity"], 6),
                         "K_arcsec_per_yr": round(p["scaling_factor_arcsec_per_year"], 4),
                         "psi_dot_arcsec_per_yr": round(p["precession_rate_arcsec_per_year"], 4)})
        except NotApplicableError as exc:
            rows.append({"body": name, "obliquity_deg": "-", "H_d": "-", "K_arcsec_per_yr": "-",
                         "psi_dot_arcsec_per_yr": f"not applicable ({exc.reason})"})
        except EphemError as exc:       # a user's dataset: a body the catalogue took but an answer refuses
            rows.append({"body": name, "obliquity_deg": "-", "H_d": "-", "K_arcsec_per_yr": "-",
                         "psi_dot_arcsec_per_yr": f"error ({exc})"})
    typer.echo(_rows_to_table(rows))
    # Vesta's, as the paper's; a user's dataset may not hold it. The Earth's and the Moon's series are in the
    # Delaunay arguments, not in harmonics of the mean anomaly: not what the title says.
    for name in sorted(bodies, key=lambda n: n.lower() != "vesta"):
        try:
            terms = api.nutation(name, dataset)["terms"][:6]
        except EphemError:              # its row above says why
            continue
        if terms and all(t.get("multiple") is not None for t in terms):
            break
    else:
        typer.echo("No body of this dataset has a nutation series in harmonics of the mean anomaly.")
        return
    typer.echo(f"Nutation of {name} (arcsec), harmonics of the mean anomaly")
    typer.echo(_rows_to_table([{k: (round(t[k], 4) if isinstance(t[k], float) else t[k]) for k in DEMO_NUTATION_COLUMNS}
                               for t in terms]))


# ------------------------------------------------------------------ ephem catalogue import

catalogue_app = _Typer(cls=_Group, no_args_is_help=True,
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
    from .bodies.importer import import_catalogue

    try:
        result = import_catalogue(orbits, poles, name, orbit_format.value if orbit_format else None,
                                  skip_unmatched=skip_unmatched, force=force)
    except EphemError as exc:
        _fail(exc)
    for skipped in result.skipped:
        typer.echo(f"note: skipped {skipped}", err=True)
    names = result.catalogue.names
    typer.echo(f"{'replaced' if result.replaced else 'wrote'} {result.path}: dataset {name!r}, {len(names)} "
               f"bod{'y' if len(names) == 1 else 'ies'} ({', '.join(names)}); select it with --dataset {name}")


def main() -> None:  # pragma: no cover
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
