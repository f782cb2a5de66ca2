# Each target sets itself up on a fresh machine: .venv, the package and its dependencies.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test test-slow lint bench figures clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install -qq --upgrade pip
	$(BIN)/pip install -qq -e '.[test,sim,city,fbx]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/python -m shapegen.demo

# The quick lane on every core; the slowest tests are printed. The long validations (marked
# slow) run in `make test-slow`; CI runs both.
test: $(STAMP)
	$(BIN)/python -m pytest -q -n auto -m "not slow" --durations=15

test-slow: $(STAMP)
	$(BIN)/python -m pytest -q -n auto -m slow --durations=15

lint: $(STAMP)
	$(BIN)/ruff check shapegen tests benchmarks docs
	$(BIN)/ruff format --check shapegen tests benchmarks docs/*.py

# The quicker benchmarks; the others (statics up to 10 000 blocks, simulation) are listed in
# docs/performance.md with their commands.
bench: $(STAMP)
	$(BIN)/python benchmarks/bench_derivation.py
	$(BIN)/python benchmarks/bench_contacts.py
	$(BIN)/python benchmarks/bench_interactive.py
	$(BIN)/python benchmarks/bench_rules.py

# The figures the README and docs/ state (rewritten where the code now gives others) and their
# pictures, remade from the code: docs/make_figures.py (long: the parthenon's searches, the
# design page in Chromium). `.venv/bin/python docs/make_figures.py --check` changes nothing.
figures: $(STAMP)
	$(BIN)/python docs/make_figures.py

clean:
	rm -rf $(VENV) out build *.egg-info
