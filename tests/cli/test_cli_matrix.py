"""Every command of the CLI in every format it offers, for a body of every theory family (issue 29).

The matrix is read from the CLI itself, so that nothing new escapes it:

* the commands are the typer app's command tree (sub-commands included, ``catalogue import``); a command that
  is not in :data:`SPECS` fails :func:`test_every_command_has_a_spec` until someone gives it arguments and a
  check, and a spec without a command fails it too;
* the formats are the choices of each command's ``--format`` option (a command without one runs once with its
  default output; ``plot`` takes its format from ``--out``'s suffix, checked against ``ephem.answers.figures.CONTENT_TYPES``,
  which is read here likewise, and its kinds from ``ephem.answers.figures.KINDS``);
* the families are one body each of the theories of ``ephem.families.THEORIES`` (a Sun-only main-belt asteroid,
  a Sun-only planet-crosser, the Earth, the Moon, Mars with its free wobble) and a body of a user's dataset that
  ``ephem catalogue import`` made from the samples in tests/data/import; a new theory family fails
  :func:`test_the_families_cover_every_theory` until a body of it joins :data:`FAMILIES`.

Each case runs in-process (typer's CliRunner) and asserts exit 0 and that the output parses: JSON loads and
holds the command's documented keys, CSV has its header and rows, a table its header, rule and rows; the files
written are well-formed (PNG chunks, SVG as XML, the PCK read by SPICE, the tables in their formats, the batch's
partitions by pyarrow). The cases where a family is not applicable are listed in :data:`NOT_APPLICABLE` and
must exit 3 with the reason, so a change of either behaviour fails here. Spans are short and steps coarse: the
whole file runs in about half a minute on one core.
"""
from __future__ import annotations

import csv
import io
import json
import math
import re
import tomllib
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import pytest
import typer
from typer.testing import CliRunner

from ephem import api
from ephem.answers import figures as plots
from ephem.exports import tables
from ephem.bodies.catalogue import get_body, load_catalogue
from ephem.cli import app, one_body

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "tests" / "data" / "import"
USER = "matrix"                           # the user dataset every "user" case reads
runner = CliRunner()


# ------------------------------------------------------------------ what the CLI offers, read from it

def command_tree() -> dict[str, object]:
    """Every leaf command of the CLI by its full name ("precession", "catalogue import")."""
    found = {}

    def walk(command, path):
        subs = getattr(command, "commands", None)
        if subs:
            for name, sub in subs.items():
                walk(sub, (*path, name))
        else:
            found[" ".join(path)] = command
    walk(typer.main.get_command(app), ())
    return found


def format_choices(command) -> list[str] | None:
    """The values the command's ``--format`` option accepts, or None when it has none."""
    option = next((p for p in command.params if "--format" in getattr(p, "opts", ())), None)
    if option is None:
        return None
    descriptor = getattr(option, "type_descriptor", None)          # typer >= 0.2x (its own click)
    choices = descriptor.choices if descriptor is not None else getattr(option.type, "choices", None)
    assert choices, f"{command.name}: --format is not a choice: its values cannot be enumerated"
    return [getattr(c, "value", c) for c in choices]


COMMANDS = command_tree()


# ------------------------------------------------------------------ the families

@dataclass(frozen=True)
class Family:
    body: str
    dataset: str = "current"
    published_wobble: bool = True       # a free-wobble amplitude J in the catalogue (Lara 2014, IERS, ...)

    def args(self) -> list[str]:
        return [self.body, "--dataset", self.dataset]

    def j_arcsec(self) -> list[str]:
        """The wobble amplitude a command needs when the catalogue gives none (a user of the asteroid would)."""
        return [] if self.published_wobble else ["--J-arcsec", "10"]


FAMILIES = {
    "sun_only": Family("vesta", published_wobble=False),        # the single-perturber ladder, main belt
    "planet_crosser": Family("itokawa", published_wobble=False),  # the same ladder, an orbit crossing the Earth's
    "earth": Family("earth"),                                  # the lunisolar theory
    "moon": Family("moon"),                                    # the synchronous rotator: Cassini state, librations
    "mars": Family("mars"),                                    # the ladder with a published free wobble
    "user": Family("eros", USER),                              # a body of a dataset made by `ephem catalogue import`
}


