"""Bring your own data: `ephem catalogue import` (ephem/bodies/importer.py with orbit_files, pole_table and
import_records; docs/catalogue_import.md).

The sample files in tests/data/import/ carry the values of data/catalogue/current.toml (its MPCORB records for
Ceres, Vesta and Eros, its WGCCRE poles and periods, its moments) in the formats users have: the MPC's MPCORB
layout, the SBDB API's JSON, the SBDB query's CSV, and a pole/period CSV. So the import must reproduce the
shipped elements to their printed digits, and the imported dataset must give the shipped dataset's answers.
Every dataset is written into a temporary directory through $EPHEM_USER_CATALOGUE_DIR; nothing uses the network.
"""
import ast
import hashlib
import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from ephem import api
from ephem.bodies.catalogue import load_catalogue
from ephem.bodies.datasets import available_datasets, user_catalogue_dir
from ephem.bodies.import_records import CatalogueImportError
from ephem.bodies.importer import import_catalogue
from ephem.bodies.orbit_files import julian_day, parse_mpcorb, parse_orbits, unpack_designation, unpack_epoch
from ephem.bodies.pole_table import parse_poles
from ephem.cli import app as cli
from ephem.base.errors import InvalidInputError

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data" / "import"
MPCORB, SBDB_JSON, SBDB_CSV, POLES = (DATA / "mpcorb_sample.dat", DATA / "sbdb_sample.json", DATA / "sbdb_sample.csv",
                                      DATA / "poles_sample.csv")
BODIES = ("Ceres", "Vesta", "Eros")
ELEMENTS = {"a": "a_au", "e": "e", "i": "i_deg", "node": "node_deg", "peri": "peri_deg",
            "mean_anomaly": "mean_anomaly_deg", "epoch": "epoch_jd_tdb"}

#: a printed value written and read back through the import: its decimal digits survive, so only the last
#: binary digit may differ (1e-15 relative); anything more is a parsing error
READ_BACK = 1e-15


@pytest.fixture
def user_dir(tmp_path, monkeypatch):
    where = tmp_path / "user-catalogue"
    monkeypatch.setenv("EPHEM_USER_CATALOGUE_DIR", str(where))
    return where


# ------------------------------------------------------------------------------------------ parsing

def test_the_packed_epochs_and_designations_unpack():
    assert unpack_epoch("K25BL") == (2025, 11, 21) and julian_day(2025, 11, 21) == pytest.approx(2461000.5, abs=1e-9)
    assert unpack_epoch("K156R") == (2015, 6, 27) and julian_day(2015, 6, 27) == pytest.approx(2457200.5, abs=1e-9)   # current.toml: Steins
    assert julian_day(2000, 1, 1.5) == pytest.approx(2451545.0, abs=1e-9)
    assert unpack_designation("00001") == "1" and unpack_designation("A0345") == "100345"
    assert unpack_designation("K07Tf8A") == "2007 TA418" and unpack_designation("J95X00A") == "1995 XA"
    for bad in ("K25BZ", "K25D0", "X25BL", "K2BL", "K2502"):
        with pytest.raises(ValueError):
            unpack_epoch(bad)


@pytest.mark.parametrize("path", [MPCORB, SBDB_JSON, SBDB_CSV], ids=lambda p: p.name)
def test_parsing_reproduces_the_catalogue_elements(path):
    """The samples hold the MPCORB records current.toml quotes: the same numbers to their printed digits."""
    orbits = {o.name: o for o in parse_orbits(path.read_text(encoding="utf-8"), path.name)}
    assert sorted(orbits) == sorted(BODIES)
    current = load_catalogue("current")
    for name in BODIES:
        shipped = current.get(name)
        for key, attr in ELEMENTS.items():
            assert getattr(orbits[name].orbit, attr) == getattr(shipped.orbit, attr), (name, key)
            assert orbits[name].values[key].value == shipped.values[f"orbit.{key}"].value, (name, key)


