# qdmeta: the two commands a user needs are `make run` and `make test`.
# Release build in build/, sanitizer (address + undefined) build in build-asan/.
JOBS ?= $(shell nproc)
BUILD ?= build
ASAN_BUILD ?= build-asan
DEMO_OUT ?= results/demo
CMAKE_FLAGS ?=

.PHONY: all deps build run test test-sanitize bench clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

# The most complete demo so far: plain MAP-Elites on 20-D Rastrigin (1,000,000 evaluations),
# then a small QD-Meta Translation run (2,000,000 bottom-level evaluations, about 10 s on 2 cores).
run: build
	$(BUILD)/qdmeta run --config configs/rastrigin/map-elites.toml --out $(DEMO_OUT)/map-elites --overwrite
	$(BUILD)/qdmeta run --config configs/rastrigin/qdmeta-translation.toml --out $(DEMO_OUT)/qdmeta-translation --evals 2000000 --overwrite
	@echo "Results in $(DEMO_OUT)/map-elites and $(DEMO_OUT)/qdmeta-translation: metrics.csv (statistics over evaluations),"
	@echo "meta.csv (QD-Meta: meta-fitness per meta-generation), archive.csv (final elites), summary.json"

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
