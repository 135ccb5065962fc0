# Thin wrapper around CMake for the two commands of the README.
#   make demo   install dependencies, build, run the seed's solid-mass and 50 % rectangular-tank cases on the
#               beam (a few minutes on 2 cores), write the seed's figures, say where the results are
#   make test   install dependencies, build, run the C tests (ctest) and the Python tests (pytest, in JOBS processes)
#   make validate  build, run every validation case and write docs/validation/README.md (long: hours on
#               2 cores; not part of make test); CASES=a,b runs a subset, VALIDATE_FLAGS=--quick a smoke run
#   make format clang-format the C sources
# `make build` also makes the Python package in python/ importable by this checkout's own Python, $(PYTHON): a
# virtual environment in $(BUILD)/venv over /usr/bin/python3 and its Debian packages (scripts/install-python.sh);
# nothing outside the checkout is written, so that two checkouts do not take over each other's `import flexslosh`.
BUILD   ?= build
JOBS    ?= 2
VENV    := $(abspath $(BUILD))/venv
PYTHON  ?= $(VENV)/bin/python3
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1

.PHONY: all deps build python demo test test-c test-python bench validate format clean

all: build

deps:
	@bash scripts/install-deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD) -j $(JOBS)
	@VENV=$(VENV) bash scripts/install-python.sh

# the Python environment alone (part of build)
python:
	@VENV=$(VENV) bash scripts/install-python.sh

demo: build
	@BUILD=$(BUILD) PYTHON=$(PYTHON) bash scripts/demo.sh

test-c: build
	cd $(BUILD) && ctest --output-on-failure

test-python: build
	FLEXSLOSH_BUILD=$(abspath $(BUILD)) $(PYTHON) -m pytest -q -n $(JOBS) --dist loadfile --durations=15 tests/python

test: test-c test-python

bench: build
	$(BUILD)/bench_terms -fs_dx 0.005 -reps 20
	$(BUILD)/bench_rhs -fs_case dam_break -fs_dx 0.01 -steps 20 -reps 40
	$(PYTHON) bench/bench_taylor_green.py
	$(PYTHON) bench/bench_dam_break.py
	$(PYTHON) bench/bench_coupled.py
	$(PYTHON) bench/bench_dam_break_3d.py
	$(PYTHON) bench/bench_memory.py
	$(PYTHON) bench/bench_memory.py -- -fs_neighbour_candidates bits
	$(PYTHON) bench/bench_memory.py --dim 3
	$(if $(DUALSPHYSICS),$(PYTHON) bench/bench_dualsphysics.py --dualsphysics $(DUALSPHYSICS))

# the validation report (python/flexslosh/validate.py): every case, or CASES=taylor_green,dam_break
CASES          ?=
VALIDATE_FLAGS ?=
validate: build
	FLEXSLOSH_BUILD=$(abspath $(BUILD)) PYTHONPATH=$(abspath python) $(PYTHON) -m flexslosh.validate $(if $(CASES),--cases $(CASES)) $(VALIDATE_FLAGS)

# the C sources in the project's format (.clang-format; tests/python/test_format.py checks it)
format:
	clang-format -i -style=file $$(find src include app plugins bench tests/c -name '*.[ch]')

clean:
	rm -rf $(BUILD)