def test_the_format_is_detected_and_the_mpc_names_have_aliases():
    from ephem.bodies.orbit_files import detect_format

    assert [detect_format(p.read_text(encoding="utf-8"), p.name) for p in (MPCORB, SBDB_JSON, SBDB_CSV)] == \
        ["mpcorb", "sbdb-json", "sbdb-csv"]
    ceres = parse_mpcorb(MPCORB.read_text(encoding="utf-8"), MPCORB.name)[0]
    assert ceres.name == "Ceres" and {"(1) Ceres", "1", "00001"} <= set(ceres.aliases)
    assert ceres.line == 11                              # after MPCORB.DAT's header, counted in the file
    assert "JD TT" in ceres.values["epoch"].note and "TT - TDB < 2 ms" in ceres.values["epoch"].note


def test_sigmas_become_uncertainties():
    ceres = parse_orbits(SBDB_JSON.read_text(encoding="utf-8"), SBDB_JSON.name)[0]
    assert ceres.values["e"].uncertainty == pytest.approx(4.1e-12, rel=READ_BACK) and ceres.values["e"].note is None
    vesta = parse_orbits(SBDB_CSV.read_text(encoding="utf-8"), SBDB_CSV.name)[1]
    assert vesta.values["a"].uncertainty is None and vesta.values["a"].note == "no uncertainty given in the import"
    poles = {p.name: p for p in parse_poles(POLES.read_text(encoding="utf-8"), POLES.name)}
    assert poles["EROS"].values["pole_ra_deg"].uncertainty == pytest.approx(0.02, rel=READ_BACK)
    assert poles["Ceres"].values["rotation_period_hours"].uncertainty == pytest.approx(1.9060312535174382e-08, rel=READ_BACK)


# ------------------------------------------------------------------------------------------ round trip

@pytest.mark.parametrize("path", [MPCORB, SBDB_JSON, SBDB_CSV], ids=lambda p: p.name)
def test_the_round_trip_gives_the_shipped_answers(path, user_dir):
    name = "mine-" + path.suffix.lstrip(".")
    result = import_catalogue(path, POLES, name)
    assert result.path == user_dir / f"{name}.toml" and result.path.is_file()
    assert name in available_datasets() and available_datasets()[:2] == ["current", "petit2014"]
    cat = load_catalogue(name)
    assert cat.names == list(BODIES)
    for body in BODIES:
        mine, shipped = api.precession(body, dataset=name), api.precession(body, dataset="current")
        assert mine["dataset"] == name
        for key in ("precession_rate_arcsec_per_year", "obliquity_deg", "dynamical_ellipticity",
                    "scaling_factor_arcsec_per_year"):
            # the same printed digits in both files: the same floats, so the same answer to rounding
            assert mine[key] == pytest.approx(shipped[key], rel=1e-12, abs=0), (body, key)
    assert cat.get("Vesta").naif_id == 2000004 and cat.get("ceres").kind == "dwarf_planet"


def test_the_dataset_records_its_files_and_what_they_did_not_give(user_dir):
    result = import_catalogue(MPCORB, POLES, "recorded", today="2026-01-02")
    doc = tomllib.loads(result.path.read_text(encoding="utf-8"))
    sources = doc["dataset"]["sources"]
    assert sources["import:orbits:mpcorb_sample.dat"]["sha256"] == hashlib.sha256(MPCORB.read_bytes()).hexdigest()
    assert sources["import:poles:poles_sample.csv"]["sha256"] == hashlib.sha256(POLES.read_bytes()).hexdigest()
    desc = doc["dataset"]["description"]
    assert "2026-01-02" in desc and "mpcorb_sample.dat" in desc and hashlib.sha256(MPCORB.read_bytes()).hexdigest() in desc
    eros = load_catalogue("recorded").get("eros").values
    assert eros["pole.ra"].uncertainty == pytest.approx(0.02, rel=READ_BACK) and eros["pole.ra"].source == "import:poles:poles_sample.csv"
    assert eros["orbit.e"].source == "import:orbits:mpcorb_sample.dat"
    assert eros["orbit.e"].note == "no uncertainty given in the import" and eros["orbit.e"].uncertainty is None
    assert "TT - TDB < 2 ms" in eros["orbit.epoch"].note
    record = api.body_record("eros", dataset="recorded")
    assert record["values"]["pole.dec"]["uncertainty"] == pytest.approx(0.02, rel=READ_BACK)


