"""``ephem batch --format ecsv``: each partition as POST /v1/batch's ECSV (ephem.exports.qtable), read back by astropy.

One one-worker cluster on 127.0.0.1 for the module (~3 s to start); the runs go to it through ``--scheduler``.
"""
from __future__ import annotations

import csv

import numpy as np
import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.base.errors import InvalidInputError
from ephem.cli import app

from test_batch import CORRUPT, read_outputs, write_population

ROWS, PER = 7, 4          # two partitions, the second shorter
#: columns checked for their unit (None: a plain column) and numbers
UNITS = {"obliquity_deg": "deg", "dynamical_ellipticity": None, "precession_rate_arcsec_per_year": "arcsec / yr",
         "scaling_factor_arcsec_per_year": "arcsec / yr", "nutation_1_period_days": "d",
         "nutation_1_longitude_amplitude_arcsec": "arcsec", "nutation_1_multiple": None,
         "estimated_error_mas": "mas", "obliquity_deg_uncertainty": "deg"}


@pytest.fixture(scope="module")
def cluster():
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as c:
        yield c.scheduler_address


def _numbers(column) -> np.ndarray:
    """A column read back (a Quantity, masked or not, or a plain column) as floats, NaN where masked."""
    if hasattr(column, "unmasked"):         # a MaskedQuantity
        data, mask = column.unmasked.value, column.mask
    elif hasattr(column, "mask"):           # a MaskedColumn (an integer column with a null)
        data, mask = column.data.data, column.mask
    else:
        data, mask = getattr(column, "value", column), False
    return np.where(np.asarray(mask), np.nan, np.asarray(data, dtype=float))


def test_ecsv_partitions_hold_the_csv_numbers_with_the_posts_units_and_metadata(tmp_path, cluster, monkeypatch):
    from astropy.table import QTable

    monkeypatch.chdir(tmp_path)
    source = write_population(tmp_path / "bodies.csv", ROWS)
    res = CliRunner().invoke(app, ["batch", "bodies.csv", "--out", "ecsv", "--scheduler", cluster,
                                   "--partition-rows", str(PER), "--format", "ecsv", "--quiet"])
    assert res.exit_code == 0, res.output
    assert res.stdout.startswith(f"{ROWS} rows (1 failed) in 2 partitions to ")
    files = sorted(p.name for p in (tmp_path / "ecsv").glob("part-*"))
    assert files == ["part-00000.ecsv", "part-00001.ecsv"]
    api.run_batch(source, tmp_path / "csv", scheduler=cluster, partition_rows=PER, output_format="csv")
    want = read_outputs(tmp_path / "csv", "csv")

    parts = [QTable.read(tmp_path / "ecsv" / f, format="ascii.ecsv") for f in files]
    assert [len(t) for t in parts] == [PER, ROWS - PER]
    assert parts[0].colnames == want.column_names
    names = [n for t in parts for n in t["name"].tolist()]
    assert names == want.column("name").to_pylist()
    errors = [e or "" for t in parts for e in t["error"].tolist()]       # an empty reason reads back masked
    assert errors == want.column("error").to_pylist() and errors[CORRUPT].startswith("e: ")
    for key, unit in UNITS.items():
        column = parts[0][key]
        assert (str(column.unit) if getattr(column, "unit", None) is not None else None) == unit, key
        got = np.concatenate([_numbers(t[key]) for t in parts])
        expected = np.asarray(want.column(key).to_pylist(), dtype=float)
        assert np.array_equal(np.isnan(got), np.isnan(expected)), key      # NaN in the CSV is masked in ECSV
        # both files hold each double's shortest repr: the same value to the last bit; 1e-15 is a few ulps
        np.testing.assert_allclose(got, expected, rtol=1e-15, atol=0, equal_nan=True, err_msg=key)
    assert np.isnan(_numbers(parts[0]["obliquity_deg"])[CORRUPT])

    # the units, descriptions and metadata are the POST's: the same answer through the same builder
    with open(source, newline="") as f:
        rows = [{k: v for k, v in r.items() if k != "comment" and v != ""} for r in csv.DictReader(f)][:PER]
    post = api.to_qtable(api.batch(rows))
    assert post.colnames == parts[0].colnames
    for key in post.colnames:
        assert getattr(post[key], "unit", None) == getattr(parts[0][key], "unit", None), key
        assert post[key].info.description == parts[0][key].info.description, key
    assert {k: v for k, v in parts[0].meta.items() if k != "source"} == \
        {k: v for k, v in post.meta.items() if k != "source"}
    assert parts[1].meta["source"] == f"ephem batch {source}, partition 1"

    # a rerun resumes from the ECSV files: their rows and failed rows are counted back
    again = api.run_batch(source, tmp_path / "ecsv", scheduler=cluster, partition_rows=PER, output_format="ecsv")
    assert (again.partitions_skipped, again.rows, again.rows_failed, again.rows_computed) == (2, ROWS, 1, 0)


def test_an_unknown_format_names_ecsv_among_the_choices(tmp_path):
    source = write_population(tmp_path / "bodies.csv", 2)
    with pytest.raises(InvalidInputError, match="must be one of parquet, csv, ecsv") as exc:
        api.run_batch(source, tmp_path / "out", output_format="xls")
    assert exc.value.field == "format"
