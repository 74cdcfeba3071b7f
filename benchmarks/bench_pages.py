"""The web page's cost over its API answers (issue 31: "a body page renders in the time of its API answer plus a
few milliseconds").

For each body, in one process and one run (ratios, not absolute times): the wall time of GET /bodies/{body}
(the catalogue record, the precession and the nutation, rendered as HTML) against the sum of the three JSON
routes it answers from (GET /v1/bodies/{body}, /precession, /nutation), and a track page (a year at 10 days)
against GET /v1/bodies/{body}/track with the same query; each the median of ``REPS`` requests after one to warm
the caches, through FastAPI's TestClient (no network).

    python benchmarks/bench_pages.py          # prints a table; RESULTS_pages.md keeps a run
"""
from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fastapi.testclient import TestClient  # noqa: E402

from service.app import create_app  # noqa: E402
from service.settings import Settings  # noqa: E402

REPS = 15
BODIES = ("vesta", "itokawa", "earth", "moon")
TRACK = "start=2025-01-01&stop=2026-01-01&step_days=10"


def _median_ms(client: TestClient, urls: list[str]) -> float:
    for u in urls:                                      # warm: the caches the first request builds
        assert client.get(u).status_code == 200, u
    times = []
    for _ in range(REPS):
        t0 = time.perf_counter()
        for u in urls:
            client.get(u)
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def main() -> None:
    with TestClient(create_app(Settings(warm_up=True))) as c:
        print(f"{'body':10s} {'page ms':>9s} {'API ms':>9s} {'page - API':>11s}   "
              f"{'track page':>10s} {'track API':>10s} {'difference':>10s}")
        for b in BODIES:
            page = _median_ms(c, [f"/bodies/{b}"])
            answers = _median_ms(c, [f"/v1/bodies/{b}", f"/v1/bodies/{b}/precession", f"/v1/bodies/{b}/nutation"])
            tpage = _median_ms(c, [f"/bodies/{b}/track?{TRACK}"])
            tapi = _median_ms(c, [f"/v1/bodies/{b}/track?{TRACK}"])
            print(f"{b:10s} {page:9.2f} {answers:9.2f} {page - answers:+11.2f}   {tpage:10.2f} {tapi:10.2f} "
                  f"{tpage - tapi:+10.2f}")


if __name__ == "__main__":
    main()
