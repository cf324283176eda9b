# varsym: thin wrapper over CMake. `make run` reproduces the paper into out/, `make test` runs
# every test. Both install missing Debian packages first (scripts/install-deps.sh).
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
OUT ?= out
VARSYM = $(BUILD_DIR)/apps/varsym/varsym

.PHONY: all deps configure build run test bench soak clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -Wno-dev >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# Reproduces the paper: Table 1 (text and CSV), Figures 1 and 2 (PNG and SVG, with their data
# and gnuplot scripts), all into $(OUT)/.
run: build
	@mkdir -p $(OUT)
	$(VARSYM) paper table1 --output $(OUT)/table1.txt
	$(VARSYM) paper table1 --format csv --output $(OUT)/table1.csv
	$(VARSYM) paper figure1 --output $(OUT)/figure1.svg --output $(OUT)/figure1.png
	$(VARSYM) paper figure2 --output $(OUT)/figure2.svg --output $(OUT)/figure2.png
	@cat $(OUT)/table1.txt
	@echo "varsym: wrote $(OUT)/table1.{txt,csv} and $(OUT)/figure{1,2}.{png,svg,csv,gp}"

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD_DIR)/bench/varsym_bench --benchmark_min_time=0.2

soak: build
	$(BUILD_DIR)/bench/varsym_soak

clean:
	rm -rf $(BUILD_DIR) $(OUT)
