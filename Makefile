# framefree — two commands: `make demo` (the main job) and `make test` (the test suite).
# Both create the virtual environment in .venv on first use and install everything needed.

PYTHON ?= python3
VENV   ?= .venv
BIN     = $(VENV)/bin
STAMP   = $(VENV)/.framefree-installed

.PHONY: demo test lint bench env clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[dev,robot]"
	touch $(STAMP)

env: $(STAMP)

demo: $(STAMP)
	$(BIN)/framefree demo

# Two workers on two cores, each running the compiled kernels on one thread: with two threads
# each, OpenMP's idle threads took 13 % more CPU and the suite 6 % longer.
test: $(STAMP)
	NUMBA_NUM_THREADS=1 $(BIN)/python -m pytest -n 2 -m "not realtime"
	$(BIN)/python -m pytest -m realtime

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_core.py

clean:
	rm -rf $(VENV) .pytest_cache .ruff_cache
