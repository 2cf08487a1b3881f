"""Deterministic validation of the wallette (docs/study.md, 5): peaks, initial
stiffness, and the sensitivity of the peak to the loading rate and to the
mesh."""
import numpy as np
import pandas as pd

from . import equations as E
from .plots import save_figure
from . import statistics as A


def initial_stiffness(curve, lo=0.1, hi=0.4):
    """Slope (kN/mm) of a straight line fitted to the pre-peak points of the
    load-displacement curve between lo and hi times the peak load."""
    ipk = int(np.argmax(curve["load_kN"].to_numpy()))
    pre = curve.iloc[: ipk + 1]
    P, u = pre["load_kN"].to_numpy(), pre["displacement_mm"].to_numpy()
    sel = (P >= lo * P.max()) & (P <= hi * P.max())
    if sel.sum() < 2:
        return np.nan
    return float(np.polyfit(u[sel], P[sel], 1)[0])


def summary_table(results, curves):
    """One row per run ('<case>_sv<sigma_v>'), with the change of P_max
    against the 'reference' case at the same precompression."""
    rows = []
    for run, r in results.items():
        case = run.rsplit("_sv", 1)[0]
        rows.append(dict(run=run, case=case, sigma_v_mpa=r["sigma_v_mpa"], P_max_kN=r["P_max_kN"],
                         disp_at_peak_mm=r["disp_at_peak_mm"], strength_mpa=r["strength_mpa"],
                         initial_stiffness_kN_per_mm=initial_stiffness(curves[run]),
                         failure_mode=r["failure_mode"], status=r["status"], steps=r["steps"],
                         wall_time_s=r["wall_time_s"], classification=r["classification"]))
    t = pd.DataFrame(rows).sort_values(["sigma_v_mpa", "case"]).reset_index(drop=True)
    ref = t[t.case == "reference"].set_index("sigma_v_mpa")["P_max_kN"]
    t["P_max_change_vs_reference_pct"] = [
        100.0 * (p / ref[s] - 1.0) if s in ref.index else np.nan for p, s in zip(t.P_max_kN, t.sigma_v_mpa)]
    return t


