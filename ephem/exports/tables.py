"""Nutation tables in the layouts of Petit, Souchay & Lhotka (2014), as CSV, Markdown, LaTeX or JSON.

Two layouts, each a pair of tables (longitude, obliquity):

* ``sin-cos`` (the paper's Tables 5-8): Sin, Cos, Amp (arcsec), Period (years), Arg. As in the
  paper Amp is the amplitude of the pole's displacement on the sky, the answer's ``*_amplitude_arcsec``: in
  longitude sqrt(Sin² + Cos²) · sin ε (Δψ sin ε, where Δψ runs along the ecliptic) or sqrt(Sin² + Cos²) where
  the theory's Δψ is already a displacement (the Moon's σ: Δψ), in obliquity sqrt(Sin² + Cos²) (Δε).
* ``amp-period`` (Tables 9-10): Amp (mas) and Period (days), the same amplitudes.

Every header names its quantity (``Δψ Sin (")``, ``Amp Δψ sin ε (mas)``, ``Amp Δε (mas)``), and the CSV and JSON
rows say it in ``amp_of`` (the answer's ``amplitude_quantities``), so that a table and the answer it came from are
compared quantity for quantity.

Arg is the multiple of the body's mean anomaly M; for the Earth's lunisolar series (terms with
``delaunay_multipliers``) it is their integer combination of the Delaunay arguments, written "2F−2D+2Ω"
in Markdown and LaTeX and given as the five columns l, l', F, D, Omega (in that order: IERS 2010
eq. 5.43) in CSV and JSON, which then have no ``multiple`` column. Input: the answer of :func:`ephem.answers.requests.nutation`
(with ``*_uncertainty`` keys on its terms when the catalogue's uncertainties were propagated: they
become ± columns). :func:`render_nutation` gives the text; :func:`write_tables` writes a set of
bodies at once. Every format is rendered from the same rows (:func:`table_rows`), so they carry
the same numbers (tests/exports/test_tables.py parses each back).
"""
from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path
from typing import Callable, Iterable

from ..base.errors import InvalidInputError
from ..orbit.lunar import DELAUNAY_NAMES

FORMATS = {"csv": "text/csv; charset=utf-8", "markdown": "text/markdown; charset=utf-8",
           "latex": "application/x-latex; charset=utf-8", "json": "application/json"}
EXTENSIONS = {"csv": "csv", "markdown": "md", "latex": "tex", "json": "json"}
LAYOUTS = ("sin-cos", "amp-period")
COMPONENTS = ("longitude", "obliquity")

#: (key, header, LaTeX header) of each layout's numeric columns, then the argument; ``{sym}`` is the component's
#: symbol (Δψ, Δε) and ``{amp}`` the quantity its Amp is (Δψ sin ε, Δψ, Δε), each in its table's own script
_COLUMNS = {
    "sin-cos": [("sin_arcsec", "{sym} Sin (\")", r"{sym} Sin ($''$)"), ("cos_arcsec", "{sym} Cos (\")", r"{sym} Cos ($''$)"),
                ("amp_arcsec", "Amp {amp} (\")", r"Amp {amp} ($''$)"), ("period_years", "Period (year)", "Period (year)")],
    "amp-period": [("amp_mas", "Amp {amp} (mas)", "Amp {amp} (mas)"), ("period_days", "Per (days)", "Per (days)")],
}
#: each component's symbol, and the quantity its amplitude is unless the answer says otherwise
SYMBOLS = {"longitude": "Δψ", "obliquity": "Δε"}
DEFAULT_AMPLITUDE_OF = {"longitude": "Δψ sin ε", "obliquity": "Δε"}
_LATEX_SYMBOLS = (("Δψ", r"$\Delta\psi$"), ("Δε", r"$\Delta\varepsilon$"), ("sin ε", r"$\sin\varepsilon$"))
_PAPER_TABLES = {"sin-cos": "Tables 5-8", "amp-period": "Tables 9-10"}
#: digits after the decimal point, as printed in the paper
_DIGITS = {"sin-cos": 4, "amp-period": {"amp_mas": 2, "period_days": 4}}


def _check(layout: str, fmt: str | None = None) -> None:
    if layout not in LAYOUTS:
        raise InvalidInputError("layout", f"must be one of {', '.join(LAYOUTS)}, got {layout!r}")
    if fmt is not None and fmt not in FORMATS:
        raise InvalidInputError("format", f"must be one of {', '.join(FORMATS)}, got {fmt!r}")


def _arg(k: int) -> str:
    return "M" if k == 1 else f"{k}M"


