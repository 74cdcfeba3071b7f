"""Fitting a NAIF text PCK to the spin-axis track: W0's tables, SPICE's evaluation, the angles chosen.

:mod:`ephem.answers.kernels` describes the kernel and the fit. Here:
the IAU orientation tables that place W0, the kernel's evaluation as SPICE does it, and the greedy
orthogonal least-squares choice of the angles."""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace

import numpy as np

from ..bodies.catalogue import Body
from ..base.constants import ARCSEC, J2000_JD, MAS
from ..base.constants import JULIAN_CENTURY_DAYS as CENTURY_DAYS
from ..base.errors import InvalidInputError
from ..orbit.geometry import angle_between
from ..theory.interface import Spectrum
from .pck_kernel import (FRAME_FROM_J2000, BodyFit, jd_text, kernel_radec, radec_of_units, rotation_x, rounding_bound,
                         theta_rad, unit_vectors)

#: Terms are added until the fit error is below this (mas) ...
FIT_AIM_MAS = 0.1
#: ... and, when the angle budget runs out first, the kernel is written if its error is below this (mas);
#: both are lowered to a tenth of the model's estimated error where that is smaller.
FIT_LIMIT_MAS = 1.0
#: ... or, for a model whose own estimated error is large (the Moon's: arcseconds to arcminutes), this fraction
#: of it where that is larger: the kernel then adds at most 5 % to the error the model already has (the Moon's
#: librations over ten years: 156 mas with 100 angles against an estimate of 7.3″)
FIT_LIMIT_FRACTION = 0.05
#: Default cap on the nutation-precession angles per body (TISBOD's MAXANG before N0067).
DEFAULT_MAX_ANGLES = 100
#: Hard cap (TISBOD N0067 buffers 200 angles per body).
SPICE_MAX_ANGLES = 200
#: Fit epochs per period of the fastest candidate term, and bounds on the fit grid.
SAMPLES_PER_PERIOD = 8
MIN_FIT_SAMPLES = 1500
MAX_FIT_SAMPLES = 40_000
#: The check grid is this many times denser than the fit grid, offset from it by half its step.
CHECK_DENSITY = 4
#: The largest error on the two grids is raised by this factor to bound the maxima between their epochs:
#: with >= 32 epochs per period of the fastest term, a sinusoid's peak exceeds its sampled maximum by at
#: most 1/cos(π/32) - 1 = 0.5%.
CHECK_MARGIN = 1.02
#: A candidate column whose part outside the basis is below this fraction of its norm is neither scored nor
#: added: a nearly dependent column is fitted with large coefficients that cancel, which costs the kernel
#: digits (see rounding_bound), and its updated inner products have lost their precision.
SCORED = DEPENDENT = 1e-6
#: The greedy choice (_pick): candidates whose downdated score is within this factor of the best, where those
#: are reliable (error < 1e-4), and all others, are scored exactly (the exact scores' error is below 1e-10) ...
SHORTLIST = 0.5
#: ... scoring, in the shortlist, columns down to SCORED / SHORTLIST_SLACK of their norm (whose downdated norm
#: is the least accurate), the exact score then applying SCORED ...
SHORTLIST_SLACK = 10.0
#: ... and candidates within rounding of the best exact score are a tie: the data (the track) are taken to
#: carry NOISE_ULPS ulps of rounding (different SIMD kernels move it by 1), the exact scores RELATIVE_TIE.
NOISE_ULPS = 16
RELATIVE_TIE = 1e-8
#: ... the columns scored exactly are kept (orthogonalised, updated per basis vector) up to this many bytes
KEPT_COLUMNS_BYTES = 64 << 20
#: A track that comes nearer than this to the J2000 pole (degrees of declination) is fitted in ECLIPJ2000.
MAX_J2000_DEC_DEG = 80.0
# The IAU WGCCRE orientation models, used only to place our W0 (module docstring). Asteroids and Mars:
# Archinal et al. (2018), the WGCCRE 2015 report, as in NAIF's pck00011.tpc, read in NAIF's test utility
# T_PCKANG (which checks that kernel's models) and cross-checked for Ceres, Vesta and Eros against
# independent transcriptions; the asteroids' W1 give the catalogue's rotation periods, and the Mars
# series at J2000 gives the catalogue's J2000 pole (317.68085, 52.88644). Earth: the WGCCRE 2009 model
# (Archinal et al. 2011; the 2015 report gives none), as in NAIF's pck00010.tpc.
_WGCCRE_2015 = "IAU WGCCRE 2015 (Archinal et al. 2018, Celest. Mech. Dyn. Astr. 130:22), as in NAIF pck00011.tpc"
_WGCCRE_2009 = "IAU WGCCRE 2009 (Archinal et al. 2011, Celest. Mech. Dyn. Astr. 109:101), as in NAIF pck00010.tpc"
#: Constant poles: NAIF id -> (RA deg, DEC deg, W0 deg, W1 deg/day).
_IAU_CONSTANT_POLE = {
    2000001: (291.418, 66.764, 170.65, 952.1532),            # Ceres
    2000004: (309.031, 42.235, 285.39, 1617.3329428),        # Vesta
    2000433: (11.35, 17.22, 326.07, 1639.38864745),          # Eros
    2002867: (91.0, -62.0, 321.76, 1428.09917),              # Steins
    2025143: (90.53, -66.30, 0.0, 712.143),                  # Itokawa
}
#: Mars (WGCCRE 2015): constant, rate (per century or per day), then (amplitude, phase0, phase rate per century).
_MARS_RA = (317.269202, -0.10927547, ((0.000068, 198.991226, 19139.4819985), (0.000238, 226.292679, 38280.8511281),
                                      (0.000052, 249.663391, 57420.7251593), (0.000009, 266.183510, 76560.6367950),
                                      (0.419057, 79.398797, 0.5042615)))
