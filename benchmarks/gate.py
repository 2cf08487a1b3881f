"""Refactor gate: the rows and curves of a fixed set of runs, every digit.

A refactor must leave every value written here unchanged, bit for bit:
each run's row (wall and start-up times and the solver version aside) and
its whole curve.  ``--out FILE`` writes them (JSON, floats as repr);
``--compare FILE`` reports every difference and exits 1 if there is one.

    python benchmarks/gate.py --out before.json            # on the old code
    python benchmarks/gate.py --compare before.json        # on the new code

The set covers every kernel path (elasto-plastic, elastic and rigid units,
large displacements, each joint law, gravity, precompression, the three
tests, a spatial field), the validation runs of config/config.yaml at the
study's numerics, and ten samples of the committed study of each variant
at 0 and 0.5 MPa (results/study/samples_*.parquet; --quick: the kernel
paths only).
"""
import argparse
import json
import os
import sys
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import yaml  # noqa: E402

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
SKIP = ("wall_time_s", "solver_version", "startup_s")


def study_runs(n=10, levels=(0.0, 0.5)):
    """(name, overrides, sample record, variant) of the first n samples per
    variant of the Willis study (config/studies/willis.yaml, Study.draw:
    the committed samples)."""
    from masonrydem.study.file import load_study
    with open("config/config.yaml") as f:
        numerics = yaml.safe_load(f)["numerics"]
    study = load_study("config/studies/willis.yaml")
    out = []
    for variant in ("nonspatial", "spatial"):
        for i, s in enumerate(study.draw(variant).records()[:n]):
            for sv in levels:
                out.append((f"study_{variant}_s{i}_sv{sv}",
                            numerics + [f"loading.precompression.pressure={sv * 1e6}"], s, variant))
    return out


def validation_runs():
    with open("config/config.yaml") as f:
        config = yaml.safe_load(f)
    v = config["validation"]
    return {f"validation_{c['name']}_sv{sv}": (W, config["numerics"] + c["overrides"]
                                               + [f"loading.precompression.pressure={sv * 1e6}"])
            for c in v["cases"] for sv in v["precompression_mpa"]}


def run_one(scene_file, overrides, sample=None, variant=None):
    """(row, curve) of one run, values as they are written."""
    from masonrydem.specimen.protocol import simulate
    from masonrydem.specimen.row import curve, outcome_row
    from masonrydem.scene import build_scene
    labels, settings, label = {}, None, None
    if sample is not None:
        labels = dict(variant=variant, sample=int(sample["sample"]), inputs=sample["inputs"])
        settings, label = sample["settings"], f"{variant}:s{int(sample['sample'])}"
    outcome = simulate(build_scene(scene_file, overrides, settings, label), progress=False)
    return outcome_row(outcome, **labels).values(), curve(outcome)


def record(row, curve):
    def clean(v):
        if isinstance(v, (float, np.floating)):
            return repr(float(v))
        return v.item() if hasattr(v, "item") else v
    return dict(row={k: clean(v) for k, v in row.items() if k not in SKIP},
                curve={k: [repr(float(x)) for x in np.asarray(v)] for k, v in curve.items()})


def compare(out, ref):
    """Every difference between two gate records, as lines: (values that
    differ, columns only one side has)."""
    lines, columns = [], {}
    for name, rec in out.items():
        if name not in ref:
            lines.append(f"{name}: not in the reference")
            continue
        for part in ("row", "curve"):
            a, b = ref[name][part], rec[part]
            for k in sorted(set(a) | set(b)):
                if k in ("variant", "sample") and a.get(k) is None:      # labels the old rows lacked
                    continue
                if (k in a) != (k in b):
                    columns.setdefault(f"{part}.{k} {'dropped' if k in a else 'added'}", []).append(name)
                elif a[k] != b[k]:
                    lines.append(f"{name} {part}.{k}: before {str(a[k])[:80]}, now {str(b[k])[:80]}")
    return lines, [f"{col} in {len(runs)} runs (e.g. {runs[0]})" for col, runs in columns.items()]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out")
    ap.add_argument("--compare")
    ap.add_argument("--quick", action="store_true", help="the kernel paths only")
    args = ap.parse_args()
    runs = [(n, s, o, None, None) for n, (s, o) in RUNS.items()]
    if not args.quick:
        runs += [(n, s, o, None, None) for n, (s, o) in validation_runs().items()]
        runs += [(n, W, o, s, v) for n, o, s, v in study_runs()]
    out = {}
    for name, scene, overrides, sample, variant in runs:
        t0 = time.perf_counter()
        out[name] = record(*run_one(scene, overrides, sample, variant))
        r = out[name]["row"]
        print(f"{name:32s} {r['P_max_kN']:>22s} {r['steps']:6d} {r['status']}  {time.perf_counter() - t0:.1f} s",
              file=sys.stderr, flush=True)
    if args.out:
        with open(args.out, "w") as f:
            json.dump(out, f)
    if args.compare:
        with open(args.compare) as f:
            diff, columns = compare(out, json.load(f))
        for line in columns:
            print("COLUMN", line, file=sys.stderr)
        for line in diff:
            print("DIFFERENT", line, file=sys.stderr)
        print(f"identical: {len(out)} runs, rows and curves" if not diff else f"{len(diff)} differences",
              file=sys.stderr)
        return 1 if diff else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
