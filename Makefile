# qdmeta: the two commands a user needs are `make run` and `make test`.
# Release build in build/, sanitizer (address + undefined) build in build-asan/.
JOBS ?= $(shell nproc)
BUILD ?= build
ASAN_BUILD ?= build-asan
DEMO_OUT ?= results/demo
CMAKE_FLAGS ?=

.PHONY: all deps build run test test-long test-all test-sanitize test-pip test-slurm bench clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

# The most complete demo so far: a small version of the paper's Rastrigin study (every condition
# of configs/rastrigin/experiment.toml, 2 replicates of 1,000,000 evaluations, both tests), then
# its report (figures and report.md). Run it again to reuse the finished runs.
DEMO_REPLICATES ?= 2
DEMO_EVALS ?= 1000000
# Builds only what the demo runs: the qdmeta command line (the report is tools/report.py, read from
# the source tree), not the tests, benchmarks or examples.
run: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS) --target qdmeta_cli
	$(BUILD)/qdmeta experiment --config configs/rastrigin/experiment.toml --out $(DEMO_OUT) --replicates $(DEMO_REPLICATES) --evals $(DEMO_EVALS)
	@echo "Report: $(DEMO_OUT)/report.md (figures in $(DEMO_OUT)/figures); runs in $(DEMO_OUT)/<condition>/seed-<r>/"

# ctest without the long tests, then the installed package: examples/own-task built against
# `cmake --install` and run. The long tests (label "long", tests/CMakeLists.txt: the RHex smoke
# study, the MPI and kill-and-resume end-to-end tests, the study scripts, the robustness matrices,
# tools/'s pytest) are `make test-long`; `make test-all` runs both, as CI must. It builds what these
# need (target qdmeta_test_programs, cmake/test_programs.cmake): all but the benchmarks of bench/
# and the test programs that only long tests run, which `make build`, `make bench` and
# `make test-long` build.
test: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS) --target qdmeta_test_programs
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) -LE long
	JOBS=$(JOBS) bash scripts/test-installed-package.sh $(BUILD)

test-long: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS) -L long

test-all: test test-long

# pip install . into a fresh virtual environment, then the Python suite; and the suite against
# build/python under numpy 2 (both need the Python package index).
test-pip: build
	bash scripts/test-pip-install.sh
	bash scripts/test-numpy2.sh $(BUILD)

# scripts/slurm-experiment.sh on a real SLURM started on this machine (installs Debian's slurmd,
# slurmctld and munge, stops the daemons it started): a small RHex-on-MuJoCo experiment, one array
# task cancelled mid-run and resubmitted, its report compared with a local qdmeta experiment's.
test-slurm: deps $(BUILD)/build.ninja
	JOBS=$(JOBS) bash scripts/test-slurm.sh $(BUILD)

$(ASAN_BUILD)/build.ninja:
	cmake -S . -B $(ASAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Debug -DQDMETA_SANITIZE=ON -DQDMETA_BUILD_BENCH=OFF $(CMAKE_FLAGS)

test-sanitize: deps $(ASAN_BUILD)/build.ninja
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

bench: build
	@for b in $(BUILD)/bench/*_bench; do echo "== $$b"; $$b; done

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)
