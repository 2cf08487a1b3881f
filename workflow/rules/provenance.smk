# Provenance that survives a clone (docs/workflow.md, "Reusing committed results").
#
# Snakemake decides what to rerun from its record of each output (rule,
# parameters, input files and their checksums: .snakemake/metadata), and,
# where it has none, from file times.  A clone has no record, and git does
# not keep file times, so every committed result would look out of date.
# So after every successful run the records of the results under R are
# saved to R/provenance.json, and on a checkout that lacks them (a clone)
# or holds older ones (a pull) they are put back before Snakemake plans.
# Then Snakemake judges a clone as it judges the workspace that made the
# results: an input newer than an output is compared by checksum, a changed
# parameter reruns the job.
#
# A record also keeps its job's start and end times, which the report's
# run-time view shows (restored with a job id of their own: the outputs of
# one job count as one job).  A record saved without them (before they were
# kept) stands for a job whose times are unknown: when the report is built
# it is left out, as Snakemake leaves out an output without a record, and a
# record whose times are impossible refuses the report (check_record_times).
#
# Two things make the records enough:
# - every step that collects simulations carries, as its parameter
#   'simulations', the solver's source hash and every run's settings
#   (get_runs): the runs' own files are not committed, so on a clone a
#   changed solver or setting is seen there and reruns all they affect;
# - every step run by a script carries its code as a parameter (get_code), and the
#   profile's rerun triggers leave out 'code', which compares the script's
#   file time.
import functools
import sys
import hashlib
import json
from pathlib import Path
from types import SimpleNamespace

from masonrydem.pipeline.fingerprint import code_fingerprint
from masonrydem.pipeline.snakemake_state import (building_report, delete_record, read_record, record_path,
                                                 record_times_error, recorded_paths, write_record)

PROVENANCE = f"{R}/provenance.json"
# the rules whose outputs are runs: not committed, so not recorded (and the
# batches of the study's runs, simulate_<k> and simulate_fine_<k>)
PER_RUN_RULES = {"accuracy_run", "accuracy_check_run", "accuracy_scaling_run", "modelform_run", "hard_case_run",
                 "reduced_run", "specimen_run"}


def per_run_rule(name):
    """Whether the rule ``name`` makes runs (PER_RUN_RULES)."""
    return name in PER_RUN_RULES or (name or "").startswith("simulate_")
# what a record keeps: Snakemake's fields that decide a rerun (not the
# command line, which names this machine's interpreter), and the job's
# times for the report
RECORD = ("rule", "input", "log", "params", "code", "record_format_version", "conda_env", "container_img_url",
          "software_stack_hash", "input_checksums", "starttime", "endtime")


def _digest(*items):
    return hashlib.sha256(json.dumps(items, sort_keys=True, default=str).encode()).hexdigest()[:16]


def get_code(script):
    """What decides a script rule's outputs besides its inputs and settings:
    the script and the package's modules it imports, transitively
    (masonrydem.pipeline.fingerprint)."""
    return code_fingerprint(Path(workflow.basedir, "workflow", "scripts", f"{script}.py"))


