"""The one interface (ephem.theory.interface, ephem.families): every family behind it answers alike."""
from __future__ import annotations

import numpy as np
import pytest

from ephem.bodies.catalogue import get_body
from ephem.rotation.free_motion import make_wobble
from ephem.base.constants import ROUNDING
from ephem.theory.tracks import pole_vectors
from ephem.sun.family import SunLadder
from ephem.earth.family import LunisolarTheory
from ephem.families import MODELS, THEORIES, theory_for
from ephem.theory.interface import SpinAxisTheory
from ephem.theory.requests import Epochs, ModelChoice


def test_each_body_is_served_by_the_family_its_perturbers_call_for():
    """The family its perturbers call for, with the long-term model after the family's own (ephem.longterm.with_long_term)."""
    assert isinstance(theory_for(get_body("earth"), ("Moon", "Sun")).inner, LunisolarTheory)
    assert isinstance(theory_for(get_body("earth"), ("Sun",)).inner, SunLadder)
    vesta = theory_for(get_body("vesta"), ("Sun",))
    assert isinstance(vesta.inner, SunLadder) and vesta.models == SunLadder.models + ("long_term",)
    assert set(MODELS) == {m for family in THEORIES for m in family.models} | {"long_term"}
    for family in THEORIES:
        assert issubclass(family, SpinAxisTheory) and not getattr(family, "__abstractmethods__", None)
        assert set(family.descriptions) == set(family.models)


@pytest.mark.parametrize("body, perturbers, model, start", [
    ("vesta", ("Sun",), "hansen", 2451545.0),
    ("vesta", ("Sun",), "second_order", 2451545.0),
    ("earth", ("Moon", "Sun"), "lunisolar", 2460000.5),
])
@pytest.mark.parametrize("wobble", [False, True])
def test_the_grid_track_is_the_track_at_the_same_epochs(body, perturbers, model, start, wobble):
    """The fast path on an even grid (Epochs.grid) and the track at any epochs (Epochs.at) are one track: the
    grid evaluation's recurrences differ from direct sines by rounding, a few 1e-16 rad per term summed
    over a few dozen terms; ROUNDING (1e-12 rad) is the floor every estimate carries for it."""
    b = get_body(body)
    theory = theory_for(b, perturbers, "figure")
    if wobble:
        theory = theory.with_wobble(make_wobble(b, 30.0, 1.0, None))
    t0, step, count = start, 3.7, 500
    est = theory.named(theory.grid(t0, step, count), ModelChoice(model))
    choice = est.choice if est is not None else ModelChoice(model, free_wobble=wobble)
    grid = theory.track(choice, Epochs.grid(t0, step, count))
    anywhere = theory.track(choice, Epochs.at(theory.grid(t0, step, count)))
    assert est is None or est.free_wobble == wobble
    u, v = pole_vectors(grid), pole_vectors(anywhere)
    # atan2(|u x v|, u . v): an arccos of the dot product cannot resolve angles below ~1e-8 rad
    angle = np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.sum(u * v, axis=1))
    assert float(np.max(angle)) < ROUNDING
    # the angles themselves, not only the pole: ψ within the same floor
    assert float(np.max(np.abs(grid.psi - anywhere.psi))) < ROUNDING
