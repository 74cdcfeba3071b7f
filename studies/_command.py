"""The command line shared by the chart studies: ``python -m studies.NAME [--out DIR] [--quick]``.

Each study's ``tasks(out_dir, quick=False)`` lists its jobs (label, zero-argument callable); the command runs
them under a progress bar and says where the charts went.
"""
from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import typer

#: Where the committed charts live (relative to the project root, where the studies run from).
DEFAULT_OUT = Path("docs/charts")


def run_charts(jobs, out: Path, doc: str) -> None:
    """Run the (label, job) pairs under a progress bar, then name the directory and the doc they belong to."""
    with typer.progressbar(jobs, label="charts", item_show_func=lambda job: job[0] if job else "") as bar:
        for _, job in bar:
            job()
    typer.echo(f"wrote {len(jobs)} charts to {out}/ (see {doc})")


def chart_app(tasks: Callable[..., list], doc: str, help: str, quick_help: str) -> typer.Typer:
    """A one-command typer app: ``--out DIR`` (default docs/charts) and ``--quick``; ``tasks(out, quick=...)``
    is looked up when the command runs (a callable that reads the study module's ``tasks``)."""
    app = typer.Typer(add_completion=False, help=help)

    @app.command(help=help)
    def charts(out: Path = typer.Option(DEFAULT_OUT, "--out", help="Directory for the PNG, SVG and CSV."),
               quick: bool = typer.Option(False, "--quick", help=quick_help)) -> None:
        run_charts(tasks(out, quick=quick), out, doc)

    return app
