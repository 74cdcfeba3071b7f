"""``ephem track BODY ... --models``: the comparison of every model in each format (JSON: the library's answer; CSV
and the table: one row per model, the chosen one on stderr), ``--out`` writing its chart, and the options that do not
apply refused naming the field (exit 2)."""
from __future__ import annotations

import csv
import io
import json
import xml.etree.ElementTree as ET

import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.cli import app

runner = CliRunner()
ARGS = ["track", "vesta", "--start", "2025-01-01", "--stop", "2026-01-01", "--step-days", "30",
        "--tolerance-mas", "100", "--models"]
COLUMNS = ["name", "order", "variant", "estimated_error_mas", "estimated_cpu_ms", "estimated_memory_mb", "eligible",
           "chosen"]


@pytest.fixture(scope="module")
def want() -> dict:
    return api.track_models("vesta", "2025-01-01", "2026-01-01", 30.0, tolerance_mas=100.0)


def parse_table(text: str) -> tuple[list[str], list[list[str]]]:
    """(header, rows) of the CLI's aligned table, each cell read in the span of its column's rule of dashes."""
    lines = text.rstrip("\n").split("\n")
    spans, at = [], 0
    for dashes in lines[1].split("  "):
        spans.append((at, at + len(dashes)))
        at += len(dashes) + 2
    cells = [[line[a:b].strip() for a, b in spans] for line in lines]
    return cells[0], cells[2:]


def _run(*extra: str):
    return runner.invoke(app, ARGS + list(extra))


def test_json_is_the_librarys_answer(want):
    res = _run("--format", "json")
    assert res.exit_code == 0, res.output
    got = json.loads(res.stdout)
    assert got["chosen"] == want["chosen"] and len(got["models"]) == len(want["models"])
    assert got["models"] == json.loads(json.dumps(want["models"]))


def test_csv_has_one_row_per_model_with_the_numbers(want):
    res = _run("--format", "csv")
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(io.StringIO(res.stdout)))
    assert list(rows[0]) == COLUMNS + ["why"]
    assert len(rows) == len(want["models"])
    for row, m in zip(rows, want["models"]):
        assert row["name"] == m["name"] and row["chosen"] == str(m["chosen"])
        if m["estimated_error_mas"] is not None:
            assert float(row["estimated_error_mas"]) == pytest.approx(m["estimated_error_mas"], rel=1e-15)
            assert float(row["estimated_cpu_ms"]) == pytest.approx(m["estimated_cpu_ms"], rel=1e-15)
    assert [r["name"] for r in rows if r["chosen"] == "True"] == [want["chosen"]]
    assert res.stderr.startswith(f"{len(want['models'])} models over 13 epochs; chosen: {want['chosen']}")


def test_the_table_has_the_columns_and_one_row_per_model(want):
    res = _run("--format", "table")
    assert res.exit_code == 0, res.output
    header, rows = parse_table(res.stdout)
    assert header == COLUMNS and len(rows) == len(want["models"])
    chosen = [r for r in rows if r[-1] == "True"]
    assert len(chosen) == 1 and chosen[0][0] == want["chosen"] and chosen[0][-2] == "True"   # eligible too
    over = [r for r, m in zip(rows, want["models"]) if m["available"] and m["estimated_error_mas"] > 100.0]
    assert over and all(r[-2] == "False" for r in over)


@pytest.mark.parametrize("suffix", ["svg", "png"])
def test_out_writes_the_chart(tmp_path, want, suffix):
    out = tmp_path / "charts" / f"vesta.{suffix}"
    res = _run("--format", "table", "--out", str(out))
    assert res.exit_code == 0, res.output
    data = out.read_bytes()
    assert f"wrote {out} ({len(data)} bytes)" in res.stderr
    assert data == api.models_chart(want, fmt=suffix)
    if suffix == "svg":
        root = ET.fromstring(data)
        assert root.get("role") == "img"
    else:
        assert data[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("extra, field", [
    (["--order", "4"], "order"), (["--model", "hansen"], "model"), (["--rotation-phase-deg", "10"],
                                                                      "rotation_phase_deg"),
    (["--free-wobble-phase-deg", "30"], "free_wobble_phase_deg"), (["--out", "chart.pdf"], "out")])
def test_what_does_not_apply_is_refused_naming_the_field(tmp_path, extra, field):
    res = _run(*extra)
    assert res.exit_code == 2 and res.stderr.startswith(f"error: {field}: "), res.output
    assert res.stdout == "" and not list(tmp_path.iterdir())


def test_out_without_models_and_a_bad_step_are_refused():
    res = runner.invoke(app, ARGS[:-1] + ["--out", "chart.svg"])
    assert res.exit_code == 2 and res.stderr.startswith("error: out: "), res.output
    res = runner.invoke(app, ARGS[:7] + ["0", "--models"])
    assert res.exit_code == 2 and res.stderr.startswith("error: step_days: must be positive"), res.output
