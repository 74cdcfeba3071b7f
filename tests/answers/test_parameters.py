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


def test_a_familys_own_entries_stand_instead_of_the_shared_ones():
    """``own`` entries (a plot's span, in years for a history) replace the shared entry of that name for the
    functions that give them, written once; the other names still come from the shared table."""
    from ephem.answers import figures
    from ephem.answers.parameters import PARAMETERS, entries, shared_parameters

    own = entries("start, stop : float\n    Years.\n")

    @shared_parameters(own=own)
    def f(start, stop, body):
        """F.

        Parameters
        ----------
        start, stop
        body
        """

    assert "start, stop : float\n            Years." in f.__doc__ and PARAMETERS["body"].split("\n")[0] in f.__doc__
    assert PARAMETERS["start, stop"].split("\n")[1].strip() not in f.__doc__
    for fn in (figures.plot_request, figures.render):
        assert "for ``obliquity-history``" in fn.__doc__ and "at most :data:`MAX_PLOT_POINTS` epochs" in fn.__doc__
