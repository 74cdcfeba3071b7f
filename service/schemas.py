"""Pydantic schemas: the JSON contract of the routes (units in the key names)."""
from __future__ import annotations

import math
from typing import Annotated, Literal, Optional, Union

from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, Field, GetPydanticSchema
from pydantic_core import PydanticCustomError

from ephem.api import AXES, CALENDAR_SCALES, GM_CENTER, MAX_ANGLE_DEG, MAX_ORDER, MODELS, Body, Orbit, Pole

# strict: JSON true is not a number, nor "2.36" (a string) one; JSON integers are still numbers
Finite = ConfigDict(allow_inf_nan=False, extra="forbid", strict=True)


def known_model(name: str) -> str:
    """``name`` if a family of the registry answers to it (ephem.api.MODELS, read at each request: a family registered
    after this module was imported is known), else the 422 a Literal of the names would give."""
    if name not in MODELS:
        names = [repr(m) for m in MODELS]
        raise PydanticCustomError("literal_error", "Input should be {expected}",
                                  {"expected": f"{', '.join(names[:-1])} or {names[-1]}"})
    return name


def known_centre(name: str) -> str:
    """``name`` if it is an orbit centre the library knows (ephem.api.GM_CENTER, read at each request: a centre
    registered after this module was imported, ephem.api.register_centres, is known), else a Literal's 422."""
    if name not in GM_CENTER:
        names = [repr(c) for c in GM_CENTER]
        raise PydanticCustomError("literal_error", "Input should be {expected}",
                                  {"expected": " or ".join(filter(None, (", ".join(names[:-1]), names[-1])))})
    return name


CentreName = Annotated[str, AfterValidator(known_centre), GetPydanticSchema(
    get_pydantic_json_schema=lambda core, handler: {"type": "string", "enum": list(GM_CENTER)})]
# the names come from the library (one source each): the models of ephem.families (their enum in the schema made when
# the app's OpenAPI is, from the registry then), the axes of ephem.sun.ladder
RungName = Annotated[str, AfterValidator(known_model), GetPydanticSchema(
    get_pydantic_json_schema=lambda core, handler: {"type": "string", "enum": list(MODELS)})]
Perturbers = Field(None, description="the bodies whose torque the answer includes: the orbit's centre (the Sun), "
                                     "and for the Earth by default the Moon too (the lunisolar theory)")
AxisName = Literal[AXES]
TimeScaleName = Literal[CALENDAR_SCALES]


def CalendarDates(scale: str):
    """The epochs' calendar dates in ``scale``: present when the request's time_scale is ``scale``."""
    return Field(None, description=f"the epochs as {scale.upper()} calendar dates, ISO 8601 to the millisecond "
                                   f"(YYYY-MM-DDThh:mm:ss.sss; a year outside 0000-9999 with its sign), beside jd_tdb; "
                                   f"present when time_scale={scale}" + (" (the default)" if scale == "utc" else ""),
                 examples=[["2040-01-01T00:00:00.000"]])


#: what an angle taken modulo 360 deg accepts (ephem.bodies.catalogue.MAX_ANGLE_DEG), appended to its description
ANGLE_RULE = (f"; any number of turns within ±{MAX_ANGLE_DEG:g} deg (beyond it the doubles are more than "
              f"{math.ulp(MAX_ANGLE_DEG):.2g} deg apart and the angle modulo 360 loses its digits: 422 naming the "
              "field)")


ANGLE_BOUNDS = {"minimum": -MAX_ANGLE_DEG, "maximum": MAX_ANGLE_DEG}


def _angle_bounds(schema: dict) -> None:
    """State MAX_ANGLE_DEG in the JSON Schema, on the number branch (anyOf with null for an optional angle). The
    library enforces it (ephem.bodies.catalogue.check_angle), with the reason in the 422, so pydantic is not asked to."""
    for branch in schema.get("anyOf", [schema]):
        if branch.get("type") == "number":
            branch.update(ANGLE_BOUNDS)


def Angle(description: str, default=...):
    """A field holding an angle in degrees, taken modulo 360 deg."""
    return Field(default, description=description + ANGLE_RULE, json_schema_extra=_angle_bounds)


RotationPhase = ("the angle of the long (least-inertia) axis in the body's equator from the ascending node of the "
                 "orbit on it at the pole epoch, deg: lets the track add the semi-diurnal terms of the rotation "
                 "scale (without it the tolerance can add the Oppolzer offset alone)")


