"""The cost model's structure (ephem.theory.cost, data/cost_model.toml, and each family's costs module and table):
every unit used and every unit read present,
each CPU unit with its measurement, and the predictions' dependence on what a process keeps (cold against warm).

No timing here: benchmarks/bench_calibration.py holds the predictions to the measured CPU (RESULTS_calibration.md).
"""
from __future__ import annotations

import ast
import importlib
import itertools
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ephem.base.paths import data_dir
from ephem.bodies.catalogue import Body, Orbit, Pole, get_body
from ephem.families import FAMILIES
from ephem.forced import pole_uncertainty, uncertainty
from ephem.forced.precession_nutation import cached_model
from ephem.orbit import de421, hansen
from ephem.sun.ladder import Ladder
from ephem.theory import cost

ROOT = Path(__file__).resolve().parents[2]
COST_PY = ROOT / "ephem" / "theory" / "cost.py"
J2000 = 2451545.0
_serial = itertools.count()


def _predictors() -> dict[Path, str]:
    """Each module of predictors and the table of data/ it reads: ephem/theory/cost.py the shared cost_model.toml, each
    family's costs module (beside the family the registry names) its own ``TABLE``."""
    found = {COST_PY: "cost_model.toml"}
    for family in FAMILIES:
        module = family.module.rsplit(".", 1)[0] + ".costs"
        path = ROOT / Path(*module.split(".")).with_suffix(".py")
        if path.exists():
            found[path] = importlib.import_module(module).TABLE
    return found


def _toml_units(table: str = "cost_model.toml") -> dict:
    return tomllib.loads((data_dir() / table).read_text(encoding="utf-8"))["unit"]


def _calls(path: Path, name: str) -> set[str]:
    """The literal unit names of the ``name(...)`` calls of ``path`` (``_u("a" if x else "b")``: both)."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == name:
            arg = node.args[0]
            if isinstance(arg, ast.Constant):
                names.add(arg.value)
            elif isinstance(arg, ast.IfExp):
                names |= {a.value for a in (arg.body, arg.orelse) if isinstance(a, ast.Constant)}
    return names


def _units_read() -> dict[str, set[str]]:
    """The unit names each table's predictors read: a module's ``_u(...)`` its own table's, a family's ``unit(...)``
    the shared table's, and the values of SERIALISATIONS."""
    reads = {table: set() for table in _predictors().values()}
    for path, table in _predictors().items():
        reads[table] |= _calls(path, "_u")
        reads["cost_model.toml"] |= _calls(path, "unit")
    reads["cost_model.toml"] |= set(cost.SERIALISATIONS.values())
    return reads


def test_each_family_prices_its_own_work():
    """The Earth's and the Moon's predictors and units are their own (issue 43), each table read by one module."""
    tables = list(_predictors().values())
    assert {"cost_model.toml", "earth_costs.toml", "moon_costs.toml"} <= set(tables)
    assert len(set(tables)) == len(tables)


def test_every_unit_in_the_toml_is_used_by_a_predictor():
    for table, read in _units_read().items():
        unused = set(_toml_units(table)) - read
        assert not unused, f"units no predictor reads in data/{table}: {sorted(unused)}"


def test_every_unit_a_predictor_reads_is_in_the_toml():
    for table, read in _units_read().items():
        missing = read - set(_toml_units(table))
        assert not missing, f"units the predictors read that data/{table} lacks: {sorted(missing)}"
    # and each read goes through _u or unit with a literal name (a computed name would escape both checks)
    for path in _predictors():
        computed = [n for n in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
                    if isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id in ("_u", "unit")
                    and not isinstance(n.args[0], (ast.Constant, ast.IfExp, ast.Subscript))]
        assert not computed, path


def test_only_the_predictors_read_the_unit_costs():
    """The units are the predictors' (one place to calibrate each): no other module of the library reads a table."""
    reads = re.compile(r"unit_costs\(\)|unit_table\(|read_toml\([^)]*cost|\"cost_model\.toml\"|_costs\.toml")
    readers = [p.relative_to(ROOT) for p in (ROOT / "ephem").rglob("*.py")
               if p not in _predictors() and reads.search(p.read_text(encoding="utf-8"))]
    assert readers == []


