"""The text of a NAIF text PCK (``KPL/PCK``): its comment block and each body's data block.

The comment block says what was fitted and how well (:mod:`ephem.answers.kernels` describes the kernel)."""
from __future__ import annotations

import math
import textwrap
import unicodedata
import warnings

from ..base.errors import InvalidInputError
from .pck_kernel import FRAME_CODES, BodyFit, jd_text

def _num(x: float) -> str:
    """A kernel number: the shortest repr that reads back to the same double, exponent in upper case."""
    if isinstance(x, int):
        return str(x)
    if not math.isfinite(x):
        raise InvalidInputError("kernel", f"non-finite coefficient {x!r}")  # pragma: no cover - fits are finite
    return repr(float(x)).upper()


def _assign(name: str, values, per_line: int = 2) -> list[str]:
    vals = [_num(v) for v in values]
    head = f"   {name:<27} = ( "
    pad = " " * len(head)
    lines = [(head if i == 0 else pad) + "  ".join(vals[i:i + per_line]) for i in range(0, len(vals), per_line)]
    lines[-1] += " )"
    return lines


def time_text(jd: float, scale: str) -> str:
    from astropy.time import Time
    from erfa import ErfaWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ErfaWarning)     # "dubious year": UTC beyond the leap-second table
        return getattr(Time(jd, format="jd", scale="tdb"), scale).isot + " " + scale.upper()


#: ASCII for the symbols our texts use (a text kernel is ASCII: NAIF, Kernel Required Reading).
_ASCII = {"ψ": "psi", "ε": "eps", "θ": "theta", "Ω": "Omega", "ω": "omega", "Δ": "Delta", "Ψ": "Psi", "φ": "phi",
          "ν": "nu", "μ": "mu", "µ": "u", "π": "pi", "∝": "propto", "″": '"', "′": "'", "°": " deg", "·": "*",
          "×": "x", "−": "-", "–": "-", "—": "--", "≤": "<=", "≥": ">=", "≈": "~", "±": "+-", "²": "^2",
          "³": "^3", "√": "sqrt", "∞": "inf", "…": "...", "‘": "'", "’": "'", "“": '"', "”": '"', "̇": "dot"}


def ascii_text(text: str) -> str:
    """``text`` in printable ASCII and newlines: known symbols spelt out, accents dropped, anything else '?'."""
    out = []
    for ch in text:
        if 32 <= ord(ch) < 127 or ch == "\n":
            out.append(ch)
        elif ch in _ASCII:
            out.append(_ASCII[ch])
        else:
            base = unicodedata.normalize("NFKD", ch).encode("ascii", "ignore").decode("ascii")
            out.append(base if base.isprintable() and base else "?")
    return "".join(out)


def _wrap(text: str, width: int, indent: str) -> list[str]:
    return textwrap.wrap(ascii_text(text), width=width, initial_indent=indent, subsequent_indent=indent)


