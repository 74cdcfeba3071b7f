"""ephem.batch.distributed: a catalogue of bodies through ephem.batch.population.evaluate on a dask.distributed cluster.

Every cluster here is on 127.0.0.1 (the socket guard allows nothing else). The runs that must start their own
LocalCluster (the two-worker run, the killed worker) do; the others share one two-worker cluster of this module
through ``scheduler=``, which also exercises the path of an existing cluster. A LocalCluster costs ~3-4 s to
start on two cores, so there are three per test process at most.
"""
from __future__ import annotations

import csv
import os
import re
import signal
import time
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from ephem.batch import distributed as batch
from ephem.batch import population
from ephem.batch.partitions import INERTIA_GROUPS, REQUIRED_COLUMNS
from ephem.batch.task import known_columns
from ephem.cli import app
from ephem.base.errors import InvalidInputError

#: a Vesta-like body (tests/conftest.py's vesta_like), the mean anomaly and eccentricity varied per row
BASE = {"a_au": 2.3615413, "e": 0.0901676, "i_deg": 7.14406, "node_deg": 103.70232, "peri_deg": 151.53711,
        "mean_anomaly_deg": 26.80969, "epoch_jd_tdb": 2461000.5, "pole_ra_deg": 309.031, "pole_dec_deg": 42.2264,
        "rotation_period_hours": 5.3421, "moment_a": 0.3433, "moment_b": 0.3546, "moment_c": 0.42}
HEADER = ["name", *BASE, "e_sigma", "comment"]
CORRUPT = 3     # the row with e = 1.5: an unbound orbit


def write_population(path: Path, rows: int, corrupt: int | None = CORRUPT) -> Path:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(HEADER)
        for j in range(rows):
            row = dict(BASE, mean_anomaly_deg=(BASE["mean_anomaly_deg"] + 7.0 * j) % 360.0,
                       e=0.02 + 0.25 * (j % 13) / 13)
            if j == corrupt:
                row["e"] = 1.5
            w.writerow([f"body-{j}", *row.values(), 1e-4 if j % 2 else "", "a column the engine ignores"])
    return path


TEXT_COLUMNS = ("name", "model", "error", "history_error")


def read_csv_output(path: Path) -> pa.Table:
    """A CSV output with its types: text for the text columns, float for the rest (not inferred per file)."""
    names = path.read_text().splitlines()[0].replace('"', "").split(",")
    return pacsv.read_csv(path, convert_options=pacsv.ConvertOptions(
        column_types={c: pa.string() if c in TEXT_COLUMNS else pa.float64() for c in names},
        strings_can_be_null=False))


def read_outputs(out: Path, fmt: str) -> pa.Table:
    files = sorted(out.glob(f"part-*.{fmt}"))
    return pa.concat_tables([(pq.read_table if fmt == "parquet" else read_csv_output)(f) for f in files])


def direct(path: Path) -> dict[str, np.ndarray]:
    """The whole input through the core in this process, as one partition."""
    table = pacsv.read_csv(path)
    columns = {c: np.asarray(table.column(c).to_pylist(), dtype=object if c == "name" else float)
               for c in table.column_names if c != "comment"}
    return population.evaluate(columns)


def assert_answers(table: pa.Table, path: Path, rows: int) -> None:
    """Every input row has its output row, in order; the corrupt one has its reason, the others are answered
    as the core answers them in one piece."""
    assert table.num_rows == rows
    assert table.column("name").to_pylist() == [f"body-{j}" for j in range(rows)]
    error = table.column("error").to_pylist()
    assert error[CORRUPT].startswith("e: ") and "1.5" in error[CORRUPT]
    assert [e for j, e in enumerate(error) if j != CORRUPT] == [""] * (rows - 1)
    obliquity = np.asarray(table.column("obliquity_deg").to_pylist(), dtype=float)
    assert np.isnan(obliquity[CORRUPT])
    want = direct(path)
    good = np.arange(rows) != CORRUPT
    for key in ("obliquity_deg", "precession_rate_arcsec_per_year", "nutation_1_period_days",
                "obliquity_deg_uncertainty"):
        got = np.asarray(table.column(key).to_pylist(), dtype=float)
        # the same arithmetic on fewer rows at a time: numpy's vectorised sums round by a few ulps differently
        # with the array's length (seen: 1 ulp of 27.48 deg, 4e-15); 1e-12 relative is ~1000 times that
        np.testing.assert_allclose(got[good], want[key][good], rtol=1e-12, atol=0, err_msg=key)
    sigma = np.asarray(table.column("obliquity_deg_uncertainty").to_pylist(), dtype=float)
    assert np.isfinite(sigma[1]) and np.isnan(sigma[0])   # e_sigma on odd rows only: propagated where given


