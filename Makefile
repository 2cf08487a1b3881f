# Set-up and entry points. `make reproduce` and `make test` work on a fresh machine.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: reproduce test bench bench-reduced mutants clean-cache slurm-up slurm-down test-cluster

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(STAMP)

# the default target (all but the accuracy and model-form studies, whose
# committed summaries it reuses), then the report; says first what it will run
reproduce: $(STAMP)
	@echo "make reproduce: validation, the 1000-run study, hard cases, reduced models and specimens,"
	@echo "then results/report.zip: 30 to 45 minutes on two cores from a fresh clone (README)."
	@echo "The accuracy and model-form studies are not rerun: their committed summaries are reused"
	@echo "(snakemake --cores 2 accuracy modelform)."
	@$(BIN)/snakemake -n --quiet rules
	$(BIN)/snakemake --cores 2
	$(BIN)/snakemake --report results/report.zip all accuracy modelform

test: $(STAMP)
	$(BIN)/python -m pytest -q

bench: $(STAMP)
	$(BIN)/python benchmarks/bench.py

# the reduced models of the wallette (rigid, elastic units) against the full
# one: P_max change and speed-up per case (snakemake reduced)
bench-reduced: $(STAMP)
	$(BIN)/snakemake --cores 2 --quiet progress reduced
	$(BIN)/python -c "import pandas as pd; print(pd.read_csv('results/reduced/summary.csv').to_string(index=False))"

# seeded faults in the analysis, classification, sampling, masonry rules and
# result tables, each run against the tests that guard its module: every
# one must be caught (benchmarks/mutants.py; about 5 minutes)
mutants: $(STAMP)
	$(BIN)/python benchmarks/mutants.py

clean-cache:
	find src -name __pycache__ -type d -exec rm -rf {} +

# A one-node SLURM cluster on this machine (root: apt-get installs munge,
# slurm-wlm, slurmdbd, mariadb-server), and the smoke study through the
# cluster profile against the same study run locally (tests/test_cluster.py;
# not part of `make test`: pyproject.toml deselects the marker "cluster").
slurm-up:
	tools/local-slurm.sh start

slurm-down:
	tools/local-slurm.sh stop

test-cluster: $(STAMP) slurm-up
	$(BIN)/python -m pytest -q -m cluster -rs tests/test_cluster.py
