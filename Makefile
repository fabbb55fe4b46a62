# Entry points. `make demo` and `make test` install what is missing first.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
CHROMATAG := $(BUILD_DIR)/cli/chromatag

.PHONY: all deps configure build demo test bench asan tsan fuzz format clean

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The main job on a built-in default. Only the tool and its libraries are
# built; tests and benchmarks wait for `make test` and `make bench`.
demo: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target chromatag
	@scripts/demo.sh $(CHROMATAG)

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# BENCH_ARGS=--quick for a short comparison; --publish copies it to docs/benchmarks/.
BENCH_ARGS ?=
bench: build
	@scripts/bench.sh $(BUILD_DIR) $(BENCH_ARGS)

# AddressSanitizer + UndefinedBehaviorSanitizer (float-cast-overflow
# included) build and test run with clang, in the portable configuration
# (CHROMATAG_NATIVE off), so that clang and the portable build are built and
# tested too. Fontconfig and GLib keep caches until exit: cmake/lsan.supp
# names them. Without the Python module (a sanitized extension cannot load
# into an unsanitized python3) and the installed-tree test (the installed
# archives would need the sanitizer runtime in every consumer).
SANITIZER_FLAGS = -DCHROMATAG_NATIVE=OFF -DCHROMATAG_BUILD_BENCH=OFF -DCHROMATAG_BUILD_PYTHON=OFF \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++
asan: export LSAN_OPTIONS = suppressions=$(CURDIR)/cmake/lsan.supp:print_suppressions=0
asan:
	@$(MAKE) --no-print-directory test BUILD_DIR=build-asan BUILD_TYPE=RelWithDebInfo \
	  CMAKE_FLAGS="-DCHROMATAG_SANITIZE=ON $(SANITIZER_FLAGS)"

# ThreadSanitizer on what runs threads: one Detector shared by several
# threads, and detect --jobs.
tsan: deps
	@cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCHROMATAG_TSAN=ON \
	  $(SANITIZER_FLAGS) >/dev/null
	@cmake --build build-tsan -j $(JOBS) --target detector_scene_test cli_test chromatag
	@cd build-tsan && TSAN_OPTIONS="halt_on_error=1 suppressions=$(CURDIR)/cmake/tsan.supp" \
	  ctest --output-on-failure -j $(JOBS) \
	  -R "OneDetectorServesSeveralThreads|CliLiveTest"

# libFuzzer harnesses (tests/fuzz), FUZZ_SECONDS each (scripts/fuzz.sh).
FUZZ_SECONDS ?= 60
fuzz: deps
	@scripts/fuzz.sh $(FUZZ_SECONDS)

# clang-format 14 (Debian 12's; scripts/install-deps.sh installs it): other
# versions format some constructs differently. `make test` checks the tree
# with it (the clang_format test).
CLANG_FORMAT ?= clang-format-14
format:
	@git ls-files '*.h' '*.cc' | xargs $(CLANG_FORMAT) -i

clean:
	@rm -rf build build-asan build-tsan build-fuzz
