"""The averaged spin equation, integrated along a moving orbit over millennia and millions of years.

Averaged over the rotation and over the orbit, the torque of the orbit's centre (and, for the Earth, of the
Moon, whose orbit precesses about the ecliptic in 18.6 years) turns the unit spin axis ŝ about the orbit
normal n̂ (Ward 1973, Science 181, 260; Laskar, Joutel & Robutel 1993, A&A 270, 522, eq. 1; Kinoshita 1977's
secular part):

    dŝ/dt = α (ŝ·n̂) (ŝ × n̂) + Ω_gp (n̂ × ŝ),

α the precession constant (the body's own theory gives ψ̇ = α cos ε: Petit et al. eq. 25 for one perturber,
the lunisolar series for the Earth), which scales with the orbit as n² (1 − e²)^(−3/2) ∝ a⁻³ (1 − e²)^(−3/2),
and Ω_gp the geodesic precession (:mod:`ephem.orbit.relativity`, ∝ a^(−5/2) (1 − e²)^(−1)), which turns the axis
about n̂ in the orbital sense. The orbit normal n̂(t), a(t) and e(t) come from an orbit history (the shipped
N-body histories of :mod:`ephem.longterm.nbody_orbit`, or the secular theory of :mod:`ephem.longterm.secular_orbit`), each with
``pole_at``, ``eccentricity_at`` and ``semi_major_axis_at`` of Julian years from J2000.0 TDB.

The equation is integrated from the body's mean pole at its epoch, both ways, by a 4th-order splitting (Blanes &
Moan 2002's S6: with the time frozen the field is a rotation about n̂ by a known angle; :func:`_split_side`), scipy's
DOP853 the reference (``method="DOP853"``), together with neighbouring solutions (the precession constant and the
pole displaced by their 1σ, or by a stated probe where no σ is published): their divergence from the nominal solution is the estimate's sensitivity terms (of the pole
and of the obliquity), and where their obliquities part by more than :data:`MEANINGFUL_LIMIT` the history stops
meaning anything (Laskar & Robutel 1993's method for Mars' chaotic obliquity). What the averaged equation leaves out (the nutation: periodic terms of at most a body's
half peak-to-peak nutation) is the estimate's ``nutation`` term.

Angles in radians, times in Julian years (365.25 d) from J2000.0 TDB, vectors in the ecliptic and equinox of
J2000, unless a name says otherwise.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..base.budget import checkpoint
from ..bodies.catalogue import Body
from ..base.constants import J2000_JD, JULIAN_YEAR_DAYS
from ..base.errors import NotApplicableError
from ..orbit.geometry import angle_between, icrf_to_ecliptic_matrix, lon_lat
from ..orbit.relativity import geodesic_precession_rate
from ..forced.catalogue_sigmas import dynamical_ellipticity_sigma, input_sigmas
from ..theory.cost import spin_history
from .cubic_spline import CubicSpline

#: DOP853's relative tolerance (the reference path): over 4 Myr (the shipped N-body orbits) the Earth's pole moves
#: by 0.9″ at 1e-10, Vesta's by 0.5″, Ceres' and Mars' by 0.1″, their obliquities by at most 0.13″, far below the
#: nutation the averaged equation leaves out (the Earth's 12″). At 1e-8 the Earth's pole moved by 11.6″ once its
#: tidal neighbour joined the stacked solutions; 5e-9 costs 15-30 % more evaluations than 1e-8, 1e-10 twice as many.
#: The splitting (the default) is within 0.02″ of DOP853 at 5e-13 there (but Eros: :data:`SPLIT_NORMAL_TURN`); a
#: RTOL tightened below 5e-9 refines its steps by (5e-9 / RTOL)^(1/4) (its order), rounded up to a power of two
#: (tests/longterm/test_spin_history.py tightens it a hundredfold)
RTOL = 5e-9
ATOL = 1e-12
#: the integrators: "splitting" (the default, :func:`_split_side`) and "DOP853" (the reference: scipy's, at RTOL)
METHODS = ("splitting", "DOP853")
METHOD = "splitting"
#: where the neighbouring solutions' obliquities part by more than this, the history stops meaning anything
#: (radians): the obliquity is then known to no better than a degree
MEANINGFUL_LIMIT = math.radians(1.0)
#: the relative probe of the precession constant's own change over the span, which no source bounds: the equation
#: holds the moments and the spin fixed (the figure's response to ice loads, true polar wander, YORP; the Earth's
#: mean tidal drift is counted apart, ephem.earth.model.tidal_constant_drift). It is added in quadrature to the published
#: σ of today's constant (Mars': 2.8e-4, Baland et al. 2020; the Earth's: 3e-7, IERS 2010), which alone would
#: claim a constant known over millions of years to that level: the Earth's estimate would then no longer cover
#: La2004 beyond ±0.3 Myr (tests/longterm/test_against_laskar2004.py)
DEFAULT_CONSTANT_PROBE = 1e-3
#: the pole probe where no σ is published (radians): 0.01°, the printed digits of most catalogue poles
DEFAULT_POLE_PROBE = math.radians(0.01)


@dataclass(frozen=True)
class SpinConstants:
    """What the averaged spin equation needs of a body (from its own theory; radians and Julian years).

    ``orbit_constant`` α₀ is the precession constant of the orbit centre's torque at (``a0_au``, ``e0``);
    ``fixed_constant`` the part that does not follow the heliocentric orbit (the Earth: the Moon's);
    ``geodesic_rate`` Ω_gp at (a0, e0). ``constant_sigma`` and ``pole_sigma`` are the 1σ of α (relative) and of
    the pole (radians), None where unpublished; ``constant_drift`` the change of α per year that the equation leaves
    out (relative; tides), which the α neighbour adds as |t − t0| grows. ``nutation`` is the largest periodic displacement of the pole the
    averaged equation leaves out.
    """

    body: str
    epoch_years: float
    mean_pole: np.ndarray = field(repr=False)
    orbit_constant: float
    fixed_constant: float
    geodesic_rate: float
    a0_au: float
    e0: float
    nutation: float
    constant_sigma: float | None = None
    pole_sigma: float | None = None
    source: str = ""
    #: the secular change of α the averaged equation leaves out, relative per year (the Earth's tides: ephem.earth.family
    #: TIDAL_CONSTANT_DRIFT_PER_YEAR); the α neighbour drifts away at this rate from the epoch, both ways
    constant_drift: float = 0.0

    def constants(self, a_au, e) -> tuple[np.ndarray, np.ndarray]:
        """(α, Ω_gp) in rad/yr on an orbit of semi-major axis ``a_au`` and eccentricity ``e`` (arrays)."""
        a_au, e = np.asarray(a_au, dtype=float), np.asarray(e, dtype=float)
        bound = np.isfinite(a_au) & (a_au > 0.0) & np.isfinite(e) & (np.abs(e) < 1.0)
        if not bound.all():     # an orbit's history (its spline between samples, say) leaving the bound orbits
            i = int(np.argmin(bound))
            raise NotApplicableError(self.body, f"the orbit's history leaves the bound orbits (a = {a_au.flat[i]:.4g} "
                                     f"AU, e = {e.flat[i]:.4g}), where the averaged spin's constants are undefined")
        a_ratio = self.a0_au / a_au
        e2 = e ** 2
        one_e2 = (1.0 - self.e0**2) / (1.0 - e2)
        alpha = self.orbit_constant * a_ratio**3 * one_e2**1.5 + self.fixed_constant
        return alpha, self.geodesic_rate * a_ratio**2.5 * one_e2

    @property
    def orbit_body(self) -> str:
        """Whose orbit history drives the spin: the body's own."""
        return self.body

    def history(self, orbit, years, progress=None) -> "SpinHistory":
        """:func:`integrate` along ``orbit``."""
        return integrate(self, orbit, years, progress)

    def cost(self, span_years: float, epochs: int, sides: int = 1):
        """What :meth:`history` costs over ``span_years`` at ``epochs`` epochs (:func:`ephem.theory.cost.spin_history`),
        the splitting's steps per orbit sample as :func:`split_steps` sets them on the body's own orbit; ``sides``:
        of the epoch the epochs reach (:func:`integrate` runs outward to each, its fixed work once a side)."""
        scale = 1.0 + math.hypot(self.constant_sigma or 0.0, DEFAULT_CONSTANT_PROBE) \
            + abs(self.constant_drift) * span_years
        rate = (abs(self.orbit_constant) + abs(self.fixed_constant)) * scale + abs(self.geodesic_rate)
        return spin_history(span_years, epochs, steps_per_sample(rate), sides)


def steps_per_sample(rate_rad_per_year: float) -> int:
    """The splitting's steps per orbit sample (:func:`split_steps`) for a precession rate bound |α| + |Ω_gp|
    (rad/yr), the orbit normal's turn aside: what a history's cost is priced at before its orbit is sampled."""
    return int(split_steps(np.array([abs(rate_rad_per_year) * ORBIT_SAMPLE_YEARS]), np.zeros(1))[0])


@dataclass(frozen=True)
class SpinHistory:
    """The averaged spin axis at the requested epochs (radians; ``years`` from J2000.0 TDB)."""

    years: np.ndarray
    spin: np.ndarray              # (N, 3) unit spin axis, ecliptic J2000
    orbit_pole: np.ndarray        # (N, 3) unit orbit normal, ecliptic J2000
    obliquity: np.ndarray
    precession_angle: np.ndarray  # the equinox's retrograde turn since the epoch, unwrapped
    pole_ra: np.ndarray           # ICRF
    pole_dec: np.ndarray
    orbit_inclination: np.ndarray  # n̂ from the J2000 ecliptic pole
    terms: dict                   # name -> (N,) estimated error of the pole, radians
    obliquity_terms: dict         # name -> (N,) estimated error of the obliquity, radians
    unestimated: tuple = ()
    meaningful_years: tuple = (-math.inf, math.inf)
    evaluations: int = 0

    @property
    def error(self) -> np.ndarray:
        total = np.zeros(self.years.shape)
        for v in self.terms.values():
            total = total + v
        return np.minimum(total, math.pi)


#: the orbit's sampling for the integration (years): the shipped histories' own step. A natural cubic spline
#: through samples h apart misses a mode of period P by ~(2π h / P)⁴ / 384 of its amplitude, 1e-6 for the fastest
#: orbit-plane mode of the catalogue (Ceres' 22 kyr); resampling at 250 years moves 4-Myr histories by < 4″, at
#: 1000 years (dropping half the osculating samples' short-period noise) by up to 150″. A C² interpolant keeps
#: DOP853's steps long (a C¹ one, Catmull–Rom, took 3x more)
ORBIT_SAMPLE_YEARS = 500.0
#: the least spacing of the orbit's knots (years, ~32 s): a shorter span is sampled on knots this far apart
MIN_KNOT_YEARS = 1e-6


class _SampledOrbit:
    """n̂(t), α(t) and Ω_gp(t) sampled once on an even grid and splined: ``spline`` for arrays of epochs (the
    splitting), :meth:`at` in plain floats for DOP853's right-hand side (called ~10⁴ times per million years: numpy's
    per-call overhead would dominate)."""

    def __init__(self, orbit, spin: SpinConstants, lo: float, hi: float):
        # samples on [lo, hi] only (the orbit may end there), at most ORBIT_SAMPLE_YEARS apart
        intervals = max(int(math.ceil((hi - lo) / ORBIT_SAMPLE_YEARS)), 3)
        # a span too short for knots MIN_KNOT_YEARS apart (a history within seconds of the spin's epoch): knots that
        # far apart, the orbit held at hi beyond it (it moves by ~1e-12 rad in 1e-6 years), not knots that float64
        # cannot tell apart or a spline that divides by a subnormal spacing
        short = not hi - lo >= intervals * MIN_KNOT_YEARS
        t = lo + MIN_KNOT_YEARS * np.arange(4.0) if short else np.linspace(lo, hi, intervals + 1)
        n = orbit.pole_at(np.minimum(t, hi))
        alpha, gp = spin.constants(orbit.semi_major_axis_at(np.minimum(t, hi)), orbit.eccentricity_at(np.minimum(t, hi)))
        self.t0 = float(t[0])
        self.h = float(t[1] - t[0])
        self.knots, self.normal, self.alpha, self.geodesic = t, n, alpha, gp
        self.spline = CubicSpline(t, np.column_stack([n, alpha, gp]))
        self.last = t.size - 2

    @cached_property
    def rows(self) -> list:
        """One flat tuple per interval: (c3, c2, c1, c0) of each of the 5 columns, a single lookup per call."""
        c = self.spline.c                                                # (4, intervals, 5)
        return [tuple(map(float, row)) for row in np.transpose(c, (1, 2, 0)).reshape(c.shape[1], 20)]

    def at(self, t: float) -> tuple:
        x = t - self.t0
        j = min(max(int(x / self.h), 0), self.last)
        dx = x - j * self.h
        r = self.rows[j]
        return (((r[0] * dx + r[1]) * dx + r[2]) * dx + r[3], ((r[4] * dx + r[5]) * dx + r[6]) * dx + r[7],
                ((r[8] * dx + r[9]) * dx + r[10]) * dx + r[11], ((r[12] * dx + r[13]) * dx + r[14]) * dx + r[15],
                ((r[16] * dx + r[17]) * dx + r[18]) * dx + r[19])


#: how often (right-hand-side calls) the integration reports its progress and checks the request's deadline
REPORT_EVERY = 500


def _rhs(sampled: _SampledOrbit, scales: tuple, counter: list, report=None, drifts: tuple | None = None,
         t0: float = 0.0):
    """The right-hand side for k stacked solutions (α scaled by ``scales[i] + drifts[i] |t − t0|``):
    dŝ/dt = (α (ŝ·n̂) − Ω_gp) (ŝ × n̂). Every :data:`REPORT_EVERY` calls, ``report(t)`` (the deadline's checkpoint
    and the caller's progress)."""
    k = len(scales)
    drifts = drifts or (0.0,) * k

    def f(t, y):
        counter[0] += 1
        if report is not None and counter[0] % REPORT_EVERY == 0:
            report(t)
        nx, ny, nz, alpha, gp = sampled.at(t)
        norm = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
        nx, ny, nz = nx * norm, ny * norm, nz * norm
        out = [0.0] * (3 * k)
        for i in range(k):
            x, y_, z = y[3 * i], y[3 * i + 1], y[3 * i + 2]
            f_ = alpha * (scales[i] + drifts[i] * abs(t - t0)) * (x * nx + y_ * ny + z * nz) - gp
            out[3 * i] = f_ * (y_ * nz - z * ny)
            out[3 * i + 1] = f_ * (z * nx - x * nz)
            out[3 * i + 2] = f_ * (x * ny - y_ * nx)
        return out

    return f


def _neighbours(spin: SpinConstants, n0: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple]:
    """Initial states (k, 3), α scales (k,), the probed terms and the α drifts (k,): the nominal solution, α by its
    σ and the probe of its change (:data:`DEFAULT_CONSTANT_PROBE`) drifting as ``constant_drift``, and the pole
    moved by its σ (or probe) obliquely (half along the meridian through the orbit normal, half across it: a generic
    direction, which picks up the fastest divergence, Lyapunov's, whatever its direction)."""
    s0 = spin.mean_pole / np.linalg.norm(spin.mean_pole)
    d_alpha = math.hypot(spin.constant_sigma or 0.0, DEFAULT_CONSTANT_PROBE)
    d_pole = spin.pole_sigma if spin.pole_sigma is not None else DEFAULT_POLE_PROBE
    across = np.cross(n0, s0)
    if np.linalg.norm(across) < 1e-12:  # the pole on the orbit normal: any direction across it
        across = np.cross(s0, [1.0, 0.0, 0.0] if abs(s0[0]) < 0.9 else [0.0, 1.0, 0.0])
    across /= np.linalg.norm(across)
    oblique = (across + np.cross(s0, across)) / math.sqrt(2.0)
    states = [s0, s0, math.cos(d_pole) * s0 + math.sin(d_pole) * oblique]
    scales = np.array([1.0, 1.0 + d_alpha, 1.0])
    probes = ("precession_constant",) + (("pole",) if spin.pole_sigma is None else ())
    return np.array(states), scales, probes, (0.0, float(spin.constant_drift), 0.0)


def integrate(spin: SpinConstants, orbit, years, progress=None, method: str | None = None) -> SpinHistory:
    """The averaged spin axis of ``spin`` along ``orbit`` at ``years`` (a 1-D array, any order), with the
    estimate's terms (module docstring). ``progress``: called with the fraction of the span integrated (0 to 1)
    now and then (a console's progress bar). ``method``: one of :data:`METHODS` (None: :data:`METHOD`)."""
    method = METHOD if method is None else method
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    years = np.asarray(years, dtype=float)
    t0 = spin.epoch_years
    n0 = orbit.pole_at(t0)
    y0, scales, probes, drifts = _neighbours(spin, n0)
    counter = [0]
    lo, hi = min(years.min(), t0), max(years.max(), t0)
    done = {"before": 0.0}

    def report(t: float) -> None:
        checkpoint()
        if progress is not None:
            side = t0 - t if t < t0 else t - t0
            progress(min(1.0, (done["before"] + side) / max(hi - lo, 1e-300)))

    sampled = _SampledOrbit(orbit, spin, lo, hi)
    scales_f = tuple(map(float, scales))
    states = np.empty((years.size, scales.size, 3))
    precession = np.empty(years.size)
    lon0 = _equinox_longitude(y0[0], n0)
    for side in (years < t0, years >= t0):
        if not side.any():
            continue
        t_end = float(years[side].min() if years[side].min() < t0 else years[side].max())
        if t_end == t0:
            states[side] = y0
            precession[side] = 0.0
            continue
        if method == "DOP853":
            from scipy.integrate import solve_ivp      # not at import: a one-body answer never loads the integrators

            f = _rhs(sampled, scales_f, counter, report, drifts, t0)
            sol = solve_ivp(f, (t0, t_end), y0.ravel(), method="DOP853", rtol=RTOL, atol=ATOL, dense_output=True)
            if not sol.success:
                raise RuntimeError(f"the spin integration of {spin.body} failed: {sol.message}")
            states[side] = sol.sol(years[side]).T.reshape(-1, scales.size, 3)
            precession[side] = _precessionangle_between(sol, orbit, t0, t_end, lon0, years[side])
        else:
            nodes, snaps = _split_side(sampled, y0, scales_f, drifts, t0, t_end, report)
            states[side] = _split_to(sampled, nodes, snaps, years[side], scales_f, drifts, t0)
            counter[0] += _STAGES.shape[1] * (nodes.size - 1 + int(side.sum()))
            precession[side] = _split_precession(nodes, snaps[:, 0], years[side], states[side][:, 0], orbit, t0, lon0)
        done["before"] += abs(t_end - t0)
    if progress is not None:
        progress(1.0)
    states /= np.linalg.norm(states, axis=-1, keepdims=True)
    s = states[:, 0]
    n = orbit.pole_at(years)
    eps = [angle_between(states[:, k], n) for k in range(3)]
    # the neighbours' distances cross zero as they wind about each other: the estimate is their envelope, the
    # largest so far from the epoch outward
    terms = {"nutation": np.full(years.shape, spin.nutation),
             "precession_constant": outward_max(years, t0, angle_between(states[:, 1], s)),
             "pole": outward_max(years, t0, angle_between(states[:, 2], s))}
    obliquity_terms = {"nutation": np.full(years.shape, spin.nutation),
                       "precession_constant": outward_max(years, t0, np.abs(eps[1] - eps[0])),
                       "pole": outward_max(years, t0, np.abs(eps[2] - eps[0]))}
    return history_arrays(years, s, n, precession, terms, obliquity_terms, probes, t0,
                          np.maximum(obliquity_terms["precession_constant"], obliquity_terms["pole"]), counter[0])


# ----------------------------------------------------------------------------- the splitting
#
# With the time frozen, the field is a rotation about n̂(t) at the rate −(α(t) c − Ω_gp(t)), c = ŝ·n̂ unchanged by
# it: flow B, exact. Advancing the time with ŝ held is flow A. Their composition (Blanes & Moan 2002, J. Comput.
# Appl. Math. 142, 313, Table 2's S6: e^{a1 hA} e^{b1 hB} e^{a2 hA} ... e^{b6 hB} e^{a7 hA}, symmetric, order 4,
# six B stages) is a product of six rotations per step, each about n̂ at a time inside the step. On a fixed orbit
# A and B commute and a step is exact. The steps cut each orbit sample interval in a power of two (:func:`split_steps`),
# so that every stage sees one cubic piece of the spline.

_S6_A = (0.0792036964311957, 0.353172906049774, -0.0420650803577195)
_S6_B = (0.209515106613362, -0.143851773179818)
#: (2, 6): each B stage's time within the step (fraction of h, the running sum of the a's) and its weight b
_STAGES = np.array([np.cumsum(_S6_A + (1.0 - 2.0 * sum(_S6_A),) + _S6_A[::-1][:2]),
                    _S6_B + (0.5 - sum(_S6_B),) * 2 + _S6_B[::-1]])
#: the splitting's steps: at most this much |α| + |Ω_gp| times the step (radians: the precession's rate bound, and
#: α the rate at which it answers a change of c) ...
SPLIT_RATE_ANGLE = 0.5
#: ... and at most this turn of the orbit normal between two samples per step (radians, the chord). Measured over the
#: shipped spans, the three solutions, against DOP853 at rtol 5e-13: with one step per 500-year sample Mars, Ceres
#: (whose normal turns 0.027 rad a sample, the catalogue's fastest regular orbit) and Steins are within 0.005″ of
#: it, the Earth and Vesta within 0.02″, DOP853's own error there (5e-12 against 5e-13: 0.05″, 0.03″); Eros (|α| to
#: 1440″/yr, its normal jumping up to 0.13 rad between samples: 1.8 steps a sample) within 0.4″ where its history
#: means something (0.006″ at half these limits, 3.6 steps a sample; tests/longterm/test_history_stepper.py)
SPLIT_NORMAL_TURN = 0.03
#: steps between two report() calls (the deadline's checkpoint, the caller's progress): ~5 ms
SPLIT_CHUNK = 512
#: at most 2^20 steps per orbit sample (500 years in 4-hour steps): beyond, the request's deadline stops it
MAX_SPLIT_LEVELS = 20


def split_steps(rate_angle: np.ndarray, turn: np.ndarray) -> np.ndarray:
    """Steps per orbit sample interval: the least power of two bringing ``rate_angle`` (|α| + |Ω_gp| times the
    interval, radians) within :data:`SPLIT_RATE_ANGLE` and ``turn`` (the orbit normal's, radians) within
    :data:`SPLIT_NORMAL_TURN`, times RTOL's refinement. Compared with powers of two exactly, so a last-bit change
    of a rate moves the count only where it sits on a power of two, and then the answer by that interval's
    truncation error alone (a share of the whole history's, which the tests hold within its budget)."""
    x = np.maximum(np.asarray(rate_angle, float) / SPLIT_RATE_ANGLE, np.asarray(turn, float) / SPLIT_NORMAL_TURN)
    m = np.ones(x.shape)
    for _ in range(MAX_SPLIT_LEVELS):
        more = x > m
        if not more.any():
            break
        m[more] *= 2.0
    refine = 1
    while refine < (5e-9 / RTOL) ** 0.25 * (1.0 - 1e-12) and refine < 2 ** MAX_SPLIT_LEVELS:
        refine *= 2
    return m.astype(np.int64) * refine


def _split_grid(sampled: _SampledOrbit, scales: tuple, drifts: tuple, t0: float, t_end: float) -> np.ndarray:
    """The step nodes from ``t0`` outward to ``t_end``: the samples between, each interval cut in its
    :func:`split_steps` (the α neighbour's scale at its largest over the span)."""
    k = sampled.knots
    inner = k[(k > t0) & (k < t_end)] if t_end > t0 else k[(k < t0) & (k > t_end)][::-1]
    ends = np.concatenate([[t0], inner, [t_end]])
    a, b = ends[:-1], ends[1:]
    j = np.clip(((0.5 * (a + b) - k[0]) // sampled.h).astype(np.int64), 0, sampled.last)
    scale = max(s + abs(d) * abs(t_end - t0) for s, d in zip(scales, drifts))
    rate = np.maximum(np.abs(sampled.alpha[:-1]), np.abs(sampled.alpha[1:])) * scale \
        + np.maximum(np.abs(sampled.geodesic[:-1]), np.abs(sampled.geodesic[1:]))
    turn = np.linalg.norm(sampled.normal[1:] - sampled.normal[:-1], axis=-1)
    m = split_steps(rate * np.diff(k), turn)[j]
    seg = np.repeat(np.arange(a.size), m)
    i = np.arange(seg.size) - np.repeat(np.cumsum(m) - m, m)
    return np.concatenate([a[seg] + (b[seg] - a[seg]) * (i / m[seg]), [t_end]])


def _stage_rows(sampled: _SampledOrbit, t: np.ndarray, bh: np.ndarray, scales: tuple, drifts: tuple, t0: float):
    """At the stage epochs ``t`` with weights ``bh`` (years): the unit n̂ (N, 3), b h Ω_gp (N,) and b h α of each
    stacked solution (N, k)."""
    v = sampled.spline(t)
    n = v[:, :3] / np.linalg.norm(v[:, :3], axis=-1, keepdims=True)
    dt = np.abs(t - t0)
    alpha = np.column_stack([bh * v[:, 3] * (s + d * dt) for s, d in zip(scales, drifts)])
    return n, bh * v[:, 4], alpha


def _split_side(sampled: _SampledOrbit, y0: np.ndarray, scales: tuple, drifts: tuple, t0: float, t_end: float,
                report) -> tuple[np.ndarray, np.ndarray]:
    """The step nodes from ``t0`` to ``t_end`` (:func:`_split_grid`) and the three solutions there (G, 3, 3), by
    the S6 splitting. The loop is plain floats, three solutions abreast: numpy's per-call overhead would be
    ten times the arithmetic; the stages' n̂, α and Ω_gp are evaluated beforehand, a chunk at a time."""
    nodes = _split_grid(sampled, scales, drifts, t0, t_end)
    h = np.diff(nodes)
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = y0.tolist()
    snaps = [(ax, ay, az, bx, by, bz, cx, cy, cz)]
    cos, sin = math.cos, math.sin
    stages = _STAGES.shape[1]
    for start in range(0, h.size, SPLIT_CHUNK):
        report(float(nodes[start]))
        hc = h[start:start + SPLIT_CHUNK, None]
        n, g, alpha = _stage_rows(sampled, (nodes[start:start + hc.size, None] + _STAGES[0] * hc).ravel(),
                                  (_STAGES[1] * hc).ravel(), scales, drifts, t0)
        left = stages
        # each stage turns each solution about n̂ by θ = b h (Ω_gp − α c): s cos θ + (n̂ × s) sin θ + n̂ c (1 − cos θ)
        for nx, ny, nz, gh, a0, a1, a2 in np.column_stack([n, g, alpha]).tolist():
            c = ax * nx + ay * ny + az * nz
            th = gh - a0 * c
            co, si = cos(th), sin(th)
            d = c * (1.0 - co)
            ax, ay, az = (ax * co + (ny * az - nz * ay) * si + nx * d, ay * co + (nz * ax - nx * az) * si + ny * d,
                          az * co + (nx * ay - ny * ax) * si + nz * d)
            c = bx * nx + by * ny + bz * nz
            th = gh - a1 * c
            co, si = cos(th), sin(th)
            d = c * (1.0 - co)
            bx, by, bz = (bx * co + (ny * bz - nz * by) * si + nx * d, by * co + (nz * bx - nx * bz) * si + ny * d,
                          bz * co + (nx * by - ny * bx) * si + nz * d)
            c = cx * nx + cy * ny + cz * nz
            th = gh - a2 * c
            co, si = cos(th), sin(th)
            d = c * (1.0 - co)
            cx, cy, cz = (cx * co + (ny * cz - nz * cy) * si + nx * d, cy * co + (nz * cx - nx * cz) * si + ny * d,
                          cz * co + (nx * cy - ny * cx) * si + nz * d)
            left -= 1
            if not left:
                snaps.append((ax, ay, az, bx, by, bz, cx, cy, cz))
                left = stages
    return nodes, np.array(snaps).reshape(-1, 3, 3)


def _split_to(sampled: _SampledOrbit, nodes: np.ndarray, snaps: np.ndarray, at: np.ndarray, scales: tuple,
              drifts: tuple, t0: float) -> np.ndarray:
    """The solutions (E, 3, 3) at the epochs ``at``: one S6 step from the node at or before each (outward), a
    part of a step, all epochs at once (an epoch on a node takes a step of zero: the node's state, exactly)."""
    p = np.clip(np.searchsorted(np.abs(nodes - t0), np.abs(at - t0), side="right") - 1, 0, nodes.size - 1)
    h = at - nodes[p]
    s = snaps[p]
    for c, b in _STAGES.T:
        n, g, alpha = _stage_rows(sampled, nodes[p] + c * h, b * h, scales, drifts, t0)
        dot = np.einsum("ekx,ex->ek", s, n)
        th = g[:, None] - alpha * dot
        co, si = np.cos(th)[..., None], np.sin(th)[..., None]
        s = s * co + np.cross(n[:, None, :], s) * si + n[:, None, :] * (dot[..., None] * (1.0 - co))
    return s


def _split_precession(nodes, spin_nodes, at, spin_at, orbit, t0: float, lon0: float) -> np.ndarray:
    """The equinox's retrograde turn since ``t0`` at ``at``, unwrapped through the step nodes and the epochs in
    order from ``t0`` outward (a step turns the equinox by less than |α| + |Ω_gp| times it plus the normal's turn
    over sin ε: at most 0.5 + 0.03 / sin ε rad by :func:`split_steps`, short of π above ε = 0.7°)."""
    t = np.concatenate([nodes[1:], at])
    s = np.concatenate([spin_nodes[1:], spin_at])
    lon = _equinox_longitude(s / np.linalg.norm(s, axis=-1, keepdims=True), orbit.pole_at(t))
    order = np.argsort(np.abs(t - t0), kind="stable")
    unwrapped = np.unwrap(np.concatenate([[lon0], lon[order]]))[1:]
    turned = np.empty(t.size)
    turned[order] = -(unwrapped - lon0)
    return turned[nodes.size - 1:]


def _equinox_longitude(s: np.ndarray, n: np.ndarray) -> np.ndarray:
    """The longitude on the J2000 ecliptic of the equinox ŝ × n̂ (the equator's ascending node on the orbit)."""
    g = np.cross(s, n)
    return np.arctan2(g[..., 1], g[..., 0])


def _precessionangle_between(sol, orbit, t0: float, t_end: float, lon0: float, at: np.ndarray) -> np.ndarray:
    """The equinox's retrograde turn since ``t0`` at the epochs ``at``, unwrapped on the integrator's own steps
    (DOP853 takes well under a twelfth of a precession period per step at these tolerances) and between them
    on a grid of a tenth of the step."""
    steps = sol.t
    fine = np.unique(np.concatenate([np.linspace(a, b, 11) for a, b in zip(steps[:-1], steps[1:])] + [at]))
    s = sol.sol(fine)[:3].T
    lon = _equinox_longitude(s / np.linalg.norm(s, axis=-1, keepdims=True), orbit.pole_at(fine))
    order = np.argsort(np.abs(fine - t0))
    lon_sorted = np.unwrap(np.concatenate([[lon0], lon[order]]))[1:]
    turned = np.empty(fine.size)
    turned[order] = -(lon_sorted - lon0)
    return np.interp(at, fine, turned)


def outward_max(years: np.ndarray, t0: float, d: np.ndarray) -> np.ndarray:
    """The running largest of ``d`` from the epoch ``t0`` outward, both ways (``years`` in any order)."""
    out = np.array(d, dtype=float)
    for side in (years >= t0, years < t0):
        idx = np.flatnonzero(side)
        if idx.size:
            order = idx[np.argsort(np.abs(years[idx] - t0), kind="stable")]
            out[order] = np.maximum.accumulate(out[order])
    return out


def history_arrays(years, s, n, precession, terms, obliquity_terms, probes, t0: float, spread,
                   evaluations: int) -> SpinHistory:
    """A :class:`SpinHistory` from the spin axes ``s`` and orbit normals ``n`` (N, 3) at ``years``; ``spread``:
    the neighbouring solutions' divergence in obliquity, which sets where the history stops meaning anything."""
    ra, dec = lon_lat(s @ icrf_to_ecliptic_matrix())
    inclination = np.arctan2(np.hypot(n[:, 0], n[:, 1]), n[:, 2])
    return SpinHistory(years, s, n, angle_between(s, n), precession, ra, dec, inclination, terms, obliquity_terms, probes,
                       _meaningful(years, t0, spread), evaluations)


def _meaningful(years: np.ndarray, t0: float, spread: np.ndarray) -> tuple[float, float]:
    """The span about the epoch over which the neighbours stay within :data:`MEANINGFUL_LIMIT`."""
    past, future = -math.inf, math.inf
    bad = spread > MEANINGFUL_LIMIT
    before, after = bad & (years < t0), bad & (years >= t0)
    if before.any():
        past = float(years[before].max())
    if after.any():
        future = float(years[after].min())
    return past, future


def spin_constants(body: Body, pole_epoch_jd: float, icrf_from_orbit: np.ndarray, obliquity: float,
                   orbit_constant: float, fixed_constant: float, nutation: float, source: str,
                   constant_drift: float = 0.0) -> SpinConstants:
    """A body's :class:`SpinConstants` from its theory's mean pole (the orbit frame ``icrf_from_orbit``, whose
    third column is the orbit normal, and the mean ``obliquity`` on it, at the pole epoch) and precession
    constants (rad/day: ψ̇ = (``orbit_constant`` + ``fixed_constant``) cos ε). The pole's σ is the catalogue's
    (RA and Dec, combined on the sky), or None."""
    pole_orbit = np.array([0.0, math.sin(obliquity), math.cos(obliquity)])
    mean_pole = icrf_to_ecliptic_matrix() @ (icrf_from_orbit @ pole_orbit)
    o = body.orbit
    sig = input_sigmas(body)
    ra_s, dec_s = sig.get("pole.ra"), sig.get("pole.dec")
    pole_sigma = None if ra_s is None or dec_s is None else \
        math.radians(math.hypot(ra_s * math.cos(math.radians(body.pole.dec_deg)), dec_s))
    # α ∝ n² H_d / ω: its relative σ from H_d's and the period's (the semi-major axes' relative errors, below
    # 1e-8 for every catalogue orbit, are left out); None where H_d has no σ
    hd_s, period_s = dynamical_ellipticity_sigma(body), sig.get("rotation.period")
    constant_sigma = None if hd_s is None else \
        math.hypot(hd_s / body.hd, (period_s or 0.0) / body.rotation_period_hours)
    return SpinConstants(body.name, (pole_epoch_jd - J2000_JD) / JULIAN_YEAR_DAYS, mean_pole,
                         orbit_constant * JULIAN_YEAR_DAYS, fixed_constant * JULIAN_YEAR_DAYS,
                         geodesic_precession_rate(o.a_au, o.e, o.center) * JULIAN_YEAR_DAYS, o.a_au, o.e,
                         nutation, constant_sigma, pole_sigma, source, constant_drift)
