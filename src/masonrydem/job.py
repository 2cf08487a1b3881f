"""One simulation of the study as a light job (the workflow's rule
simulate runs it as a shell command, with no Snakemake script wrapper):

  python -m masonrydem.job SCENE --samples samples_V.json --variant V --sv MPA
      --sample N [--set key=value ...] --result RESULT.json --curve CURVE.json

It imports only what a simulation needs (no pandas; of scipy only the BLAS
that the linear cells' products call), writes its
row and its curve as JSON whatever happens (a run that raises is recorded
with status 'error' and the exception as its message), and reports its own
start-up: ``startup_s``, from the interpreter's start to the first step's
set-up (imports and reading the inputs).
"""
import argparse
import json
import os
import sys
import time


def _error_row(e, sample, variant, sv):
    from .study import sample_inputs
    return dict(variant=variant, sample=int(sample["sample"]), sigma_v_mpa=sv, status="error", ok=False,
                message=f"{type(e).__name__}: {e}", **sample_inputs(sample))


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m masonrydem.job", description=__doc__.split("\n\n")[0])
    p.add_argument("scene")
    p.add_argument("--samples", required=True)
    p.add_argument("--variant", required=True)
    p.add_argument("--sv", type=float, required=True, help="precompression (MPa)")
    p.add_argument("--sample", type=int, required=True)
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--result", required=True)
    p.add_argument("--curve", required=True)
    p.add_argument("--threads", type=int, default=1)
    args = p.parse_args(argv)
    import numba
    import numpy as np

    from .runner import CURVE_COLUMNS, write_json
    from .scene import load_scene
    from .study import run_sample
    numba.set_num_threads(args.threads)
    with open(args.samples) as f:
        sample = next(s for s in json.load(f) if s["sample"] == args.sample)
    startup = time.time() - _process_start()
    try:
        row, curve, _, _ = run_sample(load_scene(args.scene, args.set), sample, args.variant, args.sv, frame=False)
        curve = {k: np.asarray(v).tolist() for k, v in curve.items()}
    except Exception as e:  # nothing lost: the row says what happened
        import traceback
        traceback.print_exc()
        row = _error_row(e, sample, args.variant, args.sv)
        curve = {c: [] for c in CURVE_COLUMNS}
    row["startup_s"] = startup
    write_json(args.curve, curve)
    write_json(args.result, {k: (v.item() if hasattr(v, "item") else v) for k, v in row.items()})
    print(json.dumps(row, default=str))
    return 0


def _process_start():
    """The interpreter's start (wall clock), from /proc (Linux), else now."""
    try:
        with open(f"/proc/{os.getpid()}/stat") as f:
            ticks = float(f.read().rsplit(")", 1)[1].split()[19])
        with open("/proc/uptime") as f:
            uptime = float(f.read().split()[0])
        return time.time() - uptime + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return time.time()


if __name__ == "__main__":
    code = main()
    # its outputs are written (atomically) and closed: skip the interpreter's
    # teardown of numba and LLVM, 0.2 s of a job that simulates for 2
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
