"""The ``de421`` model of the Moon's family: JPL's DE421 lunar orientation itself, inside its span.

Read through :mod:`ephem.moon.lunar_kernel`, it is the
analogue of a fast rotator's ``real_orbit``: inside the kernel's span (1900-2051), where the package shipping it is
installed, its estimate DE421's own accuracy; refused elsewhere, naming the span. Radians, JD TDB."""
from __future__ import annotations

import math

import numpy as np

from ..base.constants import ARCSEC, ROUNDING
from ..base.errors import NotApplicableError
from ..forced.precession_nutation import Track
from ..theory.results import Estimate
from . import lunar_kernel
from .model import SynchronousModel

#: the rounding of DE421's PA-ME angles to 0.01″ (±0.005″ about two axes), rad
PA_ROUNDING = 0.005 * math.sqrt(2.0) * ARCSEC


def kernel_unavailable(jd_tdb) -> str | None:
    """Why DE421's lunar orientation cannot serve these epochs (JD TDB), naming the span, or None."""
    why = lunar_kernel.unavailable()
    if why is not None:
        return why
    lo, hi = lunar_kernel.span()
    t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
    if t.size and (t.min() < lo or t.max() > hi):
        return (f"DE421's lunar orientation spans JD {lo:.1f} to {hi:.1f} TDB (1900-01-01 to 2051-01-01); these epochs "
                f"need JD {float(t.min()):.1f} to {float(t.max()):.1f}")
    return None


def kernel_track(m: SynchronousModel, t: np.ndarray, figure: bool) -> Track:
    """The ``de421`` model's track: DE421's principal axes (``figure``) or its ME frame, read from the kernel;
    refused (not applicable, with the span) where it does not reach."""
    import erfa

    why = kernel_unavailable(t)
    if why is not None:
        raise NotApplicableError(m.body.name, why)
    axes = lunar_kernel.pa_axes_icrf(t)
    if not figure:
        axes = axes @ m.me_to_pa
    return m.track_of_poles(t, np.einsum("nij,nj->ni", erfa.ecm06(t, np.zeros_like(t)), axes[:, :, 2]))


def kernel_estimate(t: np.ndarray, figure: bool) -> Estimate:
    """The ``de421`` model's estimate over the epochs ``t``: DE421's own accuracy (data/moon_orientation.toml [kernel],
    the change from DE418 the frame kernel measures: 0.45 µrad in the principal axes, ``figure``; 0.27 µrad in the ME
    frame, with the PA-ME angles' rounding), where the kernel is installed and spans the epochs."""
    why = kernel_unavailable(t)
    if why is not None:
        return Estimate("de421", None, {}, available=False, why_not=why)
    k = lunar_kernel.kernel_data()
    if figure:
        terms = {"ephemeris": k["pa_accuracy_microrad"] * 1e-6}
    else:
        terms = {"ephemeris": k["me_accuracy_microrad"] * 1e-6, "pa_offset": PA_ROUNDING}
    return Estimate("de421", None, {**terms, "rounding": ROUNDING})