def test_every_cpu_unit_says_what_it_was_measured_at():
    for table in _predictors().values():
        text = (data_dir() / table).read_text(encoding="utf-8")
        lines = [line for line in text.splitlines() if re.match(r"^[a-z0-9_]+ *=", line)]
        assert len(lines) == len(_toml_units(table))
        cpu = [line for line in lines if re.match(r"^[a-z0-9_]+_s(_[a-z0-9_]+)? *=", line)]
        assert len(cpu) > (30 if table == "cost_model.toml" else 3)
        silent = [line.split("=")[0].strip() for line in cpu if "measured" not in line.split("#", 1)[-1]]
        assert not silent, f"CPU units of data/{table} whose comment gives no measurement: {silent}"


def _body(e: float = 0.2) -> Body:
    """A body of the caller's, named afresh so that no cache holds anything of it."""
    return Body(f"cost-test-{next(_serial)}", Orbit(2.5, e, 5.0, 40.0, 70.0, 10.0, J2000), Pole(60.0, 50.0, J2000), 6.0,
                dynamical_ellipticity=0.1)


def test_the_estimates_price_what_the_process_does_not_keep_yet():
    """Cold, a track pays for the body's model, second-order theory and tables; once they are kept it does not."""
    b = _body()
    ladder = Ladder(b)
    cold = ladder.cost(None, J2000, J2000 + 3650.0, 100)
    built = {p.what.split(" (")[0] for p in cold.parts}
    assert any(w.startswith("the body's model") for w in built)
    assert any(w.startswith("the body's second-order theory") for w in built)
    assert any(w.startswith("the estimates' tables") for w in built)
    ladder.estimates(J2000 + np.arange(100) * 36.5)          # builds them
    warm = ladder.cost(None, J2000, J2000 + 3650.0, 100)
    assert not any(p.what.startswith(("the body's", "the estimates' tables")) for p in warm.parts)
    assert 0 < warm.cpu_s < cold.cpu_s
    assert {p.what for p in warm.parts} <= {p.what for p in cold.parts}


def test_the_same_question_asked_again_is_priced_at_its_kept_estimates():
    """The ladder keeps a question's estimates per epochs (issue 39's identical question, over-predicted by the whole
    estimates' work before): the price of the same grid then charges a look-up; another grid, or the memo emptied,
    the estimates in full."""
    from ephem.sun import ladder as ladder_module
    ladder = Ladder(_body())
    t0, step, count = J2000 + 0.25, 10.0, 37
    t = t0 + step * np.arange(count)                         # as ephem.answers.requests.track_arrays builds it
    t_end = t0 + step * (count - 1)
    estimates = lambda c: next(p for p in c.parts if p.what.startswith("the error estimates"))   # noqa: E731
    first = ladder.cost(None, t0, t_end, count)
    assert "kept" not in estimates(first).what
    ladder.estimates(t)
    again = ladder.cost(None, t0, t_end, count)
    assert "kept from the same question" in estimates(again).what
    assert estimates(again).cpu_s < estimates(first).cpu_s / 100
    assert "kept" not in estimates(ladder.cost(None, t0, t_end + step, count + 1)).what       # another grid
    ladder_module._cached_estimates.cache_clear()
    assert "kept" not in estimates(ladder.cost(None, t0, t_end, count)).what


@pytest.mark.parametrize("rung, order", [("secular", None), ("series", 2), ("series", 15), ("hansen", None),
                                         ("second_order", None), ("numerical", None)])
def test_a_rungs_price_holds_no_caches_state(rung, order):
    """A choice by cost ranks the rungs' prices (ephem.theory.choice): the same in a worker that has served the body
    and in one that has not, so that the answer does not depend on which worker gives it."""
    b = _body()
    before = Ladder(b).cost(rung, J2000, J2000 + 3650.0, 1000, order).cpu_s
    cached_model(b)
    cached_model(b, order)
    Ladder(b).estimates(J2000 + np.arange(10) * 365.0)
    assert Ladder(b).cost(rung, J2000, J2000 + 3650.0, 1000, order).cpu_s == pytest.approx(before, rel=1e-12)


def test_the_real_orbit_is_charged_until_its_path_is_kept():
    vesta = get_body("vesta")
    t0, t1 = 2466154.5, 2466519.5                      # 2040-2041, inside DE421
    de421._cached_path.cache_clear()
    assert not de421.path_kept(vesta, min(vesta.pole.epoch_jd_tdb, t0), t1)
    cold = Ladder(vesta).cost("real_orbit", t0, t1, 10)
    assert any(p.what.startswith("the real orbit") for p in cold.parts)
    de421.sun_path(vesta, min(vesta.pole.epoch_jd_tdb, t0), t1)
    assert de421.path_kept(vesta, min(vesta.pole.epoch_jd_tdb, t0), t1)
    warm = Ladder(vesta).cost("real_orbit", t0, t1, 10)
    assert not any(p.what.startswith("the real orbit") for p in warm.parts) and warm.cpu_s < cold.cpu_s
    de421._cached_path.cache_clear()
    assert not de421.path_kept(vesta, min(vesta.pole.epoch_jd_tdb, t0), t1)