def test_a_replaced_dataset_is_seen_without_clearing_a_cache(user_dir, tmp_path):
    import_catalogue(MPCORB, POLES, "again")
    assert load_catalogue("again").get("Vesta").rotation_period_hours == pytest.approx(5.3421276322, rel=READ_BACK)
    with pytest.raises(InvalidInputError, match="already exists.*--force"):
        import_catalogue(MPCORB, POLES, "again")
    changed = tmp_path / "poles.csv"
    changed.write_text(POLES.read_text(encoding="utf-8").replace("5.3421276322", "5.3421"), encoding="utf-8")
    result = import_catalogue(MPCORB, changed, "again", force=True)
    assert result.replaced
    assert load_catalogue("again").get("Vesta").rotation_period_hours == pytest.approx(5.3421, rel=READ_BACK)


def test_a_user_dataset_does_not_shadow_a_shipped_one(user_dir):
    for name in ("current", "petit2014", "Current", "PETIT2014"):
        with pytest.raises(InvalidInputError, match="shipped dataset") as info:
            import_catalogue(MPCORB, POLES, name)
        assert info.value.field == "name"
    for name in ("../evil", "", "a b", "_hidden", "x" * 65):
        with pytest.raises(InvalidInputError, match="dataset name"):
            import_catalogue(MPCORB, POLES, name)
    user_dir.mkdir(parents=True)
    (user_dir / "current.toml").write_text("[dataset]\nname = 'current'\n", encoding="utf-8")  # put there by hand
    assert available_datasets().count("current") == 1
    assert "Vesta" in load_catalogue("current").names                                          # the shipped one wins


