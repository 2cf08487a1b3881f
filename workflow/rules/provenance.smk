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
# Two things make the records enough:
# - every step that collects simulations carries, as its parameter
#   'simulations', the solver's source hash and every run's settings
#   (get_runs): the runs' own files are not committed, so on a clone a
#   changed solver or setting is seen there and reruns all they affect;
# - every step run by a script carries its code as a parameter (get_code), and the
#   profile's rerun triggers leave out 'code', which compares the script's
#   file time.
import base64
import functools
import hashlib
import json
from pathlib import Path
from types import SimpleNamespace

PROVENANCE = f"{R}/provenance.json"
METADATA = Path(".snakemake") / "metadata"
# the rules whose outputs are one run each: not committed, so not recorded
PER_RUN_RULES = {"simulate", "simulate_fine", "accuracy_run", "accuracy_check_run", "accuracy_scaling_run",
                 "modelform_run", "hard_case_run", "reduced_run", "specimen_run"}
# what a record keeps: Snakemake's fields that decide a rerun (not the
# command line, which names this machine's interpreter, nor times)
RECORD = ("rule", "input", "log", "params", "code", "record_format_version", "conda_env", "container_img_url",
          "software_stack_hash", "input_checksums")


def _digest(*items):
    return hashlib.sha256(json.dumps(items, sort_keys=True, default=str).encode()).hexdigest()[:16]


@functools.cache
def _module_code(name):
    return masonrydem.source_code(name, (Path(masonrydem.__file__).parent / name).read_text())


def _package_imports(text, inside):
    """The package's modules a source imports (absolute imports of
    masonrydem, and relative ones ``inside`` the package)."""
    import ast
    names = set()
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level == 1 and inside or base.split(".")[0] == "masonrydem":
                sub = base.removeprefix("masonrydem").lstrip(".")
                names |= {sub.split(".")[0]} if sub else {a.name for a in node.names}
        elif isinstance(node, ast.Import):
            names |= {a.name.split(".")[1] for a in node.names if a.name.startswith("masonrydem.")}
    here = Path(masonrydem.__file__).parent
    return {f"{n}.py" for n in names if (here / f"{n}.py").is_file()}


@functools.cache
def _module_imports(name):
    """The package's modules that a package module imports (each parsed once)."""
    return frozenset(_package_imports((Path(masonrydem.__file__).parent / name).read_text(), True))


@functools.cache
def _modules_used(name):
    """A package module and every package module it imports, transitively."""
    found, todo = set(), {name}
    while todo:
        n = todo.pop()
        found.add(n)
        todo |= _module_imports(n) - found
    return frozenset(found)


def get_code(script):
    """What decides a script rule's outputs besides its inputs and settings:
    the script and the package's modules it imports, transitively
    (docstrings and comments aside); the solver's source hash stands for
    those outside the analysis modules (masonrydem.ANALYSIS_ONLY)."""
    text = Path(workflow.basedir, "workflow", "scripts", f"{script}.py").read_text()
    used = set().union(*(_modules_used(m) for m in _package_imports(text, False)))
    analysis = sorted(used & set(masonrydem.ANALYSIS_ONLY))
    return _digest(masonrydem.source_code(f"{script}.py", text), *(_module_code(n) for n in analysis),
                   get_solver_hash() if used - set(analysis) else None)


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
    return get_runs(get_study_sets, [dict(level=d) for d in plan.study_level_dirs(config)], repr(get_study_design()),
                    scene=get_study_scene())


def _record_path(path):
    """Where Snakemake's file store keeps the record of an output
    (snakemake/persistence/file.py: the path in URL-safe base64, cut into
    names of at most 254 characters)."""
    b64 = base64.urlsafe_b64encode(str(path).encode()).decode()
    parts = [b64[i:i + 254] for i in range(0, len(b64), 254)]
    return METADATA.joinpath(*[f"@{p}" for p in parts[:-1]], parts[-1])


def _sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest() if Path(path).is_file() else None


@functools.cache
def _single_run(path):
    """Whether ``path`` is a single run's output (not committed)."""
    return any(workflow.get_rule(name).is_producer(path) for name in PER_RUN_RULES)


def _kept(record, saved):
    """What a saved record keeps: RECORD's fields, with the checksums of the
    inputs that are committed (outside R, saved themselves, or under R but
    no single run's output: a table kept as data, such as the accuracy
    study's references), and paths under R written from '{R}/' (a copy of
    the results elsewhere is judged as the results are)."""
    def rel(path):
        return f"{{R}}/{path[len(R) + 1:]}" if path.startswith(f"{R}/") else path
    kept = {k: record.get(k) for k in RECORD}
    kept["input"] = [rel(f) for f in record.get("input") or []]
    kept["log"] = [rel(f) for f in record.get("log") or []]
    kept["input_checksums"] = {rel(f): s for f, s in (record.get("input_checksums") or {}).items()
                               if f in saved or not f.startswith(f"{R}/") or not _single_run(f)}
    return kept


def _placed(record):
    """A saved record with its paths under this R."""
    def here(path):
        return f"{R}{path[3:]}" if path.startswith("{R}/") else path
    return dict(record, input=[here(f) for f in record["input"]], log=[here(f) for f in record["log"]],
                input_checksums={here(f): s for f, s in record["input_checksums"].items()})


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
        record = _record_path(path)
        try:
            local = json.loads(record.read_text())
        except (OSError, ValueError):
            local = None
        if local and ((local.get("endtime") or 0) >= newer_than or _kept(local, entries) == entry["record"]):
            continue
        record.parent.mkdir(parents=True, exist_ok=True)
        record.write_text(json.dumps(_placed(entry["record"])))


def save_provenance():
    """Save the records of every output under R but the single runs' to
    R/provenance.json (paths relative to R)."""
    records = {}
    for path in sorted(p for p in Path(R).rglob("*") if p.is_file()):
        try:
            record = json.loads(_record_path(path).read_text())
        except (OSError, ValueError):
            continue
        if record.get("rule") not in PER_RUN_RULES and not record.get("incomplete"):
            records[path.as_posix()] = record
    entries = {Path(p).relative_to(R).as_posix(): {"sha256": _sha256(p), "record": _kept(r, records)}
               for p, r in records.items()}
    text = json.dumps(entries, indent=1, sort_keys=True) + "\n"
    if not Path(PROVENANCE).is_file() or Path(PROVENANCE).read_text() != text:
        Path(PROVENANCE).write_text(text)
