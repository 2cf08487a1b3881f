"""masonrydem command line: the one entry point of a simulation, for a
user, the study's jobs and the workflow's runs alike.

  masonrydem run SCENE.yaml [--set path.to.key=value ...] --out DIR [--state] [--quiet] [--threads N]
      [--samples FILE --variant V --sample N [--sample M ...] [--lanes L]] [--format parquet|json] [--exit-zero]
  masonrydem check SCENE.yaml [--set path.to.key=value ...] | masonrydem check STUDY.yaml
  masonrydem predict PREDICTOR NAME=VALUE ...
  masonrydem fit LAB.csv --name NAME --setting KEY [--measured M] [--depth D] [--factor F --source S] ...

``check`` validates a scene or a study file and estimates what it runs
(pipeline/check.py) without building, drawing or running anything; ``predict`` evaluates a study's prediction equations
(predict.py); ``fit`` reads a lab's results and writes a study file's
variable block (analysis/labsheet.py, analysis/labfit.py).

Exit codes: 0 the run ended ok; 1 it ended not ok (its row says why:
status and message); 2 bad input, refused before any computation (the
message names the setting as the scene or the command line writes it); 3
an internal error (a run that raised still writes its row, status
'error').  With --exit-zero (the workflow's jobs), 0 whenever the row is
written: the row's status says how the run ended.

A study job (--samples) reads samples of a study's samples file and runs
the scene with each sample's settings: a batch, its runs of one mesh
advanced in lock-step, up to --lanes at a time (specimen/protocol.py,
simulate_many), each giving the bits it gives alone.  Each run writes its
row and curve as it ends, into --out with {sample} replaced by its number
(results/study/runs/nonspatial/sigma_v0.15/s{sample}); a sample the scene
refuses, or a run that fails, is a row with its status.  A run
reports its share of the process's start-up, ``startup_s``: from the
interpreter's start to the first simulation's start (imports and reading
the inputs), over the batch's runs.  Run as ``python -m masonrydem.cli``,
it skips the interpreter's teardown of numba and LLVM once its outputs
are written (0.2 s).
"""
import argparse
import os
import sys
import tempfile
import time
import traceback
from pathlib import Path

import yaml

from .errors import InputError
from .pipeline.check import explained, is_study, study_summary, summary
from .scene import build_scene, setting_unit, to_si
from .sources import __version__
from .study import load_study

# The solver (dem, specimen) and the analysis are imported inside the
# commands that need them: `check` and `predict` load no compiler and no
# scikit-learn (docs/architecture.md).


def check_threads(n):
    """``--threads``: between 1 and the cores numba may use."""
    from .dem import max_threads
    cores = max_threads()
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


def read_samples(path, numbers):
    """The samples ``numbers`` of a samples file (JSON: a list of records)."""
    from .specimen.row import read_json
    try:
        samples = {s.get("sample"): s for s in read_json(path)}
    except (OSError, ValueError) as e:
        raise InputError("--samples", f"cannot read {path}: {e}") from None
    missing = [n for n in numbers if n not in samples]
    if missing:
        raise InputError("--sample", f"{path} has no sample {missing[0]}")
    return [samples[n] for n in numbers]


def scenes_of(args):
    """The typed scenes of the command line: [(the scene, the sample's
    record or None, the sample's refusal or None)], the file with its --set
    overrides, then each --sample's settings.  A sample the scene refuses
    gives the scene without the sample and the refusal: the job records it
    as a run with status 'error'."""
    overrides = list(args.set) + (["outputs.state=true"] if args.state else [])
    if args.samples is None:
        if args.sample or args.variant is not None:
            raise InputError("--sample", "runs a study's sample: needs --samples FILE")
        return [(build_scene(args.scene, overrides), None, None)]
    if not args.sample or args.variant is None:
        raise InputError("--samples", "needs --variant V and --sample N (once or more)")
    if args.state:
        raise InputError("--state", "writes one run's final state: not with --samples (run the sample alone)")
    records = read_samples(args.samples, args.sample)
    out = []
    for sample in records:
        if "settings" not in sample:
            raise InputError("--samples", f"{args.samples}: sample {sample.get('sample')} has no settings: a samples "
                                          "file of an older version; rerun the study's sample rule")
        try:
            out.append((build_scene(args.scene, overrides, sample["settings"], f"{args.variant}:s{sample['sample']}"),
                        sample, None))
        except InputError as e:
            out.append((build_scene(args.scene, overrides), sample, e))
    return out


