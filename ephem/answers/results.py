"""The answers as objects a notebook holds: the contract's dicts, with their table, a plain copy and a short repr.

Every public answer of :mod:`ephem.answers.requests` (and the batch's) is one of these classes: a ``dict`` (the
bodies list a ``list``) subclass holding exactly the keys it held before, so that whatever read the dicts reads them
unchanged -- ``ans["model"]["name"]``, ``json.dumps``, orjson, FastAPI's responses, ``==`` against a plain dict,
pickling, ``copy.deepcopy`` -- and the JSON contract is the same byte for byte. What they add is for a person at a
notebook:

- ``to_qtable()``: the astropy ``QTable`` the ECSV output writes (:func:`ephem.exports.qtable.to_qtable`): Quantity
  columns in the units the keys name, ``jd_tdb`` a TDB ``Time``, the model and the estimate in ``meta``;
  ``to_ecsv()`` the same table as ECSV text. An answer that is not table-shaped (a body's record, the comparison of
  models, a body of the user's own with its several parts) says so, naming where its tables are;
- ``to_dict()``: a plain, deep copy, ready for JSON: nested dicts and lists only, numpy arrays as lists, a
  ``Quantity`` (an answer asked with ``quantities=True``) as its number in the unit its key names, a ``Time`` as its
  JD TDB;
- a short ``repr``: the kind, the body and dataset, the model and the counts (epochs, terms, rows), never the arrays.

The classes add no state of their own (``__slots__ = ()``): an answer is its keys.
"""
from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..base.errors import InvalidInputError
from ..base.units import unit_of
from ..exports.qtable import to_ecsv, to_qtable

if TYPE_CHECKING:
    from astropy.table import QTable


def _loaded(module: str, name: str):
    """``module.name`` if the module is loaded already, else None: a value cannot be an astropy ``Time`` or
    ``Quantity`` unless astropy was imported, so a plain answer never loads it."""
    found = sys.modules.get(module)
    return None if found is None else getattr(found, name, None)


def plain(value: Any, unit: str | None = None) -> Any:
    """A deep copy of an answer's value made of dicts, lists, str, int, float, bool and None only.

    Parameters
    ----------
    value : object
        An answer or part of one: dicts, lists, tuples, numpy arrays and scalars, astropy ``Quantity`` and ``Time``.
    unit : str or None
        The unit a ``Quantity`` found here is given in (the unit its key names, :func:`ephem.base.units.unit_of`);
        None for its own unit's number.

    Returns
    -------
    object
        The same value as JSON reads it: a ``Time`` as its Julian date TDB (days), a ``Quantity`` as its number in
        ``unit``, numpy values as Python numbers.
    """
    if isinstance(value, dict):
        return {k: plain(v, unit_of(k) if isinstance(k, str) and unit_of(k) else unit) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v, unit) for v in value]
    time = _loaded("astropy.time", "Time")
    if time is not None and isinstance(value, time):
        return plain(value.tdb.jd)
    quantity = _loaded("astropy.units", "Quantity")
    if quantity is not None and isinstance(value, quantity):
        return plain(value.to_value(unit) if unit is not None else value.value)
    if isinstance(value, np.ndarray):
        return [plain(v, unit) for v in value.tolist()] if value.dtype == object else value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value


