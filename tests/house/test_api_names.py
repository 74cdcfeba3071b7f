"""Every public name of ephem.api resolves on first use in a fresh interpreter (the names load lazily, PEP 562):
a name whose module only some other import happened to load (ephem.base.memo, once the families stopped loading
each other) would fail for the first caller, as the service's import did."""
from __future__ import annotations

import subprocess
import sys


def test_every_public_name_resolves_first_in_a_fresh_interpreter():
    code = ("import importlib, sys\n"
            "names = importlib.import_module('ephem.api').__all__\n"
            "bad = []\n"
            "for name in names:\n"
            "    try:\n"
            "        getattr(sys.modules['ephem.api'], name)\n"
            "    except Exception as exc:\n"
            "        bad.append(f'{name}: {exc!r}')\n"
            "print(len(names)); print('\\n'.join(bad))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    count, *bad = out.strip().splitlines()
    assert int(count) > 50 and not bad, bad


def test_each_name_alone_resolves_first():
    """One interpreter per name, each asked for first: the names of packages' submodules and of the families'
    registry, which no other import is sure to have loaded."""
    import ephem.api as api
    names = list(api.__all__)
    code = ("import sys, ephem.api as a\nbad = []\n"
            "for name in sys.argv[1:]:\n"
            "    try:\n        getattr(a, name)\n    except Exception as exc:\n        bad.append(name)\n"
            "print(' '.join(bad))\n")
    for name in ("memo", "budget", "Budget", "charge", "MODELS", "AXES", "TIME_PATTERN_ECMA", "HistorySpec"):
        out = subprocess.run([sys.executable, "-c", code, name], capture_output=True, text=True, check=True).stdout
        assert out.strip() == "", (name, out)
    assert set(names) >= {"memo", "budget", "MODELS"}
