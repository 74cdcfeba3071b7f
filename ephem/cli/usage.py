"""The CLI's option parsing: usage errors, and option values parsed without typer's pydantic adapters.

Usage errors as ``error: FIELD: why`` with exit status 2; option values are parsed
here rather than by typer's pydantic adapters (building those costs more than a one-body answer).

:class:`UsageTyper` and :class:`UsageGroup` are the typer app and group every command of :mod:`ephem.cli` is
registered on.
"""
from __future__ import annotations

import difflib
import math
import re
from contextlib import contextmanager
from dataclasses import dataclass
from enum import Enum
from typing import Any

import typer
from typer.core import TyperCommand, TyperGroup

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


#: what ``{name}`` in an option's help stands for: a function called when the help is shown (a command module adds
#: its own: ``--model``'s names are the families' registry's, read then, so that no other command loads the library)
HELP_VALUES: dict = {}


class _Command(TyperCommand):
    """A command whose extra arguments are a usage error naming them, and whose options' help may hold a
    ``{name}`` of :data:`HELP_VALUES`, filled when the help is shown."""

    def format_help(self, ctx, formatter):
        for param in self.params:
            template = getattr(param, "help_template", None) or getattr(param, "help", None) or ""
            names = [n for n in HELP_VALUES if "{" + n + "}" in template]
            if names:
                param.help_template = template
                for n in names:
                    template = template.replace("{" + n + "}", HELP_VALUES[n]())
                param.help = template
        return super().format_help(ctx, formatter)

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


class UsageGroup(TyperGroup):
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


class UsageTyper(typer.Typer):
    """typer.Typer whose commands are :class:`_Command` (the group class is given as ``cls``)."""

    def command(self, name: str | None = None, *, cls=None, **kwargs):
        return super().command(name, cls=cls or _Command, **kwargs)
