# cnc-motion: the two commands are `make demo` and `make test` (see README.md).
VENV   := .venv
PY     := $(VENV)/bin/python
PYTHON ?= python3
CARGO  ?= cargo

.PHONY: all build fmu demo test test-rust test-python bench lint clean venv

all: build

venv: $(VENV)/.installed

# Project-local virtual environment with the pinned Python dependencies.
$(VENV)/.installed: requirements.txt
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet --disable-pip-version-check -r requirements.txt
	touch $@

build:
	$(CARGO) build --release --workspace --bins --lib

fmu: build
	./target/release/cnc-motion package --output target/fmu/CncMotion.fmu
	./target/release/package-machine-structure target/fmu/MachineStructure.fmu

demo: build venv
	$(PY) examples/demo.py

test: test-rust test-python

test-rust:
	$(CARGO) test --workspace

test-python: build venv
	$(PY) -m pytest -q tests/python

bench:
	$(CARGO) bench --workspace

lint:
	$(CARGO) fmt --all --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

clean:
	rm -rf out target/fmu