class _Tabled:
    """What every answer adds to its dict (or list): the table, the plain copy, the short repr."""

    __slots__ = ()
    #: the table kind (:data:`ephem.exports.qtable.TABLE_KINDS`), or None for an answer that is no table
    kind: ClassVar[str | None] = None
    #: where the tables of an answer that is no table are, for its error
    no_table: ClassVar[str] = ""

    def to_dict(self) -> Any:
        """The answer as plain Python data, deep-copied and ready for JSON.

        Returns
        -------
        dict or list
            Nested dicts and lists of str, int, float, bool and None, the keys and units of the answer
            (:func:`plain`: arrays as lists, a ``Quantity`` in its key's unit, a ``Time`` as JD TDB).
        """
        return plain(self)

    def to_qtable(self, *, source: str | None = None) -> QTable:
        """The answer as the astropy ``QTable`` the ECSV output writes (:func:`ephem.exports.qtable.to_qtable`).

        Parameters
        ----------
        source : str or None
            Where the answer came from (a URL, a command line), written in the table's ``meta``; default the
            library's function.

        Returns
        -------
        astropy.table.QTable
            Columns as ``Quantity`` in the units their keys name (deg, arcsec, mas, arcsec / yr, d, yr), ``jd_tdb`` a
            TDB ``Time``, a description on every column, the model and the estimate in ``meta``.

        Raises
        ------
        InvalidInputError
            Naming ``answer``, for an answer that is not table-shaped (it says where its tables are).
        """
        if self.kind is None:
            raise InvalidInputError("answer", f"{type(self).__name__} is not table-shaped: {self.no_table}")
        return to_qtable(self, source=source)

    def to_ecsv(self, *, source: str | None = None) -> str:
        """The answer's :meth:`to_qtable` written as ECSV (:func:`ephem.exports.qtable.to_ecsv`).

        Parameters
        ----------
        source : str or None
            Where the answer came from, written in the YAML header.

        Returns
        -------
        str
            The ECSV text (``text/x-ecsv``): the header with each column's unit and description, then the rows.
        """
        if self.kind is None:
            raise InvalidInputError("answer", f"{type(self).__name__} is not table-shaped: {self.no_table}")
        return to_ecsv(self, source=source)

    def _summary(self) -> list[str]:
        return []

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {'; '.join(p for p in self._summary() if p)}>"

    def _repr_pretty_(self, printer, cycle: bool) -> None:     # IPython: the same short text
        printer.text(repr(self))


def _count(values, what: str) -> str:
    n = len(values) if values is not None else 0
    return f"{n} {what}" if n != 1 else f"1 {what[:-1] if what.endswith('s') else what}"


class Answer(_Tabled, dict):
    """An answer: a dict of the contract's keys (units in their names) with :meth:`to_qtable`, :meth:`to_dict` and a
    short repr."""

    __slots__ = ()

    def _who(self) -> str:
        body = self.get("body", self.get("name"))
        dataset = self.get("dataset")
        return f"{body} ({dataset})" if body is not None and dataset else "" if body is None else str(body)

    def _model(self) -> str:
        model = self.get("model")
        if not isinstance(model, dict) or model.get("name") is None:
            return ""
        text = f"model {model['name']}"
        if model.get("order") is not None:
            text += f" order {model['order']}"
        error = model.get("estimated_error_mas")
        if isinstance(error, (int, float)) and not isinstance(error, bool):
            text += f", estimated error {error:.3g} mas"
        elif error is not None and hasattr(error, "value"):     # a Quantity (quantities=True)
            text += f", estimated error {float(error.value):.3g} {error.unit}"
        return text

    def _summary(self) -> list[str]:
        return [self._who(), self._model()]


class BodyRecord(Answer):
    """A body's catalogue record (:func:`ephem.answers.requests.body_record`): every value with its unit, 1-sigma and
    source, the correlations and the interior model."""

    __slots__ = ()
    no_table = "a record of values with units and sources; the catalogue's table is list_bodies().to_qtable()"

    def _summary(self) -> list[str]:
        return [self._who(), _count(self.get("values"), "values")]


class PrecessionAnswer(Answer):
    """The precession answer (:func:`ephem.answers.requests.precession`): obliquity (deg), H_d, K and the precession
    rate (arcsec/yr), each with its 1-sigma; a one-row table."""

    __slots__ = ()
    kind = "precession"

    def _summary(self) -> list[str]:
        rate = self.get("precession_rate_arcsec_per_year")
        rate = f"{rate:.6g} arcsec/yr" if isinstance(rate, float) else ""
        return [self._who(), rate, self._model()]


class NutationAnswer(Answer):
    """The nutation answer (:func:`ephem.answers.requests.nutation`): the terms of the nutation in longitude and in
    obliquity (arcsec); a table of a row per term."""

    __slots__ = ()
    kind = "nutation"

    def _summary(self) -> list[str]:
        return [self._who(), _count(self.get("terms"), "terms"), self._model()]


