"""What a study's runs say: statistics with bootstrap intervals
(statistics.py), prediction equations (equations.py) and ``predict``
(predict.py), Sobol indices (sensitivity.py), characteristic strengths
(fractiles.py), the equations on other brick formats (brick_formats.py),
the deterministic tables, design rules and the source paper's scorecard
(validation.py), and what accuracy costs in time (accuracy.py).

Every function takes the study's names and numbers (its inputs' columns,
its swept setting, its terms) as arguments."""

# its modules, each imported on its own: a caller of one loads no other's
# libraries (scikit-learn, matplotlib, pyvista)
__all__ = ["accuracy", "brick_formats", "design", "equations", "fractiles", "labfit", "labsheet", "needs", "plots",
           "predict", "sensitivity", "sobol_check", "statistics", "validation"]
