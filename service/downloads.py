"""What a download is saved as: one file-name rule for the API's and the web page's tables.

The file names of the service's tables (``Content-Disposition``), and the history's CSV.

A name says the body, the dataset, the table and its layout, and ends with its format's extension
(``vesta_current_nutation_amp-period.md``, ``ceres_current_track.csv``), so that two downloads of different tables
never overwrite each other and a saved file says what it holds (issue 41: the page's downloads were saved as
``nutation``, without an extension, all under one name).
"""
from __future__ import annotations

import csv
import io
import re

#: a format's file extension
EXTENSIONS = {"csv": "csv", "markdown": "md", "latex": "tex", "json": "json", "table-json": "json",
              "svg": "svg", "png": "png", "ecsv": "ecsv"}
#: the history's columns, as its CSV writes them (every array of GET /v1/bodies/{body}/history)
HISTORY_CSV_KEYS = ("year", "obliquity_deg", "precession_angle_deg", "pole_ra_deg", "pole_dec_deg",
                    "orbit_inclination_deg", "estimated_error_deg", "obliquity_error_deg")


def filename(body: str, dataset: str, *what: str, fmt: str) -> str:
    """``<body>_<dataset>_<what…>.<ext>`` in lower case, anything but letters, digits, '-' and '_' as '_'."""
    stem = "_".join([body, dataset, *what]).lower()
    return re.sub(r"[^a-z0-9_-]+", "_", stem).strip("_") + "." + EXTENSIONS[fmt]


def disposition(name: str) -> dict[str, str]:
    """The header that saves a response under ``name``."""
    return {"content-disposition": f'attachment; filename="{name}"'}


def history_csv(answer: dict) -> str:
    """The history answer's arrays as CSV, one header line (the answer's keys, units in them), one row per epoch,
    each number as its shortest repr (it reads back to the same double)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(HISTORY_CSV_KEYS)
    columns = [answer[k] for k in HISTORY_CSV_KEYS]
    writer.writerows([repr(float(c[i])) for c in columns] for i in range(len(answer["year"])))
    return out.getvalue()
