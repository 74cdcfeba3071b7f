"""The request's objects (ephem.theory.requests): the model chosen as one value, the epochs as one value."""
from __future__ import annotations

import numpy as np
import pytest

from ephem.bodies.catalogue import get_body
from ephem.families import theory_for
from ephem.theory.requests import Epochs, ModelChoice, TrackRequest
from ephem.theory.results import Estimate


def test_an_estimate_gives_the_choice_it_is_of():
    est = Estimate("second_order", None, {"a": 1e-9}, free_wobble=True, rotation_scale="oppolzer")
    assert est.choice == ModelChoice("second_order", None, free_wobble=True, rotation_scale=True)
    assert Estimate("series", 4, {}).choice == ModelChoice("series", 4)


def test_a_grid_and_the_same_epochs_as_an_array_are_the_same_epochs():
    grid = Epochs.grid(2451545.0, 3.5, 5)
    assert grid.is_grid and grid.count == 5
    assert grid.stop == pytest.approx(2451545.0 + 14.0, abs=1e-9)
    anywhere = Epochs.at(grid.jd_tdb)
    assert not anywhere.is_grid and anywhere.count == 5 and anywhere.stop == grid.stop
    np.testing.assert_array_equal(anywhere.jd_tdb, grid.jd_tdb)
    assert Epochs.at(2451545.0).count == 1


def test_the_family_fills_in_its_default_model():
    """The Sun's ladder: exact coefficients by default, the truncated series with an e-order (the choice's)."""
    vesta = theory_for(get_body("vesta"), ("Sun",))
    assert vesta.resolved(ModelChoice()).model == "hansen"
    assert vesta.resolved(ModelChoice(order=4)) == ModelChoice("series", 4)
    assert vesta.resolved(ModelChoice("numerical")).model == "numerical"


def test_the_request_asks_for_the_wobble_and_the_rotation_terms_it_gave():
    b = get_body("eros")
    req = TrackRequest(b, ("Sun",), "figure", Epochs.grid(2451545.0, 1.0, 3), choice=ModelChoice("hansen"),
                       rotation_phase=0.5)
    assert req.dataset == b.dataset
    assert req.asked == ModelChoice("hansen", None, free_wobble=False, rotation_scale=True)


def test_the_request_prints_on_one_short_line_not_the_whole_body():
    """A notebook prints the request: the body's name and dataset, the perturbers, the axis, the epochs' count and
    span, the tolerance or the model named; not the Body's every value (the dataclass's repr ran to ~800 characters)."""
    from ephem import api
    req = api.track_request("Vesta", "2040-01-01", "2040-02-01", 1.0, dataset="petit2014", tolerance_mas=5.0)
    text = repr(req)
    assert len(text) < 200 and "\n" not in text
    for part in ("Vesta (petit2014)", "under Sun", "axis figure", "32 epochs", f"{req.epochs.start:.10g}",
                 f"{req.epochs.stop:.10g}", "by 1 d", "tolerance 5 mas"):
        assert part in text, (part, text)
    assert "values" not in text and "Measured" not in text      # nothing of the Body's record
    named = repr(TrackRequest(get_body("eros"), ("Sun",), "angular_momentum", Epochs.at([2451545.0]),
                              choice=ModelChoice("series", 4), rotation_phase=0.5))
    assert "Eros (current)" in named and "1 epoch JD 2451545" in named and "model series order 4" in named
    assert "rotation phase 28.6479 deg" in named and "tolerance" not in named
    assert "model default" in repr(api.track_request("Earth", "2040-01-01", "2040-01-02", 1.0))


def test_a_kept_request_compares_the_models_its_keywords_compare():
    """api.track_models_of(request) is api.track_models of the same keywords (ephem track --models computes it from
    the request its options make); a request naming one track's model or rotation phase is refused naming it."""
    from ephem import api
    from ephem.base.errors import InvalidInputError
    keywords = dict(tolerance_mas=50.0, perturbers="sun", dataset="petit2014")
    kept = api.track_models_of(api.track_request("earth", "2040-01-01", "2040-03-01", 0.5, **keywords))
    assert kept == api.track_models("earth", "2040-01-01", "2040-03-01", 0.5, **keywords)
    assert kept["epochs"] == 121 and len(kept["models"]) >= 2
    for field, options in (("model", dict(model="hansen")), ("rotation_phase_deg", dict(rotation_phase_deg=10.0))):
        with pytest.raises(InvalidInputError) as err:
            api.track_models_of(api.track_request("eros", "2040-01-01", "2040-01-02", 1.0, **options))
        assert err.value.field == field
