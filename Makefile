# nephele — thin wrapper around CMake/CTest (like Neovim's Makefile).
#   make deps   install the Debian packages the project needs (idempotent)
#   make        configure + build (Release with debug info, Ninja)
#   make test   deps + build + the whole CTest suite (unit and GL tests on llvmpipe), without
#               the `blender` label (make test-blender; .ci/run runs both)
#   make demo   deps + build + render the built-in sample storm
#   make bench  deps + build + Google Benchmark suite, JSON/CSV into build/bench/
#   make bench-accuracy  deps + build + `nephele-bench accuracy` (run time against error), into build/accuracy/
#   make test-sanitize   clang build with ASan + UBSan (-Werror in CI) in build-sanitize/, unit + GL + CLI tests
#   make test-sanitize-ci  the part of it CI runs (.ci/run): parsers, models, GL context, fuzz corpus
#   make fuzz   the same clang build + a bounded libFuzzer campaign of each tests/fuzz target
BUILD_DIR  ?= build
BUILD_TYPE ?= RelWithDebInfo
CMAKE_ARGS ?=
CTEST_ARGS ?=
# Tests run two at a time: the suite is parallel-safe (754/754 passed with -j2 on a machine at load
# 9-13 in the seventeenth session), and the CPU references, file I/O and process start-up of one
# test overlap the llvmpipe rendering of the other. TEST_JOBS=1 runs them one by one.
TEST_JOBS  ?= 2
# Warnings are errors in CI (CI=true) and whenever NEPHELE_WERROR=ON is passed.
ifeq ($(CI),true)
  CMAKE_ARGS += -DNEPHELE_WERROR=ON
endif

.PHONY: all deps build test test-blender test-sanitize test-sanitize-ci fuzz demo bench bench-accuracy clean install
all: build

deps:
	@bash tools/install-deps.sh

$(BUILD_DIR)/build.ninja:
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_ARGS)

build: $(BUILD_DIR)/build.ninja
	cmake --build $(BUILD_DIR)

test: deps
	$(MAKE) build
	cd $(BUILD_DIR) && ctest --output-on-failure -j$(TEST_JOBS) -LE blender $(CTEST_ARGS)
	@echo "GL backends exercised by the gl tests:"
	@NEPHELE_LOG=warn NEPHELE_GL=egl NEPHELE_EGL_PLATFORM=device $(BUILD_DIR)/tests/gl/nephele_glinfo
	@NEPHELE_LOG=warn NEPHELE_GL=egl NEPHELE_EGL_PLATFORM=surfaceless $(BUILD_DIR)/tests/gl/nephele_glinfo
	@NEPHELE_LOG=warn NEPHELE_GL=osmesa $(BUILD_DIR)/tests/gl/nephele_glinfo

# Blender (Cycles, CPU) imports and renders `nephele export-vdb` output (docs/interop.md)
test-blender: deps
	@bash tools/install-deps.sh tools/debian-packages-blender.txt
	$(MAKE) build
	cd $(BUILD_DIR) && ctest --output-on-failure -L blender $(CTEST_ARGS)

# The clang and sanitizer job (issue 17) in one build: clang++ with -fsanitize=address,undefined,
# UB aborting the test (-fno-sanitize-recover), the shared sanitizer runtime. Runs the unit, gl and
# cli labels: since session 19 that includes the api, cli, install, python and stress tests
# (docs/reliability.md, "Session 19 run"), and the interop label but Blender (OpenVDB and NanoVDB
# export; session 21). Programs we did not build or built without the
# sanitizers (ffmpeg, gst-launch-1.0, melt, python3, the install test's consumer) get the ASan
# runtime preloaded by their tests (cmake/NepheleTesting.cmake, nephele_sanitize_host_tests).
# Mesa's llvmpipe is not instrumented; LSan ignores what it allocates (tools/lsan-suppressions.txt).
# -O1 with line tables only: the sanitizers' stack traces need lines, not variables, and the build
# is what this job's time goes to (asserts stay on: no NDEBUG).
SANITIZE_DIR   ?= build-sanitize
SANITIZE_FLAGS ?= -O1 -gline-tables-only
SANITIZE_TESTS ?= -L "unit|gl|cli|interop" -LE blender
SANITIZE_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS=suppressions=$(CURDIR)/tools/lsan-suppressions.txt
test-sanitize: deps
	CC=clang CXX=clang++ cmake -S . -B $(SANITIZE_DIR) -G Ninja -DCMAKE_BUILD_TYPE=None \
	  "-DCMAKE_C_FLAGS=$(SANITIZE_FLAGS)" "-DCMAKE_CXX_FLAGS=$(SANITIZE_FLAGS)" \
	  -DNEPHELE_SANITIZE=ON -DNEPHELE_FUZZ=ON -DNEPHELE_BUILD_BENCHMARKS=OFF $(CMAKE_ARGS)
	cmake --build $(SANITIZE_DIR)
	cd $(SANITIZE_DIR) && $(SANITIZE_ENV) ctest --output-on-failure $(SANITIZE_TESTS) $(CTEST_ARGS)

