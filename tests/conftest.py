import pytest

from ephem.catalogue import Body, Orbit, Pole


@pytest.fixture
def vesta_like():
    """A Vesta-like body built in code (independent of the catalogue files)."""
    return Body("Vesta-like", Orbit(2.3615413, 0.0901676, 7.14406, 103.70232, 151.53711, 26.80969, 2461000.5),
                Pole(309.031, 42.2264), 5.3421, moments=(0.3433, 0.3546, 0.42))