def test_the_user_directory_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.delenv("EPHEM_USER_CATALOGUE_DIR", raising=False)
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "xdg"))
    assert user_catalogue_dir() == tmp_path / "xdg" / "ephem" / "catalogue"
    monkeypatch.delenv("XDG_DATA_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert user_catalogue_dir() == tmp_path / "home" / ".local" / "share" / "ephem" / "catalogue"


def test_skip_unmatched_leaves_out_the_bodies_of_one_file(user_dir, tmp_path):
    poles = tmp_path / "poles.csv"
    lines = [ln for ln in POLES.read_text(encoding="utf-8").splitlines() if not ln.startswith("EROS")]
    poles.write_text("\n".join(lines + ["Pallas,34.0,,-4.0,,,7.81,,0.3,0.31,0.33,,"]) + "\n", encoding="utf-8")
    with pytest.raises(CatalogueImportError, match=r"poles\.csv:7: name: 'Pallas' has no orbit in mpcorb_sample\.dat"):
        import_catalogue(MPCORB, poles, "skip")
    result = import_catalogue(MPCORB, poles, "skip", skip_unmatched=True)
    assert result.catalogue.names == ["Ceres", "Vesta"]
    assert any("Pallas" in s for s in result.skipped) and any("Eros" in s for s in result.skipped)


# ------------------------------------------------------------------------------------------ bad inputs

def _edited(tmp_path, source: Path, old: str, new: str, name: str | None = None) -> Path:
    text = source.read_text(encoding="utf-8")
    assert old in text, old
    out = tmp_path / (name or source.name)
    out.write_text(text.replace(old, new, 1), encoding="utf-8")
    return out


BAD = [  # (file edited, old text, new text, the words of the error: file:line: field: why)
    (POLES, "rotation_period_hours,rotation_period_hours_sigma,", "", "poles_sample.csv:4: rotation_period_hours: "
     "missing column"),
    (POLES, "pole_ra_deg,pole_ra_deg_sigma", "pole_ra,pole_ra_deg_sigma", "poles_sample.csv:4: pole_ra_deg: missing column"),
    (SBDB_CSV, "w,ma,epoch,sigma_e", "w,mean_anom,epoch,sigma_e", "sbdb_sample.csv:4: ma: missing column"),
    (MPCORB, "00004               K25BL", "00004               K25BZ", "mpcorb_sample.dat:12: epoch (columns 21-25): "
     "not an MPC packed epoch: 'K25BZ'"),
    (SBDB_CSV, "26.80969,2461000.5", "26.80969,2025-11-21", "sbdb_sample.csv:6: epoch: not a Julian date (TDB): "
     "'2025-11-21'"),
    (SBDB_JSON, '"epoch": "2461000.5", "equinox": "J2000", "orbit_id"', '"epoch": "soon", "equinox": "J2000", "orbit_id"',
     "sbdb_sample.json:3: [0].orbit.epoch: not a Julian date"),
    (POLES, "vesta,309.031", "Pallas,309.031", "poles_sample.csv:6: name: 'Pallas' has no orbit"),
    (MPCORB, "0.0795764", "1.0795764", "mpcorb_sample.dat:11: eccentricity (columns 71-79): eccentricity must "
     "satisfy 0 <= e < 1"),
    (SBDB_CSV, "0.222836,1.458121", "-0.222836,1.458121", "sbdb_sample.csv:7: e: eccentricity must satisfy 0 <= e < 1"),
    (SBDB_JSON, '"value": "0.0901676"', '"value": "1.5"', "sbdb_sample.json:15: [1].orbit.elements.e: eccentricity must"),
    (POLES, "66.76033,0.0002", "96.76033,0.0002", "poles_sample.csv:5: pole_dec_deg: declination must lie in [-90, 90]"),
    (POLES, "0.3441021942944278,0.3553760217975722", "0.3641021942944278,0.3553760217975722", "poles_sample.csv:6: moment_a, moment_b, moment_c: "
     "principal moments must satisfy A <= B <= C"),
    (POLES, "5.270257308,,", "fast,,", "poles_sample.csv:7: rotation_period_hours: not a number: 'fast'"),
    (POLES, "EROS,11.35,0.02", "EROS,11.35,-0.02", "poles_sample.csv:7: pole_ra_deg_sigma: an uncertainty must be >= 0"),
    (MPCORB, "00001               K25BL 231.53974 ", "00001               K25BL  231.53974",
     "mpcorb_sample.dat:11: column 36: should be blank in the MPCORB layout"),
    (POLES, "name,", "name,colour,", "poles_sample.csv:4: colour: unknown column"),
]


@pytest.mark.parametrize("source, old, new, words", BAD, ids=[f"{b[0].name}:{b[3].split(': ')[1]}" for b in BAD])
def test_bad_inputs_name_the_file_line_and_field(source, old, new, words, tmp_path, user_dir):
    path = _edited(tmp_path, source, old, new)
    orbits, poles = (path, POLES) if source != POLES else (MPCORB, path)
    with pytest.raises(CatalogueImportError) as info:
        import_catalogue(orbits, poles, "bad")
    assert words in str(info.value)
    assert not (user_dir / "bad.toml").exists()


def test_a_record_quoted_elsewhere_reads_as_the_catalogue_has_it():
    """The Steins record current.toml takes from a PyKEP script (data/references.toml), whose readable designation
    and date of last observation have lost their column alignment (the date spills into the name's columns)."""
    line = ("02867   12.5   0.15 K156R 270.95697  251.13031   55.37206    9.93452  0.1454330  0.27123521   2.3635892  "
            "0 MPO332844  1677  21 1951-2015 0.44 M-v 38h MPCLINUX   0000   (2867)   Steins   20150328")
    (steins,) = parse_mpcorb(line + "\n", "steins.dat")
    assert steins.name == "Steins" and "2867" in steins.aliases
    shipped = load_catalogue("current").get("Steins")
    for key, attr in ELEMENTS.items():
        assert getattr(steins.orbit, attr) == getattr(shipped.orbit, attr), key


def test_a_misaligned_mpcorb_line_is_refused_not_misread():
    line = MPCORB.read_text(encoding="utf-8").splitlines()[-1].replace("  304.27008", " 304.27008 ")
    with pytest.raises(CatalogueImportError, match=r"eros\.dat:1: column 48: should be blank in the MPCORB layout"):
        parse_mpcorb(line + "\n", "eros.dat")
    n_moved = MPCORB.read_text(encoding="utf-8").splitlines()[-1].replace("0.55977529", "0.65977529")
    with pytest.raises(CatalogueImportError, match=r"eros\.dat:1: mean daily motion \(columns 81-91\): n = 0.65977529"):
        parse_mpcorb(n_moved + "\n", "eros.dat")


def test_duplicates_and_empty_files_are_refused(tmp_path):
    text = POLES.read_text(encoding="utf-8") + "CERES,1,,2,,,3,,0.3,0.31,0.33,,\n"
    with pytest.raises(CatalogueImportError, match=r"p\.csv:8: name: 'CERES' appears twice \(also line 5\)"):
        parse_poles(text, "p.csv")
    with pytest.raises(CatalogueImportError, match="no orbit records"):
        parse_mpcorb("\n\n", "empty.dat")
    with pytest.raises(InvalidInputError, match="format: must be one of"):
        parse_orbits("x", "x.dat", "xml")


# ------------------------------------------------------------------------------------------ CLI and service

runner = CliRunner()


def test_the_cli_imports_and_then_answers_with_the_dataset(user_dir):
    res = runner.invoke(cli, ["catalogue", "import", "--orbits", str(MPCORB), "--poles", str(POLES), "--name", "cli"])
    assert res.exit_code == 0, res.output
    assert f"wrote {user_dir / 'cli.toml'}" in res.stdout and "3 bodies (Ceres, Vesta, Eros)" in res.stdout
    res = runner.invoke(cli, ["precession", "vesta", "--dataset", "cli"])
    assert res.exit_code == 0, res.output
    answer = json.loads(res.stdout)
    assert answer["dataset"] == "cli"
    assert answer["precession_rate_arcsec_per_year"] == pytest.approx(
        api.precession("vesta")["precession_rate_arcsec_per_year"], rel=1e-12)
    res = runner.invoke(cli, ["bodies", "--dataset", "cli", "--format", "csv"])
    assert res.exit_code == 0 and res.stdout.count("\n") == 4


@pytest.mark.parametrize("args, words", [
    (["--name", "current"], "error: name: 'current' is a shipped dataset"),
    # an MPCORB file read as SBDB JSON: the file, the line and the field are named
    (["--name", "x", "--format", "sbdb-json"], "error: mpcorb_sample.dat:1: json: not valid JSON"),
    (["--name", "x", "--format", "xml"], "error: format: must be one of mpcorb, sbdb-json, sbdb-csv"),
])
def test_the_cli_refuses_with_status_2(args, words, user_dir):
    res = runner.invoke(cli, ["catalogue", "import", "--orbits", str(MPCORB), "--poles", str(POLES), *args])
    assert res.exit_code == 2, res.output
    assert res.stderr.startswith(words), res.stderr
    assert len(res.stderr.strip().splitlines()) == 1 and "Traceback" not in res.stderr


def test_the_cli_notes_what_it_skipped(user_dir, tmp_path):
    orbits = tmp_path / "two.dat"
    orbits.write_text("\n".join(MPCORB.read_text(encoding="utf-8").splitlines()[:-1]) + "\n", encoding="utf-8")
    res = runner.invoke(cli, ["catalogue", "import", "--orbits", str(orbits), "--poles", str(POLES), "--name", "two"])
    assert res.exit_code == 2 and "poles_sample.csv:7: name: 'EROS' has no orbit in two.dat" in res.stderr
    res = runner.invoke(cli, ["catalogue", "import", "--orbits", str(orbits), "--poles", str(POLES), "--name", "two",
                              "--skip-unmatched"])
    assert res.exit_code == 0, res.output
    assert "note: skipped EROS (poles_sample.csv line 7: no orbit)" in res.stderr
    assert "2 bodies (Ceres, Vesta)" in res.stdout


def test_the_service_selects_an_imported_dataset(user_dir):
    """The service reads the dataset names at start-up: a fresh process, as after an import."""
    import_catalogue(SBDB_CSV, POLES, "served")
    probe = ("from fastapi.testclient import TestClient\n"
             "from service.app import app\n"
             "c = TestClient(app)\n"
             "r = c.get('/v1/bodies/ceres/precession?dataset=served')\n"
             "print(r.status_code, r.json()['dataset'], r.json()['precession_rate_arcsec_per_year'])\n")
    env = {**os.environ, "EPHEM_USER_CATALOGUE_DIR": str(user_dir), "EPHEM_WARM_UP": "0"}
    proc = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    status, dataset, rate = proc.stdout.split()
    assert (status, dataset) == ("200", "served")
    assert float(rate) == pytest.approx(api.precession("ceres")["precession_rate_arcsec_per_year"], rel=1e-12)


@pytest.mark.parametrize("module", ["importer", "import_records", "orbit_files", "pole_table"])
def test_the_import_modules_use_no_network(module):
    tree = ast.parse((ROOT / "ephem" / "bodies" / f"{module}.py").read_text(encoding="utf-8"))
    imported = {a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    imported |= {(n.module or "").split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.level == 0}
    assert not imported & {"urllib", "http", "requests", "httpx", "socket", "skyfield", "astroquery", "ftplib"}, imported