# ------------------------------------------------------------------ how each command is run and checked

@dataclass
class Case:
    command: str
    fmt: str | None         # the --format value (or plot's suffix); None: the command's default output
    variant: str            # a family, a kind-family pair (plot), a dataset, or an input file (catalogue import)
    out: Path               # a directory of the case's own for the files it writes

    @property
    def family(self) -> Family:
        return FAMILIES[self.variant.split(":")[-1]]


@dataclass
class Spec:
    args: Callable[[Case], list[str]]           # the command line after the command's name (without --format)
    check: Callable[[Case, object], None]       # the result (exit 0) parses and holds what is documented
    variants: Callable[[], list[str]] = lambda: list(FAMILIES)
    formats: Callable[[object], list[str | None]] | None = None   # default: the --format choices, or [None]
    format_args: Callable[[Case], list[str]] = lambda case: ["--format", case.fmt] if case.fmt else []


def _records(result) -> object:
    """The stdout of a JSON case, loaded (NaN and infinity are not JSON: the CLI refuses to write them)."""
    return json.loads(result.stdout, parse_constant=lambda word: pytest.fail(f"{word} in the JSON"))


def parse_table(text: str) -> tuple[list[str], list[list[str]]]:
    """(header, rows) of the CLI's aligned table: a header line, a rule of dashes per column, rows; every line
    as wide as the rule, each cell right-aligned in its column's span (what ``ephem.cli.common.rows_to_table`` writes)."""
    table, _, notes = text.partition("\n\n")        # the notes where a 1-sigma is a lower bound, after a blank line
    assert all(line.startswith("note: ") for line in notes.splitlines()), f"not a note after the table:\n{text}"
    lines = table.rstrip("\n").split("\n")
    assert len(lines) >= 3, f"a table needs a header, a rule and a row:\n{text}"
    rule = lines[1]
    spans = [m.span() for m in re.finditer(r"-+", rule)]
    assert spans and re.fullmatch(r"-+(  -+)*", rule.strip()), f"no rule under the header:\n{text}"
    assert all(len(line) == len(rule) for line in lines), f"the lines are not aligned:\n{text}"
    cells = [[line[a:b].strip() for a, b in spans] for line in lines]
    for line in lines:                                             # nothing between the columns
        gaps = "".join(line[b:a] for (_, b), (a, _) in zip(spans, spans[1:]))
        assert gaps.strip() == "", line
    assert all(cells[0]), f"a column without a name:\n{text}"
    return cells[0], cells[2:]


def parse_csv(text: str) -> tuple[list[str], list[dict]]:
    reader = csv.DictReader(io.StringIO(text))
    rows = list(reader)
    assert reader.fieldnames and rows, f"a CSV needs a header and a row:\n{text}"
    assert all(None not in row and None not in row.values() for row in rows), "a row of another width"
    return list(reader.fieldnames), rows


def check_rows(columns: Callable[[Case], list[str]], json_check: Callable[[Case, object], None],
               note: str | None = None, exact: bool = True):
    """A check of a command that prints JSON, CSV or a table of ``columns`` (exactly, or at least them); ``note``:
    the start of the line it writes to stderr with CSV and tables (the model, the body's identity), whose
    stdout must then be the table alone."""
    def check(case: Case, result) -> None:
        if case.fmt == "json":
            json_check(case, _records(result))
            return
        want, whole = columns(case), exact
        if case.fmt == "ecsv":              # astropy's table: the columns and more (the 1-sigma, the Delaunay ...)
            from astropy.table import QTable

            table = QTable.read(result.stdout, format="ascii.ecsv")
            header, rows = list(table.colnames), list(table)
            whole = exact and not {"jd_tdb", "year"} & set(want)    # an epoch table adds its per-epoch 1-sigma
            assert table.meta["source"].split()[1] == case.command, table.meta["source"]
        elif case.fmt == "csv":
            header, rows = parse_csv(result.stdout)
        else:
            header, rows = parse_table(result.stdout)
        assert (header == want) if whole else set(want) <= set(header), (header, want)
        assert rows
        if note is not None:
            lines = result.stderr.splitlines()
            assert lines and lines[-1].startswith(note), result.stderr
    return check


