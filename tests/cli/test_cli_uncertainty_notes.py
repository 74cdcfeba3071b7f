"""Where an answer's 1-sigma is a lower bound (issue 41: Vesta's rate read 13.64875 +- 1.02e-9 arcsec/yr, though only
its rotation period has a sigma), the CLI's table and CSV say so beside the number, as the page and the JSON do."""
from __future__ import annotations

import csv
import io

from typer.testing import CliRunner

from ephem import api
from ephem.cli import app

runner = CliRunner()


def test_the_table_says_which_uncertainties_are_lower_bounds():
    bounds = api.precession("vesta")["uncertainty"]["lower_bounds"]
    assert "precession_rate_arcsec_per_year" in bounds          # the case the issue met
    out = runner.invoke(app, ["precession", "vesta", "--format", "table"])
    assert out.exit_code == 0, out.output
    notes = [line for line in out.stdout.splitlines() if line.startswith("note:")]
    assert len(notes) == len(bounds)
    for key, why in bounds.items():
        assert f"note: {key}_uncertainty is a lower bound (>=): {why}" in notes


def test_the_csv_keeps_its_one_header_and_says_it_beside_the_data():
    out = runner.invoke(app, ["precession", "vesta", "--format", "csv"])
    assert out.exit_code == 0, out.output
    rows = list(csv.reader(io.StringIO(out.stdout)))
    assert len(rows) == 2 and "precession_rate_arcsec_per_year_uncertainty" in rows[0]
    assert "precession_rate_arcsec_per_year_uncertainty is a lower bound" in out.stderr


def test_an_answer_without_lower_bounds_gets_no_note():
    """Itokawa's values carry no propagated sigma that is a lower bound (none of its inputs has one): no note."""
    assert not (api.precession("itokawa").get("uncertainty") or {}).get("lower_bounds")
    out = runner.invoke(app, ["precession", "itokawa", "--format", "table"])
    assert out.exit_code == 0, out.output
    assert "note:" not in out.stdout and "lower bound" not in out.stdout
