# Two entry points (see README): `make demo` and `make test`.
# Both create a virtual environment inside the checkout on first use.
# The interpreter .venv is made with: PYTHON=... where given, else tools/pick_python.sh picks
# python3.11 (pybullet has wheels for it), else the newest of 3.13 and 3.12.
PYTHON ?=
VENV := .venv
BIN := $(VENV)/bin
# The bench extra's PPO needs torch. A plain `pip install torch` pulls a CUDA build of several
# GB; give a CPU index to get the CPU build instead, e.g.
#   make test TORCH_INDEX=https://download.pytorch.org/whl/cpu
# (left empty, pip takes torch from its usual sources, a local CPU wheel where one is there).
TORCH_INDEX ?=

.PHONY: demo test test-fast ruff lint bench

# The core package alone: everything the demo needs.
$(BIN)/qdsega: pyproject.toml
	@python="$$(PYTHON='$(PYTHON)' /bin/sh tools/pick_python.sh)" && echo "$$python -m venv $(VENV)" \
		&& "$$python" -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e .
	touch $@

# The test, Ray, bench and mjcf extras on top (torch first, so that it comes from TORCH_INDEX).
$(VENV)/extras: $(BIN)/qdsega
	$(BIN)/pip install --quiet $(if $(TORCH_INDEX),--index-url $(TORCH_INDEX)) torch==2.13.0
	$(BIN)/pip install --quiet -e ".[test,ray,bench,mjcf]"
	touch $@

# The main job: assemble every shipped formation, learn quadruped in memo mode, check it with
# exact physics against the best reference gait, film it, draw it and write one HTML page, all
# into runs/demo/ (replaced on every run).
DEMO := runs/demo

demo: $(BIN)/qdsega
	$(BIN)/qdsega assemble assemblies/*.yaml --out-dir out/assemblies
	$(BIN)/qdsega train quadruped --sim memo --preset memo-legged --workers 2 --seed 0 \
		--out $(DEMO) --overwrite
	$(BIN)/qdsega evaluate $(DEMO)
	$(BIN)/qdsega render $(DEMO) -o $(DEMO)/gait.mp4
	$(BIN)/qdsega plot $(DEMO)
	$(BIN)/qdsega report $(DEMO)

SOURCES := qdsega tools experiments tests

ruff: $(VENV)/extras
	$(BIN)/ruff check $(SOURCES)
	$(BIN)/ruff format --check $(SOURCES)

lint: ruff
	$(BIN)/mypy

# The tests on two processes. Bytecode is written even where PYTHONDONTWRITEBYTECODE is set: the
# tests start many processes, and each would compile the package again.
PYTEST := PYTHONDONTWRITEBYTECODE= $(BIN)/pytest -q -n 2 --dist worksteal

# Everything: ruff, then every test (the slow end-to-end ones too) with mypy beside them (the
# tests leave a core idle now and then, and mypy takes it); fails if either does.
test: ruff
	@$(BIN)/mypy & checker=$$!; \
	$(PYTEST); tests=$$?; \
	wait $$checker && exit $$tests

# The fast tier, for working: every test not marked slow (under a minute).
test-fast: $(VENV)/extras
	$(PYTEST) -m "not slow"

# benchmarks/BENCHMARKS.md from scratch (about 9 hours on 2 cores; re-running continues;
# --ray spreads it over a cluster: docs/benchmarks.md).
bench: $(VENV)/extras
	$(BIN)/qdsega bench --out benchmarks --jobs 2
