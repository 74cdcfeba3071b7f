"""Every example in docs/api.md runs: Python as doctests, `$ ephem …` through the CLI, `$ curl …` through
the service. A shown output line must match a printed line (… stands for any text), in order."""
import doctest
import re
import shlex
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from ephem.cli import app as cli
from service.app import app as web

DOC = Path(__file__).resolve().parent.parent / "docs" / "api.md"


def console_examples(text: str) -> list[tuple[str, list[str]]]:
    """(command, expected lines) of every `$ ` line in the ```console blocks."""
    examples = []
    for block in re.findall(r"```console\n(.*?)```", text, flags=re.S):
        for line in block.splitlines():
            if line.startswith("$ "):
                examples.append((line[2:], []))
            elif examples and line.strip():
                examples[-1][1].append(line.rstrip())
    return examples


def matches_in_order(expected: list[str], printed: str) -> str | None:
    """None when each expected line matches a printed line, in order; else the first that does not."""
    lines = printed.splitlines()
    i = 0
    for want in expected:
        pattern = re.compile(".*".join(re.escape(part) for part in want.strip().split("…")))
        while i < len(lines) and not pattern.fullmatch(lines[i].strip()):
            i += 1
        if i == len(lines):
            return want
        i += 1
    return None


def run(command: str) -> tuple[int, str]:
    argv = shlex.split(command)
    if argv[0] == "ephem":
        res = CliRunner().invoke(cli, argv[1:])
        return res.exit_code, res.stderr + res.stdout      # the docs show the notes on stderr first
    assert argv[0] == "curl", command
    method, data, headers, url, output = "GET", None, {}, None, None
    it = iter(argv[1:])
    for arg in it:
        if arg == "-X":
            method = next(it)
        elif arg == "-d":
            data = next(it)
        elif arg == "-o":
            output = next(it)
        elif arg == "-H":
            name, value = next(it).split(":", 1)
            headers[name.strip()] = value.strip()
        elif not arg.startswith("-"):
            url = arg
    path = re.sub(r"^https?://[^/]+", "", url)
    r = TestClient(web).request(method, path, content=data, headers=headers)
    if output is not None:                        # -o FILE: the body goes to the file, nothing is printed
        Path(output).write_bytes(r.content)
        return (0 if r.status_code < 400 else 22), ""
    return (0 if r.status_code < 400 else 22), r.text


EXAMPLES = console_examples(DOC.read_text(encoding="utf-8"))


def test_the_page_has_examples_for_every_route_and_command():
    commands = " ".join(c for c, _ in EXAMPLES)
    for route in [r.path for r in web.routes if getattr(r, "include_in_schema", False)]:
        pattern = re.sub(r"\{[^}]+\}", "[^/?']+", route) + r"(?:[?']|$)"
        assert re.search(pattern, commands), f"no example of {route}"
    for command in cli.registered_commands:
        name = command.name or command.callback.__name__.replace("_", "-")
        if name != "demo":
            assert f"ephem {name}" in commands, f"no example of ephem {name}"


@pytest.mark.parametrize("command,expected", EXAMPLES, ids=[c[:60] for c, _ in EXAMPLES])
def test_console_example(command, expected, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)                    # commands that write files write here
    status, printed = run(command)
    refused = any(line.startswith(("error:", '{"type":')) for line in expected)
    assert (status != 0) == refused, printed
    missing = matches_in_order(expected, printed)
    assert missing is None, f"{missing!r} not in:\n{printed}"


def test_python_examples():
    result = doctest.testfile(str(DOC), module_relative=False, optionflags=doctest.ELLIPSIS
                              | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.attempted > 20 and result.failed == 0, result
