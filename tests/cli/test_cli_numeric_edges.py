"""Every CLI command at the numeric edges of its options (issue 42): exit 0 with finite numbers, or the refusal naming
the option (``error: FIELD: why``, exit 2; 3 where the theory does not apply); never a traceback, never NaN.

As tests/service/test_numeric_edges.py does for the routes, and generated likewise from the CLI itself (the typer
command tree, as tests/cli/test_cli_matrix.py reads it): each command with a number or a time among its options
has a minimal valid command line in :data:`BASELINES` (a command without one is listed in :data:`NO_NUMERIC_INPUT`),
and each float or integer option takes 0, -0, ±5e-324, 1e-300 and ±1e308 in turn; the time options of a track take
the spans of the service's test (start = stop, one double apart, the issue's sub-resolution step), the histories its
spans within a breath of J2000. The values are picked, not drawn, and the whole file runs in seconds.
"""
from __future__ import annotations

import math
import re

import pytest
import typer
from typer.testing import CliRunner

from ephem.cli import app

runner = CliRunner()
J2000, ULP = 2451545.0, 2.0 ** -31

BASELINES = {
    "precession": ["precession", "vesta"],
    "nutation": ["nutation", "vesta"],
    "track": ["track", "ceres", "--start", "2020-01-01", "--stop", "2020-03-01", "--step-days", "30"],
    "history": ["history", "vesta", "--start-year", "-400", "--stop-year", "0", "--step-years", "200", "--quiet"],
    "free-motion": ["free-motion", "vesta", "--start", "2020-01-01", "--stop", "2020-01-03", "--step-days", "0.5",
                    "--J-arcsec", "10"],
    "tables": ["tables", "vesta", "--format", "csv", "--out", "{tmp}"],
    "plot": ["plot", "vesta", "--start", "2020-01-01", "--stop", "2020-03-01", "--out", "{tmp}/p.svg"],
    "pck": ["pck", "vesta", "--start", "2020-01-01", "--stop", "2021-01-01", "--out", "{tmp}/v.tpc"],
}
#: commands with no number or time among their options, or whose numbers are tested elsewhere, and why
NO_NUMERIC_INPUT = {"bodies": "the list", "body": "a record", "demo": "no input", "catalogue import": "files",
                    "batch": "its numbers are the rows' (tests/batch) and the history's, which POST /v1/batch and "
                             "tests/service/test_numeric_edges.py take through the same ephem.api.batch"}
COMMON = ("0", "-0.0", "5e-324", "-5e-324", "1e-300", "1e+308", "-1e+308")
SPANS = {"track": [["--start", "JD2451545", "--stop", "JD2451545"],
                   ["--start", "JD2451545", "--stop", f"JD{J2000 + ULP!r}", "--step-days", repr(ULP)],
                   ["--start", "JD2451545", "--stop", "JD2451545.000000001", "--step-days", "1e-12"],
                   ["--start", "JD2451545", "--stop", f"JD{J2000 - ULP!r}"],
                   ["--start", "2000-01-01T12:00:00 TDB", "--stop", "2000-01-01T12:00:00 TDB"]],
         "history": [["--start-year", "-5e-324", "--stop-year", "4.2e-90", "--step-years", "500"],
                     ["--start-year", "0", "--stop-year", "1e-322", "--step-years", "5e-324"],
                     ["--start-year", "0", "--stop-year", "0", "--step-years", "1"],
                     ["--start-year", "1000", "--stop-year", "1000.0000000001", "--step-years", "1e-14"]],
         "plot": [["--start", "JD2451545", "--stop", f"JD{J2000 + 10 * ULP!r}"],
                  ["--start", "JD2451545", "--stop", f"JD{J2000 + ULP!r}"]],
         "pck": [["--start", "JD2451545", "--stop", f"JD{J2000 + 1000 * ULP!r}"]]}


def commands() -> dict[str, object]:
    found = {}

    def walk(command, path):
        subs = getattr(command, "commands", None)
        if subs:
            for name, sub in subs.items():
                walk(sub, (*path, name))
        else:
            found[" ".join(path)] = command
    walk(typer.main.get_command(app), ())
    return found


def numeric_options(command) -> list[str]:
    """The command's float and integer options (``--step-days``)."""
    out = []
    for p in command.params:
        annotation = getattr(getattr(p, "type_descriptor", None), "annotation", None)
        if annotation in (float, int) and getattr(p, "opts", None):
            out.append(p.opts[0])
    return out


def test_every_command_with_numeric_options_has_a_baseline():
    tree = commands()
    missing = [name for name, c in tree.items()
               if numeric_options(c) and name not in BASELINES and name not in NO_NUMERIC_INPUT]
    assert not missing, f"commands with no numeric-edge baseline: {missing}"
    assert set(BASELINES) <= set(tree)


def _with(args: list[str], option: str, value: str) -> list[str]:
    args = list(args)
    if option in args:
        args[args.index(option) + 1] = value
    else:
        args += [option, value]
    return args


def _cases() -> list[tuple[str, list[str]]]:
    tree, out, seen = commands(), [], set()
    for name, base in BASELINES.items():
        changes = [[(o, v)] for o in numeric_options(tree[name]) for v in COMMON]
        changes += [list(zip(s[::2], s[1::2])) for s in SPANS.get(name, [])]
        for change in changes:
            args = base
            for option, value in change:
                args = _with(args, option, value)
            key = tuple(args)
            if key not in seen:
                seen.add(key)
                out.append((" ".join(f"{o}={v}" for o, v in change), args))
    return out


CASES = _cases()
NON_FINITE = re.compile(r"(?i)(?<![\w.])[-+]?(nan|inf|infinity)(?![\w])")


@pytest.mark.parametrize("args", [a for _, a in CASES], ids=[f"{a[0]} {i}" for i, a in CASES])
def test_cli_numeric_edge(args, tmp_path):
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    res = runner.invoke(app, args)
    assert "Traceback" not in res.output and res.exception is None or isinstance(res.exception, SystemExit), \
        (args, res.output[-800:], res.exception)
    assert res.exit_code in (0, 2, 3), (args, res.exit_code, res.output[-800:])
    if res.exit_code == 2:
        m = re.match(r"error: (?:[^:\n]+: )?([\w.\[\]]+): ", res.stderr)      # "error: Vesta: cut_mas: why"
        assert m, (args, res.stderr)
        field = m.group(1).split(".")[-1].split("[")[0]
        options = {a.lstrip("-").replace("-", "_").lower() for a in args if a.startswith("--")}
        assert field.lower() in options | {"start", "stop", "step_days", "step_years", "start_year", "stop_year",
                                           "j_arcsec", "free_wobble_j_arcsec", "kind"}, (args, res.stderr)
    if res.exit_code == 0:
        assert not NON_FINITE.search(res.stdout), (args, NON_FINITE.search(res.stdout))
        for path in tmp_path.iterdir():
            if path.suffix in (".svg", ".csv", ".tpc", ".md", ".tex", ".json"):
                text = path.read_text(errors="replace")
                text = re.sub(r"(?s)<style\b.*?</style>", " ", text)
                assert not NON_FINITE.search(re.sub(r"<[^>]+>", " ", text)), (args, path.name)


def test_the_cases_are_few_and_reach_every_numeric_option():
    tree = commands()
    for name in BASELINES:
        moved = {a for label, args in CASES if args[0] == name.split()[0] for a in re.findall(r"--[\w-]+", label)}
        assert set(numeric_options(tree[name])) <= moved, name
    assert len(CASES) < 400 and not math.isnan(len(CASES))
