# varsym: thin wrapper over CMake. `make run` builds the tool alone and reproduces the paper into
# out/; `make test` builds and runs every test. Both install missing Debian packages first
# (scripts/install-deps.sh).
BUILD_DIR ?= build
BUILD_TYPE ?= Release
# The compiler of a new build directory: clang++, unless CXX is set (CXX=g++ make test). Clang 14
# compiles varsym's templates about twice as fast as GCC 12, and the code it makes runs as fast
# (docs/development.md has the measurements). An existing build directory keeps its compiler.
ifeq ($(origin CXX),default)
CXX := clang++
endif
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
OUT ?= out
VARSYM = $(BUILD_DIR)/apps/varsym/varsym

.PHONY: all deps configure build tool python python-tool run test install san-configure test-sanitize \
  test-sanitize-cli fuzz bench bench-optimal bench-robots bench-contact soak clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -Wno-dev \
	  $(if $(wildcard $(BUILD_DIR)/CMakeCache.txt),,-DCMAKE_CXX_COMPILER=$(CXX)) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The command-line tool: varsym and varsym-optimize (the optimizer, which `varsym optimize` runs).
tool: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_tool varsym_optimize_tool

# The Python package, in $(BUILD_DIR)/python (PYTHONPATH=$(BUILD_DIR)/python imports it); to
# install it with pip, see docs/python.md.
python: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_python

# varsym._tool: the command line in-process (varsym.call), optional beside the package.
python-tool: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_python_tool

# Installs the headers and the CMake package (find_package(varsym)) under PREFIX.
PREFIX ?= /usr/local
install: configure
	@cmake --install $(BUILD_DIR) --prefix $(PREFIX)

# Reproduces the paper: Table 1 (text and CSV), Figures 1 and 2 (PNG and SVG, with their data
# and gnuplot scripts), all into $(OUT)/. Builds the program varsym alone (the models layer and
# the front end), not the optimizer.
run: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_tool
	@mkdir -p $(OUT)
	$(VARSYM) paper table1 --output $(OUT)/table1.txt
	$(VARSYM) paper table1 --format csv --output $(OUT)/table1.csv
	$(VARSYM) paper figure1 --output $(OUT)/figure1.svg --output $(OUT)/figure1.png
	$(VARSYM) paper figure2 --output $(OUT)/figure2.svg --output $(OUT)/figure2.png
	@cat $(OUT)/table1.txt
	@echo "varsym: wrote $(OUT)/table1.{txt,csv} and $(OUT)/figure{1,2}.{png,svg,csv,gp}"

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# The whole test suite again, built by clang with AddressSanitizer and UndefinedBehaviorSanitizer
# (-O1, Eigen's assertions on, any report fatal), and the libFuzzer target beside it. Clang,
# because GCC 12's UBSan instrumentation of the Eigen and autodiff templates compiles about 1.5x
# slower than clang's, and the fuzzer needs clang anyway. The Python package is left out: the
# interpreter would need the sanitizer runtimes preloaded.
SAN_DIR ?= build-sanitize
SAN_FLAGS = -O1 -gline-tables-only -fno-omit-frame-pointer -fsanitize=address,undefined \
  -fno-sanitize-recover=all
SAN_DEPS = clang libclang-rt-14-dev
san-configure: deps
	@bash scripts/install-deps.sh $(SAN_DEPS)
	@cmake -S . -B $(SAN_DIR) -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None \
	  -DCMAKE_CXX_FLAGS="$(SAN_FLAGS)" -DVARSYM_BUILD_BENCH=OFF -DVARSYM_FUZZ=ON \
	  -DVARSYM_BUILD_PYTHON=OFF -DVARSYM_MPI=OFF -Wno-dev >/dev/null

test-sanitize: san-configure
	@cmake --build $(SAN_DIR) -j $(JOBS)
	@cd $(SAN_DIR) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/fuzz/lsan.supp ctest --output-on-failure -j $(JOBS)

