"""One simulation of a scene: precompression, then the displacement-
controlled test (bending, tension or triplet shear); the result row, the
curve and (on request) the final state.

Nothing is lost: a run that fails or diverges still yields its row, with
its status and message.  Outputs are written to temporary files and renamed
(atomic).
"""
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from . import __version__, source_hash
from . import kernels as K
from .classify import classify
from .errors import InputError
from .solver import PEAK_UNBALANCE, Solver
from .specimen import build, strength

GOOD = ("load_drop", "displacement_limit")
DROP_WINDOW = 1e-4   # m: 'drop_after_peak' is the load lost within this displacement after the peak


class Progress:
    """Prints step, load, displacement and ratio every ``every`` seconds."""

    def __init__(self, stage, u0=0.0, every=2.0, stream=sys.stderr):
        self.stage, self.u0, self.every, self.stream = stage, u0, every, stream
        self.t0 = self.last = time.perf_counter()

    def __call__(self, s):
        now = time.perf_counter()
        if now - self.last < self.every:
            return
        self.last = now
        P, u = (s.last[K.h_force(0)], s.last[K.h_disp(0)]) if s.ngrp else (0.0, 0.0)
        print(f"[{self.stage}] step {s.step:8d}  load {P / 1e3:8.3f} kN  disp {(u - self.u0) * 1e3:7.4f} mm"
              f"  ratio {s.last[K.H_RATIO]:.2e}  ({now - self.t0:.0f} s)", file=self.stream, flush=True)


def downsample(disp, load, n):
    """About n points evenly spaced along the curve's steps, always keeping
    the first, the last and the peak."""
    idx = np.unique(np.concatenate([np.linspace(0, disp.size - 1, n).round().astype(int),
                                    [int(np.argmax(load))]]))
    return idx


def scene_inputs(scene):
    """The inputs of a row that the scene gives by itself."""
    return dict(
        scene=scene["name"],
        sigma_v_mpa=scene["loading"]["precompression"]["pressure"] / 1e6,
        blocks=scene["physics"]["blocks"],
        elastic_element=scene["numerics"]["elastic_element"],
        cells="x".join(str(c) for c in scene["numerics"]["cells"]),
        subcontact_refine=refine_label(scene["numerics"]["subcontact_refine"]),
    )


def refine_label(refine):
    """A sub-contact refinement as the rows record it: '2', '1x2x1' per axis
    (as cells), or per kind of contact 'head:1x2x1,bed:1'."""
    if isinstance(refine, dict):
        return ",".join(f"{k}:{refine_label(v)}" for k, v in refine.items())
    return "x".join(str(r) for r in refine) if isinstance(refine, (list, tuple)) else str(refine)


def inputs_row(specimen):
    """The inputs that vary in the study (field means for spatial ones)."""
    return dict(
        scene_inputs(specimen.scene),
        E_b_mpa=float(np.mean(specimen.E_b)) / 1e6,
        f_tu_mpa=float(np.mean(specimen.f_tu)) / 1e6,
        f_tj_mpa=float(np.mean(specimen.f_tj)) / 1e6,
        phi_j_deg=float(np.mean(specimen.phi_j)),
        units=len(specimen.units),
    )


CURVE_COLUMNS = ("step", "displacement_mm", "load_kN", "ratio", "unbalance")


def error_row(scene, error, wall_time_s=math.nan):
    """The row of a run that raised: its inputs as the scene gives them,
    status 'error' and the exception as its message."""
    return dict(scene_inputs(scene), status="error", ok=False, message=f"{type(error).__name__}: {error}",
                wall_time_s=wall_time_s, solver_version=f"{__version__}+{source_hash()}")


def run_scene(scene, progress=True):
    """``simulate`` with the curve as a pandas DataFrame."""
    import pandas as pd
    row, curve, specimen, solver = simulate(scene, progress)
    return row, pd.DataFrame(curve), specimen, solver


