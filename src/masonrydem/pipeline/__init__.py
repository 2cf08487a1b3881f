"""What a workflow runs: every stage's runs and the scene overrides of
each (plan.py), a scene's or a study's cost estimated before anything
runs (check.py), and the one place that reads Snakemake's record store
(snakemake_state.py)."""

# its modules, each imported on its own: a caller of one loads no other's
# libraries (scikit-learn, matplotlib, pyvista)
__all__ = ["check", "fingerprint", "plan", "snakemake_state"]
