"""The accuracy study's arithmetic: convergence reference, Pareto front,
knee, power-law fits, subsample comparison; and the scope of the solver
hash that decides which runs a source change reruns."""
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from masonrydem import sources
from masonrydem.analysis import accuracy


def test_richardson_recovers_limit_and_order():
    """P(n) = 10 + 3 n^-1.5 on non-uniform levels 4, 6, 8: the limit 10 and
    the order 1.5 are recovered to round-off."""
    n = np.array([4.0, 6.0, 8.0])
    P_inf, p = accuracy.richardson(n, 10 + 3 * n ** -1.5)
    assert P_inf == pytest.approx(10.0, abs=1e-9) and p == pytest.approx(1.5, abs=1e-7)


def test_observed_orders_of_consecutive_levels():
    """P(n) = 5 + 2 n^-1.2 on levels 7, 9, ..., 15 shows the order 1.2 on
    every three consecutive levels; a kink (a level raised) shows as '-'
    where the three are not monotone."""
    n = np.arange(7.0, 16.0, 2.0)
    assert accuracy.observed_orders(n, 5 + 2 * n ** -1.2) == "1.20 1.20 1.20"
    P = 5 + 2 * n ** -1.2
    P[3] += 0.1
    assert accuracy.observed_orders(n, P).split()[2] == "-"


def test_richardson_refuses_non_monotone_levels():
    assert np.isnan(accuracy.richardson([4, 6, 8], [15.0, 14.0, 14.5])[0])


def test_reference_evidence():
    """A path has converged when its two finest levels lie within 1 %: the
    reference is then the Richardson limit of the three finest (with the
    observed order), or the finest level when they are not monotone; a
    path whose two finest differ by more is flagged and its finest level
    stands."""
    n = np.array([4, 8, 16])
    r = accuracy.reference(pd.DataFrame(dict(cells_n=n, P_max_kN=5 + 0.8 / n)))
    assert r["reference_kN"] == pytest.approx(5.0) and r["order"] == pytest.approx(1.0)
    assert r["method"].startswith("Richardson") and r["last_two_diff"] == pytest.approx(0.05 / 5.05)
    r = accuracy.reference(pd.DataFrame(dict(cells_n=n, P_max_kN=[5.0, 4.97, 4.99])))
    assert r["reference_kN"] == 4.99 and r["method"].startswith("finest level")
    # monotone, but the steps grow: no order either
    r = accuracy.reference(pd.DataFrame(dict(cells_n=n, P_max_kN=[5.0, 4.999, 4.98])))
    assert r["reference_kN"] == 4.98 and r["method"].startswith("finest level") and np.isnan(r["order"])
    r = accuracy.reference(pd.DataFrame(dict(cells_n=n, P_max_kN=5 + 8.0 / n)))
    assert r["method"].startswith("NOT CONVERGED") and r["reference_kN"] == 5.5


def test_pareto_front():
    """A run is on the front when no cheaper run is at least as accurate."""
    cost = [1, 2, 3, 4, 5]
    err = [0.10, 0.12, 0.05, 0.05, -0.01]
    assert accuracy.pareto_front(cost, err) == [0, 2, 4]


def test_knee_is_cheapest_setting_within_tolerance_with_right_modes():
    t = pd.DataFrame(dict(
        setting=["a", "a", "b", "b", "c", "c"], case=["x", "y"] * 3,
        error=[0.05, 0.01, 0.01, -0.015, 0.005, 0.001],
        mode_ok=[True, True, True, False, True, True], ok=[True] * 6,
        wall_time_s=[1, 1, 2, 2, 8, 8]))
    k = accuracy.knee(t, 0.02)
    assert list(k.setting) == ["a", "b", "c"]
    assert k.loc[k.knee, "setting"].item() == "c"           # a: 5 % off; b: wrong mode in case y
    assert k.loc[k.setting == "b", "max_abs_error"].item() == pytest.approx(0.015)


def test_power_fit():
    x = np.array([1.0, 2.0, 4.0, 8.0])
    a, k = accuracy.power_fit(x, 2.0 * x ** 1.7)
    assert a == pytest.approx(2.0) and k == pytest.approx(1.7)


