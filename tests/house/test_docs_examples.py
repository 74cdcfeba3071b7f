"""Every example in README.md and docs/*.md runs: Python as doctests, `$ ephem …` (or `$ .venv/bin/ephem …`)
through the CLI, `$ curl …` through the service. A shown output line must match a printed line (… stands for
any text, numbers match within one unit of their last shown digit), in order.

How the ```console blocks are read:
- `$ COMMAND`: a command, shell-quoted; a trailing `# remark` is a shell comment; a quote left open continues
  the command on the next lines (a curl `-d '{…}'` body written over several lines); `> FILE` and curl's
  `-o FILE` send the output to FILE. A command must be complete (no `…`): readers copy them.
- the other lines: expected output. A line that starts with whitespace continues a line of compact JSON above
  it (one that starts with {" or [{), joined to it without the line break and the indentation: long JSON is
  wrapped for the page between two of its tokens. Other indented lines are lines of their own (a table's
  header, indented JSON). Two or more spaces then `#` start a remark for the reader, not output. A run of
  spaces matches any run of spaces (a table's columns). Numbers that change from run to run (timings) or
  with the machine (rounding noise) are shown as `…`.
"""
import doctest
import re
import shlex
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from ephem.cli import app as cli
from service.app import app as web

ROOT = Path(__file__).resolve().parents[2]
API_DOC = ROOT / "docs" / "api.md"
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

REMARK = re.compile(r"\s{2,}#.*$")          # "output  # a remark for the reader"


def _complete(command: str) -> bool:
    try:
        shlex.split(command, comments=True)
    except ValueError:                      # "No closing quotation": the command goes on, on the next line
        return False
    return True


def console_examples(text: str) -> list[tuple[str, list[str]]]:
    """(command, expected lines) of every `$ ` line in the ```console blocks."""
    examples = []
    for block in re.findall(r"```console\n(.*?)```", text, flags=re.S):
        lines = iter(block.splitlines())
        for line in lines:
            if line.startswith("$ "):
                command = line[2:]
                while not _complete(command):
                    command += "\n" + next(lines)
                examples.append((command, []))
            elif examples and line.strip():
                want = REMARK.sub("", line).rstrip()
                if line[0].isspace() and examples[-1][1] and examples[-1][1][-1].startswith(('{"', "[{")):
                    examples[-1][1][-1] += want.lstrip()
                else:
                    examples[-1][1].append(want)
    return examples


def python_blocks(text: str) -> list[str]:
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


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


def _literal(text: str) -> str:
    """``text`` as a pattern in which a run of spaces matches any run of spaces."""
    return re.sub(r"(?:\\ )+", " +", re.escape(text))


def line_matches(want: str, line: str) -> bool:
    """``want`` (… for any text, numbers within one unit of their last digit) matches the printed ``line``."""
    parts = []
    for chunk in want.strip().split("…"):
        pos, pieces = 0, []
        for m in NUMBER.finditer(chunk):
            pieces.append(_literal(chunk[pos:m.start()]) + f"({NUMBER.pattern})")
            pos = m.end()
        pieces.append(_literal(chunk[pos:]))
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
    assert line_matches("x     1  …", "x  1.0000000001        7e-17") and not line_matches("x 1", "x1")


def test_the_console_reader():
    text = ("```console\n"
            "$ ephem track mars --format table   # a remark\n"
            "model: real_orbit, … ms        # on stderr\n"
            "     jd_tdb  psi_arcsec\n"
            "$ curl -s -X POST 127.0.0.1:8000/x -d '{\n"
            '    "a": 1}\' > out.json\n'
            '{"a":1,\n'
            ' "b":2}\n'
            "```\n")
    assert console_examples(text) == [("ephem track mars --format table   # a remark", ["model: real_orbit, … ms", "     jd_tdb  psi_arcsec"]),
                                      ("curl -s -X POST 127.0.0.1:8000/x -d '{\n    \"a\": 1}' > out.json",
                                       ['{"a":1,"b":2}'])]


