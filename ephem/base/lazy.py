"""The faces' lazy names: each public name loads its own module on first use (PEP 562).

The faces :mod:`ephem.api` and :mod:`ephem.host` each keep their table of ``name -> (module relative to ephem,
attribute)`` and their ``__all__``; this module gives them the ``__getattr__`` and ``__dir__`` that load a name's
module on its first access and keep the value in the face's namespace, so that importing a face loads nothing but
this module (the CLI's start-up, benchmarks/RESULTS_cli.md).
"""
from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, MutableMapping, Sequence


def lazy_names(face: str, namespace: MutableMapping[str, object], names: Mapping[str, tuple[str, str]],
               public: Sequence[str]) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of the face ``face`` (its module name, for the error), whose globals are
    ``namespace``: a name of ``names`` loads ``(module relative to ephem, attribute)`` on its first access, once (the
    value is kept in ``namespace``, so later lookups are ordinary); an attribute that its package has not imported
    yet is taken as a submodule (``memo``); any other name raises AttributeError. ``__dir__`` lists the loaded
    globals and ``public`` (the face's ``__all__``)."""

    def __getattr__(name: str):
        try:
            module, attribute = names[name]
        except KeyError:
            raise AttributeError(f"module {face!r} has no attribute {name!r}") from None
        package = importlib.import_module(module, "ephem")
        try:
            value = getattr(package, attribute)
        except AttributeError:   # a submodule (memo) that nothing has imported yet
            value = importlib.import_module(f"{module}.{attribute}", "ephem")
        namespace[name] = value      # once: later lookups are ordinary
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(public))

    return __getattr__, __dir__