def test_compare_subsample():
    """Default runs 10 % above the fine ones, sample by sample: mean 10 %
    higher, COV equal, ratio constant; a failed run is excluded and
    counted; modes counted per setting."""
    fine = pd.DataFrame(dict(sigma_v_mpa=0.0, sample=range(5), P_max_kN=[10.0, 12, 9, 11, 13],
                             failure_mode=["joint"] * 4 + ["brick"], ok=True))
    default = fine.assign(P_max_kN=1.1 * fine.P_max_kN, failure_mode=["joint"] * 5)
    default.loc[4, "ok"] = False
    r = accuracy.compare_subsample(default, fine).iloc[0]
    assert r.runs == 4 and r.excluded == 1
    assert r.mean_diff == pytest.approx(0.1) and r.cov_diff == pytest.approx(0.0, abs=1e-12)
    assert r.ratio_mean == pytest.approx(1.1) and r.ratio_cov == pytest.approx(0.0, abs=1e-12)
    assert r.brick_fine == 0 and r.joint_default == 4 and r.same_mode == 4


def test_solver_hash_covers_everything_a_simulation_runs():
    """Every package module that a simulation imports (what a run runs,
    in a fresh interpreter: the protocol, the row and its state) is in the
    hash, so that changing it reruns the simulations; the analysis, the
    study, the report and the pipeline are neither imported by a run nor
    hashed.  (The package's own __init__, sources.py and the command line are not
    hashed: they decide nothing a simulation computes.)"""
    code = ("import sys, masonrydem.specimen.protocol, masonrydem.specimen.row, masonrydem.specimen.state, "
            "masonrydem.scene; "
            "print('\\n'.join(m.__file__ for n, m in sys.modules.items() if n.startswith('masonrydem')))")
    files = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    pkg = Path(sources.__file__).parent
    imported = {Path(f).relative_to(pkg).as_posix() for f in files} - {"__init__.py", "sources.py"}
    hashed = set(sources.simulation_sources())
    assert imported <= hashed, imported - hashed
    assert "scene/schema.yaml" in hashed and "dem/kernels/step.py" in hashed
    assert not any(s.split("/")[0] in ("analysis", "study", "report", "pipeline") for s in hashed | imported)


def test_the_source_hash_ignores_documentation_only():
    """A docstring, a comment or a schema description does not rerun the
    simulations; a changed statement or a changed default does."""
    from masonrydem.sources import source_code
    base = source_code("m.py", "def f(x):\n    return x + 1\n")
    assert source_code("m.py", '"""module"""\ndef f(x):  # add one\n    """one more"""\n\n    return x + 1\n') == base
    assert source_code("m.py", "def f(x):\n    return x + 2\n") != base
    assert source_code("m.py", 'def f(x):\n    """only a docstring"""\n') == source_code("m.py", "def f(x):\n    pass\n")
    y = source_code("s.yaml", "a: {description: one text, type: number, default: 1.0}\ndescription: {type: string}\n")
    assert source_code("s.yaml", "a: {description: another, type: number, default: 1.0}\n"
                                 "description: {type: string}\n") == y
    assert source_code("s.yaml", "a: {description: one text, type: number, default: 2.0}\n"
                                 "description: {type: string}\n") != y
    assert len(sources.source_hash()) == 12


def test_references_are_read_only_when_todays_solver_reproduces_them():
    """The summary reads the references' table (results/accuracy/references.csv)
    only after the coarsest path level, rerun now, gives the table's P_max to
    its printed digits in the same steps; anything else (another P_max, other
    steps, a run the table lacks) is refused with the command that remakes it."""
    import pandas as pd
    from masonrydem.analysis.accuracy import check_references
    table = pd.DataFrame([dict(case="joint_sv0", setting="path_c7x3x2", P_max_kN=12.5737, steps=33000)])
    same = dict(case="joint_sv0", setting="path_c7x3x2", P_max_kN=12.573731237951991, steps=33000)
    check_references(table, [same])
    for other in (dict(same, P_max_kN=12.57385), dict(same, steps=33500), dict(same, case="brick_sv0")):
        with pytest.raises(ValueError, match="forcerun accuracy_references"):
            check_references(table, [other])
