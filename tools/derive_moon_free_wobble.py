"""Measure the Moon's free wobble in DE421's lunar orientation (data/moon_orientation.toml [free_wobble]).

No theory gives a free mode's amplitude and phase: they are what the Moon was last excited to, observed. Here they
are measured as Rambaux & Williams (2011) did, in DE421's principal axes, with their period: the `librations` model
without the wobble (ephem.moon.model.SynchronousModel.axes, principal axes) is taken from DE421's axes, daily over
the lunar-laser-ranging era (1970-2010: DE421 fits ranges from 1970 on, and extrapolates before), and the small
body-frame rotation left over is fitted, about X and about Y, by a cosine and a sine at the wobble's period. The rest
of the span (1900-1970, 2010-2050) stays out of the fit, so the comparison there (tests/moon/
test_against_de421_moon.py) is a prediction.

    python -m tools.derive_moon_free_wobble          # prints the [free_wobble] numbers to paste, and the fit's rms

tests/moon/test_against_de421_moon.py re-measures them and checks the shipped numbers.
"""
from __future__ import annotations

import math

import numpy as np

from ephem.base.constants import ARCSEC
from ephem.bodies.catalogue import get_body
from ephem.moon.model import synchronous_model
from ephem.moon.orientation import orientation_data
from ephem.moon.lunar_kernel import pa_axes_icrf


def body_residual(model, jd_tdb) -> np.ndarray:
    """The small rotation (N, 3), radians, in the body frame, taking the model's principal axes without the wobble
    to DE421's: the vector of the antisymmetric part of B_model^T B_DE421."""
    import erfa

    t = np.asarray(jd_tdb, dtype=float)
    ours = model.axes(t, wobble=False, figure=True)
    de421 = erfa.ecm06(t, np.zeros_like(t)) @ pa_axes_icrf(t)           # ecliptic and equinox of date
    m = np.einsum("nji,njk->nik", ours, de421)
    return 0.5 * np.stack([m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]], axis=-1)


def measure(model=None, start: float | None = None, stop: float | None = None) -> dict:
    """The wobble's (cos, sin) about body X and Y (arcsec) at the shipped period and epoch, fitted to DE421 daily
    over [start, stop] (JD TDB; default the shipped fit span), with the fit's rms (arcsec)."""
    d = orientation_data()["free_wobble"]
    model = model or synchronous_model(get_body("moon"))
    lo, hi = d["fit_span_jd_tdb"] if start is None else (start, stop)
    t = np.arange(lo, hi, 1.0)
    r = body_residual(model, t) / ARCSEC
    ph = 2.0 * math.pi * (t - d["epoch_jd_tdb"]) / d["period_days"]
    X = np.stack([np.cos(ph), np.sin(ph)], axis=-1)
    cx, *_ = np.linalg.lstsq(X, r[:, 0], rcond=None)
    cy, *_ = np.linalg.lstsq(X, r[:, 1], rcond=None)
    rms = float(np.sqrt(np.mean((r[:, 0] - X @ cx) ** 2 + (r[:, 1] - X @ cy) ** 2)))
    return {"x_cos_arcsec": float(cx[0]), "x_sin_arcsec": float(cx[1]), "y_cos_arcsec": float(cy[0]),
            "y_sin_arcsec": float(cy[1]), "rms_arcsec": rms}


def main() -> None:
    fit = measure()
    for key in ("x_cos_arcsec", "x_sin_arcsec", "y_cos_arcsec", "y_sin_arcsec"):
        print(f"{key} = {fit[key]:.3f}")
    print(f"# amplitudes {math.hypot(fit['x_cos_arcsec'], fit['x_sin_arcsec']):.3f} x "
          f"{math.hypot(fit['y_cos_arcsec'], fit['y_sin_arcsec']):.3f} arcsec; the fit's rms {fit['rms_arcsec']:.3f}")


if __name__ == "__main__":
    main()