#: The Delaunay multipliers' symbols in Markdown and LaTeX (their CSV and JSON columns are DELAUNAY_NAMES).
_DELAUNAY_SYMBOLS = ("l", "l′", "F", "D", "Ω")
_DELAUNAY_LATEX = ("l", "l'", "F", "D", r"\Omega")


def delaunay_arg(multipliers, latex: bool = False) -> str:
    """The argument k·(l, l′, F, D, Ω) as text: [0, 0, 2, -2, 2] -> "2F−2D+2Ω" (LaTeX: "$2F-2D+2\\Omega$")."""
    symbols, minus = (_DELAUNAY_LATEX, "-") if latex else (_DELAUNAY_SYMBOLS, "−")
    parts = []
    for k, name in zip(multipliers, symbols):
        k = int(k)
        if k == 0:
            continue
        sign = minus if k < 0 else ("+" if parts else "")
        parts.append(f"{sign}{'' if abs(k) == 1 else abs(k)}{name}")
    text = "".join(parts) or "0"
    return f"${text}$" if latex else text


def amplitude_of(answer: dict, comp: str) -> str:
    """The quantity the component's Amp is ("Δψ sin ε", "Δψ", "Δε"): the answer's ``amplitude_quantities`` (the
    theory's own word), else the paper's."""
    return (answer.get("amplitude_quantities") or {}).get(f"{comp}_amplitude_arcsec", DEFAULT_AMPLITUDE_OF[comp])


def headers(answer: dict, comp: str, layout: str, latex: bool = False) -> list[str]:
    """The numeric columns' headers of one table, each naming its quantity (``Δψ Sin (")``, ``Amp Δψ sin ε (mas)``)."""
    sym, amp = SYMBOLS[comp], amplitude_of(answer, comp)
    if latex:
        for plain, tex in _LATEX_SYMBOLS:
            sym, amp = sym.replace(plain, tex), amp.replace(plain, tex)
        amp = amp.replace("$ $", " ")           # "$\Delta\psi$ $\sin\varepsilon$" reads as one product
    return [(tex if latex else label).format(sym=sym, amp=amp) for _, label, tex in _COLUMNS[layout]]


def _is_delaunay(answer: dict) -> bool:
    return any(t.get("delaunay_multipliers") is not None for t in answer["terms"])


def table_rows(answer: dict, layout: str = "sin-cos") -> list[dict]:
    """Rows of both tables of a layout: ``component``, ``multiple``, ``arg``, the layout's columns and, where
    the answer carries them, their 1-σ uncertainties (``<column>_uncertainty``)."""
    _check(layout)
    eps = math.radians(answer["obliquity_deg"])
    sin_eps = math.sin(eps)
    rows = []
    for comp in COMPONENTS:
        for t in answer["terms"]:
            s, c = t[f"{comp}_sin_arcsec"], t[f"{comp}_cos_arcsec"]
            # the pole's displacement as the theory gives it (the Moon's Δψ = σ is one already), else the paper's
            amp = t.get(f"{comp}_amplitude_arcsec")
            if amp is None:
                amp = math.hypot(s, c) * (abs(sin_eps) if comp == "longitude" else 1.0)
            if t.get("delaunay_multipliers") is not None:
                k = [int(v) for v in t["delaunay_multipliers"]]
                row = {"component": comp, "arg": delaunay_arg(k), **dict(zip(DELAUNAY_NAMES, k))}
            else:
                row = {"component": comp, "multiple": int(t["multiple"]), "arg": _arg(int(t["multiple"]))}
            sig_amp = t.get(f"{comp}_amplitude_arcsec_uncertainty")
            row["amp_of"] = amplitude_of(answer, comp)
            if layout == "sin-cos":
                row.update(sin_arcsec=s, cos_arcsec=c, amp_arcsec=amp, period_years=t["period_years"])
                for key in ("sin", "cos"):
                    if f"{comp}_{key}_arcsec_uncertainty" in t:
                        row[f"{key}_arcsec_uncertainty"] = t[f"{comp}_{key}_arcsec_uncertainty"]
                if f"{comp}_amplitude_arcsec_uncertainty" in t:
                    row["amp_arcsec_uncertainty"] = sig_amp
            else:
                row.update(amp_mas=amp * 1e3, period_days=t["period_days"])
                if f"{comp}_amplitude_arcsec_uncertainty" in t:
                    row["amp_mas_uncertainty"] = None if sig_amp is None else sig_amp * 1e3
            rows.append(row)
    return rows