def test_the_numerical_rungs_are_priced_for_the_orbits_on_both_sides_of_the_pole_epoch():
    """They integrate from the pole epoch to the farthest epoch on each side: 1950-2050 is twice 2000-2050."""
    b = get_body("ceres")
    one = Ladder(b).cost("numerical", J2000, J2000 + 50 * 365.25, 10)
    both = Ladder(b).cost("numerical", J2000 - 50 * 365.25, J2000 + 50 * 365.25, 10)
    u = cost.unit_costs()
    orbits = lambda c: next(p for p in c.parts if p.what.startswith("the spin axis integrated")).cpu_s \
        - u["base_s"] - 10 * u["dense_output_s"]                                             # noqa: E731
    assert orbits(both) == pytest.approx(2 * orbits(one), rel=1e-9)


def test_kept_asks_the_caches_it_names():
    """cost.kept reads the per-body caches by name (ephem.base.memo), below the layer that keeps them: the names are
    those of the caches the pole's 1-sigma uses."""
    b = get_body("mars")
    with_sigma = 1
    for fn in (pole_uncertainty.cached_pole_sensitivity, uncertainty.propagated):
        fn.cache_clear()
    cold = cost.pole_uncertainty(b, with_sigma, 100)
    key = b.with_sigmas(None)          # the σ caches key on the σ too (Body.with_sigmas)
    assert not cost.kept(cost.POLE_SENSITIVITY, *key) and not cost.kept(cost.PROPAGATED, *key)
    pole_uncertainty.cached_pole_sensitivity(b, None)
    uncertainty.propagated(b, None)
    assert cost.kept(cost.POLE_SENSITIVITY, *key) and cost.kept(cost.PROPAGATED, *key)
    warm = cost.pole_uncertainty(b, with_sigma, 100)
    assert len(warm.parts) == 1 and len(cold.parts) == 3 and warm.cpu_s < cold.cpu_s
    assert cost.pole_uncertainty(b, 0, 100) == cost.FREE


def test_the_shared_series_order_is_the_one_hansen_cuts_from():
    assert cost.SHARED_SERIES_ORDER == getattr(hansen, "_SHARED_ORDER")


def test_the_answer_cost_drops_what_is_kept():
    """A precession answer: the model and the propagated sigmas are charged while the process does not keep them."""
    from ephem.families import theory_for
    b = get_body("vesta")
    cached_model.cache_clear()
    uncertainty.propagated.cache_clear()
    theory = theory_for(b, b.perturbers)
    cold = theory.answer_cost(None)
    cached_model(b)
    uncertainty.propagated(b, None)
    warm = theory.answer_cost(None)
    assert warm.cpu_s < cold.cpu_s and len(warm.parts) < len(cold.parts)


@pytest.mark.parametrize("body, years", [("steins", (-50, 50)), ("ceres", (0, 1)), ("eros", (0, 30)),
                                         ("mars", (-500, 500)), ("vesta", (10, 20))])
def test_the_estimates_are_priced_for_the_samples_the_rotation_averaging_takes(body, years, monkeypatch):
    """The price counts the epochs rotation_averaging_bound samples (ephem.forced.physics_errors.
    rotation_averaging_samples, from the body alone): the same number as the bound's grids hold, each call (a long
    span's orbit-mean drift, sampled once per body and kept, is built first)."""
    from ephem.forced import physics_errors, rotation_scale
    b = get_body(body)
    first, last = J2000 + 365.25 * years[0], J2000 + 365.25 * years[1]
    physics_errors.rotation_averaging_bound(b, cached_model(b), np.array([first, last]))
    rotation_scale._samples.clear()       # the span's samples, kept for the next few asks: sampled afresh here
    sampled = []
    real = rotation_scale._span_grid
    monkeypatch.setattr(rotation_scale, "_span_grid", lambda m, span, count: sampled.append(count) or real(m, span, count))
    physics_errors.rotation_averaging_bound(b, cached_model(b), np.array([first, last]))
    assert physics_errors.rotation_averaging_samples(b, first, last) == sum(sampled)