def get_file_digest(path):
    """A source file by its content: the parameter that stands for a scene
    file, an input of the single runs marked ancient (their records are
    not saved, and a clone's file times say nothing)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16]


def get_runs(sets, runs, *extra, scene=None):
    """What decides the simulations a step collects: the solver's source
    hash, the scene (config's unless given) and each run's settings
    (``sets`` of each run's wildcards)."""
    return _digest(get_solver_hash(), get_file_digest(scene or config["scene"]),
                   [sets(SimpleNamespace(**w)) for w in runs], *extra)


def get_study_runs_key():
    """get_runs of the study: every level's settings and the samples' seed
    (their number is in the list of inputs)."""
    return get_runs(get_study_sets, [dict(level=d) for d in plan.study_level_dirs(config)], get_study_draw(),
                    scene=get_study_scene())


def _sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest() if Path(path).is_file() else None


@functools.cache
def _run_products():
    """The products of the rules that make runs (Rule.is_producer's, read
    once): the paths without wildcards as a set, the patterns with them as
    their regular expressions."""
    products = [o for r in workflow.rules if per_run_rule(r.name) for o in r.products()]
    return ({str(o) for o in products if not o.get_wildcard_names()},
            [o.regex() for o in products if o.get_wildcard_names()])


@functools.cache
def _single_run(path):
    """Whether ``path`` is a single run's output (not committed)."""
    paths, patterns = _run_products()
    return path in paths or any(p.match(path) for p in patterns)


def _kept(record, saved):
    """What a saved record keeps: RECORD's fields, with the checksums of the
    inputs that are committed (outside R, saved themselves, or under R but
    no single run's output: a table kept as data, such as the accuracy
    study's references), and paths under R written from '{R}/' (a copy of
    the results elsewhere is judged as the results are)."""
    def rel(path):
        return f"{{R}}/{path[len(R) + 1:]}" if path.startswith(f"{R}/") else path
    kept = {k: record.get(k) for k in RECORD if k not in ("starttime", "endtime") or record.get(k) is not None}
    kept["input"] = [rel(f) for f in record.get("input") or []]
    kept["log"] = [rel(f) for f in record.get("log") or []]
    kept["input_checksums"] = {rel(f): s for f, s in (record.get("input_checksums") or {}).items()
                               if f in saved or not f.startswith(f"{R}/") or not _single_run(f)}
    return kept


def _placed(record):
    """A saved record with its paths under this R, and a job id that is the
    same for the outputs of one job (its rule and start time)."""
    def here(path):
        return f"{R}{path[3:]}" if path.startswith("{R}/") else path
    job = int(_digest(record["rule"], record.get("starttime")), 16) if record.get("starttime") else None
    return dict(record, input=[here(f) for f in record["input"]], log=[here(f) for f in record["log"]],
                input_checksums={here(f): s for f, s in record["input_checksums"].items()}, job_hash=job)


def restore_provenance():
    """Put the saved records back where this checkout has none, or an older
    one than the saved file (a pull brought newer results) that differs,
    for each output that is the file the record describes (same checksum)
    or is not here (a run's picture state, not committed)."""
    saved = Path(PROVENANCE)
    if not saved.is_file():
        return
    newer_than = saved.stat().st_mtime
    entries = {f"{R}/{name}": entry for name, entry in json.loads(saved.read_text()).items()}
    for path, entry in entries.items():
        if Path(path).exists() and _sha256(path) != entry["sha256"]:
            continue
        local = read_record(path)
        if local and ((local.get("endtime") or 0) >= newer_than or _kept(local, entries) == entry["record"]):
            continue
        write_record(path, _placed(entry["record"]))


def check_record_times():
    """When the report is built: the records of the outputs under R as the
    report's run-time view reads them.  A record without times (put back
    from a file saved before times were kept: its job ran elsewhere, when
    is not known) is removed, so that the view leaves its job out (the
    next run puts it back); a record whose times are impossible refuses
    the report, naming its output."""
    unknown, wrong = [], []
    for path in sorted(p for p in recorded_paths() if p.startswith(f"{R}/")):
        record = read_record(path)
        if record is None or record.get("incomplete"):
            continue
        if record.get("starttime") is None and record.get("endtime") is None:
            unknown.append(path)
        elif error := record_times_error(record):
            wrong.append(f"{path} (made by {record.get('rule')}): {error}")
    for path in unknown:
        delete_record(path)
    if unknown:
        print(f"masonrydem: {len(unknown)} outputs under {R} have records without run times (put back from "
              f"{PROVENANCE}, saved before times were kept): their jobs are left out of the report's run times",
              file=sys.stderr)
    if wrong:
        print("masonrydem: the report is refused: these records' run times are impossible (Snakemake's "
              "records, .snakemake/metadata); rerun their jobs (snakemake --forcerun RULE) or remove the "
              "records (snakemake --cleanup-metadata FILE):\n  " + "\n  ".join(wrong), file=sys.stderr)
        sys.exit(1)


def save_provenance():
    """Save the records of every output under R but the single runs' to
    R/provenance.json (paths relative to R); a folder below R with a
    provenance.json of its own is another workflow's results (a further
    study's), whose records are its own."""
    records = {}
    others = [p.parent for p in Path(R).rglob("provenance.json") if p.parent != Path(R)]
    for path in sorted(p for p in Path(R).rglob("*") if p.is_file()):
        if any(path.is_relative_to(other) for other in others):
            continue
        record = read_record(path)
        if record is None:
            continue
        if not per_run_rule(record.get("rule")) and not record.get("incomplete"):
            records[path.as_posix()] = record
    entries = {Path(p).relative_to(R).as_posix(): {"sha256": _sha256(p), "record": _kept(r, records)}
               for p, r in records.items()}
    text = json.dumps(entries, indent=1, sort_keys=True) + "\n"
    if not Path(PROVENANCE).is_file() or Path(PROVENANCE).read_text() != text:
        Path(PROVENANCE).write_text(text)
