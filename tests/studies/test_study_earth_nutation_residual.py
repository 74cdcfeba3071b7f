"""The Earth's nutation residual chart (studies.earth_nutation_residual, the chart of docs/earth.md), coarsely.

The numbers it draws are tested in tests/earth/test_against_erfa.py, the rigid series and the non-rigid one (every 2
days, as the committed chart); here the study writes its three files and its summary tells the two series apart.
"""
import ast
import csv

import pytest

from studies import earth_nutation_residual as enr


def test_the_chart_writes_csv_png_svg_and_the_transfer_function_shrinks_the_residual(tmp_path, capsys):
    prefix = str(tmp_path / "residual")
    enr.main([prefix])                                      # python -m studies.earth_nutation_residual PREFIX
    stats = ast.literal_eval(capsys.readouterr().out.strip())   # the printed dict of rms and max, mas
    for ext in ("csv", "png", "svg"):
        assert (tmp_path / f"residual.{ext}").stat().st_size > 0
    with open(prefix + ".csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert float(rows[0]["year"]) == pytest.approx(1900.0, abs=0.01) and float(rows[-1]["year"]) > 2099.9
    # docs/earth.md: rigid 63.2 / 22.3 mas rms, times T 1.80 / 1.68
    assert stats["psi_rms_mas"] == pytest.approx(63.2, abs=0.1) and stats["eps_rms_mas"] == pytest.approx(22.3, abs=0.1)
    assert stats["psi_nonrigid_rms_mas"] == pytest.approx(1.80, abs=0.01)
    assert stats["eps_nonrigid_rms_mas"] == pytest.approx(1.68, abs=0.01)
