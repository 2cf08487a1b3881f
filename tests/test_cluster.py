"""The cluster path for real: the smoke study through SLURM with the
cluster profile (profiles/slurm: per-rule resources, a batch of the
study's simulations a cluster job), the whole smoke DAG end to end,
against the smoke study's simulations run locally (`snakemake --cores 2`,
target study/runs.parquet: the rest of the DAG does not change P_max), bit
for bit in P_max; and a batch job killed with scancel.  About 20 min on two busy
cores.  Needs a running SLURM (`make test-cluster` starts a one-node one with
tools/local-slurm.sh); skipped when `sinfo` does not answer, and never part
of `make test` (pyproject.toml deselects the marker)."""
import shutil
import subprocess
import sys
import time

import pandas as pd
import pytest

pytestmark = pytest.mark.cluster

SNAKEMAKE = [sys.executable, "-m", "snakemake"]
SMOKE = ["--configfile", "config/smoke.yaml"]


def slurm_answers():
    """None if SLURM is up (sinfo lists a partition that is up), else why not."""
    if shutil.which("sinfo") is None:
        return "no SLURM here (sinfo not found): start one with `make slurm-up` (tools/local-slurm.sh)"
    try:
        r = subprocess.run(["sinfo", "-h", "-o", "%P %a"], capture_output=True, text=True, timeout=30)
    except subprocess.TimeoutExpired:
        return "sinfo did not answer in 30 s: is slurmctld running? (make slurm-up)"
    if r.returncode != 0:
        return f"sinfo does not answer ({r.stderr.strip()[:200]}): start SLURM with `make slurm-up`"
    if not any(line.split()[-1:] == ["up"] for line in r.stdout.splitlines()):
        return f"no partition is up: {r.stdout.strip()!r}"
    return None


def sacct(run_id):
    """The cluster jobs of one Snakemake run (its jobs are named by its run id)."""
    out = subprocess.run(["sacct", "-X", "-P", "-n", "--name", run_id, "-S", "now-1days", "-o",
                          "JobID,State,AllocCPUS,ReqMem,Timelimit,Elapsed,Comment"],
                         capture_output=True, text=True, check=True).stdout
    cols = ["job", "state", "cpus", "mem", "timelimit", "elapsed", "comment"]
    return pd.DataFrame([line.split("|") for line in out.splitlines() if line], columns=cols)


@pytest.fixture(scope="module")
def cluster():
    reason = slurm_answers()
    if reason:
        pytest.skip(reason)


@pytest.fixture(scope="module")
def local(cluster, tmp_path_factory):
    """The smoke study's simulations and their table, run locally."""
    res = tmp_path_factory.mktemp("local") / "results"
    t0 = time.monotonic()
    r = subprocess.run(SNAKEMAKE + [f"{res}/study/runs.parquet", "--cores", "2"] + SMOKE
                       + ["--config", f"results={res}"], capture_output=True, text=True)
    assert r.returncode == 0, (r.stdout + r.stderr)[-5000:]
    print(f"\nsmoke study's runs locally: {time.monotonic() - t0:.0f} s")
    return pd.read_parquet(res / "study" / "runs.parquet")


def planned_submissions(cmd):
    """What a cluster run of ``cmd`` will submit, from its own dry run: every
    job it plans that has outputs (a rule with inputs only, like `all`,
    runs nowhere).  Returns (that count, the planned batches of the study's
    simulations, the simulations they hold)."""
    import re
    text = subprocess.run(cmd + ["-n"], capture_output=True, text=True, check=True).stdout
    alone, rule = 0, None
    for line in text.splitlines():
        if m := re.match(r"(?:local)?rule (\w+):$", line):
            rule = m.group(1)
        elif line.startswith("    output:") and rule:
            alone, rule = alone + 1, None
        elif line.startswith("["):
            rule = None
    batches = re.findall(r"rule simulate_\d+:\n(?:\s+input:.*\n)?\s+output: (.*)\n", text)
    return alone, len(batches), sum(b.count("result.json") for b in batches)


@pytest.fixture(scope="module")
def runs(cluster, tmp_path_factory):
    """The whole smoke DAG on the cluster, end to end, and what its plan
    said it would submit."""
    root = tmp_path_factory.mktemp("cluster")
    cmd = SNAKEMAKE + ["--profile", "profiles/slurm"] + SMOKE + ["--config", f"results={root}"]
    expected = planned_submissions(cmd)
    t0 = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    log = r.stdout + r.stderr
    assert r.returncode == 0, log[-5000:]
    print(f"\nsmoke through SLURM (whole DAG): {time.monotonic() - t0:.0f} s")
    run_id = [x.split()[-1] for x in log.splitlines() if x.startswith("SLURM run ID:")][0]
    return root, run_id, log, expected


