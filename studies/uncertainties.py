"""The catalogue's uncertainties as the answers carry them, body by body, and the linear σ against a Monte Carlo.

A study, not the library (see :mod:`studies`): run from the project root as ``python -m studies.uncertainties``.
It prints three Markdown tables for docs/uncertainties.md (*Results*, *Sensitivities*):

* the precession answer's 1σ of every body of the ``current`` dataset (``ephem.api.precession``, whichever theory
  serves it), whether they are complete (every input with a σ) and which inputs carry one;
* for the single-perturber theory's bodies, the linear σ of :func:`ephem.forced.uncertainty.propagate` against
  :func:`ephem.forced.uncertainty.monte_carlo` (N = 1000, seed 0), as ratios MC/linear for ε, ψ̇, Δψ, Δε;
* the sensitivities of ε and ψ̇ to the pole, the period, a and e, for a σ from elsewhere.
"""
from __future__ import annotations

from ephem import api
from ephem.bodies.catalogue import load_catalogue
from ephem.base.errors import NotApplicableError
from ephem.forced.catalogue_sigmas import input_sigmas
from ephem.forced.uncertainty import monte_carlo, propagate

KEYS = ("obliquity_deg", "precession_rate_arcsec_per_year", "dynamical_ellipticity", "scaling_factor_arcsec_per_year")
RATIO_KEYS = ("obliquity_deg", "precession_rate_arcsec_per_year", "delta_psi_half_peak_to_peak_arcsec",
              "delta_epsilon_half_peak_to_peak_arcsec")


def _g(x) -> str:
    return "–" if x is None else f"{x:.3g}"


def answers_table(dataset: str = "current") -> str:
    rows = ["| body | ε (°) | ψ̇ (″/yr) | σ ε (°) | σ ψ̇ (″/yr) | σ H_d | σ K (″/yr) | complete | inputs with σ |",
            "|---|---|---|---|---|---|---|---|---|"]
    for b in load_catalogue(dataset).bodies:
        p = api.precession(b.name, dataset=dataset)
        u = p["uncertainty"]
        with_sigma = sorted(k for k, m in b.values.items() if m.uncertainty is not None and not k.endswith("epoch")
                            and not k.startswith("inertia.derived_from") and k != "rotation.rate")
        rows.append(f"| {b.name} | {p['obliquity_deg']:.2f} | {p['precession_rate_arcsec_per_year']:.4f} | "
                    + " | ".join(_g(p[f"{k}_uncertainty"]) for k in KEYS)
                    + f" | {'yes' if u['complete'] else 'no'} | {', '.join(with_sigma) or 'none'} |")
    return "\n".join(rows)


def monte_carlo_table(dataset: str = "current") -> str:
    rows = ["| body | MC/linear ε, ψ̇, Δψ, Δε |", "|---|---|"]
    for b in load_catalogue(dataset).bodies:
        if not any(s for s in input_sigmas(b).values()):
            continue
        try:
            mc = monte_carlo(b, 1000, 0)
        except NotApplicableError:
            continue
        ratios = [mc["comparison"][k]["ratio"] for k in RATIO_KEYS]
        rows.append(f"| {b.name} | {', '.join('–' if r is None else f'{r:.2f}' for r in ratios)} |")
    return "\n".join(rows)


def sensitivities_table(dataset: str = "current") -> str:
    """∂ε and ∂ψ̇ per catalogue unit of the pole, the period, a and e (the single-perturber theory)."""
    rows = ["| body | ε (°) | ∂ε/∂α | ∂ε/∂δ | ∂ψ̇/∂α (″/yr/°) | ∂ψ̇/∂δ (″/yr/°) | ∂ψ̇/∂P (″/yr/h) | ∂ψ̇/∂a (″/yr/AU) "
            "| ∂ψ̇/∂e (″/yr) |", "|---|---|---|---|---|---|---|---|---|"]
    for b in load_catalogue(dataset).bodies:
        try:
            r = propagate(b)
        except NotApplicableError:
            continue
        se, sp = r["sensitivities"]["obliquity_deg"], r["sensitivities"]["precession_rate_arcsec_per_year"]
        rows.append(f"| {b.name} | {r['values']['obliquity_deg']:.2f} | {se['pole.ra']:.3g} | {se['pole.dec']:.3g} | "
                    + " | ".join(f"{sp[k]:.3g}" for k in ("pole.ra", "pole.dec", "rotation.period", "orbit.a",
                                                           "orbit.e")) + " |")
    return "\n".join(rows)


if __name__ == "__main__":
    print(answers_table())
    print()
    print(monte_carlo_table())
    print()
    print(sensitivities_table())