def _run(args):
    """``run``: one scene, or a batch of a study's samples."""
    check_threads(args.threads)
    if args.lanes < 1:
        raise InputError("--lanes", f"must be at least 1, got {args.lanes}")
    runs = scenes_of(args)
    if args.samples is None:
        outs = [output_dir(args.out)]
    elif "{sample}" not in args.out and len(runs) > 1:
        raise InputError("--out", f"{args.out} is one folder for {len(runs)} runs: write {{sample}} where each "
                                  "run's number goes (runs/s{sample})")
    else:
        outs = [output_dir(args.out.replace("{sample}", str(sample["sample"]))) for _, sample, _ in runs]
    from .dem import set_threads
    set_threads(args.threads)
    startup = time.time() - _process_start()
    if args.samples is None:
        return _run_one(args, runs[0][0], outs[0], startup)
    return _run_batch(args, runs, outs, startup)


def _run_one(args, scene, out, startup):
    from .specimen.row import empty_curve, error_row, write
    t0 = time.perf_counter()
    try:
        row, curve, state, error = _simulate(scene, not args.quiet)
    except Exception as e:   # nothing lost: the row says what happened
        traceback.print_exc()
        row = error_row(scene, e, time.perf_counter() - t0)
        curve, error = empty_curve(), e
        state = True if scene.outputs.state else None
    row.startup_s = startup
    write(out, row, curve, args.format, state)
    return _report(row, error, out, args.exit_zero)


def _simulate(scene, progress):
    """(row, curve, final state for VTK or None, None)."""
    from .specimen.protocol import simulate
    from .specimen.row import curve, outcome_row
    outcome = simulate(scene, progress=progress)
    state = None
    if scene.outputs.state:
        from .specimen.state import state_blocks
        state = state_blocks(outcome.specimen, outcome.state)
    return outcome_row(outcome), curve(outcome), state, None


def _run_batch(args, runs, outs, startup):
    """The samples of ``runs`` as a batch: each run's row and curve into
    its folder of ``outs`` as it ends, with a line."""
    from .specimen.protocol import simulate_many
    from .specimen.row import curve, empty_curve, error_row, outcome_row, sample_inputs, write
    codes, oks = [], []
    t0 = time.perf_counter()
    lanes = min(args.lanes, len(runs))

    def finish(i, outcome, error):
        scene, sample, refused = runs[i]
        labels = dict(variant=args.variant, sample=sample["sample"])
        inputs = sample.get("inputs", {})
        if error is None:
            try:
                row, run_curve = outcome_row(outcome, **labels, inputs=inputs, lanes=lanes), curve(outcome)
            except Exception as e:   # nothing lost
                error = e
        if error is not None:
            if not isinstance(error, InputError):
                traceback.print_exception(error)
            values = sample_inputs(sample, inputs) if refused is not None else None
            row = error_row(scene, error, time.perf_counter() - t0, **labels, inputs=inputs, values=values)
            run_curve = empty_curve()
        row.startup_s = startup / len(runs)
        write(outs[i], row, run_curve, args.format)
        codes.append(_report(row, error, outs[i], args.exit_zero, quiet=True))
        oks.append(row.ok)
        if not args.quiet:
            print(f"[{len(codes)}/{len(runs)}] {args.variant} s{row.sample}: {row.status}, P_max {row.P_max_kN:.3f} kN, "
                  f"{row.steps} steps ({time.perf_counter() - t0:.0f} s)", file=sys.stderr, flush=True)

    for i, (_, _, refused) in enumerate(runs):
        if refused is not None:
            finish(i, None, refused)
    simulate_many([scene for scene, _, refused in runs if refused is None],
                  _renumbered(finish, [i for i, (_, _, refused) in enumerate(runs) if refused is None]), lanes)
    print(f"{len(runs)} runs, {sum(oks)} ok, in {time.perf_counter() - t0:.1f} s on {lanes} lanes -> {args.out}")
    return max(codes)


def _renumbered(finish, index):
    """``finish`` called with the index of a run among all from its index
    among those simulated."""
    return lambda i, outcome, error: finish(index[i], outcome, error)


