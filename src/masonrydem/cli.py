"""masonrydem command line.

  masonrydem run SCENE.yaml [--set path.to.key=value ...] --out DIR [--state] [--quiet] [--threads N]

Exit codes: 0 the run ended ok; 1 it ended not ok (its row says why:
status and message); 2 bad input, refused before any computation (the
message names the setting as the scene or the command line writes it); 3
an internal error (a run that raised still writes its row, status
'error').
"""
import argparse
import sys
import tempfile
import traceback
from pathlib import Path

from . import __version__
from .errors import InputError


def check_threads(n):
    """``--threads``: between 1 and the cores numba may use."""
    import numba
    cores = numba.config.NUMBA_NUM_THREADS
    if not 1 <= n <= cores:
        raise InputError("--threads", f"must be between 1 and {cores} (the cores of this machine), got {n}")
    return n


def output_dir(out):
    """``--out``: a folder, created if need be and tried for writing now,
    before any computation (not found out after the run)."""
    if not out.strip():
        raise InputError("--out", "is empty: name the folder to write the results into")
    path = Path(out)
    for p in (path, *path.parents):
        if p.exists():
            if not p.is_dir():
                raise InputError("--out", f"{out} is a file, not a folder" if p == path else
                                 f"{out} lies under {p}, which is a file, not a folder")
            break
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError as e:
        raise InputError("--out", f"cannot write into {out}: {e.strerror}") from None
    return path


def _run(args):
    check_threads(args.threads)
    from .scene import load_scene
    scene = load_scene(args.scene, list(args.set or []) + (["outputs.state=true"] if args.state else []))
    out = output_dir(args.out)
    import numba

    from .runner import run_and_write
    numba.set_num_threads(args.threads)
    row, error = run_and_write(out, scene, progress=not args.quiet, state=scene["outputs"]["state"])
    if error is not None:
        print(f"masonrydem: internal error: {row['message']} (status 'error' -> {out})", file=sys.stderr)
        return 3
    print(f"{row['status']}: P_max {row['P_max_kN']:.3f} kN at {row['disp_at_peak_mm']:.3f} mm, "
          f"strength {row['strength_mpa']:.3f} MPa, {row['classification']}; "
          f"{row['steps']} steps, {row['wall_time_s']:.1f} s -> {out}")
    if not row["ok"]:
        print(f"masonrydem: the run ended not ok ({row['status']}): {row['message']}", file=sys.stderr)
    return 0 if row["ok"] else 1


def main(argv=None):
    parser = argparse.ArgumentParser(prog="masonrydem", description="Masonry micro-model DEM solver.",
                                     epilog="exit codes: 0 ok, 1 the run ended not ok, 2 bad input, 3 internal error")
    parser.add_argument("--version", action="version", version=f"masonrydem {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run one scene and write result.parquet, curve.parquet (and state.vtm)")
    run.add_argument("scene", help="scene YAML file (see config/scenes/willis.yaml)")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="override a scene setting, e.g. --set loading.precompression.pressure=0.15e6")
    run.add_argument("--out", required=True, help="output directory")
    run.add_argument("--state", action="store_true", help="also write the final state (state.vtm)")
    run.add_argument("--quiet", action="store_true", help="no progress lines")
    run.add_argument("--threads", type=int, default=1, help="numba threads (default 1, at most the machine's cores)")
    args = parser.parse_args(argv)
    try:
        return _run(args)
    except InputError as e:
        print(f"masonrydem: invalid input: {e}", file=sys.stderr)
        return 2
    except Exception:
        traceback.print_exc()
        print("masonrydem: internal error (please report it with the traceback above)", file=sys.stderr)
        return 3


if __name__ == "__main__":
    sys.exit(main())
