# cnc-motion: the two commands are `make demo` and `make test` (see README.md).
PYTHON ?= python3
CARGO  ?= cargo
# Binaries follow CARGO_TARGET_DIR when it is set; the FMUs always go to target/fmu.
BIN    := $(or $(CARGO_TARGET_DIR),target)/release
# The demo's environment: the package installed as a user installs it (not editable, the FMUs
# inside it) with the `plot` extra. Every version pinned by constraints.txt.
VENV   := .venv
PY     := $(VENV)/bin/python
# The full environment (tests, co-simulation masters, sweeps): the package editable, every extra.
FULL   := .venv-full
FPY    := $(FULL)/bin/python
PIP    := pip install --quiet --disable-pip-version-check -c constraints.txt
# Where the FMUs go into the Python package (package data, not committed).
PKG_FMU := python/cnc_motion_sim/fmu

# cargo runs its jobs in parallel itself; the targets run in order (the venv's build backend calls
# `make fmu` again, which must not race a `make fmu` of this run).
.NOTPARALLEL:

.PHONY: all build fmu demo test test-rust test-python bench lint clean venv venv-full ssp cosim sweep fuzz system-deps

all: build

# One release build serves the demo and the tests: `cargo test --release` reuses every artifact
# of this command (the FMU's shared library included) and only adds the test binaries. The
# example (examples/plan_dump.rs) brings in the dev-dependencies, so that their features (serde's
# `alloc`, syn's `full`, through criterion) are the same here as in the tests' build: without it
# cargo compiles every crate that uses serde a second time for the tests.
build:
	$(CARGO) build --release --workspace --lib --bins --examples

# Both FMUs, then copied into the Python package (only when their bytes changed).
STRUCTURE_PACKAGE ?= $(BIN)/package-machine-structure target/fmu/MachineStructure.fmu

fmu: build
	$(BIN)/cnc-motion package --output target/fmu/CncMotion.fmu
	$(STRUCTURE_PACKAGE)
	@mkdir -p $(PKG_FMU)
	@for f in CncMotion MachineStructure; do \
	  cmp -s target/fmu/$$f.fmu $(PKG_FMU)/$$f.fmu || cp target/fmu/$$f.fmu $(PKG_FMU)/$$f.fmu; done

