"""The report: its captions' numbers (captions.py), figures
(figures.py) and 3-D pictures (pictures.py)."""