def same_p_max(a, b):
    """Same rows, and P_max the same float64s bit for bit, not merely close."""
    key = ["variant", "sigma_v_mpa", "sample"]
    a, b = a.sort_values(key).reset_index(drop=True), b.sort_values(key).reset_index(drop=True)
    assert len(a) == len(b) == 32 and (a[key] == b[key]).all().all()
    assert (a.P_max_kN.to_numpy().view("u8") == b.P_max_kN.to_numpy().view("u8")).all()
    assert (a.failure_mode == b.failure_mode).all() and (a.status == b.status).all()


def test_cluster_study_matches_local_bit_for_bit(runs, local):
    root = runs[0]
    same_p_max(pd.read_parquet(root / "study" / "runs.parquet"), local)


def test_cluster_jobs_were_batches_and_accounted(runs):
    """Every job went through SLURM and its accounting: as many jobs
    submitted, and accounted, as the run's own plan holds (its dry run);
    the study's 32 simulations were 4 batch jobs of 8 (config/smoke.yaml:
    batch.runs), each on one core with a batch's runtime (a minute a run,
    at least 10), and every job completed."""
    root, run_id, log, (expected, batches, simulations) = runs
    jobs = sacct(run_id)
    submitted = [x for x in log.splitlines() if "has been submitted with SLURM jobid" in x]
    assert (batches, simulations) == (4, 32) and len(jobs) == len(submitted) == expected, (expected, jobs.to_string())
    assert (jobs.state == "COMPLETED").all(), jobs.to_string()
    study = jobs[jobs.comment.str.match(r"rule_simulate_\d+")]
    assert len(study) == 4, jobs.to_string()
    for g in study.itertuples():
        assert (g.cpus, g.mem, g.timelimit) == ("1", "2000M", "00:10:00"), g
    assert (root / "study" / "statistics.csv").stat().st_size > 0


def test_killed_batch_job_rerun_finishes_only_what_is_missing(local, tmp_path):
    """scancel a batch job of the study's simulations while it runs:
    Snakemake reports the failure (no retry here: --retries 0) and keeps
    the batches that had finished; the rerun plans and runs only the
    killed batch's simulations (and any not started), and the table
    matches the local run bit for bit."""
    import re
    res = tmp_path / "results"
    cmd = SNAKEMAKE + [f"{res}/study/runs.parquet", "--profile", "profiles/slurm"] + SMOKE + ["--config",
                                                                                             f"results={res}"]
    out = tmp_path / "killed.log"  # a file, not a pipe: Snakemake would block on a full pipe
    with open(out, "w") as f:
        p = subprocess.Popen(cmd + ["--retries", "0"], stdout=f, stderr=subprocess.STDOUT)
        killed = None
        deadline = time.monotonic() + 1800
        while p.poll() is None and time.monotonic() < deadline:
            time.sleep(2)
            if killed is None:
                q = subprocess.run(["squeue", "-h", "-t", "RUNNING", "-o", "%i %k"], capture_output=True, text=True)
                ids = [x.split()[0] for x in q.stdout.splitlines() if re.match(r"rule_simulate_\d+", x.split()[-1])]
                if ids:
                    subprocess.run(["scancel", ids[0]], check=True)
                    killed = ids[0]
        if p.poll() is None:
            p.kill()
    log = out.read_text()
    assert killed, "no batch job was seen running: " + log[-3000:]
    assert p.returncode not in (0, None) and "Error in rule simulate_" in log, log[-3000:]
    kept = len(list((res / "study" / "runs").glob("*/sigma_v*/s*/curve.json")))
    assert kept < 32 and kept % 8 == 0, kept
    plan = subprocess.run(cmd + ["-n"], capture_output=True, text=True).stdout
    batches = re.findall(r"rule simulate_\d+:\n(?:\s+input:.*\n)?\s+output: (.*)\n", plan)
    assert sum(b.count("result.json") for b in batches) == 32 - kept, plan[-3000:]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, (r.stdout + r.stderr)[-5000:]
    same_p_max(pd.read_parquet(res / "study" / "runs.parquet"), local)