def comment_lines(fits: list[BodyFit], t0: float, t1: float, generated: str, max_angles: int) -> list[str]:
    L = [
        "Spin-axis orientation from ephem (ephem-asteroid-pn): forced precession and nutation",
        "===========================================================================",
        "",
        f"   Generated:      {generated}",
        f"   Validity span:  {time_text(t0, 'utc')}  to  {time_text(t1, 'utc')}",
        f"                   {time_text(t0, 'tdb')}  to  {time_text(t1, 'tdb')}",
        f"                   {jd_text(t0)}  to  {jd_text(t1)}",
        "",
        "   Outside the span the fit is extrapolated: do not use the kernel there.",
        "",
        "Bodies",
        "--------------------------------------------------------",
        "",
    ]
    for f in fits:
        info = f.model
        est = info.get("estimated_error_mas")
        order = "" if info.get("order") is None else f", e-order {info['order']}"
        L.append(f"   {f.name} (NAIF ID {f.naif_id}), dataset '{f.dataset}'")
        L += _wrap(f"Model: rung '{info.get('name')}'{order} of ephem's fidelity ladder, "
                   f"{info.get('description')}; estimated error "
                   + ("not estimated" if est is None else f"{est:.6g} mas") + " (the model against the truth, "
                   "over the span; see ephem's docs/accuracy.md).", 92, "      ")
        L += _wrap(f"Fit error: {f.fit_error_mas:.4g} mas, the largest angle between this kernel's pole and "
                   f"ephem's track over the span ({f.check_epochs} epochs; rms {f.fit_rms_mas:.3g} mas; aim "
                   f"{f.fit_aim_mas:.4g} mas, limit {f.fit_limit_mas:.4g} mas).", 92, "      ")
        L += _wrap(f"Terms: RA and DEC in {f.frame}; {len(f.angles)} nutation-precession angles in "
                   f"BODY{f.angles_owner}_NUT_PREC_ANGLES: {len(f.terms)} frequencies, each as a pair of angles "
                   f"theta, theta + 90 deg, with theta = (the phase of a nutation term: {f.term_label}) + j Psi, "
                   f"Psi the precession angle (rate psidot = {f.precession_rate_deg_per_day:.6g} deg/day).",
                   92, "      ")
        L += _wrap(f"Prime meridian: {f.pm_source}.", 92, "      ")
        for w in info.get("warnings") or []:
            L += _wrap(f"Note: {w}.", 92, "      ")
        if f.angles_owner != f.naif_id:
            L += _wrap(f"WARNING: SPICE takes this planet's angles (and its reference frame) from the system "
                       f"barycentre's BODY{f.angles_owner}_... variables, which its satellites share in NAIF's "
                       "generic PCKs: loaded after such a PCK this kernel replaces the satellites' angles, and "
                       "loaded before it, its own are replaced. Do not load both.", 92, "      ")
        L.append("")
    L += [
        "Model and conventions",
        "--------------------------------------------------------",
        "",
        "   The pole is ephem's forced precession-nutation track (Kinoshita's theory on ephem's",
        "   fidelity ladder), fitted by linear least squares in the form SPICE evaluates (PCK",
        "   Required Reading; SPICELIB TISBOD):",
        "",
        "      RA  = RA0  + RA1  T + RA2  T**2 + SUM a_i sin(theta_i)     (deg)",
        "      DEC = DEC0 + DEC1 T + DEC2 T**2 + SUM d_i cos(theta_i)     (deg)",
        "      W   = W0   + W1   d                                        (deg)",
        "      theta_i = theta0_i + theta1_i T                            (deg, deg/century)",
        "",
        "   T: Julian centuries of TDB, d: days of TDB, both from J2000 (JD 2451545.0 TDB).",
        "   The pole's frequencies are those of the nutation terms (multiples of the orbital mean",
        "   motion: the argument is the mean anomaly; for the Earth with the Moon, the lunisolar",
        "   series' arguments) offset by multiples of the precession rate psidot: the nutation's",
        "   displacement turns with the pole about the orbit normal.",
        "",
        "   Frame: ephem's poles are ICRF. As in the IAU WGCCRE models of NAIF's generic PCKs, they",
        "   are given as if in SPICE's J2000 frame, which differs from the ICRF by the frame bias",
        "   (about 20 mas, more than the fit error). A pole within 10 deg of the J2000 pole is given",
        "   in ECLIPJ2000 (BODY#_CONSTANTS_REF_FRAME = 17) instead: near a frame's pole RA is a poor",
        "   coordinate. SPICE turns the constants into J2000 itself.",
        "",
        "   Prime meridian: the catalogue gives the rotation period P, not W0; W1 = 360 deg / P (days).",
        "   Each body's entry above says where W0 comes from; the pole does not depend on W.",
        "",
        f"   Angles: at most {max_angles} per body (SPICE toolkits before N0067 hold 100, N0067 200).",
        "   BODY#_MAX_PHASE_DEGREE = 1 states that they are linear in T.",
        "",
        "   Use: furnsh this file; then pxform('J2000', 'IAU_<BODY>', et) or tipbod('J2000', id, et)",
        "   (whose third row is the pole) give the orientation, et = (JD TDB - 2451545.0) * 86400.",
        "",
    ]
    return L


def data_block(f: BodyFit) -> list[str]:
    nid, own = f.naif_id, f.angles_owner
    out = [f"   {f.name}: pole RA, DEC in {f.frame} (deg, deg/century, deg/century**2); prime meridian",
           "   (deg, deg/day, deg/day**2); nutation-precession angles (deg, deg/century).", "",
           "\\begindata", ""]
    out += _assign(f"BODY{own}_CONSTANTS_REF_FRAME", [FRAME_CODES[f.frame]])
    out += _assign(f"BODY{nid}_POLE_RA", f.pole_ra)
    out += _assign(f"BODY{nid}_POLE_DEC", f.pole_dec)
    out += _assign(f"BODY{nid}_PM", f.pm)
    if f.angles:
        out.append("")
        out += _assign(f"BODY{nid}_NUT_PREC_RA", f.nut_prec_ra)
        out += _assign(f"BODY{nid}_NUT_PREC_DEC", f.nut_prec_dec)
        out.append("")
        out += _assign(f"BODY{own}_MAX_PHASE_DEGREE", [1])
        out += _assign(f"BODY{own}_NUT_PREC_ANGLES", [x for pair in f.angles for x in pair])
    out += ["", "\\begintext", ""]
    return out