def caption(answer: dict, comp: str, layout: str = "sin-cos", sigma: bool = False) -> str:
    """The table's caption: what, which body and dataset, ε, how Amp is formed."""
    what = "longitude" if comp == "longitude" else "obliquity"
    quantity = amplitude_of(answer, comp)
    formed = "(Sin² + Cos²)^½ sin ε" if quantity.endswith("sin ε") else "(Sin² + Cos²)^½"
    shift = "" if quantity != "Δψ" else ", Δψ being already the pole's displacement"
    if layout == "sin-cos":
        amp = f"Amp = {quantity} = {formed}{shift}"
        lead = f"Nutation in {what}"
    else:
        amp = f"Amp {quantity} = {formed}{shift}; periods in days"
        lead = f"Amplitude of the nutation in {what} {quantity}"
    return (f"{lead} for {answer['body']} ({answer['dataset']} dataset, ε = {answer['obliquity_deg']:.4f}°; "
            f"{amp}; argument: "
            + ("integer combinations of the Delaunay arguments l, l′, F, D, Ω (IERS 2010 eq. 5.43); "
               if _is_delaunay(answer) else "multiples of the mean anomaly M; ")
            + (f"± 1σ from the catalogue's uncertainties, where it gives them{_lower_bound(answer)}; " if sigma else "")
            + f"layout of Petit et al. 2014 {_PAPER_TABLES[layout]})")


def _lower_bound(answer: dict) -> str:
    """Where the terms' σ leave out inputs without one (the answer's ``uncertainty.lower_bounds``): that they are
    lower bounds, and why."""
    why = ((answer.get("uncertainty") or {}).get("lower_bounds") or {}).get("terms")
    return f", lower bounds ({why})" if why else ""


def _digits(layout: str, key: str, digits: int | None) -> int:
    if digits is not None:
        return digits
    d = _DIGITS[layout]
    return d if isinstance(d, int) else d[key]


def _has_sigma(rows: list[dict], key: str) -> bool:
    return any(f"{key}_uncertainty" in r for r in rows)


def _cell(row: dict, key: str, places: int, latex: bool = False) -> str:
    value = f"{row[key]:.{places}f}"
    sigma = row.get(f"{key}_uncertainty")
    if sigma is None:           # unknown (no input with a published σ moves it)
        return value
    pm = r" $\pm$ " if latex else " ± "
    # a σ below the printed digits is shown with two significant digits, not as a misleading "± 0.00"; a value
    # and σ that both vanish at these digits (a coefficient that is zero but for rounding) show the value alone
    half_unit = 0.5 * 10.0 ** -places
    if sigma < half_unit and abs(row[key]) < half_unit:
        return value
    shown = f"{sigma:.{places}f}" if sigma >= half_unit else f"{sigma:.1e}"
    return value + pm + shown


_LATEX_SPECIAL = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
                  "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}


def latex_escape(text: str) -> str:
    """Text with LaTeX's special characters escaped (body names are user input)."""
    return "".join(_LATEX_SPECIAL.get(ch, ch) for ch in text)


def _latex_caption(answer: dict, comp: str, layout: str, sigma: bool) -> str:
    text = latex_escape(caption(answer, comp, layout, sigma)).replace("±", r"$\pm$").replace("σ", r"$\sigma$")
    for plain, tex in (("MR²", r"MR$^2$"), ("ε", r"$\varepsilon$"), ("°", r"$^\circ$"), ("l′", r"$l'$"), ("Ω", r"$\Omega$"), ("Δψ", r"$\Delta\psi$"), ("Δε", r"$\Delta\varepsilon$"),
                       ("(Sin² + Cos²)\\textasciicircum{}½", r"$(\mathrm{Sin}^2 + \mathrm{Cos}^2)^{1/2}$")):
        text = text.replace(plain, tex)
    return text


