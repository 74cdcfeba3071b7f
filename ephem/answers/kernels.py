"""NAIF SPICE text PCK kernels (``KPL/PCK``) fitted to the spin-axis track.

A text PCK gives a body's orientation as three angles of time (NAIF, *PCK Required Reading*,
pck.req, "Models for the Sun, Planets, and Asteroids" and "Models for Satellites in Text PCK
Kernels"; SPICELIB TISBOD, toolkit N0067):

    RA  = RA0  + RA1  T + RA2  T² + Σ_i a_i sin θ_i          (degrees)
    DEC = DEC0 + DEC1 T + DEC2 T² + Σ_i d_i cos θ_i          (degrees)
    W   = W0   + W1   d + W2   d²                            (degrees)
    θ_i = θ0_i + θ1_i T                                      (degrees, degrees per Julian century)

T in Julian centuries and d in days of TDB from J2000 (JD 2451545.0 TDB). The kernel variables are
``BODYnnn_POLE_RA``, ``BODYnnn_POLE_DEC``, ``BODYnnn_PM`` (each [c0, c1, c2]), ``BODYnnn_NUT_PREC_RA``
(the a_i), ``BODYnnn_NUT_PREC_DEC`` (the d_i) and ``BODYbbb_NUT_PREC_ANGLES`` (the pairs θ0_i, θ1_i).
bbb is SPICELIB ZZBODBRY's "barycenter code" of nnn: nnn // 100 for a planet or satellite code
100-999, nnn // 10000 for 10000-99999, and nnn itself for any other body, so that an asteroid such as
Vesta (2000004) carries its own ``BODY2000004_NUT_PREC_ANGLES`` while the Earth's angles are the
Earth-Moon system's ``BODY3_NUT_PREC_ANGLES``. The same code names ``BODYbbb_CONSTANTS_REF_FRAME``
(the inertial frame of RA and DEC, an IRFNUM code; default J2000) and ``BODYbbb_MAX_PHASE_DEGREE``
(the angles' polynomial degree, default 1), which the kernels written here state explicitly. TISBOD
signals SPICE(INSUFFICIENTANGLES) when a coefficient list is longer than the angle list and holds
at most 200 angles per body (N0067); older toolkits hold 100 (MAXANG in TISBOD and BODEUL), the
default cap here.

The fit. The track (:func:`ephem.answers.requests.track_arrays`) is quasi-periodic in two frequencies: the
orbital mean motion n (the nutation's argument is the mean anomaly M) and the precession rate ψ̇
(the pole turns about the orbit normal, and the nutation's displacement turns with it). Its right
ascension and declination are therefore sums of terms at k n + j ψ̇ (k >= 0, any j), which SPICE's
angles, linear in T, represent exactly; one frequency takes two angles (θ and θ + 90°) because RA
takes only sines and DEC only cosines. The quadratic polynomials carry the secular motion. The
frequencies (0 <= k <= 2 k_max of the nutation series, |j| <= :data:`ephem.sun.ladder.TRACK_SIDEBANDS`; for the Earth with
the Moon, the ``lunisolar`` model, the lunisolar series' terms instead, their phases in the Delaunay
arguments linearised at the span's middle, |j| <= :data:`ephem.earth.model.TRACK_SIDEBANDS`) are chosen one at a time
by orthogonal least squares (the one that lowers the residual most), the coefficients by linear least
squares over a dense grid of the span, RA weighted by cos DEC so that both residuals are angles on
the sky. The fit error is the largest angle between the kernel's pole, evaluated as SPICE does, and
the track over the fit grid and a grid :data:`CHECK_DENSITY` times denser offset from it, raised by
:data:`~ephem.exports.pck_fit.CHECK_MARGIN` for the maxima between epochs, plus
:func:`~ephem.exports.pck_kernel.rounding_bound` for SPICE's
double-precision arithmetic. Terms are added until that error is below the
aim (:data:`~ephem.exports.pck_fit.FIT_AIM_MAS`); if the angle budget runs out first the kernel is written only if the
error is below the limit (:data:`~ephem.exports.pck_fit.FIT_LIMIT_MAS`; both default to a tenth of the model's estimated
error where that is smaller, the limit raised to 5 % of that error where it is larger (the Moon's
models, whose estimates are arcseconds: the kernel adds at most 5 % to them); both are ``fit_tolerance_mas`` when given), and otherwise refused
(:class:`~ephem.base.errors.InvalidInputError` on ``stop``).

Frames. The track's poles are ICRF; SPICE's J2000 frame differs from the ICRF by the frame bias
(~20 mas). Like the IAU WGCCRE models in NAIF's generic PCKs, the kernel gives ICRF coordinates as
J2000 ones. A pole within 10° of the J2000 pole (the Earth's) makes RA a poor coordinate (it swings
through 180° as the pole passes near the frame's pole); such a body's RA and DEC are ecliptic
longitude and latitude in SPICE's ECLIPJ2000 (``BODYbbb_CONSTANTS_REF_FRAME = 17``), and SPICE
rotates them back.

The prime meridian. The catalogue has the rotation period P but no W0: W1 = 360° / P (days) and, for
the bodies :func:`~ephem.exports.pck_fit.iau_orientation` knows (the catalogue's asteroids, Mars, the Earth), W0 puts the
prime meridian where the IAU WGCCRE model puts it at the middle of the span: the IAU model's body x
axis there, projected on our kernel's equator, measured from our node. Our pole and the IAU's differ
(the IAU asteroid poles are fixed, ours precess), so this is the nearest meridian to the IAU's, not the
IAU's W; over the span the two drift apart by the difference of the node motions and of W1. For
other bodies W0 = 0. The pole does not depend on W.
"""
from __future__ import annotations