def has_keys(keys, nested: dict[str, set] | None = None):
    """A JSON check: the object holds ``keys``; ``nested``: keys of its sub-objects (or of every item of a list)."""
    def check(case: Case, answer) -> None:
        assert isinstance(answer, dict), type(answer)
        assert set(keys) <= set(answer), set(keys) - set(answer)
        for key, sub in (nested or {}).items():
            items = answer[key] if isinstance(answer[key], list) else [answer[key]]
            assert items, f"{key} is empty"
            for item in items:
                assert set(sub) <= set(item), (key, set(sub) - set(item))
    return check


def arrays(keys, then=None):
    """A JSON check of a time series: ``keys`` are arrays of one length >= 1 of finite numbers."""
    def check(case: Case, answer) -> None:
        has_keys(keys)(case, answer)
        lengths = {len(answer[k]) for k in keys}
        assert len(lengths) == 1 and lengths.pop() >= 1, {k: len(answer[k]) for k in keys}
        assert all(isinstance(v, (int, float)) and math.isfinite(v) for k in keys for v in answer[k]
                   if v is not None)
        if then is not None:
            then(case, answer)
    return check


MODEL_KEYS = {"name", "order", "estimated_error_mas", "error_terms_mas", "tolerance_mas", "cost_ms"}
PRECESSION_KEYS = ("body", "dataset", "obliquity_deg", "dynamical_ellipticity", "scaling_factor_arcsec_per_year",
                   "precession_rate_arcsec_per_year")
TERM_KEYS = ("period_days", "period_years", "longitude_sin_arcsec", "longitude_cos_arcsec", "obliquity_sin_arcsec",
             "obliquity_cos_arcsec")
HISTORY_KEYS = ("year", "obliquity_deg", "precession_angle_deg", "pole_ra_deg", "pole_dec_deg",
                "orbit_inclination_deg", "estimated_error_deg", "obliquity_error_deg")
SPAN = ["--start", "2000-01-01", "--stop", "2000-05-01"]


def _bodies_json(case: Case, answer) -> None:
    assert isinstance(answer, list) and answer
    assert all({"name", "naif_id", "kind", "dataset"} <= set(b) and b["dataset"] == case.variant for b in answer)


def _track_model(case: Case, answer) -> None:
    model = answer["model"]
    assert MODEL_KEYS | {"axis", "free_wobble", "rotation_scale"} <= set(model)
    if case.variant == "mars":   # the tolerance needs the free wobble and the liquid core: the track follows both
        assert model["free_wobble"] is not None and model["estimated_error_mas"] <= 80.0
        assert model["name"] == "nonrigid"


def _track_args(case: Case) -> list[str]:
    if case.variant == "mars":      # the README's example: the wobble's phase given, a tolerance that needs it
        return [*case.family.args(), "--start", "2000-01-01", "--stop", "2010-01-01", "--step-days", "1000",
                "--tolerance-mas", "80", "--free-wobble-phase-deg", "30"]
    return [*case.family.args(), *SPAN, "--step-days", "40"]


def _nutation_columns(case: Case) -> list[str]:
    # the Earth's and the Moon's terms are in the Delaunay arguments: their multipliers as five columns
    lead = ["multiple", *api.DELAUNAY_NAMES] if case.variant in ("earth", "moon") else ["multiple"]
    return [*lead, *TERM_KEYS]


# --- files

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def check_png(data: bytes) -> None:
    """The PNG signature, then chunks whose lengths add up, from IHDR (of a non-empty image) to IEND."""
    assert data[:8] == PNG_MAGIC, data[:8]
    pos, kinds = 8, []
    while pos < len(data):
        length = int.from_bytes(data[pos:pos + 4], "big")
        kinds.append(data[pos + 4:pos + 8])
        pos += 12 + length
    assert pos == len(data) and kinds[0] == b"IHDR" and kinds[-1] == b"IEND" and b"IDAT" in kinds, kinds
    width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
    assert width > 0 and height > 0


