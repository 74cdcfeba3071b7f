"""The shared parameter descriptions (ephem.answers.parameters): a name alone in a Parameters section becomes its whole
entry at the function's definition, a name the table has not is refused, and no public answer is left with a bare name."""
from __future__ import annotations

import inspect

import pytest

from ephem import api
from ephem.answers.parameters import PARAMETERS, shared_parameters


def test_a_name_alone_becomes_its_entry_and_others_stay():
    def f(body, step_days, flag):
        """Do.

        Parameters
        ----------
        body
        flag : bool
            Its own text.
        step_days

        Returns
        -------
        None
        """
    doc = inspect.getdoc(shared_parameters(f))
    assert PARAMETERS["body"] in doc and PARAMETERS["step_days"] in doc
    assert "flag : bool\n    Its own text." in doc
    assert doc.index("body :") < doc.index("flag :") < doc.index("step_days :")


def test_a_name_the_table_has_not_is_refused():
    def f(colour):
        """Do.

        Parameters
        ----------
        colour
        """
    with pytest.raises(KeyError, match="colour"):
        shared_parameters(f)


def test_every_public_answer_has_each_entry_in_full():
    for name in api.__all__:
        fn = getattr(api, name)
        if not inspect.isfunction(fn) or not fn.__module__.startswith("ephem.answers."):
            continue
        doc = inspect.getdoc(fn) or ""
        if "Parameters\n----------\n" not in doc:
            continue
        section = doc.split("Parameters\n----------\n", 1)[1].split("\n\n")[0]
        bare = [line for line in section.splitlines() if line.strip() in PARAMETERS]
        assert not bare, f"{name}: {bare}"