_MARS_DEC = (54.432516, -0.05827105, ((0.000051, 122.433576, 19139.9407476), (0.000141, 43.058401, 38280.8753272),
                                      (0.000031, 57.663379, 57420.7517205), (0.000005, 79.476401, 76560.6495004),
                                      (1.591274, 166.325722, 0.5042615)))
_MARS_W = (176.049863, 350.891982443297, ((0.000145, 129.071773, 19140.0328244), (0.000157, 36.352167, 38281.0473591),
                                          (0.000040, 56.668646, 57420.9295360), (0.000001, 67.364003, 76560.2552215),
                                          (0.000001, 104.792680, 95700.4387578), (0.584542, 95.391654, 0.5042615)))


def iau_orientation(naif_id: int, jd_tdb: float) -> tuple[float, float, float, str] | None:
    """The IAU WGCCRE model's pole RA, DEC and prime meridian W (degrees, J2000 frame) at ``jd_tdb``, and its
    source; None for a body without one here."""
    d = jd_tdb - J2000_JD
    T = d / CENTURY_DAYS
    if naif_id in _IAU_CONSTANT_POLE:
        ra, dec, w0, w1 = _IAU_CONSTANT_POLE[naif_id]
        return ra, dec, w0 + w1 * d, _WGCCRE_2015
    if naif_id == 499:
        def series(c, rate_t, periodic, trig):
            return c + rate_t + sum(a * trig(math.radians(p0 + p1 * T)) for a, p0, p1 in periodic)
        return (series(_MARS_RA[0], _MARS_RA[1] * T, _MARS_RA[2], math.sin),
                series(_MARS_DEC[0], _MARS_DEC[1] * T, _MARS_DEC[2], math.cos),
                series(_MARS_W[0], _MARS_W[1] * d, _MARS_W[2], math.sin), _WGCCRE_2015)
    if naif_id == 399:
        return -0.641 * T, 90.0 - 0.557 * T, 190.147 + 360.9856235 * d, _WGCCRE_2009
    return None


def _rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


# --------------------------------------------------------------------------- fitting