def _span(values, unit: str) -> str:
    """The first and last of an epoch column, for a repr ('' for none)."""
    if values is None or len(values) == 0:
        return ""
    time = _loaded("astropy.time", "Time")
    if time is not None and isinstance(values, time):
        values = values.tdb.jd
    first, last = (float(getattr(v, "value", v)) for v in (values[0], values[-1]))
    return f"{first:.10g}..{last:.10g} {unit}"


class TrackAnswer(Answer):
    """A spin-axis track (:func:`ephem.answers.requests.track`, ``track_arrays``): psi, the nutation (arcsec), the
    obliquity and the pole (deg) at each epoch (JD TDB); a table of a row per epoch."""

    __slots__ = ()
    kind = "track"

    def _summary(self) -> list[str]:
        epochs = self.get("jd_tdb")
        return [self._who(), _count(epochs, "epochs"), _span(epochs, "JD TDB"), self._model()]


class FreeMotionAnswer(Answer):
    """The torque-free wobble (:func:`ephem.answers.requests.free_motion_answer`, ``free_motion_arrays``): the figure
    axis's offsets from the angular momentum (arcsec) at each epoch; a table of a row per epoch."""

    __slots__ = ()
    kind = "free_motion"

    def _summary(self) -> list[str]:
        epochs = self.get("jd_tdb")
        period = self.get("wobble_period_days")
        period = f"wobble period {float(getattr(period, 'value', period)):.6g} d" if period is not None else ""
        return [self._who(), _count(epochs, "epochs"), _span(epochs, "JD TDB"), period]


class HistoryAnswer(Answer):
    """The spin axis over millennia (:func:`ephem.answers.requests.history`): obliquity, precession angle, pole (deg)
    at each epoch (Julian years from J2000.0 TDB); a table of a row per epoch."""

    __slots__ = ()
    kind = "history"

    def _summary(self) -> list[str]:
        years = self.get("year")
        return [self._who(), _count(years, "epochs"), _span(years, "yr"), self._model()]


class ModelsAnswer(Answer):
    """Speed against accuracy for one request (:func:`ephem.answers.requests.track_models`): every model's estimated
    error (mas) and predicted cost (CPU ms), and the one a tolerance picks."""

    __slots__ = ()
    no_table = "a comparison of models; its rows are ephem.api.track_models_rows(answer), its chart models_chart(answer)"

    def _summary(self) -> list[str]:
        chosen = self.get("chosen")
        epochs = self.get("epochs")
        return [self._who(), _count(self.get("models"), "models"), f"{epochs} epochs" if epochs is not None else "",
                f"chosen {chosen}" if chosen is not None else ""]


class PrecessionNutationAnswer(Answer):
    """The answer for a body of the user's own (:func:`ephem.answers.requests.precession_nutation`): its
    ``precession``, ``nutation`` and, when asked, ``track`` and ``history``, each an answer of its own kind."""

    __slots__ = ()
    no_table = "its parts are: answer['precession'].to_qtable(), answer['nutation'], answer['track'], answer['history']"

    def _summary(self) -> list[str]:
        part = self.get("precession") or {}
        return [str(part.get("body", "")), "parts " + ", ".join(self)]


class BatchAnswer(Answer):
    """The batch answer (:func:`ephem.answers.batches.batch`): a row per input body, the output columns in order;
    a table of a row per body."""

    __slots__ = ()
    kind = "batch"

    def _summary(self) -> list[str]:
        rows = self.get("rows") or []
        failed = sum(1 for r in rows if isinstance(r, dict) and r.get("error"))
        return [_count(rows, "rows"), f"{failed} with an error" if failed else "", _count(self.get("columns"), "columns"),
                self._model()]


class BodiesAnswer(_Tabled, list):
    """The catalogue's bodies (:func:`ephem.answers.requests.list_bodies`): a list of one dict per body (name, NAIF
    id, orbit, period, pole, H_d); a table of a row per body."""

    __slots__ = ()
    kind = "bodies"

    def _summary(self) -> list[str]:
        datasets = sorted({str(r.get("dataset")) for r in self if isinstance(r, dict)})
        names = [str(r.get("name")) for r in self[:4] if isinstance(r, dict)]
        return [_count(self, "bodies"), "dataset " + ", ".join(datasets) if datasets else "",
                ", ".join(names) + (", ..." if len(self) > 4 else "")]
