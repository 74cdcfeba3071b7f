"""Each chart study runs as ``python -m studies.NAME [--out DIR] [--quick]`` (the former ``ephem bench``):
the shared command (studies/_command.py) runs every task of the study, with the options given, and
writes to docs/charts by default."""
from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from studies import accuracy, estimate_ratios, free_motion, rotation_scale


@pytest.mark.parametrize("study, tasks, page", [(accuracy, 3, "docs/accuracy.md"),
                                                (free_motion, 2, "docs/free_motion.md"),
                                                (rotation_scale, 1, "docs/accuracy.md"),
                                                (estimate_ratios, 1, "docs/accuracy.md")])
def test_the_command_runs_every_task(study, tasks, page, monkeypatch, tmp_path):
    ran = []
    monkeypatch.setattr(study, "tasks", lambda out, quick=False: [
        (f"job{i}", lambda i=i: ran.append((i, out, quick))) for i in range(tasks)])
    res = CliRunner().invoke(study.app, ["--out", str(tmp_path), "--quick"])
    assert res.exit_code == 0, res.output
    assert ran == [(i, tmp_path, True) for i in range(tasks)] and f"wrote {tasks} charts" in res.output
    assert page in res.output
    ran.clear()
    res = CliRunner().invoke(study.app, [])
    assert res.exit_code == 0, res.output
    assert ran == [(i, Path("docs/charts"), False) for i in range(tasks)]      # the committed charts, full size
