"""Nutation tables in the layout of Petit et al. (2014) Tables 5-8: Sin, Cos, Amp, Period, Arg.

One table for the longitude, one for the obliquity. As in the paper, the longitude's Amp is
sqrt(Sin² + Cos²) · sin ε (the pole's displacement on the sky) and the obliquity's is
sqrt(Sin² + Cos²); periods in years; Arg the multiple of the mean anomaly M. Input: the answer of
:func:`ephem.api.nutation`. Output: CSV, Markdown or LaTeX (booktabs) text.
"""
from __future__ import annotations

import csv
import io
import math

FORMATS = {"csv": "text/csv; charset=utf-8", "markdown": "text/markdown; charset=utf-8",
           "latex": "application/x-latex; charset=utf-8"}


def nutation_rows(answer: dict) -> list[dict]:
    """Rows (component, Sin, Cos, Amp, Period, Arg) of both tables, arcsec and years."""
    sin_eps = math.sin(math.radians(answer["obliquity_deg"]))
    rows = []
    for comp, key in (("longitude", "longitude"), ("obliquity", "obliquity")):
        for t in answer["terms"]:
            s, c = t[f"{key}_sin_arcsec"], t[f"{key}_cos_arcsec"]
            amp = math.hypot(s, c) * (sin_eps if comp == "longitude" else 1.0)
            k = t["multiple"]
            rows.append({"component": comp, "sin_arcsec": s, "cos_arcsec": c, "amp_arcsec": amp,
                         "period_years": t["period_years"], "arg": "M" if k == 1 else f"{k}M"})
    return rows


def _caption(answer: dict, comp: str) -> str:
    what = "longitude" if comp == "longitude" else "obliquity"
    amp = "Amp = (Sin² + Cos²)^½ sin ε" if comp == "longitude" else "Amp = (Sin² + Cos²)^½"
    return (f"Nutation in {what} for {answer['body']} ({answer['dataset']} dataset, ε = "
            f"{answer['obliquity_deg']:.4f}°; {amp}; argument: multiples of the mean anomaly M)")


def render_nutation(answer: dict, fmt: str, digits: int = 4) -> str:
    """The nutation answer as ``csv``, ``markdown`` or ``latex`` text."""
    rows = nutation_rows(answer)
    if fmt == "csv":
        buf = io.StringIO()
        w = csv.DictWriter(buf, fieldnames=list(rows[0]) if rows else
                           ["component", "sin_arcsec", "cos_arcsec", "amp_arcsec", "period_years", "arg"],
                           lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
        return buf.getvalue()
    f = f"{{:.{digits}f}}"
    blocks = []
    for comp in ("longitude", "obliquity"):
        part = [r for r in rows if r["component"] == comp]
        cells = [[f.format(r["sin_arcsec"]), f.format(r["cos_arcsec"]), f.format(r["amp_arcsec"]),
                  f.format(r["period_years"]), r["arg"]] for r in part]
        if fmt == "markdown":
            lines = [f"**{_caption(answer, comp)}**", "",
                     "| Sin (\") | Cos (\") | Amp (\") | Period (year) | Arg |", "|---:|---:|---:|---:|:---|"]
            lines += ["| " + " | ".join(c) + " |" for c in cells]
            blocks.append("\n".join(lines))
        elif fmt == "latex":
            caption = _caption(answer, comp).replace("ε", r"$\varepsilon$").replace("°", r"$^\circ$") \
                .replace("(Sin² + Cos²)^½", r"$(\mathrm{Sin}^2 + \mathrm{Cos}^2)^{1/2}$")
            lines = [r"\begin{table}", r"\centering", rf"\caption{{{caption}}}",
                     r"\begin{tabular}{rrrrl}", r"\toprule",
                     r"Sin ($''$) & Cos ($''$) & Amp ($''$) & Period (year) & Arg \\", r"\midrule"]
            lines += [" & ".join(c[:4] + [c[4].replace("M", r"$M$")]) + r" \\" for c in cells]
            lines += [r"\bottomrule", r"\end{tabular}", r"\end{table}"]
            blocks.append("\n".join(lines))
        else:
            raise ValueError(f"unknown table format {fmt!r}; choose from {', '.join(FORMATS)}")
    return "\n\n".join(blocks) + "\n"
