# Thin wrapper around CMake for the README's two commands.
#   make demo            install missing packages, build the CLI, render corridor to out/corridor.png
#   make test            install missing packages, build, run the whole suite (CTest)
#   make test SANITIZE=1 the same under ASan + UBSan (separate build folder)
#   make test TSAN=1     the tests labelled `threads` under ThreadSanitizer
#                        (build-tsan; scripts/tsan.sh fails on any report)
#   make bench           the workload table of docs/PERFORMANCE.md against llvmpipe;
#                        SIMD=avx2 (or any --simd variant) for every row
#                        (scripts/bench.sh; not part of the test suite)
#   make fuzz            libFuzzer harnesses with clang, ASan + UBSan, 60 s each
#                        (scripts/fuzz.sh; not part of the test suite)
#   make fuzz-long       each harness to 10 M executions (FUZZ_RUNS, FUZZ_MAX_TIME: see
#                        scripts/fuzz-long.sh) at nice 19, nproc at once, with a faster
#                        build (-O2, UBSan only, build-fuzz-long/); then minimises each
#                        corpus back into tests/fuzz/corpus/NAME/ and prints a summary
#   make test-aarch64    cross build for 64-bit ARM (cmake/aarch64-linux-gnu.cmake) and the
#                        suite under qemu-user (build-aarch64/; not part of `make test`)
#   make hw              the RTL of hw/ (docs/HARDWARE.md): installs verilator, yosys, nextpnr
#                        (deps --hw), builds, runs scripts/hw.sh: Verilator testbenches against
#                        `persp vectors`, iCE40 and Yosys+ABC synthesis, out/hw/summary.{json,md}
#   make difftest        persp against Mesa llvmpipe on 2000 random scenes (SEEDS=A:B),
#                        a summary per filter; failing scenes kept in out/difftest/
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
# Keep the build's output to its progress lines.
MAKEFLAGS += --no-print-directory
ifeq ($(SANITIZE),1)
BUILD ?= build-san
CMAKE_FLAGS += -DPERSP_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug
else ifeq ($(TSAN),1)
BUILD ?= build-tsan
CMAKE_FLAGS += -DPERSP_TSAN=ON -DCMAKE_BUILD_TYPE=Debug
else
BUILD ?= build
endif

.PHONY: all deps configure build demo test test-aarch64 bench fuzz fuzz-long difftest clean format hw

all: build

deps:
	@bash scripts/deps.sh

configure: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# The demo needs the CLI (and the model import helper it depends on), not
# the test programs: `make test` builds those.
demo: configure
	@cmake --build $(BUILD) -j $(JOBS) --target persp_cli
	@mkdir -p out
	@echo "+ $(BUILD)/persp render corridor -o out/corridor.png"
	@$(BUILD)/persp render corridor -o out/corridor.png

test: build
ifeq ($(TSAN),1)
	@bash scripts/tsan.sh $(BUILD) $(JOBS)
else
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
endif

test-aarch64:
	@bash scripts/deps.sh --aarch64
	@cmake -S . -B build-aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake \
		-DPERSP_OSMESA=OFF -DPERSP_VIEWER=OFF >/dev/null
	@cmake --build build-aarch64 -j $(JOBS)
	@cd build-aarch64 && ctest --output-on-failure -j $(JOBS)

hw: build
	@bash scripts/deps.sh --hw
	@bash scripts/hw.sh $(BUILD)

bench: build
	@SIMD=$(SIMD) bash scripts/bench.sh $(BUILD)/persp out/bench$(if $(SIMD),-$(SIMD))

SEEDS ?= 1:2001
difftest: build
	@test -x $(BUILD)/persp_difftest || { echo "difftest: persp_difftest was not built (needs OSMesa, libosmesa6-dev: bash scripts/deps.sh)"; exit 1; }
	@echo "+ $(BUILD)/persp_difftest --seeds $(SEEDS) --fail-dir out/difftest"
	@$(BUILD)/persp_difftest --seeds $(SEEDS) --fail-dir out/difftest

fuzz:
	@bash scripts/deps.sh --optional
	@cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DPERSP_FUZZ=ON -DCMAKE_BUILD_TYPE=Debug >/dev/null
	@cmake --build build-fuzz -j $(JOBS)
	@bash scripts/fuzz.sh build-fuzz

fuzz-long:
	@bash scripts/deps.sh --optional
	@cmake -S . -B build-fuzz-long -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DPERSP_FUZZ=ON \
		-DPERSP_FUZZ_SANITIZERS=undefined -DCMAKE_BUILD_TYPE=RelWithDebInfo \
		-DPERSP_BUILD_TESTS=OFF -DPERSP_BUILD_CLI=OFF -DPERSP_BUILD_EXAMPLES=OFF >/dev/null
	@cmake --build build-fuzz-long -j $(JOBS)
	@bash scripts/fuzz-long.sh build-fuzz-long

format:
	@clang-format -i include/*.h src/*/*.[ch] tools/persp/*.[ch] tests/*/*.[ch]

clean:
	rm -rf build build-san build-tsan build-fuzz build-fuzz-long build-aarch64 out