import math
from datetime import UTC, datetime
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ..base.errors import InvalidInputError
from ..base.grids import SAFE_SPACINGS, resolution
from ..base.times import to_jd_tdb
from ..base.units import in_unit
from ..bodies.catalogue import DEFAULT_DATASET, Body, resolve_body
from ..exports.pck_fit import CHECK_DENSITY, DEFAULT_MAX_ANGLES, MIN_FIT_SAMPLES, SPICE_MAX_ANGLES, fit_body
from ..exports.pck_kernel import PckResult, angles_owner
from ..exports.pck_text import ascii_text, comment_lines, data_block, time_text
from ..families import theory_for
from . import requests
from .requests import Epoch
from .parameters import shared_parameters

if TYPE_CHECKING:
    from astropy.units import Quantity


def _track(body, start, stop, step_days, **kwargs) -> dict:
    """The fit's track: :func:`ephem.answers.requests.track_arrays`, looked up at each call (the stability tests
    perturb it there), without the calendar dates (the fit reads jd_tdb). The fit gives a body, which carries its
    dataset, and the model asked for by keyword (:func:`ephem.exports.pck_fit.fit_body`)."""
    return requests.track_arrays(body, start, stop, step_days, **{"time_scale": None, **kwargs})


@shared_parameters
def write_pck(bodies: str | int | Body | Sequence[str | int | Body], start: Epoch, stop: Epoch, *,
              tolerance_mas: float | Quantity | None = None, model: str | None = None, order: int | None = None,
              axis: str = "figure", dataset: str = DEFAULT_DATASET, perturbers: str | Sequence[str] | None = None,
              fit_tolerance_mas: float | Quantity | None = None, max_angles: int = DEFAULT_MAX_ANGLES,
              generated: datetime | None = None) -> PckResult:
    """A NAIF text PCK (``KPL/PCK``) of the bodies' poles over [start, stop], fitted to ephem's track.

    The fit (the module's docstring) follows the track of :func:`ephem.answers.requests.track` with this model (the
    Earth with the Moon: the lunisolar series' terms are the frequencies); by default it aims at
    :data:`~ephem.exports.pck_fit.FIT_AIM_MAS` and accepts up to :data:`~ephem.exports.pck_fit.FIT_LIMIT_MAS` (each at
    most a tenth of the model's estimated error).

    Parameters
    ----------
    bodies : str, int, Body or sequence of them
        One body or a list: names, NAIF ids or :class:`~ephem.bodies.catalogue.Body` (with a ``naif_id``).
    start, stop : str, float or astropy.time.Time
        The span: ISO 8601 text (UTC unless a scale is named), a JD TDB or a ``Time``.
    tolerance_mas
    model
    order
    axis
    dataset
    perturbers
    fit_tolerance_mas : float or Quantity, optional
        The largest angle allowed between the kernel's pole and the track anywhere in the span, milliarcseconds.
    max_angles : int
        The nutation-precession angles allowed per body: default 100, the limit of SPICE toolkits before N0067; at
        most 200.
    generated : datetime, optional
        The time stamped in the comments (default now).

    Returns
    -------
    PckResult
        ``text`` (the kernel, ASCII), per-body fits (``fit_error_mas``, ``models``) and the span (JD TDB and UTC).

    Raises
    ------
    UnknownBodyError
        For an unknown body.
    NotApplicableError
        Where no theory holds (a Moon under the Sun alone).
    InvalidInputError
        Naming the field, for bad inputs; ``stop`` for a span the fit cannot follow within the limit.
    """
    t0 = to_jd_tdb(start, "start")
    t1 = to_jd_tdb(stop, "stop")
    if not t1 > t0:
        raise InvalidInputError("stop", f"stop (JD {t1} TDB) must be after start (JD {t0} TDB)")
    least = SAFE_SPACINGS * resolution(t0, t1) * CHECK_DENSITY * (MIN_FIT_SAMPLES - 1)
    if t1 - t0 < least:     # the check grid's step would be finer than the span's Julian dates resolve
        raise InvalidInputError("stop", f"stop is {t1 - t0:.4g} d after start: a kernel's fit samples the span at "
                                f"{CHECK_DENSITY * (MIN_FIT_SAMPLES - 1)} steps at least, which float64 Julian dates "
                                f"resolve over a span of at least {least:.4g} d")
    if isinstance(bodies, (str, int, Body)):
        bodies = [bodies]
    try:
        bodies = list(bodies)
    except TypeError:
        raise InvalidInputError("bodies", f"expected body names or NAIF ids, got {bodies!r}") from None
    if not bodies:
        raise InvalidInputError("bodies", "give at least one body")
    if isinstance(max_angles, bool) or not isinstance(max_angles, int) or not 0 <= max_angles <= SPICE_MAX_ANGLES:
        raise InvalidInputError("max_angles", f"must be an integer in [0, {SPICE_MAX_ANGLES}], got {max_angles!r}")
    if fit_tolerance_mas is not None:
        fit_tolerance_mas = in_unit(fit_tolerance_mas, "mas", "fit_tolerance_mas")
        if isinstance(fit_tolerance_mas, bool) or not isinstance(fit_tolerance_mas, (int, float)) \
                or not math.isfinite(fit_tolerance_mas) or fit_tolerance_mas <= 0.0:
            raise InvalidInputError("fit_tolerance_mas", "must be a positive finite number of milliarcseconds, "
                                    f"got {fit_tolerance_mas!r}")
    resolved = [resolve_body(b, dataset) for b in bodies]
    seen, owners = set(), {}
    for b in resolved:
        if b.naif_id is None:
            raise InvalidInputError("naif_id", "a body needs a NAIF id to name its kernel variables", b.name)
        if b.naif_id in seen:
            raise InvalidInputError("bodies", f"{b.name} (NAIF ID {b.naif_id}) is listed twice")
        seen.add(b.naif_id)
        own = angles_owner(b.naif_id)
        if own in owners:
            raise InvalidInputError("bodies", f"{b.name} and {owners[own]} would share BODY{own}_NUT_PREC_ANGLES "
                                    "(one planetary system): write them to separate kernels")
        owners[own] = b.name
    # the model asked for, one value from here to each body's track
    asked = {"tolerance_mas": tolerance_mas, "model": model, "order": order, "axis": axis, "perturbers": perturbers}
    fits = [fit_body(b, t0, t1, asked, fit_tolerance_mas, max_angles, track=_track, theory_for=theory_for)
            for b in resolved]
    when = generated or datetime.now(UTC)
    stamp = (when.astimezone(UTC) if when.tzinfo else when).strftime("%Y-%m-%dT%H:%M:%S UTC")
    lines = ["KPL/PCK", "", "\\begintext", ""]
    lines += comment_lines(fits, t0, t1, stamp, max_angles)
    for f in fits:
        lines += data_block(f)
    lines += ["End of kernel", ""]
    return PckResult(text=ascii_text("\n".join(lines)), bodies=tuple(fits), start_jd_tdb=t0, stop_jd_tdb=t1,
                     start_utc=time_text(t0, "utc"), stop_utc=time_text(t1, "utc"), generated_utc=stamp)


def write_pck_file(path: str | Path, bodies: str | int | Body | Sequence[str | int | Body], start: Epoch, stop: Epoch,
                   **kwargs) -> PckResult:
    """:func:`write_pck` with the text written to ``path`` (conventionally ``*.tpc``, ASCII).

    Parameters
    ----------
    path : str or Path
        The file written.
    bodies : str, int, Body or sequence of them
        As :func:`write_pck`.
    start, stop : str, float or astropy.time.Time
        As :func:`write_pck`.
    **kwargs
        :func:`write_pck`'s keywords (``tolerance_mas``, ``model``, ``order``, ``axis``, ``dataset``, ``perturbers``,
        ``fit_tolerance_mas``, ``max_angles``, ``generated``).

    Returns
    -------
    PckResult
        As :func:`write_pck`.
    """
    result = write_pck(bodies, start, stop, **kwargs)
    Path(path).write_text(result.text, encoding="ascii")
    return result
