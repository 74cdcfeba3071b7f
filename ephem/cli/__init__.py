"""The command-line interface: the ``ephem`` command and its subcommands.

The commands: ``ephem bodies | body | precession | nutation | track | history | free-motion | tables |
plot | pck | batch | demo | catalogue import``.

``bodies``, ``body``, ``precession``, ``nutation``, ``track``, ``history`` and ``free-motion`` print JSON (the
default), CSV or an aligned text table (``--format json|csv|table``); ``tables`` writes csv, markdown, latex or json
files, ``plot`` PNG or SVG (``--out``'s suffix), ``pck`` a text kernel, ``batch`` parquet, csv or ecsv partitions, ``demo``
text tables; ``catalogue import``'s ``--format`` is its orbit file's. tests/cli/test_cli_matrix.py runs every command in
every format for a body of every theory family. Errors go to stderr as ``error: FIELD: why``
with exit status 2 (bad input, unknown body, and what the option parser refuses: a malformed
number, an unknown option or command, a missing one), 3 (theory not applicable) or 1 (``ephem batch``:
partitions that still failed after their retries; the others are written and a rerun resumes).

The commands take the library only through :mod:`ephem.api`. Start-up is kept short for one-body answers: the
api (numpy, the catalogue, the models) is imported by each command rather than at the top, so ``--help`` and
usage errors never load it, and option values are parsed by :mod:`ephem.cli.usage` rather than by typer's
pydantic adapters. The modules:

- :mod:`ephem.cli.usage`: option parsing, usage errors.
- :mod:`ephem.cli.common`: the app, shared options, printing.
- :mod:`ephem.cli.one_body`: the answers printed.
- :mod:`ephem.cli.files`: the commands that write files.
- :mod:`ephem.cli.demo`: the tour.
- :mod:`ephem.cli.__main__`: ``python -m ephem.cli``, what the ``ephem`` script runs.
"""
from __future__ import annotations

from .common import app
# each registers its commands on the app; in this order, the order `ephem --help` lists them
from . import one_body  # noqa: F401,E402,I001
from . import files  # noqa: F401,E402
from . import demo  # noqa: F401,E402


def main() -> None:  # pragma: no cover
    app()
