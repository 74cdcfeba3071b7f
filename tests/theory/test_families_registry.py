"""The families' registry (ephem.families) chooses a family without importing the others: its static table must
say what the family classes themselves say, and choosing must agree with every class's own ``serves``."""
from __future__ import annotations

import subprocess
import sys

import pytest

from ephem import families
from ephem.bodies.catalogue import load_catalogue


def test_the_static_table_names_each_family_class_and_its_models():
    classes = families.THEORIES
    assert len(classes) == len(families.FAMILIES)
    for entry, cls in zip(families.FAMILIES, classes):
        assert cls.__name__ == entry.name
        assert tuple(cls.models) == entry.models, entry.name
        assert cls.summary == entry.summary, entry.name
    union = tuple(dict.fromkeys(m for cls in reversed(classes) for m in cls.models))
    from ephem.longterm.with_long_term import NAME
    assert families.MODELS == union + (NAME,)


@pytest.mark.parametrize("perturbers", [None, ("Sun",), ("Earth",), ("Moon", "Sun"), ("Sun", "Moon")])
def test_the_registry_chooses_as_the_classes_serves_would(perturbers):
    classes = families.THEORIES
    for body in load_catalogue().bodies:
        p = tuple(perturbers or body.perturbers)
        first = next((cls for cls in classes if cls.serves(body, p)), None)
        if first is None:
            with pytest.raises(families.NotApplicableError):
                families.theory_for(body, p)
        else:
            assert type(families.theory_for(body, p).inner) is first, (body.name, p)


def test_a_sun_only_body_loads_neither_the_moon_nor_the_earth_family():
    code = ("import sys; from ephem import families; from ephem.bodies.catalogue import get_body; "
            "b = get_body('vesta'); families.theory_for(b, b.perturbers); "
            "print(sorted(m for m in ('ephem.moon.family', 'ephem.earth.family', 'ephem.sun.family') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "['ephem.sun.family']"
