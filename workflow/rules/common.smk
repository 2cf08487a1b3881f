import os

import masonrydem

R = config["results"]  # root of every output (config/smoke.yaml: .test/results)


def caption(name):
    """The caption of a report item, written by its rule with the numbers it
    found (template: workflow/report/NAME.rst; written to R/report/NAME.rst)."""
    return os.path.abspath(f"{R}/report/{name}.rst")


def template(name):
    return f"workflow/report/{name}.rst"


def effective(*lists):
    """Scene overrides in order, without those a later one replaces (same
    key): the parameters then say only what a run uses, so that changing a
    default that a run overrides anyway does not rerun it."""
    flat = [o for lst in lists for o in lst]
    keys = [o.split("=", 1)[0] for o in flat]
    return [o for i, o in enumerate(flat) if keys[i] not in keys[i + 1:]]


def get_solver_hash():
    """Hash of the solver's source: a param of every simulation rule, so that
    a change to src/ reruns the simulations (Snakemake does not track it)."""
    return masonrydem.source_hash()


def get_validation_runs():
    v = config["validation"]
    return [f"{c['name']}_sv{sv}" for c in v["cases"] for sv in v["precompression_mpa"]]


def get_validation_overrides(wildcards):
    """Scene overrides of one validation run: its case's plus the
    precompression."""
    case = {c["name"]: c["overrides"] for c in config["validation"]["cases"]}[wildcards.case]
    return effective(config["numerics"], case, [f"loading.precompression.pressure={float(wildcards.sv) * 1e6}"])


def get_validation_outputs():
    v = config["validation"]
    return (
        [R + "/validation/summary.csv", R + "/validation/load_displacement.png",
         R + "/validation/model_numbering.png"]
        + expand(R + "/validation/damage_{run}.png", run=v["pictures"])
    )


def reduced_cases():
    """Case -> overrides of the reduced-model comparison (config 'reduced')."""
    return {c["name"]: c["overrides"] for c in config.get("reduced", {}).get("cases", [])}


def get_reduced_outputs():
    return [R + "/reduced/summary.csv"] if config.get("reduced") else []


def specimen_cases():
    """Case -> {scene, overrides} of the further specimens (config 'specimens')."""
    return {c["name"]: c for c in config.get("specimens", [])}


def get_specimen_outputs():
    return [R + "/specimens/summary.csv"] if config.get("specimens") else []


def get_stability_outputs():
    return [R + "/stability/hard_cases.csv"] if config.get("hard_cases") else []


def get_study_runs(kind):
    """Every simulation's result (kind 'result') or curve file."""
    s = config["study"]
    suffix = ".parquet" if kind == "result" else "_curve.parquet"
    return expand(R + "/study/runs/{variant}/sv{sv}/s{sample}" + suffix, variant=s["variants"],
                  sv=s["precompression_mpa"], sample=range(s["n_samples"]))


def study_pictures():
    """(variant, failure mode) of the study's 3-D pictures."""
    return [(v, m) for v in config["study"]["variants"] for m in ("joint", "brick")]


def get_study_outputs():
    return [R + f"/study/pictures/{v}_{m}.png" for v, m in study_pictures()] + [R + "/study/" + name for name in (
        "statistics.csv", "correlations.csv", "increase.csv", "sampling_check.csv", "running_mean.png", "brick_share.png",
        "correlation_vs_sigma.png", "scatter_deviation.png", "curves_by_mode.png", "equations.csv",
        "predicted_vs_simulated.png", "design_comparison.png")]


# --- accuracy study (issue 5) -------------------------------------------
A = config.get("accuracy")


def grid_setting(cells, refine):
    return "c{}x{}x{}_r{}".format(*cells, refine)


def accuracy_grid():
    """Setting id -> mesh overrides: the grid cells x sub-contacts, the
    extra candidates and the finer path levels (on top of config numerics,
    like every accuracy run: the references then have the defaults' loading
    rate and stops, and the defaults' error is the mesh error alone)."""
    out = {}
    for cells in A["cells"]:
        for r in A["subcontact_refine"]:
            out[grid_setting(cells, r)] = [f"numerics.cells={list(cells)}", f"numerics.subcontact_refine={r}"]
    for cells in A["extra_cells"]:
        for r in A["extra_refine"]:
            out[grid_setting(cells, r)] = [f"numerics.cells={list(cells)}", f"numerics.subcontact_refine={r}"]
    r = max(A["subcontact_refine"])
    for cells in path_cells()[len(A["cells"]):]:
        out[grid_setting(cells, r)] = [f"numerics.cells={list(cells)}", f"numerics.subcontact_refine={r}"]
    return out


def accuracy_oat(case):
    """Setting id -> overrides of the defaults themselves and of one
    setting changed at a time, around the defaults or around the grid
    setting named by 'around' (e.g. the loading rate on a fine mesh)."""
    out = {"default": []}
    grid = accuracy_grid()
    for s in A["settings"]:
        if "around" in s and s["around"] not in grid:
            raise ValueError(f"config accuracy.settings {s['name']}.around: {s['around']!r} is not a grid setting "
                             f"(cells x subcontact_refine, extra_cells x extra_refine, path_cells)")
        if case in s.get("cases", [c["name"] for c in A["cases"]]):
            for v in s["values"]:
                out[f"{s['name']}_{v}"] = [*grid.get(s.get("around"), []), f"{s['key']}={v}"]
    return out


def accuracy_oat_baselines():
    """One-at-a-time setting id -> the setting it varies ('default' or its 'around')."""
    return {f"{s['name']}_{v}": s.get("around", "default") for s in A["settings"] for v in s["values"]} if A else {}


def path_cells():
    """The refinement path (run at the finest sub-contact refinement)."""
    return A["cells"] + A["path_cells"]


def get_accuracy_overrides(wildcards):
    case = {c["name"]: c["overrides"] for c in A["cases"]}[wildcards.case]
    setting = {**accuracy_grid(), **accuracy_oat(wildcards.case)}[wildcards.setting]
    return effective(config["numerics"], case, setting)


def get_accuracy_runs(kind):
    return [f"{R}/accuracy/runs/{c['name']}/{s}/{kind}.parquet"
            for c in A["cases"] for s in [*accuracy_grid(), *accuracy_oat(c["name"])]]


def get_subsample_runs(which):
    """The study's own runs ('default') or their reruns with fine settings."""
    sub = A["subsample"]
    root = "study/runs" if which == "default" else "accuracy/subsample"
    return expand(R + "/" + root + "/nonspatial/sv{sv}/s{sample}.parquet", sv=sub["precompression_mpa"],
                  sample=range(sub["n_samples"]))


def get_accuracy_outputs():
    if A is None:
        return []
    return [R + "/accuracy/" + name for name in (
        "runs.csv", "convergence.csv", "choice.csv", "pareto.png", "scaling.csv", "scaling.png",
        "subsample.csv", "subsample.png")]
