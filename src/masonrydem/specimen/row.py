"""The result of one simulation as one declared row (``Row``) and its
curve, and their one writer (``write``): JSON or Parquet, atomically.
A study's run also carries the study's inputs, by the names its study
file gives them (``study_inputs``: f_tj_mpa, bond_mpa, L_mm).

Nothing is lost: a run that raised has a row too (``error_row``), with
status 'error' and the exception as its message.  The columns:
docs/formulation.md, section 12.
"""
import functools
import json
import math
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..sources import __version__, source_hash
from .classify import classify
from ..scene import column, to_shown
from ..scene import setting_unit
from ..dem import PEAK_UNBALANCE, max_rotation
from .protocol import DROP_WINDOW, GOOD, post_peak

CURVE_COLUMNS = ("step", "displacement_mm", "load_kN", "ratio", "unbalance")
NAN = math.nan


@dataclass
class Row:
    """One run: its labels (a study's variant and sample), the scene's test
    and model, a study's inputs (``inputs``: column -> value, field means
    for spatial ones; one column each in the written row), the peak and
    strength, the failure mode with its evidence, how the run ended, the
    model's size, and provenance."""
    variant: str = None
    sample: int = None
    scene: str = None
    sigma_v_mpa: float = NAN
    blocks: str = None
    elastic_element: str = None
    cells: str = None
    subcontact_refine: str = None
    inputs: dict = field(default_factory=dict)
    units: int = None
    P_max_kN: float = NAN
    disp_at_peak_mm: float = NAN
    strength_mpa: float = NAN
    failure_mode: str = None
    cracked_units: int = None
    unit_crack_fraction: float = NAN
    cracked_brick_volume_frac: float = NAN
    broken_joints: int = None
    n_joints: int = None
    classification: str = None
    drop_after_peak: float = NAN
    status: str = "error"
    ok: bool = False
    message: str = ""
    precompression_status: str = None
    steps: int = None
    peak_step: int = None
    ratio_at_peak: float = NAN
    unbalance_at_peak: float = NAN
    max_unbalance_after_peak: float = NAN
    post_peak: str = None
    tets: int = None
    linear_cells: int = None
    subcontacts: int = None
    max_rotation_rad: float = NAN
    wall_time_s: float = NAN
    lanes: int = 1
    solver_version: str = None
    startup_s: float = NAN

    def values(self):
        """The row as written: its fields, the study's inputs as columns of
        their own in the place of ``inputs``."""
        out = {}
        for k, v in asdict(self).items():
            out.update(v) if k == "inputs" else out.__setitem__(k, v)
        return out


@functools.cache
def version():
    """The solver's version, package and source hash (the code this process
    loaded: computed once)."""
    return f"{__version__}+{source_hash()}"


def scene_labels(scene, variant=None, sample=None, inputs=None):
    """The row's labels, the scene's test and model as the typed scene gives
    them, and a study's ``inputs`` (name -> the scene setting it drives)
    as columns (``study_inputs``)."""
    d = scene.discretization
    return dict(variant=variant, sample=sample, scene=scene.name,
                sigma_v_mpa=scene.loading.precompression.pressure / 1e6, blocks=scene.physics.blocks,
                elastic_element=d.elastic_element, cells="x".join(str(c) for c in d.cells),
                subcontact_refine=d.refine_label, inputs=study_inputs(scene, inputs or {}), units=scene.geometry.n_units)


def study_inputs(scene, inputs):
    """A study's inputs (name -> the scene setting it drives) as the row's
    columns: each the scene's value of its setting (a property given per
    unit or joint: its mean over them) in the unit results show it in,
    under the column the study names (f_tj_mpa)."""
    out = {}
    for name, setting in inputs.items():
        unit = setting_unit(setting)
        out[column(name, unit)] = to_shown(scene.value(setting), unit)
    return out


def sample_inputs(sample, inputs):
    """The inputs of a study's sample record as ``study_inputs`` gives
    them, from the sample's own values (a list per item: their mean): the
    row of a sample the scene refused."""
    out = {}
    for name, setting in inputs.items():
        unit = setting_unit(setting)
        out[column(name, unit)] = to_shown(float(np.mean(sample[name])), unit)
    return out


def error_row(scene, error, wall_time_s=NAN, variant=None, sample=None, inputs=None, values=None):
    """The row of a run that raised: the scene's labels, the study's
    ``inputs`` (name -> setting) from the scene or, where given, their
    ``values`` (those of a sample the scene refused: ``sample_inputs``),
    status 'error' and the exception as its message."""
    labels = scene_labels(scene, variant, sample, inputs)
    if values is not None:
        labels["inputs"] = values
    return Row(**labels, status="error", ok=False, message=f"{type(error).__name__}: {error}",
               wall_time_s=wall_time_s, solver_version=version())


