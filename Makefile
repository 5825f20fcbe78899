# The README's two commands: `make demo` and `make test`. Everything else is a helper.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release

.PHONY: all setup configure build python test demo bench clean

all: build

setup:
	@bash scripts/setup

configure: setup
	@cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS) > /dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The Python module alone (build/python); `make build` and `make test` build it too.
python: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target ballagg_python

test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

demo: build
	$(BUILD_DIR)/bin/ballagg run --out out/demo

bench: build
	/usr/bin/python3 bench/ed_scaling.py

clean:
	rm -rf $(BUILD_DIR)