def assert_same(got: pa.Table, want: pa.Table) -> None:
    """The same columns and values, NaN where NaN (pyarrow's equals takes NaN for unequal)."""
    assert got.column_names == want.column_names
    for name in want.column_names:
        np.testing.assert_array_equal(np.asarray(got.column(name).to_pylist()),
                                      np.asarray(want.column(name).to_pylist()), err_msg=name)


@pytest.fixture(scope="module")
def cluster():
    """A two-worker cluster on 127.0.0.1 that the resume, format and CLI tests share (``scheduler=``)."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0") as c:
        yield c.scheduler_address


# ------------------------------------------------------------------ the engine's own cluster

def test_a_population_on_a_two_worker_local_cluster(tmp_path):
    """(a) Every row answered, the corrupt row with its reason, the others as the core gives them."""
    source = write_population(tmp_path / "bodies.csv", 10)
    seen = []
    result = batch.run(source, tmp_path / "out", workers=2, partition_rows=4,
                       progress=lambda done, total: seen.append((done, total)))
    assert (result.partitions, result.partitions_skipped, result.rows, result.rows_failed) == (3, 0, 10, 1)
    assert result.rows_computed == 10 and result.out_path == (tmp_path / "out").absolute()
    assert seen == [(0, 3), (1, 3), (2, 3), (3, 3)]
    assert result.dashboard_link is None           # no bokeh in the lock: no dashboard to show
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["_input", "part-00000.parquet",
                                                                     "part-00001.parquet", "part-00002.parquet"]
    assert_answers(read_outputs(tmp_path / "out", "parquet"), source, 10)
    # a reader of the directory sees the answers only (pyarrow skips _input/ and the dot-files)
    assert pq.read_table(tmp_path / "out").num_rows == 10


def test_a_worker_killed_mid_run_costs_a_retry_not_the_job(tmp_path):
    """(b) One worker is killed (SIGKILL) while it computes a partition, once a first partition is done: its
    nanny starts a new worker, the scheduler reruns the lost task and every partition is written."""
    from distributed import default_client

    rows, per = 4_000, 1_000        # 0.15-1.5 s a partition on one (shared) core: the kill lands inside a task
    source = write_population(tmp_path / "bodies.csv", rows)
    killed = []

    def kill_once(done: int, total: int) -> None:
        if done < 1 or killed:
            return
        client = default_client()           # the run's client, in the calling thread
        # right after a task completes the scheduler may hold the next ones queued for a moment, with no worker
        # processing (seen under a loaded -n 2 suite): wait for one to take a task, else try at the next partition
        busy, deadline = [], time.monotonic() + 5.0
        while not busy and time.monotonic() < deadline:
            busy = [w for w, keys in client.processing().items() if keys]
            if not busy:
                time.sleep(0.01)
        if not busy:
            return
        pid = client.run(os.getpid, workers=busy[:1])[busy[0]]
        os.kill(pid, signal.SIGKILL)
        killed.append((pid, busy[0]))

    result = batch.run(source, tmp_path / "out", workers=2, partition_rows=per, progress=kill_once)
    assert killed, "no worker was killed"
    assert (result.partitions, result.rows, result.rows_failed) == (4, rows, 1)
    table = read_outputs(tmp_path / "out", "parquet")
    assert table.num_rows == rows and table.column("name").to_pylist() == [f"body-{j}" for j in range(rows)]
    assert not list((tmp_path / "out").glob(".part-*"))     # no temporary file left over


# ------------------------------------------------------------------ on an existing cluster (scheduler=)

def test_a_rerun_computes_only_the_missing_partitions(tmp_path, cluster):
    """(c) Resume: a deleted output is recomputed, the others are skipped (untouched); the answers are those
    of the first run."""
    source = write_population(tmp_path / "bodies.csv", 10)
    out = tmp_path / "out"
    first = batch.run(source, out, scheduler=cluster, partition_rows=3)
    assert (first.partitions, first.partitions_skipped) == (4, 0)
    before = read_outputs(out, "parquet")
    stamps = {p.name: p.stat().st_mtime_ns for p in out.glob("part-*")}
    (out / "part-00002.parquet").unlink()
    seen = []
    second = batch.run(source, out, scheduler=cluster, partition_rows=3,
                       progress=lambda done, total: seen.append(done))
    assert (second.partitions, second.partitions_skipped, second.rows_computed) == (4, 3, 3)
    assert (second.rows, second.rows_failed) == (10, 1)      # the skipped partitions are counted from their files
    assert seen == [3, 4]
    after = {p.name: p.stat().st_mtime_ns for p in out.glob("part-*")}
    assert {k: v for k, v in after.items() if k != "part-00002.parquet"} == \
        {k: v for k, v in stamps.items() if k != "part-00002.parquet"}
    assert_same(read_outputs(out, "parquet"), before)        # same partition, same worker code: the same bits
    # nothing left: a third run computes nothing and starts no task
    third = batch.run(source, out, scheduler=cluster, partition_rows=3)
    assert (third.partitions_skipped, third.rows_computed, third.rows) == (4, 0, 10)


def test_changed_settings_or_input_are_refused_until_fresh(tmp_path, cluster):
    source = write_population(tmp_path / "bodies.csv", 6)
    out = tmp_path / "out"
    batch.run(source, out, scheduler=cluster, partition_rows=3)
    with pytest.raises(InvalidInputError, match="partition_rows was 3, now 2") as exc:
        batch.run(source, out, scheduler=cluster, partition_rows=2)
    assert exc.value.field == "out"
    with pytest.raises(InvalidInputError, match="output_format was 'parquet', now 'csv'"):
        batch.run(source, out, scheduler=cluster, partition_rows=3, output_format="csv")
    os.utime(source, ns=(1, 1))                     # touched, same content: still the same input
    assert batch.run(source, out, scheduler=cluster, partition_rows=3).partitions_skipped == 2
    write_population(source, 7)                     # another content
    with pytest.raises(InvalidInputError, match="is not the file the partitions were made from"):
        batch.run(source, out, scheduler=cluster, partition_rows=3)
    again = batch.run(source, out, scheduler=cluster, partition_rows=2, fresh=True)
    assert (again.partitions, again.partitions_skipped, again.rows) == (4, 0, 7)
    assert sorted(p.name for p in out.glob("part-*")) == [f"part-0000{j}.parquet" for j in range(4)]


@pytest.mark.parametrize("fmt", ["parquet", "csv"])
def test_parquet_and_csv_outputs(tmp_path, cluster, fmt):
    """(e) Either format holds the same answers (CSV: the shortest decimals that read back to the same float)."""
    source = write_population(tmp_path / "bodies.csv", 8)
    result = batch.run(source, tmp_path / "out", scheduler=cluster, partition_rows=5, output_format=fmt)
    assert sorted(p.name for p in (tmp_path / "out").glob("part-*")) == [f"part-00000.{fmt}", f"part-00001.{fmt}"]
    assert (result.rows, result.rows_failed) == (8, 1)
    table = read_outputs(tmp_path / "out", fmt)
    assert table.column_names == list(population.OUTPUT_COLUMNS)
    assert_answers(table, source, 8)


def test_a_parquet_input_and_a_cell_that_is_not_a_number(tmp_path, cluster):
    """A Parquet input gives what its CSV gives; a text cell that is not a number spoils its row only."""
    source = write_population(tmp_path / "bodies.csv", 6)
    table = pacsv.read_csv(source)
    pq.write_table(table, tmp_path / "bodies.parquet", row_group_size=4)
    batch.run(tmp_path / "bodies.parquet", tmp_path / "pq", scheduler=cluster, partition_rows=5)
    assert_answers(read_outputs(tmp_path / "pq", "parquet"), source, 6)
    text = source.read_text().splitlines()
    text[5] = text[5].replace(f",{BASE['i_deg']},", ",abc,")       # row 4's inclination
    (tmp_path / "text.csv").write_text("\n".join(text) + "\n")
    result = batch.run(tmp_path / "text.csv", tmp_path / "text", scheduler=cluster, partition_rows=5)
    assert result.rows_failed == 2
    error = read_outputs(tmp_path / "text", "parquet").column("error").to_pylist()
    assert error[4] == "i_deg: not a number: 'abc'" and error[5] == ""


def test_the_cli(tmp_path, cluster, monkeypatch):
    """(d) ephem batch: the summary line, the files, a rerun that resumes, the history columns, and the
    refusals with the field named (status 2)."""
    monkeypatch.chdir(tmp_path)
    write_population(tmp_path / "bodies.csv", 5)
    runner = CliRunner()
    args = ["batch", "bodies.csv", "--out", "out", "--scheduler", cluster, "--partition-rows", "2", "--format",
            "csv", "--history", "--start-year", "-1000", "--stop-year", "0", "--step-years", "100"]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    assert re.fullmatch(r"5 rows \(1 failed\) in 3 partitions to .*out/, [\d.]+ s, [\d.e+]+ bodies/s\n", res.stdout)
    assert "3 partitions, 5 rows on 2 workers" in res.stderr
    table = read_outputs(tmp_path / "out", "csv")
    assert table.num_rows == 5 and set(population.HISTORY_COLUMNS) <= set(table.column_names)
    assert np.all(np.asarray(table.column("obliquity_max_deg").to_pylist())[[0, 1, 2, 4]]
                  >= np.asarray(table.column("obliquity_min_deg").to_pylist())[[0, 1, 2, 4]])
    res = runner.invoke(app, args + ["--quiet"])
    assert res.exit_code == 0 and res.stderr == ""
    assert res.stdout.startswith("5 rows (1 failed) in 3 partitions, 3 resumed to ")
    for bad, message in [(["batch", "bodies.csv", "--out", "o2", "--history"], "error: start_year: missing; give "
                                                                               "--start-year with --history"),
                         (["batch", "bodies.txt", "--out", "o2"], "error: input: unknown format"),
                         (["batch", "bodies.csv", "--out", "o2", "--workers", "0"], "error: workers: must be >= 1"),
                         (["batch", "bodies.csv", "--out", "o2", "--format", "xls"], "error: format: must be one of")]:
        res = runner.invoke(app, bad)
        assert res.exit_code == 2 and res.stderr.startswith(message), (bad, res.output)


# ------------------------------------------------------------------ the input's refusals (no cluster)

def test_the_required_columns_are_the_cores():
    assert REQUIRED_COLUMNS == population.REQUIRED
    assert {c for group in INERTIA_GROUPS for c in group} <= set(population.INPUT_COLUMNS)
    assert "e_sigma" in known_columns(population)


def test_bad_inputs_are_refused_naming_the_field(tmp_path):
    source = write_population(tmp_path / "bodies.csv", 3)
    lines = source.read_text().splitlines()

    def refused(text: str, name="x.csv", **kw) -> InvalidInputError:
        (tmp_path / name).write_text(text) if isinstance(text, str) else (tmp_path / name).write_bytes(text)
        with pytest.raises(InvalidInputError) as exc:
            batch.run(tmp_path / name, tmp_path / "never", **kw)
        return exc.value

    no_e = "\n".join(",".join(c for i, c in enumerate(line.split(",")) if i != 2) for line in lines)
    assert refused(no_e).field == "e"
    renamed = "\n".join([lines[0].replace("a_au", "a")] + lines[1:])
    err = refused(renamed)
    assert err.field == "a_au" and "is 'a' meant?" in str(err)
    no_inertia = "\n".join(",".join(c for i, c in enumerate(line.split(",")) if i not in (12, 13)) for line in lines)
    assert refused(no_inertia).field == "dynamical_ellipticity"
    assert "Row #3: Expected 16 columns, got 3: a,b,c" in str(refused("\n".join(lines[:2] + ["a,b,c"] + lines[3:])))
    surplus = refused("\n".join(lines[:2] + [lines[2] + ",9"] + lines[3:]))      # a cell more than the header
    assert surplus.field == "input" and "Expected 16 columns, got 17" in str(surplus)
    # not UTF-8 in the first block: pyarrow raised from open_csv, an uncaught ArrowInvalid (a traceback, status 1)
    latin = refused("\n".join(lines[:2]).encode() + b"\n\xff" + "\n".join(lines[2:]).encode() + b"\n")
    assert latin.field == "input" and "UTF8" in str(latin)
    assert refused(b"PAR1 not parquet", name="x.parquet").field == "input"
    assert refused("", name="empty.csv").field == "input"
    assert refused(source.read_text(), name="x.xlsx").field == "input"
    assert refused(source.read_text(), partition_rows=0).field == "partition_rows"
    assert refused(source.read_text(), output_format="xls").field == "format"
    assert refused(source.read_text(), history=population.HistorySpec(0, -10, 1)).field == "stop_year"
    # refused once, before the work, as each row's history would be: a step whose count of epochs overflowed
    # int() in every task (failed partitions), and one over the cap of epochs (every row's history_error)
    assert refused(source.read_text(), history=population.HistorySpec(0, 10, 5e-324)).field == "step_years"
    assert refused(source.read_text(), history=population.HistorySpec(0, 1e6, 1)).field == "step_years"
    with pytest.raises(InvalidInputError, match="no such file") as exc:
        batch.run(tmp_path / "missing.csv", tmp_path / "never")
    assert exc.value.field == "input" and not (tmp_path / "never").exists()
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("mine")
    with pytest.raises(InvalidInputError, match="holds no batch") as exc:
        batch.run(source, tmp_path / "mine")
    assert exc.value.field == "out" and (tmp_path / "mine" / "notes.txt").exists()
