"""The one place that reads or writes Snakemake's own state: its record of
each output (the metadata store that decides reruns), which the workflow
saves for a clone and puts back (workflow/rules/provenance.smk).

The layout is Snakemake's file persistence as read from Snakemake 9.27
(snakemake/persistence/file.py, FilePersistence._record_path): a record is
a JSON file under .snakemake/metadata whose name is the output's path in
URL-safe base64, cut into names one shorter than the file system allows
(255 on Linux, so 254), all but the last prefixed with '@' as folders.
pyproject.toml pins Snakemake to the range this was read from, and
tests/test_architecture.py runs Snakemake and fails when its records
are not where ``record_path`` says.
"""
import datetime
import json
import os
import sys
from base64 import urlsafe_b64encode
from pathlib import Path

METADATA = Path(".snakemake") / "metadata"


def record_path(path, root=METADATA):
    """Where Snakemake keeps the record of the output ``path`` (as the
    workflow names it, relative to its working directory)."""
    longest = os.pathconf(root if Path(root).exists() else ".", "PC_NAME_MAX") if os.name == "posix" else 255
    cut = (longest or 255) - 1
    b64 = urlsafe_b64encode(str(path).encode()).decode()
    parts = [b64[i:i + cut] for i in range(0, len(b64), cut)]
    return Path(root).joinpath(*[f"@{p}" for p in parts[:-1]], parts[-1])


def read_record(path, root=METADATA):
    """The record of ``path`` (a dict), or None where there is none."""
    try:
        return json.loads(record_path(path, root).read_text())
    except (OSError, ValueError):
        return None


def write_record(path, record, root=METADATA):
    """Writes the record of ``path``."""
    where = record_path(path, root)
    where.parent.mkdir(parents=True, exist_ok=True)
    where.write_text(json.dumps(record))


def recorded_paths(root=METADATA):
    """The outputs Snakemake holds a record of (their paths as ``record_path``
    encodes them)."""
    from base64 import urlsafe_b64decode
    for where in Path(root).rglob("*") if Path(root).is_dir() else ():
        if where.is_file():
            yield urlsafe_b64decode("".join(part.lstrip("@") for part in where.relative_to(root).parts)).decode()


def delete_record(path, root=METADATA):
    """Removes the record of ``path``, if there is one."""
    record_path(path, root).unlink(missing_ok=True)


# no job of this project ran before its first commit (November 2026), so
# none before 2026: an earlier time is a clock's zero or a lost record
EARLIEST = datetime.datetime(2026, 1, 1).timestamp()


def record_times_error(record):
    """What is impossible about a record's start and end times (Unix
    seconds), or None: a time missing, before 2026 or an end before the
    start (the report's run-time view would show a negative run time)."""
    start, end = record.get("starttime"), record.get("endtime")
    if start is None or end is None:
        return f"start {start}, end {end}: a time missing"
    if min(start, end) < EARLIEST:
        return f"{datetime.datetime.fromtimestamp(min(start, end)):%Y-%m-%d %H:%M}, before 2026"
    if end < start:
        return f"ends {start - end:.3g} s before it starts"
    return None


def building_report(argv=None):
    """Whether Snakemake was called to build a report (its --report option)."""
    return any(a == "--report" or a.startswith("--report=") for a in (sys.argv if argv is None else argv))
