"""Answers as astropy tables (ephem.exports.qtable, issue 41 and issue 43 item 1): every table-shaped answer as a
``QTable`` whose columns are Quantities in the units their keys name, ``jd_tdb`` a TDB ``Time``, every column
described, the metadata in ``meta``; and as ECSV, which ``QTable.read(..., format="ascii.ecsv")`` reads back to the
same table and the same numbers as the answer's.

The numbers' budget: a double written as its shortest repr reads back to itself (repr round-trips), so the
comparisons allow one unit in the last place (2.2e-16 relative), no more. :func:`check_read_back` is shared by the
service's and the CLI's tests (tests/service/test_ecsv.py, tests/cli/test_cli_ecsv.py).
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from astropy import units as u
from astropy.table import QTable
from astropy.time import Time

import ephem
from ephem import api, host
from ephem.base.errors import InvalidInputError
from ephem.base.units import unit_of
from ephem.orbit.lunar import DELAUNAY_NAMES

#: one unit in the last place of a double, relative: what a repr round trip may move a number by (it moves none)
ULP = 2.3e-16
#: keys of an epoch answer that are lists but not per epoch
NOT_PER_EPOCH = ("moments_over_C", "perturbers")


def expected_columns(answer) -> dict[str, list]:
    """The columns a table of ``answer`` must have, by key, with the answer's values: stated here from the answers'
    shapes (docs/api.md), independently of the builder."""
    if isinstance(answer, list):                                     # the bodies list
        return {k: [r[k] for r in answer] for k in answer[0]}
    if "rows" in answer:                                             # a batch
        return {k: [r.get(k) for r in answer["rows"]] for k in answer["columns"]}
    if "terms" in answer:                                            # nutation: a row per term
        rows = []
        for t in answer["terms"]:
            row = {k: v for k, v in t.items() if k != "delaunay_multipliers"}
            if t.get("delaunay_multipliers") is not None:       # five columns after the multiple, as the CLI's
                row = {"multiple": None, **dict(zip(DELAUNAY_NAMES, t["delaunay_multipliers"])), **row}
            rows.append(row)
        return {k: [r.get(k) for r in rows] for k in dict.fromkeys(k for r in rows for k in r)}
    epoch = "jd_tdb" if "jd_tdb" in answer else "year" if "year" in answer else None
    if epoch is None:                                                # precession: one row of its scalars
        return {k: [v] for k, v in answer.items() if not isinstance(v, (dict, list))}
    n = len(answer[epoch])
    return {k: list(np.asarray(v).tolist()) for k, v in answer.items()
            if k not in NOT_PER_EPOCH and isinstance(v, (list, np.ndarray)) and np.ndim(v) == 1 and len(v) == n}


def expected_unit(key: str):
    if key == "year":
        return u.yr
    unit = unit_of(key)
    return None if unit is None else u.Unit(unit)


def check_table(table: QTable, answer, ordered: bool = True) -> None:
    """``table`` holds ``answer``'s columns, in their units, with its values (masked where it has null); in the
    answer's order unless ``ordered`` is false (the service's JSON orders a nutation term's keys as its schema)."""
    expected = expected_columns(answer)
    if ordered:
        assert table.colnames == list(expected), (table.colnames, list(expected))
    else:
        assert sorted(table.colnames) == sorted(expected), (table.colnames, list(expected))
    for key, values in expected.items():
        col = table[key]
        assert col.info.description, key
        if key == "jd_tdb":
            assert isinstance(col, Time) and col.scale == "tdb" and col.format == "jd", key
            np.testing.assert_allclose(col.jd1 + col.jd2, np.asarray(values, dtype=float), rtol=ULP, atol=0)
            continue
        present = [v for v in values if v is not None]
        mask = np.ma.getmaskarray(col) if hasattr(col, "mask") else np.zeros(len(col), bool)
        if present and all(isinstance(v, str) for v in present):     # text: ECSV writes null and "" alike, ""
            assert ["" if m else str(x) for x, m in zip(col, mask)] == ["" if v is None else v for v in values], key
            continue
        assert list(mask) == [v is None for v in values], key
        unit = expected_unit(key)
        if unit is not None:
            assert isinstance(col, u.Quantity) and col.unit == unit, (key, getattr(col, "unit", None), unit)
            numbers = np.asarray(getattr(col, "unmasked", col).to_value(unit), dtype=float)
        else:
            assert not isinstance(col, u.Quantity), key
            numbers = np.asarray(np.ma.getdata(col), dtype=float)
        got = numbers[~mask]
        want = np.asarray([float(v) for v in present], dtype=float)
        assert np.all(np.isfinite(got)), key
        np.testing.assert_allclose(got, want, rtol=ULP, atol=0, err_msg=key)


def check_read_back(text: str, answer, source: str | None = None, ordered: bool = True) -> QTable:
    """ECSV ``text`` read by astropy: ``answer``'s table (:func:`check_table`) with the answer's metadata."""
    assert text.startswith("# %ECSV 1.0"), text[:40]
    table = QTable.read(text, format="ascii.ecsv")
    check_table(table, answer, ordered)
    meta = table.meta
    assert meta["version"] == ephem.__version__
    if source is not None:
        assert meta["source"] == source
    if isinstance(answer, dict) and isinstance(answer.get("model"), dict):
        assert meta["model"]["name"] == answer["model"]["name"]
        if answer["model"].get("estimated_error_mas") is not None:
            assert math.isclose(meta["estimate"]["estimated_error_mas"], answer["model"]["estimated_error_mas"],
                                rel_tol=ULP)
    calendar = [k for k in expected_columns(answer) if k.endswith("_iso")]
    if calendar:
        assert meta["time_scale"] == calendar[0][:-4]
    return table


