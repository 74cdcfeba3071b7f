"""Every public name of ephem.api and of ephem.host (the hosts' interface) resolves on first use in a fresh interpreter (the names load lazily, PEP 562):
a name whose module only some other import happened to load (ephem.base.memo, once the families stopped loading
each other) would fail for the first caller, as the service's import did."""
from __future__ import annotations

import subprocess
import sys

import pytest

#: each face and the fewest public names it must have
FACES = {"ephem.api": 50, "ephem.host": 8}
#: what a host sets around its answers: in ephem.host, out of the user's face (issue 43)
HOST_ONLY = {"Budget", "budget", "charge", "prepaid", "current_budget", "memo", "warm_up"}


@pytest.mark.parametrize("face", sorted(FACES))
def test_every_public_name_resolves_first_in_a_fresh_interpreter(face):
    code = ("import importlib, sys\n"
            f"names = importlib.import_module({face!r}).__all__\n"
            "bad = []\n"
            "for name in names:\n"
            "    try:\n"
            f"        getattr(sys.modules[{face!r}], name)\n"
            "    except Exception as exc:\n"
            "        bad.append(f'{name}: {exc!r}')\n"
            "print(len(names)); print('\\n'.join(bad))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    count, *bad = out.strip().splitlines()
    assert int(count) >= FACES[face] and not bad, bad


def test_the_hosts_names_are_in_the_hosts_face_alone():
    """The budget, the caches and the warm-up are ephem.host's; the errors a budget raises are in both faces."""
    import ephem.api as api
    import ephem.host as host
    assert HOST_ONLY <= set(host.__all__) and not HOST_ONLY & set(api.__all__)
    errors = {"OverBudgetError", "DeadlineExceededError", "BusyError"}
    assert errors <= set(host.__all__) & set(api.__all__)
    assert all(getattr(api, e) is getattr(host, e) for e in errors)
    with pytest.raises(AttributeError, match="ephem.api"):
        api.warm_up  # noqa: B018


def test_each_name_alone_resolves_first():
    """One interpreter per name, each asked for first: the names of packages' submodules and of the families'
    registry, which no other import is sure to have loaded."""
    import ephem.api as api
    names = list(api.__all__)
    code = ("import sys, ephem.api as a\nbad = []\n"
            "for name in sys.argv[1:]:\n"
            "    try:\n        getattr(a, name)\n    except Exception as exc:\n        bad.append(name)\n"
            "print(' '.join(bad))\n")
    for name in ("MODELS", "AXES", "TIME_PATTERN_ECMA", "HistorySpec", "OverBudgetError"):
        out = subprocess.run([sys.executable, "-c", code, name], capture_output=True, text=True, check=True).stdout
        assert out.strip() == "", (name, out)
    assert set(names) >= {"MODELS", "OverBudgetError"}
    host_code = code.replace("ephem.api", "ephem.host")
    for name in ("memo", "budget", "Budget", "charge", "warm_up"):
        out = subprocess.run([sys.executable, "-c", host_code, name], capture_output=True, text=True,
                             check=True).stdout
        assert out.strip() == "", (name, out)
