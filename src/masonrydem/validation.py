"""Deterministic validation of the wallette (docs/study.md, 5): peaks, initial
stiffness, and the sensitivity of the peak to the loading rate and to the
mesh."""
import numpy as np
import pandas as pd


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
    import matplotlib.pyplot as plt
    levels = sorted(table.sigma_v_mpa.unique())
    fig, axes = plt.subplots(1, len(levels), figsize=(6 * len(levels), 4.5), squeeze=False)
    style = {"reference": dict(color="k", lw=2), "half_rate": dict(color="tab:blue", ls="--"),
             "strong_joints": dict(color="tab:red", lw=1.5)}
    for ax, sv in zip(axes[0], levels):
        for _, r in table[table.sigma_v_mpa == sv].iterrows():
            c = curves[r.run]
            ax.plot(c.displacement_mm, c.load_kN, label=f"{r.case}: {r.P_max_kN:.2f} kN ({r.failure_mode})",
                    **style.get(r.case, {}))
        ax.set_title(f"sigma_v = {sv:g} MPa")
        ax.set_xlabel("load-line displacement (mm)")
        ax.set_ylabel("total load P (kN)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


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


def reduced_table(results, tolerance):
    """The reduced models against the full one (results: (case, model) ->
    result row; model 'full' is the reference): per run P_max, its change,
    the failure mode, steps, run time and speed-up, and whether the reduced
    model is good enough (P_max within ``tolerance`` and the same mode)."""
    rows = []
    for (case, model), r in results.items():
        full = results[(case, "full")]
        change = r["P_max_kN"] / full["P_max_kN"] - 1.0
        rows.append(dict(case=case, model=model, sigma_v_mpa=r["sigma_v_mpa"], f_tj_mpa=r["f_tj_mpa"],
                         status=r["status"], P_max_kN=r["P_max_kN"], change_pct=100.0 * change,
                         failure_mode=r["failure_mode"], steps=r["steps"], wall_time_s=r["wall_time_s"],
                         speedup=full["wall_time_s"] / r["wall_time_s"],
                         good_enough=bool(r["ok"] and abs(change) <= tolerance
                                          and r["failure_mode"] == full["failure_mode"])))
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
        row = dict(case=case, test=sc.loading.test, sigma_v_mpa=r["sigma_v_mpa"], f_tj_mpa=r["f_tj_mpa"],
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
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
