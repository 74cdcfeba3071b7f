"""The Moon family's own result: the Cassini state its theory derives, beside the precession answer's values.

A :class:`~ephem.theory.results.FamilySummary`: its fields declare their units, and :mod:`ephem.answers.render` writes
it as the answer's ``cassini`` object (angles in degrees, the node's rate in degrees per year with its period in years,
the free librations' periods in days) without knowing the family.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..theory.results import FamilySummary, quantity


@dataclass(frozen=True)
class CassiniSummary(FamilySummary):
    """A synchronous satellite's Cassini state as its theory derives it (:mod:`ephem.forced.cassini`), beside the
    served mean pole: angles in radians, the node's rate in rad/day, the free librations' periods in days."""

    answer_key: ClassVar[str] = "cassini"

    equator_inclination: float = quantity("rad")          # the catalogue pole's, to the ecliptic
    derived_equator_inclination: float = quantity("rad")
    derived_obliquity: float = quantity("rad")
    orbit_inclination: float = quantity("rad")
    node_rate: float = quantity("rad/day", period="node_period_years")
    beta: float = quantity()
    gamma: float = quantity()
    free_libration_longitude_days: float = quantity()
    free_libration_latitude_days: float = quantity()
    free_precession_space_days: float = quantity()
    free_wobble_days: float = quantity()
