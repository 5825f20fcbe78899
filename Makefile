# The README's two commands: `make demo` and `make test`. Everything else is a helper.
#   make demo    builds the command line alone (no tests, no benchmarks) and runs it once
#   make test    builds the libraries, the command line, the Python module and the tests; runs them
#   make bench   builds the benchmark tools too and runs bench/ed_scaling.py
# WERROR=ON makes the project's warnings errors (CI: .ci/run).
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release
WERROR ?= OFF

.PHONY: all setup configure build python install test demo bench clean sanitize fuzz sanitize-configure

all: build

setup:
	@bash scripts/setup

configure: setup
	@cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) -DBALLAGG_WERROR=$(WERROR) > /dev/null

# Everything but the benchmark tools.
build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The Python module alone (build/python); `make build` and `make test` build it too.
python: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target ballagg_python

# The binary, the plotting script and the Python module under PREFIX (default /usr/local,
# where Debian's /usr/bin/python3 finds the module: `sudo make install`), docs/python.md.
install: build
	cmake --install $(BUILD_DIR) $(if $(PREFIX),--prefix $(PREFIX))

test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

demo: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target ballagg
	$(BUILD_DIR)/bin/ballagg run --out out/demo

bench: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target ballagg_bench
	/usr/bin/python3 bench/ed_scaling.py

# AddressSanitizer + UndefinedBehaviorSanitizer (clang), in build-sanitize: the test suite
# (`make sanitize`, SANITIZE_TESTS selects a ctest regex) and the libFuzzer targets
# (`make fuzz`, FUZZ_SECONDS each). docs/hardening.md.
SANITIZE_DIR ?= build-sanitize
SANITIZE_FLAGS = -fsanitize=address,undefined,fuzzer-no-link -fno-omit-frame-pointer -fno-sanitize-recover=all
SANITIZE_TESTS ?= .
FUZZ_SECONDS ?= 30
SANITIZE_LSAN = suppressions=$(CURDIR)/tests/sanitize/lsan.supp:print_suppressions=0

sanitize-configure: setup
	@cmake -S . -B $(SANITIZE_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
	  -DCMAKE_CXX_COMPILER=clang++ -DBALLAGG_BENCH=OFF -DBALLAGG_FUZZ=ON -DBALLAGG_WERROR=$(WERROR) \
	  "-DCMAKE_C_FLAGS=$(SANITIZE_FLAGS)" "-DCMAKE_CXX_FLAGS=$(SANITIZE_FLAGS)" \
	  "-DCMAKE_EXE_LINKER_FLAGS=$(SANITIZE_FLAGS)" "-DCMAKE_SHARED_LINKER_FLAGS=$(SANITIZE_FLAGS)" > /dev/null

# The Python module's tests are left out: an ASan-built extension needs libasan preloaded
# into /usr/bin/python3 (and the sanitizer build does not build the module it would install).
sanitize: sanitize-configure
	@cmake --build $(SANITIZE_DIR) -j $(JOBS) --target ballagg_tests ballagg
	ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 LSAN_OPTIONS=$(SANITIZE_LSAN) \
	  ctest --test-dir $(SANITIZE_DIR) --output-on-failure -j $(JOBS) -E '^PythonModule(AsRoot|Install)?$$' -R '$(SANITIZE_TESTS)'

fuzz: sanitize-configure
	@cmake --build $(SANITIZE_DIR) -j $(JOBS) --target fuzz_targets
	@LSAN_OPTIONS=$(SANITIZE_LSAN) bash tests/fuzz/run_fuzzers $(SANITIZE_DIR) $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD_DIR) $(SANITIZE_DIR)
