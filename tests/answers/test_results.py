"""The answers as objects (ephem.answers.results): each public answer is a dict (the bodies a list) that reads,
serialises, compares and pickles as the plain dict it was, with .to_qtable() (the ECSV's table), .to_dict() (a plain,
JSON-ready deep copy) and a short repr.

What can fail here: a class that changes the JSON (the contract) or the orjson bytes the service sends, a copy that
shares a list with the answer, a table other than the one api.to_qtable builds, a repr that prints the arrays."""
from __future__ import annotations

import copy
import json
import pickle

import numpy as np
import orjson
import pytest

from ephem import api
from ephem.answers import results

SPAN = ("2040-01-01", "2040-07-01", 30.0)


def _answers():
    """(name, answer) of every public answer function, small requests."""
    return [
        ("track", api.track("vesta", *SPAN)),
        ("track_arrays", api.track_arrays("vesta", *SPAN, tolerance_mas=100.0)),
        ("track_quantities", api.track("ceres", *SPAN, quantities=True)),
        ("precession", api.precession("vesta")),
        ("precession_quantities", api.precession("itokawa", quantities=True)),
        ("nutation", api.nutation("vesta", dataset="petit2014", order=4)),
        ("history", api.history("ceres", -1000.0, 0.0, 500.0)),
        ("free_motion", api.free_motion_answer("earth", "2030-01-01", "2031-01-01", 91.0)),
        ("free_motion_arrays", api.free_motion_arrays("earth", "2030-01-01", "2031-01-01", 91.0)),
        ("models", api.track_models("vesta", *SPAN, tolerance_mas=100.0)),
        ("record", api.body_record("vesta")),
        ("bodies", api.list_bodies()),
    ]


ANSWERS = _answers()
CLASSES = {"track": api.TrackAnswer, "track_arrays": api.TrackAnswer, "track_quantities": api.TrackAnswer,
           "precession": api.PrecessionAnswer, "precession_quantities": api.PrecessionAnswer,
           "nutation": api.NutationAnswer, "history": api.HistoryAnswer, "free_motion": api.FreeMotionAnswer,
           "free_motion_arrays": api.FreeMotionAnswer, "models": api.ModelsAnswer, "record": api.BodyRecord,
           "bodies": api.BodiesAnswer}


def _has_arrays(answer) -> bool:
    """An answer holding numpy arrays, Quantity or Time (its == is elementwise; json.dumps does not take it)."""
    return isinstance(answer, dict) and any(isinstance(v, np.ndarray) or hasattr(v, "unit") or hasattr(v, "jd1")
                                            for v in answer.values())


def _same(a, b) -> bool:
    """a and b equal, arrays compared element by element (their to_dict, which is JSON's view)."""
    return results.plain(a) == results.plain(b)


def _spoil(value) -> None:
    """Change every list and dict nested in ``value``, in place."""
    if isinstance(value, dict):
        for v in value.values():
            _spoil(v)
        value["spoilt"] = True
    elif isinstance(value, list):
        for v in value:
            _spoil(v)
        value.append("spoilt")


def _only_plain(value) -> bool:
    if isinstance(value, dict):
        return type(value) is dict and all(type(k) is str and _only_plain(v) for k, v in value.items())
    if isinstance(value, list):
        return type(value) is list and all(_only_plain(v) for v in value)
    return type(value) in (str, int, float, bool, type(None))


@pytest.mark.parametrize("name, answer", ANSWERS, ids=[n for n, _ in ANSWERS])
def test_each_answer_is_its_class_and_the_dict_it_was(name, answer):
    assert type(answer) is CLASSES[name]
    assert isinstance(answer, (dict, list))
    base = dict if isinstance(answer, dict) else list
    if not _has_arrays(answer):
        assert answer == base(answer) and base(answer) == answer        # equality with the plain container, both ways
    back = pickle.loads(pickle.dumps(answer))
    assert type(back) is type(answer) and _same(back, answer) and list(back) == list(answer)
    assert _same(copy.deepcopy(answer), answer)


@pytest.mark.parametrize("name, answer", [(n, a) for n, a in ANSWERS if "quantities" not in n],
                         ids=[n for n, _ in ANSWERS if "quantities" not in n])
def test_the_json_is_unchanged(name, answer):
    """json.dumps and the service's orjson (numpy natively) write the same bytes as for the plain dict."""
    plain = dict(answer) if isinstance(answer, dict) else list(answer)
    option = orjson.OPT_SERIALIZE_NUMPY
    assert orjson.dumps(answer, option=option) == orjson.dumps(plain, option=option)
    if not _has_arrays(answer):
        assert json.dumps(answer) == json.dumps(plain)


