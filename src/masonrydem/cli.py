"""masonrydem command line.

  masonrydem run SCENE.yaml [--set path.to.key=value ...] --out DIR [--state] [--quiet]
"""
import argparse
import sys

from . import __version__
from .errors import InputError


def _run(args):
    import numba

    from .runner import run_scene, write_outputs
    from .scene import load_scene
    numba.set_num_threads(max(1, args.threads))
    # refused here, before any computation
    scene = load_scene(args.scene, list(args.set or []) + (["outputs.state=true"] if args.state else []))
    row, curve, specimen, solver = run_scene(scene, progress=not args.quiet)
    write_outputs(args.out, row, curve, specimen, solver, state=scene["outputs"]["state"])
    print(f"{row['status']}: P_max {row['P_max_kN']:.3f} kN at {row['disp_at_peak_mm']:.3f} mm, "
          f"strength {row['strength_mpa']:.3f} MPa, {row['classification']}; "
          f"{row['steps']} steps, {row['wall_time_s']:.1f} s -> {args.out}")
    return 0 if row["ok"] else 1


def main(argv=None):
    parser = argparse.ArgumentParser(prog="masonrydem", description="Masonry micro-model DEM solver.")
    parser.add_argument("--version", action="version", version=f"masonrydem {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run one scene and write result.parquet, curve.parquet (and state.vtm)")
    run.add_argument("scene", help="scene YAML file (see config/scenes/willis.yaml)")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="override a scene setting, e.g. --set loading.precompression.pressure=0.15e6")
    run.add_argument("--out", required=True, help="output directory")
    run.add_argument("--state", action="store_true", help="also write the final state (state.vtm)")
    run.add_argument("--quiet", action="store_true", help="no progress lines")
    run.add_argument("--threads", type=int, default=1, help="numba threads (default 1)")
    args = parser.parse_args(argv)
    try:
        return _run(args)
    except InputError as e:
        print(f"masonrydem: invalid input: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