def simulate(scene, progress=True):
    """Runs a validated scene.  Returns (row, curve, specimen, solver), the
    curve a dict of arrays (step, displacement_mm, load_kN, ratio,
    unbalance).  BLAS (the linear cells' matrix products) runs on one
    thread: a run is one job of one thread, and its results do not depend
    on the machine's core count.  The kernels' np.dot calls scipy's BLAS,
    which numba loads at the first product: loaded after the limit, it ran
    on every core, and two runs side by side on two cores spun against each
    other (pc 4x4x3 cells, 3000 steps: 42.7 s against 5.7 s).  So it is
    loaded first, then limited."""
    import scipy.linalg.cython_blas  # noqa: F401
    threadpool_limits(limits=1, user_api="blas")
    t0 = time.perf_counter()
    specimen = build(scene)
    num, load = scene["numerics"], scene["loading"]
    s = Solver(specimen.model, damping=num["damping"], safety=num["safety"],
               record_every=num["record_every"], chunk=500)
    row = inputs_row(specimen)
    pre_status, pre_message = "none", ""
    res = None
    if load["precompression"]["pressure"] > 0:
        pre = load["precompression"]
        res = s.run(pre["max_steps"], ratio_tol=pre["ratio_tol"],
                    progress=Progress("precompression") if progress else None)
        pre_status, pre_message = res.status, res.message
    g = s.monitor_index("load")
    u0 = float(s.last[K.h_disp(g)])
    start = s.step
    loaded = res is None or res.status in ("converged", "max_steps")
    stage = specimen.stage
    if loaded:
        s.vpres[specimen.drive] = specimen.velocity
        res = s.run(stage["max_steps"], disp_limit=u0 + stage["max_displacement"], load_drop=stage["load_drop"],
                    monitor="load", balance="support", ramp_steps=stage["ramp_steps"],
                    progress=Progress(specimen.test, u0) if progress else None)
    H = s.history.array()
    H = H[H[:, K.H_STEP] > start]         # the loading stage
    step, ratio, P, u = H[:, K.H_STEP], H[:, K.H_RATIO], H[:, K.h_force(g)], H[:, K.h_disp(g)]
    # no loading stage (the precompression failed): no peak
    peak_P, peak_u, peak_step, peak_ratio, peak_unbalance = (
        s.history.peak[g] if loaded and g in s.history.peak else (math.nan, math.nan, -1, math.nan, math.nan))
    status, message = res.status, res.message
    if res.status in GOOD and math.isnan(peak_P):
        status, message = "no_peak", (f"the load was never within {PEAK_UNBALANCE:.0%} of balanced after the "
                                      "velocity ramp: no peak counts (lower the rate)")
    # a peak inside the velocity ramp does not count (History): a run that
    # reached its stop criteria would report a later, lower load as its peak
    ramp = P[step <= start + stage["ramp_steps"]]
    if res.status in GOOD and ramp.size and not ramp.max() <= peak_P:
        status, message = "peak_in_ramp", (f"the load peaked at {ramp.max() / 1e3:.4g} kN within the velocity ramp "
                                           f"(the first {stage['ramp_steps']} steps), where a peak does not count: "
                                           "lower the rate or the ramp steps")
    # a test on a wall the precompression left out of equilibrium measures nothing
    if pre_status == "max_steps" and status in GOOD:
        status, message = "precompression_unconverged", (
            f"the precompression did not reach equilibrium ({pre_message} with the unbalanced-force ratio above "
            f"loading.precompression.ratio_tol, {load['precompression']['ratio_tol']:g}); the {specimen.test} "
            f"stage then ended with {res.status}: {res.message}")
    # after the peak: did the load stay near equilibrium, or did it snap (a
    # sudden crack that displacement control cannot follow, carried by inertia)?
    unbalance = s.unbalance(H, g)
    unbalance_after = unbalance[step > peak_step] if peak_step >= 0 else unbalance[:0]
    after_unbalance = float(np.nanmax(unbalance_after)) if unbalance_after.size else math.nan
    after = P[(u >= peak_u) & (u <= peak_u + DROP_WINDOW)]
    drop = 1.0 - after.min() / peak_P if after.size and peak_P > 0 else math.nan
    idx = downsample(u, P, scene["outputs"]["curve_points"]) if H.shape[0] else slice(0)
    curve = dict(step=step[idx].astype(np.int64), displacement_mm=(u[idx] - u0) * 1e3, load_kN=P[idx] / 1e3,
                 ratio=ratio[idx], unbalance=unbalance[idx])
    out = scene["outputs"]
    row.update(
        P_max_kN=peak_P / 1e3,
        disp_at_peak_mm=(peak_u - u0) * 1e3,
        strength_mpa=strength(peak_P, specimen) / 1e6,
        **classify(specimen, s, out["crack_damage"], out["crack_through"], out["broken_joint_damage"]),
        drop_after_peak=drop,
        status=status,
        ok=status in GOOD,
        message=message,
        precompression_status=pre_status,
        steps=int(s.step),
        peak_step=int(peak_step),
        ratio_at_peak=peak_ratio,
        unbalance_at_peak=peak_unbalance,
        max_unbalance_after_peak=after_unbalance,
        post_peak=("none" if math.isnan(after_unbalance) else "dynamic" if after_unbalance >= PEAK_UNBALANCE
                   else "quasi-static"),
        tets=int(s.zones.tets.shape[0]),
        linear_cells=int(s.assembly.cells.nodes.shape[0]),
        subcontacts=int(s.js.shape[0]),
        max_rotation_rad=s.max_rotation(),
        wall_time_s=time.perf_counter() - t0,
        solver_version=f"{__version__}+{source_hash()}",
    )
    return row, curve, specimen, s


