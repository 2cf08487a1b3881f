"""``masonrydem check SCENE``: the scene validated, the model it builds
counted, and a run's time and memory estimated, from the scene's numbers
alone: nothing is built or run.

The time is the cost of one step times the steps.  The cost of a step
is the sum of each kind of item times its measured cost on one core
(docs/speed.md, ``make bench``: a joint sub-contact 15 ns, a linear cell
37 ns, a tetrahedral zone 25 ns elasto-plastic or 17 ns elastic, the
node update about 9 ns a node).  The steps are bounded by the drive: the
ramp and the displacement limit over the rate, at most the test's
max_steps, and the precompression's own stage.  A run that reaches its
load drop, or passes its peak, stops sooner."""
import math

from ..dem.laws import MohrCoulomb
from ..specimen.size import model_size

# seconds per step and item, one core (docs/speed.md, 2026-11-25)
COST = dict(sub_contacts=15e-9, cells=37e-9, zones_plastic=25e-9, zones_elastic=17e-9, nodes=9e-9)


def step_seconds(scene, size):
    """The estimated cost of one step (s) of the scene's model of ``size``."""
    plastic = scene.physics.model.material is MohrCoulomb
    zones = COST["zones_plastic" if plastic else "zones_elastic"]
    return (size["sub_contacts"] * COST["sub_contacts"] + size["cells"] * COST["cells"]
            + size["tetrahedra"] * zones + size["nodes"] * COST["nodes"])


def step_bound(scene):
    """(steps at most: the test's drive, the precompression stage's at most)."""
    d = scene.loading.drive
    drive = min(d.max_steps, d.ramp_steps + math.ceil(d.max_displacement / d.rate))
    pre = scene.loading.precompression
    return drive, (pre.max_steps if pre.pressure > 0 else 0)


def summary(scene):
    """The lines ``check`` prints for a validated scene."""
    g, ph, num = scene.geometry, scene.physics, scene.discretization
    size = model_size(g, ph, num, scene.loading)
    per_step = step_seconds(scene, size)
    drive, pre = step_bound(scene)
    L, H, T = g.unit_length, g.unit_height, g.unit_width
    lines = [
        f"scene {scene.name!r}: valid",
        f"  specimen: {g.courses} courses x {g.units_per_course} units of {L * 1e3:g} x {H * 1e3:g} x "
        f"{T * 1e3:g} mm, joints {g.joint_thickness * 1e3:g} mm ({g.n_units} units, {len(g.joints)} joints)",
        f"  physics: {ph.blocks} blocks, {ph.joints} joints; test: {scene.loading.test}",
        f"  model: {size['nodes']:,} nodes, {size['tetrahedra']:,} tetrahedra, {size['cells']:,} cells, "
        f"{size['sub_contacts']:,} sub-contacts (upper estimates; cells {list(num.cells)}, "
        f"refine {num.refine_label})",
        f"  memory: about {size['bytes'] / 1e6:.0f} MB at most",
        f"  time: about {per_step * 1e6:.0f} us a step on one core; the test's drive allows at most "
        f"{drive:,} steps ({_duration(drive * per_step)})"
        + (f", the precompression at most {pre:,} more" if pre else ""),
        "  a run that reaches its load drop, or passes its peak (loading.bending.past_peak), stops sooner",
        "  nothing was built or run",
    ]
    return lines


def _duration(seconds):
    if seconds < 120:
        return f"{seconds:.1f} s"
    if seconds < 7200:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"
