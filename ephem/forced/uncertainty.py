"""Propagation of the catalogue's 1-sigma uncertainties to the precession and nutation.

Outputs: the obliquity, the precession rate ψ̇, H_d, the scaling factor K, the half
peak-to-peak nutation Δψ, Δε (Petit et al. Table 4) and, per harmonic kM of the
nutation, the Sin/Cos coefficients in longitude and obliquity, their amplitudes as
the paper prints them (longitude: sqrt(Sin² + Cos²)·sin ε; obliquity: sqrt(Sin² + Cos²))
and the period.

Inputs: the values the model reads from the catalogue, in the catalogue's own units
(``orbit.a``, ``orbit.e``, ``orbit.i``, ``orbit.node``, ``orbit.peri``,
``orbit.mean_anomaly``, ``pole.ra``/``pole.dec`` (or ``pole.lon``/``pole.lat``),
``rotation.period``, and ``inertia.A``/``B``/``C`` or ``inertia.dynamical_ellipticity``,
whichever sets H_d). Epochs are definitions, not measurements, and the mean radius
does not enter these outputs.

:func:`propagate` is linear: σ_out² = Σ_ij J_i ρ_ij J_j σ_i σ_j with the Jacobian J from
central finite differences, step h_i = σ_i / 100 (see :data:`STEP_FRACTION`), and the
inputs correlated as the catalogue says (:attr:`ephem.bodies.catalogue.Body.correlations`: stated by a source,
or implied by deriving several values from one measurement) and as ``correlations`` adds. :func:`monte_carlo` samples the inputs (normal) and recomputes,
as a check of the linear answer where the model is not linear over ±1σ (large pole
uncertainties, small obliquities).

Both evaluate a private replica of :func:`ephem.forced.precession_nutation.build_model` that keeps the Hansen
coefficients of the eccentricity and sums the nutation at the pole epoch directly
(0.14 ms a call, 15-30 times faster than rebuilding the model; the tests check that it
returns the model's numbers, nominal and perturbed).
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..bodies.catalogue import Body, dynamical_ellipticity, resolve_body, spin_rate_rad_per_day
from ..base.constants import ARCSEC, JULIAN_YEAR_DAYS
from ..base.errors import InvalidInputError
from ..orbit.geometry import icrf_to_ecliptic_matrix, spin_geometry, unit_vector
from ..orbit.hansen import hansen_exact, hansen_series
from ..orbit.harmonics import series_extrema
from ..orbit.kepler import mean_motion_rad_per_day
from .kinoshita import mean_pole, nutation_coefficients, precession_rate, scaling_factor
from ..base.memo import bytes_bounded
from .catalogue_sigmas import CatalogueInput, catalogue_inputs, correlation_matrix, input_sigmas, no_uncertainty_reasons
from .precession_nutation import cached_model, model_for

#: Central-difference step as a fraction of the input's σ. The linear σ is J·σ with J the
#: derivative at the nominal point. Truncation error of the central difference, relative:
#: (h²/6)·f'''/f' = 1e-4 × (the curvature over ±1σ); rounding error, relative:
#: ~1e-16·|f| / (h·|f'|) = 1e-14 / (the input's relative contribution σ_i f'/f), so only
#: contributions below 1e-10 of the output (immaterial) lose digits. Checked in the tests
#: against a step twice as large (Richardson: they agree to 1e-6).
STEP_FRACTION = 0.01
#: Steps for inputs without an uncertainty (used only for the reported sensitivities), in the
#: model's units: angles 1e-6 deg, a 1e-7 relative, e 1e-7, period and moments 1e-7 relative.
_DEFAULT_STEP = {"angle": 1e-6, "a": 1e-7, "e": 1e-7, "relative": 1e-7}

_PER_YEAR = JULIAN_YEAR_DAYS / ARCSEC   # rad/day -> arcsec/yr

#: Scalar outputs (public keys of ephem.answers.requests.precession / ephem.answers.requests.nutation).
SCALAR_KEYS = ("obliquity_deg", "precession_rate_arcsec_per_year", "dynamical_ellipticity",
               "scaling_factor_arcsec_per_year", "delta_psi_half_peak_to_peak_arcsec",
               "delta_epsilon_half_peak_to_peak_arcsec")
#: Per-term outputs (public keys of ephem.answers.requests.nutation's terms, plus the paper's amplitudes).
TERM_KEYS = ("period_days", "longitude_sin_arcsec", "longitude_cos_arcsec", "obliquity_sin_arcsec",
             "obliquity_cos_arcsec", "amplitude_longitude_arcsec", "amplitude_obliquity_arcsec")

ASSUMPTIONS = [
    "1-sigma uncertainties as the catalogue gives them (value's unit), normal errors",
    ("inputs independent except where the catalogue or the caller gives correlations: a source's stated ones "
     "(a pole's RA and Dec) and those a derivation implies (moments derived from one polar moment or one shape "
     "are correlated, data/catalogue/SCHEMA.md)"),
    "pole RA and Dec uncertainties are per coordinate (the RA one is an angle of RA, not of arc)",
    ("linear propagation: central finite differences, step sigma/100; the Monte Carlo check "
     "(monte_carlo) shows where the model is not linear over +-1 sigma"),
    ("the theory itself is taken as exact: its truncation and averaging errors are in the "
     "'model' part of the answers, not here"),
]


# --------------------------------------------------------------------------- the replica of build_model

class _Rejected(Exception):
    """A sampled input set that no body can have (e ≥ 1, C < B, …)."""


class _Replica:
    """The numbers of :func:`ephem.forced.precession_nutation.build_model` as a function of the model-unit inputs.

    Mirrors build_model and kinoshita.nutation_series step by step (the same formulas: the
    coefficients of kinoshita.nutation_coefficients, the mean pole of kinoshita.mean_pole), with
    the Hansen coefficients kept per e and the nutation at the pole epoch summed directly.
    ``kmax`` fixes the number of harmonics to that of the nominal model, so that perturbed
    outputs line up term by term.
    """

    def __init__(self, body: Body, keys: list[str], order: int | None, kmax: int):
        self.keys = keys
        self.center = body.orbit.center
        self.t0 = body.pole.epoch_jd_tdb
        self.orbit_epoch = body.orbit.epoch_jd_tdb
        self.ecliptic_pole = "pole.lon" in keys
        self.ecl_from_icrf = icrf_to_ecliptic_matrix()
        self.order = order
        self.kmax = kmax
        self.k = np.arange(1, kmax + 1, dtype=float)
        self.explicit_hd = "inertia.dynamical_ellipticity" in keys
        self._hansen: dict[float, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def hansen(self, e: float):
        h = self._hansen.get(e)
        if h is None:
            if self.order is None:
                co = hansen_exact(e)
                if co.kmax < self.kmax:
                    co = hansen_exact(e, self.kmax)
            else:
                co = hansen_series(self.order).evaluate(e)
            sl = slice(1, self.kmax + 1)
            h = (co.c0[sl], co.c2[sl], co.s2[sl])
            if len(self._hansen) > 64:
                self._hansen.clear()
            self._hansen[e] = h
        return h

    def state(self, x: np.ndarray) -> dict:
        """Model quantities for one input vector (model units, in the order of ``keys``)."""
        v = dict(zip(self.keys, x))
        a, e, period = v["orbit.a"], v["orbit.e"], v["rotation.period"]
        if a <= 0.0 or not 0.0 <= e < 1.0 or period <= 0.0:
            raise _Rejected("a, e or period out of range")
        if self.explicit_hd:
            hd = v["inertia.dynamical_ellipticity"]
            if not 0.0 < hd <= 0.5:
                raise _Rejected("H_d out of (0, 0.5]")
        else:
            A, B, C = v["inertia.A"], v["inertia.B"], v["inertia.C"]
            # A and B may swap (H_d is symmetric in them); C must stay the largest moment
            if min(A, B) <= 0.0 or C < max(A, B) or C > A + B:
                raise _Rejected("moments not those of a rigid body spinning about C")
            hd = dynamical_ellipticity(min(A, B), max(A, B), C)
        n = mean_motion_rad_per_day(a, self.center)
        K = scaling_factor(n, spin_rate_rad_per_day(period), hd)
        if self.ecliptic_pole:
            s_ecl = unit_vector(math.radians(v["pole.lon"]), math.radians(v["pole.lat"]))
        else:
            s_ecl = self.ecl_from_icrf @ unit_vector(math.radians(v["pole.ra"]), math.radians(v["pole.dec"]))
        i, node, peri = (math.radians(v[k]) for k in ("orbit.i", "orbit.node", "orbit.peri"))
        try:
            geo = spin_geometry(s_ecl, i, node, peri)
        except InvalidInputError:
            raise _Rejected("spin axis normal to the orbit") from None
        m_t0 = math.radians(v["orbit.mean_anomaly"]) + n * (self.t0 - self.orbit_epoch)
        skm, ckm = np.sin(self.k * m_t0), np.cos(self.k * m_t0)
        c0, c2, s2 = self.hansen(e)
        last = {}

        def nutation_at_pole_epoch(eps_trial: float, theta_trial: float) -> tuple[float, float]:
            # kinoshita.nutation_series without the amplitude cut, summed at the pole epoch only
            coef = last["coef"] = nutation_coefficients(K, n, eps_trial, theta_trial, self.k, c0, c2, s2)
            return coef[0] @ skm + coef[1] @ ckm, coef[2] @ skm + coef[3] @ ckm

        eps_mean = mean_pole(geo.obliquity, geo.equinox_to_pericentre, nutation_at_pole_epoch)[0]
        coef = last["coef"]
        return {"hd": hd, "n": n, "K": K, "obliquity": eps_mean,
                "precession_rate": precession_rate(K, eps_mean, e, self.order), "coefficients": coef}

    def outputs(self, x: np.ndarray, extrema: tuple | None) -> np.ndarray:
        """Output vector in public units: the scalars of SCALAR_KEYS, then TERM_KEYS per term.

        ``extrema`` (x_max, x_min of Δψ, then of Δε): the half peak-to-peak is taken at these
        mean anomalies (its derivative there is the derivative of the true one, the extrema
        being stationary); None locates them anew (Monte Carlo).
        """
        s = self.state(x)
        lon_s, lon_c, obl_s, obl_c = s["coefficients"]
        if extrema is None:
            half_psi, half_eps = series_extrema(lon_s, lon_c)[0], series_extrema(obl_s, obl_c)[0]
        else:
            xs = np.asarray(extrema)
            sk, ck = np.sin(np.outer(xs, self.k)), np.cos(np.outer(xs, self.k))
            vals_psi = sk[:2] @ lon_s + ck[:2] @ lon_c
            vals_eps = sk[2:] @ obl_s + ck[2:] @ obl_c
            half_psi, half_eps = 0.5 * (vals_psi[0] - vals_psi[1]), 0.5 * (vals_eps[0] - vals_eps[1])
        eps = s["obliquity"]
        scalars = [math.degrees(eps), s["precession_rate"] * _PER_YEAR, s["hd"], s["K"] * _PER_YEAR,
                   half_psi / ARCSEC, half_eps / ARCSEC]
        amp_lon = np.hypot(lon_s, lon_c) * math.sin(eps) / ARCSEC
        amp_obl = np.hypot(obl_s, obl_c) / ARCSEC
        period = 2.0 * math.pi / (self.k * s["n"])
        terms = np.stack([period, lon_s / ARCSEC, lon_c / ARCSEC, obl_s / ARCSEC, obl_c / ARCSEC,
                          amp_lon, amp_obl], axis=1)
        return np.concatenate([scalars, terms.ravel()])


# --------------------------------------------------------------------------- the set-up shared by both methods

@dataclass
class _Setup:
    body: Body
    dataset: str
    order: int | None
    inputs: list[CatalogueInput]
    replica: _Replica
    x0: np.ndarray            # model units
    y0: np.ndarray            # nominal outputs
    extrema: tuple
    multiples: np.ndarray
    rho: np.ndarray


def _setup(b: Body, order, uncertainties, correlations) -> _Setup:
    # the answers' own validation of the order and of the theory's applicability

    m = model_for(b, b.dataset, order)          # raises NotApplicableError for the Moon
    inputs = catalogue_inputs(b, uncertainties)
    keys = [i.key for i in inputs]
    kmax = int(m.nutation.multiple.max()) if m.nutation.multiple.size else 0
    replica = _Replica(b, keys, m.order, kmax)
    x0 = np.array([i.value * i.factor for i in inputs])
    lon_s, lon_c, obl_s, obl_c = replica.state(x0)["coefficients"]
    # the extremes located as the answers locate them (harmonics.series_extrema: grid, then Newton)
    _, xp_max, xp_min = series_extrema(lon_s, lon_c)
    _, xe_max, xe_min = series_extrema(obl_s, obl_c)
    extrema = (xp_max, xp_min, xe_max, xe_min)
    y0 = replica.outputs(x0, extrema)
    return _Setup(b, b.dataset, m.order, inputs, replica, x0, y0, extrema,
                  np.arange(1, kmax + 1), correlation_matrix(inputs, correlations, b))


def difference_step(inp: CatalogueInput, x_model: float) -> float:
    """Finite-difference step in model units."""
    if inp.sigma:
        return STEP_FRACTION * inp.sigma * inp.factor
    if inp.kind == "angle":
        return _DEFAULT_STEP["angle"]
    if inp.kind == "e":
        return _DEFAULT_STEP["e"]
    return _DEFAULT_STEP["relative" if inp.kind == "relative" else "a"] * abs(x_model)


def _jacobian(st: _Setup, which: list[int], step_scale: float = 1.0) -> np.ndarray:
    """d outputs / d input (per model unit of the input) for the inputs ``which``: (n_out, len(which))."""
    cols = []
    for j in which:
        h = step_scale * difference_step(st.inputs[j], st.x0[j])
        xp, xm = st.x0.copy(), st.x0.copy()
        xp[j] += h
        xm[j] -= h
        try:
            cols.append((st.replica.outputs(xp, st.extrema) - st.replica.outputs(xm, st.extrema)) / (2.0 * h))
        except _Rejected:   # at the edge of the domain (e = 0, H_d = 0.5, ...): one-sided, second order
            sign = 1.0
            try:
                st.replica.outputs(xp, st.extrema)
            except _Rejected:
                sign = -1.0
            x1, x2 = st.x0.copy(), st.x0.copy()
            x1[j] += sign * h
            x2[j] += sign * 2.0 * h
            try:
                y1, y2 = st.replica.outputs(x1, st.extrema), st.replica.outputs(x2, st.extrema)
            except _Rejected:
                raise InvalidInputError(st.inputs[j].key, "cannot be varied either way from its value: "
                                        "no derivative", st.body.name) from None
            cols.append(sign * (-3.0 * st.y0 + 4.0 * y1 - y2) / (2.0 * h))
    return np.stack(cols, axis=1) if cols else np.zeros((st.y0.size, 0))


def _scalar_and_terms(vector: np.ndarray, kmax: int) -> tuple[np.ndarray, np.ndarray]:
    ns = len(SCALAR_KEYS)
    return vector[:ns], vector[ns:].reshape(kmax, len(TERM_KEYS))


# --------------------------------------------------------------------------- public

def propagate(body: str | int | Body, order: int | None = None, *,
              uncertainties: Mapping[str, float | None] | None = None,
              correlations: Mapping[tuple[str, str], float] | None = None, sensitivities: bool = True) -> dict:
    """Linear 1-σ uncertainties of the precession-nutation outputs from the inputs' 1-σ.

    ``body``: a :class:`Body` (its dataset with it), or a catalogue name / NAIF id of the default dataset (another
    dataset's body: ``get_body(name, dataset)``).
    ``uncertainties``: {input key: σ or None}, overriding the catalogue's (σ in the unit of
    ``inputs[key]["unit"]``, the catalogue value's own). ``correlations``: {(key, key): ρ};
    without them the inputs are independent.

    Returns the public keys with ``_uncertainty`` appended (``obliquity_deg_uncertainty``,
    ``precession_rate_arcsec_per_year_uncertainty``, ``dynamical_ellipticity_uncertainty``,
    ``scaling_factor_arcsec_per_year_uncertainty``, ``delta_psi_half_peak_to_peak_arcsec_uncertainty``,
    ``delta_epsilon_half_peak_to_peak_arcsec_uncertainty``); ``terms`` (one per nutation term, as in
    :func:`ephem.answers.requests.nutation`, each with ``<key>_uncertainty`` for TERM_KEYS, the nominal
    amplitudes, ``contributions`` and ``dominant_input``); ``values`` (nominal scalars);
    ``contributions`` {output: {input: J_i σ_i}} (signed, output units; with independent inputs
    σ² = Σ of their squares); ``dominant_input`` {output: input or None};
    ``sensitivities`` {output: {input: ∂output/∂input per catalogue unit}} for every input,
    with or without σ (``sensitivities=False``: only for the inputs with a σ, whose derivatives the
    uncertainties need, the rest reported as 0; the answers of :mod:`ephem.answers.requests` use this: each
    derivative costs two model evaluations, seconds at high e); ``inputs`` (the propagated ones: value, unit, uncertainty, source);
    ``unpropagated_inputs`` (inputs with no σ: their contribution is unknown, not zero);
    ``assumptions``.

    Raises NotApplicableError where the theory does not apply (the Moon: its Cassini-state answers say "not propagated").
    """
    st = _setup(resolve_body(body), order, uncertainties, correlations)
    n_in = len(st.inputs)
    which = list(range(n_in)) if sensitivities else [j for j, i in enumerate(st.inputs) if i.sigma is not None]
    J = np.zeros((st.y0.size, n_in))
    J[:, which] = _jacobian(st, which)                                # per model unit
    factors = np.array([i.factor for i in st.inputs])
    sig = np.array([(i.sigma or 0.0) * i.factor for i in st.inputs])  # model units
    contrib = J * sig[None, :]                                        # (n_out, n_in), output units
    var = np.einsum("oi,ij,oj->o", contrib, st.rho, contrib)
    sigma = np.sqrt(np.maximum(var, 0.0))
    sens = J * factors[None, :]                                       # per catalogue unit
    propagated = [i for i in st.inputs if i.sigma is not None]
    prop_idx = [j for j, i in enumerate(st.inputs) if i.sigma is not None]
    kmax = st.replica.kmax

    def per_output(row_c, row_s):
        c = {st.inputs[j].key: float(row_c[j]) for j in prop_idx}
        dom = max(c, key=lambda key: abs(c[key])) if c and max(abs(v) for v in c.values()) > 0 else None
        return c, dom, {inp.key: float(row_s[j]) for j, inp in enumerate(st.inputs)}

    s_sig, t_sig = _scalar_and_terms(sigma, kmax)
    s_y0, t_y0 = _scalar_and_terms(st.y0, kmax)
    ns, nt = len(SCALAR_KEYS), len(TERM_KEYS)
    ans = {"body": st.body.name, "dataset": st.dataset, "order": st.order,
           "method": f"linear: central finite differences, step {STEP_FRACTION:g} sigma"}
    contributions, dominant, sensitivities = {}, {}, {}
    for o, key in enumerate(SCALAR_KEYS):
        ans[f"{key}_uncertainty"] = float(s_sig[o])
        contributions[key], dominant[key], sensitivities[key] = per_output(contrib[o], sens[o])
    terms = []
    for t in range(kmax):
        entry = {"multiple": int(st.multiples[t]),
                 "amplitude_longitude_arcsec": float(t_y0[t, TERM_KEYS.index("amplitude_longitude_arcsec")]),
                 "amplitude_obliquity_arcsec": float(t_y0[t, TERM_KEYS.index("amplitude_obliquity_arcsec")])}
        tc, td = {}, {}
        for q, key in enumerate(TERM_KEYS):
            row = ns + t * nt + q
            entry[f"{key}_uncertainty"] = float(t_sig[t, q])
            tc[key], td[key], _ = per_output(contrib[row], sens[row])
        entry["contributions"], entry["dominant_input"] = tc, td
        terms.append(entry)
    ans["terms"] = terms
    ans["values"] = {key: float(s_y0[o]) for o, key in enumerate(SCALAR_KEYS)}
    ans["contributions"] = contributions
    ans["dominant_input"] = dominant
    ans["sensitivities"] = sensitivities
    ans["inputs"] = {i.key: {"value": i.value, "unit": i.unit, "uncertainty": i.sigma, "source": i.source}
                     for i in propagated}
    ans["unpropagated_inputs"] = [i.key for i in st.inputs if i.sigma is None]
    ans["no_uncertainty_reasons"] = no_uncertainty_reasons(st.body, ans["unpropagated_inputs"])
    ans["correlations"] = {f"{st.inputs[a].key}|{st.inputs[b].key}": float(st.rho[a, b])
                           for a in range(n_in) for b in range(a + 1, n_in) if st.rho[a, b] != 0.0}
    ans["assumptions"] = list(ASSUMPTIONS)
    return ans


def monte_carlo(body: str | int | Body, n: int = 1000, seed: int = 0, order: int | None = None, *,
                uncertainties: Mapping[str, float | None] | None = None,
                correlations: Mapping[tuple[str, str], float] | None = None) -> dict:
    """Monte Carlo check of :func:`propagate`: sample the inputs, recompute, take the sample std.

    Inputs are drawn normal with their σ (and ``correlations``), seeded (``numpy`` PCG64 via
    ``default_rng(seed)``); angles need no wrapping (a pole pushed past ±90° of Dec is the
    same direction as the wrapped one). Samples no body can have (e ≥ 1, a period ≤ 0,
    moments with C not the largest, H_d outside (0, 0.5]) are dropped and counted
    (``rejected``). Returns the same ``<key>_uncertainty`` keys as :func:`propagate` (sample
    std, ddof 1), ``terms`` likewise, and ``comparison`` {output: {linear, monte_carlo, ratio,
    bias_sigma (mean − nominal)/σ_mc}} for the scalars (None where the linear σ is 0), with
    ``relative_standard_error`` ≈ 1/sqrt(2(N−1)), the sampling error of a std estimated from
    N normal samples.
    """
    if isinstance(n, bool) or not isinstance(n, int) or n < 2:
        raise InvalidInputError("n", f"need an integer number of samples >= 2, got {n!r}")
    st = _setup(resolve_body(body), order, uncertainties, correlations)
    lin = propagate(st.body, order, uncertainties=uncertainties, correlations=correlations)
    sig = np.array([(i.sigma or 0.0) * i.factor for i in st.inputs])
    live = np.nonzero(sig > 0.0)[0]          # inputs without a σ stay exactly at their value
    rho = st.rho[np.ix_(live, live)]
    try:
        root = np.linalg.cholesky(rho)
    except np.linalg.LinAlgError:            # fully correlated inputs: a singular, semi-definite ρ
        w, v = np.linalg.eigh(rho)
        root = v * np.sqrt(np.clip(w, 0.0, None))[None, :]
    rng = np.random.default_rng(seed)
    draws = np.repeat(st.x0[None, :], n, axis=0)
    draws[:, live] += (rng.standard_normal((n, live.size)) @ root.T) * sig[live]
    rows, rejected = [], 0
    for x in draws:
        try:
            rows.append(st.replica.outputs(x, None))
        except _Rejected:
            rejected += 1
    kmax = st.replica.kmax
    ans = {"body": st.body.name, "dataset": st.dataset, "order": st.order, "n": n, "seed": seed,
           "valid": len(rows), "rejected": rejected}
    if len(rows) < 2:
        raise InvalidInputError("n", f"only {len(rows)} of {n} samples describe a possible body", st.body.name)
    y = np.array(rows)
    std = y.std(axis=0, ddof=1)
    mean = y.mean(axis=0)
    s_std, t_std = _scalar_and_terms(std, kmax)
    s_mean, _ = _scalar_and_terms(mean, kmax)
    s_y0, _ = _scalar_and_terms(st.y0, kmax)
    comparison = {}
    for o, key in enumerate(SCALAR_KEYS):
        ans[f"{key}_uncertainty"] = float(s_std[o])
        lin_s = lin[f"{key}_uncertainty"]
        comparison[key] = {"linear": lin_s, "monte_carlo": float(s_std[o]),
                           "ratio": float(s_std[o] / lin_s) if lin_s > 0 else None,
                           "bias_sigma": float((s_mean[o] - s_y0[o]) / s_std[o]) if lin_s > 0 and s_std[o] > 0
                           else None}
    ans["terms"] = [{"multiple": int(st.multiples[t]),
                     **{f"{key}_uncertainty": float(t_std[t, q]) for q, key in enumerate(TERM_KEYS)}}
                    for t in range(kmax)]
    ans["comparison"] = comparison
    ans["relative_standard_error"] = 1.0 / math.sqrt(2.0 * (len(rows) - 1))
    ans["linear"] = lin
    return ans


# a user's body of many harmonics holds ~0.5 MB here (e = 0.9): bounded in bytes (ephem.base.memo); keyed by the σ too
@bytes_bounded(key=lambda b, order=None: b.with_sigmas(order))
def propagated(b: Body, order: int | None) -> dict:
    """The 1-σ uncertainties of :func:`propagate`, with 0 (no input of known σ moves the value: its σ is
    unknown, not zero) replaced by None. A body none of whose inputs has a σ (a user's body) skips the
    propagation: every σ is None, at no cost."""
    def unknown_as_none(d: dict) -> dict:
        return {k: (None if k.endswith("_uncertainty") and v == 0.0 else v) for k, v in d.items()}

    sigmas = input_sigmas(b)
    if all(s is None for s in sigmas.values()):
        u = {f"{k}_uncertainty": None for k in SCALAR_KEYS}
        u["terms"] = [{"multiple": int(k), **{f"{key}_uncertainty": None for key in TERM_KEYS}}
                      for k in cached_model(b, order).nutation.multiple]
        u.update(dominant_input={k: None for k in SCALAR_KEYS}, unpropagated_inputs=list(sigmas),
                 no_uncertainty_reasons=no_uncertainty_reasons(b, list(sigmas)), assumptions=list(ASSUMPTIONS))
        return u
    u = unknown_as_none(propagate(b, order, sensitivities=False))
    u["terms"] = [unknown_as_none(t) for t in u["terms"]]
    return u


def summary(u: dict) -> dict:
    """The answers' ``uncertainty`` object from :func:`propagated`."""
    return {"method": "linear propagation of the catalogue's 1-sigma uncertainties (ephem.forced.uncertainty); they "
                      "cover only the inputs with a published sigma (complete: false when some input has none, "
                      "each listed with the reason, and the sigmas are then lower bounds), and null means no such "
                      "input moves the value (its uncertainty is unknown, not zero)",
            "complete": not u["unpropagated_inputs"],
            "dominant_input": u["dominant_input"], "unpropagated_inputs": list(u["unpropagated_inputs"]),
            "no_uncertainty_reasons": dict(u["no_uncertainty_reasons"]), "assumptions": list(u["assumptions"])}
