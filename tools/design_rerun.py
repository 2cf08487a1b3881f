"""Brute force against the re-weighting of a design target
(docs/lab-to-design.md, section 10): the study rerun from scratch at lab
draws that the design's interval rests on.

    python tools/design_rerun.py config/config.yaml config/studies/waal_lab_workflow.yaml

The workflow's design rule draws the lab fits' parameters theta*_b from its seed;
this takes the three whose re-weighted 5 % fractile at the first level is
the lab-only interval's lower end, its median and its upper end, draws a
fresh study of the same size at each (the lab-fitted variables' means and
COVs theta*_b, the others as the study file has them, a seed of its own),
runs it at every level, and sets its 5 % fractile (lognormal, with the
exact interval of its runs) beside the re-weighted one at the same
theta*_b.  Writes RESULTS/design/rerun.csv and prints it.
"""
import json
import sys
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from masonrydem.analysis import design, fractiles
from masonrydem.cli import main as cli
from masonrydem.pipeline import plan

RERUN_SEED = 7      # the fresh studies' samples: another seed than the study's


def _run(args):
    cli(args)
    return json.loads(Path(args[args.index("--out") + 1], "result.json").read_text())


def main(configs):
    config = {}
    for c in configs:
        config.update(yaml.safe_load(Path(c).read_text()))
    study, cfg, out = plan.study(config), config["design"], Path(config["results"], "design")
    runs = pd.read_parquet(Path(config["results"], "study", "runs.parquet"))
    runs = runs[(runs.variant == study.regression_variant) & runs.ok]
    lab, sampling, columns, _ = design.study_inputs(study, cfg.get("bond"), cfg.get("units"))
    boots = {v: (dist, vals, design.lab_draws(vals, dist, cfg["draws"], g))
             for (v, (dist, vals)), g in zip(lab.items(), np.random.default_rng(cfg["seed"]).spawn(len(lab)))}
    level = study.level_column()
    reweighted = {}
    for lv, g in runs.groupby(level):
        _, w, U, EU, VU = design.weighted_runs(
            {v: g[col].to_numpy() * scale for v, (col, scale) in columns.items()}, sampling, boots)
        reweighted[lv] = (np.exp(design.linear_replicates(np.log(g.strength_mpa.to_numpy()), U, w, EU, VU, 0.05, 0)[0]),
                          design.ess(w))
    lab_only = reweighted[min(reweighted)][0]
    picks = {q: int(np.nanargmin(np.abs(lab_only - np.nanpercentile(lab_only, q)))) for q in (2.5, 50, 97.5)}
    rows, jobs = [], []
    for q, b in picks.items():
        variables = tuple(replace(v, mean=float(boots[v.name][2][0][b]), cov=float(boots[v.name][2][1][b]))
                          if v.name in lab else v for v in study.variables)
        drawn = replace(study, variables=variables, seed=RERUN_SEED,
                        variants={"rerun": {"draw": "wallette", "correlation_length": None}}).draw("rerun")
        folder = out / "rerun" / f"q{q:g}"
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "samples.json").write_text(json.dumps(drawn.records()))
        for lv, si in zip(sorted(reweighted), study.levels):
            for s in range(study.samples):
                jobs.append((q, b, lv, ["run", study.scene, "--samples", str(folder / "samples.json"), "--sample",
                                        str(s), "--variant", "rerun", "--set", f"{study.sweep_setting}={si}",
                                        "--out", str(folder / f"{lv:g}" / f"s{s}"), "--format", "json", "--quiet",
                                        "--exit-zero"]))
    with ProcessPoolExecutor(2) as pool:
        results = list(pool.map(_run, [j[3] for j in jobs]))
    table = pd.DataFrame([dict(q=q, b=b, level=lv, strength=r["strength_mpa"], ok=r["ok"])
                          for (q, b, lv, _), r in zip(jobs, results)])
    for (q, lv), g in table[table.ok].groupby(["q", "level"]):
        b = picks[q]
        f, e = reweighted[lv][0][b], reweighted[lv][1][b]
        brute, lo, hi = fractiles.lognormal_fractile(g.strength.to_numpy())
        rows.append({level: lv, "lab_quantile": q, "draw": b,
                     **{f"{v}_mean_mpa": boots[v][2][0][b] / 1e6 for v in lab},
                     **{f"{v}_cov": boots[v][2][1][b] for v in lab},
                     "reweighted_mpa": float(f), "ess": float(e), "rerun_mpa": brute, "rerun_lo_mpa": lo,
                     "rerun_hi_mpa": hi, "rerun_runs": len(g), "inside": bool(lo <= f <= hi)})
    result = pd.DataFrame(rows)
    result.to_csv(out / "rerun.csv", index=False, float_format="%.4g")
    print(result.to_string())


if __name__ == "__main__":
    main(sys.argv[1:])
