"""What the CLI's option parser refuses reads like the library's errors: ``error: FIELD: why`` on stderr,
exit status 2, the field named as ephem.api and the service name it, no usage page, no rich box, no
traceback; and NaN or infinity is refused for every float option, as not a number."""
import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.cli import app
from ephem.base.errors import InvalidInputError

runner = CliRunner()
SPAN = ["--start", "2020-01-01", "--stop", "2021-01-01"]
TRACK = ["track", "vesta", *SPAN]
HISTORY = ["history", "ceres", "--start-year", "-2000", "--stop-year", "0", "--step-years", "1000"]
BATCH = ["batch", "bodies.csv", "--out", "out", "--history", "--start-year", "-1000", "--stop-year", "0",
         "--step-years", "100"]


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
    (["precession", "vesta", "--format", "xml"], "format", "must be one of json, csv, table, ecsv, got 'xml'"),
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
    ([*TRACK, "--step-days", "30"], "--rotation-phase-deg", "rotation_phase_deg"),
    (HISTORY, "--start-year", "start_year"),
    (HISTORY, "--stop-year", "stop_year"),
    (HISTORY, "--step-years", "step_years"),
    (HISTORY, "--tolerance-mas", "tolerance_mas"),
    (["plot", "ceres", "--kind", "obliquity-history", "--start", "-2000", "--stop", "0", "--out", "x.png"],
     "--step-years", "step_years"),
    (BATCH, "--start-year", "start_year"),
    (BATCH, "--stop-year", "stop_year"),
    (BATCH, "--step-years", "step_years"),
]


def _float_options() -> set[tuple[str, str]]:
    """(command, option) of every float option of the CLI, read from its command tree."""
    from typing import get_args

    import typer

    def walk(command, path):
        for name, sub in getattr(command, "commands", {}).items():
            yield from walk(sub, (*path, name))
        for param in command.params:
            annotation = param.type_descriptor.annotation
            if param.param_type_name == "option" and (annotation is float or float in get_args(annotation)):
                yield " ".join(path), max(param.opts, key=len)
    return set(walk(typer.main.get_command(app), ()))


def test_the_float_options_listed_are_every_float_option():
    # a new float option must join FLOAT_OPTIONS (its NaN and infinity refused), so the list is checked whole
    listed = {(args[0] if args[0] != "catalogue" else " ".join(args[:2]), option) for args, option, _ in FLOAT_OPTIONS}
    assert listed == _float_options()


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


# ------------------------------------------------------------------ messages a user met (issue 29)

def test_a_count_over_the_cap_is_the_integer_count():
    # 100 077.3 days at 1 d/sample are 100 078 samples; the message said "1e+05 samples exceed the cap of 100000"
    jd = 2451545.0
    for stop, step, count in [(jd + 100077.3, 1.0, "100078"), (jd + 1e6, 1e-12, "about 1e+18"),
                              (jd + 10.0, 5e-324, "more than 1e+308")]:      # the count overflows to inf
        with pytest.raises(InvalidInputError) as info:
            api.epoch_grid(jd, stop, step, max_samples=100_000)
        assert info.value.field == "step_days"
        assert info.value.reason.startswith(f"{count} samples exceed the cap of 100000; "), info.value.reason
    # a part step past the last sample is not a sample: 99 999.5 days at 1 d are 100 000 samples, within the cap
    assert api.epoch_grid(jd, jd + 99999.5, 1.0, max_samples=100_000)[2] == 100_000
    # the CLI's cap (10^6) through the option parser and the library
    err = refused(["track", "vesta", "--start", "2451545", "--stop", "3451545.4", "--step-days", "1"], "step_days")
    assert "1000001 samples exceed the cap of 1000000" in err


def test_a_plot_over_the_cap_of_epochs_says_how_many():
    from ephem.answers import figures as plots

    cap = plots.MAX_PLOT_POINTS
    err = refused(["plot", "ceres", "--kind", "obliquity-history", "--start", "-2000", "--stop", "0",
                   "--step-years", "0.01", "--out", "x.png"], "step_years")
    assert f"200001 epochs exceed the cap of {cap}" in err
    with pytest.raises(InvalidInputError, match=r"^step_years: more than 1e\+308 epochs exceed"):
        plots._check_step_years(5e-324, -2000.0, 0.0)
    # a part step past the cap's last epoch is within the cap, here and in the history's own grid
    from ephem.longterm.history import history_grid

    step = 2000.0 / (cap - 0.5)
    assert plots._check_step_years(step, -2000.0, 0.0) == step
    assert len(history_grid(-2000.0, 0.0, step, cap)) == cap


@pytest.mark.parametrize("body, theory", [("earth", "the Earth's lunisolar theory"),
                                          ("moon", "the Cassini-state theory")])
def test_a_theory_is_named_once(body, theory):
    # the theory's summary already starts with "the": the message read "the the Earth's lunisolar theory"
    err = refused(["track", body, *SPAN, "--step-days", "30", "--rotation-phase-deg", "10"],
                  f"{body.capitalize()}: rotation_phase_deg")
    assert f"rotation_phase_deg: {theory}" in err and "does not model the rotation scale" in err
    assert "the the" not in err


def test_every_theory_summary_reads_after_a_verb():
    # the summaries are put into messages as they are ("is served by {summary}"): each carries its article
    from ephem.families import THEORIES

    for family in THEORIES:
        assert family.summary.startswith("the ") and not family.summary.startswith("the the "), family


def test_demo_of_an_unknown_dataset_names_it():
    err = refused(["demo", "--dataset", "nosuch"], "dataset")
    assert "unknown dataset 'nosuch'" in err
