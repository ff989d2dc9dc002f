# Two entry points (see README): `make demo` and `make test`.
# Both create a virtual environment inside the checkout on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test lint setup

$(BIN)/qdsega: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[test]"
	touch $(BIN)/qdsega

setup: $(BIN)/qdsega

demo: setup
	$(BIN)/qdsega assemble assemblies/*.yaml --out-dir out/assemblies

lint: setup
	$(BIN)/ruff check qdsega tools tests
	$(BIN)/ruff format --check qdsega tools tests

test: lint
	$(BIN)/pytest -q
