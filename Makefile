# Set-up and entry points. `make reproduce` and `make test` work on a fresh machine.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: reproduce report test test-browser bench bench-reduced mutants clean-cache slurm-up slurm-down test-cluster

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(STAMP)

# A reproduction check: every simulation but the accuracy study's, rerun
# from the code alone into a folder of its own (never into the committed
# results/), its report, then run by run against the committed tables
# (tools/compare_results.py; exit status 1 when a run differs).  Snakemake
# resumes an interrupted reproduction; rm -rf reproduction to start afresh.
# ACCURACY=1 reruns the accuracy study too (hours more: README); otherwise
# its committed summaries are copied in for the report.
REPRO := reproduction/results
ACCURACY ?= 0
reproduce: $(STAMP)
	@echo "make reproduce: validation, the 1000-run study, hard cases, reduced models, specimens and the"
	@echo "model-form study, rerun into $(REPRO) (its time on two cores: README), then"
	@echo "$(REPRO)/report.zip and a run-by-run comparison with results/."
	@$(BIN)/snakemake all modelform $(if $(filter 1,$(ACCURACY)),accuracy) --config results=$(REPRO) -n --quiet rules
	$(BIN)/snakemake --cores 2 all modelform $(if $(filter 1,$(ACCURACY)),accuracy) --config results=$(REPRO)
ifneq ($(ACCURACY),1)
	@echo "The accuracy study is not rerun (ACCURACY=1 reruns it): its committed summaries go into the report."
	mkdir -p $(REPRO)/accuracy $(REPRO)/report/tables
	cp results/accuracy/*.csv results/accuracy/*.png $(REPRO)/accuracy/
	cp results/report/accuracy_*.rst $(REPRO)/report/
	cp results/report/tables/accuracy_*.html $(REPRO)/report/tables/
endif
	$(BIN)/snakemake --report $(REPRO)/report.zip all accuracy modelform --config results=$(REPRO)
	$(BIN)/python tools/compare_results.py results $(REPRO) $(if $(filter 1,$(ACCURACY)),,--copied accuracy/runs.csv)

# the report of the committed results (results/report.zip; on a clone it
# reruns nothing: docs/workflow.md, "Reusing committed results")
report: $(STAMP)
	$(BIN)/snakemake --report results/report.zip all accuracy modelform

# the suite in TEST_WORKERS processes (pytest-xdist), a test file's tests in
# one of them: from a fresh clone most of its time is numba compiling the
# kernels' specialisations, a process at a time each
TEST_WORKERS ?= 2
test: $(STAMP)
	$(BIN)/python -m pytest -q -rs -n $(TEST_WORKERS) --dist loadfile

# the committed report (results/report.zip) in headless Chromium: the landing
# page readable at 1280x800 and 1920x1080, its links working, the key tables
# shown in place; screenshots in .test/browser/ (tests/test_report_browser.py,
# part of `make test` where Chromium is installed: apt-get install chromium)
test-browser: $(STAMP)
	$(BIN)/python -m pytest -q -rs -m browser tests/test_report_browser.py

bench: $(STAMP)
	$(BIN)/python benchmarks/bench.py

# the reduced models of the wallette (rigid, elastic units) against the full
# one: P_max change and speed-up per case (snakemake reduced)
bench-reduced: $(STAMP)
	$(BIN)/snakemake --cores 2 --quiet progress reduced
	$(BIN)/python -c "import pandas as pd; print(pd.read_csv('results/reduced/summary.csv').to_string(index=False))"

# seeded faults in every module of the study's end (masonry rules, units,
# the result row, classification, the study file and its sampling,
# statistics, equations, Sobol indices, fractiles, brick formats, predict,
# the validation tables, captions), each run against the tests that guard
# its module: every one must be caught, a fault whose text no longer
# matches fails the tool (benchmarks/mutants.py; about 7 minutes)
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
