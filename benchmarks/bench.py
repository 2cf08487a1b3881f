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
The kernels are timed on realistic states: the reference wallette loaded
past its peak (joint failure: joints softening), and a strong-joint
wallette past its peak (brick failure: zones cracking, reported under
"brick_failure").  ``--tiny``: the same on a wallette of 2 x 2 units of
one cell each, a few hundred steps (tests/test_bench.py runs it, so that
the benchmark cannot break unnoticed).
"""
import json
import os
import subprocess
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

from masonrydem import Solver  # noqa: E402
from masonrydem import kernels as K  # noqa: E402
from masonrydem.kernels.joints import contact_forces  # noqa: E402
from masonrydem.kernels.zones import zone_forces  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402
from masonrydem.specimen import build  # noqa: E402

SCENE = "config/scenes/willis.yaml"
TINY = ["geometry.courses=2", "geometry.units_per_course=2", "numerics.cells=[1, 1, 1]",
        "loading.bending.supports_x=[0.1, 0.5]", "loading.bending.loads_x=[0.25, 0.35]"]

FRESH = """
import time, sys
t0 = time.perf_counter()
import masonrydem
from masonrydem import Solver
from masonrydem.scene import load_scene
from masonrydem.specimen import build
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


def _kernels(zlaw, jlaw):
    """The zone and joint kernels of these laws, as the step kernel
    compiles them (the law ids are constants of the wrappers), each run
    ``n`` times per call: a call from Python costs tens of microseconds
    (its containers are typed and unboxed), which the loop amortises."""
    @njit(error_model="numpy")
    def zones(n, dt, nodes, z, scratch):
        for _ in range(n):
            zone_forces(zlaw, dt, nodes, z, scratch)

    @njit(error_model="numpy")
    def joints(n, dt, nodes, bodies, sc):
        for _ in range(n):
            contact_forces(jlaw, 0, 0, dt, nodes, bodies, sc)

    return zones, joints


def best_of(fn, n, repeat=5):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        best = min(best, time.perf_counter() - t0)
    return best / n


def kernel_times(overrides, steps=6000, ramp=2000):
    """Loads the wallette of SCENE (with ``overrides``) for ``steps`` steps,
    then times the zone and joint kernels on copies of that state and a
    stretch of whole steps."""
    sp = build(load_scene(SCENE, overrides))
    s = Solver(sp.model, chunk=500)
    s.vpres[sp.drive] = [0.0, 5e-8, 0.0]
    s.run(steps, ramp_steps=ramp)
    nodes = s.nodes._replace(v=s.v.copy(), f=np.zeros_like(s.f))
    zs = s.zones._replace(state=s.zs.copy(), stress=s.stress.copy())
    js = s.joints._replace(state=s.js.copy())
    zone_kernel, joint_kernel = _kernels(s.assembly.zlaw, s.assembly.jlaw)

    zone_kernel(1, 1e-3, nodes, zs, s.scratch)
    joint_kernel(1, 1e-3, nodes, s.bodies, js)
    t_zone = best_of(lambda: zone_kernel(200, 1e-3, nodes, zs, s.scratch), 1) / 200
    t_joint = best_of(lambda: joint_kernel(2000, 1e-3, nodes, s.bodies, js), 1) / 2000
    t_step = best_of(lambda: s.cycle(500), 1, repeat=6) / 500
    nt, nsc = zs.tets.shape[0], js.area.shape[0]
    return dict(ns_per_tet_step=round(t_zone / nt * 1e9, 1),
                ns_per_subcontact_step=round(t_joint / nsc * 1e9, 1),
                steps_per_s=round(1.0 / t_step, 1),
                tetrahedra=int(nt), subcontacts=int(nsc),
                cracked_zones=int((s.zone_damage() > 0).sum()),
                damaged_subcontacts=int((s.js[:, K.JS_D] > 0).sum()),
                share_zones=round(t_zone / t_step, 3), share_joints=round(t_joint / t_step, 3))


def main(tiny=False):
    fresh_process_times(1)          # make sure the cache is warm
    import_s, load_s = fresh_process_times(1 if tiny else 3)
    base, steps, ramp = (TINY, 600, 200) if tiny else ([], 6000, 2000)
    ref = kernel_times(base, steps, ramp)
    # strong joints: the bricks crack (brick failure), so the plastic path runs
    brick = kernel_times(base + ["materials.joints.ft=1.0e6", "materials.joints.GI=30.0"], int(1.5 * steps), ramp)
    out = dict(ref)
    out.update(kernel_load_s=round(load_s, 3), import_s=round(import_s, 3),
               brick_failure={k: brick[k] for k in ("ns_per_tet_step", "ns_per_subcontact_step",
                                                     "steps_per_s", "cracked_zones")})
    print(json.dumps(out))


if __name__ == "__main__":
    main(tiny="--tiny" in sys.argv[1:])
