# cnc-motion: the two commands are `make demo` and `make test` (see README.md).
VENV   := .venv
PY     := $(VENV)/bin/python
PYTHON ?= python3
CARGO  ?= cargo
# Binaries follow CARGO_TARGET_DIR when it is set; the FMUs always go to target/fmu.
BIN    := $(or $(CARGO_TARGET_DIR),target)/release

.PHONY: all build fmu demo test test-rust test-python bench lint clean venv cosim sweep fuzz system-deps

all: build

venv: $(VENV)/.installed

# Project-local virtual environment: the package in python/ (editable, with its test extras),
# every version pinned by constraints.txt.
$(VENV)/.installed: python/pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/pip install --quiet --disable-pip-version-check -c constraints.txt -e 'python[test]'
	touch $@

# System libraries of the pinned Python packages: Ecos (ecospy) loads oneTBB's libtbb.so.12.
# Installed with apt-get where missing (as root: CI, a fresh machine); skipped when present.
SYSTEM_LIBS := libtbb.so.12:libtbb12
system-deps:
	@for pair in $(SYSTEM_LIBS); do lib=$${pair%%:*}; pkg=$${pair#*:}; \
	  /sbin/ldconfig -p | grep -q "$$lib" && continue; \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing $$pkg (for $$lib)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$$pkg" >/dev/null; \
	  else echo "missing $$lib: run 'sudo apt-get install $$pkg' (needed by ecospy)" >&2; exit 1; fi; \
	done

build:
	$(CARGO) build --release --workspace --bins --lib

# Both FMUs and the SSP that couples them (examples/cosim.ssp, generated, not committed).
STRUCTURE_PACKAGE ?= $(BIN)/package-machine-structure target/fmu/MachineStructure.fmu

fmu: build venv system-deps
	$(BIN)/cnc-motion package --output target/fmu/CncMotion.fmu
	$(STRUCTURE_PACKAGE)
	$(PY) examples/make_ssp.py

demo: fmu
	$(PY) examples/demo.py
	$(PY) examples/cosim.py --out out

cosim: fmu
	$(PY) examples/cosim.py --master slaves
	$(PY) examples/cosim.py --master fmpy-ssp
	$(PY) examples/cosim.py --master libcosim
	$(PY) examples/cosim.py --master ecos

sweep: fmu
	$(PY) examples/sweep.py

test: test-rust test-python

test-rust:
	$(CARGO) test --workspace

test-python: fmu
	$(PY) -m pytest -q tests/python

# Fresh seeds, more cases: every property test with a new random seed (PROPTEST_RNG_SEED unset),
# then the fuzz harness of tests/fuzz.rs with FUZZ_CASES mutated programs and machine files on a
# new seed (printed, so a failure can be replayed with CNC_FUZZ_SEED=...).
FUZZ_CASES ?= 50000
fuzz:
	env -u PROPTEST_RNG_SEED $(CARGO) test --workspace --release
	env -u CNC_FUZZ_SEED CNC_FUZZ_CASES=$(FUZZ_CASES) $(CARGO) test --release --test fuzz -- --nocapture

# The FMU benchmark loads target/release/libcnc_motion.so: build the libraries first.
bench:
	$(CARGO) build --release --workspace --lib
	$(CARGO) bench --workspace

lint:
	$(CARGO) fmt --all --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

clean:
	rm -rf out target/fmu examples/cosim.ssp

# --- win64 in the same FMUs (issue 18): the two cdylibs cross-compiled for Windows with Debian's
# mingw-w64 and tested under wine64 (tests/python/test_fmu_win64.py, harness in tests/c/).
# Self-contained block: `fmu` and `system-deps` gain prerequisites here.
WIN64_TARGET := x86_64-pc-windows-gnu
WIN64_DIR    := $(or $(CARGO_TARGET_DIR),target)/$(WIN64_TARGET)/release
WIN64_DLLS   := $(WIN64_DIR)/cnc_motion.dll $(WIN64_DIR)/machine_structure.dll
# file:Debian package, installed with apt-get where the file is missing (Debian's wine64 puts its
# loader in /usr/lib/wine, off the PATH).
CROSS_DEBS   := /usr/bin/x86_64-w64-mingw32-gcc:gcc-mingw-w64-x86-64 /usr/lib/wine/wine64:wine64
HARNESS_DIR  := target/harness

.PHONY: win64 system-deps-cross harness

fmu: win64
system-deps: system-deps-cross
test-python: harness

win64: system-deps-cross
	$(CARGO) build --release --lib --target $(WIN64_TARGET) -p cnc-motion -p machine-structure

system-deps-cross:
	@missing=; for pair in $(CROSS_DEBS); do file=$${pair%%:*}; \
	  [ -x "$$file" ] || missing="$$missing $${pair#*:}"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing$$missing"; apt-get update -qq && \
	    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	  else echo "missing:$$missing: run 'sudo apt-get install$$missing' (win64 cross build and test)" >&2; exit 1; fi; \
	fi
	@rustup target list --installed | grep -qx '$(WIN64_TARGET)' || rustup target add $(WIN64_TARGET)

# The C importer of tests/c for Linux (dlopen) and Windows (LoadLibrary, run under wine), and the
# bcryptprimitives.dll that wine 8 lacks (ProcessPrng, imported by Rust's std), beside the .exe.
harness: $(HARNESS_DIR)/fmi2_harness $(HARNESS_DIR)/win64/fmi2_harness.exe $(HARNESS_DIR)/win64/bcryptprimitives.dll

$(HARNESS_DIR)/fmi2_harness: tests/c/fmi2_harness.c
	@mkdir -p $(@D)
	$(CC) -O2 -Wall -Wextra -o $@ $< -ldl

$(HARNESS_DIR)/win64/fmi2_harness.exe: tests/c/fmi2_harness.c | system-deps-cross
	@mkdir -p $(@D)
	x86_64-w64-mingw32-gcc -O2 -Wall -Wextra -o $@ $<

$(HARNESS_DIR)/win64/bcryptprimitives.dll: tests/c/bcryptprimitives.c | system-deps-cross
	@mkdir -p $(@D)
	x86_64-w64-mingw32-gcc -O2 -Wall -shared -o $@ $< -ladvapi32
