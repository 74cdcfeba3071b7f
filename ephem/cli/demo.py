"""``ephem demo``: a short tour of the theory, printed as text tables.

The precession of every body of a dataset and one body's nutation.
"""
from __future__ import annotations

import typer

from .common import DatasetOpt, app, fail, rows_to_table


#: the columns of the demo's nutation table: the paper's (Petit et al. Tables 5-8) and the amplitudes; the sigmas,
#: ~1e-5 arcsec, would print as 0 at its four decimals (``ephem nutation BODY --format table`` gives them)
DEMO_NUTATION_COLUMNS = ("multiple", "period_days", "period_years", "longitude_sin_arcsec", "longitude_cos_arcsec",
                         "obliquity_sin_arcsec", "obliquity_cos_arcsec", "longitude_amplitude_arcsec",
                         "obliquity_amplitude_arcsec")


@app.command()
def demo(dataset: str = DatasetOpt):
    """A short tour: precession of every body of the dataset (the Moon: its Cassini state), and Vesta's
    nutation (in a dataset without Vesta, its first body whose series is in harmonics of the mean anomaly)."""
    from .. import api

    try:
        bodies = [b["name"] for b in api.list_bodies(dataset=dataset)]
    except api.EphemError as exc:
        fail(exc, api.NotApplicableError)
    typer.echo(f"Precession rates ({dataset} dataset)")
    rows = []
    for name in bodies:
        try:
            p = api.precession(name, dataset=dataset)
            rows.append({"body": name, "obliquity_deg": round(p["obliquity_deg"], 4),
                         "H_d": round(p["dynamical_ellipticity"], 6),
                         "K_arcsec_per_yr": round(p["scaling_factor_arcsec_per_year"], 4),
                         "psi_dot_arcsec_per_yr": round(p["precession_rate_arcsec_per_year"], 4)})
        except api.NotApplicableError as exc:
            rows.append({"body": name, "obliquity_deg": "-", "H_d": "-", "K_arcsec_per_yr": "-",
                         "psi_dot_arcsec_per_yr": f"not applicable ({exc.reason})"})
        except api.EphemError as exc:       # a user's dataset: a body the catalogue took but an answer refuses
            rows.append({"body": name, "obliquity_deg": "-", "H_d": "-", "K_arcsec_per_yr": "-",
                         "psi_dot_arcsec_per_yr": f"error ({exc})"})
    typer.echo(rows_to_table(rows))
    # Vesta's, as the paper's; a user's dataset may not hold it. The Earth's and the Moon's series are in the
    # Delaunay arguments, not in harmonics of the mean anomaly: not what the title says.
    for name in sorted(bodies, key=lambda n: n.lower() != "vesta"):
        try:
            terms = api.nutation(name, dataset=dataset)["terms"][:6]
        except api.EphemError:          # its row above says why
            continue
        if terms and all(t.get("multiple") is not None for t in terms):
            break
    else:
        typer.echo("No body of this dataset has a nutation series in harmonics of the mean anomaly.")
        return
    typer.echo(f"Nutation of {name} (arcsec), harmonics of the mean anomaly")
    typer.echo(rows_to_table([{k: (round(t[k], 4) if isinstance(t[k], float) else t[k]) for k in DEMO_NUTATION_COLUMNS}
                               for t in terms]))
