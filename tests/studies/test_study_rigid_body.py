"""The rigid-body study (studies.rigid_body, the tables of docs/rigid_body_study.md): its helpers.

The study itself (rung 5 against rung 7 as ω/n falls) runs in its quick version as chart 4 of
studies.accuracy (tests/studies/test_study_accuracy.py); the rigid body and the error bound are the library's
(tests/forced/test_rigid.py).
"""
import pytest

from studies.rigid_body import StudyRow, threshold_ratio


def test_threshold_ratio_interpolates_log_log():
    rows = [StudyRow("x", r, 0.0, 1.0, 0.0, 1.0 / r, 0.0) for r in (1.0, 5.0, 20.0, 100.0)]
    # figure relative error 1/r crosses 0.1 at r = 10
    assert threshold_ratio(rows) == pytest.approx(10.0, rel=1e-12)   # a log, a division, an exp: a few ε
    assert threshold_ratio(rows, level=2.0) == 1.0      # above the level from the start: the first ratio, copied