def outcome_row(outcome, variant=None, sample=None, inputs=None, lanes=1):
    """The row of a simulation (protocol.Outcome); ``inputs``: a study's
    (name -> the scene setting it drives); ``lanes``: of its batch."""
    sp, state, scene = outcome.specimen, outcome.state, outcome.specimen.scene
    test = outcome.test
    peak = test.record.peaks[test.record.history.group("load")] if test is not None else None
    P, u, step, _ = _load_line(outcome)
    after_unbalance, _ = post_peak(outcome)
    peak_P = peak.load if peak else NAN
    peak_u = peak.disp if peak else NAN
    after = P[(u >= peak_u) & (u <= peak_u + DROP_WINDOW)]
    out = scene.outputs
    return Row(
        **scene_labels(scene, variant, sample, inputs),
        P_max_kN=peak_P / 1e3, disp_at_peak_mm=(peak_u - outcome.u0) * 1e3, strength_mpa=sp.strength(peak_P) / 1e6,
        **classify(sp, state, out.crack_damage, out.crack_through, out.broken_joint_damage),
        drop_after_peak=1.0 - after.min() / peak_P if after.size and peak_P > 0 else NAN,
        status=outcome.status, ok=outcome.status in GOOD, message=outcome.message,
        precompression_status=outcome.precompression.ending.status if outcome.precompression else "none",
        steps=int(state.step), peak_step=peak.step if peak else -1, ratio_at_peak=peak.ratio if peak else NAN,
        unbalance_at_peak=peak.unbalance if peak else NAN, max_unbalance_after_peak=after_unbalance,
        post_peak=("none" if math.isnan(after_unbalance) else "dynamic" if after_unbalance >= PEAK_UNBALANCE
                   else "quasi-static"),
        tets=int(state.zones.tets.shape[0]), linear_cells=int(state.assembly.cells.nodes.shape[0]),
        subcontacts=int(state.joints.state.shape[0]), max_rotation_rad=max_rotation(state),
        wall_time_s=outcome.wall_time, lanes=lanes, solver_version=version())


def _load_line(outcome):
    """The test's recorded rows: load, displacement, step and ratio (empty
    without a test)."""
    if outcome.test is None:
        return np.zeros(0), np.zeros(0), np.zeros(0, np.int64), np.zeros(0)
    h = outcome.test.record.history
    return h.force_of("load"), h.disp_of("load"), h.step, h.ratio


def curve(outcome):
    """The load-displacement curve of the test: about outputs.curve_points
    rows of its recorded ones (``downsample``), the load line's displacement
    from its start (mm), the load (kN), the model's ratio and the load's
    unbalance."""
    P, u, step, ratio = _load_line(outcome)
    _, unbalance = post_peak(outcome)
    idx = downsample(u, P, outcome.specimen.scene.outputs.curve_points) if P.size else slice(0)
    return dict(step=step[idx].astype(np.int64), displacement_mm=(u[idx] - outcome.u0) * 1e3, load_kN=P[idx] / 1e3,
                ratio=ratio[idx], unbalance=unbalance[idx] if unbalance is not None else np.zeros(0))


def empty_curve():
    return {c: np.zeros(0, np.int64 if c == "step" else float) for c in CURVE_COLUMNS}


def downsample(disp, load, n):
    """About n points evenly spaced along the curve's steps, always keeping
    the first, the last and the peak."""
    return np.unique(np.concatenate([np.linspace(0, disp.size - 1, n).round().astype(int), [int(np.argmax(load))]]))


def write(out_dir, row, curve, fmt="parquet", state=None):
    """DIR/result.FMT (one row) and DIR/curve.FMT, FMT json or parquet;
    with ``state`` (a pyvista MultiBlock, or True for a run that left
    none: an empty one) DIR/state.vtm, written last."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    values = {k: _plain(v) for k, v in row.values().items()}
    curve = {k: np.asarray(v).tolist() for k, v in curve.items()}
    if fmt == "json":
        write_json(out_dir / "result.json", values)
        write_json(out_dir / "curve.json", curve)
    else:
        import pandas as pd
        atomic_write(out_dir / "result.parquet", lambda p: pd.DataFrame([values]).to_parquet(p, index=False))
        atomic_write(out_dir / "curve.parquet", lambda p: pd.DataFrame(curve).astype(
            {"step": "int64"}).to_parquet(p, index=False))
    if state is not None:   # a .vtm is an index plus a folder of pieces
        if state is True:
            import pyvista as pv
            state = pv.MultiBlock()
        state.save(str(out_dir / "state.vtm"))


def _plain(v):
    return v.item() if hasattr(v, "item") else v


def read_json(path):
    return json.loads(Path(path).read_text())


def write_json(path, obj):
    """``obj`` as JSON (NaN as NaN: Python's json reads it back), atomically."""
    atomic_write(path, lambda p: Path(p).write_text(json.dumps(obj)))


def atomic_write(path, write_to):
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    write_to(tmp)
    os.replace(tmp, path)