class _Ols:
    """Orthogonal least squares for one coordinate (Chen, Billings & Luo 1989, Int. J. Control 50:1873): an
    orthonormal basis (modified Gram-Schmidt, orthogonalised twice) of weighted columns, the residual of
    the weighted data, and for every candidate column c the inner products of its part c' orthogonal to
    the basis, from which a candidate's score, the exact drop in the residual's energy it would bring,
    follows. They are updated as each basis vector q joins (q is orthogonal to the earlier ones, so
    q·c' = q·c): |c'|² -= (q·c)², s'·c' -= (q·s)(q·c), r·c' -= (q·r)(q·c). A candidate whose part outside
    the basis is below SCORED of its norm is not scored (its products have lost their precision), and a
    column whose part is below DEPENDENT is not added (its coefficient is zero)."""

    def __init__(self, weight: np.ndarray, data: np.ndarray, candidates: np.ndarray):
        self.w = weight
        self.data = weight * data
        self.residual = self.data.copy()
        self.cand = weight[:, None] * candidates               # weighted candidate columns (never changed)
        s, c = self.cand[:, 0::2], self.cand[:, 1::2]
        self.ss0 = np.einsum("ij,ij->j", s, s)
        self.cc0 = np.einsum("ij,ij->j", c, c)
        self.ss, self.cc, self.sc = self.ss0.copy(), self.cc0.copy(), np.einsum("ij,ij->j", s, c)
        self.bs, self.bc = self.residual @ s, self.residual @ c
        self.Q = np.empty((16, data.size))                      # rows: the orthonormal basis (grown by doubling)
        self.m = 0
        self.r: list[np.ndarray] = []                           # column j of R, length j + 1
        self.keys: list = []                                    # what each basis column is
        # candidates already scored exactly keep their columns orthogonalised against the first kept_m[slot]
        # basis vectors; rescoring one projects out only the vectors added since (the near-dependent ones are
        # rescored at every step: O(N) each instead of O(m N))
        self.kept_index: dict[int, int] = {}                    # candidate -> its slot (a pair of columns)
        self.kept_rows = np.empty((0, data.size))
        self.kept_m = np.empty(0, dtype=int)

    def add(self, column: np.ndarray, key) -> bool:
        v = self.w * column
        norm0 = float(np.linalg.norm(v))
        coeffs = np.zeros(self.m + 1)
        if self.m:
            Q = self.Q[: self.m]
            for _ in range(2):
                c = Q @ v
                coeffs[:-1] += c
                v = v - c @ Q
        norm = float(np.linalg.norm(v))
        if norm0 == 0.0 or norm <= DEPENDENT * norm0:          # numerically dependent on the basis
            return False
        q = v / norm
        coeffs[-1] = norm
        if self.m == self.Q.shape[0]:
            self.Q = np.concatenate([self.Q, np.empty_like(self.Q)])
        self.Q[self.m] = q
        self.m += 1
        self.r.append(coeffs)
        self.keys.append(key)
        qr = float(q @ self.residual)
        self.residual -= q * qr
        if self.cand.shape[1]:
            y = q @ self.cand
            ys, yc = y[0::2], y[1::2]
            self.ss -= ys * ys
            self.cc -= yc * yc
            self.sc -= ys * yc
            self.bs -= qr * ys
            self.bc -= qr * yc
        return True

    def scores(self) -> np.ndarray:
        """The residual's energy drop for each candidate pair of columns (sin, cos), or for the one of them
        that is scored; -1 where neither is. From the downdated inner products: cheap, but |c'|² = |c|² - Σ(q·c)²
        cancels for a nearly dependent candidate (relative error ~ m ε |c|²/|c'|², up to 1e-2 at SCORED), so
        these only shortlist (:meth:`pick`)."""
        return _pair_scores(self.ss, self.cc, self.sc, self.bs, self.bc, self.ss0, self.cc0, SCORED / SHORTLIST_SLACK)

    def screen_reliable(self) -> np.ndarray:
        """Where the downdated scores are within 1e-4 of the exact ones: both columns' parts outside the basis
        above RELIABLE of their norms (the error of |c'|² is ~ m ε |c|², at most 64 m ε |c|²)."""
        bound = 64.0 * max(self.m, 1) * np.finfo(float).eps
        return (self.ss >= self.ss0 * bound * 1e4) & (self.cc >= self.cc0 * bound * 1e4)

    def exact_scores(self, idx: np.ndarray) -> np.ndarray:
        """:meth:`scores` of candidates ``idx`` from their columns orthogonalised explicitly (twice) against the
        basis: relative error ~ ε |c|/|c'| <= 1e-10, against up to 1e-2 for the downdated ones. Columns are
        held as rows here (contiguous: gathered and projected without strides)."""
        Q = self.Q[: self.m]
        rows = np.empty((2 * len(idx), self.data.size))
        new = [j for j, i in enumerate(idx) if int(i) not in self.kept_index]
        if new:
            fresh = self.cand[:, np.repeat(2 * idx[new], 2) + np.tile([0, 1], len(new))].T.copy()
            for _ in range(2 if self.m else 0):
                fresh -= (fresh @ Q.T) @ Q
            rows[[2 * j + p for j in new for p in (0, 1)]] = fresh
            self._keep(idx[new], fresh)
        fresh_at = set(new)
        old = [(j, self.kept_index[int(i)]) for j, i in enumerate(idx) if j not in fresh_at]
        for m0 in sorted({int(self.kept_m[slot]) for _, slot in old}):
            group = [(j, slot) for j, slot in old if self.kept_m[slot] == m0]
            src = np.array([2 * slot + p for _, slot in group for p in (0, 1)])
            block = self.kept_rows[src]
            if m0 < self.m:                 # orthogonal to the first m0 already: the vectors added since, once
                Qn = Q[m0:]
                block -= (block @ Qn.T) @ Qn
                self.kept_rows[src] = block
                self.kept_m[[slot for _, slot in group]] = self.m
            rows[[2 * j + p for j, _ in group for p in (0, 1)]] = block
        s, c = rows[0::2], rows[1::2]
        ss, cc = np.einsum("ij,ij->i", s, s), np.einsum("ij,ij->i", c, c)
        return _pair_scores(ss, cc, np.einsum("ij,ij->i", s, c), s @ self.residual, c @ self.residual,
                            self.ss0[idx], self.cc0[idx], SCORED)

    def _keep(self, idx: np.ndarray, rows: np.ndarray) -> None:
        """Keep candidates ``idx``'s columns (``rows``, orthogonal to the whole basis), within KEPT_COLUMNS_BYTES."""
        used = len(self.kept_index)
        take = min(KEPT_COLUMNS_BYTES // (16 * self.data.size) - used, idx.size)
        if take <= 0:
            return
        if 2 * (used + take) > self.kept_rows.shape[0]:          # grow by doubling: no copy per step
            grown = np.empty((max(2 * (used + take), 2 * self.kept_rows.shape[0]), self.data.size))
            grown[:2 * used] = self.kept_rows[:2 * used]
            self.kept_rows = grown
            self.kept_m = np.concatenate([self.kept_m, np.empty(grown.shape[0] // 2 - self.kept_m.size, int)])
        self.kept_rows[2 * used:2 * (used + take)] = rows[:2 * take]
        self.kept_m[used:used + take] = self.m
        self.kept_index.update({int(i): used + j for j, i in enumerate(idx[:take])})

    def tie_width(self, best: float) -> float:
        """How far apart (in score units) two candidates' exact scores can be moved by rounding, near a best
        score ``best``: the data carry the track's rounding, δ = NOISE_ULPS ulps of their largest value at
        each epoch, which moves a projection of the residual by at most |δ|₂ = δ √N, so a score s = |P r|²
        by 2 √s δ √N; and the exact scores' own relative error (RELATIVE_TIE)."""
        delta = NOISE_ULPS * np.finfo(float).eps * float(np.max(np.abs(self.data))) * math.sqrt(self.data.size)
        return 2.0 * math.sqrt(max(best, 0.0)) * delta + delta * delta + RELATIVE_TIE * best

    def coefficients(self) -> dict:
        """Least-squares coefficient of each column added, by key (back substitution in R)."""
        m = self.m
        R = np.zeros((m, m))
        for j, col in enumerate(self.r):
            R[: j + 1, j] = col
        return dict(zip(self.keys, np.linalg.solve(R, self.Q[:m] @ self.data)))


def _pair_scores(ss, cc, sc, bs, bc, ss0, cc0, scored: float) -> np.ndarray:
    """The drop in the residual's energy from fitting a pair of columns (s, c) orthogonalised against the basis,
    from their inner products (ss = s·s, cc, sc; bs = r·s, bc); a column below ``scored`` of its norm
    (ss0, cc0) is not scored, and where neither is, -1."""
    s_ok = ss > scored ** 2 * ss0
    c_ok = cc > scored ** 2 * cc0
    det = ss * cc - sc * sc
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.maximum(np.where(s_ok, bs * bs / np.where(s_ok, ss, 1.0), -1.0),
                         np.where(c_ok, bc * bc / np.where(c_ok, cc, 1.0), -1.0))
        both = s_ok & c_ok & (det > 1e-6 * ss * cc)
        out[both] = (cc[both] * bs[both] ** 2 - 2.0 * sc[both] * bs[both] * bc[both]
                     + ss[both] * bc[both] ** 2) / det[both]
    return out


def _pick(ra: _Ols, dec: _Ols, available: np.ndarray, order_key) -> int | None:
    """The next candidate of the greedy fit, or None when none lowers the residual: the one with the largest
    drop in the residual's energy, RA and DEC together, made independent of the last bits of the data.

    The downdated scores shortlist the candidates within a factor SHORTLIST of the best where they are
    reliable (their error is far below that), and every candidate where they are not; the shortlist is scored
    exactly; candidates whose exact scores lie within what rounding can
    move them of the best are a tie (sidebands j Ψ of one base differ by ψ̇ j, which a span of years barely
    resolves: their scores agree to 1e-7), which ``order_key`` breaks: the choice then no longer flips with
    the CPU's SIMD kernels (a 1-ulp change of the track moved 2 of Vesta's angles before)."""
    s_ra, s_dec = ra.scores(), dec.scores()
    screen = np.where((s_ra < 0.0) & (s_dec < 0.0), -1.0, np.maximum(s_ra, 0.0) + np.maximum(s_dec, 0.0))
    screen[~available] = -1.0
    reliable = (ra.screen_reliable() & dec.screen_reliable()) | (screen <= 0.0)
    best = float(screen[reliable].max(initial=-1.0))
    short = np.flatnonzero(((screen >= SHORTLIST * best) & (best > 0.0)) | (~reliable & available))
    if short.size == 0:
        return None
    x_ra, x_dec = ra.exact_scores(short), dec.exact_scores(short)
    exact = np.where((x_ra < 0.0) & (x_dec < 0.0), -1.0, np.maximum(x_ra, 0.0) + np.maximum(x_dec, 0.0))
    top = float(exact.max())
    if top <= 0.0:
        return None
    ties = short[exact >= top - (ra.tie_width(top) + dec.tie_width(top))]
    return int(min(ties, key=order_key))


def _candidates(spec: Spectrum, span: float, fit_step: float) -> list[tuple[int, int]]:
    """(base, j) of the frequencies worth trying: positive, resolved by the fit grid (at least
    SAMPLES_PER_PERIOD / 2 epochs per period), and, for the precession alone, not a mere polynomial."""
    fastest = 2.0 * math.pi / (0.5 * SAMPLES_PER_PERIOD * fit_step)
    out = []
    for i in range(len(spec.labels)):
        for j in range(-spec.max_sideband, spec.max_sideband + 1):
            f = spec.frequency(i, j)
            if f <= 0.0 or f > fastest or (spec.theta1[i] == 0.0 and f * span < 1e-3):
                continue
            out.append((i, j))
    return out


def fit_body(b: Body, t0: float, t1: float, asked: Mapping[str, object], fit_tolerance_mas: float | None,
             max_angles: int, *, track, theory_for) -> BodyFit:
    """The kernel's fit of ``b``'s pole over [t0, t1] (JD TDB); ``b`` carries its dataset. ``asked``: the track's
    model as the track answer's keywords take it (``tolerance_mas``, ``model``, ``order``, ``axis``, ``perturbers``:
    :func:`ephem.answers.requests.track`'s), one value from the kernel's request to the track. ``track``: the track
    answer's arrays for a grid (:func:`ephem.answers.requests.track_arrays`'s arguments and result), ``theory_for``:
    the family serving a body (:func:`ephem.families.theory_for`), for its spectrum; both given by the caller
    (:mod:`ephem.answers.kernels`), as this module renders what the answers computed and asks them nothing itself."""
    span = t1 - t0
    # the model: chosen once (by tolerance, name or default) for the span's two ends, then named for both
    # grids, so that a tolerance cannot pick another one for other epochs
    probe = track(b, t0, t1, span, **asked)
    info = probe["model"]
    estimate = info.get("estimated_error_mas")
    if fit_tolerance_mas is not None:
        aim = limit = float(fit_tolerance_mas)
    else:
        tenth = math.inf if estimate is None else 0.1 * estimate
        aim, limit = min(FIT_AIM_MAS, tenth), min(FIT_LIMIT_MAS, tenth)
        if estimate is not None:
            limit = max(limit, FIT_LIMIT_FRACTION * estimate)

    T0, T1 = (t0 - J2000_JD) / CENTURY_DAYS, (t1 - J2000_JD) / CENTURY_DAYS
    Tm, Th = 0.5 * (T0 + T1), 0.5 * (T1 - T0)
    theory = theory_for(b, tuple(info["perturbers"]), asked["axis"])
    spec = theory.spectrum(aim, Tm)            # refined below from the track (the rates the higher rungs change)
    fastest = max(spec.frequency(i, spec.max_sideband) for i in range(len(spec.labels)))
    count = int(min(MAX_FIT_SAMPLES, max(MIN_FIT_SAMPLES,
                                         math.ceil(SAMPLES_PER_PERIOD * fastest * span / (2.0 * math.pi)) + 1)))
    step = span / (count - 1)
    named = {**asked, "tolerance_mas": None, "order": info["order"], "model": info["name"]}
    ans = track(b, t0, t1, step, max_samples=count + 1, **named)
    t = ans["jd_tdb"]
    check_count = CHECK_DENSITY * (t.size - 1)
    check_step = span / check_count
    chk = track(b, t0 + 0.5 * check_step, t1, check_step, max_samples=check_count + 1, **named)
    t_chk = chk["jd_tdb"]
    spec = theory.spectrum(aim, Tm, t, ans["psi_arcsec"] * ARCSEC)

    # the frame: J2000 unless the pole comes near its pole
    frame = "J2000" if float(np.max(np.abs(ans["pole_dec_deg"]))) <= MAX_J2000_DEC_DEG else "ECLIPJ2000"
    rot = FRAME_FROM_J2000[frame]
    u_fit = unit_vectors(ans["pole_ra_deg"], ans["pole_dec_deg"]) @ rot.T
    u_chk = unit_vectors(chk["pole_ra_deg"], chk["pole_dec_deg"]) @ rot.T
    ra_deg, dec_deg = radec_of_units(u_fit)
    ra_deg -= 360.0 * math.floor(ra_deg[ra_deg.size // 2] / 360.0)      # RA in [0°, 360°) mid-span

    T = (t - J2000_JD) / CENTURY_DAYS
    u = (T - Tm) / Th
    cands = _candidates(spec, span, step)
    cand_cols = np.empty((t.size, 2 * len(cands)))
    if cands:
        theta = theta_rad(np.array([spec.angle(i, j) for i, j in cands]), T)
        cand_cols[:, 0::2], cand_cols[:, 1::2] = np.sin(theta), np.cos(theta)
    ra = _Ols(np.cos(np.radians(dec_deg)), ra_deg, cand_cols)        # RA weighted by cos DEC: an angle
    dec = _Ols(np.ones_like(t), dec_deg, cand_cols)
    for key, c in (("p0", np.ones_like(u)), ("p1", u), ("p2", u * u)):
        if not (ra.add(c, key) and dec.add(c, key)):
            raise RuntimeError("polynomial columns dependent")  # pragma: no cover - >= 1500 distinct epochs

    def assemble(chosen) -> BodyFit:
        return _assemble(b, info, frame, chosen, spec, ra.coefficients(), dec.coefficients(), Tm, Th,
                         aim, limit)

    def measure(fit: BodyFit) -> tuple[float, float, int]:
        e1 = angle_between(unit_vectors(*kernel_radec(fit, t)), u_fit)
        e2 = angle_between(unit_vectors(*kernel_radec(fit, t_chk)), u_chk)
        worst = (max(float(e1.max()), float(e2.max())) * CHECK_MARGIN + rounding_bound(fit, t_chk)) / MAS
        return worst, math.sqrt(float(np.mean(np.concatenate([e1, e2]) ** 2))) / MAS, e1.size + e2.size

    chosen: list[tuple[int, int]] = []
    available = np.ones(len(cands), dtype=bool)
    result = None
    while True:
        # the weighted residuals are the angles on the sky to first order: a cheap test on the fit grid first
        approx = float(np.max(np.hypot(ra.residual, dec.residual))) * 3.6e6 * CHECK_MARGIN       # deg -> mas
        if approx <= aim:
            fit = assemble(chosen)
            worst, rms, epochs = measure(fit)
            if worst <= aim:
                result = (fit, worst, rms, epochs)
                break
        if 2 * (len(chosen) + 1) > max_angles or not available.any():
            break
        i = _pick(ra, dec, available, lambda n: (abs(cands[n][1]), cands[n][1], cands[n][0]))
        if i is None:
            break
        available[i] = False
        took = [basis.add(cand_cols[:, 2 * i + p], (cands[i], p)) for basis in (ra, dec) for p in (0, 1)]
        if any(took):
            chosen.append(cands[i])
    if result is None:          # the aim was not reached: all the terms the budget allows
        fit = assemble(chosen)
        worst, rms, epochs = measure(fit)
        if not worst <= limit:
            raise InvalidInputError(
                "stop", f"the span {jd_text(t0)} to {jd_text(t1)} cannot be fitted within {limit:.4g} mas "
                f"with at most {max_angles} nutation-precession angles (best {worst:.4g} mas with "
                f"{2 * len(chosen)} angles); shorten the span (or write several kernels), raise max_angles "
                f"(up to {SPICE_MAX_ANGLES}, SPICE N0067) or fit_tolerance_mas", b.name)
        result = (fit, worst, rms, epochs)
    fit, worst, rms, epochs = result
    return replace(fit, fit_error_mas=worst, fit_rms_mas=rms, check_epochs=epochs,
                   **dict(zip(("pm", "pm_source"), _prime_meridian(b, fit, 0.5 * (t0 + t1)))))


def _assemble(b: Body, info: dict, frame: str, chosen, spec: Spectrum, ra_coef, dec_coef, Tm: float,
              Th: float, aim: float, limit: float) -> BodyFit:
    """Kernel coefficients from the fitted ones: the polynomial in u = (T - Tm)/Th re-expanded in T, and each
    frequency's (sin, cos) pair as the coefficients of the angles θ and θ + 90°."""
    def poly(c) -> tuple[float, float, float]:
        a0, a1, a2 = (float(c[key]) for key in ("p0", "p1", "p2"))
        return (a0 - a1 * Tm / Th + a2 * Tm * Tm / (Th * Th), a1 / Th - 2.0 * a2 * Tm / (Th * Th), a2 / (Th * Th))

    angles, ra_terms, dec_terms = [], [], []
    for kj in chosen:
        theta0, theta1 = spec.angle(*kj)
        angles += [(theta0, theta1), ((theta0 + 90.0) % 360.0, theta1)]
        ra_s, ra_c = (float(ra_coef.get((kj, p), 0.0)) for p in (0, 1))
        dec_s, dec_c = (float(dec_coef.get((kj, p), 0.0)) for p in (0, 1))
        ra_terms += [ra_s, ra_c]            # sin θ, sin(θ + 90°) = cos θ
        dec_terms += [dec_c, -dec_s]        # cos θ, cos(θ + 90°) = -sin θ
    return BodyFit(
        name=b.name, naif_id=int(b.naif_id), dataset=b.dataset, model=dict(info), frame=frame,
        fit_error_mas=math.nan, fit_rms_mas=math.nan, fit_aim_mas=aim, fit_limit_mas=limit, check_epochs=0,
        pole_ra=poly(ra_coef), pole_dec=poly(dec_coef), pm=(0.0, 0.0, 0.0), pm_source="",
        angles=tuple(angles), nut_prec_ra=tuple(ra_terms), nut_prec_dec=tuple(dec_terms),
        terms=tuple((spec.labels[i], j) for i, j in chosen), term_label=spec.describe,
        precession_rate_deg_per_day=spec.psi_theta1 / CENTURY_DAYS)


def _frame_axes(ra_deg: float, dec_deg: float, w_deg: float) -> np.ndarray:
    """Rows: the body-fixed axes, in the reference frame, of the PCK Euler angles: [W]3 [90° - DEC]1 [90° + RA]3
    (pck.req, "Orientation Models used by PCK Software")."""
    a, d, w = (math.radians(x) for x in (ra_deg, dec_deg, w_deg))
    return _rz(w) @ rotation_x(math.pi / 2 - d) @ _rz(math.pi / 2 + a)


def _prime_meridian(b: Body, fit: BodyFit, jd_anchor: float) -> tuple[tuple[float, float, float], str]:
    """((W0 deg, W1 deg/day, 0), statement): W1 from the catalogue period; W0 such that at ``jd_anchor`` (the
    span's middle) the prime meridian lies where the IAU model puts it (its x axis projected on our equator)."""
    w1 = 360.0 / (b.rotation_period_hours / 24.0)
    iau = iau_orientation(int(b.naif_id), jd_anchor)
    if iau is None:
        return (0.0, w1, 0.0), ("W0 = 0: no IAU prime meridian is known here for this body, so the origin of "
                                "longitude is arbitrary (the pole does not depend on W); W1 = 360 deg / the "
                                "catalogue's rotation period")
    ra_i, dec_i, w_i, source = iau
    x_iau = _frame_axes(ra_i, dec_i, w_i)[0] @ FRAME_FROM_J2000[fit.frame].T     # the IAU x axis, kernel frame
    ra_k, dec_k = (float(x[0]) for x in fit.pole_radec(jd_anchor))
    axes = _frame_axes(ra_k, dec_k, 0.0)                    # W = 0: x along the kernel's node
    w_anchor = math.degrees(math.atan2(float(x_iau @ axes[1]), float(x_iau @ axes[0])))
    w0 = (w_anchor - w1 * (jd_anchor - J2000_JD)) % 360.0
    j2000 = iau_orientation(int(b.naif_id), J2000_JD)
    return (w0, w1, 0.0), (
        f"W0 = {w0:.6f} deg puts the prime meridian where the IAU model does ({source}; its W at J2000 "
        f"{j2000[2] % 360.0:.6f} deg about its pole RA {j2000[0]:.6f}, DEC {j2000[1]:.6f} deg) at the span's "
        f"middle, {jd_text(jd_anchor)}; W1 = 360 deg / the catalogue's rotation period")