def render_nutation(answer: dict, fmt: str, digits: int | None = None, layout: str = "sin-cos") -> str:
    """The nutation answer as ``csv``, ``markdown``, ``latex`` (booktabs, two ``table`` floats ready for
    ``\\input``) or ``json`` text in the given layout. ``digits``: places after the point (default as
    printed in the paper); CSV and JSON carry full precision.

    Parameters
    ----------
    answer : dict
        A nutation answer (:func:`ephem.api.nutation`): its terms' coefficients in arcseconds, periods in days.
    fmt : str
        One of :data:`FORMATS`: "csv", "markdown", "latex" or "json".
    digits : int or None
        Decimal places of the coefficients (arcsec) in the markdown and LaTeX tables; None: as Petit et al. (2014)
        print them.
    layout : str
        One of :data:`LAYOUTS`: "sin-cos" (the sine and cosine coefficients of each term, arcsec) or "amp-period"
        (each term's amplitude, arcsec, and period, days).

    Returns
    -------
    str
        The table's text, as a file of that format holds it.
    """
    _check(layout, fmt)
    rows = table_rows(answer, layout)
    columns = _COLUMNS[layout]
    sigma = any(v is not None for r in rows for k, v in r.items() if k.endswith("_uncertainty"))
    if fmt == "csv":
        keys = ["component", "arg", *DELAUNAY_NAMES] if _is_delaunay(answer) else ["component", "multiple", "arg"]
        for key, *_ in columns:
            keys.append(key)
            if _has_sigma(rows, key):
                keys.append(f"{key}_uncertainty")
        keys.append("amp_of")           # the quantity each row's amp is (Δψ sin ε, Δε)
        buf = io.StringIO()
        writer = csv.DictWriter(buf, fieldnames=keys, lineterminator="\n", extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
        return buf.getvalue()
    if fmt == "json":
        tables = []
        for comp in COMPONENTS:
            part = [{k: v for k, v in r.items() if k != "component"} for r in rows if r["component"] == comp]
            tables.append({"component": comp, "caption": caption(answer, comp, layout, sigma), "rows": part})
        return json.dumps({"body": answer["body"], "dataset": answer["dataset"], "layout": layout,
                           "obliquity_deg": answer["obliquity_deg"], "tables": tables}, indent=1) + "\n"
    blocks = []
    for comp in COMPONENTS:
        part = [r for r in rows if r["component"] == comp]
        latex = fmt == "latex"
        cells = [[_cell(r, key, _digits(layout, key, digits), latex) for key, *_ in columns] for r in part]
        if fmt == "markdown":
            head = headers(answer, comp, layout) + ["Arg"]
            lines = [f"**{caption(answer, comp, layout, sigma)}**", "", "| " + " | ".join(head) + " |",
                     "|" + "---:|" * len(columns) + ":---|"]
            lines += ["| " + " | ".join(c + [r["arg"]]) + " |" for c, r in zip(cells, part)]
        else:
            head = headers(answer, comp, layout, latex=True) + ["Arg"]
            lines = [r"\begin{table}", r"\centering", rf"\caption{{{_latex_caption(answer, comp, layout, sigma)}}}",
                     r"\begin{tabular}{" + "r" * len(columns) + "l}", r"\toprule", " & ".join(head) + r" \\",
                     r"\midrule"]
            lines += [" & ".join(c + [delaunay_arg([r[k] for k in DELAUNAY_NAMES], latex=True) if "l" in r
                                      else r["arg"].replace("M", r"$M$")]) + r" \\" for c, r in zip(cells, part)]
            lines += [r"\bottomrule", r"\end{tabular}", r"\end{table}"]
        blocks.append("\n".join(lines))
    return "\n\n".join(blocks) + "\n"


def write_tables(answers: Iterable[dict], out_dir: Path, formats: Iterable[str] = ("csv", "markdown", "latex", "json"),
                 layouts: Iterable[str] = LAYOUTS, progress: Callable[[str], None] | None = None) -> list[Path]:
    """Write every (answer, layout, format) table into ``out_dir`` as ``<body>_<dataset>_<layout>.<ext>``;
    returns the paths. ``progress`` is called with each file name as it is written.

    Parameters
    ----------
    answers : iterable of dict
        Nutation answers (:func:`ephem.api.nutation`), one per body and dataset.
    out_dir : Path
        The directory the files go to (made if missing).
    formats : iterable of str
        The formats to write, of :data:`FORMATS`.
    layouts : iterable of str
        The layouts to write, of :data:`LAYOUTS`.
    progress : callable or None
        Called with each file's name once it is written; None: nothing is told.

    Returns
    -------
    list of Path
        The files written, in the order written.
    """
    formats, layouts = list(formats), list(layouts)
    for layout in layouts:
        _check(layout)
    for fmt in formats:
        _check(LAYOUTS[0], fmt)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for answer in answers:
        stem = f"{answer['body'].lower().replace(' ', '_')}_{answer['dataset']}"
        for layout in layouts:
            for fmt in formats:
                path = out / f"{stem}_{layout}.{EXTENSIONS[fmt]}"
                path.write_text(render_nutation(answer, fmt, layout=layout), encoding="utf-8")
                written.append(path)
                if progress is not None:
                    progress(path.name)
    return written