def check_svg(data: bytes) -> None:
    root = ET.fromstring(data)
    assert root.tag == "{http://www.w3.org/2000/svg}svg", root.tag
    assert len(list(root.iter())) > 10                           # drawn, not an empty canvas


FIGURE_CHECKS = {"png": check_png, "svg": check_svg}


def check_plot(case: Case, result) -> None:
    path = case.out / f"figure.{case.fmt}"
    assert result.stdout.startswith(f"wrote {path} (") and path.is_file()
    FIGURE_CHECKS[case.fmt](path.read_bytes())         # a new figure format: a KeyError until it has a check


def _plot_args(case: Case) -> list[str]:
    kind, family = case.variant.split(":")
    fam = FAMILIES[family]
    span = {"obliquity-history": ["--start", "-2000", "--stop", "0", "--step-years", "1000"],
            "free-wobble": ["--start", "2000-01-01", "--stop", "2000-01-03", *fam.j_arcsec()]}
    return [*fam.args(), "--kind", kind, *span.get(kind, ["--start", "2000-01-01", "--stop", "2002-01-01"]),
            "--dpi", "40", "--out", str(case.out / f"figure.{case.fmt}")]


def check_latex(text: str) -> None:
    """Environments nest and close, braces balance, every row of a tabular has its columns' count of cells."""
    stack = []
    for kind, env in re.findall(r"\\(begin|end)\{(\w+)\}", text):
        if kind == "begin":
            stack.append(env)
        else:
            assert stack and stack.pop() == env, env
    assert not stack, stack
    bare = re.sub(r"\\[{}]", "", text)
    assert bare.count("{") == bare.count("}")
    tabulars = re.findall(r"\\begin\{tabular\}\{([lrc]+)\}(.*?)\\end\{tabular\}", text, flags=re.S)
    assert tabulars
    for spec, body in tabulars:
        rows = [r for r in body.split("\\\\") if r.strip() and not re.fullmatch(r"\s*(\\\w+rule\s*)+", r)]
        assert rows and all(r.count("&") == len(spec) - 1 for r in rows), (spec, rows[:3])


