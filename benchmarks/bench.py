"""Solver speed on a wallette-sized model (24 bricks), one thread.

Prints one JSON line:
  ns_per_tet_step         zone kernel time / (tetrahedra x steps)
  ns_per_subcontact_step  joint kernel time / (sub-contacts x steps)
  steps_per_s             whole time steps per second (zones, joints,
                          bearings, node update, histories)
  kernel_load_s           a fresh process: time of the first time step of a
                          small model once the kernels are cached (import of
                          the package not included; reported apart)
  import_s                a fresh process: `import masonrydem`
The kernels are timed on a realistic state: the reference wallette loaded
past its peak, so that part of the zones and joints are yielding.
"""
import json
import os
import subprocess
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from masonrydem import Solver  # noqa: E402
from masonrydem import kernels as K  # noqa: E402
from masonrydem.scene import build, load_scene  # noqa: E402

SCENE = "config/scenes/willis.yaml"

FRESH = """
import time, sys
t0 = time.perf_counter()
import masonrydem
from masonrydem import Solver
from masonrydem.scene import build, load_scene
t1 = time.perf_counter()
sp = build(load_scene("config/scenes/willis.yaml", ["geometry.courses=2", "numerics.cells=[1, 1, 1]"]))
s = Solver(sp.model)
t2 = time.perf_counter()
s.cycle(1)
t3 = time.perf_counter()
print(t1 - t0, t3 - t2)
"""


def fresh_process_times(repeat=3):
    out = []
    for _ in range(repeat):
        r = subprocess.run([sys.executable, "-c", FRESH], capture_output=True, text=True, check=True)
        out.append([float(x) for x in r.stdout.split()])
    return np.median(np.array(out), axis=0)


def best_of(fn, n, repeat=5):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        best = min(best, time.perf_counter() - t0)
    return best / n


def main():
    fresh_process_times(1)          # make sure the cache is warm
    import_s, load_s = fresh_process_times()
    sp = build(load_scene(SCENE))
    s = Solver(sp.model, chunk=500)
    for st in sp.loads:
        s.set_strip_velocity(st, [0.0, 5e-8, 0.0])
    s.run(6000)                     # past the peak: cracked zones, damaged joints
    b = s.b
    nt, nsc = b["tets"].shape[0], b["joints"]["area"].shape[0]
    # time the kernels on copies of the state (they advance it)
    v = s.v.copy()
    f = np.zeros_like(s.f)
    stress, zs, js = s.stress.copy(), s.zs.copy(), s.js.copy()
    de, ev_, pending, a, evec = s._scratch
    zlaw = K.ZONE_MOHR_COULOMB

    def zones():
        K.zone_forces(zlaw, 1e-3, v, f, b["x0"], b["tets"], b["dn"], b["vol"], b["wt"], b["gptr"],
                      b["gnodes"], b["gnptr"], b["zp"], zs, stress, de, ev_, pending, a, evec)

    j = b["joints"]

    def joints():
        K.contact_forces(b["jlaw"], 1e-3, v, f, j["nodes"], j["cnt"], j["w"], j["axes"], j["area"],
                         j["par"], js)

    zones()
    joints()
    t_zone = best_of(zones, 200)
    t_joint = best_of(joints, 2000)
    nsteps = 2000
    t0 = time.perf_counter()
    s.cycle(nsteps)
    t_step = (time.perf_counter() - t0) / nsteps
    print(json.dumps(dict(
        ns_per_tet_step=round(t_zone / nt * 1e9, 1),
        ns_per_subcontact_step=round(t_joint / nsc * 1e9, 1),
        steps_per_s=round(1.0 / t_step, 1),
        kernel_load_s=round(load_s, 3),
        import_s=round(import_s, 3),
        tetrahedra=int(nt), subcontacts=int(nsc), nodes=int(b["nn"]),
        cracked_zones=int((s.zone_damage() > 0).sum()),
        damaged_subcontacts=int((s.js[:, K.JS_D] > 0).sum()),
        share_zones=round(t_zone * 1.0 / t_step, 3),
        share_joints=round(t_joint * 1.0 / t_step, 3),
    )))


if __name__ == "__main__":
    main()
