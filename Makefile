# qdmeta: the two commands a user needs are `make run` and `make test`.
# Release build in build/, sanitizer (address + undefined) build in build-asan/.
JOBS ?= $(shell nproc)
BUILD ?= build
ASAN_BUILD ?= build-asan
DEMO_OUT ?= results/demo-map-elites
CMAKE_FLAGS ?=

.PHONY: all deps build run test test-sanitize bench clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

# The most complete demo so far: plain MAP-Elites on 20-D Rastrigin, 1,000,000 evaluations.
run: build
	$(BUILD)/qdmeta run --config configs/rastrigin/map-elites.toml --out $(DEMO_OUT) --overwrite
	@echo "Results in $(DEMO_OUT)/: metrics.csv (statistics over evaluations), archive.csv (final elites), summary.json"

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

$(ASAN_BUILD)/build.ninja:
	cmake -S . -B $(ASAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Debug -DQDMETA_SANITIZE=ON -DQDMETA_BUILD_BENCH=OFF $(CMAKE_FLAGS)

test-sanitize: deps $(ASAN_BUILD)/build.ninja
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

bench: build
	@for b in $(BUILD)/bench/*_bench; do echo "== $$b"; $$b; done

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)