PY_SOURCES := constraints.txt python/pyproject.toml python/build_support/backend.py \
              $(wildcard python/cnc_motion_sim/*.py)

venv: fmu $(VENV)/.installed

# Reinstalled when the package or its FMUs change (pip always rebuilds a local directory).
$(VENV)/.installed: $(PY_SOURCES) $(wildcard $(PKG_FMU)/*.fmu)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(VENV)/bin/$(PIP) './python[plot]'
	touch $@

venv-full: $(FULL)/.installed

$(FULL)/.installed: constraints.txt python/pyproject.toml
	test -x $(FPY) || $(PYTHON) -m venv $(FULL)
	$(FULL)/bin/$(PIP) -e './python[test]'
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

demo: venv
	$(PY) examples/demo.py
	$(PY) examples/cosim.py --out out

# examples/cosim.ssp: both FMUs and their coupling, for SSP importers (generated, not committed).
ssp: venv
	$(PY) -m cnc_motion_sim.ssp --out examples/cosim.ssp

cosim: fmu venv-full system-deps
	$(FPY) examples/cosim.py --master slaves
	$(FPY) examples/cosim.py --master fmpy-ssp
	$(FPY) examples/cosim.py --master libcosim
	$(FPY) examples/cosim.py --master ecos

sweep: fmu venv-full
	$(FPY) examples/sweep.py

test: test-rust test-python

# The release profile of `make build` (see there); the C-ABI tests load the shared library cargo
# builds with them (target/release/deps/libcnc_motion.so; tests/common/mod.rs). The random tests
# run on CI's seeds (.ci/run) unless the environment sets others, so the test command never
# fails by chance; `make fuzz` runs fresh seeds.
test-rust:
	PROPTEST_RNG_SEED=$${PROPTEST_RNG_SEED:-20261123} CNC_FUZZ_SEED=$${CNC_FUZZ_SEED:-20261123} \
		$(CARGO) test --release --workspace

test-python: fmu venv-full system-deps
	$(FPY) -m pytest -q tests/python

# Fresh seeds, more cases: every property test with a new random seed (printed, so a failure can
# be replayed with PROPTEST_RNG_SEED=...; unset, tests/monotone_props.rs keeps CI's), then the fuzz
# harness of tests/fuzz.rs with FUZZ_CASES mutated programs and machine files on a new seed
# (printed, so a failure can be replayed with CNC_FUZZ_SEED=...). Every part runs whatever an
# earlier one found (the monotone-limit property fails now and then on fresh seeds, README), and
# the target fails if any did.
FUZZ_CASES ?= 50000
fuzz:
	rc=0; seed=$$(od -An -N4 -tu4 /dev/urandom | tr -d ' '); echo "PROPTEST_RNG_SEED=$$seed"; \
		PROPTEST_RNG_SEED=$$seed $(CARGO) test --workspace --release --no-fail-fast || rc=$$?; \
		CNC_FUZZ_SEED=$$(od -An -N4 -tu4 /dev/urandom | tr -d ' ') CNC_FUZZ_CASES=$(FUZZ_CASES) \
		$(CARGO) test --release --test fuzz -- --nocapture || rc=$$?; \
		exit $$rc

# The FMU benchmark loads target/release/libcnc_motion.so: build the libraries first.
bench:
	$(CARGO) build --release --workspace --lib
	$(CARGO) bench --workspace

lint:
	$(CARGO) fmt --all --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

clean:
	rm -rf out target/fmu examples/cosim.ssp $(PKG_FMU) python/build

# --- win64 and aarch64-linux in the same FMUs (issue 18): the two cdylibs cross-compiled for
# Windows with Debian's mingw-w64 and for aarch64 Linux with Debian's aarch64 gcc (the FMI 3.0
# archives only: FMI 2.0 names no aarch64 platform), tested under wine64 and qemu-aarch64
# (tests/python/test_fmu_platforms.py, harness in tests/c/).
# Self-contained block: `fmu` and `system-deps` gain prerequisites here.
WIN64_TARGET := x86_64-pc-windows-gnu
ARM64_TARGET := aarch64-unknown-linux-gnu
CROSS_TARGETS := $(WIN64_TARGET) $(ARM64_TARGET)
# file:Debian package, installed with apt-get where the file is missing (Debian's wine64 puts its
# loader in /usr/lib/wine, off the PATH; qemu-user runs the aarch64 harness, with the aarch64 C
# library of libc6-dev-arm64-cross under /usr/aarch64-linux-gnu).
CROSS_DEBS   := /usr/bin/x86_64-w64-mingw32-gcc:gcc-mingw-w64-x86-64 /usr/lib/wine/wine64:wine64 \
                /usr/bin/aarch64-linux-gnu-gcc:gcc-aarch64-linux-gnu \
                /usr/aarch64-linux-gnu/lib/libc.so:libc6-dev-arm64-cross /usr/bin/qemu-aarch64:qemu-user
HARNESS_DIR  := target/harness
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER ?= aarch64-linux-gnu-gcc

.PHONY: cross win64 aarch64 system-deps-cross harness

fmu: cross
system-deps: system-deps-cross
test-python: harness

# Both cross targets in one cargo call (cargo shares the build plan and runs the jobs together).
cross: system-deps-cross
	$(CARGO) build --release --lib $(CROSS_TARGETS:%=--target %) -p cnc-motion -p machine-structure

win64: system-deps-cross
	$(CARGO) build --release --lib --target $(WIN64_TARGET) -p cnc-motion -p machine-structure

aarch64: system-deps-cross
	$(CARGO) build --release --lib --target $(ARM64_TARGET) -p cnc-motion -p machine-structure

system-deps-cross:
	@missing=; for pair in $(CROSS_DEBS); do file=$${pair%%:*}; pkg=$${pair#*:}; \
	  [ -e "$$file" ] || case " $$missing " in *" $$pkg "*) ;; *) missing="$$missing $$pkg";; esac; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing$$missing"; apt-get update -qq && \
	    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	  else echo "missing:$$missing: run 'sudo apt-get install$$missing' (cross builds and their tests)" >&2; exit 1; fi; \
	fi
	@for t in $(CROSS_TARGETS); do \
	  rustup target list --installed | grep -qx "$$t" || rustup target add "$$t"; done

# The C importer of tests/c for Linux (dlopen), Windows (LoadLibrary, run under wine) and aarch64
# Linux (dlopen, run under qemu-aarch64), and the bcryptprimitives.dll that wine 8 lacks
# (ProcessPrng, imported by Rust's std), beside the .exe.
harness: $(HARNESS_DIR)/fmi2_harness $(HARNESS_DIR)/win64/fmi2_harness.exe $(HARNESS_DIR)/win64/bcryptprimitives.dll \
         $(HARNESS_DIR)/aarch64/fmi2_harness

$(HARNESS_DIR)/fmi2_harness: tests/c/fmi2_harness.c
	@mkdir -p $(@D)
	$(CC) -O2 -Wall -Wextra -o $@ $< -ldl

$(HARNESS_DIR)/win64/fmi2_harness.exe: tests/c/fmi2_harness.c | system-deps-cross
	@mkdir -p $(@D)
	x86_64-w64-mingw32-gcc -O2 -Wall -Wextra -o $@ $<

$(HARNESS_DIR)/win64/bcryptprimitives.dll: tests/c/bcryptprimitives.c | system-deps-cross
	@mkdir -p $(@D)
	x86_64-w64-mingw32-gcc -O2 -Wall -shared -o $@ $< -ladvapi32

$(HARNESS_DIR)/aarch64/fmi2_harness: tests/c/fmi2_harness.c | system-deps-cross
	@mkdir -p $(@D)
	aarch64-linux-gnu-gcc -O2 -Wall -Wextra -o $@ $< -ldl
