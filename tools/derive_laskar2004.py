"""Derive data/laskar2004/: the Earth's and Mars' obliquity and eccentricity histories of Laskar et al. (2004), the
outside references of the long-term spin axis (tests/longterm/test_against_laskar2004.py, docs/long_term.md).

The sources are IMCCE's published solution files (Laskar, Robutel, Joutel, Gastineau, Correia & Levrard 2004,
A&A 428, 261, "A long-term numerical solution for the insolation quantities of the Earth"; Laskar, Correia,
Gastineau, Joutel, Levrard & Robutel 2004, Icarus 170, 343, "Long term evolution and chaotic diffusion of the
insolation quantities of Mars"), distributed at http://vo.imcce.fr/insola/ : per line the time from J2000 in
kyr, the eccentricity, the obliquity (rad) and the longitude of perihelion from the moving equinox (rad). This
script keeps the time, e and the obliquity in degrees over [-3 Myr, +1 Myr] at their 1-kyr step, and records
each source file's SHA-256 in the header (the files are not shipped: 1-4 MB each).

    python tools/derive_laskar2004.py DIR      # DIR holds the IMCCE files named below
"""
from __future__ import annotations

import hashlib
import math
import sys
from pathlib import Path

OUT = Path(__file__).resolve().parent.parent / "data" / "laskar2004"
SPAN_KYR = (-3000.0, 1000.0)
#: output file -> (solution, past file, future file, what the solution is)
FILES = {
    "earth_la2004.csv": ("La2004 Earth", "INSOLN.LA2004.BTL.100.ASC", "INSOLP.LA2004.BTL.ASC",
                         "Laskar et al. 2004, A&A 428, 261: nominal solution, tidal dissipation and climate friction "
                         "as in the paper"),
    "mars_la2004.csv": ("La2004 Mars", "INSOLN.LA2004.MARS.ASC", "INSOLP.LA2004.MARS.ASC",
                        "Laskar et al. 2004, Icarus 170, 343: initial precession rate p = -7.597 arcsec/yr (Yoder et "
                        "al. 2003), k2 = 0.149, Q = 92 (IMCCE README)"),
    "mars_la2003.csv": ("La2003 Mars", "INSOLN.LA2003.MARS.ASC", "INSOLP.LA2003.MARS.ASC",
                        "Laskar et al. 2004's neighbouring solution: p = -7.576 arcsec/yr (Folkner et al. 1997), "
                        "k2 = 0.14, Q = 50; La2004 - La2003 shows the solutions' precision (IMCCE README)"),
}


def rows(path: Path):
    for line in path.read_text().splitlines():
        parts = line.replace("D", "E").split()
        if len(parts) >= 3:
            t = float(parts[0])
            if SPAN_KYR[0] <= t <= SPAN_KYR[1]:
                yield t, float(parts[1]), math.degrees(float(parts[2]))


def main(src: Path) -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for name, (solution, past, future, what) in FILES.items():
        table = {}
        sums = []
        for f in (past, future):
            p = src / f
            sums.append(f"{f} sha256 {hashlib.sha256(p.read_bytes()).hexdigest()}")
            for t, e, eps in rows(p):
                table[t] = (e, eps)
        with open(OUT / name, "w") as fh:
            fh.write(f"# {solution}: {what}\n# from IMCCE's files ({'; '.join(sums)}) by tools/derive_laskar2004.py\n"
                     "# year: Julian years from J2000; eccentricity; obliquity_deg: the spin axis from the orbit "
                     "normal\nyear,eccentricity,obliquity_deg\n")
            for t in sorted(table):
                e, eps = table[t]
                fh.write(f"{t * 1000.0:.0f},{e:.8f},{eps:.7f}\n")


if __name__ == "__main__":
    main(Path(sys.argv[1]))