def check_markdown(text: str) -> None:
    lines = text.splitlines()
    rules = [i for i, line in enumerate(lines) if re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", line)]
    assert rules
    for i in rules:                                 # the header above, rows below, all of the rule's width
        width = lines[i].count("|")
        assert lines[i - 1].count("|") == width and lines[i + 1].count("|") >= width


def check_table_file(fmt: str, text: str) -> None:
    if fmt == "csv":
        header, _ = parse_csv(text)
        assert "component" in header
    elif fmt == "json":
        doc = json.loads(text)
        assert {"body", "dataset", "layout", "tables"} <= set(doc) and all(t["rows"] for t in doc["tables"])
    elif fmt == "markdown":
        check_markdown(text)
    elif fmt == "latex":
        check_latex(text)
    else:
        pytest.fail(f"no check for the tables' format {fmt!r}: add one")


def check_tables(case: Case, result) -> None:
    fam = case.family
    name = get_body(fam.body, fam.dataset).name.lower().replace(" ", "_")
    want = {f"{name}_{fam.dataset}_{layout}.{tables.EXTENSIONS[case.fmt]}" for layout in tables.LAYOUTS}
    assert {p.name for p in case.out.iterdir()} == want
    assert result.stdout == f"wrote {len(want)} files for 1 bodies to {case.out}/\n"      # the progress: stderr
    for name in want:
        check_table_file(case.fmt, (case.out / name).read_text(encoding="utf-8"))


def check_pck(case: Case, result) -> None:
    """The kernel as SPICE reads it: the body's pole constants, and a pole at mid-span near the track's."""
    import spiceypy as spice

    path = case.out / "kernel.tpc"
    text = path.read_text(encoding="ascii")
    assert text.startswith("KPL/PCK") and "\\begindata" in text and "\\begintext" in text
    assert re.search(r"fitting error [\d.e+-]+ mas with \d+ angles", result.stdout) and result.stdout.endswith(
        f"wrote {path}\n")
    fam = case.family
    naif = get_body(fam.body, fam.dataset).naif_id
    spice.furnsh(str(path))
    try:
        assert spice.bodfnd(naif, "POLE_RA") and spice.bodfnd(naif, "POLE_DEC") and spice.bodfnd(naif, "PM")
        ans = api.track(fam.body, "2000-03-01", "2000-03-01", 1.0, dataset=fam.dataset)
        jd = ans["jd_tdb"][0]
        z = spice.tipbod("J2000", naif, (jd - 2451545.0) * 86400.0)[2]
        ra, dec = math.radians(ans["pole_ra_deg"][0]), math.radians(ans["pole_dec_deg"][0])
        want = (math.cos(dec) * math.cos(ra), math.cos(dec) * math.sin(ra), math.sin(dec))
        gap = math.degrees(math.acos(min(1.0, sum(a * b for a, b in zip(z, want)))))
        assert gap < 0.01, f"SPICE's pole is {gap:.3g} deg from the track's"      # the fit: well under 1 mas
    finally:
        spice.unload(str(path))


def check_demo(case: Case, result) -> None:
    assert result.stdout.startswith(f"Precession rates ({case.variant} dataset)\n")
    first, second = result.stdout.split("\n\n", 1)
    header, rows = parse_table(first.split("\n", 1)[1])
    assert header[0] == "body" and [r[0] for r in rows] == [b["name"] for b in api.list_bodies(dataset=case.variant)]
    title, table = second.split("\n", 1)
    assert re.fullmatch(r"Nutation of \w+ \(arcsec\), harmonics of the mean anomaly", title)
    header, rows = parse_table(table)
    assert header[0] == "multiple" and [r[0] for r in rows] == [str(k) for k in range(1, 7)]


# --- catalogue import: one sample per orbit format the option offers

ORBIT_SAMPLES = {"mpcorb": "mpcorb_sample.dat", "sbdb-json": "sbdb_sample.json", "sbdb-csv": "sbdb_sample.csv"}


def _import_args(case: Case) -> list[str]:
    # a new orbit format needs a sample file here: a KeyError until it has one
    return ["--orbits", str(SAMPLES / ORBIT_SAMPLES[case.fmt]), "--poles", str(SAMPLES / "poles_sample.csv"),
            "--name", f"import-{case.fmt}", "--force"]


def check_import(case: Case, result) -> None:
    m = re.fullmatch(r"(?:wrote|replaced) (.+): dataset 'import-[\w-]+', 3 bodies \(Ceres, Vesta, Eros\); select it "
                     r"with --dataset import-[\w-]+\n", result.stdout)
    assert m, result.stdout
    data = tomllib.loads(Path(m.group(1)).read_text(encoding="utf-8"))
    assert data
    listed = runner.invoke(app, ["bodies", "--dataset", f"import-{case.fmt}", "--format", "json"])
    assert listed.exit_code == 0 and [b["name"] for b in json.loads(listed.stdout)] == ["Ceres", "Vesta", "Eros"]


# --- batch: a table of the heliocentric families' bodies

BATCH_COLUMNS = ("name", "a_au", "e", "i_deg", "node_deg", "peri_deg", "mean_anomaly_deg", "epoch_jd_tdb",
                 "pole_ra_deg", "pole_dec_deg", "pole_epoch_jd_tdb", "rotation_period_hours", "dynamical_ellipticity")


def batch_bodies() -> list:
    """The families' bodies the batch's input can state: its orbits are heliocentric (docs/batch_input.md), so
    the Moon's cannot be given (the batch has no centre column)."""
    bodies = [get_body(f.body, f.dataset) for f in FAMILIES.values()]
    return [b for b in bodies if b.orbit.center == "Sun"]


def _batch_args(case: Case) -> list[str]:
    source = case.out / "bodies.csv"
    with open(source, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(BATCH_COLUMNS)
        for b in batch_bodies():
            o = b.orbit
            writer.writerow([b.name, o.a_au, o.e, o.i_deg, o.node_deg, o.peri_deg, o.mean_anomaly_deg, o.epoch_jd_tdb,
                             b.pole.ra_deg, b.pole.dec_deg, b.pole.epoch_jd_tdb, b.rotation_period_hours, b.hd])
    return [str(source), "--out", str(case.out / "answers"), "--scheduler", BATCH_CLUSTER["address"], "--quiet"]


def check_batch(case: Case, result) -> None:
    names = [b.name for b in batch_bodies()]
    assert result.stdout.startswith(f"{len(names)} rows (0 failed) in 1 partitions to "), result.stdout
    parts = sorted((case.out / "answers").glob(f"part-*.{case.fmt}"))
    assert len(parts) == 1, list((case.out / "answers").iterdir())
    if case.fmt == "parquet":
        import pyarrow.parquet as pq

        rows = pq.read_table(parts[0]).to_pylist()
    elif case.fmt == "csv":
        _, rows = parse_csv(parts[0].read_text(encoding="utf-8"))
    elif case.fmt == "ecsv":        # POST /v1/batch's ECSV: the obliquity in deg, an empty error read back masked
        from astropy.table import QTable

        table = QTable.read(parts[0], format="ascii.ecsv")
        assert table["obliquity_deg"].unit == "deg"
        rows = [{"name": n, "error": e or "", "obliquity_deg": o} for n, e, o in
                zip(table["name"].tolist(), table["error"].tolist(), table["obliquity_deg"].to_value("deg"))]
    else:
        pytest.fail(f"no check for the batch's format {case.fmt!r}: add one")
    assert [r["name"] for r in rows] == names and all(r["error"] == "" for r in rows)
    assert all(0.0 <= float(r["obliquity_deg"]) <= 180.0 for r in rows)


BATCH_CLUSTER: dict[str, str] = {}


# --- the specs

SPECS: dict[str, Spec] = {
    "bodies": Spec(
        args=lambda case: ["--dataset", case.variant],
        variants=lambda: ["current", "petit2014", USER],
        check=check_rows(lambda case: ["name", "naif_id", "kind", "dataset"], _bodies_json, exact=False)),
    "body": Spec(
        args=lambda case: case.family.args(),
        check=check_rows(lambda case: list(one_body.BODY_CSV_COLUMNS if case.fmt == "csv" else one_body.BODY_TABLE_COLUMNS),
                         has_keys(["name", "naif_id", "kind", "dataset", "dynamical_ellipticity", "perturbers",
                                   "values", "correlations"]), note="")),
    "precession": Spec(
        args=lambda case: case.family.args(),
        check=check_rows(lambda case: list(PRECESSION_KEYS), has_keys([*PRECESSION_KEYS, "model"],
                                                                       {"model": MODEL_KEYS}), exact=False)),
    "nutation": Spec(
        args=lambda case: [*case.family.args(), "--cut-mas", "10"] if case.variant == "earth" else case.family.args(),
        check=check_rows(_nutation_columns, has_keys(["body", "dataset", "terms", "model"],
                                                     {"terms": TERM_KEYS, "model": MODEL_KEYS}), exact=False)),
    "track": Spec(
        args=_track_args,
        check=check_rows(lambda case: [api.TRACK_KEYS[0], "utc_iso", *api.TRACK_KEYS[1:]],
                         arrays(api.TRACK_KEYS, _track_model), note="model: ")),
    "history": Spec(
        args=lambda case: [*case.family.args(), "--start-year", "-2000", "--stop-year", "0", "--step-years", "1000",
                           "--quiet"],
        check=check_rows(lambda case: list(HISTORY_KEYS),
                         arrays(HISTORY_KEYS, lambda case, a: has_keys(["model", "meaningful_from_year",
                                                                        "meaningful_to_year"])(case, a)),
                         note="model: ")),
    "free-motion": Spec(
        args=lambda case: [*case.family.args(), *SPAN, "--step-days", "30", *case.family.j_arcsec()],
        check=check_rows(lambda case: [api.FREE_MOTION_KEYS[0], "utc_iso", *api.FREE_MOTION_KEYS[1:]],
                         arrays(api.FREE_MOTION_KEYS, lambda case, a: has_keys(
                             ["wobble_period_days", "precession_period_days", "mode", "method"])(case, a)),
                         note="")),
    "tables": Spec(
        args=lambda case: [*case.family.args(), "--out", str(case.out)],
        check=check_tables),
    "plot": Spec(
        args=_plot_args,
        variants=lambda: [f"{kind}:{family}" for kind in plots.KINDS for family in FAMILIES],
        # the format is --out's suffix, refused unless plots.CONTENT_TYPES has it (ephem.cli.files.plot)
        formats=lambda command: list(plots.CONTENT_TYPES),
        format_args=lambda case: [],
        check=check_plot),
    "pck": Spec(
        args=lambda case: [*case.family.args(), *SPAN, "--out", str(case.out / "kernel.tpc")],
        check=check_pck),
    "batch": Spec(
        args=_batch_args,
        variants=lambda: ["table"],
        check=check_batch),
    "demo": Spec(
        args=lambda case: ["--dataset", case.variant],
        variants=lambda: ["current", "petit2014", USER],
        check=check_demo),
    "catalogue import": Spec(      # its --format is the orbit file's: one sample each
        args=_import_args,
        variants=lambda: ["samples"],
        check=check_import),
}

#: (command, variant) -> what the refusal says: the family is not applicable to the command (exit 3)
NOT_APPLICABLE = {
    # no long-term orbit serves a planet-crosser: the secular theory excludes orbits meeting a planet's, and the
    # shipped N-body orbits are the catalogue's main-belt and planetary bodies' (docs/long_term.md)
    ("history", "planet_crosser"): "no orbit model serves this span",
    ("plot", "obliquity-history:planet_crosser"): "no orbit model serves this span",
}


def cases() -> list:
    params = []
    for name, command in sorted(COMMANDS.items()):
        spec = SPECS.get(name)
        if spec is None:
            continue                            # test_every_command_has_a_spec says so
        formats = spec.formats(command) if spec.formats else (format_choices(command) or [None])
        for fmt in formats:
            for variant in spec.variants():
                params.append(pytest.param(name, fmt, variant, id=f"{name}-{fmt or 'default'}-{variant}"))
    return params


CASES = cases()


# ------------------------------------------------------------------ fixtures

@pytest.fixture(scope="module", autouse=True)
def user_dataset(tmp_path_factory):
    """A user catalogue directory of this module's own holding the dataset USER, imported by the CLI from the
    shipped samples (the other modules' user directory is left as it was)."""
    where = tmp_path_factory.mktemp("user-catalogue")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("EPHEM_USER_CATALOGUE_DIR", str(where))
        load_catalogue.cache_clear()
        res = runner.invoke(app, ["catalogue", "import", "--orbits", str(SAMPLES / "mpcorb_sample.dat"),
                                  "--poles", str(SAMPLES / "poles_sample.csv"), "--name", USER])
        assert res.exit_code == 0, res.output
        yield where
    load_catalogue.cache_clear()


@pytest.fixture(scope="module")
def batch_cluster():
    """One single-threaded worker in this process on 127.0.0.1 (starts in ~0.1 s; ephem batch's own local
    cluster of processes costs seconds), given to ephem batch as --scheduler."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, host="127.0.0.1", protocol="tcp://",
                      dashboard_address="127.0.0.1:0") as cluster:
        BATCH_CLUSTER["address"] = cluster.scheduler_address
        yield cluster.scheduler_address
    BATCH_CLUSTER.clear()


# ------------------------------------------------------------------ the tests

def test_every_command_has_a_spec():
    # a new command fails here until it is given arguments and a check in SPECS; a removed one, until its spec goes
    assert set(COMMANDS) == set(SPECS), {"without a spec": sorted(set(COMMANDS) - set(SPECS)),
                                         "spec of no command": sorted(set(SPECS) - set(COMMANDS))}


def test_the_formats_are_read_from_the_options():
    # the introspection reads what the parser accepts: a format it would miss is one the matrix would not run
    assert format_choices(COMMANDS["track"]) == ["json", "csv", "table", "ecsv"]
    assert format_choices(COMMANDS["body"]) == ["json", "csv", "table"]      # a record: a unit per value
    assert format_choices(COMMANDS["tables"]) == list(tables.FORMATS)
    assert format_choices(COMMANDS["catalogue import"]) == list(ORBIT_SAMPLES)
    assert format_choices(COMMANDS["pck"]) is None
    assert len(CASES) >= 150


def test_the_families_cover_every_theory():
    # one body per theory the registry serves, Mars' ladder with a published free wobble, a user's body
    from ephem.families import THEORIES, theory_for

    served = {}
    for key, fam in FAMILIES.items():
        if fam.dataset == USER:
            continue                                       # checked below, once the dataset exists
        body = get_body(fam.body, fam.dataset)
        served[key] = type(theory_for(body, body.perturbers).inner)
    assert set(served.values()) == set(THEORIES), served
    user = get_body(FAMILIES["user"].body, USER)
    assert user.dataset == USER and type(theory_for(user, user.perturbers).inner) in THEORIES


@pytest.mark.parametrize("command, fmt, variant", CASES)
def test_command_format_family(command, fmt, variant, tmp_path, request):
    spec = SPECS[command]
    if command == "batch":
        request.getfixturevalue("batch_cluster")
    case = Case(command, fmt, variant, tmp_path)
    argv = [*command.split(), *spec.args(case), *spec.format_args(case)]
    res = runner.invoke(app, argv)
    if res.exception is not None and not isinstance(res.exception, SystemExit):
        raise res.exception                                 # a crash: its own traceback
    why = NOT_APPLICABLE.get((command, variant))
    if why is not None:
        assert res.exit_code == 3, (argv, res.output)
        name = get_body(case.family.body, case.family.dataset).name
        assert res.stderr.startswith(f"error: not applicable to {name}:"), res.stderr
        assert why in res.stderr and res.stdout == "", res.output
        assert not [p for p in tmp_path.rglob("*") if p.is_file()]         # nothing written
        return
    assert res.exit_code == 0, (argv, res.output)
    assert "Traceback" not in res.output
    spec.check(case, res)


def test_the_not_applicable_cases_are_in_the_matrix():
    # a listed case that the matrix no longer runs would pass silently
    ran = {(p.values[0], p.values[2]) for p in CASES}
    assert set(NOT_APPLICABLE) <= ran, set(NOT_APPLICABLE) - ran


def test_a_user_dataset_without_vesta_has_a_demo(tmp_path, monkeypatch):
    # `ephem demo` showed Vesta's nutation whatever the dataset: a user's dataset without Vesta was a traceback
    monkeypatch.setenv("EPHEM_USER_CATALOGUE_DIR", str(tmp_path))
    load_catalogue.cache_clear()
    poles = tmp_path / "eros.csv"
    poles.write_text("\n".join(line for line in (SAMPLES / "poles_sample.csv").read_text().splitlines()
                               if not line.lower().startswith(("ceres,", "vesta,"))) + "\n")
    res = runner.invoke(app, ["catalogue", "import", "--orbits", str(SAMPLES / "mpcorb_sample.dat"), "--poles",
                              str(poles), "--name", "eros-only", "--skip-unmatched"])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["demo", "--dataset", "eros-only"])
    assert res.exit_code == 0, res.output
    assert "Nutation of Eros (arcsec), harmonics of the mean anomaly" in res.stdout
    load_catalogue.cache_clear()


def test_history_json_is_the_readme_example():
    # the README's `ephem history ceres --start-year -30000 --stop-year 0 --step-years 10000` in its default
    # format ended in "Object of type ndarray is not JSON serializable"
    res = runner.invoke(app, ["history", "ceres", "--start-year", "-30000", "--stop-year", "0", "--step-years",
                              "10000", "--quiet"])
    assert res.exit_code == 0, res.output
    answer = json.loads(res.stdout)
    assert answer["year"] == [-30000.0, -20000.0, -10000.0, 0.0]
    assert answer["obliquity_deg"][0] == pytest.approx(9.9417, abs=1e-3)      # the README's table: 9.941…
