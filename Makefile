# cubecal — top-level entry points. Each target first makes sure the Debian
# packages are installed, then configures and builds in Release mode.
BUILD   ?= build
JOBS    ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release -DCUBECAL_WERROR=ON

# Seconds per fuzz target: `make fuzz`, and the short pass `make test` ends with.
FUZZ_SECONDS      ?= 300
TEST_FUZZ_SECONDS ?= 20
# The pass `make test` runs follows one fixed path through the inputs, so a
# submission's CI is repeatable; `make fuzz` explores anew each time.
TEST_FUZZ_SEED    ?= 1

.PHONY: all deps configure build demo test fuzz bench clean docs

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

demo: build
	@$(BUILD)/bin/cubecal demo

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
	@FUZZ_SECONDS=$(TEST_FUZZ_SECONDS) FUZZ_SEED=$(TEST_FUZZ_SEED) JOBS=$(JOBS) bash fuzz/run.sh

# libFuzzer targets (fuzz/): clang, ASan + UBSan, in build-fuzz/.
fuzz: deps
	@FUZZ_SECONDS=$(FUZZ_SECONDS) JOBS=$(JOBS) bash fuzz/run.sh

# The documentation site (Sphinx: docs/, the Python docstrings, Doxygen's C++
# reference; a warning fails it). Doxygen's reference alone: --target docs.
docs: configure
	@cmake --build $(BUILD) --target docs_site
	@echo "Documentation site: $(abspath $(BUILD))/docs/site/index.html"

bench: build
	@bash bench/run.sh $(BUILD)

# Debian package (cmake/Packaging.cmake): $(BUILD)/cubecal_<version>_<arch>.deb
.PHONY: package
package: build
	@cd $(BUILD) && cpack -G DEB
	@deb=$$(ls -t $(abspath $(BUILD))/cubecal_*.deb | head -n 1); echo "Debian package: $$deb (install: apt install $$deb)"

clean:
	rm -rf $(BUILD) build-fuzz

# Installs the command, libraries, headers, CMake package, man pages and the
# Python module under PREFIX (default /usr/local, where Debian's python3
# finds the module); the install step says where each went.
PREFIX ?= /usr/local
.PHONY: install
install: build
	@cmake --install $(BUILD) --prefix $(PREFIX)