class FreeWobbleInfo(BaseModel):
    J_arcsec: float = Field(description="the wobble's amplitude: the angle between the figure axis and the angular "
                                        "momentum at its epoch, arcsec")
    phase_deg: float = Field(description="the figure axis's position angle about the angular momentum at the epoch, "
                                         "from the ICRF north through east, deg")
    epoch_jd_tdb: float


class RotationScaleInfo(BaseModel):
    modelled: Literal["oppolzer", "all"] = Field(description="the rotation-scale terms the track adds: the figure "
                                                             "axis's Oppolzer offset, or with the semi-diurnal terms "
                                                             "too (needs the rotation phase)")
    rotation_phase_deg: Optional[float] = Field(description="the rotation phase the request gave, deg, or null")


class ChoiceCandidate(BaseModel):
    name: RungName
    order: Optional[int] = Field(description="e-power order (series), else null")
    free_wobble: bool = Field(description="the variant follows the free wobble")
    rotation_scale: Optional[Literal["oppolzer", "all"]] = Field(description="the variant adds these rotation-scale "
                                                                           "terms, or null")
    estimated_error_mas: float = Field(description="its estimate over the epochs, mas (within the tolerance)")
    estimated_cpu_ms: float = Field(description="its predicted CPU time for these epochs, ms")
    estimated_memory_mb: float = Field(description="its predicted peak memory, MB")
    chosen: bool


class Choice(BaseModel):
    rule: str = Field(description="how a tolerance chooses: the model predicted cheapest among those within it")
    reason: str = Field(description="why the chosen model won, in words (naming the cheaper models estimated beyond "
                                    "the tolerance and the dearer ones not run for an estimate)")
    eligible: list[ChoiceCandidate] = Field(description="every model and variant whose estimate met the tolerance, "
                                                        "in the family's order (every model: GET "
                                                        "/v1/bodies/{body}/track/models)")


class ModelInfo(BaseModel):
    theory: str
    eccentricity_order: Optional[Union[int, Literal["exact"]]] = Field(
        description="e-power order of the Hansen coefficients, \"exact\", or null for the lunisolar theory (the "
                    "Earth with the Moon: its series are cut by amplitude, cut_mas)")
    assumptions: list[str]
    warnings: list[str]
    spin_orbit_ratio: float
    min_spin_orbit_ratio: float
    pole_epoch_jd_tdb: float
    orbit_epoch_jd_tdb: float
    name: RungName = Field(description="the model that computed the answer (a rung of the fidelity ladder, or the "
                                       "model of another family)")
    order: Optional[int] = Field(description="e-power order of the Hansen coefficients (series rung), else null")
    description: str
    estimated_error_mas: Optional[float] = Field(
        description="estimated upper bound on the pole's distance from the truth over the epochs, mas "
                    "(for rates and nutation terms: the truncation bound); never 0: null where nothing is "
                    "truncated (estimate_covers says what it bounds)")
    estimate_covers: str = Field(description="what estimated_error_mas bounds: the whole (tracks: every named "
                                             "term) or the truncation alone (rates and nutation series)")
    error_terms_mas: Optional[dict[str, float]] = Field(description="the estimate by named term, mas")
    tolerance_mas: Optional[float] = Field(description="the tolerance that chose the rung, if one was given")
    cost_ms: float = Field(description="wall time of the computation, ms")
    axis: Optional[AxisName] = Field(None, description="tracks: the pole followed, the figure axis (default), the "
                                                       "angular momentum, the figure axis's forced motion "
                                                       "(forced_figure, the CIP's analogue) or a synchronous body's "
                                                       "mean rotation axis (mean_rotation)")
    free_wobble: Optional[FreeWobbleInfo] = Field(None, description="tracks: the free wobble added to the figure "
                                                                    "axis, or null when it is left out")
    rotation_scale: Optional[RotationScaleInfo] = Field(None, description="tracks: the rotation-scale terms added "
                                                        "(ephem.forced.rotation_scale), or null when none are")
    perturbers: Optional[list[str]] = Perturbers
    cut_mas: Optional[float] = Field(None, description="the lunisolar theory (name \"lunisolar\"): the amplitude cut "
                                                       "of its nutation series, mas")
    choice: Optional[Choice] = Field(None, description="tracks chosen by tolerance_mas: how the model was chosen "
                                                       "(docs/accuracy.md, How the model is chosen)")