def read_json(path):
    import json
    return json.loads(Path(path).read_text())


def write_json(path, obj):
    """``obj`` as JSON (NaN as NaN: Python's json reads it back), atomically."""
    import json
    atomic_write(path, lambda p: Path(p).write_text(json.dumps(obj)))


def atomic_write(path, write):
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    write(tmp)
    os.replace(tmp, path)


def record_error(out_dir, scene, error, wall_time_s=math.nan):
    """Writes the row of a run that raised (``error_row``) and an empty
    curve into ``out_dir``; returns the row."""
    import pandas as pd
    row = error_row(scene, error, wall_time_s)
    write_outputs(out_dir, row, pd.DataFrame({c: [] for c in CURVE_COLUMNS}))
    return row


def run_and_write(out_dir, scene, progress=True, state=False):
    """``run_scene`` with its outputs written into ``out_dir``
    (``write_outputs``).  Nothing lost: a run that raises (refused input
    aside) writes its error row and an empty curve instead
    (``record_error``).  Returns (row, the exception or None)."""
    t0 = time.perf_counter()
    try:
        row, curve, specimen, solver = run_scene(scene, progress=progress)
    except InputError:
        raise
    except Exception as e:   # nothing lost: the row says what happened
        import traceback
        traceback.print_exc()
        return record_error(out_dir, scene, e, time.perf_counter() - t0), e
    write_outputs(out_dir, row, curve, specimen, solver, state=state)
    return row, None


def write_outputs(out_dir, row, curve, specimen=None, solver=None, state=False):
    """DIR/result.parquet (one row), DIR/curve.parquet and, with ``state``,
    DIR/state.vtm (the final state, deformed mesh with zone and joint
    damage)."""
    import pandas as pd
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    atomic_write(out_dir / "result.parquet", lambda p: pd.DataFrame([row]).to_parquet(p, index=False))
    atomic_write(out_dir / "curve.parquet", lambda p: curve.to_parquet(p, index=False))
    if state:   # a .vtm is an index plus a folder of pieces: written last
        from .viz import state_blocks
        state_blocks(specimen, solver).save(str(out_dir / "state.vtm"))
