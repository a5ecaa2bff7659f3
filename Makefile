# Strandlight build. `make` builds build/strandlight; see README for every target.
# BUILD selects the output directory so several builds (release, asan) can live side by side.
BUILD ?= build
CC ?= gcc
CXX ?= g++
OPT ?= -O2
SAN ?=
WERROR ?= -Werror

CPPFLAGS += -Ihost -Ikernels -Icpu -Icpu/reference -I/usr/include/OpenEXR \
            -D_DEFAULT_SOURCE -D_POSIX_C_SOURCE=200809L -DCL_TARGET_OPENCL_VERSION=120 \
            -DSL_KERNEL_DIR='"$(abspath kernels)"'
# No errno from math and no floating-point traps (we read neither): sqrt inlines, and loops whose
# lanes compute both sides of a select (the SRBF nodes: kernels/srbf_deon.h) vectorise. Every
# operation still rounds as IEEE says (unlike -ffast-math).
MATHFLAGS := -fno-math-errno -fno-trapping-math
CFLAGS += -std=c11 $(OPT) $(MATHFLAGS) -g -Wall -Wextra $(WERROR) -MMD -MP $(SAN)
CXXFLAGS += -std=c++17 $(OPT) -g -Wall -Wextra $(WERROR) -MMD -MP $(SAN) \
            -I/usr/include/Imath -I/usr/include/OpenEXR -I/usr/include/imgui -Ihost -Ikernels -Icpu
LDLIBS += -lOpenCL -lOpenEXR-3_1 -lOpenEXRCore-3_1 -lIex-3_1 -lImath-3_1 -lcjson -lstb -lembree3 \
          -limgui -lglfw -lGL -lstdc++ -lpthread -lm
LDFLAGS += $(SAN)

# Every C file under host/ (but the CLI's main.c), cpu/ and cpu/reference/ goes into one library
# that the binary and the unit tests share; new files in any folder of the tree are picked up
# without editing this Makefile (docs/design.md draws the tree). Host headers are included by
# their path below host/ ("passes/light/shadow.h"); kernels/ and cpu/ headers by name.
LIB_C   := $(filter-out host/cli/main.c,$(shell find host cpu -name '*.c' | sort))
LIB_CXX := $(shell find host -name '*.cpp' | sort)
TEST_C  := $(shell find test -name 'test_*.c' -not -path 'test/fuzz/*' | sort) test/test_main.c
LIB_OBJ := $(LIB_C:%.c=$(BUILD)/%.o) $(LIB_CXX:%.cpp=$(BUILD)/%.o)
TEST_OBJ := $(TEST_C:%.c=$(BUILD)/%.o)
$(TEST_OBJ): CPPFLAGS += -Itest

.PHONY: all deps run test test-farm asan bench gpu-check fuzz format clean
all: $(BUILD)/strandlight $(BUILD)/unit_tests

$(BUILD)/libstrandlight.a: $(LIB_OBJ)
	@mkdir -p $(@D)
	rm -f $@ && ar rcs $@ $^

$(BUILD)/strandlight: $(BUILD)/host/cli/main.o $(BUILD)/libstrandlight.a
	$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(BUILD)/unit_tests: $(TEST_OBJ) $(BUILD)/libstrandlight.a
	$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

# The C twins' hot loops for AVX2 + FMA, chosen at run time (cpu/srbf_deon_c_avx2.c).
ifeq ($(shell uname -m),x86_64)
$(BUILD)/cpu/srbf_deon_c_avx2.o: CFLAGS += -mavx2 -mfma
endif

$(BUILD)/%.o: %.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

$(BUILD)/%.o: %.cpp
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -c -o $@ $<

deps:
	bash scripts/deps.sh

run: $(BUILD)/strandlight
	$(BUILD)/strandlight render data/default.json --exr out/default.exr --png out/default.png

test: all
	bash test/run.sh $(BUILD)

# The same suite with AddressSanitizer + UndefinedBehaviorSanitizer. PoCL/LLVM leak at exit
# when PoCL compiles a kernel (measured, see ../shared/design/toolchain.md): suppressed by name.
asan:
	$(MAKE) BUILD=build-asan OPT=-O1 SAN="-fsanitize=address,undefined -fno-omit-frame-pointer" all
	ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 LSAN_OPTIONS=suppressions=$(abspath test/lsan.supp) \
	UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 bash test/run.sh build-asan

# A real single-node Slurm on localhost renders an orbit as an array job (docs/farm.md).
test-farm: all
	bash test/farm/run.sh $(BUILD)

bench: all
	bash test/bench/bench.sh $(BUILD)

# The GPU check (issue 20, docs/performance.md "GPU check"): builds, then kernels --check and the
# goal scene's frames on the first GPU OpenCL device, figures into docs/performance.md; without a
# GPU a smoke run on PoCL that writes nothing. Never a prerequisite of all or test.
gpu-check:
	bash scripts/gpu_check.sh --build $(BUILD)

# Builds every libFuzzer target (build-fuzz/); with FUZZ_SECONDS=N also runs each for N s on a
# copy of its seed corpus (test/cli/test_fuzz.sh) and fails when any target finds a crash.
fuzz:
	bash test/fuzz/build.sh
	@if [ -n "$(FUZZ_SECONDS)" ]; then mkdir -p build-fuzz/run && \
	  FUZZ_BUILD=build-fuzz FUZZ_SECONDS=$(FUZZ_SECONDS) TMP=build-fuzz/run bash test/cli/test_fuzz.sh \
	    | tee build-fuzz/run/fuzz.log && ! grep -q '^FAIL' build-fuzz/run/fuzz.log; fi

format:
	clang-format -i $$(find host cpu kernels test -name '*.[ch]' -o -name '*.cpp' -o -name '*.cl' | grep -v '^test/fuzz/corpus') 2>/dev/null || true

clean:
	rm -rf build build-asan build-* out

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