class BodySummary(BaseModel):
    name: str
    naif_id: Optional[int]
    kind: str
    dataset: str
    a_au: float
    e: float
    orbit_center: str
    rotation_period_hours: float
    pole_ra_deg: float
    pole_dec_deg: float
    dynamical_ellipticity: float


class MeasuredValue(BaseModel):
    value: float
    unit: str
    uncertainty: Optional[float] = Field(description="1-sigma, same unit; null: none published")
    no_uncertainty: Optional[str] = Field(None, description="why no 1-sigma is published (null when one is)")
    source: str
    reference: Optional[dict]
    note: Optional[str]


class Correlation(BaseModel):
    inputs: list[str] = Field(description="the two values whose errors are correlated")
    value: float = Field(description="the correlation coefficient, in [-1, 1]")


class InteriorParameter(BaseModel):
    value: float
    unit: str = Field(description="the value's unit (empty: dimensionless)")
    uncertainty: Optional[float] = Field(description="1-sigma, same unit; null: none published")
    no_uncertainty: Optional[str] = Field(None, description="why no 1-sigma is published (null when one is)")


class InteriorAlternative(BaseModel):
    model: Literal["rigid", "transfer_function"]
    form: Optional[str] = Field(description="the transfer function's formula (fluid_core_resonance, "
                                            "iers1996_resonance); null when rigid")
    parameters: dict[str, InteriorParameter]
    source: Optional[str] = Field(description="a key of data/interiors.toml's [references.*]")
    reference: Optional[dict] = Field(description="the source's citation, where it was read and its status")
    why: Optional[str] = Field(description="why the body is rigid (null otherwise)")
    left_out: list[str] = Field(description="what the model leaves out")
    parameters_file: Optional[str] = Field(description="the file holding the parameters when they are not listed")


class Interior(InteriorAlternative):
    """The interior model of the forced nutation (data/interiors.toml, docs/interiors.md)."""
    alternatives: dict[str, InteriorAlternative] = Field(description="other published parameter sets, by name")


class BodyRecord(BaseModel):
    name: str
    naif_id: Optional[int]
    kind: str
    dataset: str
    orbit_center: str
    dynamical_ellipticity: float
    dynamical_ellipticity_from: str
    perturbers: Optional[list[str]] = Perturbers
    values: dict[str, MeasuredValue]
    correlations: list[Correlation] = Field(
        description="correlations of the values' errors: stated by a source, or implied by deriving several values "
                    "from one measurement (data/catalogue/SCHEMA.md)")
    interior: Interior = Field(description="the body's interior model of the forced nutation: rigid (with why) or a "
                                           "transfer function (form, parameters, source)")


class UncertaintyInfo(BaseModel):
    method: str
    dominant_input: dict[str, Optional[str]] = Field(description="the input whose uncertainty moves each value most")
    unpropagated_inputs: list[str] = Field(description="inputs without a published uncertainty (unknown, not zero)")
    complete: bool = Field(description="whether every input has a published uncertainty; false: the 1-sigma values "
                                       "cover only those that have one and are lower bounds")
    no_uncertainty_reasons: dict[str, str] = Field(
        description="for each unpropagated input, why it has no uncertainty (the catalogue record's reason)")
    assumptions: list[str]
    lower_bounds: Optional[dict[str, str]] = Field(
        None, description="for each value given a 1-sigma that an input without one also moves (its sigma is then a "
                          "lower bound), which inputs have a sigma and which have none, by the value's key ('terms': "
                          "the nutation terms'): 'only the rotation period has a σ; the orbit, the pole and C/MR² "
                          "have none'",
        examples=[{"precession_rate_arcsec_per_year": "only the rotation period has a σ; the orbit, the pole and "
                                                      "C/MR² have none"}])


Sigma = Field(None, description="1-sigma uncertainty from the catalogue's, same unit; null when no input with a "
                                "published uncertainty moves the value")