def run(command: str) -> tuple[int, str]:
    """Exit status and what the command prints: stderr (the docs show its notes first), then stdout unless
    `> FILE` or curl's `-o FILE` sends it to FILE."""
    argv = shlex.split(command, comments=True)
    target = None
    if ">" in argv:
        i = argv.index(">")
        argv, target = argv[:i] + argv[i + 2:], argv[i + 1]
    if Path(argv[0]).name == "ephem":                 # ephem or .venv/bin/ephem
        res = CliRunner().invoke(cli, argv[1:])
        status, out, err = res.exit_code, res.stdout_bytes, res.stderr
    else:
        assert argv[0] == "curl", command
        (status, out), err = curl(argv[1:]), ""
        if "-o" in argv:
            target = argv[argv.index("-o") + 1]
    if target is not None:
        Path(target).write_bytes(out)
        return status, err
    return status, err + out.decode()


def curl(args: list[str]) -> tuple[int, bytes]:
    """curl's options the docs use, through the service's test client; status 22 for an HTTP error (as -f)."""
    method, data, headers, url = "GET", None, {}, None
    it = iter(args)
    for arg in it:
        if arg == "-X":
            method = next(it)
        elif arg == "-d":
            data, method = next(it), ("POST" if method == "GET" else method)
        elif arg == "-o":
            next(it)
        elif arg == "-H":
            name, value = next(it).split(":", 1)
            headers[name.strip()] = value.strip()
        elif not arg.startswith("-"):
            url = arg
    path = re.sub(r"^(?:https?://)?[^/]+", "", url)    # 127.0.0.1:8000/… with or without http://
    r = TestClient(web).request(method, path, content=data, headers=headers)
    return (0 if r.status_code < 400 else 22), r.content


def _examples(pages) -> list:
    return [pytest.param(page, command, expected, id=f"{page.name}: {REMARK.sub('', command.splitlines()[0])[:70]}")
            for page in pages for command, expected in console_examples(page.read_text(encoding="utf-8"))]


EXAMPLES = _examples(PAGES)


def test_every_example_block_runs():
    pages = {p.name for p, *_ in (e.values for e in EXAMPLES)}
    assert {"README.md", "api.md", "earth.md"} <= pages, pages
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for block in python_blocks(text):               # a Python block without >>> would run nowhere
            assert block.lstrip().startswith(">>> "), f"{page.name}: a ```python block that is not a doctest:\n{block}"


def test_the_api_page_has_examples_for_every_route_and_command():
    commands = " ".join(c for c, _ in console_examples(API_DOC.read_text(encoding="utf-8")))
    for route in [r.path for r in web.routes if getattr(r, "include_in_schema", False)]:
        pattern = re.sub(r"\{[^}]+\}", "[^/?']+", route) + r"(?:[?']|$)"
        assert re.search(pattern, commands), f"no example of {route}"
    for command in cli.registered_commands:
        name = command.name or command.callback.__name__.replace("_", "-")
        if name != "demo":
            assert f"ephem {name}" in commands, f"no example of ephem {name}"


@pytest.mark.parametrize("page,command,expected", EXAMPLES)
def test_console_example(page, command, expected, tmp_path, monkeypatch):
    assert "…" not in command, "write the command in full: readers copy it"
    monkeypatch.chdir(tmp_path)                    # commands that write files write here
    status, printed = run(command)
    refused = any(line.startswith(("error:", '{"type":')) for line in expected)
    assert (status != 0) == refused, printed
    missing = matches_in_order(expected, printed)
    assert missing is None, f"{missing!r} not in:\n{printed}"


@pytest.mark.parametrize("page", [p for p in PAGES if ">>> " in p.read_text(encoding="utf-8")], ids=lambda p: p.name)
def test_python_examples(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)                    # examples that write files write here
    result = doctest.testfile(str(page), module_relative=False, optionflags=doctest.ELLIPSIS
                              | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.attempted > 0 and result.failed == 0, result
