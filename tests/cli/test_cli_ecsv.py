"""The CLI's tables as astropy's ECSV and its dates as people read them (issue 41): ``--format ecsv`` on bodies,
precession, nutation, track, history and free-motion writes the table ephem.api.to_ecsv writes, which
``QTable.read`` reads back with the units the keys name and the same numbers as the command's JSON (one ulp:
tests/exports/test_qtable.py's check), the command line its source; ``--time-scale`` chooses the scale of the
calendar dates beside jd_tdb."""
from __future__ import annotations

import csv
import io
import json

import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.cli import app
from ephem.cli.common import TimeScale
from tests.exports.test_qtable import check_read_back

runner = CliRunner()

COMMANDS = {
    "bodies": ["bodies", "--dataset", "petit2014"],
    "precession": ["precession", "vesta"],
    "nutation": ["nutation", "vesta", "--order", "4"],
    "nutation_earth": ["nutation", "earth", "--cut-mas", "10"],
    "track": ["track", "ceres", "--start", "2040-01-01", "--stop", "2040-03-01", "--step-days", "20"],
    "track_tdb": ["track", "mars", "--start", "2030-01-01", "--stop", "2030-02-01", "--step-days", "10",
                  "--time-scale", "tdb"],
    "history": ["history", "ceres", "--start-year", "-1000", "--stop-year", "0", "--step-years", "250", "--quiet"],
    "free_motion": ["free-motion", "mars", "--start", "2030-01-01", "--stop", "2030-01-03", "--step-days", "0.5",
                    "--time-scale", "tt"],
}


def run(argv: list[str]) -> str:
    res = runner.invoke(app, argv)
    assert res.exit_code == 0, (argv, res.output)
    return res.stdout


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_table_command_writes_ecsv_that_astropy_reads_as_its_json(name):
    argv = COMMANDS[name]
    answer = json.loads(run([*argv, "--format", "json"]))
    table = check_read_back(run([*argv, "--format", "ecsv"]), answer)
    assert table.meta["source"].startswith(f"ephem {argv[0]} ") and "--format ecsv" in table.meta["source"]


def test_the_scales_are_the_librarys():
    assert [s.value for s in TimeScale] == list(api.CALENDAR_SCALES)


@pytest.mark.parametrize("scale", ["utc", "tt", "tdb"])
def test_the_track_csv_has_its_dates_in_the_scale_asked(scale):
    text = run([*COMMANDS["track"], "--format", "csv", "--time-scale", scale])
    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0][:2] == ["jd_tdb", f"{scale}_iso"]
    answer = json.loads(run([*COMMANDS["track"], "--time-scale", scale]))
    assert [r[1] for r in rows[1:]] == answer[f"{scale}_iso"]


def test_a_bad_scale_is_a_usage_error_naming_it():
    res = runner.invoke(app, [*COMMANDS["track"], "--time-scale", "ut1"])
    assert res.exit_code == 2 and "time_scale" in res.output


@pytest.mark.parametrize("argv", [["body", "vesta", "--format", "ecsv"],
                                  [*COMMANDS["track"], "--models", "--format", "ecsv"]],
                         ids=["body record", "track models"])
def test_what_is_no_table_of_units_is_refused(argv):
    res = runner.invoke(app, argv)
    assert res.exit_code == 2 and "format" in res.output and "Traceback" not in res.output