class CassiniInfo(BaseModel):
    """The Cassini state of a synchronous rotator (ephem.forced.cassini): the served mean pole and what the theory derives."""
    equator_inclination_deg: float = Field(description="the served mean pole's inclination to the Laplace plane "
                                                       "(the Moon: the ecliptic of date), from the catalogue pole")
    derived_equator_inclination_deg: float = Field(description="the same from the torque's balance against the "
                                                               "node's regression (the moments, n, i, the node rate)")
    derived_obliquity_deg: float = Field(description="the derived spin axis's angle from the orbit normal, i + I")
    orbit_inclination_deg: float
    node_rate_deg_per_year: float = Field(description="the node's inertial rate on the Laplace plane")
    node_period_years: float
    beta: float = Field(description="(C − A)/B")
    gamma: float = Field(description="(B − A)/C")
    free_libration_longitude_days: float
    free_libration_latitude_days: float = Field(description="in the frame turning with the node")
    free_precession_space_days: float
    free_wobble_days: float


class Precession(BaseModel):
    body: str
    dataset: str
    obliquity_deg: float
    dynamical_ellipticity: float
    scaling_factor_arcsec_per_year: float
    precession_rate_arcsec_per_year: float
    obliquity_deg_uncertainty: Optional[float] = Sigma
    dynamical_ellipticity_uncertainty: Optional[float] = Sigma
    scaling_factor_arcsec_per_year_uncertainty: Optional[float] = Sigma
    precession_rate_arcsec_per_year_uncertainty: Optional[float] = Sigma
    geodesic_precession_rate_arcsec_per_year: Optional[float] = Field(
        None, description="the geodesic (de Sitter) precession, which turns the axis about the orbit normal the other "
                          "way from the torque's rate (for the Moon: the Earth-Moon system's about the Sun)")
    geodesic_precession_in_rate: Optional[bool] = Field(
        None, description="true where precession_rate_arcsec_per_year is an observed rate that already contains the "
                          "geodesic precession (the Moon's node, fitted to observations); false where it is the "
                          "torque's alone")
    observable_precession_rate_arcsec_per_year: Optional[float] = Field(
        None, description="what radio tracking measures: precession_rate_arcsec_per_year (the torque's alone) less "
                          "the geodesic precession, or the rate itself where it contains it already")
    observable_precession_rate_arcsec_per_year_uncertainty: Optional[float] = Sigma
    cassini: Optional[CassiniInfo] = Field(None, description="a synchronous rotator (the Moon): its Cassini state")
    uncertainty: UncertaintyInfo
    perturbers: Optional[list[str]] = Perturbers
    model: ModelInfo


class NutationTerm(BaseModel):
    multiple: Optional[int] = Field(description="the harmonic of the mean anomaly M; null for the lunisolar theory's "
                                                "terms, whose argument is delaunay_multipliers")
    delaunay_multipliers: Optional[list[int]] = Field(
        None, description="the lunisolar theory (the Earth with the Moon): the argument's integer multipliers of the "
                          "Delaunay arguments [l, l′, F, D, Ω] (IERS 2010 eq. 5.43), as in the IAU 2000A tables",
        min_length=5, max_length=5)
    period_days: float
    period_years: float
    longitude_sin_arcsec: float
    longitude_cos_arcsec: float
    obliquity_sin_arcsec: float
    obliquity_cos_arcsec: float
    period_days_uncertainty: Optional[float] = Sigma
    longitude_sin_arcsec_uncertainty: Optional[float] = Sigma
    longitude_cos_arcsec_uncertainty: Optional[float] = Sigma
    longitude_amplitude_arcsec: float = Field(description="the amplitude of the pole's displacement in longitude, "
                                              "the paper's Amp: Δψ sin ε = (Sin² + Cos²)^½ sin ε, or Δψ where Δψ is "
                                              "one already (the Moon's σ); the answer's amplitude_quantities names it")
    longitude_amplitude_arcsec_uncertainty: Optional[float] = Sigma
    obliquity_sin_arcsec_uncertainty: Optional[float] = Sigma
    obliquity_cos_arcsec_uncertainty: Optional[float] = Sigma
    obliquity_amplitude_arcsec: float = Field(description="the paper's Amp: Δε = (Sin² + Cos²)^½")
    obliquity_amplitude_arcsec_uncertainty: Optional[float] = Sigma
    longitude_sin_rate_arcsec_per_century: Optional[float] = Field(
        None, description="lunisolar terms: the coefficient's rate (Poisson term), arcsec per Julian century")
    longitude_cos_rate_arcsec_per_century: Optional[float] = None
    obliquity_sin_rate_arcsec_per_century: Optional[float] = None
    obliquity_cos_rate_arcsec_per_century: Optional[float] = None