def figure(table, curves, path):
    """Load against displacement of the validation runs, one panel per
    level.  The half-rate curve is drawn dashed over the reference, which
    is drawn wide and light beneath it: where they agree, both stay in
    sight.  There is no measured curve to set beside them; each panel
    says so."""
    import matplotlib.pyplot as plt
    levels = sorted(table.sigma_v_mpa.unique())
    fig, axes = plt.subplots(1, len(levels), figsize=(5 * len(levels), 4.5), squeeze=False)
    style = {"reference": dict(color="0.65", lw=4.5, zorder=1),
             "half_rate": dict(color="tab:blue", ls=(0, (4, 2)), lw=1.5, zorder=3),
             "strong_joints": dict(color="tab:red", lw=1.5, zorder=2)}
    for ax, sv in zip(axes[0], levels):
        for _, r in table[table.sigma_v_mpa == sv].iterrows():
            c = curves[r.run]
            ax.plot(c.displacement_mm, c.load_kN, label=f"{r.case}: {r.P_max_kN:.2f} kN ({r.failure_mode})",
                    **style.get(r.case, {}))
        ax.set_title(f"$\\sigma_v$ = {sv:g} MPa")
        ax.set_xlabel("load-line displacement (mm)")
        ax.set_ylabel("total load $P$ (kN)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=10, loc="lower right")
        ax.text(0.98, 0.26, "no measured curve: none is available\nfor this wallette (docs/study.md, 5)",
                transform=ax.transAxes, ha="right", va="bottom", fontsize=10, color="0.35")
    fig.tight_layout()
    save_figure(fig, path)


def hard_cases_table(results, expect):
    """One row per hard-case run (results: run id -> result row): outcome,
    peak, steps and the unbalanced-force ratio at the peak; whether the
    failure mode is the one the strengths call for (``expect``: case ->
    'joint', 'brick' or 'any'); for a half-rate rerun the change of P_max
    against its case."""
    rows = []
    for run, r in results.items():
        case = run.removesuffix("_half_rate")
        change = 100.0 * (r["P_max_kN"] / results[case]["P_max_kN"] - 1.0) if run != case else np.nan
        rows.append(dict(run=run, case=case, expect=expect[case], status=r["status"], ok=r["ok"], failure_mode=r["failure_mode"],
                         mode_as_expected=expect[case] in ("any", r["failure_mode"]), P_max_kN=r["P_max_kN"],
                         disp_at_peak_mm=r["disp_at_peak_mm"], steps=r["steps"], peak_step=r["peak_step"],
                         ratio_at_peak=r["ratio_at_peak"],
                         unbalance_at_peak=r["unbalance_at_peak"], post_peak=r["post_peak"], wall_time_s=r["wall_time_s"],
                         half_rate_change_pct=change, message=r["message"]))
    return pd.DataFrame(rows)


def reduced_table(results, tolerance, scenes):
    """The reduced models against the full one (results: (case, model) ->
    result row; model 'full' is the reference; scenes: (case, model) -> the
    typed scene): per run the joints' tensile bond, P_max, its change, the
    failure mode, steps, run time and speed-up, and whether the reduced
    model is good enough (P_max within ``tolerance`` and the same mode)."""
    rows = []
    for (case, model), r in results.items():
        full = results[(case, "full")]
        change = r["P_max_kN"] / full["P_max_kN"] - 1.0
        f_tj = scenes[(case, model)].value("materials.joints.ft") / 1e6
        rows.append(dict(case=case, model=model, sigma_v_mpa=r["sigma_v_mpa"], f_tj_mpa=f_tj,
                         status=r["status"], P_max_kN=r["P_max_kN"], change_pct=100.0 * change,
                         failure_mode=r["failure_mode"], steps=r["steps"], wall_time_s=r["wall_time_s"],
                         speedup=full["wall_time_s"] / r["wall_time_s"],
                         good_enough=bool(r["ok"] and abs(change) <= tolerance
                                          and r["failure_mode"] == full["failure_mode"])))
    return pd.DataFrame(rows)


def modelform_table(results, labels):
    """The model-form study (results: (case, sigma_v, option) -> result
    row; option 'baseline', the scene as it stands, is the reference of its
    case and level; labels: option -> (assumption, the option's label),
    pipeline.plan.modelform_labels): per run the assumption and the
    option's label, P_max, its change against the baseline, the failure
    mode and whether it changed."""
    rows = []
    for (case, sv, option), r in results.items():
        base = results[(case, sv, "baseline")]
        rows.append(dict(case=case, sigma_v_mpa=sv, assumption=labels[option][0], option=labels[option][1],
                         status=r["status"], P_max_kN=r["P_max_kN"],
                         change_pct=100.0 * (r["P_max_kN"] / base["P_max_kN"] - 1.0), failure_mode=r["failure_mode"],
                         mode_changed=r["failure_mode"] != base["failure_mode"], steps=r["steps"]))
    return pd.DataFrame(rows)


def specimen_table(results, curves, scenes):
    """One row per further specimen (tension, triplet): peak, the test's
    stress at the peak and at the end of the run (the mean over the last
    tenth of the displacement).  Triplets also get the
    Coulomb closed forms of their bed joints: peak shear stress
    c_j + sigma_v tan(phi) (every point of the joint at its strength at
    once) and residual sigma_v tan(phi) (cohesion gone, friction left)."""
    rows = []
    for case, r in results.items():
        sc, curve = scenes[case], curves[case]
        u = curve["displacement_mm"]
        end = float(curve["load_kN"][u >= 0.9 * u.max()].mean()) / r["P_max_kN"]   # the last tenth
        row = dict(case=case, test=sc.loading.test, sigma_v_mpa=r["sigma_v_mpa"],
                   f_tj_mpa=sc.value("materials.joints.ft") / 1e6,
                   P_max_kN=r["P_max_kN"], disp_at_peak_mm=r["disp_at_peak_mm"], stress_mpa=r["strength_mpa"],
                   end_stress_mpa=end * r["strength_mpa"], failure_mode=r["failure_mode"], status=r["status"],
                   steps=r["steps"], wall_time_s=r["wall_time_s"], classification=r["classification"])
        if row["test"] == "triplet":
            j = sc.materials.joints       # a triplet's joints alike: the first one's properties
            mu = np.tan(np.radians(j.phi[0]))
            row.update(peak_closed_form_mpa=(j.c[0] + sc.loading.precompression.pressure * mu) / 1e6,
                       residual_closed_form_mpa=r["sigma_v_mpa"] * mu)
            row.update(peak_error=row["stress_mpa"] / row["peak_closed_form_mpa"] - 1,
                       residual_error=row["end_stress_mpa"] / row["residual_closed_form_mpa"] - 1)
        rows.append(row)
    return pd.DataFrame(rows)


def specimen_figure(table, curves, path):
    """Tension: load against the pulled faces' displacement; triplet: shear
    stress on the bed joints against the middle unit's slip, with the
    closed-form peak (dashed) and residual (dotted)."""
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    for r in table[table.test == "tension"].itertuples():
        c = curves[r.case]
        a.plot(c.displacement_mm, c.load_kN, label=f"{r.case}: {r.P_max_kN:.1f} kN, {r.failure_mode}")
    a.set(xlabel="displacement of the pulled faces (mm)", ylabel="load P (kN)",
          title="direct tension parallel to the bed joints")
    for r in table[table.test == "triplet"].itertuples():
        c = curves[r.case]
        line, = b.plot(c.displacement_mm, c.load_kN / r.P_max_kN * r.stress_mpa,
                       label=f"sigma_v {r.sigma_v_mpa:g} MPa: peak {r.stress_mpa:.3f} MPa")
        b.axhline(r.peak_closed_form_mpa, ls="--", lw=0.8, color=line.get_color())
        b.axhline(r.residual_closed_form_mpa, ls=":", lw=0.8, color=line.get_color())
    b.set(xlabel="slip of the middle unit (mm)", ylabel="shear stress P / 2A (MPa)",
          title="triplet shear\n(dashed: c + sigma tan phi, dotted: sigma tan phi)")
    for ax in (a, b):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


# --- design rules (docs/study.md, 14) -------------------------------------------------
def lourenco_gaetani(c_j, f_tu, overlap, unit_height):
    """Lower bounds of Lourenco & Gaetani: stepped (joint) failure
    f = c_j l_o / h_b; brick failure f = f_tu / 2 (MPa)."""
    return c_j * overlap / unit_height, 0.5 * f_tu


def as3700(f_mt, f_ut, f_d):
    """AS3700 horizontal bending at mean values (capacity factor 1,
    k_p = 1): stepped f = 2 sqrt(f_mt)(1 + f_d / f_mt), capped at
    4 sqrt(f_mt); line f = 0.44 f_ut + 0.56 f_mt (MPa)."""
    f_d = np.asarray(f_d, float)
    stepped = np.minimum(2.0 * np.sqrt(f_mt) * (1.0 + f_d / f_mt), 4.0 * np.sqrt(f_mt))
    line = np.full_like(f_d, 0.44 * f_ut + 0.56 * f_mt)
    return stepped, line


def as3700_vertical(f_mt, f_d):
    """AS3700 vertical bending at mean values (capacity factor 1): the
    bond with the precompression, f = f_mt + f_d, capped at 3 f_mt (MPa;
    M_cv = phi f'_mt Z_d + f_d Z_d <= 3 phi f'_mt Z_d, clause 7.4.2 as a
    secondary source gives it: docs/study.md, 14)."""
    f_d = np.asarray(f_d, float)
    return np.minimum(f_mt + f_d, 3.0 * f_mt)


def design_inputs(scene):
    """What the design rules need of a typed scene (the study's wallette at
    its mean properties): the overlap l_o = bond offset x modelled unit
    length and the height h_b of a modelled unit (unit + joint), in m; the
    joints' c_ratio (c_j = c_ratio f_tj); the joints' tensile bond f_tj
    (ft_joints) and the units' tensile strength f_tu (ft_units), in MPa,
    means over the joints and units."""
    g, j = scene.geometry, scene.materials.joints
    return dict(l_o=g.bond_overlap, h_b=g.modelled_unit[2], c_ratio=j.c_ratio,
                ft_joints=scene.value("materials.joints.ft") / 1e6, ft_units=scene.value("materials.units.ft") / 1e6)


def design_table(fits, ns, resid_sd, levels, design, means, columns, level, level_column, direction="horizontal"):
    """Against the precompression ``levels``: the lower-of-two prediction
    at the mean properties with a band of one standard deviation, which
    combines the scatter of the prediction over the sampled properties
    (the inputs of the samples of ``ns``) with the residual scatter the
    equations leave (inputs they do not use, and the misfit); the
    prediction's mean over the samples; the Lourenco-Gaetani and AS3700
    rules at the mean properties (``design``: ``design_inputs``; AS3700
    f_mt from f_tj, the flexural bond ~ the joint's tensile bond, f_ut from
    f_tu).  NaN predictions without an equation.  ``means``: each input's
    mean (Study.means), ``columns``: the inputs' columns in ``ns``,
    ``level``: the precompression's name as an input, ``level_column``
    its column (the table's first).  In vertical bending (``direction``)
    AS3700's vertical rule instead (``as3700_vertical``): the horizontal
    rules' planes of failure are not its."""
    f_tu, f_tj = design["ft_units"], design["ft_joints"]
    pred = band = prop_sd = prop_mean = np.full_like(levels, np.nan)
    if fits:
        joint, brick = E.joint_and_brick(fits)
        pred, _ = E.lower_of_two(joint, brick, {**means, level: levels})
        props = ns.drop_duplicates("sample")            # the properties of every sample with an ok run
        prop_mean, prop_sd = E.prediction_over_samples(joint, brick, E.inputs_of(props, columns), level, levels)
        band = np.sqrt(prop_sd ** 2 + resid_sd ** 2)
    curves = dict(prediction=pred, band_sd=band, property_sd=prop_sd, mean_over_samples=prop_mean)
    if direction == "vertical":
        return pd.DataFrame({level_column: levels, **curves, "as3700_vertical": as3700_vertical(f_tj, levels)})
    lg = lourenco_gaetani(design["c_ratio"] * f_tj, f_tu, design["l_o"], design["h_b"])
    as_stepped, as_line = as3700(f_tj, f_tu, levels)
    return pd.DataFrame({level_column: levels, **dict(**curves, lg_stepped=lg[0], lg_brick=lg[1],
                                                      as3700_stepped=as_stepped, as3700_line=as_line)})


# --- the source paper side by side (docs/study.md, 17; docs/findings.md) ---------------
def paper_equation(paper, mode, terms):
    """The paper's Eq. 10 for ``mode`` as an equation for equations.predict,
    on our ``terms`` (a term it does not have has coefficient 0; its terms
    are named as our study file names its inputs)."""
    c = paper["equations"][mode]
    unknown = set(c) - {"intercept", *terms}
    if unknown:
        raise ValueError(f"the paper's {mode} equation has terms our study's equations lack: {sorted(unknown)}")
    return dict(intercept=float(c["intercept"]), coef={k: float(c.get(k, 0.0)) for k in terms})


def _card_row(item, mode, sv, paper, ours, lo=np.nan, hi=np.nan):
    """One line of the scorecard; the difference in % of the paper's value."""
    return dict(item=item, mode=mode, sigma_v_mpa=sv, paper=paper, ours=ours, ours_lo=lo, ours_hi=hi,
                difference_pct=100.0 * (ours / paper - 1.0) if paper else np.nan,
                paper_inside=bool(lo <= paper <= hi) if np.isfinite([paper, lo, hi]).all() else None)


def _per_sample(runs, values):
    """Sums of ``values`` (a column per statistic) and run counts per sample:
    the parts of a ratio statistic whose samples are resampled whole."""
    g = pd.DataFrame(values, index=runs.index).assign(_n=1.0).groupby(runs["sample"]).sum()
    return g.drop(columns="_n").to_numpy(), g["_n"].to_numpy()


def _ratio_rows(runs, values, resamples, seed):
    """Point estimates and 95 % bootstrap intervals of sum(values) / runs."""
    num, den = _per_sample(runs, values)
    lo, hi = A.bootstrap_interval(len(den), lambda i: (num[i].sum(1) / den[i].sum(1)[:, None]).T, resamples, seed)
    return num.sum(0) / den.sum(), lo, hi


def paper_comparison(paper, runs, stats, inc, equations, spec, resamples, seed, settle_tol=0.01):
    """The scorecard: every published figure of ``paper`` (config/paper.yaml)
    beside ours on the same variant, with our 95 % interval (from the
    tables' _lo/_hi columns, or resampled here), the difference and
    whether the paper's value lies inside.  Also the paper's Eq. 10 on our
    runs (MAPE, bias), both equations at the mean properties (P_max, kN),
    and the run (in sample order) from which the running mean at the
    highest level stays within ``settle_tol`` of its final value.
    ``spec``: the study's (pipeline.plan.analysis: its terms, its inputs'
    columns and means, its swept setting's name and column)."""
    v, level, terms = paper["variant"], spec["level_column"], tuple(spec["terms"])
    runs = runs[(runs.variant == v) & runs.ok]
    st = stats[stats.variant == v].set_index(["mode", level])
    rows = []
    for mode, fig in paper["f_max_kN"].items():
        for sv, mean, cov in zip(paper["precompression_mpa"], fig["mean"], fig["cov"]):
            hit = [k for k in st.index if k[0] == mode and np.isclose(k[1], sv)]
            if hit:
                r = st.loc[hit[0]]
                rows += [_card_row("F_max mean (kN)", mode, sv, mean, r.P_max_mean_kN, r.P_max_mean_kN_lo,
                                   r.P_max_mean_kN_hi),
                         _card_row("F_max COV", mode, sv, cov, r.P_max_cov, r.P_max_cov_lo, r.P_max_cov_hi)]
    modes = runs.failure_mode.to_numpy()
    share, lo, hi = _ratio_rows(runs, np.column_stack([modes == "joint", modes == "brick"]), resamples, seed)
    total = sum(paper["failures"].values())
    rows += [_card_row(f"failures (of {total} runs)", m, np.nan, paper["failures"][m], share[k] * total,
                       lo[k] * total, hi[k] * total) for k, m in enumerate(("joint", "brick"))]
    i = inc[inc.variant == v].set_index("mode")
    rows += [_card_row("increase of the mean, lowest to highest level (%)", m, np.nan, p, 100 * i.increase[m],
                       100 * i.increase_lo[m], 100 * i.increase_hi[m]) for m, p in paper["increase_pct"].items()
             if m in i.index]
    eqs = equations.set_index("mode")
    for m in ("joint", "brick"):
        if m in eqs.index and np.isfinite(eqs.intercept.get(m, np.nan)):
            p = paper_equation(paper, m, terms)
            rows += [_card_row(f"Eq. 10 coefficient: {t}", m, np.nan, (p["coef"] | {"intercept": p["intercept"]})[t],
                               eqs.loc[m].get(t, np.nan), eqs.loc[m].get(f"{t}_lo", np.nan),
                               eqs.loc[m].get(f"{t}_hi", np.nan))
                     for t in ("intercept",) + terms]
    if "lower of two" in eqs.index:
        r = eqs.loc["lower of two"]
        rows.append(_card_row("Eq. 10 MAPE (%)", "lower of two", np.nan, paper["equations"]["mape_pct"], r.mape_pct,
                              r.mape_pct_lo, r.mape_pct_hi))
    rows += _paper_equation_on_runs(paper, runs, terms, spec["columns"], resamples, seed)
    rows += _equations_at_means(paper, eqs, terms, spec["means"], spec["level"])
    top = runs[np.isclose(runs[level], max(paper["precompression_mpa"]))].sort_values("sample")
    if len(top):
        rm = A.running_mean(top.P_max_kN)
        off = np.flatnonzero(np.abs(rm / rm[-1] - 1.0) > settle_tol)
        rows.append(_card_row(f"running mean within {100 * settle_tol:g} % of its final value from run", "all",
                              max(paper["precompression_mpa"]), paper["running_mean_settles_after"],
                              float(off[-1] + 2 if off.size else 1)))
    return pd.DataFrame(rows)


def _paper_equation_on_runs(paper, runs, terms, columns, resamples, seed):
    """The paper's Eq. 10 scored on our runs of each mode, and the lower of
    its two on all: MAPE and bias (mean of (predicted - simulated) /
    simulated), in %."""
    rows = []
    joint, brick = (E.predict(paper_equation(paper, m, terms), E.inputs_of(runs, columns)) for m in ("joint", "brick"))
    for m, pred in (("joint", joint), ("brick", brick), ("lower of two", np.minimum(joint, brick))):
        sel = (runs.failure_mode == m).to_numpy() if m != "lower of two" else np.ones(len(runs), bool)
        if sel.sum() == 0:
            continue
        e = 100.0 * (pred[sel] - runs.strength_mpa.to_numpy()[sel]) / runs.strength_mpa.to_numpy()[sel]
        est, lo, hi = _ratio_rows(runs[sel], np.column_stack([np.abs(e), e]), resamples, seed)
        own = paper["equations"]["mape_pct"] if m == "lower of two" else np.nan     # its MAPE on its own runs
        rows += [_card_row(f"Eq. 10 on our runs: {name} (%)", m, np.nan, p, est[k], lo[k], hi[k])
                 for k, (name, p) in enumerate((("MAPE", own), ("bias", np.nan)))]
    return rows


def _equations_at_means(paper, eqs, terms, means, level):
    """P_max (kN) at the study's mean properties (``means``: input -> its
    mean) and each of the paper's levels (of the input ``level``) by the
    paper's Eq. 10 and by ours (of the ``terms``), mode by mode."""
    eq = paper["equations"]
    per_kN = 6.0 * eq["moment_arm_m"] / (eq["section_b_m"] * eq["section_h_m"] ** 2) / 1e3   # MPa per kN
    rows = []
    for m in ("joint", "brick"):
        if m not in eqs.index or not np.isfinite(eqs.intercept.get(m, np.nan)):
            continue
        ours = dict(intercept=eqs.loc[m, "intercept"], coef={t: eqs.loc[m, t] for t in terms})
        for sv in paper["precompression_mpa"]:
            p, o = (float(E.predict(e, {**means, level: sv})[0]) / per_kN
                    for e in (paper_equation(paper, m, terms), ours))
            rows.append(_card_row("equation at the mean properties: P_max (kN)", m, sv, p, o))
    return rows
