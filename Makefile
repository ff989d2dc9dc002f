# Two entry points (see README): `make demo` and `make test`.
# Both create a virtual environment inside the checkout on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test lint setup bench

$(BIN)/qdsega: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	# torch 2.13.0 (CPU) first, where a file of it is on disk: stable-baselines3 (the bench
	# extra) would otherwise pull a CUDA build of several GB; elsewhere pip fetches it.
	$(BIN)/pip install --quiet torch==2.13.0
	$(BIN)/pip install --quiet -e ".[test,ray,bench]"
	touch $(BIN)/qdsega

setup: $(BIN)/qdsega

# The main job: assemble, learn snake5 in memo mode, check it with exact physics, film it,
# draw it and write one HTML page, all into runs/demo/ (replaced on every run).
DEMO := runs/demo

demo: setup
	$(BIN)/qdsega assemble assemblies/*.yaml --out-dir out/assemblies
	$(BIN)/qdsega train assemblies/snake5.yaml --sim memo --preset paper-snake \
		--generations 8 --workers 2 --seed 0 --out $(DEMO) --overwrite
	$(BIN)/qdsega evaluate $(DEMO)
	$(BIN)/qdsega render $(DEMO) -o $(DEMO)/gait.mp4
	$(BIN)/qdsega plot $(DEMO)
	$(BIN)/qdsega report $(DEMO)

lint: setup
	$(BIN)/ruff check qdsega tools tests
	$(BIN)/ruff format --check qdsega tools tests

test: lint
	$(BIN)/pytest -q -n 2 --dist worksteal

# BENCHMARKS.md from scratch (about an hour on 2 cores; re-running continues a stopped one).
bench: setup
	$(BIN)/qdsega bench --out benchmarks --jobs 2