class Nutation(BaseModel):
    body: str
    dataset: str
    argument: str
    mean_anomaly_at_epoch_deg: float
    orbit_epoch_jd_tdb: float
    mean_motion_deg_per_day: float
    obliquity_deg: float
    terms: list[NutationTerm]
    amplitude_quantities: dict[str, str] = Field(
        description="the quantity each term's amplitude key is, by key: longitude_amplitude_arcsec is Δψ sin ε (the "
                    "pole's displacement, Δψ running along the ecliptic) or Δψ (the Moon's σ, a displacement "
                    "already); obliquity_amplitude_arcsec is Δε. The tables' Amp columns (format=csv, markdown, "
                    "latex) are the same quantities and say so in their headers",
        examples=[{"longitude_amplitude_arcsec": "Δψ sin ε", "obliquity_amplitude_arcsec": "Δε"}])
    delta_psi_half_peak_to_peak_arcsec: float
    delta_epsilon_half_peak_to_peak_arcsec: float
    delta_psi_half_peak_to_peak_arcsec_uncertainty: Optional[float] = Sigma
    delta_epsilon_half_peak_to_peak_arcsec_uncertainty: Optional[float] = Sigma
    uncertainty: UncertaintyInfo
    perturbers: Optional[list[str]] = Perturbers
    model: ModelInfo


class Track(BaseModel):
    body: str
    dataset: str
    jd_tdb: list[float]
    utc_iso: Optional[list[str]] = CalendarDates("utc")
    tt_iso: Optional[list[str]] = CalendarDates("tt")
    tdb_iso: Optional[list[str]] = CalendarDates("tdb")
    psi_arcsec: list[float]
    delta_psi_arcsec: list[float]
    delta_epsilon_arcsec: list[float]
    obliquity_deg: list[float]
    obliquity_deg_uncertainty: Optional[float] = Sigma
    pole_ra_deg: list[float]
    pole_dec_deg: list[float]
    pole_uncertainty_deg: Optional[list[float]] = Field(
        None, description="the 1-sigma of the angle between the served and the true pole at each epoch, deg, from "
                          "the catalogue's 1-sigma (the inputs without one do not count); null where none has one")
    perturbers: Optional[list[str]] = Perturbers
    model: ModelInfo


class TrackModelEntry(BaseModel):
    """One model of the family serving the body, over the request's epochs (ephem.api.track_models)."""
    name: RungName = Field(description="the model (a rung of the fidelity ladder, or the family's model)")
    order: Optional[int] = Field(description="e-power order of the Hansen coefficients (series), else null")
    description: str
    available: bool = Field(description="whether the model can serve these epochs (why_not says why not)")
    why_not: Optional[str] = Field(description="why the model cannot serve these epochs, or null")
    estimated_error_mas: Optional[float] = Field(description="estimated upper bound on the pole's distance from the "
                                                             "truth over the epochs, mas; null: not estimated")
    error_terms_mas: Optional[dict[str, float]] = Field(description="the estimate by named term, mas")
    free_wobble: bool = Field(description="the variant adds the free wobble of the figure axis")
    rotation_scale: Optional[Literal["oppolzer", "all"]] = Field(
        description="the rotation-scale terms the variant adds (the Oppolzer offset, or all), or null")
    estimated_cpu_ms: Optional[float] = Field(description="predicted CPU time of its track, ms of one core "
                                                          "(ephem.theory.cost); null where not available")
    estimated_memory_mb: Optional[float] = Field(description="predicted peak memory of its track, MB")
    eligible: Optional[bool] = Field(None, description="available, and within tolerance_mas when one is given")
    why: Optional[str] = Field(None, description="why the model is eligible, ineligible or chosen")
    chosen: bool = Field(description="the model tolerance_mas picks")


