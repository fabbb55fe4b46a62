# Entry points. `make demo` and `make test` install what is missing first.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=
CHROMATAG := $(BUILD_DIR)/cli/chromatag

.PHONY: all deps configure build demo test bench asan format clean

all: build

deps:
	@scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The main job on a built-in default.
demo: build
	@scripts/demo.sh $(CHROMATAG)

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# BENCH_ARGS=--quick for a short comparison; --publish copies it to docs/benchmarks/.
BENCH_ARGS ?=
bench: build
	@scripts/bench.sh $(BUILD_DIR) $(BENCH_ARGS)

# AddressSanitizer + UndefinedBehaviorSanitizer build and test run, in the
# portable configuration (CHROMATAG_NATIVE off), so that it is built and tested
# too. Fontconfig and GLib keep caches until exit: cmake/lsan.supp names them.
# Without the Python module (a sanitized extension cannot load into an
# unsanitized python3) and the installed-tree test (the installed archives
# would need the sanitizer runtime in every consumer).
asan: export LSAN_OPTIONS = suppressions=$(CURDIR)/cmake/lsan.supp:print_suppressions=0
asan:
	@$(MAKE) --no-print-directory test BUILD_DIR=build-asan BUILD_TYPE=RelWithDebInfo \
	  CMAKE_FLAGS="-DCHROMATAG_SANITIZE=ON -DCHROMATAG_NATIVE=OFF -DCHROMATAG_BUILD_BENCH=OFF -DCHROMATAG_BUILD_PYTHON=OFF"

# clang-format 14 (Debian 12's; scripts/install-deps.sh installs it): other
# versions format some constructs differently. `make test` checks the tree
# with it (the clang_format test).
CLANG_FORMAT ?= clang-format-14
format:
	@git ls-files '*.h' '*.cc' | xargs $(CLANG_FORMAT) -i

clean:
	@rm -rf build build-asan
