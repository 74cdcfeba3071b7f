"""The forced model of one perturber in words: the theory, what it assumes, and the warnings a body earns."""
from __future__ import annotations

import math

from ..bodies.catalogue import Body
from .precession_nutation import MIN_SPIN_ORBIT_RATIO, PrecessionNutation

#: Obliquity within this many degrees of 90: ψ̇ ∝ cos ε is small and poorly determined.
NEAR_RIGHT_ANGLE_DEG = 2.0
THEORY = ("Kinoshita (1977) forced precession-nutation in the solar torque, as in Petit, Souchay & Lhotka (2014), "
          "on the fidelity ladder of ephem.sun.ladder")
#: What every rung of the ladder assumes (each rung's own besides: :data:`ephem.sun.rungs.RUNGS`).
ASSUMPTIONS = [
    "rigid body; figure, rotation and angular-momentum axes coincide (free wobble J = 0)",
    "torque averaged over the rotation; triaxial P22 term of the potential dropped",
    "single perturber: the orbit's centre",
    "the track includes the geodesic (de Sitter) precession about the orbit normal (ephem.orbit.relativity; the "
    "second_order and numerical rungs its instantaneous rate, the others its orbit average, the rest in the "
    "estimate's geodesic term); the precession answer's precession_rate_arcsec_per_year is the torque's alone",
]


def model_info(m: PrecessionNutation, b: Body, assumptions: list) -> dict:
    """An answer's ``model`` object for the forced model ``m`` of ``b``: the theory, ``assumptions``, the warnings
    the body earns, the spin-orbit ratio and the epochs."""
    warnings = []
    if abs(math.degrees(m.obliquity) - 90.0) < NEAR_RIGHT_ANGLE_DEG:
        warnings.append("obliquity within 2 deg of 90: the precession rate (∝ cos ε) is small and "
                        "dominated by the obliquity's uncertainty")
    if b.hd_from == "dynamical_ellipticity" and b.hd_from_moments is not None \
            and abs(b.hd - b.hd_from_moments) > 1e-4 * b.hd:
        given = b.values.get("inertia.dynamical_ellipticity")
        why = "see data/errata.toml" if given is None or given.source.startswith("petit2014") \
            else f"source {given.source}: {given.note}" if given.note else f"source {given.source}"
        warnings.append(f"dynamical ellipticity {b.hd:.6g} given explicitly; the catalogue moments imply "
                        f"{b.hd_from_moments:.6g} ({why})")
    return {
        "theory": THEORY,
        "eccentricity_order": "exact" if m.order is None else m.order,
        "assumptions": assumptions,
        "warnings": warnings,
        "spin_orbit_ratio": m.spin_orbit_ratio,
        "min_spin_orbit_ratio": MIN_SPIN_ORBIT_RATIO,
        "pole_epoch_jd_tdb": m.pole_epoch,
        "orbit_epoch_jd_tdb": m.orbit_epoch,
    }