class TrackModels(BaseModel):
    """Speed against accuracy for one request: every model with its estimate and predicted cost, in the family's
    order, and the one the tolerance picks."""
    body: str
    dataset: str
    perturbers: Optional[list[str]] = Perturbers
    theory: str = Field(description="the family of theories serving the body")
    start_jd_tdb: float = Field(description="the first epoch, JD TDB")
    stop_jd_tdb: float = Field(description="the last epoch on the grid, JD TDB")
    epochs: int = Field(description="the number of epochs")
    tolerance_mas: Optional[float] = Field(description="the request's tolerance, mas, or null")
    rule: Optional[str] = Field(None, description="how the model is chosen")
    chosen: Optional[RungName] = Field(description="the model the tolerance picks, or null (none given, or none "
                                                   "within it)")
    chosen_order: Optional[int] = Field(None, description="the chosen model's e-order, or null")
    why_chosen: Optional[str] = Field(None, description="why that model, or null")
    models: list[TrackModelEntry]


OrbitModelName = Literal["secular", "nbody"]


class HistoryOrbit(BaseModel):
    model: OrbitModelName = Field(description="secular (Laplace-Lagrange) or nbody (REBOUND WHFast from DE421)")
    source: Optional[str] = Field(description="what produced the orbit")
    horizon_years: Optional[list[float]] = Field(
        description="(past, future) years from J2000.0 over which the orbit normal holds to 1 arcmin, or null")


class HistoryCandidate(BaseModel):
    """One orbit model of a history's choice (ephem.longterm.orbit_selection)."""
    name: OrbitModelName
    available: bool = Field(description="whether the model can serve the span (why_not says why not)")
    why_not: Optional[str] = Field(description="why the model cannot serve the span, or null")
    estimated_error_mas: Optional[float] = Field(description="its estimate over the span, mas; null: not run for "
                                                             "one (dearer than the chosen model, or not chosen)")
    estimated_cpu_ms: Optional[float] = Field(description="its predicted CPU time, ms of one core; null: unavailable")
    eligible: Optional[bool] = Field(description="whether its estimate meets tolerance_mas; null: not estimated, or "
                                                 "no tolerance given")
    chosen: bool


class HistoryModel(BaseModel):
    name: OrbitModelName = Field(description="the orbit model the spin was integrated along")
    description: str
    theory: str = Field(description="the family of theories serving the body (its precession constant)")
    spin: str = Field(description="where the precession constant comes from")
    orbit: HistoryOrbit
    estimated_error_mas: float = Field(description="estimated upper bound on the pole's distance from the truth "
                                                   "over the span, mas")
    error_terms_mas: dict[str, float] = Field(description="the estimate's largest value of each named term, mas")
    obliquity_error_terms_mas: dict[str, float] = Field(description="the same for the obliquity alone (the terms of "
                                                                    "obliquity_error_deg), mas")
    probed_terms: list[str] = Field(description="terms whose input has no published 1-sigma: a probe was used")
    estimates_mas: dict[str, float] = Field(description="each orbit model tried, its estimate, mas")
    tolerance_mas: Optional[float]
    cost_ms: float
    assumptions: list[str]
    warnings: list[str]
    perturbers: Optional[list[str]] = Perturbers
    rule: Optional[str] = Field(None, description="how the orbit model is chosen: named, the default without a "
                                                  "tolerance, or the cheapest predicted among those within it")
    why_chosen: Optional[str] = Field(None, description="why that orbit model: with a tolerance, 'cheapest predicted "
                                                        "of N eligible: ...' and the others' reasons")
    candidates: Optional[list[HistoryCandidate]] = Field(None, description="each orbit model examined, as the choice "
                                                                           "saw it")


class History(BaseModel):
    body: str
    dataset: str
    year: list[float] = Field(description="Julian years (365.25 d) from J2000.0 TDB; negative is the past")
    obliquity_deg: list[float] = Field(description="the spin axis from the orbit normal, deg")
    precession_angle_deg: list[float] = Field(description="the equinox's retrograde turn since the pole epoch, "
                                                          "measured on the J2000 ecliptic, unwrapped, deg")
    pole_ra_deg: list[float] = Field(description="ICRF")
    pole_dec_deg: list[float]
    orbit_inclination_deg: list[float] = Field(description="the orbit normal from the J2000 ecliptic pole, deg")
    estimated_error_deg: list[float] = Field(description="the estimate at each epoch, deg")
    obliquity_error_deg: list[float] = Field(description="the estimate of the obliquity alone at each epoch, deg "
                                                         "(docs/long_term.md)")
    meaningful_from_year: Optional[float] = Field(description="before this the history means nothing (neighbouring "
                                                              "solutions part by more than 1 deg), or null; equal "
                                                              "to meaningful_to_year: nowhere")
    meaningful_to_year: Optional[float] = Field(description="after this the history means nothing, or null")
    perturbers: Optional[list[str]] = Perturbers
    model: HistoryModel


