"""The report: its captions' numbers (captions.py), figures
(figures.py) and 3-D pictures (pictures.py)."""

# its modules, each imported on its own: a caller of one loads no other's
# libraries (scikit-learn, matplotlib, pyvista)
__all__ = ["captions", "directions", "figures", "landing", "pictures", "tables"]
