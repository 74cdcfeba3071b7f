"""What the CLI's option parser refuses reads like the library's errors: ``error: FIELD: why`` on stderr,
exit status 2, the field named as ephem.api and the service name it, no usage page, no rich box, no
traceback; and NaN or infinity is refused for every float option, as not a number."""
import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.cli import app
from ephem.errors import InvalidInputError

runner = CliRunner()
SPAN = ["--start", "2020-01-01", "--stop", "2021-01-01"]
TRACK = ["track", "vesta", *SPAN]


def refused(args: list[str], field: str) -> str:
    res = runner.invoke(app, args)
    assert res.exit_code == 2, res.output
    assert res.stdout == ""
    err = res.stderr
    assert err.startswith(f"error: {field}: "), err
    assert len(err.strip().splitlines()) == 1, err                     # one line: no usage page
    assert not set("╭│╰─") & set(err), err                            # no rich box
    assert "Traceback" not in err and "Usage:" not in err, err
    return err


@pytest.mark.parametrize("args, field, words", [
    ([*TRACK, "--step-days", "abc"], "step_days", "must be a number, got 'abc'"),
    (["precession", "vesta", "--format", "xml"], "format", "must be one of json, csv, table, got 'xml'"),
    (["nutation", "vesta", "--order", "-1"], "order", "integer in [0, 30]"),           # ephem.api's own check
    (["precession", "vesta", "--order", "1.5"], "order", "must be an integer, got '1.5'"),
    (["precession", "vesta", "--tolerance-mas", "-5"], "tolerance_mas", "positive finite number"),
    (["precession", "vesta", "--tolerance-mas", "0"], "tolerance_mas", "positive finite number"),
    (["pck", "vesta", *SPAN, "--out", "x.tpc", "--max-angles", "many"], "max_angles", "must be an integer"),
    (TRACK, "step_days", "missing; give --step-days"),
    (["track", "vesta", "--stop", "2021-01-01", "--step-days", "1"], "start", "missing; give --start"),
    (["precession"], "body", "missing; give BODY"),
    (["body"], "body", "missing"),
    (["track", "vesta", "--step-days", "1", "--start"], "start", "--start needs a value"),
    (["precession", "vesta", "--help=yes"], "--help", "--help takes no value"),
])
def test_parser_errors_name_the_field(args, field, words):
    assert words in refused(args, field)


@pytest.mark.parametrize("args, field, words", [
    (["precession", "vesta", "--frob"], "--frob", "no such option"),
    (["precession", "vesta", "--tolerence-mas", "3"], "--tolerence-mas", "did you mean --tolerance-mas?"),
    (["frobnicate"], "command", "no such command 'frobnicate'; one of bodies, body, precession"),
    (["precesion", "vesta"], "command", "did you mean precession"),
    (["fortune", "accuracy"], "command", "no such command 'fortune'; one of bodies, body, precession"),
    (["precession", "vesta", "ceres"], "arguments", "unexpected extra argument 'ceres'"),
])
def test_unknown_options_commands_and_extra_arguments(args, field, words):
    assert words in refused(args, field)


FLOAT_OPTIONS = [  # every float option of every command
    (TRACK, "--step-days", "step_days"),
    (["free-motion", "mars", *SPAN], "--step-days", "step_days"),
    (["plot", "vesta", *SPAN, "--out", "x.png"], "--step-days", "step_days"),
    (["precession", "vesta"], "--tolerance-mas", "tolerance_mas"),
    (["nutation", "vesta"], "--tolerance-mas", "tolerance_mas"),
    ([*TRACK, "--step-days", "30"], "--tolerance-mas", "tolerance_mas"),
    (["plot", "vesta", *SPAN, "--out", "x.png"], "--tolerance-mas", "tolerance_mas"),
    (["pck", "vesta", *SPAN, "--out", "x.tpc"], "--tolerance-mas", "tolerance_mas"),
    (["nutation", "earth"], "--cut-mas", "cut_mas"),
    ([*TRACK, "--step-days", "30"], "--free-wobble-phase-deg", "free_wobble_phase_deg"),
    ([*TRACK, "--step-days", "30"], "--free-wobble-J-arcsec", "free_wobble_J_arcsec"),
    (["free-motion", "mars", *SPAN, "--step-days", "30"], "--J-arcsec", "J_arcsec"),
    (["plot", "vesta", *SPAN, "--out", "x.png"], "--J-arcsec", "J_arcsec"),
    (["plot", "vesta", *SPAN, "--out", "x.png"], "--dpi", "dpi"),
]


@pytest.mark.parametrize("args, option, field", FLOAT_OPTIONS, ids=[f"{a[0]}{o}" for a, o, _ in FLOAT_OPTIONS])
@pytest.mark.parametrize("text", ["nan", "NaN", "inf", "-inf", "1e400"])
def test_nan_and_infinity_are_not_numbers_for_every_float_option(args, option, field, text, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)                      # nothing may be written, but if it were: here
    err = refused([*args, option, text], field)
    if text.lower() == "nan":
        assert f"got '{text}' (NaN is not a number)" in err
    else:
        assert f"must be a finite number, got '{text}'" in err
    assert "range" not in err
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("call, args, field", [
    (lambda: api.track("vesta", "2020-01-01", "2021-01-01", float("nan")), [*TRACK, "--step-days", "nan"], "step_days"),
    (lambda: api.precession("vesta", tolerance_mas=-5.0), ["precession", "vesta", "--tolerance-mas", "-5"],
     "tolerance_mas"),
])
def test_the_field_names_are_the_apis(call, args, field):
    # the name the CLI gives an input is the one ephem.api (and so the service) gives it
    with pytest.raises(InvalidInputError) as info:
        call()
    assert info.value.field == field
    refused(args, field)


def test_help_is_unchanged():
    res = runner.invoke(app, ["--help"])
    assert res.exit_code == 0 and "Usage" in res.stdout and "precession" in res.stdout
    res = runner.invoke(app, ["track", "--help"])
    assert res.exit_code == 0 and "--step-days" in res.stdout and "--tolerance-mas" in res.stdout
    res = runner.invoke(app, [])                                        # a bare `ephem` shows the help
    assert "Usage" in res.output and "error:" not in res.output


def test_good_values_still_parse():
    res = runner.invoke(app, [*TRACK, "--step-days", " 120 ", "--format", "csv", "--order", "+4", "--model", "series"])
    assert res.exit_code == 0, res.output
    assert res.stdout.splitlines()[0].startswith("jd_tdb,") and len(res.stdout.splitlines()) == 5