# The tool alone under the sanitizers, and its end-to-end tests (run, checkpoints, files, signals,
# every model and scheme through the library): what CI runs, in a third of test-sanitize's time.
test-sanitize-cli: san-configure
	@cmake --build $(SAN_DIR) -j $(JOBS) --target varsym_tool varsym_optimize_tool
	@cd $(SAN_DIR) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/fuzz/lsan.supp \
	  VARSYM_SANITIZED=1 ctest --output-on-failure -j $(JOBS) -R '^cli'

# libFuzzer over the command line, config files and checkpoints for FUZZ_SECONDS; seeds in
# fuzz/corpus, new inputs kept in $(SAN_DIR)/corpus, a crashing input in $(SAN_DIR)/crash-*.
FUZZ_SECONDS ?= 50
# The dictionary is fuzz/cli.dict plus every model's name and parameter options, generated from
# the models layer's registry (varsym models --format csv).
fuzz: san-configure
	@cmake --build $(SAN_DIR) -j $(JOBS) --target varsym_fuzz varsym_tool
	@mkdir -p $(SAN_DIR)/corpus
	@{ cat fuzz/cli.dict; $(SAN_DIR)/apps/varsym/varsym models --format csv | \
	  awk -F, 'NR > 1 { print "\"" $$1 "\""; if ($$4 != "") print "\"" $$4 "\"" }' | sort -u; } \
	  > $(SAN_DIR)/cli.dict
	$(SAN_DIR)/fuzz/varsym_fuzz -max_total_time=$(FUZZ_SECONDS) -timeout=10 -close_fd_mask=3 \
	  -artifact_prefix=$(SAN_DIR)/ -dict=$(SAN_DIR)/cli.dict $(SAN_DIR)/corpus fuzz/corpus

bench: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_bench varsym_bench_family
	$(BUILD_DIR)/bench/varsym_bench --benchmark_min_time=0.2
	$(BUILD_DIR)/bench/varsym_bench_family --benchmark_min_time=0.2
	bash bench/compilers.sh 5
	@$(MAKE) --no-print-directory bench-robots
	@$(MAKE) --no-print-directory bench-contact
	@$(MAKE) --no-print-directory bench-optimal

# Optimal control: time, iterations and accuracy per second (bench/bench_optimal.cpp), and of
# URDF robots (bench/bench_robot_optimal.cpp). Part of `make bench`.
bench-optimal: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_bench_optimal varsym_bench_robot_optimal
	$(BUILD_DIR)/bench/varsym_bench_optimal 3
	$(BUILD_DIR)/bench/varsym_bench_robot_optimal 3

# URDF robots against MuJoCo (bench/bench_robots.cpp; docs/robots.md): MuJoCo from Debian's
# libmujoco-dev, installed here as a benchmark peer only. ROBOT_BENCH: the sections to run
# (check steps precision scaling, and energy FILE for the 10^6-step energy data).
ROBOT_BENCH ?= check steps precision scaling
bench-robots: deps
	@bash scripts/install-deps.sh libmujoco-dev
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -Wno-dev >/dev/null
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_bench_robots
	$(BUILD_DIR)/bench/varsym_bench_robots $(ROBOT_BENCH)

# Hard contact with Coulomb friction against MuJoCo (bench/bench_contact.cpp): a box on an
# incline, a dropped ball, the A1 quadruped standing and dropped under PD, a tumbling box; one
# markdown table. CONTACT_ROUNDS: interleaved rounds of the A1's timed runs.
CONTACT_ROUNDS ?= 5
bench-contact: deps
	@bash scripts/install-deps.sh libmujoco-dev
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -Wno-dev >/dev/null
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_bench_contact
	$(BUILD_DIR)/bench/varsym_bench_contact $(CONTACT_ROUNDS)

soak: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target varsym_soak
	$(BUILD_DIR)/bench/varsym_soak

clean:
	rm -rf $(BUILD_DIR) $(SAN_DIR) $(OUT)
