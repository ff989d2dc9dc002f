# Two entry points (see README): `make demo` and `make test`.
# Both create a virtual environment inside the checkout on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test lint setup

$(BIN)/qdsega: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[test,ray]"
	touch $(BIN)/qdsega

setup: $(BIN)/qdsega

# The main job: assemble, learn snake5 in memo mode, check it with exact physics, film it,
# draw it and write one HTML page, all into runs/demo/ (replaced on every run).
DEMO := runs/demo

demo: setup
	$(BIN)/qdsega assemble assemblies/*.yaml --out-dir out/assemblies
	$(BIN)/qdsega train assemblies/snake5.yaml --sim memo --preset paper-snake \
		--generations 12 --workers 2 --seed 0 --out $(DEMO) --overwrite
	$(BIN)/qdsega evaluate $(DEMO)
	$(BIN)/qdsega render $(DEMO) -o $(DEMO)/gait.mp4
	$(BIN)/qdsega plot $(DEMO)
	$(BIN)/qdsega report $(DEMO)

lint: setup
	$(BIN)/ruff check qdsega tools tests
	$(BIN)/ruff format --check qdsega tools tests

test: lint
	$(BIN)/pytest -q -n 2
