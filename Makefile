# Set-up and entry points. `make reproduce` and `make test` work on a fresh machine.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: install reproduce report test test-browser bench bench-reduced mutants clean-cache slurm-up slurm-down test-cluster

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip

# the package and its test tools, at the versions the committed results were made with
CONSTRAINTS := workflow/envs/constraints.txt
$(STAMP): pyproject.toml $(CONSTRAINTS) | $(BIN)/python
	$(BIN)/pip install --quiet -e '.[test]' -c $(CONSTRAINTS)
	touch $(STAMP)

# the install alone: .venv with the package, editable, and its test extras
install: $(STAMP)

# A reproduction check: every committed study rerun from the code alone
# into a folder of its own (never into the committed results/), then
# compared with results/ (tools/compare_results.py).  First each further
# study, by its own workflow config (config/studies/*_workflow.yaml and
# formats/*_workflow.yaml): its study, and its design value where the
# config has a design section, into the reproduction's copy of its folder
# (results/studies/nf -> $(REPRO)/studies/nf).  Then the main workflow's
# default target and the model-form study, whose report pages of the
# further studies and brick formats' scores read those reruns
# (further_results), and the report.  The comparison walks results/: every
# study it holds, every run, derived table, predictor and design table;
# one missing or different exits 1.  Snakemake resumes an interrupted
# reproduction; rm -rf reproduction to start afresh.  ACCURACY=1 reruns
# the accuracy study too (hours more: README); otherwise its committed
# summaries are copied in for the report.
REPRO := reproduction/results
ACCURACY ?= 0
STUDY_CONFIGS := $(sort $(wildcard config/studies/*_workflow.yaml config/studies/formats/*_workflow.yaml))
# a study in its other bending direction (study: direction:) pairs with the
# first direction's runs: after every other one
PAIRED_CONFIGS := $(shell grep -l '^  direction:' $(STUDY_CONFIGS))
STUDY_CONFIGS := $(filter-out $(PAIRED_CONFIGS),$(STUDY_CONFIGS)) $(PAIRED_CONFIGS)
REPRO_CONFIG := results=$(REPRO) further_results=$(REPRO)/studies
reproduce: $(STAMP)
	@echo "make reproduce: the further studies ($(STUDY_CONFIGS:config/studies/%_workflow.yaml=%)), then validation,"
	@echo "the 1000-run study, hard cases, reduced models, specimens and the model-form study, rerun into"
	@echo "$(REPRO) (its time on two cores: README), then $(REPRO)/report.zip and a comparison"
	@echo "of every committed study, run by run and table by table, with results/."
	@set -e; for f in $(STUDY_CONFIGS); do \
	  out=$$(sed -n 's|^results: *results/|$(REPRO)/|p' $$f); \
	  test -n "$$out" || { echo "$$f: its results folder is not under results/"; exit 1; }; \
	  targets="study$$(grep -q '^design:' $$f && echo ' design' || true)"; \
	  echo "$$f: $$targets into $$out"; \
	  $(BIN)/snakemake --cores 2 $$targets --configfile config/config.yaml $$f --config results=$$out; \
	done
	@$(BIN)/snakemake all modelform $(if $(filter 1,$(ACCURACY)),accuracy) --config $(REPRO_CONFIG) -n --quiet rules
	$(BIN)/snakemake --cores 2 all modelform $(if $(filter 1,$(ACCURACY)),accuracy) --config $(REPRO_CONFIG)
ifneq ($(ACCURACY),1)
	@echo "The accuracy study is not rerun (ACCURACY=1 reruns it): its committed summaries go into the report."
	mkdir -p $(REPRO)/accuracy $(REPRO)/report/tables
	cp results/accuracy/*.csv results/accuracy/*.png $(REPRO)/accuracy/
	cp results/report/accuracy_*.rst $(REPRO)/report/
	cp results/report/tables/accuracy_*.html $(REPRO)/report/tables/
endif
	$(BIN)/snakemake --report $(REPRO)/report.zip all accuracy modelform --config $(REPRO_CONFIG)
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
# the result row, classification, the study file, its sampling and terms,
# statistics, equations, Sobol indices and their check on the solver,
# fractiles, brick formats, predict, the lab sheet, its fit and the design
# value, the validation tables, captions, the landing page), each run
# against the tests that guard its module: every one must be caught; a
# fault whose text no longer matches fails the tool, and
# tests/test_mutants.py in `make test` (benchmarks/mutants.py)
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