USER_ROWS = [
    {"name": "my-asteroid", "a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
     "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5, "pole_ra_deg": 309.03, "pole_dec_deg": 42.23,
     "rotation_period_hours": 5.342, "moment_a": 0.3433, "moment_b": 0.3546, "moment_c": 0.42, "e_sigma": 0.001},
    {"name": "unbound", "a_au": 2.36, "e": 1.5, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
     "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5, "pole_ra_deg": 309.03, "pole_dec_deg": 42.23,
     "rotation_period_hours": 5.342, "dynamical_ellipticity": 0.17},
]

ANSWERS = {
    "bodies": lambda: api.list_bodies(),
    "precession": lambda: api.precession("vesta"),
    "nutation": lambda: api.nutation("vesta", order=4),
    "nutation_earth": lambda: api.nutation("earth"),
    "track": lambda: api.track("ceres", "2040-01-01", "2040-03-01", 20.0),
    "track_arrays_tt": lambda: api.track_arrays("mars", "2030-01-01", "2030-02-01", 10.0, time_scale="tt"),
    "free_motion": lambda: api.free_motion_answer("mars", "2030-01-01", "2030-01-03", 0.5, time_scale="tdb"),
    "history": lambda: api.history("ceres", -1000.0, 0.0, 250.0),
    "batch": lambda: api.batch(USER_ROWS, history={"start_year": -400, "stop_year": 0, "step_years": 200}),
}


@pytest.fixture(scope="module", params=sorted(ANSWERS))
def answer(request):
    return request.param, ANSWERS[request.param]()


def test_the_qtable_holds_the_answer_in_units(answer):
    name, ans = answer
    table = api.to_qtable(ans)
    check_table(table, ans)
    assert table.meta["table"] in api.TABLE_KINDS and table.meta["version"] == ephem.__version__


def test_the_ecsv_reads_back_as_the_answer(answer):
    name, ans = answer
    check_read_back(api.to_ecsv(ans, source="a test"), ans, "a test")


def test_the_epochs_are_time_ready():
    ans = api.track("ceres", "2040-01-01", "2040-03-01", 20.0)
    table = QTable.read(api.to_ecsv(ans), format="ascii.ecsv")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")            # ERFA's "dubious year": 2040 is past the leap-second table
        assert table["jd_tdb"].utc.isot[0] == "2040-01-01T00:00:00.000" == table["utc_iso"][0]
    assert table.meta["time_scales"] == {"jd_tdb": "tdb", "utc_iso": "utc"}


def test_the_history_says_its_years_are_julian_years_of_tdb():
    table = api.to_qtable(api.history("ceres", -1000.0, 0.0, 500.0))
    assert table["year"].unit == u.yr and "J2000.0 TDB" in table["year"].info.description
    assert table.meta["time_scale"] == "tdb"


def test_the_metadata_names_the_model_the_source_and_the_citations():
    table = api.to_qtable(api.precession("vesta"), source="ephem precession vesta")
    meta = table.meta
    assert meta["table"] == "precession" and meta["body"] == "Vesta" and meta["source"] == "ephem precession vesta"
    assert meta["model"]["theory"].startswith("Kinoshita") and meta["citations"][0] == meta["model"]["theory"]
    assert any("Konopliv" in c for c in meta["citations"]), meta["citations"]      # Vesta's pole and period


def test_a_nutation_table_names_its_amplitudes_quantity():
    meta = api.to_qtable(api.nutation("vesta")).meta
    assert meta["amplitude_quantities"]["longitude_amplitude_arcsec"] == "Δψ sin ε"


@pytest.mark.parametrize("answer", [api.body_record, lambda name: {"precession": {}, "nutation": {}}, lambda n: [],
                                    lambda n: "vesta"])
def test_an_answer_that_is_no_table_is_refused_naming_it(answer):
    with pytest.raises(InvalidInputError) as err:
        api.to_qtable(answer("vesta"))
    assert err.value.field == "answer"


def test_the_ecsv_writing_is_charged_before_it_runs():
    ans = api.track_arrays("ceres", "2040-01-01", "2041-01-01", 1.0)
    with host.budget(cpu_s=1e-3, memory_mb=1e3):
        with pytest.raises(api.OverBudgetError):
            api.to_ecsv(ans)


@pytest.mark.parametrize("call", [lambda q: api.track("ceres", "2040-01-01", "2040-03-01", 20.0, quantities=q),
                                  lambda q: api.precession("vesta", quantities=q),
                                  lambda q: api.free_motion_answer("mars", "2030-01-01", "2030-01-02", 0.5,
                                                                   quantities=q)],
                         ids=["track", "precession", "free_motion"])
def test_an_answer_with_quantities_gives_the_same_table(call):
    plain, with_units = api.to_qtable(call(False)), api.to_qtable(call(True))
    assert with_units.colnames == plain.colnames
    check_table(with_units, call(False))