def _report(row, error, out, exit_zero, quiet=False):
    """The exit code of a run's row (module docstring); its lines unless ``quiet``."""
    if isinstance(error, InputError):   # found only once the model was built (or a sample the scene refused)
        print(f"masonrydem: invalid input: {error} (status 'error' -> {out})", file=sys.stderr)
        return 0 if exit_zero else 2
    if error is not None:
        print(f"masonrydem: internal error: {row.message} (status 'error' -> {out})", file=sys.stderr)
        return 0 if exit_zero else 3
    if not quiet:
        print(f"{row.status}: P_max {row.P_max_kN:.3f} kN at {row.disp_at_peak_mm:.3f} mm, "
              f"strength {row.strength_mpa:.3f} MPa, {row.classification}; "
              f"{row.steps} steps, {row.wall_time_s:.1f} s -> {out}")
    if not row.ok:
        print(f"masonrydem: the run ended not ok ({row.status}): {row.message}", file=sys.stderr)
    return 0 if row.ok or exit_zero else 1


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


def _check(args):
    """``check``: a scene or a study file validated and described; nothing
    built, drawn or run."""
    if is_study(args.scene):
        if args.set:
            raise InputError("--set", "changes a scene's settings; a study file's are its own: edit the file")
        print("\n".join(study_summary(load_study(args.scene))))
    else:
        print("\n".join(summary(build_scene(args.scene, args.set))))
    return 0


def _predict(args):
    """``predict``: a study's equations at the given inputs."""
    from .analysis.predict import both_directions
    inputs = {}
    for text in args.inputs:
        name, eq, value = text.partition("=")
        if not eq or not name.strip():
            raise InputError("predict", f"{text!r} is not NAME=VALUE (such as f_tu='3.5 MPa')")
        inputs[name.strip()] = value
    scene = build_scene(args.scene) if args.scene else None
    print("\n".join(both_directions(args.predictor, args.other, {n: n for n in inputs}, scene, inputs)))
    return 0


def _fit(args):
    """``fit``: a lab sheet's statistics, fits and characteristic values
    (as YAML comments), and with --name and --setting the study file's
    variable block they give (YAML on stdout)."""
    from .analysis import labfit, labsheet
    if bool(args.name) != bool(args.setting):
        given, missing = ("--name", "--setting") if args.name else ("--setting", "--name")
        raise InputError(missing, f"the study file's block needs both --name and --setting; {given} alone is "
                                  f"given (without either, fit prints the sheet's statistics alone)")
    unit = setting_unit(args.setting) if args.setting else "Pa"
    if unit is None:
        raise InputError("--setting", f"{args.setting!r} is not a numeric setting of a scene (scene/schema.yaml)")
    if args.resamples < 99:
        raise InputError("--resamples", f"{args.resamples}: at least 99 for a p-value to 0.01")
    depth = to_si(args.depth, "m", "--depth") if args.depth is not None else None
    lab = labsheet.read_sheet(args.lab, unit)
    if lab["form"] == "wallette":
        print("\n".join(f"# {line}" for line in labsheet.wallette_summary(lab)))
        return 0
    measured = lab["measured"] or args.measured
    if args.measured and lab["measured"] and args.measured != lab["measured"]:
        raise InputError("--measured", f"{args.measured}: a {lab['form'].replace('_', ' ')} sheet measures "
                                       f"{lab['measured']}")
    if args.name and measured is None:
        raise InputError("--measured", f"say what {lab['quantity']!r} measured: {', '.join(labsheet.CONVERSIONS)}")
    if not args.name:
        numbers, fits, dist = labfit.measured(lab, unit, args.seed, args.distribution, args.prior_cov, args.resamples)
        print("\n".join(f"# {line}" for line in labfit.summary(lab, numbers, fits, dist)))
        return 0
    factor, source = labsheet.conversion(measured, depth or lab["depth"], args.factor, args.source)
    entry, fits = labfit.block(lab, args.name, args.setting, unit, factor, source, args.seed, args.per,
                               args.distribution, args.prior_cov, args.resamples)
    e = entry[args.name]
    lines = labfit.summary(lab, e["provenance"]["lab"], fits, e["distribution"], (args.name, factor, source))
    print("\n".join(f"# {line}" for line in lines))
    print(yaml.safe_dump({"variables": entry}, sort_keys=False, width=100, allow_unicode=True), end="")
    return 0


