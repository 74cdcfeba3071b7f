"""Nutation tables: the paper's layouts in CSV, Markdown, LaTeX and JSON carry the same numbers, and the LaTeX
is well formed. That the amp-period layout reproduces Petit et al. (2014) Tables 9-10:
tests/forced/test_against_petit2014.py (which reads the CSV back with :func:`parse`)."""
import csv
import io
import json
import re

import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.cli import app
from ephem.base.constants import MAS
from ephem.base.errors import InvalidInputError
from ephem.orbit.lunar import DELAUNAY_NAMES
from ephem.exports.tables import FORMATS, LAYOUTS, _COLUMNS, latex_escape, render_nutation, table_rows

FORMAT_NAMES = tuple(FORMATS)


@pytest.fixture(scope="module")
def vesta():
    return api.nutation("vesta", dataset="petit2014", order=4)


def latex_problems(text: str) -> list[str]:
    """What is wrong with a LaTeX fragment of tables: unbalanced braces or math, mismatched environments,
    unescaped specials, tabular rows with the wrong number of cells. Empty when well formed."""
    problems = []
    depth, stack, dollars = 0, [], 0
    unescaped = re.sub(r"\\[\\{}$&%#_]", "", text)            # drop escaped specials and \\ row ends
    for ch in unescaped:
        depth += ch == "{"
        depth -= ch == "}"
        if depth < 0:
            problems.append("a } closes nothing")
            depth = 0
    if depth:
        problems.append(f"{depth} unclosed {{")
    dollars = unescaped.count("$")
    if dollars % 2:
        problems.append("odd number of $")
    if re.search(r"[%#_]", re.sub(r"\$[^$]*\$", "", unescaped)):
        problems.append("unescaped % # or _ outside math")
    columns = None
    for line in text.splitlines():
        for kind, name in re.findall(r"\\(begin|end)\{(\w+)\}", line):
            if kind == "begin":
                stack.append(name)
            elif not stack or stack.pop() != name:
                problems.append(f"\\end{{{name}}} does not match")
        spec = re.search(r"\\begin\{tabular\}\{([lrc]+)\}", line)
        if spec:
            columns = len(spec.group(1))
        elif columns and "&" in re.sub(r"\\&", "", line):
            cells = len(re.split(r"(?<!\\)&", line))
            if cells != columns:
                problems.append(f"row with {cells} cells in a {columns}-column tabular: {line}")
            if not line.rstrip().endswith(r"\\"):
                problems.append(f"row does not end with \\\\: {line}")
    if stack:
        problems.append(f"unclosed environments {stack}")
    return problems


def test_the_checker_catches_what_it_should():
    assert latex_problems(r"\begin{table}\begin{tabular}{rl}a & b \\ \end{tabular}\end{table}") == []
    assert latex_problems(r"\begin{table}") and latex_problems(r"{") and latex_problems("$x")
    assert latex_problems(r"\begin{tabular}{rl}" + "\n" + r"a & b & c \\" + "\n" + r"\end{tabular}")
    assert latex_problems("50% of_it")


@pytest.mark.parametrize("layout", LAYOUTS)
def test_latex_is_well_formed(vesta, layout):
    text = render_nutation(vesta, "latex", layout=layout)
    assert latex_problems(text) == []
    assert text.count(r"\begin{table}") == 2 and r"\toprule" in text and r"\bottomrule" in text


def test_latex_escapes_a_users_body_name(vesta):
    odd = dict(vesta, body="my_rock #1 & 50% {test}")
    assert latex_problems(render_nutation(odd, "latex")) == []
    assert latex_escape("a_b&c") == r"a\_b\&c"


def parse(text: str, fmt: str, layout: str) -> dict:
    """(component, multiple) -> {column: value} read back from a rendered table."""
    keys = [k for k, *_ in _COLUMNS[layout]]
    out = {}
    if fmt == "csv":
        for r in csv.DictReader(io.StringIO(text)):
            out[(r["component"], int(r["multiple"]))] = {k: float(r[k]) for k in keys}
    elif fmt == "json":
        doc = json.loads(text)
        for table in doc["tables"]:
            for r in table["rows"]:
                out[(table["component"], r["multiple"])] = {k: r[k] for k in keys}
    else:
        comp = None
        for line in text.splitlines():
            if line.startswith("**") or r"\caption" in line:      # each table opens with its caption
                comp = "longitude" if "in longitude" in line else "obliquity"
            else:
                sep = "|" if fmt == "markdown" else "&"
                cells = [c.strip() for c in line.strip().strip("|").replace(r"\\", "").split(sep)]
                if len(cells) != len(keys) + 1 or not re.match(r"-?\d+\.\d+", cells[0]):
                    continue
                arg = cells[-1].replace("$", "")
                multiple = 1 if arg == "M" else int(arg[:-1])
                out[(comp, multiple)] = {k: float(c.replace("$", "").split("±")[0].split(r"\pm")[0])
                                         for k, c in zip(keys, cells)}
    return out


