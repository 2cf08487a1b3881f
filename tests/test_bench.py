"""`make bench` runs, so that it cannot break unnoticed: benchmarks/bench.py
on a tiny wallette prints its JSON line, with the model's own counts.  Its
timings are figures to read, not to assert (speed is measured in the
benchmark, never in a test)."""
import json
import subprocess
import sys
from pathlib import Path

from masonrydem.scene import build_scene
from masonrydem.specimen.build import build

ROOT = Path(__file__).resolve().parents[1]


def test_bench_runs_on_a_tiny_wallette(monkeypatch):
    out = subprocess.run([sys.executable, "benchmarks/bench.py", "--tiny"], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout.strip().splitlines()[-1]
    r = json.loads(out)
    # importing the script must not set NUMBA_NUM_THREADS in this process: once
    # numba's threads run (the CLI sets them), a changed value makes every
    # later compilation raise
    import numba
    monkeypatch.setenv("NUMBA_NUM_THREADS", str(numba.config.NUMBA_NUM_THREADS))
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))
    from bench import MODELS, TINY
    sp = build(build_scene(str(ROOT / "config/scenes/willis.yaml"), MODELS["elasto-plastic"][1] + TINY))
    a = sp.assembly
    assert r["tetrahedra"] == 4 * 10 == a.zones.tets.shape[0]
    assert r["subcontacts"] == a.joints.area.size
    # every unit model with the kernels it runs: zones, linear cells, bodies
    models = r["models"]
    for name, key in (("elastic-zones", "ns_per_tet_step"), ("elastic-tet10", "ns_per_cell_step"),
                      ("elastic-hex8i", "ns_per_cell_step"), ("potential-crack", "ns_per_cell_step"),
                      ("rigid", "ns_per_subcontact_step")):
        assert key in models[name], name
    assert models["elastic-tet10"]["cells"] == 4 and models["elastic-tet10"]["tetrahedra"] == 0
    assert models["rigid"]["tetrahedra"] == models["rigid"]["cells"] == 0
    assert r["job"]["steps"] > 0
    assert r["bootstrap"]["same"]       # the bootstrap on two processes gives the intervals of one
