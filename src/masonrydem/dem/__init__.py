"""The discrete element solver: deformable or rigid blocks joined by
zero-thickness joints, integrated explicitly (docs/formulation.md).

- model.py: ``Model``, blocks, joints, supports and loads, and ``build``;
- laws.py: the block materials and joint laws (each a small compiled
  function chosen once);
- mesh.py, elements.py, blocks.py, contacts.py, assembly.py: the meshes,
  cells, faces, sub-contacts and the assembled arrays;
- solver.py: ``advance`` over a state (``Numerics``: how to
  integrate); batch.py: lanes of one mesh in lock-step, ``init`` (a
  batch of one); lockstep.py: the programs that drive a batch;
  stops.py: an advance loop under stop rules;
  history.py: what a run records; stability.py: masses and steps;
- kernels/: the compiled step; kernels/jit.py: numba's settings and the
  private parts of it the package relies on.

Nothing here knows of masonry, a test or a study.  The names below are
the solver's face: the layers above import them from here, never numba
or the kernels (pyproject.toml's contracts)."""
from .assembly import Assembly
from . import lockstep
from .batch import Batch, init, lane_key
from .blocks import GEOM_TOL
from .history import PEAK_UNBALANCE, History, Peak, unbalance
from .kernels.jit import lock_cache as lock_kernel_cache, max_threads, set_threads
from .kernels.layout import JS_D
from .laws import JOINT_LAWS, Elastic, JointProps, MohrCoulomb
from .model import Model
from .solver import Controls, Numerics, advance, max_rotation, prescribe, prescribe_rotation, zone_damage
from .stops import Ending, Stops, run, stage, stop_rule

__all__ = ["GEOM_TOL", "JOINT_LAWS", "JS_D", "PEAK_UNBALANCE", "Assembly", "Batch", "Controls", "Elastic", "Ending",
           "History", "JointProps", "Model", "MohrCoulomb", "Numerics", "Peak", "Stops", "advance", "init", "lane_key",
           "lock_kernel_cache", "lockstep", "max_rotation", "max_threads", "prescribe", "prescribe_rotation", "run",
           "set_threads", "stage", "stop_rule", "unbalance", "zone_damage"]