@pytest.mark.parametrize("layout", LAYOUTS)
def test_every_format_carries_the_same_numbers(vesta, layout):
    rows = {(r["component"], r["multiple"]): r for r in table_rows(vesta, layout)}
    assert len(rows) == 2 * len(vesta["terms"])
    for fmt in FORMAT_NAMES:
        got = parse(render_nutation(vesta, fmt, layout=layout), fmt, layout)
        assert set(got) == set(rows), fmt
        for key, values in got.items():
            for column, value in values.items():
                places = {"amp_mas": 2, "period_days": 4}.get(column, 4) if layout == "amp-period" else 4
                exact = fmt in ("csv", "json")   # they print repr(), which reads back to the same double
                assert value == pytest.approx(rows[key][column], abs=0 if exact else 0.51 * 10.0**-places), \
                    (fmt, key, column)


def test_amp_columns_agree_between_layouts(vesta):
    a = {(r["component"], r["multiple"]): r for r in table_rows(vesta, "sin-cos")}
    b = {(r["component"], r["multiple"]): r for r in table_rows(vesta, "amp-period")}
    for key in a:
        # one scaling by 1000 or 365.25 and a product on each side: ≤ 4 roundings, rel 1e-15 = 4.5 ε
        assert b[key]["amp_mas"] * MAS == pytest.approx(a[key]["amp_arcsec"] * 1000 * MAS, rel=1e-15)
        assert b[key]["period_days"] / 365.25 == pytest.approx(a[key]["period_years"], rel=1e-15)


@pytest.mark.parametrize("kwargs,field", [({"layout": "wide"}, "layout"), ({"fmt": "pdf"}, "format")])
def test_bad_layout_or_format_names_the_field(vesta, kwargs, field):
    with pytest.raises(InvalidInputError, match=field):
        render_nutation(vesta, kwargs.get("fmt", "csv"), layout=kwargs.get("layout", "sin-cos"))


