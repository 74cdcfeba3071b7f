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


# a number not glued to a word or to another number's digits ("petit2014" is a word, not 2014)
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def _close(shown: str, printed: str) -> bool:
    """A shown number matches a printed one within one unit of its last shown digit: the docs show values
    to 10 significant digits, and the last digits of a result change with the CPU, the BLAS and library
    versions (relative differences of ~1e-13 can carry a rounding across a shown digit)."""
    if shown == printed:
        return True
    mantissa = shown.lower().split("e")[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    exponent = int(shown.lower().split("e")[1]) if "e" in shown.lower() else 0
    unit = 10.0 ** (exponent - decimals)
    # the slack covers the binary representation of the decimal strings (|value| eps / unit, ~3e-7 here)
    return abs(float(shown) - float(printed)) <= unit * (1 + 1e-5)


def line_matches(want: str, line: str) -> bool:
    """``want`` (… for any text, numbers within one unit of their last digit) matches the printed ``line``."""
    parts = []
    for chunk in want.strip().split("…"):
        pos, pieces = 0, []
        for m in NUMBER.finditer(chunk):
            pieces.append(re.escape(chunk[pos:m.start()]) + f"({NUMBER.pattern})")
            pos = m.end()
        pieces.append(re.escape(chunk[pos:]))
        parts.append("".join(pieces))
    m = re.fullmatch(".*?".join(parts), line.strip())
    if m is None:
        return False
    shown = [n.group(0) for chunk in want.strip().split("…") for n in NUMBER.finditer(chunk)]
    return all(_close(a, b) for a, b in zip(shown, m.groups()))


def matches_in_order(expected: list[str], printed: str) -> str | None:
    """None when each expected line matches a printed line, in order; else the first that does not."""
    lines = printed.splitlines()
    i = 0
    for want in expected:
        while i < len(lines) and not line_matches(want, lines[i]):
            i += 1
        if i == len(lines):
            return want
        i += 1
    return None


def test_the_number_comparison_can_fail():
    assert line_matches("Vesta  13.67125037", "Vesta  13.67125038")       # one unit of the last digit
    assert not line_matches("Vesta  13.67125037", "Vesta  13.67125040")   # three units: a real change
    assert not line_matches("a 1.5 b", "a 1.5 c")


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
