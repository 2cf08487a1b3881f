"""Refactor gate: P_max (all digits) and step counts of a fixed set of runs.

A refactor must leave every number printed here unchanged, bit for bit.
Prints one JSON object (run -> [P_max_kN, steps, status]) and, with
``--out FILE``, writes it; ``--compare FILE`` reports every difference and
exits 1 if there is one.

    python benchmarks/gate.py --out before.json            # on the old code
    python benchmarks/gate.py --compare before.json        # on the new code

The set covers every kernel path: elasto-plastic, elastic and rigid units,
large displacements, each joint law, gravity, precompression, the three
tests (bending, tension, triplet), a spatial study sample and two runs at
the study's numerics (config/config.yaml).
"""
import argparse
import json
import os
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import pandas as pd  # noqa: E402
import yaml  # noqa: E402

from masonrydem.runner import run_scene  # noqa: E402
from masonrydem.scene import load_scene  # noqa: E402

W = "config/scenes/willis.yaml"
COARSE = ["physics.blocks=elasto-plastic", "numerics.cells=[3, 2, 1]", "loading.bending.rate=1.0e-7",
          "loading.bending.max_displacement=1.5e-3", "loading.bending.load_drop=0.5"]
STRONG = ["materials.joints.ft=1.0e6", "materials.joints.GI=30.0"]
RUNS = {
    "mc_sv0": (W, COARSE),
    "mc_sv015": (W, COARSE + ["loading.precompression.pressure=0.15e6"]),
    "mc_strong": (W, COARSE + STRONG),
    "mc_gravity": (W, COARSE + ["physics.gravity=true"]),
    "elastic": (W, COARSE + ["physics.blocks=elastic"]),
    "brittle": (W, COARSE + ["physics.joints=brittle_coulomb"]),
    "friction_sv015": (W, COARSE + ["physics.joints=friction", "loading.precompression.pressure=0.15e6"]),
    "rigid": (W, COARSE + ["physics.blocks=rigid"]),
    "rigid_large_gravity": (W, COARSE + ["physics.blocks=rigid", "physics.displacements=large",
                                         "physics.gravity=true", "loading.precompression.pressure=0.15e6"]),
    "tension": ("config/scenes/tension.yaml", []),
    "triplet": ("config/scenes/triplet.yaml", ["loading.precompression.pressure=0.2e6"]),
    "spatial_sample": (W, COARSE + ["materials.per_unit.E=[5.0e9, 25.0e9, 5.0e9, 25.0e9, 25.0e9, 5.0e9, 25.0e9, "
                                    "5.0e9, 5.0e9, 25.0e9, 5.0e9, 25.0e9, 25.0e9, 5.0e9, 25.0e9, 5.0e9, 5.0e9, "
                                    "25.0e9, 5.0e9, 25.0e9, 25.0e9, 5.0e9, 25.0e9, 5.0e9]"]),
}


def study_numerics():
    """The config's numerics (empty: the scene's own, the study's)."""
    with open("config/config.yaml") as f:
        return yaml.safe_load(f)["numerics"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out")
    ap.add_argument("--compare")
    ap.add_argument("--quick", action="store_true", help="skip the two runs at the study's numerics")
    args = ap.parse_args()
    runs = dict(RUNS)
    if not args.quick:
        runs["study_sv0"] = (W, study_numerics())
        runs["study_strong_sv015"] = (W, study_numerics() + STRONG + ["loading.precompression.pressure=0.15e6"])
    out = {}
    for name, (scene, overrides) in runs.items():
        t0 = time.perf_counter()
        row = run_scene(load_scene(scene, overrides), progress=False)[0]
        out[name] = [repr(float(row["P_max_kN"])), int(row["steps"]), row["status"]]
        print(f"{name:22s} {out[name]}  {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    print(json.dumps(out))
    if args.out:
        with open(args.out, "w") as f:
            json.dump(out, f, indent=1)
    if args.compare:
        with open(args.compare) as f:
            ref = json.load(f)
        diff = {k: (ref.get(k), v) for k, v in out.items() if ref.get(k) != v}
        for k, (a, b) in diff.items():
            print(f"DIFFERENT {k}: before {a}, now {b}", file=sys.stderr)
        print("identical" if not diff else f"{len(diff)} runs differ", file=sys.stderr)
        return 1 if diff else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