def _fit_parser(sub):
    fit = sub.add_parser("fit", help="a lab's results (CSV): statistics, fits and characteristic values; with "
                                     "--name and --setting, a study file's variable block with its provenance")
    fit.add_argument("lab", help="the lab sheet: one column 'f_tj [MPa]', or a bond-wrench or unit flexural sheet")
    fit.add_argument("--name", help="the variable's name in the study file (with --setting: write its block)")
    fit.add_argument("--setting", help="the scene setting it drives, e.g. materials.joints.ft (with --name)")
    fit.add_argument("--per", choices=("unit", "joint"), help="what carries one value where a variant draws per item")
    fit.add_argument("--measured", help="what a results column measured: flexural_bond, modulus_of_rupture or "
                                        "as_is (a sheet of raw records says it itself)")
    fit.add_argument("--depth", help="the specimens' depth for the conversion of a results column, e.g. '100 mm'")
    fit.add_argument("--factor", type=float, help="the conversion factor by hand (needs --source)")
    fit.add_argument("--source", help="where --factor comes from")
    fit.add_argument("--distribution", choices=("lognormal", "normal"), help="default: the smaller AICc")
    fit.add_argument("--prior-cov", type=float, help="a documented prior COV: EN 1990's k_n with V_X known")
    fit.add_argument("--seed", type=int, default=0, help="the goodness of fit's bootstrap seed (default 0)")
    fit.add_argument("--resamples", type=int, default=999, help="its resamples (default 999)")


def parser():
    p = argparse.ArgumentParser(prog="masonrydem", description="Masonry micro-model DEM solver.",
                                epilog="exit codes: 0 ok, 1 the run ended not ok, 2 bad input, 3 internal error")
    p.add_argument("--version", action="version", version=f"masonrydem {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run one scene and write result.parquet, curve.parquet (and state.vtm)")
    run.add_argument("scene", help="scene YAML file (see config/scenes/willis.yaml)")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="override a scene setting, e.g. --set loading.precompression.pressure=0.15e6")
    run.add_argument("--out", required=True, help="output directory (with --samples: {sample} stands for each "
                                                  "run's number)")
    run.add_argument("--state", action="store_true", help="also write the final state (state.vtm)")
    run.add_argument("--quiet", action="store_true", help="no progress lines")
    run.add_argument("--threads", type=int, default=1, help="numba threads (default 1, at most the machine's cores)")
    run.add_argument("--format", choices=("parquet", "json"), default="parquet",
                     help="of result and curve (default parquet)")
    run.add_argument("--samples", help="a study's samples file (JSON): run one of its samples")
    run.add_argument("--sample", type=int, action="append", default=[],
                     help="with --samples: a sample's number (several: a batch)")
    run.add_argument("--lanes", type=int, default=8,
                     help="with --samples: the runs advanced in lock-step at a time (default 8)")
    run.add_argument("--variant", help="with --samples: the sample's variant (as the study file names it)")
    run.add_argument("--exit-zero", action="store_true",
                     help="exit 0 whenever the row is written (its status says how the run ended)")
    check = sub.add_parser("check", help="validate a scene or a study file and print what it would run, with its "
                                         "estimated time and memory; builds, draws and runs nothing")
    check.add_argument("scene", metavar="FILE", help="a scene or a study file (YAML)")
    check.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override a scene setting")
    pred = sub.add_parser("predict", help="a study's prediction equations: strength, load, failure mode and a "
                                          "95 %% prediction interval")
    pred.add_argument("predictor", help="the study's predictor file (its regression writes it: "
                                        "results/study/predictor.json)")
    pred.add_argument("--scene", help="your wallette's scene: refused unless it is the one the equations were "
                                      "fitted on")
    pred.add_argument("--other", help="the same study's predictor in the other bending direction: both, and mu")
    pred.add_argument("inputs", nargs="+", metavar="NAME=VALUE",
                      help="each input of the study's equations by its name in the study file, with its unit, "
                           "e.g. f_tu='3.5 MPa' (a plain number is SI)")
    _fit_parser(sub)
    return p


COMMANDS = dict(check=_check, predict=_predict, fit=_fit)   # and run (main)


def main(argv=None):
    """The command line ``argv``; the exit code."""
    args = parser().parse_args(argv)
    try:
        return _run(args) if args.command == "run" else COMMANDS[args.command](args)
    except InputError as e:
        print(f"masonrydem: invalid input: {explained(e)}", file=sys.stderr)
        return 2
    except Exception:
        traceback.print_exc()
        print("masonrydem: internal error (please report it with the traceback above)", file=sys.stderr)
        return 3


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