@pytest.mark.parametrize("name, answer", ANSWERS, ids=[n for n, _ in ANSWERS])
def test_to_dict_is_a_plain_deep_copy_ready_for_json(name, answer):
    d = answer.to_dict()
    assert _only_plain(d)
    json.dumps(d, allow_nan=False)
    if "quantities" not in name:
        assert orjson.loads(orjson.dumps(answer, option=orjson.OPT_SERIALIZE_NUMPY)) == d
    # a deep copy: changing every list and dict of the copy leaves the answer as it was
    before = results.plain(answer)
    _spoil(d)
    assert results.plain(answer) == before


def test_to_dict_of_quantities_is_the_plain_answer_in_its_keys_units():
    """A track asked with quantities=True gives back, in to_dict, the plain track's numbers (the Time as its JD TDB,
    each Quantity in its key's unit): the same to the last bit, as the conversion is a unit factor of 1."""
    plain, units = api.track("ceres", *SPAN), api.track("ceres", *SPAN, quantities=True).to_dict()
    for key in api.TRACK_KEYS + ("utc_iso", "obliquity_deg_uncertainty", "pole_uncertainty_deg"):
        assert units[key] == plain[key], key
    assert units["model"]["estimated_error_mas"] == plain["model"]["estimated_error_mas"]


@pytest.mark.parametrize("name, answer", [(n, a) for n, a in ANSWERS if CLASSES[n].kind is not None],
                         ids=[n for n, a in ANSWERS if CLASSES[n].kind is not None])
def test_to_qtable_is_the_tables_own(name, answer):
    """The table is the one api.to_qtable builds of the answer (the ECSV's), columns, units and values."""
    table, want = answer.to_qtable(), api.to_qtable(answer)
    assert table.colnames == want.colnames and len(table) == len(want)
    for key in table.colnames:
        assert getattr(table[key], "unit", None) == getattr(want[key], "unit", None)
    assert {k: v for k, v in table.meta.items() if k != "source"} == {k: v for k, v in want.meta.items() if k != "source"}
    assert answer.to_ecsv(source="test").startswith("# %ECSV")


def test_a_track_table_has_units_and_a_tdb_time():
    table = api.track("vesta", *SPAN).to_qtable()
    assert table["jd_tdb"].scale == "tdb" and str(table["obliquity_deg"].unit) == "deg"
    assert str(table["psi_arcsec"].unit) == "arcsec"


@pytest.mark.parametrize("name", ["models", "record"])
def test_an_answer_without_a_table_says_where_its_tables_are(name):
    answer = dict(ANSWERS)[name]
    with pytest.raises(api.InvalidInputError) as exc:
        answer.to_qtable()
    assert exc.value.field == "answer" and "not table-shaped" in exc.value.reason


@pytest.mark.parametrize("name, answer", ANSWERS, ids=[n for n, _ in ANSWERS])
def test_the_repr_is_short_and_names_the_body(name, answer):
    text = repr(answer)
    assert text.startswith(f"<{type(answer).__name__} ") and len(text) < 200
    if name != "bodies":
        assert ("Vesta" in text or "Ceres" in text or "Earth" in text or "Itokawa" in text)


def test_a_batch_and_a_users_body_are_answers_too():
    row = {"name": "mine", "a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
           "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5, "pole_ra_deg": 309.03, "pole_dec_deg": 42.23,
           "rotation_period_hours": 5.342, "dynamical_ellipticity": 0.17}
    b = api.batch([row])
    assert type(b) is api.BatchAnswer and b.to_qtable()["name"][0] == "mine"
    assert orjson.dumps(b) == orjson.dumps(dict(b))
    vesta = api.get_body("vesta")
    both = api.precession_nutation(vesta, track={"start": SPAN[0], "stop": SPAN[1], "step_days": SPAN[2]})
    assert type(both) is api.PrecessionNutationAnswer and type(both["track"]) is api.TrackAnswer
    assert type(both["precession"]) is api.PrecessionAnswer
    assert _only_plain(both.to_dict())
    with pytest.raises(api.InvalidInputError):
        both.to_qtable()


def test_plain_needs_no_astropy_for_a_plain_answer():
    """to_dict of an answer without Quantity or Time does not ask astropy (it looks in sys.modules only)."""
    assert results.plain({"a": np.arange(3), "b": (np.float64(1.5), None)}) == {"a": [0, 1, 2], "b": [1.5, None]}