def test_cli_writes_the_whole_catalogue(tmp_path):
    res = CliRunner().invoke(app, ["tables", "--dataset", "current", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    assert "skipped" not in res.stderr          # every body answers, the Moon with its physical librations
    bodies = [b["name"] for b in api.list_bodies(dataset="current")]
    files = sorted(p.name for p in tmp_path.iterdir())
    assert len(files) == len(bodies) * 2 * 4
    assert "vesta_current_amp-period.tex" in files and "earth_current_sin-cos.json" in files
    assert "moon_current_amp-period.csv" in files
    one = CliRunner().invoke(app, ["tables", "ceres", "--format", "latex", "--layout", "sin-cos", "--out",
                                   str(tmp_path / "one")])
    assert one.exit_code == 0 and [p.name for p in (tmp_path / "one").iterdir()] == ["ceres_current_sin-cos.tex"]
    bad = CliRunner().invoke(app, ["tables", "ceres", "--format", "pdf", "--out", str(tmp_path / "bad")])
    assert bad.exit_code == 2 and "format" in bad.stderr


def test_route_serves_both_layouts(client_factory=None):
    from fastapi.testclient import TestClient

    from service.app import app as web

    c = TestClient(web)
    r = c.get("/v1/bodies/vesta/nutation?dataset=petit2014&order=4&format=table-json&layout=amp-period")
    assert r.status_code == 200 and r.headers["content-type"].startswith("application/json")
    assert r.json()["layout"] == "amp-period" and r.json()["tables"][0]["rows"][1]["amp_mas"] == pytest.approx(
        1715.42, abs=0.05 + 2e-4 * 1715.42)
    tex = c.get("/v1/bodies/vesta/nutation?format=latex&layout=amp-period").text
    # each Amp header names its quantity (issue 41): the pole's displacement, Δψ sin ε in longitude, Δε in obliquity
    assert latex_problems(tex) == [] and r"Amp $\Delta\psi \sin\varepsilon$ (mas)" in tex
    assert r"Amp $\Delta\varepsilon$ (mas)" in tex
    assert c.get("/v1/bodies/vesta/nutation?format=latex&layout=wide").status_code == 422


# ----------------------------------------------------------------------------- the Earth's lunisolar series

@pytest.fixture(scope="module")
def earth():
    return api.nutation("earth")          # the Moon and the Sun: terms in the Delaunay arguments


def parse_earth(text: str, fmt: str, layout: str) -> dict:
    """(component, arg) -> {column: value} read back from an Earth table."""
    keys = {"sin-cos": ["sin_arcsec", "cos_arcsec", "amp_arcsec", "period_years"],
            "amp-period": ["amp_mas", "period_days"]}[layout]
    out = {}
    if fmt == "csv":
        rows = list(csv.DictReader(io.StringIO(text)))
        assert "multiple" not in rows[0] and list(rows[0])[:7] == ["component", "arg", *DELAUNAY_NAMES]
        for r in rows:
            out[(r["component"], r["arg"])] = {k: float(r[k]) for k in keys}
            out[(r["component"], r["arg"])]["k"] = [int(r[c]) for c in DELAUNAY_NAMES]
    elif fmt == "json":
        for table in json.loads(text)["tables"]:
            for r in table["rows"]:
                out[(table["component"], r["arg"])] = {k: r[k] for k in keys}
                out[(table["component"], r["arg"])]["k"] = [r[c] for c in DELAUNAY_NAMES]
    else:
        comp = None
        for line in text.splitlines():
            if line.startswith("**") or r"\caption" in line:
                comp = "longitude" if "in longitude" in line else "obliquity"
                continue
            sep = "|" if fmt == "markdown" else "&"
            cells = [c.strip() for c in line.strip().strip("|").replace(r"\\", "").split(sep)]
            if len(cells) != len(keys) + 1 or not re.match(r"-?\d+\.\d+", cells[0]):
                continue
            arg = cells[-1]
            if fmt == "latex":   # $2F-2D+2\Omega$ -> 2F−2D+2Ω
                arg = arg.strip("$").replace("-", "−").replace(r"\Omega", "Ω").replace("l'", "l′")
            # "value ± σ" (the Earth's σ, from H_d's): the value is what is read back here
            out[(comp, arg)] = {k: float(re.split(r" ± | \$\\pm\$ ", c)[0]) for k, c in zip(keys, cells)}
    return out


@pytest.mark.parametrize("layout", LAYOUTS)
def test_earth_tables_carry_the_arguments_in_every_format(earth, layout):
    rows = {(r["component"], r["arg"]): r for r in table_rows(earth, layout)}
    assert len(rows) == 2 * len(earth["terms"])               # every argument written once per component
    assert rows[("longitude", "2F−2D+2Ω")]["D"] == -2 and rows[("obliquity", "Ω")]["Omega"] == 1
    for fmt in ("csv", "json", "markdown", "latex"):
        text = render_nutation(earth, fmt, layout=layout)
        got = parse_earth(text, fmt, layout)
        assert set(got) == set(rows), fmt
        for key, values in got.items():
            if "k" in values:
                assert values.pop("k") == [rows[key][c] for c in DELAUNAY_NAMES]
            for column, value in values.items():
                places = {"amp_mas": 2, "period_days": 4}.get(column, 4)
                exact = fmt in ("csv", "json")   # they print repr(), which reads back to the same double
                assert value == pytest.approx(rows[key][column], abs=0 if exact else 0.51 * 10.0**-places)
        if fmt == "latex":
            assert latex_problems(text) == []
            assert r"$2F-2D+2\Omega$" in text and r"$l'$" in text
    assert "Delaunay arguments l, l′, F, D, Ω" in render_nutation(earth, "markdown", layout=layout)


def test_asteroid_tables_keep_their_columns():
    vesta = api.nutation("vesta", dataset="petit2014", order=4)
    assert render_nutation(vesta, "csv").splitlines()[0].startswith("component,multiple,arg,")
    assert "Delaunay" not in render_nutation(vesta, "markdown")