class HistoryIn(BaseModel):
    model_config = Finite
    start_year: float = Field(description="Julian years from J2000.0 TDB (negative: the past)")
    stop_year: float = Field(description="Julian years from J2000.0 TDB")
    step_years: float = Field(description="sampling step, Julian years")
    tolerance_mas: Optional[float] = Field(None, gt=0, description="pick the cheapest orbit model whose pole is "
                                                                   "estimated within this many mas of the truth")
    orbit_model: Optional[OrbitModelName] = Field(None, description="secular or nbody (not with tolerance_mas); "
                                                                    "nbody runs within the request's budget")


class OrbitIn(BaseModel):
    """Osculating heliocentric elements, ecliptic and equinox J2000, at ``epoch_jd_tdb``."""
    model_config = Finite
    a_au: float = Field(description="semi-major axis, AU")
    e: float = Field(description="eccentricity, 0 <= e < 1")
    i_deg: float = Field(description="inclination to the ecliptic J2000, deg")
    node_deg: float = Angle("longitude of the ascending node, deg")
    peri_deg: float = Angle("argument of perihelion, deg")
    mean_anomaly_deg: float = Angle("mean anomaly at the epoch, deg")
    epoch_jd_tdb: float = Field(description="epoch of the elements, JD TDB")
    center: CentreName = Field("Sun", description="the body orbited (and torquing): the Sun, the Earth for a "
                                                  "satellite of it, or a centre a family's data adds")
    node_rate_deg_per_year: Optional[float] = Field(
        None, description="a synchronous satellite (rotation period = orbital period): the rate of its orbit's node "
                          "on its Laplace plane, deg per Julian year (negative: regressing); the Laplace plane is the "
                          "plane the elements are referred to (the ecliptic J2000), so i_deg is the orbit's "
                          "inclination to it. The pole is then the Cassini state's (ephem.moon.family)")


class PoleIn(BaseModel):
    """The instantaneous spin axis (positive pole) in the ICRF at ``epoch_jd_tdb``."""
    model_config = Finite
    ra_deg: float = Angle("right ascension, ICRF, deg")
    dec_deg: float = Field(description="declination, ICRF, deg, -90 to 90")
    epoch_jd_tdb: float = 2451545.0


class MomentsIn(BaseModel):
    """Principal moments of inertia A <= B <= C, any common normalisation."""
    model_config = Finite
    A: float
    B: float
    C: float


class TrackIn(BaseModel):
    model_config = Finite
    start: Union[float, str] = Field(description="ISO 8601 (UTC unless a scale follows) or JD TDB")
    stop: Union[float, str] = Field(description="ISO 8601 or JD TDB")
    step_days: float = Field(description="sampling step, days")
    tolerance_mas: Optional[float] = Field(None, gt=0, description="pick the cheapest model whose pole is estimated "
                                                                   "within this many mas of the truth")
    model: Optional[RungName] = Field(None, description="use this model of the family serving the body (not with "
                                                        "tolerance_mas)")
    axis: AxisName = Field("figure", description="the pole to follow: the figure axis (its free wobble counted as an "
                                                 "error), the angular momentum, forced_figure (the figure axis's "
                                                 "forced motion, as the IAU's CIP: the free wobble is polar motion), "
                                                 "or mean_rotation (a synchronous body's mean rotation axis: the "
                                                 "Moon's mean-Earth pole, the IAU's; its figure axis is 78.56″ from "
                                                 "it)")
    free_wobble_phase_deg: Optional[float] = Angle("the figure axis's position angle about the angular momentum at "
                                                   "free_wobble_epoch (north through east), deg: lets the track add "
                                                   "the free wobble", None)
    free_wobble_J_arcsec: Optional[float] = Field(None, ge=0, le=3600, description="the wobble's amplitude, arcsec "
                                                  "(a body of your own has no published one)")
    free_wobble_epoch: Optional[Union[float, str]] = Field(None, description="epoch of the phase (default: the "
                                                           "pole epoch), ISO 8601 or JD TDB")
    rotation_phase_deg: Optional[float] = Angle(RotationPhase, None)
    time_scale: TimeScaleName = Field("utc", description="the scale of the epochs' calendar dates beside jd_tdb: utc "
                                                         "(key utc_iso), tt (tt_iso) or tdb (tdb_iso)")


