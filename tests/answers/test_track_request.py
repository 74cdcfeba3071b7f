"""A track request made and kept before it is computed (api.track_request -> api.TrackRequest): the public keywords
checked in one place, the same refusals as the track's, and the track computes exactly the request it builds.

What can fail here: a check made only by the track (a request built that the track then refuses), a refusal that
names another field or says it otherwise, a request whose epochs or tolerance differ from the track's own."""
from __future__ import annotations

import dataclasses
import math

import pytest

from ephem import api

SPAN = ("2040-01-01", "2040-07-01", 30.0)
MAS_RAD = math.pi / 180.0 / 3.6e6       # a milliarcsecond in radians


def test_a_request_holds_the_checked_inputs():
    r = api.track_request("vesta", *SPAN, model="series", order=4, dataset="petit2014")
    assert isinstance(r, api.TrackRequest)
    assert r.body.name == "Vesta" and r.dataset == "petit2014" and r.perturbers == ("Sun",) and r.axis == "figure"
    t0, step, count = api.epoch_grid(*SPAN)
    assert (r.epochs.start, r.epochs.step, r.epochs.count) == (t0, step, count)
    assert r.choice.model == "series" and r.choice.order == 4 and r.tolerance is None
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.axis = "angular_momentum"


def test_a_tolerance_is_held_in_radians():
    r = api.track_request("ceres", *SPAN, tolerance_mas=250.0)
    assert r.tolerance == pytest.approx(250.0 * MAS_RAD, rel=1e-15)
    assert r.choice.model is None and r.choice.order is None


def test_the_track_computes_the_request_it_builds():
    """The track's epochs and model are the request's: the request is what the track answers."""
    r = api.track_request("mars", *SPAN, model="hansen", axis="angular_momentum")
    ans = api.track_arrays("mars", *SPAN, model="hansen", axis="angular_momentum")
    assert len(ans["jd_tdb"]) == r.epochs.count
    assert ans["jd_tdb"][0] == pytest.approx(r.epochs.start, abs=1e-9)         # days; JD TDB is exact to ~1e-9 d
    assert ans["jd_tdb"][-1] == pytest.approx(r.epochs.stop, abs=1e-9)
    assert ans["model"]["name"] == r.choice.model and ans["model"]["axis"] == r.axis


@pytest.mark.parametrize("body, kwargs, field", [
    ("vesta", {"step_days": -1.0}, "step_days"),
    ("vesta", {"model": "no-such-model"}, "model"),
    ("vesta", {"tolerance_mas": 10.0, "model": "hansen"}, "tolerance_mas"),
    ("vesta", {"tolerance_mas": -1.0}, "tolerance_mas"),
    ("vesta", {"axis": "sideways"}, "axis"),
    ("vesta", {"order": -2}, "order"),
    ("vesta", {"perturbers": "pluto"}, "perturbers"),
    ("mars", {"free_wobble_J_arcsec": 0.1}, "free_wobble_J_arcsec"),
    ("mars", {"free_wobble_phase_deg": 30.0, "rotation_phase_deg": 10.0}, "rotation_phase_deg"),
    ("earth", {"rotation_phase_deg": 10.0}, "rotation_phase_deg"),
])
def test_a_bad_input_is_refused_as_the_track_refuses_it(body, kwargs, field):
    kwargs = dict(kwargs)
    step = kwargs.pop("step_days", SPAN[2])
    with pytest.raises(api.InvalidInputError) as made:
        api.track_request(body, SPAN[0], SPAN[1], step, **kwargs)
    with pytest.raises(api.InvalidInputError) as tracked:
        api.track(body, SPAN[0], SPAN[1], step, **kwargs)
    assert made.value.field == tracked.value.field == field
    assert str(made.value) == str(tracked.value)


def test_an_unknown_body_is_refused_before_any_work():
    with pytest.raises(api.UnknownBodyError):
        api.track_request("no-such-body", *SPAN)
