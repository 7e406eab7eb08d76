# nephele — thin wrapper around CMake/CTest (like Neovim's Makefile).
#   make deps   install the Debian packages the project needs (idempotent)
#   make        configure + build (Release with debug info, Ninja)
#   make test   deps + build + the whole CTest suite (unit and GL tests on llvmpipe), without
#               the `blender` label (make test-blender; .ci/run runs both)
#   make demo   deps + build + render the built-in sample storm
#   make bench  deps + build + Google Benchmark suite, JSON/CSV into build/bench/
#   make bench-accuracy  deps + build + `nephele bench accuracy` (run time against error), into build/accuracy/
BUILD_DIR  ?= build
BUILD_TYPE ?= RelWithDebInfo
CMAKE_ARGS ?=
CTEST_ARGS ?=
# Warnings are errors in CI (CI=true) and whenever NEPHELE_WERROR=ON is passed.
ifeq ($(CI),true)
  CMAKE_ARGS += -DNEPHELE_WERROR=ON
endif

.PHONY: all deps build test test-blender demo bench bench-accuracy clean install
all: build

deps:
	@bash tools/install-deps.sh

$(BUILD_DIR)/build.ninja:
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_ARGS)

build: $(BUILD_DIR)/build.ninja
	cmake --build $(BUILD_DIR)

test: deps
	$(MAKE) build
	cd $(BUILD_DIR) && ctest --output-on-failure -LE blender $(CTEST_ARGS)
	@echo "GL backends exercised by the gl tests:"
	@NEPHELE_LOG=warn NEPHELE_GL=egl NEPHELE_EGL_PLATFORM=device $(BUILD_DIR)/tests/gl/nephele_glinfo
	@NEPHELE_LOG=warn NEPHELE_GL=egl NEPHELE_EGL_PLATFORM=surfaceless $(BUILD_DIR)/tests/gl/nephele_glinfo
	@NEPHELE_LOG=warn NEPHELE_GL=osmesa $(BUILD_DIR)/tests/gl/nephele_glinfo

# Blender (Cycles, CPU) imports and renders `nephele export-vdb` output (docs/interop.md)
test-blender: deps
	@bash tools/install-deps.sh tools/debian-packages-blender.txt
	$(MAKE) build
	cd $(BUILD_DIR) && ctest --output-on-failure -L blender $(CTEST_ARGS)

demo: deps
	$(MAKE) build
	@bash tools/demo.sh $(BUILD_DIR)

bench: deps
	$(MAKE) build
	@bash tools/bench.sh $(BUILD_DIR)

bench-accuracy: deps
	$(MAKE) build
	$(BUILD_DIR)/src/cli/nephele bench accuracy -o $(BUILD_DIR)/accuracy $(ACCURACY_ARGS)

install: build
	cmake --install $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR)
