"""One deterministic run of the reference wallette (study.md, section 4)."""
import json
import sys

import numba

numba.set_num_threads(snakemake.threads)  # noqa: F821  (one thread per job)

import numpy as np  # noqa: E402

from masonrydem.wallette import WalletteSpec, bending_moment_arm, build  # noqa: E402
from masonrydem import Solver  # noqa: E402

sm = snakemake  # noqa: F821
cfg = sm.params.settings
sys.stderr = sys.stdout = open(sm.log[0], "w")
sv = float(sm.wildcards.sv)
spec = WalletteSpec(cells=tuple(cfg["cells"]), precompression=sv * 1e6)
model, h = build(spec)
s = Solver(model, chunk=500)
pre = None
if sv > 0:   # precompression stage: load strips at rest until equilibrium
    pre = s.run(cfg["max_steps"], ratio_tol=1e-5)
    print("precompression:", pre)
for strip in h["loads"]:
    s.set_strip_velocity(strip, [0.0, cfg["rate_m_per_step"], 0.0])
u0 = s.last[3]
res = s.run(cfg["max_steps"], disp_limit=u0 + cfg["max_displacement_mm"] * 1e-3,
            load_drop=cfg["load_drop"], monitor=h["load"], ramp_steps=cfg["ramp_steps"])
print("loading:", res)
peak, upeak, _ = s.history.peak[0]
arm = bending_moment_arm(spec)
b_sec, t_sec = 0.44, spec.thickness
H = s.history.array()
np.savetxt(sm.output.curve, np.column_stack([(H[:, 4] - u0) * 1e3, H[:, 3] / 1e3]),
           delimiter=",", header="displacement_mm,load_kN", comments="", fmt="%.6g")
json.dump(dict(
    sigma_v_mpa=sv, status=res.status, message=res.message, steps=s.step,
    P_max_kN=peak / 1e3, displacement_at_peak_mm=(upeak - u0) * 1e3,
    strength_mpa=6 * (0.5 * arm * peak) / (b_sec * t_sec ** 2) / 1e6,
    cracked_zones=int((s.zone_damage() > 0).sum()),
    max_rotation_rad=s.max_rotation(), wall_time_s=res.wall_time,
), open(sm.output.summary, "w"), indent=2)