class UserBody(BaseModel):
    """A body of the user's own; give ``moments`` or ``dynamical_ellipticity``."""
    model_config = ConfigDict(allow_inf_nan=False, extra="forbid", strict=True, json_schema_extra={"examples": [{
        "name": "my-asteroid",
        "orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                  "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
        "pole": {"ra_deg": 309.03, "dec_deg": 42.23, "epoch_jd_tdb": 2451545.0},
        "rotation_period_hours": 5.342,
        "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42},
        "track": {"start": "2020-01-01", "stop": "2030-01-01", "step_days": 10}}]})
    name: str = Field("user body", max_length=100)
    orbit: OrbitIn
    pole: PoleIn
    rotation_period_hours: float
    moments: Optional[MomentsIn] = None
    dynamical_ellipticity: Optional[float] = None
    # JSON Schema counts 22.0 as an integer: an integral float is taken as one; "4" and true stay refused
    order: Optional[Annotated[int, Field(ge=0, le=MAX_ORDER), BeforeValidator(
        lambda v: int(v) if isinstance(v, float) and v.is_integer() else v)]] = Field(
        None, description=f"e-power order of the Hansen coefficients (0 to {MAX_ORDER}); omit for exact")
    track: Optional[TrackIn] = None
    history: Optional[HistoryIn] = None

    def to_body(self) -> Body:
        """The library's :class:`ephem.api.Body` of these fields (its own checks run there)."""
        return Body(name=self.name, orbit=Orbit(**self.orbit.model_dump(), body=self.name),
                    pole=Pole(**self.pole.model_dump(), body=self.name),
                    rotation_period_hours=self.rotation_period_hours,
                    moments=None if self.moments is None else (self.moments.A, self.moments.B, self.moments.C),
                    dynamical_ellipticity=self.dynamical_ellipticity)


class FreeMotion(BaseModel):
    """The torque-free wobble of the figure axis about the angular momentum (ephem.rotation.free_motion)."""
    body: str
    dataset: str
    jd_tdb: list[float]
    utc_iso: Optional[list[str]] = CalendarDates("utc")
    tt_iso: Optional[list[str]] = CalendarDates("tt")
    tdb_iso: Optional[list[str]] = CalendarDates("tdb")
    figure_axis_offset_x_arcsec: list[float] = Field(description="the figure axis from the angular momentum, in "
                                                                 "the plane normal to it, first axis, arcsec")
    figure_axis_offset_y_arcsec: list[float] = Field(description="the same, second axis, arcsec")
    wobble_angle_J_arcsec: list[float] = Field(description="the angle between the angular momentum and the C axis "
                                                           "at each epoch, arcsec")
    andoyer_nu_deg: list[float] = Field(description="Andoyer's angle ν of the angular momentum about the C axis in "
                                                    "the body frame, deg")
    wobble_period_days: float = Field(description="the period of the angular momentum about the C (long-axis "
                                                  "mode: A) axis in the body frame, days")
    precession_period_days: float = Field(description="the mean period of the figure axis about the angular "
                                                      "momentum in space, days")
    mode: Literal["short-axis", "long-axis", "separatrix"]
    method: Literal["exact", "series", "numeric"] = Field(description="the method run (auto: exact)")
    J_arcsec: float = Field(description="the wobble amplitude at start, arcsec")
    moments_over_C: list[float] = Field(description="A/C, B/C, 1", min_length=3, max_length=3)
    cost_ms: float = Field(description="wall time of the computation, ms")


class Batch(BaseModel):
    """Batch answers (ephem.api.batch): one row per input row, in order (docs/batch.md)."""
    columns: list[str] = Field(description="the output columns, in order")
    rows: list[dict] = Field(description="one object per input row: the output columns; a bad row has its reason in "
                                         "`error` and nulls elsewhere, and spoils no other row")
    model: dict


class PrecessionNutation(BaseModel):
    precession: Precession
    nutation: Nutation
    track: Optional[Track] = None
    history: Optional[History] = None


class Health(BaseModel):
    status: Literal["ok"]
    version: str
    datasets: list[str]