# The sanitizer job of CI (issue 17 item 6; .ci/run): the part of test-sanitize that fits CI's
# time. clang with ASan + UBSan, -Werror always, built from nothing in build-sanitize-ci/ (no
# coverage instrumentation, no engine, renderer or CLI: 172 of the 333 build steps), then the unit
# and gl tests of what it builds: the readers of untrusted files (io, cache, scene, geo), the
# physics and lighting models, core, the fuzz harness, and the GL context layer on all three
# backends (EGL device, EGL surfaceless, OSMesa); then the saved fuzz corpus replayed and the
# deterministic mutation campaign of the .nph reader and the scene parser under the sanitizers.
# Measured from cold on the idle 2-core machine: about 8 minutes, 20 at load 7-9 (docs/reliability.md,
# "The sanitizer job in CI"). The whole selection (the renderer, engine, CLI, API, stress) is
# `make test-sanitize`: about 2.5 hours on 2 cores.
SANITIZE_CI_DIR     ?= build-sanitize-ci
SANITIZE_CI_TARGETS ?= nephele_io_tests nephele_cache_tests nephele_scene_tests nephele_geo_tests \
  nephele_physics_tests nephele_lighting_tests nephele_unit_core_tests nephele_unit_support_tests \
  nephele_fuzz_support_tests nephele_gl_tests nephele_ocio_config \
  nephele_fuzz_replay_nph nephele_fuzz_replay_scene nephele_fuzz_mutate_nph nephele_fuzz_mutate_scene
SANITIZE_CI_TESTS   ?= ^(unit\.(Core|Case|ImageCompare|LargeBuffer|ScratchDir)|io\.|cache\.|scene\.|geo\.|physics\.|lighting\.|gl\.(egl-device|egl-surfaceless|osmesa)\.|fuzz\.FuzzHarness)
test-sanitize-ci: deps
	CC=clang CXX=clang++ cmake -S . -B $(SANITIZE_CI_DIR) -G Ninja -DCMAKE_BUILD_TYPE=None \
	  "-DCMAKE_C_FLAGS=$(SANITIZE_FLAGS)" "-DCMAKE_CXX_FLAGS=$(SANITIZE_FLAGS)" \
	  -DNEPHELE_SANITIZE=ON -DNEPHELE_WERROR=ON -DNEPHELE_BUILD_BENCHMARKS=OFF $(CMAKE_ARGS)
	cmake --build $(SANITIZE_CI_DIR) --target $(SANITIZE_CI_TARGETS)
	cd $(SANITIZE_CI_DIR) && $(SANITIZE_ENV) \
	  ctest --output-on-failure -j$(TEST_JOBS) -R '$(SANITIZE_CI_TESTS)' $(CTEST_ARGS)
	$(SANITIZE_ENV) NEPHELE_LOG=error $(SANITIZE_CI_DIR)/tests/fuzz/nephele_fuzz_replay_nph tests/fuzz/corpus/nph
	$(SANITIZE_ENV) NEPHELE_LOG=error $(SANITIZE_CI_DIR)/tests/fuzz/nephele_fuzz_replay_scene tests/fuzz/corpus/scene examples/scenes
	cd $(SANITIZE_CI_DIR)/tests/fuzz && $(SANITIZE_ENV) NEPHELE_LOG=error NEPHELE_IO_MEMORY_BUDGET_MB=512 \
	  ./nephele_fuzz_mutate_nph -seed=17 -runs=10000 $(CURDIR)/tests/fuzz/corpus/nph \
	  $(CURDIR)/tests/geo/data/lambert_4x3x2_before_geo.nph
	cd $(SANITIZE_CI_DIR)/tests/fuzz && $(SANITIZE_ENV) NEPHELE_LOG=error \
	  ./nephele_fuzz_mutate_scene -seed=17 -runs=30000 $(CURDIR)/tests/fuzz/corpus/scene $(CURDIR)/examples/scenes

# Fuzzing (issue 18): libFuzzer targets for the model loaders, the .nph reader and the scene
# parser (tests/fuzz), clang with ASan + UBSan and coverage on every library, in build-sanitize/.
# Runs a bounded campaign of FUZZ_RUNS executions per target from the seeds and the saved corpus
# (never a time limit). `make test` replays the corpus with the normal build. The build is
# test-sanitize's (the same flags: coverage instrumentation is on there too, one clang build).
FUZZ_RUNS ?= 2000
fuzz: deps
	CC=clang CXX=clang++ cmake -S . -B $(SANITIZE_DIR) -G Ninja -DCMAKE_BUILD_TYPE=None \
	  "-DCMAKE_C_FLAGS=$(SANITIZE_FLAGS)" "-DCMAKE_CXX_FLAGS=$(SANITIZE_FLAGS)" \
	  -DNEPHELE_SANITIZE=ON -DNEPHELE_FUZZ=ON -DNEPHELE_FUZZ_RUNS=$(FUZZ_RUNS) \
	  -DNEPHELE_BUILD_BENCHMARKS=OFF $(CMAKE_ARGS)
	cmake --build $(SANITIZE_DIR) --target nephele_fuzz_model nephele_fuzz_nph nephele_fuzz_scene nephele nephele-gen
	cd $(SANITIZE_DIR) && ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -R '^fuzz\.(seeds|run\.)' $(CTEST_ARGS)

demo: deps
	$(MAKE) build
	@bash tools/demo.sh $(BUILD_DIR)

bench: deps
	$(MAKE) build
	@bash tools/bench.sh $(BUILD_DIR)

bench-accuracy: deps
	$(MAKE) build
	$(BUILD_DIR)/src/cli/nephele-bench accuracy -o $(BUILD_DIR)/accuracy $(ACCURACY_ARGS)

# PREFIX=DIR installs there instead of CMAKE_INSTALL_PREFIX (/usr/local); the Python module goes to
# DIR/lib/python3/dist-packages/nephele (docs/interop.md, "Python").
install: build
	cmake --install $(BUILD_DIR) $(if $(PREFIX),--prefix $(PREFIX))

clean:
	rm -rf $(BUILD_DIR)
